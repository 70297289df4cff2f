"""Convergence of the coupled fill: membrane grid, window and coupling tolerance, one at a
time, with the observed order.

    python benchmarks/coupled_convergence.py [--end-time 0.02]

The case: the bundled ``diaphragm-fill`` (Table 4.1 diaphragm, start at tank fraction 0.5,
0.5 L/s ramped over 0.1 s, membrane with its inertia) to ``--end-time``.  Varied, the others
at the scene's values (N = 14, 16^3 cells, 2 ms windows, pressure tolerance 1e-4):

* membrane grid N = 14, 20, 26;
* window 4, 2, 1 ms (the XPBD substep follows: at most 0.3 of the explicit limit);
* coupling tolerance (relative pressure change per iteration) 1e-3, 1e-4, 1e-5.

(The fluid grid 16^3, 24^3, 32^3 is ``benchmarks/coupled_fill.py``.)  Reported at the end
time: the pressure level (Pa), the liquid's centre of mass (m) and the shape, by Eqn 6.1 (%)
against the finest member of each family (the membrane grids are compared on the finest
grid's nodes by interpolation, as Eqn 6.1 does); the observed order
p = log(|f1 - f2| / |f2 - f3|) / log(r) for a refinement ratio r (grids: spacing ratio
(N3 - 1) / (N2 - 1) and (N2 - 1) / (N1 - 1), averaged), seconds per run.
Writes ``benchmarks/output/coupled_convergence.json`` and ``.png``; prints one JSON object.
Default run: about 30 s on 2 cores.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from fsi.build import build
from fsi.compare import eqn_6_1_error
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene
from structure.volume import liquid_first_moment, liquid_volume

OUTPUT = Path(__file__).resolve().parent / "output"
FAMILIES = {
    "membrane grid": ("membrane", "grid_size", [14, 20, 26]),
    "window (s)": ("dynamics", "window", [0.004, 0.002, 0.001]),
    "coupling tolerance": ("coupling", "pressure_tolerance", [1e-3, 1e-4, 1e-5]),
}
"""Family -> (scene table, key, values coarse to fine)."""


def run(table: str, key: str, value, end_time: float) -> dict:
    scene = load_scene("diaphragm-fill")
    values = {**scene.values, table: {**scene[table], key: value}}
    values["dynamics"] = {**values["dynamics"], "end_time": end_time,
                          "frame_interval": 100_000}
    setup = build(replace(scene, values=values))
    t0 = time.perf_counter()
    result = PROCEDURES["coupled-fill"](setup, lambda f, m: None)
    x = result.groups["frames"]["node_position"][-1]
    volume = liquid_volume(setup.model, x)
    return dict(value=value, failure=result.attrs["failure"],
                level=float(result.groups["windows"]["pressure_level"][-1]),
                centre=(liquid_first_moment(setup.model, x) / volume).tolist(),
                node_position=x, faces=setup.model.face_nodes, radius=setup.model.radius,
                mean_iterations=float(result.attrs["mean_coupling_iterations"]),
                seconds=time.perf_counter() - t0)


def observed_order(f, ratio: float) -> float | None:
    """p from three values coarse to fine and the refinement ratio."""
    d1, d2 = abs(f[0] - f[1]), abs(f[1] - f[2])
    if not (d1 > 0 and d2 > 0):
        return None
    return float(np.log(d1 / d2) / np.log(ratio))


def family(name: str, end_time: float) -> dict:
    table, key, values = FAMILIES[name]
    runs = [run(table, key, v, end_time) for v in values]
    finest = runs[-1]
    for r in runs:
        r["eqn_6_1_vs_finest"] = eqn_6_1_error(finest["node_position"], finest["faces"],
                                               r["node_position"], finest["radius"])
        r["centre_vs_finest_mm"] = 1e3 * float(np.linalg.norm(np.subtract(r["centre"],
                                                                          finest["centre"])))
    if name == "membrane grid":
        ratio = 0.5 * ((values[2] - 1) / (values[1] - 1) + (values[1] - 1) / (values[0] - 1))
    else:
        ratio = values[0] / values[1]
    out = dict(values=values, ratio=ratio,
               runs=[{k: v for k, v in r.items() if k not in ("node_position", "faces")}
                     for r in runs])
    out["observed_order"] = {
        "level": observed_order([r["level"] for r in runs], ratio),
        "centre_z": observed_order([r["centre"][2] for r in runs], ratio),
        # shape: the differences to the finest, |f1 - f3| and |f2 - f3|
        "shape": (float(np.log(runs[0]["eqn_6_1_vs_finest"] / runs[1]["eqn_6_1_vs_finest"])
                        / np.log(ratio)) if runs[1]["eqn_6_1_vs_finest"] > 0 else None)}
    return out


def plot(result: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(FAMILIES), figsize=(13, 3.8))
    for ax, (name, fam) in zip(axes, result["families"].items()):
        v = fam["values"]
        ax.plot(v, [r["level"] for r in fam["runs"]], "o-", label="level (Pa)")
        ax2 = ax.twinx()
        ax2.plot(v, [r["eqn_6_1_vs_finest"] for r in fam["runs"]], "s--", color="tab:red",
                 label="Eqn 6.1 vs finest (%)")
        ax.set_xscale("log")
        ax.set_xlabel(name)
        ax.set_ylabel("pressure level (Pa)")
        ax2.set_ylabel("Eqn 6.1 against the finest (%)", color="tab:red")
        order = fam["observed_order"]
        ax.set_title(f"order: level {order['level'] or float('nan'):.2f}, "
                     f"shape {order['shape'] or float('nan'):.2f}", fontsize=9)
    fig.suptitle(f"diaphragm-fill at t = {result['end_time']} s")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end-time", type=float, default=0.02)
    parser.add_argument("--families", nargs="+", default=list(FAMILIES))
    args = parser.parse_args(argv)
    logging.getLogger().setLevel(logging.ERROR)
    result = dict(end_time=args.end_time, families={})
    for name in args.families:
        result["families"][name] = family(name, args.end_time)
        print(f"{name}: {result['families'][name]['observed_order']}", file=sys.stderr)
    OUTPUT.mkdir(exist_ok=True)
    (OUTPUT / "coupled_convergence.json").write_text(json.dumps(result, indent=1))
    plot(result, OUTPUT / "coupled_convergence.png")
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
