"""The diaphragm's static lateral compliance by membrane grid: the hydrostatic tier's measure
of what the coupled slosh run's frequency converges to.

    python benchmarks/slosh_compliance.py [--grid-sizes 10 14 20 26] [--fills 0.5]
                                          [--tilts 0.05 0.01] [--window 0.002] [--no-shell]
                                          [--set membrane.youngs_modulus=8.6e5 ...]
                                          [--quasi-static SUBSTEPS] [--smoke]

For each membrane grid N and tank fraction, the ``slosh-diaphragm`` scene's static start
(XPBD, the windows' substeps and sweeps: the fold state a coupled run starts from) is tilted
by b_x = +- tilt and C = d x_c / d b_x of liquid and membrane is measured
(:mod:`fsi.slosh.lateral_compliance`); with the shell model (exact potential-energy minimum)
polished from the same start unless ``--no-shell``. C bounds the first slosh mode,
f1 <= 1 / (2 pi sqrt(C)), and equals the coupled run's sum m_n / (M omega_n^2).
Prints one JSON object: per case C at each tilt, the response's asymmetry, convergence, the
bound (Hz and lambda1 = omega^2 R / g), and the ratio to the free surface's C = |z_c| / g
(the anchor), and the start's stretching and bending energies. ``--set`` changes one scene
key (Young's modulus, density, rim support, wrinkling) to see what sets C. ``--quasi-static``
solves the start and the tilted solves by the warm-started quasi-static XPBD iteration (one
sweep per substep, at most SUBSTEPS substeps each) instead of the coupled run's damped
dynamic substeps: the same equilibria where both converge, much cheaper where a slack
tension-field sheet creeps (its ``converged`` flags say whether the move tolerance was met).
Writes ``benchmarks/output/slosh_compliance.png`` (C / C_free against N); a full run's JSON
also goes to ``docs/data/slosh_compliance.json``. ``--smoke``: :data:`SMOKE` (N = 10, one tilt,
with the shell; the figure under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import logging
import time
import tomllib
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from fsi.setup.build import build
from fsi.slosh.lateral_compliance import first_mode_bound, free_surface_compliance
from fsi.setup.models import statics_substep
from fsi.procedures.coupled_fill import static_equilibrium
from fsi.procedures.slosh_diaphragm import (StaticStart, elastic_energies, start_compliance,
                                            static_start)
from fsi.scene import SceneError, load_scene
from fluid.container import SphericalTank
from structure.shell import ShellModel, ShellSettings, solve_equilibrium as shell_solve
from structure.volume import tank_volume
from structure.xpbd import XpbdModel, XpbdSettings

FIGURE_NAME = "slosh_compliance.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("benchmark", "cases")
#: --smoke: the options it sets
SMOKE = dict(grid_sizes=[10], fills=[0.5], tilts=[0.05])


def _setup(grid_size: int, fill: float, changes: dict):
    keys = {"membrane": {"grid_size": grid_size}, "slosh": {"fill": fill}}
    for key, value in changes.items():
        section, name = key.split(".")
        keys.setdefault(section, {})[name] = value
    try:
        return build(load_scene("slosh-diaphragm").with_keys(keys))
    except SceneError as err:
        raise SystemExit(f"--set: {err}") from None


def _change(text: str) -> tuple:
    """'section.key=value' (the value a TOML scalar) -> (key, value)."""
    key, _, value = text.partition("=")
    if key.count(".") != 1 or not value:
        raise argparse.ArgumentTypeError(f"--set {text!r}: expected section.key=value")
    return key.strip(), tomllib.loads(f"v = {value}")["v"]


def _shell(setup, start, tilts):
    """C of the shell model polished from the XPBD start, at each tilt."""
    shell, settings = ShellModel.from_membrane(setup.model, ShellSettings(),
                                               start.xpbd.bending), ShellSettings()

    def solve(state, load):
        return shell_solve(shell, state, load, settings)

    return [start_compliance(setup, start, t, solve) for t in tilts]


def energies(start) -> dict:
    """The start's stretching and bending energies (J) and its area over the rest area."""
    xp, x = start.xpbd, start.state.node_position
    stretch, bend = elastic_energies(xp, x)
    t = xp.triangles
    area = 0.5 * np.linalg.norm(np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]),
                                axis=1)
    return dict(start_stretch_energy=stretch, start_bending_energy=bend,
                start_area_ratio=float(area.sum() / xp.rest_area.sum()))


def quasi_static_start(setup, substeps: int) -> StaticStart:
    """The start by warm-started quasi-static XPBD from the manufactured shape (one sweep per
    substep at the statics' substep, the scene's slosh.start_tolerance, at most
    ``substeps``); its settings are the tilted solves' too."""
    xpbd = XpbdModel.from_membrane(setup.model)
    settings = XpbdSettings(dt=statics_substep(setup), iterations=1, warm_start=True,
                            tolerance=setup.scene["slosh"]["start_tolerance"],
                            max_steps=substeps)
    volume = setup.scene["slosh"]["fill"] * tank_volume(setup.model.radius)
    state, info = static_equilibrium(setup, xpbd, settings, volume)
    return StaticStart(xpbd, settings, volume, state, info)


def case(grid_size: int, fill: float, tilts, window: float, shell: bool,
         changes: dict, quasi_static: int = 0) -> dict:
    t0 = time.perf_counter()
    setup = _setup(grid_size, fill, changes)
    start = (quasi_static_start(setup, quasi_static) if quasi_static
             else static_start(setup, window))
    xpbd = [start_compliance(setup, start, t) for t in tilts]
    radius = setup.model.radius
    gravity = -float(setup.liquid.body_acceleration[2])
    tank = SphericalTank(radius)
    free = free_surface_compliance(tank.centroid_below(tank.level_holding(start.volume)),
                                   gravity)
    c = xpbd[-1].compliance
    omega = first_mode_bound(c)
    out = dict(grid_size=grid_size, fill=fill, tilts=list(tilts), changes=changes,
               start_solver="quasi-static" if quasi_static else "damped",
               start_converged=bool(start.info.converged),
               start_move_ratio=float(start.info.move_ratio),
               pressure_level=float(start.info.pressure_level),
               compliance=[x.compliance for x in xpbd],
               asymmetry=[x.asymmetry for x in xpbd], converged=[x.converged for x in xpbd],
               free_surface_compliance=free, ratio_to_free_surface=c / free,
               first_mode_bound_hz=omega / (2 * np.pi),
               lambda1_bound=omega**2 * radius / gravity, **energies(start))
    if shell:
        sh = _shell(setup, start, tilts)
        out.update(shell_compliance=[x.compliance for x in sh],
                   shell_asymmetry=[x.asymmetry for x in sh],
                   shell_converged=[x.converged for x in sh])
    out["seconds"] = time.perf_counter() - t0
    return out


def plot(cases: list[dict], figure: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for fill in sorted({c["fill"] for c in cases}):
        rows = [c for c in cases if c["fill"] == fill]
        n = [c["grid_size"] for c in rows]
        ax.plot(n, [c["ratio_to_free_surface"] for c in rows], "o-",
                label=f"XPBD start, tank fraction {fill:g}")
        if "shell_compliance" in rows[0]:
            ax.plot(n, [c["shell_compliance"][-1] / c["free_surface_compliance"] for c in rows],
                    "s--", label=f"shell from it, tank fraction {fill:g}")
    ax.set_xlabel("membrane grid N")
    ax.set_ylabel("C / C free surface")
    ax.set_title("Table 4.1 diaphragm: static lateral compliance")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, figure)


def save_figure(fig, path: Path) -> None:
    """Write ``fig`` to ``path`` (its folder made when missing) and close it."""
    import matplotlib.pyplot as plt
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid-sizes", type=int, nargs="+", default=[10, 14, 20, 26])
    parser.add_argument("--fills", type=float, nargs="+", default=[0.5])
    parser.add_argument("--tilts", type=float, nargs="+", default=[0.05, 0.01],
                        help="lateral body accelerations (m/s^2); the last one is reported")
    parser.add_argument("--window", type=float, default=0.002, help="s: the XPBD substep's")
    parser.add_argument("--no-shell", action="store_true")
    parser.add_argument("--set", type=_change, action="append", default=[],
                        metavar="SECTION.KEY=VALUE",
                        help="change the scene, e.g. membrane.youngs_modulus=8.6e5")
    parser.add_argument("--quasi-static", type=int, default=0, metavar="SUBSTEPS",
                        help="start and tilted solves by warm-started quasi-static XPBD, at "
                             "most SUBSTEPS substeps each (0: the coupled run's damped start)")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    figure = output_dir(args.smoke) / FIGURE_NAME
    if args.quasi_static < 0:
        parser.error(f"--quasi-static must be >= 0 substeps, got {args.quasi_static}")
    logging.basicConfig(level=logging.WARNING)
    changes = dict(args.set)
    cases = [case(n, f, args.tilts, args.window, not args.no_shell, changes, args.quasi_static)
             for f in args.fills for n in args.grid_sizes]
    plot(cases, figure)
    emit("slosh_compliance", dict(benchmark="slosh_compliance", figure=str(figure),
                                  cases=cases), args.smoke)


if __name__ == "__main__":
    main()
