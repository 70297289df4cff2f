"""Checkpoints and resume (fsi.io.checkpoint): a coupled fill killed with SIGKILL, or stopped
with SIGTERM, at a random moment after its first checkpoint, then resumed with --resume, ends
with the arrays of an uninterrupted run, bit for bit (the wall-clock seconds excepted)."""
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from fsi.io.output import read_result

SCENE = """[scene]
name = "ck"
procedure = "coupled-fill"
[dynamics]
end_time = 0.06
frame_interval = 5
checkpoint_interval = 4
"""
TIMING = {"seconds_structure", "seconds_fluid", "wall_seconds", "run_seconds",
          "seconds_per_period"}
FSI = [sys.executable, "-m", "fsi.cli"]


def _reference_and_resumed(tmp_path, scene, max_delay: float, sig=signal.SIGKILL):
    """An uninterrupted run of ``scene`` and one sent ``sig`` up to ``max_delay`` s after its
    first checkpoint, then resumed: the two result folders. SIGKILL leaves no result folder;
    SIGTERM one with the work done and the last checkpoint."""
    ref, out = tmp_path / "ref", tmp_path / "run"
    assert subprocess.run(FSI + ["run", str(scene), "--out", str(ref), "--no-plots"],
                          capture_output=True).returncode == 0
    proc = subprocess.Popen(FSI + ["run", str(scene), "--out", str(out), "--no-plots"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob(".partial-run-*/checkpoint.pkl")):
        assert proc.poll() is None and time.monotonic() < deadline
        time.sleep(0.05)
    time.sleep(random.uniform(0.0, max_delay))  # a random moment after the first checkpoint
    proc.send_signal(sig)
    status = proc.wait()
    if sig == signal.SIGKILL:
        assert not out.exists()
    else:
        assert status == 128 + sig
        assert (out / "result.h5").is_file() and (out / "checkpoint.pkl").is_file()
        assert read_result(out)["attrs"]["interrupted"] == sig
    resumed = subprocess.run(FSI + ["run", str(scene), "--out", str(out), "--no-plots",
                                    "--resume"], capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    return ref, out


def _assert_equal_arrays(ref, out, groups) -> None:
    """The results in folders ``ref`` and ``out`` hold the same ``groups`` and attributes,
    bit for bit (the wall-clock seconds excepted)."""
    a, b = read_result(ref), read_result(out)
    for group in groups:
        assert sorted(a[group]) == sorted(b[group])
        for key in set(a[group]) - TIMING:
            assert np.array_equal(a[group][key], b[group][key],
                                  equal_nan=a[group][key].dtype.kind == "f"), (group, key)
    for key in set(a["attrs"]) - TIMING:
        assert np.array_equal(a["attrs"][key], b["attrs"][key],
                              equal_nan=np.asarray(a["attrs"][key]).dtype.kind == "f"), key


def test_kill_9_then_resume_equals_an_uninterrupted_run(tmp_path):
    scene = tmp_path / "ck.toml"
    scene.write_text(SCENE)
    ref, out = _reference_and_resumed(tmp_path, scene, max_delay=1.0)
    _assert_equal_arrays(ref, out, ("frames", "windows"))
    assert not (out / "checkpoint.pkl").exists() and not list(tmp_path.glob(".partial-*"))


def test_resume_without_a_checkpoint_is_one_line(tmp_path, capsys):
    from fsi.cli import main

    scene = tmp_path / "ck.toml"
    scene.write_text(SCENE)
    assert main(["run", str(scene), "--out", str(tmp_path / "run"), "--resume"]) == 2
    assert "no checkpoint" in capsys.readouterr().err


class _Opens:
    """Unpickled, it creates the file ``path``: what a forged checkpoint could do."""

    def __init__(self, path):
        self.path = str(path)

    def __reduce__(self):
        return (open, (self.path, "w"))


def test_a_checkpoint_this_users_runs_did_not_write_is_refused_unread(tmp_path, capsys,
                                                                    monkeypatch):
    """--resume refuses, before unpickling it, a checkpoint without this user's HMAC (a
    pickle from elsewhere could run code): one line naming the file, exit 2, and the
    forged pickle's code has not run."""
    import pickle

    from fsi.cli import main

    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    scene = tmp_path / "ck.toml"
    scene.write_text(SCENE)
    out = tmp_path / "run"
    out.mkdir()
    marker = tmp_path / "ran"
    (out / "checkpoint.pkl").write_bytes(pickle.dumps({"scene": SCENE, "x": _Opens(marker)}))
    assert main(["run", str(scene), "--out", str(out), "--resume"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "checkpoint.pkl" in err and "HMAC" in err
    assert not marker.exists()


def test_checkpoint_hmac_round_trip_other_key_and_tampering(tmp_path, monkeypatch):
    """A checkpoint reads back under the key that wrote it (made on the first write, mode
    0600); under another user's key, or with one byte of its pickle changed, it is refused."""
    import stat

    from fsi.io import checkpoint

    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "a"))
    path = tmp_path / "checkpoint.pkl"
    checkpoint.write(path, {"k": np.arange(3)})
    assert stat.S_IMODE(checkpoint.key_path().stat().st_mode) == 0o600
    assert np.array_equal(checkpoint.read(path)["k"], np.arange(3))
    blob = bytearray(path.read_bytes())
    blob[-5] ^= 1
    (tmp_path / "tampered.pkl").write_bytes(bytes(blob))
    with pytest.raises(checkpoint.CheckpointRefused, match="tampered.pkl"):
        checkpoint.read(tmp_path / "tampered.pkl")
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "b"))
    with pytest.raises(checkpoint.CheckpointRefused, match="HMAC"):
        checkpoint.read(path)                  # no key of this user's yet
    checkpoint.write(tmp_path / "other.pkl", {})
    with pytest.raises(checkpoint.CheckpointRefused):
        checkpoint.read(path)                  # another key


def test_checkpoints_fall_due_by_count_or_by_wall_time(monkeypatch):
    from fsi.io import checkpoint

    clock = {"t": 100.0}
    monkeypatch.setattr(checkpoint.time, "monotonic", lambda: clock["t"])
    by_count = checkpoint.CheckpointDue(4, 0.0)
    assert [k for k in range(1, 13) if by_count(k)] == [4, 8, 12]
    by_time = checkpoint.CheckpointDue(0, 30.0)
    due = []
    for k in range(1, 13):
        clock["t"] += 10.0  # a window takes 10 s
        if by_time(k):
            due.append(k)
    assert due == [3, 6, 9, 12]
    assert not any(checkpoint.CheckpointDue(0, 0.0)(k) for k in range(1, 20))


def test_the_thesis_ramp_resumes_bit_for_bit_too(tmp_path):
    """The thesis stepper's ramp killed after a checkpoint and resumed: its picked frames and
    history equal an uninterrupted ramp's."""
    from tests.test_runs import RAMP

    scene = tmp_path / "ramp.toml"
    scene.write_text(RAMP.replace("end_time = 0.05", "end_time = 3.0")
                     .replace("frame_interval = 50", "frame_interval = 500\n"
                              "checkpoint_interval = 2000"))
    ref, out = _reference_and_resumed(tmp_path, scene, max_delay=0.5)
    a, b = read_result(ref), read_result(out)
    for group in ("frames", "history"):
        for key in set(a[group]) - TIMING:
            assert np.array_equal(a[group][key], b[group][key],
                                  equal_nan=a[group][key].dtype.kind == "f"), (group, key)


SLOSH = {"limp": """[scene]
procedure = "slosh"
[slosh]
end_time = 1.5
checkpoint_interval = 100
[motion]
kind = "impulse"
amplitude = [0.5, 0.0, 0.0]
duration = 0.1
[fluid]
cells = 12
viscosity = 0.001
""", "diaphragm": """[scene]
procedure = "slosh"
[membrane]
grid_size = 8
[slosh]
surface = "diaphragm"
end_time = 0.1
frame_interval = 5
analysis_start = 0.0
checkpoint_interval = 7
[motion]
kind = "sine"
amplitude = [0.5, 0.0, 0.0]
frequency = 2.0
[fluid]
cells = 10
"""}


@pytest.mark.parametrize("surface, sig", [
    # SIGKILL's resume is the coupled fill's test's too (test_kill_9_then_resume_...)
    pytest.param("limp", signal.SIGKILL, marks=pytest.mark.slow),
    ("diaphragm", signal.SIGTERM)])
def test_slosh_runs_resume_bit_for_bit(tmp_path, surface, sig):
    """A slosh run (either surface model) killed after a checkpoint (SIGKILL), or stopped
    (SIGTERM: the work done written, the last checkpoint kept beside it), and resumed: its
    windows, frames, fitted mode and every attribute equal an uninterrupted run's, and
    nothing of the stopped run is left."""
    scene = tmp_path / "slosh.toml"
    scene.write_text(SLOSH[surface])
    ref, out = _reference_and_resumed(tmp_path, scene, max_delay=0.5, sig=sig)
    _assert_equal_arrays(ref, out, ("frames", "windows", "surface"))
    assert "interrupted" not in read_result(out)["attrs"]
    assert not (out / "checkpoint.pkl").exists() and not list(tmp_path.glob(".partial-*"))


def test_a_resumed_run_counts_the_wall_time_before_its_checkpoint():
    """Wall seconds after a resume (seconds per period, the windows' wall_seconds, the ETA)
    include the run's time before the checkpoint."""
    from fsi.lifecycle import Run

    run = Run(lambda fraction, message: None, 10)
    records = {"windows": [{"time": 0.0}]}
    run.resumed({"groups": records, "elapsed": 100.0})
    assert run.groups is records
    assert 100.0 <= run.elapsed() < 101.0
