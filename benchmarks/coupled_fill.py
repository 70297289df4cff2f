"""Speed against accuracy of the coupled dynamic fill, by fluid grid.

    python benchmarks/coupled_fill.py [--cells 16 24 32] [--windows 10] [--smoke]

Runs the bundled ``diaphragm-fill`` scene (XPBD membrane N = 14, FiPy liquid, IQN-ILS,
0.5 L/s ramped over 0.1 s, port stub 0.06 m x 0.065 m) for its first ``--windows`` windows of
2 ms on each fluid grid, and records the seconds per window, the mean coupling iterations,
the pressure level at the end (Pa) and how far the fluid's cut-cell volume change departs
from the port's delivered volume. The finest grid is the reference of the level. Then the
bundled scene as it is (16^3, all its windows, 0.2 s) for its seconds per window (the whole
run, start equilibrium included, over its windows) and mean coupling iterations; anchor: 0.93 s
per window and 4.7 iterations before the liquid step was assembled directly (the same scene
with FiPy rebuilding its terms every step).

Prints one JSON object and writes ``benchmarks/output/coupled_fill.png`` (level error against
seconds per window, one point per grid). Anchor: the thesis's Fluent-Transient Structural run
of this case did not finish in 4+ weeks; the JSON gives the seconds per simulated second.
A full run's JSON also goes to ``docs/data/coupled_fill.json``. ``--smoke``: 16^3 and 20^3 for
one window, the bundled scene for two (the figure under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from fsi.setup.build import build
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

FIGURE_NAME = "coupled_fill.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("grids", "reference_cells", "bundled_scene", "bundled_anchor",
              "goal_seconds_per_window")
#: --smoke: the grids (the port stub needs 16^3 at least), their windows and the bundled
#: scene's windows
SMOKE_CELLS, SMOKE_WINDOWS, SMOKE_BUNDLED_WINDOWS = [16, 20], 1, 2


#: the bundled scene before the direct assembly: seconds per window, coupling iterations
ANCHOR = {"seconds_per_window": 0.93, "mean_coupling_iterations": 4.7}
#: seconds per window to reach on the bundled scene
GOAL_SECONDS_PER_WINDOW = 0.1


def run(cells: int | None, windows: int | None) -> dict:
    """The bundled scene on ``cells`` per axis for ``windows`` windows (None: as bundled):
    its numbers."""
    scene = load_scene("diaphragm-fill")
    if cells is not None:
        scene.values["fluid"]["cells"] = cells
    if windows is not None:
        scene.values["dynamics"]["end_time"] = windows * scene["dynamics"]["window"]
    setup = build(scene)  # checks the port against the grid
    t0 = time.perf_counter()
    result = PROCEDURES["coupled-fill"](setup, lambda fraction, message: None)
    seconds = time.perf_counter() - t0
    w = result.groups["windows"]
    fluid_change = w["fluid_liquid_volume"][-1] - result.groups["frames"]["fluid_liquid_volume"][0]
    return dict(cells=scene["fluid"]["cells"], windows=int(len(w["time"])), seconds=seconds,
                seconds_per_window=seconds / len(w["time"]),
                seconds_per_simulated_second=seconds / float(w["time"][-1]),
                mean_coupling_iterations=float(np.mean(w["coupling_iterations"])),
                seconds_per_coupling_iteration=seconds / float(np.sum(
                    w["coupling_iterations"])),
                all_converged=bool(np.all(w["converged"])),
                level_end_pa=float(w["pressure_level"][-1]),
                level_start_pa=float(result.attrs["start_pressure_level"]),
                fluid_volume_departure=float(fluid_change / w["delivered_volume"][-1] - 1.0),
                membrane_volume_departure=float(
                    (w["liquid_volume"][-1] - result.attrs["start_volume"])
                    / w["delivered_volume"][-1] - 1.0))


def _plot(rows: list[dict], figure: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ref = rows[-1]
    accel = ref["level_end_pa"] - ref["level_start_pa"]
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for r in rows[:-1]:
        err = abs(r["level_end_pa"] - ref["level_end_pa"]) / accel * 100
        ax.loglog(r["seconds_per_window"], err, "o")
        ax.annotate(f"{r['cells']}$^3$", (r["seconds_per_window"], err),
                    textcoords="offset points", xytext=(5, 5))
    ax.set_xlabel("seconds per 2 ms window")
    ax.set_ylabel(f"level error vs {ref['cells']}$^3$, % of the acceleration pressure")
    ax.set_title("Coupled fill: speed against accuracy by fluid grid")
    ax.grid(True, which="both", alpha=0.3)
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(figure, dpi=110)
    plt.close(fig)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, nargs="+", default=[16, 24, 32])
    parser.add_argument("--windows", type=int, default=10)
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        args.cells, args.windows = SMOKE_CELLS, SMOKE_WINDOWS
    figure = output_dir(args.smoke) / FIGURE_NAME
    logging.basicConfig(level=logging.WARNING)
    rows = [run(c, args.windows) for c in sorted(args.cells)]
    ref = rows[-1]
    for r in rows:
        r["level_difference_from_finest_pa"] = r["level_end_pa"] - ref["level_end_pa"]
    if len(rows) > 1:
        _plot(rows, figure)
    bundled = run(None, SMOKE_BUNDLED_WINDOWS if args.smoke else None)
    bundled["ratio_to_anchor"] = bundled["seconds_per_window"] / ANCHOR["seconds_per_window"]
    bundled["meets_goal"] = bundled["seconds_per_window"] <= GOAL_SECONDS_PER_WINDOW
    out = {"grids": rows, "reference_cells": ref["cells"], "figure": str(figure),
           "bundled_scene": bundled, "bundled_anchor": ANCHOR,
           "goal_seconds_per_window": GOAL_SECONDS_PER_WINDOW,
           "anchor": "thesis Fluent-Transient Structural FSI of this case: not finished in "
                     "4+ weeks (Levine 2014, sec. 4.1.2)"}
    emit("coupled_fill", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
