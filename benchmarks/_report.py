"""What every benchmark does with its result: one JSON object on stdout, and for a full run
the same in ``docs/data/<name>.json`` (where the documentation reads it) with the commit and
date it was measured at.

A ``--smoke`` run (the small configuration CI runs, ``tests/test_benchmarks.py``) prints its
JSON the same way but writes nothing into ``docs/data/``, and its figures and side files go to
:func:`output_dir` ``(True)`` (``benchmarks/output/smoke/``) so that a full run's are kept.
"""
from __future__ import annotations

import datetime
import json
import os
import subprocess
import sys
import time
from pathlib import Path

_IMPORTED = time.monotonic()

ROOT = Path(__file__).resolve().parents[1]
OUTPUT = Path(__file__).resolve().parent / "output"
DOCS_DATA = ROOT / "docs" / "data"
SMOKE_HELP = ("smoke test: the same code path on the smallest configuration (seconds); "
              "writes nothing into docs/data")


def output_dir(smoke: bool) -> Path:
    """Where a run writes its figures and side files: ``benchmarks/output`` (full) or
    ``benchmarks/output/smoke``."""
    return OUTPUT / "smoke" if smoke else OUTPUT


def commit() -> str:
    """``git rev-parse --short HEAD`` of the checkout, or "unknown"."""
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                             capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return out.stdout.strip() if out.returncode == 0 and out.stdout.strip() else "unknown"


def command() -> str:
    """The command line that ran this benchmark, as a reader would retype it:
    ``python benchmarks/SCRIPT.py ARGS``."""
    import shlex

    return " ".join(["python", f"benchmarks/{Path(sys.argv[0]).name}",
                     *map(shlex.quote, sys.argv[1:])])


def load_average() -> list:
    """The machine's 1, 5 and 15 min load averages at the end of the run (a timing taken
    beside other work reads high), or [] where the system does not say."""
    try:
        return [round(v, 2) for v in os.getloadavg()]
    except (AttributeError, OSError):
        return []


def wall_seconds() -> float:
    """Seconds since this process started (the whole command's wall time, imports
    included), read from ``/proc``; else since this module was imported."""
    try:
        ticks = os.sysconf("SC_CLK_TCK")
        with open("/proc/self/stat", encoding="ascii") as stat:
            started = int(stat.read().rsplit(")", 1)[1].split()[19]) / ticks
        with open("/proc/uptime", encoding="ascii") as uptime:
            return round(float(uptime.read().split()[0]) - started, 1)
    except (OSError, ValueError, IndexError, AttributeError):
        return round(time.monotonic() - _IMPORTED, 1)


def emit(name: str, record: dict, smoke: bool, *, allow_nan: bool = True) -> None:
    """Print ``record`` as one JSON object on one line of stdout; unless ``smoke``, also write
    it with ``commit``, ``date`` (ISO), the ``command`` that ran it, its ``command_seconds``
    (the whole command's, so the docs say how long a rerun takes) and the ``load_average``
    at its end to ``docs/data/<name>.json``.

    ``name`` is the script's name without ``.py``; ``allow_nan`` as :func:`json.dumps`'s.
    """
    text = json.dumps(record, allow_nan=allow_nan)
    if not smoke:
        DOCS_DATA.mkdir(parents=True, exist_ok=True)
        stamped = {**record, "commit": commit(), "date": datetime.date.today().isoformat(),
                   "command": command(), "command_seconds": wall_seconds(),
                   "load_average": load_average()}
        (DOCS_DATA / f"{name}.json").write_text(
            json.dumps(stamped, indent=1, allow_nan=allow_nan) + "\n")
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


def seconds_by_grid(series: dict, figure: Path, ylabel: str, title: str, extra=None) -> None:
    """Write ``figure``: seconds against membrane grid N on log axes, one line per entry of
    ``series`` (name -> entries with ``grid_size`` and ``seconds``); ``extra(ax)`` draws
    more (markers of goals or failures) before the axes are labelled."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for name, entries in series.items():
        ax.loglog([e["grid_size"] for e in entries], [e["seconds"] for e in entries], "o-",
                  label=name)
    if extra is not None:
        extra(ax)
    ax.set_xlabel("membrane grid N (N x N nodes)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(figure, dpi=100, bbox_inches="tight")
    plt.close(fig)


def profile(function, *args, top: int = 8, **kwargs):
    """Run ``function(*args, **kwargs)`` under :mod:`cProfile`; return its result and the
    ``top`` functions by own time, each ``{"function": "file:line(name)", "seconds": own
    seconds, "share": of the profiled total}``, so a speed figure is printed with where the
    time went. A numba kernel counts as one call of its dispatcher; the profiler's overhead
    falls on Python calls, so time a run without it and profile a second one."""
    import cProfile
    import pstats

    profiler = cProfile.Profile()
    result = profiler.runcall(function, *args, **kwargs)
    stats = pstats.Stats(profiler)
    total = max(stats.total_tt, 1e-300)
    rows = sorted(stats.stats.items(), key=lambda item: item[1][2], reverse=True)[:top]
    table = []
    for (filename, line, name), (_cc, _nc, own, _cum, _callers) in rows:
        short = filename
        for anchor in (str(ROOT) + "/", "site-packages/"):
            if anchor in filename:
                short = filename.split(anchor, 1)[1]
        table.append({"function": f"{short}:{line}({name})", "seconds": round(own, 4),
                      "share": round(own / total, 4)})
    return result, table
