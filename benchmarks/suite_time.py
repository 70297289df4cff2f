"""Wall time of the README's test command on a fresh clone: a new clone of this checkout's
HEAD, a new virtual environment, ``pip install -e '.[test]'``, then ``python -m pytest -q``
timed alone (numba's cache cold, as on a fresh machine). The default suite's budget is
BUDGET_SECONDS.

    python benchmarks/suite_time.py [--smoke]

Prints one JSON object (wall seconds of the test command, its summary line, the cores, the
budget and the ratio to it); the documentation's install page reads the full run's
``docs/data/suite_time.json``, written only when the suite passed (a failed or stopped suite
exits with its status and leaves the file as it was). ``--smoke`` times ``pytest -q tests/test_architecture.py`` in
this environment instead (seconds), the same timing and parsing.
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _report import SMOKE_HELP, emit

ROOT = Path(__file__).resolve().parents[1]
BUDGET_SECONDS = 300.0
DOC_FIELDS = ("wall_seconds", "summary", "budget_seconds", "ratio_to_budget", "cores")


THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
"""Removed from the timed command's environment: it runs as a user's shell runs it."""


def timed(command: list[str], cwd: Path) -> tuple[float, str, int]:
    """Run ``command`` in ``cwd`` (the environment without :data:`THREAD_VARIABLES`); its
    wall seconds, pytest's last summary line, exit status."""
    env = {k: v for k, v in os.environ.items() if k not in THREAD_VARIABLES}
    start = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    lines = [line for line in done.stdout.splitlines() if re.search(r"\d+ passed", line)]
    if done.returncode != 0:
        sys.stderr.write(done.stdout[-3000:] + done.stderr[-2000:])
    return wall, (lines[-1].strip("= ") if lines else ""), done.returncode


def fresh_clone(where: Path) -> Path:
    """A clone of HEAD with its own virtual environment and the test extra installed."""
    clone = where / "clone"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    subprocess.run([sys.executable, "-m", "venv", str(clone / ".venv")], check=True)
    subprocess.run([str(clone / ".venv" / "bin" / "pip"), "install", "-q", "-e", ".[test]"],
                   cwd=clone, check=True, capture_output=True)
    return clone


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="suite-time-") as where:
        if args.smoke:
            wall, summary, code = timed([sys.executable, "-m", "pytest", "-q", "-p", "no:xdist",
                                         "-o", "addopts=", "tests/test_architecture.py"], ROOT)
        else:
            clone = fresh_clone(Path(where))
            wall, summary, code = timed([str(clone / ".venv" / "bin" / "python"), "-m",
                                         "pytest", "-q"], clone)
    record = {"wall_seconds": round(wall, 1), "summary": summary, "exit_code": code,
              "budget_seconds": BUDGET_SECONDS, "ratio_to_budget": round(wall / BUDGET_SECONDS, 3),
              "cores": os.cpu_count(), "command": "python -m pytest -q"}
    # a suite that failed or was stopped measured nothing the documentation can quote: its
    # JSON is printed, not written into docs/data
    emit("suite_time", record, args.smoke or code != 0)
    return code


if __name__ == "__main__":
    sys.exit(main())
