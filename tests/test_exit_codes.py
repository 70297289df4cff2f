"""fsi run's exit status says whether everything converged (docs/user-guide/cli.md,
'Exit status')."""
import numpy as np

from fsi.cli import EXIT_NOT_CONVERGED, main, not_converged
from fsi.lifecycle import RunResult
from fsi.io.output import read_result
from fsi.io.plots import fill_label


def test_not_converged_names_each_group_and_attribute():
    result = RunResult(groups={"frames": {"converged": np.array([True, False, True])},
                               "windows": {"converged": np.array([True] * 5)}},
                       attrs={"start_converged": False, "all_converged": True,
                              "windows_not_converged": 4, "flag_converged": np.bool_(False)})
    # a count named *_not_converged is not a flag (the slosh run's windows_not_converged)
    assert not_converged(result) == "1 of 3 frames, start, flag"
    ok = RunResult(groups={"frames": {"converged": np.array([True])}}, attrs={})
    assert not_converged(ok) == ""


def test_a_run_with_an_unconverged_window_exits_3_and_keeps_its_result(tmp_path, capsys):
    """Two coupling iterations cannot converge a window of the bundled fill: the windows are
    accepted, the result is written, the exit status is 3 and stderr says what."""
    scene = tmp_path / "fill.toml"
    scene.write_text("[scene]\nprocedure = 'coupled-fill'\n[dynamics]\nend_time = 0.004\n"
                     "frame_interval = 1\n[coupling]\nmax_iterations = 2\n"
                     "on_max_iterations = 'accept'\n")
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out)]) == EXIT_NOT_CONVERGED == 3
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "not everything converged: 2 of 3 frames, 2 of 2 windows" in err
    res = read_result(out)
    assert not res["windows"]["converged"].any()
    assert fill_label(res["frames"], 1).endswith("NOT CONVERGED")
    assert (out / "plots" / "coupling.png").is_file()


def test_a_window_redone_in_halves_is_recorded_with_its_parts(tmp_path, capsys):
    """on_max_iterations = 'split' with split_depth = 1: each stalled window of the bundled
    fill is redone as two of half its size (each accepting its best iterate): the windows
    group says 2 parts per window and the iterations of both tries, the attribute counts the
    windows split, the run's times stay the windows' ends and the exit status says
    unconverged."""
    scene = tmp_path / "fill.toml"
    scene.write_text("[scene]\nprocedure = 'coupled-fill'\n[dynamics]\nend_time = 0.004\n"
                     "frame_interval = 1\n[coupling]\nmax_iterations = 2\n"
                     "on_max_iterations = 'split'\nsplit_depth = 1\n")
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out)]) == EXIT_NOT_CONVERGED
    assert "redone in halves: 2" in capsys.readouterr().out
    res = read_result(out)
    w = res["windows"]
    assert list(w["window_parts"]) == [2, 2] and res["attrs"]["windows_split"] == 2
    assert np.allclose(w["time"], [0.002, 0.004], rtol=0, atol=1e-15)
    assert (w["coupling_iterations"] >= 2 + 2 * 2).all()
    assert not w["converged"].any()


def test_a_solver_error_mid_run_is_one_line_and_keeps_the_work(tmp_path, capsys, monkeypatch):
    """A Courant failure after the up-front check passed (as a 2000-node-per-side grid does
    after 24 s) stops the run: exit 1, one line, the steps done written, no traceback."""
    import fsi.procedures.thesis_ramp as ramp
    from structure.thesis import CourantError
    from tests.test_runs import RAMP

    calls = {"n": 0}
    real = ramp.step

    def failing(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] > 120:
            raise CourantError("Courant number 1.7 > 1 at node 3: reduce dt (thesis Eqn 4.7)")
        return real(*args, **kwargs)
    monkeypatch.setattr(ramp, "step", failing)
    scene = tmp_path / "ramp.toml"
    scene.write_text(RAMP)
    out = tmp_path / "run"
    capsys.readouterr()
    assert main(["run", str(scene), "--out", str(out)]) == 1
    err = [line for line in capsys.readouterr().err.splitlines() if line.startswith("fsi:")]
    assert len(err) == 1 and "CourantError: Courant number 1.7" in err[0]
    res = read_result(out)
    assert res["attrs"]["solver_failure"] == "CourantError"
    assert len(res["history"]["time"]) == 2  # frames every 50 steps: steps 50 and 100
