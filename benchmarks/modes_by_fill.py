"""The linear slosh modes of the spherical tank by tank fraction, against the reference table.

    python benchmarks/modes_by_fill.py [--fills 0.1 ... 0.9] [--cells 24 32]
                                       [--surface limp] [--smoke]

Runs the bundled ``modes-by-fill`` scene (the ``modes`` procedure: one eigenvalue problem
per fill on the 3-D tank grid, the level a plane of faces) at each tank fraction
V / (4/3 pi R^3) and fluid grid, and prints one JSON object: ``cases``, one per fill and
grid, each {``fill``, ``cells``, ``surface``, ``lambda1``, ``frequency_hz``,
``slosh_mass_fraction``, ``slosh_mass_height``, ``hinge_height``, ``wall_seconds``};
``extrapolated`` per fill, Richardson's value at zero cell size from the two finest grids
(order 2, the scheme's; with three grids or more also the observed order of the three
finest); ``reference``, the table it is checked against (:data:`REFERENCE`, from
``docs/data/sphere_slosh_reference.json``) and each grid's and the extrapolation's error
from it; ``table_seconds`` per grid, the whole table's wall
time; and the time domain's peer at 0.3 and 0.7 (OpenFOAM interFoam, :data:`INTERFOAM`).
Writes ``benchmarks/output/modes_by_fill.png`` (lambda1 and the slosh mass fraction
against tank fraction, each grid, the extrapolation and the reference). A full run's JSON
also goes to ``docs/data/modes_by_fill.json``. ``--smoke``: tank fractions 0.3 and 0.7 on
12^3 and 14^3 cells (the figure under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import logging
import time


from _report import DOCS_DATA, SMOKE_HELP, emit, output_dir
from fluid.tank import tank_spacing
from fsi.analysis.extrapolation import observed_order, richardson
from fsi.constants import TANK_RADIUS
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene
from fsi.setup.build import build

FIGURE_NAME = "modes_by_fill.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("cases", "extrapolated", "reference", "table_seconds", "interfoam")
SMOKE = dict(fills=[0.3, 0.7], cells=[12, 14])
FILLS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]

#: OpenFOAM interFoam v1912 on this machine (castellated sphere, 34,776 cells, 2 cores):
#: lambda1 and wall seconds for five periods of the time domain's free decay
INTERFOAM = [{"fill": 0.3, "lambda1": 1.2924, "seconds_five_periods": 160.0, "cells": 34776},
             {"fill": 0.7, "lambda1": 1.8804, "seconds_five_periods": 110.0, "cells": 34776}]

#: lambda1 = omega^2 R / g of the rigid sphere's first lateral mode by tank fraction: the
#: independent finite-element reference (benchmarks/sphere_slosh_reference.py, 8 digits;
#: Budiansky's 1.5602 at half fill)
_SOURCE = DOCS_DATA / "sphere_slosh_reference.json"
REFERENCE: dict[str, float] = ({k: v["lambda1"] for k, v in
                                json.loads(_SOURCE.read_text())["fills"].items()}
                               if _SOURCE.exists() else {})
REFERENCE_MASS: dict[str, float] = ({k: v["slosh_mass_fraction"] for k, v in
                                     json.loads(_SOURCE.read_text())["fills"].items()}
                                    if _SOURCE.exists() else {})
REFERENCE_SOURCE = "axisymmetric P2 reference (8 digits)"


def run(fill: float, cells: int, surface: str) -> dict:
    """One fill on one grid: the modes procedure's first lateral mode."""
    scene = load_scene("modes-by-fill").with_keys(
        {"modes": {"fills": [fill], "surface": surface}, "fluid": {"cells": cells}})
    setup = build(scene)
    tic = time.perf_counter()
    result = PROCEDURES["modes"](setup, lambda fraction, message: None)
    seconds = time.perf_counter() - tic
    f = result.groups["fills"]
    return dict(fill=fill, cells=cells, surface=surface,
                **{k: float(f[k][0]) for k in ("lambda1", "frequency_hz",
                                                "slosh_mass_fraction", "slosh_mass_height",
                                                "hinge_height")},
                wall_seconds=seconds)


def extrapolate(cases: list[dict], fills, cells) -> dict:
    """Per fill: Richardson's lambda1 from the two finest grids at order 2, and with three
    grids the observed order of the three finest."""
    out = {}
    if len(cells) < 2:
        return out
    h = [tank_spacing(TANK_RADIUS, c, axisymmetric=False) for c in cells]
    for fill in fills:
        lam = [next(c["lambda1"] for c in cases if c["fill"] == fill and c["cells"] == n)
               for n in cells]
        entry = {"lambda1": richardson(lam[-2], lam[-1], h[-2], h[-1], 2.0)}
        if len(cells) >= 3:
            entry["observed_order"] = observed_order(lam[-2] - lam[-3], lam[-1] - lam[-2],
                                                     h[-3:])
        out[str(fill)] = entry
    return out


def figure(cases, extrapolated, fills, cells, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(6.5, 7), sharex=True)
    for n in cells:
        mine = [c for c in cases if c["cells"] == n]
        axes[0].plot([c["fill"] for c in mine], [c["lambda1"] for c in mine], "o-",
                     label=f"modes, {n}$^3$ cells")
        axes[1].plot([c["fill"] for c in mine], [c["slosh_mass_fraction"] for c in mine],
                     "o-", label=f"{n}$^3$ cells")
    if extrapolated:
        axes[0].plot(fills, [extrapolated[str(f)]["lambda1"] for f in fills], "k--",
                     label="Richardson, two finest")
    if REFERENCE:
        keys = sorted(REFERENCE, key=float)
        axes[0].plot([float(k) for k in keys], [REFERENCE[k] for k in keys], "ks", mfc="none",
                     ms=9, label=REFERENCE_SOURCE)
    if REFERENCE_MASS:
        keys = sorted(REFERENCE_MASS, key=float)
        axes[1].plot([float(k) for k in keys], [REFERENCE_MASS[k] for k in keys], "ks",
                     mfc="none", ms=9, label=REFERENCE_SOURCE)
    axes[0].plot([p["fill"] for p in INTERFOAM], [p["lambda1"] for p in INTERFOAM], "rx",
                 ms=9, ls="none", label="OpenFOAM interFoam (time domain)")
    axes[0].set_ylabel("lambda1 = omega$^2$ R / g")
    axes[1].set_ylabel("first slosh mass / liquid mass")
    axes[1].set_xlabel("tank fraction V / (4/3 pi R$^3$)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_title("first lateral slosh mode of the spherical tank")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fills", type=float, nargs="+", default=FILLS)
    parser.add_argument("--cells", type=int, nargs="+", default=[24, 32])
    parser.add_argument("--surface", default="limp")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    fills = SMOKE["fills"] if args.smoke else args.fills
    cells = sorted(SMOKE["cells"] if args.smoke else args.cells)
    cases, table_seconds = [], {}
    for n in cells:
        tic = time.perf_counter()
        cases += [run(fill, n, args.surface) for fill in fills]
        table_seconds[str(n)] = time.perf_counter() - tic
    extrapolated = extrapolate(cases, fills, cells)
    reference = {}
    for fill in fills:
        key = str(fill)
        if key not in REFERENCE:
            continue
        exact = REFERENCE[key]
        errors = {str(c["cells"]): c["lambda1"] / exact - 1 for c in cases if c["fill"] == fill}
        if key in extrapolated:
            errors["extrapolated"] = extrapolated[key]["lambda1"] / exact - 1
        reference[key] = {"lambda1": exact, "error": errors}
    figure(cases, extrapolated, fills, cells, output_dir(args.smoke) / FIGURE_NAME)
    emit("modes_by_fill", dict(cases=cases, extrapolated=extrapolated, reference=reference,
                               reference_source=REFERENCE_SOURCE, table_seconds=table_seconds,
                               interfoam=INTERFOAM, surface=args.surface), args.smoke)


if __name__ == "__main__":
    main()
