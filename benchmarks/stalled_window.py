"""Why a coupled window stalls short of its tolerance: the window run again five ways, and the
liquid's map probed for jumps.

    python benchmarks/stalled_window.py [--scene valve-fill] [--windows 20 84 154] [--as-bundled]
                                        [--smoke]

The coupling iterates x = H(x), H the membrane's window under the node pressures x followed by
the liquid's under the membrane's positions. A window whose residual stops falling short of
the tolerance (a cycle, or a floor) may sit at a jump of H: quasi-Newton steps assume H is
smooth. For each window index K the scene is run to the start of window K with the liquid's
map as it was before the two keys below (``fluid.pressure_fit = "block"``,
``fluid.centre_cells = "iteration"``) and a stalled window's best iterate kept
(``coupling.on_max_iterations = "accept-best"``; all three :data:`BEFORE`; ``--as-bundled``
runs the scene's own), so that the windows that stalled in the valve fill's runs with the
best iterate kept are the windows probed, then window K is run:

* as run up to it;
* with ``fluid.centre_cells = "window"`` (the cells that carry the liquid's velocity held at
  the window start's, :func:`fluid.geometry.hold_liquid_centres`);
* with ``fluid.pressure_fit = "tapered"`` (fit weights that vanish at the block's edge,
  :mod:`fluid.sampling`);
* with both;
* as run, then, as ``coupling.on_max_iterations = "split"`` does, again from its start as
  two windows of half its size, a half that stalls halved again (three times at most).

Each: iterations, whether it converged, its smallest pressure residual and the one it ended
with (the largest of its parts' for a split window) and the windows it was done in. Then,
around the best iterate of the run as run up to it, H is evaluated at x + eps d for random directions d
(|d| = |x|) and eps = 1e-4 ... 1e-8: |H_liquid(x + eps d) - H_liquid(x)| / (eps |x|) stays
constant where the liquid's map is smooth and grows as 1/eps across a jump (the membrane's
positions, the same ratio in m, as a control). Prints one JSON object (about 3 min for the
default windows of the bundled valve fill); a full run also writes it to
``docs/data/stalled_window.json``. ``--smoke``: window :data:`SMOKE_WINDOWS` only.
"""
from __future__ import annotations

import argparse
import logging
import sys
import time
from dataclasses import replace

import cloudpickle
import numpy as np

from _report import SMOKE_HELP, emit
from coupling import advance
from fsi.coupled.adapters import POINTS, PRESSURE
from fsi.setup.build import build
from fsi.lifecycle import Run
from fsi.procedures.coupled_fill import fresh_start
from fsi.scene import load_scene

BEFORE = {"fluid": {"pressure_fit": "block", "centre_cells": "iteration"},
          "coupling": {"on_max_iterations": "accept-best", "stall_iterations": 0}}
"""The liquid's map and the stalled window's handling of the runs whose stalled windows are
probed (the keys' defaults, the best iterate kept after every try's 100 iterations)."""
VARIANTS = {"as run": {}, "centre cells held": {"centre_cells": "window"},
            "tapered fit": {"pressure_fit": "tapered"},
            "both": {"centre_cells": "window", "pressure_fit": "tapered"},
            "split in halves": {"on_max_iterations": "split"}}
"""Variant -> the [fluid] keys (or ``on_max_iterations``) it changes for the window probed."""
EPSILONS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
DIRECTIONS = 6
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("scene", "run_up", "windows", "seconds")
#: --smoke: the window probed
SMOKE_WINDOWS = [1]


def _apply(parts, keys: dict) -> None:
    """The [fluid] ``keys`` of a variant put into the running participants."""
    side = parts.fluid_side
    if "centre_cells" in keys:
        side.centre_cells = keys["centre_cells"]
    if "pressure_fit" in keys:
        side.solver.model = replace(side.solver.model, pressure_fit=keys["pressure_fit"])


def _window(snapshot: bytes, keys: dict, record_inputs: bool = False):
    """Window K from ``snapshot`` under ``keys``: (summary, parts, loop, the node pressures
    given to each iteration when ``record_inputs``, the pressure residual of each iteration,
    the participants' checkpoints at the window's start)."""
    state = cloudpickle.loads(snapshot)
    parts, loop = state["parts"], state["loop"]
    _apply(parts, keys)
    if "on_max_iterations" in keys:
        loop.settings = replace(loop.settings, on_max_iterations=keys["on_max_iterations"])
    membrane, fluid = parts.membrane, parts.fluid_side
    inputs = []
    solve = membrane.solve_window
    if record_inputs:
        def recording(t, dt, data):
            inputs.append(np.array(data[PRESSURE], copy=True))
            return solve(t, dt, data)
        membrane.solve_window = recording
    start = (membrane.store_checkpoint(), fluid.store_checkpoint())
    advance(loop, membrane, fluid)
    membrane.solve_window = solve
    window = loop.log.windows[-1]
    residuals = [r[PRESSURE] for r in window.residuals]
    summary = dict(iterations=window.iterations, converged=bool(window.converged),
                   smallest_pressure_residual=float(min(residuals)),
                   last_pressure_residual=float(window.last_residuals[PRESSURE]),
                   parts=window.parts)
    return summary, parts, loop, inputs, residuals, start


def _jumps(parts, loop, inputs, residuals, start) -> dict:
    """|dH| / eps around the best iterate along random directions: liquid (relative) and
    membrane (m)."""
    membrane, fluid = parts.membrane, parts.fluid_side
    k = loop.k - 1
    t, dt = loop.t0 + k * loop.dt, loop.dt

    def H(p):
        membrane.restore_checkpoint(start[0])
        fluid.restore_checkpoint(start[1])
        out1 = membrane.solve_window(t, dt, {PRESSURE: p})
        return out1[POINTS].copy(), fluid.solve_window(t, dt, out1)[PRESSURE].copy()

    best = inputs[int(np.argmin(residuals[:len(inputs)]))]
    size = float(np.linalg.norm(best))
    x0, y0 = H(best)
    rng = np.random.default_rng(1)
    liquid, structure = [], []
    for _ in range(DIRECTIONS):
        d = rng.normal(size=best.size)
        d *= size / np.linalg.norm(d)
        row_l, row_s = [], []
        for eps in EPSILONS:
            x1, y1 = H(best + eps * d)
            row_l.append(float(np.linalg.norm(y1 - y0) / (eps * size)))
            row_s.append(float(np.linalg.norm(x1 - x0) / eps))
        liquid.append(row_l)
        structure.append(row_s)
    ratio = np.asarray(liquid)
    return dict(epsilons=list(EPSILONS), liquid=liquid, membrane=structure,
                directions_with_a_jump=int(np.sum(ratio.max(axis=1) > 10 * ratio.min(axis=1))))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="valve-fill")
    parser.add_argument("--windows", nargs="+", type=int, default=[20, 84, 154])
    parser.add_argument("--as-bundled", action="store_true",
                        help="run up to the windows with the scene's own [fluid] and "
                        "[coupling] keys")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        args.windows = SMOKE_WINDOWS
    logging.getLogger().setLevel(logging.ERROR)
    scene = load_scene(args.scene)
    setup = build(scene if args.as_bundled else scene.with_keys(BEFORE))
    dyn = setup.scene["dynamics"]
    planned = max(1, int(round(dyn["end_time"] / dyn["window"])))
    run = Run(lambda fraction, message: None, planned, dyn["frame_interval"])
    state = fresh_start(setup, run, planned)
    parts, loop = state["parts"], state["loop"]
    t0 = time.perf_counter()
    out = dict(scene=args.scene, run_up=setup.scene["fluid"], windows={})
    for k in sorted(args.windows):
        while loop.k < k:
            advance(loop, parts.membrane, parts.fluid_side)
        snapshot = cloudpickle.dumps(dict(parts=parts, loop=loop))
        entry = dict(time=float(loop.t0 + (k + 1) * loop.dt))
        for name, keys in VARIANTS.items():
            summary, *rest = _window(snapshot, keys, record_inputs=not keys)
            entry[name] = summary
            if not keys:
                entry["jumps, as run"] = _jumps(*rest)
            print(f"window {k}: {name}: {summary}", file=sys.stderr)
        out["windows"][str(k)] = entry
    out["seconds"] = time.perf_counter() - t0
    emit("stalled_window", out, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
