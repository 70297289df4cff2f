"""When to give up on a window's try: the residual histories of a coupled run's tries, and
what stopping a try early would have saved and cost.

A try of a window (``coupling.on_max_iterations = "split"``: the window's first try, or a
part that may still be halved) is scored per iteration by its largest residual over its
tolerance, s_i (below 1: converged). The rule of ``coupling.stall_iterations`` = K and
``coupling.stall_reduction`` = f: the try stops at the first iteration i with

    i - j >= K,   j = the last iteration whose s_j fell below f times the best before it,

and is split. A split window's parts start from the window's start whatever its first try
did, so a try that would have stalled anyway, stopped early, changes only the iterations
spent; a try stopped early that would have converged (a false stop) changes the run.

The run here is the scene with ``stall_iterations = 0`` (every try runs
``max_iterations``), every try's scores recorded; then, for each K and f, the tries that
converged and the rule would have stopped (false stops, and the iterations they had left),
the tries that stalled and the rule stops (caught, and the iterations saved). Prints one
JSON object; the anchor is the run's own iteration count.

    python benchmarks/stall_stop.py [--scene valve-fill] [--end-time S]
        [--stalls 20 25 30 40] [--reductions 0.3 0.5 0.9] [--smoke]

The bundled ``valve-fill`` takes about 14 min. A full run's JSON also goes to
``docs/data/stall_stop.json``. ``--smoke``: the scene's first :data:`SMOKE_WINDOWS` windows
(its tries file under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import time

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from coupling.convergence import StallRule, residual_score
from coupling.scheme import SCHEMES
from fsi.setup.build import build
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("scene", "windows", "windows_split", "tries", "iterations", "wall_seconds",
              "rules")
#: --smoke: windows of the scene run
SMOKE_WINDOWS = 2


def stop_iteration(scores, stall: int, reduction: float):
    """The iteration (1-based) at which the scheme's rule stops a try of ``scores``, or
    None."""
    rule = StallRule(stall, reduction)
    return next((i for i, s in enumerate(scores, 1) if rule(i, s)), None)


def traced_run(scene):
    """Run ``scene`` recording every try of its coupling scheme: (result, tries), each try
    {t, dt, converged, mode, scores}."""
    name = scene["coupling"]["scheme"]
    iterate, tries = SCHEMES[name], []

    def tracing(first, second, settings, acceleration, data, t, dt, window):
        try:
            return iterate(first, second, settings, acceleration, data, t, dt, window)
        finally:
            tries.append(dict(t=t, dt=dt, converged=bool(window.converged),
                              mode=settings.on_max_iterations,
                              scores=[residual_score(settings.measures, r)
                                      for r in window.residuals]))

    SCHEMES[name] = tracing
    try:
        setup = build(scene)
        result = PROCEDURES[scene["scene"]["procedure"]](setup, lambda f, m: None)
    finally:
        SCHEMES[name] = iterate
    return result, tries


def rule_table(tries, stalls, reductions) -> list:
    """For each K in ``stalls`` and f in ``reductions``: what the rule does to the tries
    that could be split (mode ``split``)."""
    splittable = [x for x in tries if x["mode"] == "split"]
    rows = []
    for k in stalls:
        for f in reductions:
            stops = [(x, stop_iteration(x["scores"], k, f)) for x in splittable]
            false = [(x, i) for x, i in stops if x["converged"] and i is not None]
            stalled = [(x, i) for x, i in stops if not x["converged"]]
            rows.append(dict(
                stall_iterations=k, stall_reduction=f, false_stops=len(false),
                their_iterations_left=sum(len(x["scores"]) - i for x, i in false),
                stalled_tries=len(stalled),
                caught=sum(i is not None for _, i in stalled),
                iterations_saved=sum(len(x["scores"]) - i for x, i in stalled
                                     if i is not None)))
    return rows


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default="valve-fill")
    p.add_argument("--end-time", type=float, default=None, help="s (default: the scene's)")
    p.add_argument("--stalls", type=int, nargs="+", default=[20, 25, 30, 40])
    p.add_argument("--reductions", type=float, nargs="+", default=[0.3, 0.5, 0.9])
    p.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = p.parse_args(argv)
    output = output_dir(args.smoke)
    keys = {"coupling": {"stall_iterations": 0}}
    if args.end_time is not None:
        keys["dynamics"] = {"end_time": args.end_time}
    scene = load_scene(args.scene).with_keys(keys)
    if args.smoke:
        scene = scene.with_keys({"dynamics": {
            "end_time": SMOKE_WINDOWS * scene["dynamics"]["window"]}})
    t0 = time.perf_counter()
    result, tries = traced_run(scene)
    seconds = time.perf_counter() - t0
    a = result.attrs
    total = int(np.sum(result.groups["windows"]["coupling_iterations"]))
    rows = rule_table(tries, args.stalls, args.reductions)
    for row in rows:
        row["fraction_saved"] = row["iterations_saved"] / total
    out = dict(scene=args.scene, end_time=float(scene["dynamics"]["end_time"]),
               windows=int(a["windows_done"]), windows_unconverged=int(a["windows_unconverged"]),
               windows_split=int(a["windows_split"]), tries=len(tries),
               tries_split_mode=sum(x["mode"] == "split" for x in tries),
               iterations=total, wall_seconds=seconds, rules=rows)
    output.mkdir(parents=True, exist_ok=True)
    (output / f"stall_stop_{args.scene}_tries.json").write_text(json.dumps(tries))
    emit("stall_stop", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
