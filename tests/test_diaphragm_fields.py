"""The diaphragm's stress, envelope, events and cycles in a run's result
(:mod:`fsi.analysis.diaphragm`), and the fatigue arithmetic (:mod:`fsi.analysis.fatigue`)."""
import numpy as np
import pytest
from conftest import TINY_RAMP

from fsi.analysis.fatigue import cycles_to_failure, miner_damage, stress_cycles
from fsi.cli import main
from fsi.io.output import read_result, units_of
from fsi.registry import SceneError
from fsi.scene import parse_scene

RAMP = TINY_RAMP.replace('name = "small-ramp"', 'name = "ramp-with-curve"') + """
[fatigue]
sn_curve = [[4.0e6, 1.0e3], [1.0e6, 1.0e5]]
peak_triangles = 3
[limits]
strain = 0.01
"""


def test_rainflow_counts_astm_e1049s_example():
    """ASTM E1049-85 (2017), Sec. 5.4.4, Fig. 6 and Table 4: the history -2 1 -3 5 -1 3 -4 4 -2
    counts as ranges 3 (0.5), 4 (1.5), 6 (0.5), 8 (1.0), 9 (0.5)."""
    cycles = stress_cycles(np.array([-2, 1, -3, 5, -1, 3, -4, 4, -2], dtype=float))
    counted = {}
    for r, _, c in cycles:
        counted[r] = counted.get(r, 0.0) + c
    assert counted == {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def test_miners_damage_on_a_log_log_sn_curve():
    """N(S) is a straight line in log-log between the points, extended above the first and
    infinite below the last: on N = 1e3 (S / 4 MPa)^(-log 100 / log 4), 2 MPa lasts 1e4
    cycles, 8 MPa 1e2; three cycles of 2 MPa and a half of 8 MPa do 3e-4 + 5e-3."""
    curve = [[4e6, 1e3], [1e6, 1e5]]
    assert cycles_to_failure(curve, np.array([8e6, 2e6, 5e5])) == pytest.approx(
        [1e2, 1e4, np.inf])
    cycles = np.array([[2e6, 0.0, 1.0]] * 3 + [[8e6, 0.0, 0.5]])
    assert miner_damage(cycles, curve) == pytest.approx(3e-4 + 5e-3)
    assert miner_damage(np.zeros((0, 3)), curve) == 0.0


@pytest.mark.parametrize("curve", ["[[1.0e6, 1.0e5]]", "[[1.0e6, 1.0e3], [2.0e6, 1.0e5]]",
                                   "[[1.0e6, -1.0], [5.0e5, 1.0e5]]", "[1.0, 2.0]"])
def test_a_bad_sn_curve_is_refused_naming_the_key(curve):
    with pytest.raises(SceneError, match="fatigue.sn_curve"):
        parse_scene(f"[fatigue]\nsn_curve = {curve}\n")


@pytest.fixture(scope="module")
def ramp_run(tmp_path_factory):
    d = tmp_path_factory.mktemp("ramp")
    (d / "ramp.toml").write_text(RAMP)
    assert main(["run", str(d / "ramp.toml"), "--out", str(d / "run")]) == 0
    return d / "run"


def test_a_run_writes_the_diaphragms_fields_envelope_events_and_cycles(ramp_run, capsys):
    res = read_result(ramp_run)
    frames, env, a = res["frames"], res["envelope"], res["attrs"]
    m = 2 * len(res["membrane"]["face_nodes"])
    for group in ("frames", "history"):
        assert res[group]["surface_stress"].shape == (len(res[group]["time"]), m)
        assert res[group]["principal_stress"].shape[1:] == (m, 2)
    # every dataset has its units (the output reference is generated from them)
    for group in ("frames", "envelope", "events", "cycles"):
        for name in res[group]:
            assert units_of(name) != "", (group, name)
    # the envelope is the frames' largest, when it happened, and the peak is the envelope's
    k = np.argmax(frames["surface_stress"], axis=0)
    assert np.array_equal(env["peak_stress"], frames["surface_stress"][k, np.arange(m)])
    assert np.array_equal(env["peak_stress_time"], frames["time"][k])
    # the run's peak is the free sheet's: the triangles between the two support rings are
    # the clamp's
    from structure.grid import triangles_from_quads
    from structure.topology import free_triangles

    sheet = free_triangles(res["membrane"]["fixed"],
                           triangles_from_quads(res["membrane"]["face_nodes"]))
    t = int(np.argmax(np.where(sheet, env["peak_stress"], -np.inf)))
    assert a["peak_stress"] == env["peak_stress"][t] == frames["surface_stress"][:, sheet].max()
    assert a["peak_stress_polar_deg"] == env["polar_deg"][t]
    assert 0 < a["peak_stress_polar_deg"] <= 90
    assert "thesis" in a["stress_law"]
    # the cycles are those of the three most loaded triangles, with Miner's sum of the curve
    loaded = np.argsort(np.where(sheet, env["peak_stress"], -np.inf))[-3:]
    assert set(np.unique(res["cycles"]["triangle"])) <= set(loaded)
    assert a["miner_damage"] >= 0 and a["miner_damage_triangle"] in res["cycles"]["triangle"]
    # every event is a change of a series between two frames
    for stamp, kind in zip(res["events"]["time"], res["events"]["event"]):
        assert stamp in frames["time"][1:] and kind.decode().split()[0] in (
            "fold", "wall", "self-contact", "inversion")
    # a strain limit set in the scene, none for the stress: its margin, and only its
    assert a["strain_margin"] == pytest.approx(0.01 / a["peak_strain"])
    assert "stress_margin" not in a
    assert main(["show", str(ramp_run)]) == 0
    shown = capsys.readouterr().out
    assert f"peak {a['peak_stress'] / 1e6:.4g} MPa" in shown and "Miner damage" in shown
    assert "no limits.stress in the scene" in shown
    assert f"limit / peak = {a['strain_margin']:.3g} " in shown
    assert (ramp_run / "plots" / "stress_envelope.png").is_file()
    assert (ramp_run / "plots" / "diaphragm_history.png").is_file()


def test_a_failed_stress_analysis_keeps_the_run_and_exits_1(tiny_sweep_scene, tmp_path,
                                                             monkeypatch, capsys):
    """The frames are the run's work: a stress analysis that raises is reported in one line
    (exit 1, ``stress_analysis_failure`` in the result, ``fsi show`` says so), and the
    result is written whole."""
    from fsi.analysis import membrane_fields

    def broken(model, scene):
        raise RuntimeError("no rule today")

    monkeypatch.setitem(membrane_fields.FIELD_RULES, "xpbd", broken)
    out = tmp_path / "run"
    assert main(["run", str(tiny_sweep_scene), "--out", str(out), "--no-plots"]) == 1
    assert "the diaphragm's stress analysis failed: RuntimeError: no rule today" in \
        capsys.readouterr().err
    res = read_result(out)
    assert res["attrs"]["stress_analysis_failure"] == "RuntimeError: no rule today"
    assert res["frames"]["node_position"].shape[0] == 2 and "envelope" not in res
    assert main(["show", str(out)]) == 0
    assert "stress: not analysed (RuntimeError: no rule today)" in capsys.readouterr().out


def test_a_frame_whose_stresses_are_not_finite_fails_and_is_written_as_missing(
        tiny_sweep_scene, tmp_path, monkeypatch, capsys, caplog):
    """A frame where a field would be inf or NaN (here: the law's rule gives an infinite
    stress in the second frame) is a failed frame: its fields are the datasets' _FillValue
    in result.h5 (no non-finite number in any dataset), ``stress_valid`` is false, stderr and
    the result name it, the run exits 3 and ``fsi show`` does not say converged: all. (The
    sweep's full inversion is analysed first, so the second call is the fill's first frame.)"""
    import h5py

    from fsi.analysis.membrane_fields import FieldRule

    calls = {"n": 0}
    sheet = FieldRule.sheet

    def second_frame_infinite(self, pos):
        fields = sheet(self, pos)
        calls["n"] += 1
        if calls["n"] == 2:
            fields["principal_stress"][0, 0] = np.inf
        return fields

    monkeypatch.setattr(FieldRule, "sheet", second_frame_infinite)
    out = tmp_path / "run"
    assert main(["run", str(tiny_sweep_scene), "--out", str(out), "--no-plots"]) == 3
    err = capsys.readouterr().err
    assert "1 of 2 frames (stress fields not finite)" in err
    assert "the stress fields are not finite in frames frame " in caplog.text
    with h5py.File(out / "result.h5") as f:
        def finite(name, item):
            if isinstance(item, h5py.Dataset) and item.dtype.kind == "f":
                assert np.all(np.isfinite(item[()])), name
        f.visititems(finite)
        ds = f["frames/von_mises_stress"]
        assert np.all(ds[0] == ds.attrs["_FillValue"]) and np.all(ds[1] != ds.attrs["_FillValue"])
        assert list(f["frames/stress_valid"][()]) == [False, True]
        assert f.attrs["stress_invalid_frames"].startswith("frames frame 0")
    res = read_result(out)
    assert np.all(np.isnan(res["frames"]["von_mises_stress"][0]))
    assert main(["show", str(out)]) == 0
    assert "converged: all" not in capsys.readouterr().out
