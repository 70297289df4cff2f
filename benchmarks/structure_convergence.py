"""Grid convergence and speed against accuracy of the thesis membrane's static sweep.

    python benchmarks/structure_convergence.py [--grids 14 20 26 38 54]

For each grid size N of the thesis scene (clamped hemisphere, hydrostatic water), the static
solver fills the tank by continuation to the same absolute liquid volumes, TANK_FRACTIONS of
the tank volume (4/3) pi R^3 (not the fill scale, whose 100 % depends on N: the clamped band
that cannot invert shrinks as 1/N). Each shape is compared with the finest grid's by the
thesis's Eqn 6.1 (volume-weighted surface difference, %), and the observed order between
successive grids is p = log(e_coarse / e_fine) / log(N_fine / N_coarse) (h ~ 1/N).

Writes ``benchmarks/output/structure_convergence.csv`` (one row per grid and volume: N, tank
fraction, seconds, Eqn 6.1 error, converged, mean and largest strain) and
``structure_speed_accuracy.png`` (wall time of the sweep against its mean Eqn 6.1 error, one
point per grid; the thesis's own 24,600 s for N = 26 as the anchor), and prints one JSON
object. Compilation is excluded (a small warm-up run first).
"""
from __future__ import annotations

import argparse
import csv
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

from fsi.build import build
from fsi.compare import eqn_6_1_error
from fsi.constants import THESIS_RUNTIME_SECONDS
from fsi.scene import parse_scene
from structure.grid import triangles_from_quads
from structure.model import MembraneState
from structure.statics import solve_equilibrium, strain_error

TANK_FRACTIONS = (0.2, 0.35, 0.5)
OUTPUT = Path(__file__).resolve().parent / "output"


def scene_for(grid_size: int):
    """The bundled thesis-static scene at another grid size."""
    return build(parse_scene(f"[scene]\nprocedure = 'volume-sweep'\n[membrane]\n"
                             f"grid_size = {grid_size}\n"))


def sweep(grid_size: int) -> dict:
    """Shapes (list of (n, 3) m), seconds, converged flags and strains at TANK_FRACTIONS."""
    setup = scene_for(grid_size)
    model, liquid = setup.model, setup.liquid
    tank = 4.0 / 3.0 * np.pi * model.radius**3
    state = MembraneState(model.node_rest_position)
    out = {"shapes": [], "seconds": [], "converged": [], "strain_mean": [], "strain_max": []}
    for fraction in TANK_FRACTIONS:
        tic = time.perf_counter()
        state, info = solve_equilibrium(model, state, liquid.pressure,
                                        liquid.body_acceleration, setup.relaxation,
                                        volume_target=fraction * tank)
        out["seconds"].append(time.perf_counter() - tic)
        out["shapes"].append(state.node_position.copy())
        out["converged"].append(bool(info.converged))
        mean, worst = strain_error(model, state.node_position)
        out["strain_mean"].append(mean)
        out["strain_max"].append(worst)
    out["faces"] = triangles_from_quads(model.face_nodes)
    out["radius"] = model.radius
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", type=int, nargs="+", default=[14, 20, 26, 38, 54])
    args = parser.parse_args(argv)
    grids = sorted(args.grids)
    logging.getLogger("fsi").setLevel(logging.ERROR)
    sweep(6)  # compile the kernels
    runs = {}
    for n in grids:
        print(f"N = {n} ...", file=sys.stderr, flush=True)
        runs[n] = sweep(n)
    finest = runs[grids[-1]]
    rows = []
    for n in grids:
        run = runs[n]
        run["error"] = [eqn_6_1_error(finest["shapes"][k], finest["faces"], run["shapes"][k],
                                      run["radius"]) for k in range(len(TANK_FRACTIONS))]
        for k, fraction in enumerate(TANK_FRACTIONS):
            rows.append({"grid_size": n, "tank_fraction": fraction,
                         "seconds": run["seconds"][k], "eqn_6_1_error_percent": run["error"][k],
                         "converged": run["converged"][k],
                         "strain_mean": run["strain_mean"][k],
                         "strain_max": run["strain_max"][k]})
    OUTPUT.mkdir(exist_ok=True)
    with open(OUTPUT / "structure_convergence.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    mean_error = {n: float(np.mean(runs[n]["error"])) for n in grids}
    seconds = {n: float(np.sum(runs[n]["seconds"])) for n in grids}
    coarse = grids[:-1]
    orders = {f"{a}-{b}": float(np.log(mean_error[a] / mean_error[b]) / np.log(b / a))
              for a, b in zip(coarse[:-1], coarse[1:]) if mean_error[b] > 0}
    _plot(grids, seconds, mean_error)
    out = {"tank_fractions": list(TANK_FRACTIONS), "reference_grid": grids[-1],
           "mean_eqn_6_1_error_percent": mean_error, "sweep_seconds": seconds,
           "observed_order": orders,
           "all_converged": {n: all(runs[n]["converged"]) for n in grids},
           "anchor": {"thesis_seconds_N26": THESIS_RUNTIME_SECONDS},
           "speedup_N26": THESIS_RUNTIME_SECONDS / seconds[26] if 26 in seconds else None}
    print(json.dumps(out, indent=1))
    return out


def _plot(grids, seconds, mean_error) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.5))
    coarse = [n for n in grids[:-1] if mean_error[n] > 0]
    ax.loglog([seconds[n] for n in coarse], [mean_error[n] for n in coarse], "o-",
              label=f"thesis particle model, static solver (vs N = {grids[-1]})")
    for n in coarse:
        ax.annotate(f"N = {n}", (seconds[n], mean_error[n]), textcoords="offset points",
                    xytext=(5, 5))
    if 26 in mean_error and mean_error[26] > 0:
        ax.scatter([THESIS_RUNTIME_SECONDS], [mean_error[26]], marker="*", s=150, color="k",
                   label="thesis MATLAB time, N = 26 (6 h 50 min), at our N = 26 error")
    ax.set_xlabel("wall time of the sweep (s)")
    ax.set_ylabel("Eqn 6.1 error against the finest grid (%)")
    ax.set_title("Speed against accuracy: static sweep")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUTPUT / "structure_speed_accuracy.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
