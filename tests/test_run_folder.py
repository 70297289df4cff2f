"""The results folder of fsi run (fsi.io.run_folder): checked before anything is computed,
replaced whole with --overwrite, and never half written."""
import os

import pytest

from fsi.cli import main
from tests.test_runs import RAMP


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(RAMP)
    return path


def _no_compute(monkeypatch):
    """Make any procedure call fail loudly: the check must come first."""
    from fsi import registry

    def refuse(self, setup, progress):
        raise AssertionError("computed before the output was checked")
    monkeypatch.setattr(registry.Procedure, "__call__", refuse)


def test_out_on_a_file_or_a_full_folder_is_refused_before_computing(tmp_path, scene, capsys,
                                                                     monkeypatch):
    _no_compute(monkeypatch)
    file = tmp_path / "a-file"
    file.write_text("x")
    assert main(["run", str(scene), "--out", str(file)]) == 2
    full = tmp_path / "full"
    full.mkdir()
    (full / "notes.txt").write_text("mine")
    assert main(["run", str(scene), "--out", str(full)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "is a file" in err[0] and "--overwrite" in err[1]
    assert (full / "notes.txt").read_text() == "mine"


def test_out_where_nothing_can_be_written_is_refused_before_computing(tmp_path, scene,
                                                                      capsys, monkeypatch):
    """Below a file (unwritable for root too), and, for other users, in a read-only folder."""
    _no_compute(monkeypatch)
    file = tmp_path / "a-file"
    file.write_text("x")
    assert main(["run", str(scene), "--out", str(file / "run")]) == 2
    assert "cannot write" in capsys.readouterr().err
    if os.geteuid() != 0:
        locked = tmp_path / "locked"
        locked.mkdir()
        locked.chmod(0o500)
        try:
            assert main(["run", str(scene), "--out", str(locked / "run")]) == 2
        finally:
            locked.chmod(0o700)
        assert "cannot write" in capsys.readouterr().err


def test_overwrite_replaces_the_folder_whole(tmp_path, scene):
    out = tmp_path / "run"
    out.mkdir()
    (out / "stale.png").write_text("an earlier run's plot")
    assert main(["run", str(scene), "--out", str(out), "--no-plots", "--overwrite"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["frames.h5", "frames.xdmf", "result.h5"]
    assert not list(tmp_path.glob(".partial-*")) and not list(tmp_path.glob(".replaced-*"))


def test_a_run_that_dies_while_plotting_leaves_no_folder_but_a_marked_partial(tmp_path, scene,
                                                                              monkeypatch):
    import fsi.io.plots

    def crash(run_dir):
        (run_dir / "plots").mkdir()
        (run_dir / "plots" / "half.png").write_text("")
        raise RuntimeError("killed while plotting")
    monkeypatch.setattr(fsi.io.plots, "make_plots", crash)
    out = tmp_path / "run"
    with pytest.raises(RuntimeError):
        main(["run", str(scene), "--out", str(out)])
    assert not out.exists()
    (partial,) = tmp_path.glob(".partial-run-*")
    assert (partial / "result.h5").is_file()


def test_a_stopped_run_s_checkpoint_in_dir_is_resumed_and_kept_if_stopped_again(tmp_path):
    """--resume finds the checkpoint a run stopped by a signal kept in DIR, stages the
    resumed run anew (DIR is replaced whole at its end), and where that run is stopped again
    before it writes a checkpoint of its own, DIR's checkpoint is carried over, not lost;
    a resumed run that finishes leaves none."""
    from fsi.io.checkpoint import CHECKPOINT_FILE
    from fsi.io.run_folder import RunFolder

    out = tmp_path / "run"
    out.mkdir()
    (out / "result.h5").write_bytes(b"stopped")
    (out / CHECKPOINT_FILE).write_bytes(b"state at window 40")
    folder = RunFolder(out, resume=True)
    assert folder.source == (out / CHECKPOINT_FILE).resolve() and not folder.resumed
    staged = folder.stage()
    assert staged != out.resolve() and staged.name.startswith(".partial-run-")
    (staged / "result.h5").write_bytes(b"stopped again")
    assert folder.commit(keep_checkpoint=True) == out
    assert (out / CHECKPOINT_FILE).read_bytes() == b"state at window 40"
    assert (out / "result.h5").read_bytes() == b"stopped again"
    again = RunFolder(out, resume=True)
    (again.stage() / "result.h5").write_bytes(b"finished")
    again.commit()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]
    assert [p.name for p in out.iterdir()] == ["result.h5"]
