"""Sweeps (fsi.sweep.file, fsi.sweep.run, fsi.sweep.data): cases from a sweep file, run on a
two-worker Dask LocalCluster, one dataset whose values are the single runs'; a failed case is
recorded and the others go on; a resumed sweep skips finished cases; a case whose worker is
killed is rerun (from its checkpoint) and ends as an uninterrupted single run."""
import json
import os
import signal
import threading
import time

import numpy as np
import pytest

from fsi.cli import main
from fsi.io.output import read_result
from fsi.sweep.file import SweepError, expand, parse_sweep
from tests.test_checkpoint import SLOSH

TINY_SCENE = """[scene]
name = "tiny"
procedure = "volume-sweep"
[membrane]
grid_size = 8
[structure]
model = "xpbd"
[sweep]
scale = "tank"
fills = [0.1, 0.2]
drain = false
"""

TINY_SWEEP = """[sweep]
name = "tiny"
scene = "tiny.toml"
plot = ["full_volume", "run_seconds"]
[vary]
membrane.grid_size = [8, 10]
sweep.fills = [[0.1, 0.2], [0.1, 0.5]]
"""
TIMING = {"run_seconds", "wall_seconds", "seconds_per_period"}


def _files(tmp_path, sweep_text=TINY_SWEEP, scene_text=TINY_SCENE):
    (tmp_path / "tiny.toml").write_text(scene_text)
    path = tmp_path / "tiny-sweep.toml"
    path.write_text(sweep_text)
    return path


def test_axes_expand_lists_ranges_and_zipped_keys(tmp_path):
    sweep = parse_sweep(TINY_SWEEP.replace(
        "[vary]", "[zip.material]\nmembrane.youngs_modulus = {start = 4e6, stop = 8e6, "
        "step = 2e6}\nmembrane.density = [1000.0, 1070.0, 1100.0]\n[vary]"),
        "s.toml", _files(tmp_path).parent)
    assert [a.name for a in sweep.axes] == ["membrane.grid_size", "sweep.fills", "material"]
    assert sweep.shape == (2, 2, 3) and len(sweep.cases) == 12
    assert sweep.axes[2].values["membrane.youngs_modulus"] == [4e6, 6e6, 8e6]
    case = sweep.cases[-1]
    assert case.name == "grid_size=10,fills=0.1x0.5,youngs_modulus=8e+06,density=1100"
    assert 'grid_size = 10' in case.scene_text and "youngs_modulus = 8000000.0" in case.scene_text
    assert expand("k", {"start": 0.1, "stop": 0.9, "num": 9})[2] == 0.3  # rounded, not 0.30..04


@pytest.mark.parametrize("name, cases", [("slosh-by-fill", 18), ("static-by-model", 12),
                                         ("valve-fill-samples", 5),
                                         ("valve-drain-samples", 5)])
def test_bundled_sweeps_build_every_case(name, cases, capsys):
    from fsi.sweep.file import load_sweep

    sweep = load_sweep(name)
    assert len(sweep.cases) == cases and sweep.name == name
    assert main(["sweeps", name]) == 0 and capsys.readouterr().out == sweep.text
    if name == "static-by-model":
        assert sweep.reference == "model=shell,grid_size=38"


@pytest.mark.parametrize("text, message", [
    ("[vary]\nslosh.fill = []", "sweep key 'slosh.fill': an empty list"),
    ("[vary]\nmembrane.grid_size = [8, 9]", "sweep case grid_size=9: scene key "
                                            "'membrane.grid_size' = 9 is out of range"),
    ("[vary]\nmembrane.colour = ['red']", "unknown scene key 'membrane.colour'"),
    ("[zip.g]\nmembrane.grid_size = [8, 10]\nfluid.cells = [16]", "differ in length"),
    ("[vary]\nfluid.cells = {start = 8, stop = 12}", "give a list of values, or"),
    ("[vary]\nmembrane.grid_size = [8]\n[zip.g]\nmembrane.grid_size = [10]",
     "key 'membrane.grid_size' is varied on two axes"),
    ("[colours]\na = 1", "unknown table [colours]"),
    ("", "nothing to vary"),
    ("reference = { membrane.density = 1.0 }\n[vary]\nmembrane.grid_size = [8, 10]",
     "'sweep.reference' = {'membrane.density': 1.0}: give a table of swept keys"),
    ("reference = { sweep.drain = false }\n[vary]\nmembrane.grid_size = [8, 10]\n"
     "sweep.drain = [false, true]", "picks 2 cases; give values that pick one"),
])
def test_a_bad_sweep_is_one_error_naming_the_key(tmp_path, text, message):
    _files(tmp_path)
    with pytest.raises(SweepError, match=message.replace("[", r"\[").replace("(", r"\(")):
        parse_sweep('[sweep]\nscene = "tiny.toml"\n' + text, "s.toml", tmp_path)


def test_two_workers_one_dataset_equal_to_single_runs_and_a_resume(tmp_path, capsys):
    """Four cases on a two-worker LocalCluster: the two whose fill 0.5 of the tank the
    N = 8 / 10 membranes cannot hold fail with the reason recorded, the others finish; the
    dataset's values equal single runs of the same scenes; --resume reruns only what is not
    finished."""
    path, out = _files(tmp_path), tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--workers", "2"]) == 1
    err = capsys.readouterr().err
    assert "2 of 4 cases failed" in err and "sweep.fills" in err
    records = [json.loads(line) for line in (out / "cases.jsonl").read_text().splitlines()]
    assert sorted(r["status"] for r in records) == [0, 0, 2, 2]
    from fsi.sweep import data as sweep_data

    ds = sweep_data.read(out)
    assert ds["exit_status"].values.tolist() == [[0, 2], [0, 2]]
    assert "membrane.grid_size" in ds.coords and ds["full_volume"].attrs["units"] == "m^3"
    assert ds["membrane.grid_size"].attrs["description"] == "nodes per grid side (thesis GridSize)"
    assert (out / "plots" / "full_volume.png").is_file()
    for i, n in enumerate((8, 10)):
        name = f"grid_size={n},fills=0.1x0.2"
        single = tmp_path / f"single-{n}"
        assert main(["run", str(out / "cases" / f"{name}.toml"), "--out", str(single),
                     "--no-plots"]) == 0
        attrs = read_result(single)["attrs"]
        for key in ("full_volume", "empty_volume", "full_pressure_level", "grid_size"):
            assert ds[key].values[i, 0] == float(attrs[key]), key
        assert np.isnan(ds["full_volume"].values[i, 1])  # the failed case wrote nothing
    # resume: one finished case removed; it and the two failed ones run again, one skipped
    import shutil

    shutil.rmtree(out / "cases" / "grid_size=10,fills=0.1x0.2")
    capsys.readouterr()
    assert main(["sweep", str(path), "--out", str(out), "--workers", "2"]) == 2
    assert main(["sweep", str(path), "--out", str(out), "--workers", "2", "--resume"]) == 1
    err = capsys.readouterr().err
    assert "1 cases finished before, skipped" in err
    assert len((out / "cases.jsonl").read_text().splitlines()) == 4 + 3
    again = sweep_data.read(out)
    assert again["full_volume"].values[1, 0] == ds["full_volume"].values[1, 0]


def test_a_resumed_sweep_answers_for_the_cases_it_skipped(tmp_path):
    """A resumed sweep with nothing left to run still fails (or reports unconverged) for the
    cases that did so before: its outcome counts their records in DIR/cases.jsonl."""
    from fsi.sweep.run import lay_out, run_sweep

    path, out = _files(tmp_path), tmp_path / "out"
    sweep = parse_sweep(path.read_text(), str(path), tmp_path)
    lay_out(sweep, out, replace=False)
    statuses = [0, 1, 3, 0]
    for case, status in zip(sweep.cases, statuses):  # every case finished, its result kept
        (out / "cases" / case.name).mkdir()
        (out / "cases" / case.name / "result.h5").write_bytes(b"")
        with open(out / "cases.jsonl", "a") as f:
            f.write(json.dumps(dict(case=case.name, status=status, reason=f"r{status}",
                                    seconds=1.0)) + "\n")
    outcome = run_sweep(sweep, out, resume=True)  # no cluster: nothing to run
    assert outcome.records == {} and len(outcome.skipped) == 4
    assert outcome.failed == [sweep.cases[1].name]
    assert outcome.unconverged == [sweep.cases[2].name]


def test_a_scheduler_that_does_not_answer_is_one_line_and_nothing_written(tmp_path, capsys):
    path, out = _files(tmp_path), tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--scheduler", "nonsense:::"]) == 2
    assert "--scheduler nonsense:::: no Dask scheduler answered" in capsys.readouterr().err
    assert not out.exists()


def test_per_fill_quantities_and_eqn_6_1_against_the_reference_case(tmp_path, capsys):
    """A static sweep's frames by requested fill: each case's pressure level is its single
    run's, the reference case's shape error is 0, another case's equals `fsi compare`'s Eqn 6.1
    against the reference (thesis Eqn 6.1), and shape_error is its mean over the fills."""
    text = TINY_SWEEP.replace('plot = ["full_volume", "run_seconds"]',
                              'plot = ["fill_shape_error"]\nreference = { membrane.grid_size '
                              '= 10 }').replace("sweep.fills = [[0.1, 0.2], [0.1, 0.5]]\n", "")
    path, out = _files(tmp_path, text), tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--workers", "1"]) == 0
    from fsi.sweep import data as sweep_data

    ds = sweep_data.read(out)
    assert ds["fill"].values.tolist() == [0.1, 0.2] and ds["fill"].attrs["fill_scale"] == "tank"
    assert ds["fill_shape_error"].dims == ("fill", "membrane.grid_size")
    assert np.all(ds["fill_shape_error"].values[:, 1] < 1e-12)  # itself, up to interpolation
    frames = read_result(out / "cases" / "grid_size=8")["frames"]
    assert ds["fill_pressure_level"].values[:, 0].tolist() == frames["pressure_level"].tolist()
    assert ds["fill_pressure_level"].attrs["units"] == "Pa"
    capsys.readouterr()
    assert main(["compare", str(out / "cases" / "grid_size=8"),
                 str(out / "cases" / "grid_size=10")]) == 0
    printed = [float(line.split()[2]) for line in capsys.readouterr().out.splitlines()[1:]]
    assert printed[0] > 0.01
    np.testing.assert_allclose(ds["fill_shape_error"].values[:, 0], printed, atol=5e-5)
    assert ds["shape_error"].values[0] == pytest.approx(np.mean(
        ds["fill_shape_error"].values[:, 0]))
    assert (out / "plots" / "fill_shape_error.png").is_file()


SLOSH_SCENE = SLOSH["limp"]  # a limp slosh run that checkpoints every 100 windows

SLOSH_SWEEP = """[sweep]
name = "kill"
scene = "tiny.toml"
plot = ["lambda1"]
[vary]
slosh.fill = [0.4, 0.6]
"""


def test_a_case_whose_worker_is_killed_is_rerun_from_its_checkpoint(tmp_path):
    """SIGKILL to the worker running a case, after the case's first checkpoint: the scheduler
    reruns the case on a restarted worker, which resumes it; its result equals a single
    uninterrupted run bit for bit, and the sweep finishes every case."""
    from dask.distributed import Client, LocalCluster

    from fsi.sweep.file import load_sweep
    from fsi.sweep.run import run_sweep
    from tests.test_checkpoint import _assert_equal_arrays

    path, out = _files(tmp_path, SLOSH_SWEEP, SLOSH_SCENE), tmp_path / "out"
    sweep = load_sweep(str(path))
    victim = sweep.cases[0].name
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        done = {}
        thread = threading.Thread(target=lambda: done.update(
            outcome=run_sweep(sweep, out, client=client)))
        thread.start()
        deadline = time.monotonic() + 120
        while not list((out / "cases").glob(f".partial-{victim}-*/checkpoint.pkl")):
            assert thread.is_alive() and time.monotonic() < deadline
            time.sleep(0.05)
        running = {addr: keys for addr, keys in client.processing().items()
                   if any(victim in str(k) for k in keys)}
        (addr,) = running
        os.kill(client.run(os.getpid)[addr], signal.SIGKILL)
        thread.join(timeout=300)
    outcome = done["outcome"]
    assert not outcome.failed and set(outcome.records) == {c.name for c in sweep.cases}
    assert outcome.records[victim]["resumed"] is True
    single = tmp_path / "single"
    assert main(["run", str(out / "cases" / f"{victim}.toml"), "--out", str(single),
                 "--no-plots"]) == 0
    _assert_equal_arrays(single, out / "cases" / victim, ("frames", "windows", "surface"))
    assert not list((out / "cases").glob(".partial-*"))


def test_a_scheduler_that_did_not_answer_leaves_no_default_client(tmp_path):
    """A Client that never connected stays dask's default scheduler unless it is made with
    set_as_default=False; a later sweep's dataset write then asked that dead scheduler for
    xarray's write lock (ValueError: invalid address 'nonsense:::')."""
    from dask.base import get_scheduler

    path, out = _files(tmp_path), tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--scheduler", "nonsense:::"]) == 2
    assert get_scheduler() is None


def test_frames_between_requested_fills_are_left_out_of_the_fill_axis():
    # a coupled run records frames every few windows (no requested fill: NaN) besides those
    # at every 0.1 of tank fraction; a sweep of such runs gathers the latter only
    from types import SimpleNamespace

    from fsi.sweep.data import fill_variables

    nan = float("nan")
    axis = SimpleNamespace(name="pressure_tolerance")
    cases = [SimpleNamespace(name="a", index=(0,)), SimpleNamespace(name="b", index=(1,))]
    sweep = SimpleNamespace(axes=[axis], shape=(2,), cases=cases, reference=None)
    frames = {"a": {"target_fill": np.array([nan, 0.2, nan, 0.3]),
                    "tank_fraction": np.array([0.15, 0.2, 0.25, 0.3])},
              "b": {"target_fill": np.array([nan, nan]),
                    "tank_fraction": np.array([0.1, 0.12])}}
    fills, data = fill_variables(sweep, {n: {"frames": f} for n, f in frames.items()})
    assert fills == [0.2, 0.3]
    np.testing.assert_array_equal(data["fill_tank_fraction"][1], [[0.2, nan], [0.3, nan]])
    only_between = {"b": {"frames": frames["b"]}}
    assert fill_variables(SimpleNamespace(axes=[axis], shape=(2,), cases=cases[1:],
                                          reference=None), only_between) == (None, {})
