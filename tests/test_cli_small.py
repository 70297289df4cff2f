"""The CLI's small things: --version, printing a bundled scene, fsi show, a folder named like
a bundled scene, units and the version in result.h5, the draining leg in ParaView."""
import subprocess
import sys

import h5py
import meshio
import pytest

from fsi.cli import main
from fsi.io.output import software_version
from fsi.scene import load_scene, parse_scene


def test_version(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"slosh-fsi {software_version()}"
    assert software_version() not in ("", "unknown")


def test_scenes_name_prints_a_bundled_scene_that_parses_to_the_same(capsys):
    assert main(["scenes", "thesis-fill"]) == 0
    text = capsys.readouterr().out
    assert parse_scene(text).values == load_scene("thesis-fill").values
    assert main(["scenes", "no-such-scene"]) == 2


def test_a_folder_named_like_a_bundled_scene_does_not_hide_it(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "thesis-static").mkdir()  # e.g. a results folder
    assert load_scene("thesis-static").name == "thesis-static"


def test_a_static_sweep_writes_units_version_and_its_draining_leg(tmp_path, tiny_sweep_scene,
                                                                  capsys):
    scene = tiny_sweep_scene
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--no-plots"]) in (0, 3)
    with h5py.File(out / "result.h5") as f:
        assert f.attrs["software_version"] == software_version()
        missing = []
        f.visititems(lambda name, obj: missing.append(name)
                     if isinstance(obj, h5py.Dataset) and "units" not in obj.attrs else None)
        assert missing == []
    reader = meshio.xdmf.TimeSeriesReader(str(out / "drain.xdmf"))
    reader.read_points_cells()
    assert reader.num_steps == 2
    capsys.readouterr()
    assert main(["show", str(out)]) == 0
    shown = capsys.readouterr().out
    assert "scene tiny, procedure volume-sweep" in shown and "drain: 2 records" in shown
    assert software_version() in shown
    # an HDF5 file that is not a result (the XDMF's heavy data) is refused in one line
    heavy = next(p for p in out.glob("*.h5") if p.name != "result.h5")
    for command in (["compare", str(out), str(heavy)], ["show", str(heavy)],
                    ["compare", str(heavy), str(out)]):
        assert main(command) == 2, command
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and str(heavy) in err and "not a result" in err


def test_only_our_own_info_lines_by_default(tmp_path):
    """Libraries' INFO messages (FiPy's solver choice among them) only with -v."""
    scene = tmp_path / "fill.toml"
    scene.write_text("[scene]\nprocedure = 'coupled-fill'\n[dynamics]\nend_time = 0.002\n")
    run = subprocess.run([sys.executable, "-m", "fsi.cli", "run", str(scene), "--out",
                          str(tmp_path / "a"), "--no-plots"], capture_output=True, text=True)
    assert run.returncode == 0
    info = [line for line in run.stderr.splitlines() if line.startswith("INFO ")]
    assert info and all(line.startswith("INFO fsi") for line in info)
    assert main(["-v", "scenes"]) == 0


def _sweep_scene(tmp_path, grid_size: int):
    scene = tmp_path / "big.toml"
    scene.write_text(load_scene("thesis-static").text.replace("grid_size = 26",
                                                              f"grid_size = {grid_size}"))
    return scene


def test_absurd_grids_are_refused_before_anything_is_computed(tmp_path, capsys):
    """A membrane grid too large for the memory, or for the relaxation's step, is one line
    naming the keys, exit 2, before the run starts and with nothing written. At the thesis's
    dt = 2e-4 s the full inversion's first pseudo-step moves a node 1.03 of its length at
    N = 400 (the relaxation's limit is 1)."""
    out = tmp_path / "run"
    assert main(["run", str(_sweep_scene(tmp_path, 1_000_000)), "--out", str(out)]) == 2
    assert "'membrane.grid_size' = 1000000" in capsys.readouterr().err
    assert main(["run", str(_sweep_scene(tmp_path, 400)), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "'relaxation.dt' = 0.0002 s and 'membrane.grid_size' = 400" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.toml"]


def test_a_grid_with_no_free_node_is_refused(tmp_path, capsys):
    """N = 4 with a clamped rim (two rings held) leaves no node free: one line naming both
    keys, exit 2, nothing written (found by tests/test_fuzz.py: the relaxation's first step
    raised a numpy ValueError)."""
    out = tmp_path / "run"
    assert main(["run", str(_sweep_scene(tmp_path, 4)), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "'membrane.grid_size' = 4 and 'membrane.support' = 'clamped'" in err
    assert "none is free" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.toml"]


def test_a_solver_error_before_the_run_starts_is_one_line(tmp_path, capsys, monkeypatch):
    """A solver's error before a run has recorded anything (here the full inversion's
    relaxation, made to fail) ends with one line and exit 1, and writes nothing."""
    from fsi.procedures import volume_sweep
    from structure.thesis import CourantError

    def fails(setup):
        raise CourantError("pseudo-step 7: a node moved 2 of its length in one step")

    monkeypatch.setattr(volume_sweep, "full_inversion", fails)
    out = tmp_path / "run"
    assert main(["run", str(_sweep_scene(tmp_path, 10)), "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert err.splitlines()[-1] == ("fsi: error: the run could not start: CourantError: "
                                    "pseudo-step 7: a node moved 2 of its length in one step; "
                                    "nothing was written")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.toml"]


def test_show_prints_a_modes_results_headline(tmp_path, capsys):
    """``fsi show`` on a modes result prints, beside its record counts, the table of the
    first lateral mode by fill that the run printed: lambda1, frequency and slosh mass."""
    text = (tmp_path / "modes.toml")
    source = load_scene("modes-by-fill").text
    text.write_text(source.replace("fills = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]",
                                   "fills = [0.5]").replace("cells = 24", "cells = 12"))
    out = tmp_path / "run"
    assert main(["run", str(text), "--out", str(out), "--no-plots"]) == 0
    ran = capsys.readouterr().out
    assert main(["show", str(out)]) == 0
    shown = capsys.readouterr().out
    assert "fills: 1 records" in shown and "lambda1" in shown
    row = next(line for line in shown.splitlines() if line.strip().startswith("0.500"))
    assert row in ran and float(row.split()[1]) == pytest.approx(1.5, abs=0.1)
