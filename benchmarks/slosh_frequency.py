"""First lateral slosh mode of the spherical tank by tank fraction: frequency, damping, slosh
mass, speed.

    python benchmarks/slosh_frequency.py [--fills 0.3 0.5 0.7] [--cells 16 24]
                                         [--limp | --surface limp|linear] [--end-time 5.0]
                                         [--level-plane anywhere|faces]
                                         [--smoke]

Runs the bundled ``slosh-half`` scene (a 0.5 m/s^2 sin^2 lateral pulse over 0.1 s, then
inviscid free decay, 2 ms windows) at each tank fraction V / (4/3 pi R^3) and fluid grid, and
prints one JSON object with, per case, ``lambda1`` = omega^2 R / g, ``frequency_hz``, ``zeta``
(with standard errors), ``slosh_mass_fraction``, ``slosh_mass_height``, ``hinge_height``,
``wall_seconds``, ``seconds_per_period`` and ``reference_error``, lambda1's relative
difference from the reference by fill (``docs/data/sphere_slosh_reference.json``).
``--surface`` picks the surface model: ``limp`` (the default, also ``--limp``: the limp
diaphragm, the moving free surface) or ``linear`` (the same linearised, with
``fluid.convection = "none"``: linear slosh theory's model). With two
grids or more, ``extrapolated`` gives per fill Richardson's value at zero cell size from the
two finest (order 2, the scheme's; with three grids or more also at the observed order of the
three finest, ``observed_order``), and its cost: the two finest runs' wall seconds for five
periods. Anchors at tank fraction 0.5: lambda1 = 1.5602 (rigid
half-full sphere, Budiansky 1960; NASTRAN demo d03031a), and the peer a user would pick for a
bare tank, OpenFOAM interFoam (v1912, this machine, 2 cores): 225 s for five periods at 34,776
cells with lambda1 off by -1.9 %. Writes ``benchmarks/output/slosh_frequency.png`` (lambda1
against tank fraction, one line per grid). A full run's JSON also goes to
``docs/data/slosh_frequency.json`` (``slosh_frequency_linear.json`` with ``--surface
linear``; ``_faces`` appended to the name with ``--level-plane faces``, the runs'
``fluid.level_plane``: the grid with a plane of faces at the level). ``--smoke``:
:data:`SMOKE` (tank fraction 0.5 on 8^3 and 10^3 cells, 20 ms windows, 2.4 s; the figure
under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import logging
from pathlib import Path

from _report import DOCS_DATA, SMOKE_HELP, emit, output_dir
from fluid.tank import tank_spacing
from fsi.setup.build import build
from fsi.constants import TANK_RADIUS
from fsi.analysis.extrapolation import observed_order, richardson
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

FIGURE_NAME = "slosh_frequency.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("cases", "extrapolated", "anchor_lambda1_half", "interfoam")
#: --smoke: the options it sets, and the window (s; the scene's is 2 ms)
SMOKE = dict(fills=[0.5], cells=[8, 10], end_time=2.4)
SMOKE_WINDOW = 0.02

#: Budiansky (1960): lambda1 = omega^2 R / g of the rigid half-full sphere
LAMBDA1_HALF = 1.5602
#: OpenFOAM interFoam v1912 on this machine: wall seconds for five periods, lambda1 error
INTERFOAM = {"seconds_five_periods": 225.0, "lambda1_error": -0.019, "cells": 34776}
KEYS = ("lambda1", "lambda1_std", "frequency_hz", "frequency_hz_std", "zeta", "zeta_std",
        "slosh_mass_fraction", "slosh_mass_height", "hinge_height", "pendulum_length",
        "tank_fraction", "wall_seconds", "seconds_per_period")


#: slosh.surface -> the fluid.convection its runs take (linear theory has no convective term)
SURFACE_CONVECTION = {"limp": "upwind", "linear": "none"}


def run(fill: float, cells: int, end_time: float, surface: str,
        window: float | None = None, level_plane: str = "anywhere") -> dict:
    """The bundled ``slosh-half`` at tank fraction ``fill`` on ``cells``^3 (and
    ``slosh.window``, s, unless None; ``fluid.level_plane``): its numbers."""
    scene = load_scene("slosh-half")
    scene.values["slosh"].update(fill=fill, end_time=end_time, surface=surface)
    if window is not None:
        scene.values["slosh"]["window"] = window
    scene.values["fluid"].update(cells=cells, convection=SURFACE_CONVECTION[surface],
                                 level_plane=level_plane)
    result = PROCEDURES["slosh"](build(scene), lambda fraction, message: None)
    out = dict(fill=fill, cells=cells, surface=surface, level_plane=level_plane)
    out.update({k: result.attrs.get(k) for k in KEYS})
    reference = reference_lambda1(fill)
    if reference is not None and out.get("lambda1") is not None:
        out["reference_error"] = out["lambda1"] / reference - 1
    if result.attrs.get("analysis_failure"):
        out["analysis_failure"] = result.attrs["analysis_failure"]
    return out


def reference_lambda1(fill: float) -> float | None:
    """lambda1 of the rigid sphere at tank fraction ``fill`` from the reference of
    ``docs/data/sphere_slosh_reference.json`` (``benchmarks/sphere_slosh_reference.py``;
    None where it has no such fill)."""
    path = DOCS_DATA / "sphere_slosh_reference.json"
    if not path.exists():
        return None
    row = json.loads(path.read_text())["fills"].get(f"{fill:.1f}")
    return None if row is None or abs(float(f"{fill:.1f}") - fill) > 1e-12 else row["lambda1"]


def extrapolated(cases: list[dict]) -> list[dict]:
    """Per fill with two grids or more: lambda1 at zero cell size (module doc)."""
    out = []
    for fill in sorted({c["fill"] for c in cases}):
        runs = sorted((c for c in cases if c["fill"] == fill and c.get("lambda1") is not None),
                      key=lambda c: c["cells"])
        if len(runs) < 2:
            continue
        h = [tank_spacing(TANK_RADIUS, c["cells"], axisymmetric=False) for c in runs]
        lam = [c["lambda1"] for c in runs]
        entry = dict(fill=fill, cells=[c["cells"] for c in runs[-2:]],
                     lambda1=richardson(lam[-2], lam[-1], h[-2], h[-1], 2.0),
                     seconds_five_periods=sum(5 * c["seconds_per_period"] for c in runs[-2:]))
        if len(runs) >= 3:
            order = observed_order(abs(lam[-3] - lam[-2]), abs(lam[-2] - lam[-1]), h[-3:])
            entry["observed_order"] = order
            if order is not None:
                entry["lambda1_at_observed_order"] = richardson(lam[-2], lam[-1], h[-2],
                                                                h[-1], order)
        if fill == 0.5:
            entry["lambda1_error"] = entry["lambda1"] / LAMBDA1_HALF - 1
        out.append(entry)
    return out


def plot(cases: list[dict], figure: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4))
    for cells in sorted({c["cells"] for c in cases}):
        pts = sorted((c["fill"], c["lambda1"]) for c in cases
                     if c["cells"] == cells and c.get("lambda1") is not None)
        if pts:
            ax.plot(*zip(*pts), "o-", label=f"{cells}$^3$ cells")
    ax.plot([0.5], [LAMBDA1_HALF], "k*", ms=12, label="Budiansky 1960 (half full)")
    ax.set_xlabel("tank fraction V / (4/3 $\\pi$ R$^3$)")
    ax.set_ylabel("$\\lambda_1 = \\omega^2 R / g$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(figure, dpi=90, bbox_inches="tight")
    plt.close(fig)


def json_name(surface: str, level_plane: str = "anywhere") -> str:
    """The name of a full run's ``docs/data`` file: ``slosh_frequency`` for the limp surface,
    ``slosh_frequency_<surface>`` for another, so the two surfaces' runs are kept apart;
    ``_faces`` appended with ``--level-plane faces``."""
    name = "slosh_frequency" if surface == "limp" else f"slosh_frequency_{surface}"
    return name + ("_faces" if level_plane == "faces" else "")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fills", type=float, nargs="+", default=[0.5])
    parser.add_argument("--cells", type=int, nargs="+", default=[24])
    parser.add_argument("--surface", choices=sorted(SURFACE_CONVECTION), default="limp",
                        help="slosh.surface of every run")
    parser.add_argument("--limp", action="store_const", dest="surface", const="limp",
                        help="the limp diaphragm (the moving free surface): --surface limp")
    parser.add_argument("--end-time", type=float, default=5.0, help="simulated seconds")
    parser.add_argument("--level-plane", choices=("anywhere", "faces"), default="anywhere",
                        help="fluid.level_plane of every run")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    figure = output_dir(args.smoke) / FIGURE_NAME
    logging.basicConfig(level=logging.WARNING)
    window = SMOKE_WINDOW if args.smoke else None
    cases = [run(f, c, args.end_time, args.surface, window, args.level_plane)
             for f in args.fills for c in args.cells]
    plot(cases, figure)
    half = [c for c in cases if c["fill"] == 0.5 and c.get("lambda1") is not None]
    for c in half:
        c["lambda1_error"] = c["lambda1"] / LAMBDA1_HALF - 1
        c["seconds_five_periods"] = 5 * c["seconds_per_period"]
        c["ratio_to_interfoam"] = c["seconds_five_periods"] / INTERFOAM["seconds_five_periods"]
    emit(json_name(args.surface, args.level_plane), dict(cases=cases, extrapolated=extrapolated(cases),
                                 anchor_lambda1_half=LAMBDA1_HALF, interfoam=INTERFOAM,
                                 figure=str(figure)), args.smoke)


if __name__ == "__main__":
    main()
