"""How a sweep scales with Dask workers on this machine: one 9-case sweep run with 1 and
with 2 workers of a ``LocalCluster``.

    python benchmarks/sweep_scaling.py [--workers 1 2] [--cells 16] [--end-time 2.0] [--smoke]

The sweep is the bundled ``slosh-half`` (limp diaphragm, impulse then free decay) at tank
fractions V / (4/3 pi R^3) 0.1 ... 0.9 (9 cases, ``--cells`` per axis, ``--end-time`` s
simulated), run by ``fsi sweep`` (:func:`fsi.sweep.run.run_sweep`) into a new folder per
worker count. Prints one JSON object: per worker count the sweep's wall seconds (cluster
start included), the sum of its cases' own wall seconds, and the speed-up against one worker
beside its anchor, the ideal for whole cases: n / ceil(n / w) for n cases of equal length on
w workers (9 cases on 2 workers: 1.8, the last case runs alone); the cases' mean wall seconds
against one worker's (how much the workers slow each other on shared cores and memory); the
profile of the wall time: the cluster's start (until the first case starts), each worker's
busy seconds and cases, and the seconds a worker stood idle while another still ran; and
whether every count's dataset holds the same first-mode lambda1 (each case runs alone in its
process, so it should, bit for bit). A full run's JSON also goes to
``docs/data/sweep_scaling.json``. ``--smoke``: :data:`SMOKE` and :data:`SMOKE_SWEPT` (two
cases of 8^3 cells, 1.5 s in 20 ms windows, on 1 and 2 workers).
"""
from __future__ import annotations

import argparse
import logging
import math
import tempfile
import time
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit
from fsi.sweep import data as sweep_data
from fsi.sweep.file import parse_sweep
from fsi.sweep.run import run_sweep

SWEEP = """[sweep]
name = "scaling"
scene = "slosh-half"
plot = []
[set]
fluid.cells = {cells}
slosh.end_time = {end_time}{extra}
[vary]
slosh.fill = {{ start = {start}, stop = {stop}, num = {cases} }}
"""
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("cases", "cells", "end_time_s", "runs", "same_results")
#: the tank fractions swept: first, last, number of cases (and no other key set)
SWEPT = dict(start=0.1, stop=0.9, cases=9, extra="")
#: --smoke: the options it sets, and what it sweeps (8^3 cells take tank fractions 0.352 ...
#: 0.648; 20 ms windows, so that 1.5 s, two periods of the first mode, end in 75)
SMOKE = dict(workers=[1, 2], cells=8, end_time=1.5)
SMOKE_SWEPT = dict(start=0.4, stop=0.6, cases=2, extra="\nslosh.window = 0.02")


def profile(records, start: float) -> dict:
    """Where a sweep's wall time went, from its cases' records (start and length, worker):
    the cluster's start until the first case, per worker its cases and busy seconds, and the
    idle seconds of workers done before the last case ended."""
    by_worker: dict = {}
    for r in records:
        by_worker.setdefault(r["pid"], []).append(r)
    ends = {pid: max(r["started"] + r["seconds"] for r in rs) for pid, rs in by_worker.items()}
    return dict(cluster_start_seconds=round(min(r["started"] for r in records) - start, 2),
                worker_cases=sorted(len(rs) for rs in by_worker.values()),
                worker_busy_seconds=sorted(round(sum(r["seconds"] for r in rs), 1)
                                           for rs in by_worker.values()),
                idle_seconds_at_end=round(sum(max(ends.values()) - e for e in ends.values()), 1))


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--cells", type=int, default=16)
    parser.add_argument("--end-time", type=float, default=2.0)
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    logging.basicConfig(level=logging.WARNING)
    import distributed  # noqa: F401  (its logging set up on import; quieted here)

    logging.getLogger("distributed").setLevel(logging.WARNING)
    sweep = parse_sweep(SWEEP.format(cells=args.cells, end_time=args.end_time,
                                     **(SMOKE_SWEPT if args.smoke else SWEPT)), "scaling")
    runs, lambdas = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for workers in args.workers:
            out = Path(tmp) / f"workers-{workers}"
            start, t0 = time.time(), time.perf_counter()
            outcome = run_sweep(sweep, out, workers=workers)
            wall = time.perf_counter() - t0
            dataset = sweep_data.collect(sweep, out)
            lambdas[workers] = dataset["lambda1"].values
            runs[str(workers)] = dict(
                wall_seconds=round(wall, 2),
                case_seconds_sum=round(sum(r["seconds"] for r in outcome.records.values()), 2),
                failed=outcome.failed, **profile(outcome.records.values(), start))
    n, first_run = len(sweep.cases), runs[str(args.workers[0])]
    base = first_run["wall_seconds"] * args.workers[0]
    for workers in args.workers:
        run = runs[str(workers)]
        run["speed_up"] = round(base / run["wall_seconds"], 3)
        run["anchor_ideal_speed_up"] = round(n / math.ceil(n / workers), 3)
        run["case_slowdown"] = round(run["case_seconds_sum"] / first_run["case_seconds_sum"], 3)
    first = lambdas[args.workers[0]]
    report = dict(benchmark="sweep_scaling", cases=len(sweep.cases), cells=args.cells,
                  end_time_s=args.end_time, runs=runs,
                  lambda1=[round(float(x), 6) for x in first],
                  same_results=all(np.array_equal(first, v, equal_nan=True)
                                   for v in lambdas.values()))
    emit("sweep_scaling", report, args.smoke)
    return report


if __name__ == "__main__":
    main()
