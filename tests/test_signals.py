"""SIGINT and SIGTERM during fsi run: the run stops at the end of its current unit of work,
writes what it did with the reason, exits 128 + the signal's number (130, 143) with one line
on stderr and no traceback."""
import signal
import subprocess
import sys
import threading
import time

import pytest

from fsi.io.output import read_result
from tests.test_runs import RAMP

LONG_RAMP = RAMP.replace("end_time = 0.05", "end_time = 50.0")
STARTUP_SECONDS = 120.0
"""The longest wait for the run's progress bar (its signal handlers are set just after)."""


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_stops_the_run_between_steps_and_keeps_the_work(tmp_path, signum, status):
    scene = tmp_path / "long.toml"
    scene.write_text(LONG_RAMP)
    out = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "fsi.cli", "run", str(scene), "--out",
                             str(out)], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                            text=True)
    seen = []  # stderr as it comes (the progress bar has no newlines)
    reader = threading.Thread(target=lambda: seen.extend(iter(lambda: proc.stderr.read(1), "")))
    reader.start()
    deadline = time.monotonic() + STARTUP_SECONDS
    while "%|" not in "".join(seen) and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.1)  # imports and build (slow on a cold clone): until the progress bar
    time.sleep(2.0)  # the first steps
    assert proc.poll() is None, "".join(seen)
    proc.send_signal(signum)
    proc.wait(timeout=60)
    reader.join(timeout=10)
    stderr = "".join(seen)
    assert proc.returncode == status, stderr
    assert "Traceback" not in stderr
    last = stderr.strip().splitlines()[-1]
    assert last.startswith(f"fsi: interrupted by {signal.Signals(signum).name}")
    res = read_result(out)
    assert res["attrs"]["interrupted"] == int(signum)
    assert res["attrs"]["failure"] == f"interrupted by signal {int(signum)}"
    assert len(res["history"]["time"]) > 0 and not (out / "plots").exists()
