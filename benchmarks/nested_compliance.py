"""One fold state of the diaphragm refined through the membrane grids: its pressure level and
static lateral compliance by grid.

    python benchmarks/nested_compliance.py [--grid-sizes 14 20 26 32 38 54] [--fill 0.5]
                                           [--tilts 0.05 0.01] [--gradient-tolerance 1e-4]
                                           [--chain] [--smoke]

Every grid's own start (``benchmarks/slosh_compliance.py``) is a different fold state, so
its C by grid mixes refinement with the choice of state. Here the ``slosh-diaphragm``
scene's static start is found once, on the first grid (its damped XPBD relaxation, as a
coupled run starts), and carried to each finer grid (:func:`structure.prolongation.prolong`;
with ``--chain`` each grid's minimum is carried to the next instead) where the shell model
polishes it to an exact potential-energy minimum holding the same
liquid volume (:func:`fsi.setup.carried_start.polish`; where that does not converge, again after
2000 of the start's XPBD substeps): the same fold state, refined. On each grid the
contents' static lateral compliance C = d x_c / d b_x (:mod:`fsi.slosh.lateral_compliance`) comes
from two more shell solves under b = (+-tilt, 0, -g) m/s^2 from that minimum.

The shell stops when its largest free-node force is ``--gradient-tolerance`` times the
pressure's force scale rho g R A_node (10 times that counts as converged): a tilt of
0.01 m/s^2 is 1e-3 of g, so the tilted solves resolve it only to about a tenth.

Prints one JSON object: per grid the level (Pa), the start's stretching and bending energies
(J), its area over the rest area, C at each tilt (s^2), the response's asymmetry (s^2: the
two tilted solves' mean displacement over the tilt; as large as C where a tilted solve left
the fold state), C over the free surface's |z_c| / g (the anchor) and the first-mode bound
1 / (2 pi sqrt(C)) (Hz), each solve's convergence and the wall seconds; over the grids whose minimum was found,
the shape against the finest by Eqn 6.1 and, over the last three (h = 1 / (N - 1)), the
observed orders of C and the level and C extrapolated to h = 0 (``grid_study``). Writes
``benchmarks/output/nested_compliance.png``; a full run's JSON also goes to
``docs/data/nested_compliance.json``. ``--smoke``: :data:`SMOKE` (three small grids, one tilt;
the figure under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np

from fsi.setup.build import build
from fsi.setup.carried_start import polish, xpbd_settle
from fsi.analysis.compare import eqn_6_1_error
from fsi.analysis.extrapolation import observed_order, richardson
from fsi.slosh.lateral_compliance import first_mode_bound, free_surface_compliance
from fsi.procedures.slosh_diaphragm import StaticStart, start_compliance, static_start
from fsi.scene import load_scene
from fluid.container import SphericalTank
from structure.model import MembraneState
from structure.prolongation import prolong
from structure.shell import ShellModel, ShellSettings, solve_equilibrium as shell_solve
from structure.xpbd import XpbdModel

from _report import SMOKE_HELP, emit, output_dir
from slosh_compliance import energies, save_figure

FIGURE_NAME = "nested_compliance.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("fill", "tilts", "start_grid", "cases", "grid_study")
#: --smoke: the options it sets
SMOKE = dict(grid_sizes=[6, 8, 10], tilts=[0.05], gradient_tolerance=1e-3)


def _setup(grid_size: int, fill: float):
    return build(load_scene("slosh-diaphragm").with_keys(
        {"membrane": {"grid_size": grid_size}, "slosh": {"fill": fill}}))


def grid_case(setup, start: StaticStart, tilts, settings: ShellSettings) -> tuple:
    """The shell's minimum from ``start`` on the grid of ``setup`` and C at each tilt:
    (its StaticStart, the case's dict)."""
    t0 = time.perf_counter()
    shell = ShellModel.from_membrane(setup.model, settings)
    xpbd = XpbdModel.from_membrane(setup.model)

    def solve(state, load):
        return shell_solve(shell, state, load, settings)

    state, info = polish(setup, start.state.node_position, start.volume,
                         start.info.pressure_level,
                         xpbd_settle(setup, xpbd, start.settings, start.volume), settings)
    polished = StaticStart(xpbd, start.settings, start.volume, state, info)
    seconds_start = time.perf_counter() - t0
    comp = [start_compliance(setup, polished, t, solve) for t in tilts]
    radius = setup.model.radius
    tank = SphericalTank(radius)
    free = free_surface_compliance(tank.centroid_below(tank.level_holding(start.volume)),
                                   -float(setup.liquid.body_acceleration[2]))
    c = comp[-1].compliance
    out = dict(grid_size=int(setup.scene["membrane"]["grid_size"]),
               pressure_level=float(info.pressure_level), start_converged=bool(info.converged),
               start_force_ratio=float(info.force_ratio), **energies(polished),
               compliance=[x.compliance for x in comp], asymmetry=[x.asymmetry for x in comp],
               converged=[x.converged for x in comp], free_surface_compliance=free,
               ratio_to_free_surface=[x.compliance / free for x in comp],
               first_mode_bound_hz=(first_mode_bound(c) / (2 * np.pi) if c > 0 else None),
               seconds_start=seconds_start, seconds=time.perf_counter() - t0)
    return polished, out


def grid_study(cases: list[dict], shapes: dict, faces: dict, radius: float) -> dict:
    """Over the grids whose minimum was found, h = 1 / (N - 1): the shape by Eqn 6.1 against
    the finest (%), and over the last three the observed order of C (the last tilt) and of
    the level, C extrapolated to h = 0 at that order (Richardson) and its first-mode bound."""
    found = [c for c in cases if c["start_converged"]]
    n = [c["grid_size"] for c in found]
    finest = n[-1]
    for c in found:
        c["eqn_6_1_vs_finest"] = eqn_6_1_error(shapes[finest], faces[finest],
                                               shapes[c["grid_size"]], radius)
    if len(found) < 3:
        return dict(grids=n)
    h = [1.0 / (k - 1) for k in n[-3:]]
    comp = [c["compliance"][-1] for c in found[-3:]]
    level = [c["pressure_level"] for c in found[-3:]]
    p_c = observed_order(abs(comp[0] - comp[1]), abs(comp[1] - comp[2]), h)
    out = dict(grids=n, sizes=h, compliance_order=p_c,
               level_order=observed_order(abs(level[0] - level[1]), abs(level[1] - level[2]),
                                          h))
    if p_c is not None:
        c0 = richardson(comp[1], comp[2], h[1], h[2], p_c)
        out.update(compliance_extrapolated=c0,
                   ratio_to_free_surface_extrapolated=c0 / found[-1]["free_surface_compliance"],
                   first_mode_bound_hz_extrapolated=first_mode_bound(c0) / (2 * np.pi))
    return out


def plot(cases: list[dict], tilts, figure: Path) -> None:
    """C / C_free and the level against N, the grids whose minimum was found; the others
    named in the title."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    found = [c for c in cases if c["start_converged"]]
    n = [c["grid_size"] for c in found]
    for k, tilt in enumerate(tilts):
        ax1.plot(n, [c["ratio_to_free_surface"][k] for c in found], "o-",
                 label=f"tilt {tilt:g} m/s²")
    ax1.set_xlabel("membrane grid N")
    ax1.set_ylabel("C / C free surface")
    ax1.legend(fontsize=8)
    ax2.plot(n, [c["pressure_level"] for c in found], "s-")
    ax2.set_xlabel("membrane grid N")
    ax2.set_ylabel("pressure level (Pa)")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
    lost = [c["grid_size"] for c in cases if not c["start_converged"]]
    fig.suptitle(f"Table 4.1 diaphragm, the N = {cases[0]['grid_size']} start's fold state "
                 f"refined" + (f" (no minimum found at N = {lost})" if lost else ""))
    save_figure(fig, figure)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid-sizes", type=int, nargs="+", default=[14, 20, 26, 32, 38, 54])
    parser.add_argument("--fill", type=float, default=0.5, help="tank fraction")
    parser.add_argument("--tilts", type=float, nargs="+", default=[0.05, 0.01],
                        help="lateral body accelerations (m/s^2); the last one is reported")
    parser.add_argument("--gradient-tolerance", type=float, default=1e-4,
                        help="the shell's force tolerance over rho g R A_node")
    parser.add_argument("--window", type=float, default=0.002, help="s: the XPBD substep's")
    parser.add_argument("--chain", action="store_true",
                        help="carry each grid's minimum to the next (default: every grid from "
                             "the first grid's start)")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    figure = output_dir(args.smoke) / FIGURE_NAME
    if sorted(args.grid_sizes) != args.grid_sizes:
        parser.error(f"--grid-sizes must rise, got {args.grid_sizes}")
    logging.basicConfig(level=logging.WARNING)
    settings = ShellSettings(gradient_tolerance=args.gradient_tolerance)
    t0 = time.perf_counter()
    setup = _setup(args.grid_sizes[0], args.fill)
    start = static_start(setup, args.window)
    xpbd_seconds = time.perf_counter() - t0
    first, cases, model, shapes, faces = start, [], setup.model, {}, {}
    for n in args.grid_sizes:
        fine = setup if n == args.grid_sizes[0] else _setup(n, args.fill)
        source = start if args.chain else first
        carried = StaticStart(source.xpbd, source.settings, source.volume, MembraneState(
            prolong(model if args.chain else setup.model, source.state.node_position,
                    fine.model)), source.info)
        start, case = grid_case(fine, carried, args.tilts, settings)
        cases.append(case)
        shapes[n], faces[n] = start.state.node_position, fine.model.face_nodes
        model = fine.model
        print(json.dumps(case), file=sys.stderr, flush=True)
    study = grid_study(cases, shapes, faces, setup.model.radius)
    plot(cases, args.tilts, figure)
    emit("nested_compliance", dict(benchmark="nested_compliance", fill=args.fill,
                                   tilts=args.tilts, gradient_tolerance=args.gradient_tolerance,
                                   start_grid=args.grid_sizes[0], chain=args.chain,
                                   xpbd_start_seconds=xpbd_seconds, figure=str(figure),
                                   cases=cases, grid_study=study), args.smoke)


if __name__ == "__main__":
    main()
