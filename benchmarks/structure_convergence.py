"""Grid convergence and speed against accuracy of every structure model's static sweep.

    python benchmarks/structure_convergence.py [--models thesis xpbd shell]
                                               [--grids 14 20 26 38 54] [--write-table]
                                               [--smoke]

For each model of :data:`fsi.setup.models.STRUCTURE_MODELS` and grid size N of the thesis scene
(clamped hemisphere, hydrostatic water), the model fills the tank by continuation to the same
absolute liquid volumes, TANK_FRACTIONS of the tank volume (4/3) pi R^3.  Each shape is
compared by the thesis's Eqn 6.1 (volume-weighted surface difference, %) with

* the reference: the ``shell`` model (exact potential-energy minimum of the membrane with
  calibrated bending) on the finest grid, when it was run; otherwise the first model's finest;
* the same model's own finest grid (self-convergence), with the observed order between
  successive grids p = log(e_coarse / e_fine) / log(N_fine / N_coarse) (h ~ 1/N).

Writes ``benchmarks/output/structure_convergence.csv`` (one row per model, grid and volume:
seconds, Eqn 6.1 error against the reference and against the model's own finest grid,
converged, mean and largest thesis strain) and ``structure_speed_accuracy.png`` (wall time of
the sweep against its mean Eqn 6.1 error, one point per model and grid; the thesis's own
24,600 s for N = 26 as the anchor) and prints one JSON object.  With ``--write-table`` the
per-fill seconds and mean errors go to ``fsi/model_table.json``, which ``structure.model =
"auto"`` reads.  Compilation is excluded (a small warm-up run per model first).  A full run's
JSON also goes to ``docs/data/structure_convergence.json``.  ``--smoke``: every model on
:data:`SMOKE_GRIDS` (its files under ``benchmarks/output/smoke/``; never the table).
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

from _report import SMOKE_HELP, emit, output_dir
from fsi.setup.build import build
from fsi.analysis.compare import eqn_6_1_error
from fsi.constants import THESIS_RUNTIME_SECONDS
from fsi.setup.models import MODEL_TABLE_FILE, STRUCTURE_MODELS, hydrostatic_load
from fsi.scene import parse_scene
from structure.grid import triangles_from_quads
from structure.model import MembraneState
from structure.statics import strain_error

TANK_FRACTIONS = (0.2, 0.35, 0.5)
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("tank_fractions", "reference", "models", "anchor")
#: --smoke: the grids (three, so that one observed order is measured)
SMOKE_GRIDS = [6, 8, 10]
TABLE = Path(__file__).resolve().parent.parent / "fsi" / "setup" / MODEL_TABLE_FILE


def scene_for(model: str, grid_size: int):
    """The thesis scene as a volume sweep with ``model`` at another grid size."""
    return build(parse_scene(f"[scene]\nprocedure = 'volume-sweep'\n[structure]\n"
                             f"model = '{model}'\n[membrane]\ngrid_size = {grid_size}\n"))


def sweep(model_name: str, grid_size: int) -> dict:
    """Shapes (list of (n, 3) m), seconds, converged flags and strains at TANK_FRACTIONS."""
    setup = scene_for(model_name, grid_size)
    model = STRUCTURE_MODELS[model_name]
    tank = 4.0 / 3.0 * np.pi * setup.model.radius**3
    out = {"shapes": [], "seconds": [], "converged": [], "strain_mean": [], "strain_max": []}
    tic = time.perf_counter()
    data = model.prepare(setup)
    prepare = time.perf_counter() - tic
    state = MembraneState(setup.model.node_rest_position)
    level = 0.0
    for k, fraction in enumerate(TANK_FRACTIONS):
        tic = time.perf_counter()
        state, info = model.solve(data, setup, state,
                                  hydrostatic_load(setup.liquid, fraction * tank, level))
        if np.isfinite(info.pressure_level):
            level = info.pressure_level
        out["seconds"].append(time.perf_counter() - tic + (prepare if k == 0 else 0.0))
        out["shapes"].append(state.node_position.copy())
        out["converged"].append(bool(info.converged))
        mean, worst = strain_error(setup.model, state.node_position)
        out["strain_mean"].append(mean)
        out["strain_max"].append(worst)
    out["faces"] = triangles_from_quads(setup.model.face_nodes)
    out["radius"] = setup.model.radius
    return out


def _errors(run, reference) -> list[float]:
    return [eqn_6_1_error(reference["shapes"][k], reference["faces"], run["shapes"][k],
                          run["radius"]) for k in range(len(TANK_FRACTIONS))]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=list(STRUCTURE_MODELS),
                        choices=list(STRUCTURE_MODELS))
    parser.add_argument("--grids", type=int, nargs="+", default=[14, 20, 26, 38, 54])
    parser.add_argument("--write-table", action="store_true",
                        help=f"write per-fill seconds and mean errors to fsi/{MODEL_TABLE_FILE}")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        args.grids, args.write_table = SMOKE_GRIDS, False
    output = output_dir(args.smoke)
    grids = sorted(args.grids)
    logging.getLogger("fsi").setLevel(logging.ERROR)
    runs: dict[str, dict[int, dict]] = {}
    for name in args.models:
        sweep(name, 6)  # compile the kernels
        runs[name] = {}
        for n in grids:
            tic = time.perf_counter()
            print(f"{name} N = {n} ...", file=sys.stderr, end=" ", flush=True)
            runs[name][n] = sweep(name, n)
            print(f"{time.perf_counter() - tic:.1f} s", file=sys.stderr, flush=True)
    ref_name = "shell" if "shell" in runs else args.models[0]
    reference = runs[ref_name][grids[-1]]
    rows, summary = [], {}
    for name, by_grid in runs.items():
        own = by_grid[grids[-1]]
        summary[name] = {}
        for n in grids:
            run = by_grid[n]
            run["error"] = _errors(run, reference)
            run["self_error"] = _errors(run, own)
            for k, fraction in enumerate(TANK_FRACTIONS):
                rows.append({"model": name, "grid_size": n, "tank_fraction": fraction,
                             "seconds": run["seconds"][k],
                             "eqn_6_1_error_percent": run["error"][k],
                             "self_eqn_6_1_error_percent": run["self_error"][k],
                             "converged": run["converged"][k],
                             "strain_mean": run["strain_mean"][k],
                             "strain_max": run["strain_max"][k]})
            summary[name][n] = {"sweep_seconds": float(np.sum(run["seconds"])),
                                "seconds_per_fill": float(np.mean(run["seconds"])),
                                "eqn_6_1_error_percent": float(np.mean(run["error"])),
                                "self_eqn_6_1_error_percent": float(np.mean(run["self_error"])),
                                "all_converged": all(run["converged"])}
        self_err = {n: summary[name][n]["self_eqn_6_1_error_percent"] for n in grids[:-1]}
        summary[name]["observed_order"] = {
            f"{a}-{b}": float(np.log(self_err[a] / self_err[b]) / np.log(b / a))
            for a, b in zip(grids[:-2], grids[1:-1]) if self_err[a] > 0 and self_err[b] > 0}
    output.mkdir(parents=True, exist_ok=True)
    with open(output / "structure_convergence.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    _plot(grids, summary, ref_name, output / "structure_speed_accuracy.png")
    out = {"tank_fractions": list(TANK_FRACTIONS), "reference": f"{ref_name} N = {grids[-1]}",
           "models": summary, "anchor": {"thesis_seconds_N26": THESIS_RUNTIME_SECONDS}}
    if "thesis" in summary and 26 in grids:
        out["speedup_thesis_N26"] = THESIS_RUNTIME_SECONDS / summary["thesis"][26]["sweep_seconds"]
    if args.write_table:
        write_table(out, grids)
    emit("structure_convergence", out, args.smoke)
    return out


def write_table(out: dict, grids: list[int]) -> None:
    """``fsi/model_table.json`` from a run's JSON ``out`` (grid keys int, or str when read back
    from the printed JSON): per model and grid (the reference point left out) seconds per fill,
    mean Eqn 6.1 error and whether every fill converged."""
    ref_name, ref_grid = out["reference"].split(" N = ")
    keys = ("seconds_per_fill", "eqn_6_1_error_percent", "all_converged")
    table = {"reference": out["reference"], "tank_fractions": out["tank_fractions"],
             "models": {name: {str(n): {k: by_grid[str(n) if str(n) in by_grid else n][k]
                                        for k in keys}
                               for n in grids if not (name == ref_name and n == int(ref_grid))}
                        for name, by_grid in out["models"].items()}}
    TABLE.write_text(json.dumps(table, indent=1) + "\n")


def _plot(grids, summary, ref_name, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    for name, by_grid in summary.items():
        pts = [n for n in grids if not (name == ref_name and n == grids[-1])]
        t = [by_grid[n]["sweep_seconds"] for n in pts]
        e = [by_grid[n]["eqn_6_1_error_percent"] for n in pts]
        line, = ax.loglog(t, e, "-", label=name)
        for n, ti, ei in zip(pts, t, e):
            # filled: every fill converged; open: at least one did not
            ax.plot(ti, ei, "o", color=line.get_color(),
                    markerfacecolor=line.get_color() if by_grid[n]["all_converged"] else "white")
            ax.annotate(f"{n}", (ti, ei), textcoords="offset points", xytext=(4, 4), fontsize=7)
    if "thesis" in summary and 26 in grids:
        ax.scatter([THESIS_RUNTIME_SECONDS], [summary["thesis"][26]["eqn_6_1_error_percent"]],
                   marker="*", s=150, color="k",
                   label="thesis MATLAB time, N = 26 (6 h 50 min), at our thesis-model error")
    ax.set_xlabel("wall time of the sweep (s)")
    ax.set_ylabel(f"Eqn 6.1 error against {ref_name}, N = {grids[-1]} (%)")
    ax.set_title("Speed against accuracy: static sweep to 20, 35, 50 % of the tank\n"
                 "(labels: N; open markers: a fill did not converge)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
