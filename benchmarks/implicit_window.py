"""The bundled diaphragm slosh (``slosh-diaphragm``) by membrane grid and window scheme: the
XPBD window (BDF2, converged sweeps) against the implicit generalised-alpha window (Newton on
the tangent stiffness): wall time, the first mode and the windows left unconverged.

    python benchmarks/implicit_window.py [--grids 14 26 38] [--schemes bdf2 generalised-alpha]
                                         [--end-time 1.5] [--budget 2400] [--merge]
                                         [--smoke]

Each case is the bundled scene with ``membrane.grid_size`` N and ``coupling.time_scheme``
set, run as ``fsi run`` runs it (static start, lateral compliance, 1 ms windows on 16^3
cells, 1.5 s, the first-mode analysis), one after the other on one core. A scheme is not run
on grids beyond the first where it took longer than ``--budget`` seconds. Per scheme and
grid it records ``grid_size``, ``nodes``, ``seconds`` (the whole run), ``start_seconds``
(static start and compliance), ``seconds_per_window``, ``lambda1``, ``frequency_hz``,
``zeta``, ``slosh_mass_fraction``, ``static_compliance`` (s^2), ``coupling_iterations``
(mean per window) and ``windows_unconverged``. Goals (issue's, the generalised-alpha
window): N = 38 in 8 min or less, N = 76 in 30 min. Writes
``benchmarks/output/implicit_window.png`` (seconds against N, the schemes side by side) and
prints one JSON object (a full run also writes it to ``docs/data/implicit_window.json``;
``--merge`` keeps that file's other schemes, so that the schemes can run as two processes
one after the other). ``--smoke``: :data:`SMOKE`.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time

import numpy as np

from _report import DOCS_DATA, SMOKE_HELP, emit, output_dir, seconds_by_grid
from fsi.registry import PROCEDURES
from fsi.scene import load_scene
from fsi.setup.build import build

FIGURE_NAME = "implicit_window.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("end_time", "schemes", "goals_seconds", "ratios")
GOALS_SECONDS = {"38": 480.0, "76": 1800.0}
"""The generalised-alpha window's goals: seconds of the whole run at N."""
SCENE = "slosh-diaphragm"
SCHEMES = ("bdf2", "generalised-alpha")
SMOKE = dict(grids=[6], end_time=0.06, cells=8)


def run_case(grid_size: int, scheme: str, end_time: float, cells: int | None) -> dict:
    keys = {"membrane": {"grid_size": grid_size}, "coupling": {"time_scheme": scheme},
            "slosh": {"end_time": end_time, "analysis_start": min(0.15, 0.2 * end_time)}}
    if cells:
        keys["fluid"] = {"cells": cells}
    setup = build(load_scene(SCENE).with_keys(keys))
    tic = time.perf_counter()
    result = PROCEDURES["slosh"](setup, lambda fraction, message: None)
    seconds = time.perf_counter() - tic
    a, w = result.attrs, result.groups["windows"]
    wall = np.asarray(w["wall_seconds"], dtype=float)
    windows = len(wall)
    start = float(wall[0]) if windows else float("nan")

    def number(key):
        value = a.get(key)
        return None if value is None or not np.isfinite(value) else float(value)

    return dict(grid_size=grid_size, nodes=grid_size * grid_size, seconds=seconds,
                start_seconds=start,
                seconds_per_window=(seconds - start) / max(windows - 1, 1),
                lambda1=number("lambda1"), frequency_hz=number("frequency_hz"),
                zeta=number("zeta"), slosh_mass_fraction=number("slosh_mass_fraction"),
                static_compliance=number("static_compliance"),
                coupling_iterations=float(np.mean(w["coupling_iterations"][1:]))
                if windows > 1 else None,
                windows_unconverged=int(np.sum(~np.asarray(w["converged"][1:], dtype=bool))),
                failure=str(a.get("failure") or ""))


def ratios(schemes: dict) -> dict:
    """Per grid run by both schemes, the generalised-alpha window against the XPBD one:
    ``seconds`` and ``seconds_per_window`` (ratios, -) and ``lambda1_difference`` (relative)."""
    out = {}
    bdf2 = {e["grid_size"]: e for e in schemes.get("bdf2", [])}
    for e in schemes.get("generalised-alpha", []):
        peer = bdf2.get(e["grid_size"])
        if peer is None:
            continue
        out[str(e["grid_size"])] = dict(
            seconds=e["seconds"] / peer["seconds"],
            seconds_per_window=e["seconds_per_window"] / peer["seconds_per_window"],
            lambda1_difference=None if not (e["lambda1"] and peer["lambda1"]) else
            e["lambda1"] / peer["lambda1"] - 1.0)
    return out


def plot(schemes: dict, figure) -> None:
    def goals(ax):
        for n, goal in GOALS_SECONDS.items():
            ax.plot(int(n), goal, "k*", ms=10)

    seconds_by_grid(schemes, figure, "seconds for the run",
                    "slosh-diaphragm by window scheme (stars: goals)", goals)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--schemes", nargs="+", default=list(SCHEMES), choices=SCHEMES)
    parser.add_argument("--grids", type=int, nargs="+", default=[14, 26, 38])
    parser.add_argument("--end-time", type=float, default=1.5, help="simulated seconds")
    parser.add_argument("--budget", type=float, default=2400.0,
                        help="seconds; a scheme stops at the first grid that takes longer")
    parser.add_argument("--merge", action="store_true",
                        help="keep the other schemes of docs/data/implicit_window.json")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    cells = None
    if args.smoke:
        vars(args).update({k: v for k, v in SMOKE.items() if k != "cells"})
        cells = SMOKE["cells"]
    if not args.end_time > 0:
        parser.error(f"--end-time must be > 0 s, got {args.end_time}")
    logging.getLogger("fsi").setLevel(logging.ERROR)
    logging.getLogger("coupling").setLevel(logging.ERROR)
    schemes = {}
    for name in args.schemes:
        schemes[name] = []
        for n in sorted(args.grids):
            print(f"{name} N = {n} ...", file=sys.stderr, end=" ", flush=True)
            entry = run_case(n, name, args.end_time, cells)
            print(f"{entry['seconds']:.1f} s, lambda1 {entry['lambda1']}, zeta "
                  f"{entry['zeta']}, {entry['windows_unconverged']} windows unconverged",
                  file=sys.stderr, flush=True)
            schemes[name].append(entry)
            if entry["seconds"] > args.budget:
                break
    if args.merge and not args.smoke and (DOCS_DATA / "implicit_window.json").is_file():
        # read at the end, so that a run of the other scheme that ended meanwhile is kept
        kept = json.loads((DOCS_DATA / "implicit_window.json").read_text())
        if kept.get("end_time") == args.end_time:
            schemes = {**{k: v for k, v in kept["schemes"].items() if k not in schemes},
                       **schemes}
    figure = output_dir(args.smoke) / FIGURE_NAME
    plot(schemes, figure)
    out = dict(end_time=args.end_time, schemes=schemes, goals_seconds=GOALS_SECONDS,
               ratios=ratios(schemes), figure=str(figure))
    emit("implicit_window", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
