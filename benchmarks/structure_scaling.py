"""Static equilibrium of the Table 4.1 hemisphere at one tank fraction from its rest shape,
by solver and membrane grid: seconds, iterations and the fitted growth of the cost.

    python benchmarks/structure_scaling.py [--solvers minimisation ...]
                                           [--grids 14 20 26 38] [--fill 0.5]
                                           [--budget 2400] [--residual-grid 38] [--smoke]

Solvers (each from the rest shape to tank fraction ``--fill``, V / (4/3 pi R^3), under the
bundled ``diaphragm-static`` scene's hydrostatic water, compilation excluded by a warm-up on
N = 6):

* ``minimisation``: the minimisation statics (:mod:`structure.minimise`: the wall as a
  barrier, projected Newton with the level as multiplier, adaptive volume steps) on the XPBD
  membrane's full law (plane-stress blocks and calibrated bending);
* ``minimisation_tension_field``: the same on the tension field with its residual stiffness
  (:data:`structure.minimise.RESIDUAL_STIFFNESS` of the full law);
* ``newton``: :func:`structure.newton.statics.fill_path` on the full law with the wall as a
  penalty, volume steps of 0.02 of the tank, SuperLU;
* ``shell``: today's shell model (XPBD start, then L-BFGS in an augmented Lagrangian;
  :mod:`structure.shell`), as ``structure.model = "shell"`` runs it;
* ``xpbd``: today's XPBD statics (damped substeps, then the warm-started polish), as
  ``structure.model = "xpbd"`` runs it.

A solver is not run on grids beyond the first where it took longer than ``--budget``
seconds (40 min). Per solver it records ``grid_size``, ``nodes``, ``seconds``,
``iterations`` (Newton iterations; L-BFGS iterations and substeps for the others), whether
it converged (``converged``; ``reached`` for the minimisation) and the pressure level (Pa;
``pressure_level``, ``level``); the minimisation also its volume ``steps``, rejected steps,
snaps, the median and 90th percentile of iterations per step, and its factorisations and
their seconds, and the end state's static lateral compliance C (s^2, tilts of +-0.01 m/s^2,
each tilted equilibrium by the minimisation). With the tension field, the residual stiffness
e of :data:`RESIDUAL_STIFFNESSES` is studied on ``--residual-grid`` (38): the same run and C
by e (``residual_stiffness``). The minimisation's seconds over the shell's on the same grid
are ``ratio_to_shell``. Each solver's exponent of seconds in nodes is fitted over its
grids. Goals
(:data:`GOALS_SECONDS`, both minimisation laws): N = 38 in 60 s or less, N = 76 in 5 min,
N = 150 in 30 min. Writes ``benchmarks/output/structure_scaling.png`` (seconds against N,
the solvers side by side) and prints one JSON object; a full run also writes it to
``docs/data/structure_scaling.json``, keeping the solvers it did not rerun from the last
run at the same fill (their commits in ``measured_at``). ``--grading START STOP DENSITY``
runs the solvers on the graded grid (:class:`structure.grid.Grading`, the scene keys
``membrane.grading_band`` and ``grading_density``) instead of App. C's: their entries go
under ``graded`` (with ``band`` and ``density``; no residual-stiffness study) and the App. C
solvers are kept as they were. ``--smoke``: :data:`SMOKE`, and the tension field on its
largest grid graded by :data:`SMOKE_GRADING`.
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from _report import DOCS_DATA, SMOKE_HELP, commit, emit, output_dir, seconds_by_grid
from fsi.procedures.slosh_diaphragm import start_compliance
from fsi.scene import load_scene
from fsi.setup.build import build, membrane_model
from fsi.setup.models import STRUCTURE_MODELS, hydrostatic_load
from structure.minimise import fill_path as minimise_fill_path
from structure.minimise import RESIDUAL_STIFFNESS, inside, minimisation_model, xpbd_terms
from structure.model import MembraneState
from structure.newton.statics import NewtonSettings, fill_path
from structure.newton.system import NewtonModel
from structure.volume import tank_volume
from structure.xpbd.model import XpbdModel

FIGURE_NAME = "structure_scaling.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("fill", "solvers", "exponents", "goals_seconds", "measured_at",
              "residual_stiffness", "ratio_to_shell", "graded")
GOALS_SECONDS = {"38": 60.0, "76": 300.0, "150": 1800.0}
"""The minimisation statics' goals, both laws: seconds at N."""
SMOKE = dict(grids=[6, 8], solvers=["newton", "minimisation", "minimisation_tension_field",
                                    "shell", "xpbd"], fill=0.2, residual_grid=6)
RESIDUAL_STIFFNESSES = (1e-3, 3e-3, 1e-2)
"""The tension field's residual stiffnesses e of the study (-)."""
SMOKE_GRADING = {"grading_band": [0.6, 0.85], "grading_density": 3.0}
"""--smoke's graded pass: the tension field on its largest grid with ``--grading 0.6 0.85 3``."""
SCENE = "diaphragm-static"
TILT = 0.01
"""m/s^2: the lateral tilt of the static compliance C (the coupled slosh runs' start's)."""


GRADING = {}
"""The scene's ``membrane`` grading keys of this run (``--grading``; empty: App. C)."""


def _setup(grid_size: int, model: str, membrane: dict = None):
    keys = {"membrane": {"grid_size": grid_size, **(membrane or {})},
            "structure": {"model": model}}
    setup = build(load_scene(SCENE).with_keys(keys))
    if GRADING:   # the sheet alone: the scene's sweep checks its XPBD start, not run here
        scene = setup.scene.with_keys({"membrane": GRADING})
        setup = replace(setup, scene=scene, model=membrane_model(scene))
    return setup


def run_newton(grid_size: int, fill: float) -> dict:
    setup = _setup(grid_size, "xpbd")
    model = NewtonModel.from_xpbd(XpbdModel.from_membrane(setup.model), load_form="energy")
    radius = setup.model.radius
    load = hydrostatic_load(setup.liquid, volume_target=fill * tank_volume(radius))
    tic = time.perf_counter()
    state, eq, report = fill_path(model, MembraneState(setup.model.node_rest_position.copy()),
                                  load, [load.volume_target], NewtonSettings())[-1]
    return dict(seconds=time.perf_counter() - tic, iterations=report.iterations,
                path_steps=report.path_steps, converged=eq.converged,
                pressure_level=eq.pressure_level, force_ratio=eq.force_ratio)


def run_registered(name: str, grid_size: int, fill: float) -> dict:
    setup = _setup(grid_size, name)
    solver = STRUCTURE_MODELS[name]
    radius = setup.model.radius
    load = hydrostatic_load(setup.liquid, volume_target=fill * tank_volume(radius))
    tic = time.perf_counter()
    data = solver.prepare(setup)
    state, eq = solver.solve(data, setup, MembraneState(setup.model.node_rest_position.copy()),
                             load)
    return dict(seconds=time.perf_counter() - tic, iterations=int(eq.steps),
                converged=bool(eq.converged), pressure_level=float(eq.pressure_level),
                force_ratio=float(eq.force_ratio))


def run_minimisation(grid_size: int, fill: float, tension_field: bool = False,
                     residual_stiffness: float = RESIDUAL_STIFFNESS) -> dict:
    """The minimisation statics (:mod:`structure.minimise`) from the rest shape (its free
    nodes moved a tenth of the barrier's gap inside the wall) to ``fill``: the full law, or the
    tension field with its residual stiffness."""
    setup = _setup(grid_size, "xpbd", {"wrinkling": "tension-field"} if tension_field else {})
    radius = setup.model.radius
    load = hydrostatic_load(setup.liquid, volume_target=fill * tank_volume(radius))
    pressure = load.liquid_density * float(np.linalg.norm(load.body_acceleration)) * radius
    terms = xpbd_terms(XpbdModel.from_membrane(setup.model), residual_stiffness)
    model, wall = minimisation_model(setup.model, terms, pressure)
    start = MembraneState(inside(wall, setup.model.node_rest_position))
    tic = time.perf_counter()
    results, report = minimise_fill_path(model, wall, start, load, [load.volume_target])
    seconds = time.perf_counter() - tic
    state, eq = results[-1]
    compliance = None
    if eq.converged:
        compliance = _compliance(setup, model, wall, state, eq, load.volume_target)
    its = report.iterations_per_step()
    return dict(seconds=seconds, iterations=report.iterations, steps=len(report.steps),
                reached=bool(eq.converged), level=float(eq.pressure_level),
                rejected=report.rejected, snaps=len(report.snaps),
                iterations_per_step_median=float(np.median(its)) if its.size else None,
                iterations_per_step_p90=float(np.percentile(its, 90)) if its.size else None,
                factorisations=report.factorisations, factor_seconds=report.factor_seconds,
                force_ratio=float(eq.force_ratio),
                compliance=None if compliance is None else compliance.compliance,
                compliance_converged=None if compliance is None else compliance.converged)


def _compliance(setup, model, wall, state, eq, volume):
    """The end state's static lateral compliance C (s^2) under tilts of +-TILT m/s^2
    (:func:`fsi.procedures.slosh_diaphragm.start_compliance`), each tilted equilibrium by the
    minimisation from the end state at its volume."""
    def solve(start_state, tilted):
        (out,), _ = minimise_fill_path(model, wall, start_state, tilted, [volume])
        return out

    start = SimpleNamespace(state=state, volume=volume, info=eq)
    return start_compliance(setup, start, TILT, solve)


RUNNERS = {"newton": run_newton,
           "minimisation": run_minimisation,
           "minimisation_tension_field": lambda n, f: run_minimisation(n, f, True),
           "shell": lambda n, f: run_registered("shell", n, f),
           "xpbd": lambda n, f: run_registered("xpbd", n, f)}


def exponent(entries: list) -> float | None:
    """Least-squares slope of log seconds against log nodes (None with fewer than two)."""
    if len(entries) < 2:
        return None
    nodes = np.log([e["nodes"] for e in entries])
    seconds = np.log([max(e["seconds"], 1e-6) for e in entries])
    return float(np.polyfit(nodes, seconds, 1)[0])


def plot(solvers: dict, figure) -> None:
    def unconverged(ax):
        for entries in solvers.values():
            for e in entries:
                if not e.get("converged", e.get("reached")):
                    ax.plot(e["grid_size"], e["seconds"], "o", mfc="white", mec="k")

    seconds_by_grid(solvers, figure, "seconds to the equilibrium",
                    "Static equilibrium from the rest shape (open: not converged)", unconverged)


def _with_earlier(solvers: dict, measured_at: dict, fill: float):
    """The solvers of this run, and those of the last full run at the same fill that this one
    did not rerun (their commits kept in ``measured_at``): a rerun of one solver does not drop
    the others' hours of measurements."""
    path = DOCS_DATA / "structure_scaling.json"
    if not path.exists():
        return solvers, measured_at
    earlier = json.loads(path.read_text())
    if earlier.get("fill") != fill:
        return solvers, measured_at
    kept = {k: v for k, v in earlier.get("solvers", {}).items() if k not in solvers}
    at = earlier.get("measured_at") or {k: earlier.get("commit") for k in kept}
    return ({**kept, **solvers},
            {**{k: at.get(k, earlier.get("commit")) for k in kept}, **measured_at})


def _smoke_graded(grid_size: int, fill: float) -> dict:
    """``graded`` of --smoke: the tension field on ``grid_size`` graded by
    :data:`SMOKE_GRADING`."""
    GRADING.update(SMOKE_GRADING)
    try:
        entry = dict(grid_size=grid_size, nodes=grid_size * grid_size,
                     **RUNNERS["minimisation_tension_field"](grid_size, fill))
    finally:
        GRADING.clear()
    return dict(band=SMOKE_GRADING["grading_band"], density=SMOKE_GRADING["grading_density"],
                solvers={"minimisation_tension_field": [entry]}, measured_at={})


def _earlier(fill: float) -> dict:
    """The last full run's JSON at the same fill ({}: none): its ``graded`` entries and
    residual-stiffness study are kept by a run that does not redo them."""
    path = DOCS_DATA / "structure_scaling.json"
    if not path.exists():
        return {}
    earlier = json.loads(path.read_text())
    return earlier if earlier.get("fill") == fill else {}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--solvers", nargs="+", default=list(RUNNERS), choices=list(RUNNERS))
    parser.add_argument("--grids", type=int, nargs="+", default=[14, 20, 26, 38])
    parser.add_argument("--fill", type=float, default=0.5, help="tank fraction to reach")
    parser.add_argument("--budget", type=float, default=2400.0,
                        help="seconds; a solver stops at the first grid that takes longer")
    parser.add_argument("--residual-grid", type=int, default=38,
                        help="the grid of the tension field's residual-stiffness study "
                             "(0: none)")
    parser.add_argument("--grading", nargs=3, type=float, metavar=("START", "STOP", "DENSITY"),
                        help="run on the graded grid (module doc)")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        vars(args).update(SMOKE)
    if args.grading:
        GRADING.update(grading_band=list(args.grading[:2]), grading_density=args.grading[2])
        args.residual_grid = 0
    if not 0.0 < args.fill < 0.79:
        parser.error(f"--fill must be in (0, 0.79) (the full inversion holds 0.79), got "
                     f"{args.fill}")
    logging.getLogger("fsi").setLevel(logging.ERROR)
    logging.getLogger("structure").setLevel(logging.ERROR)
    solvers = {}
    for name in args.solvers:
        RUNNERS[name](6, min(args.fill, 0.1))  # compile the kernels
        solvers[name] = []
        for n in sorted(args.grids):
            print(f"{name} N = {n} ...", file=sys.stderr, end=" ", flush=True)
            entry = dict(grid_size=n, nodes=n * n, **RUNNERS[name](n, args.fill))
            print(f"{entry['seconds']:.1f} s, {entry['iterations']} iterations, converged "
                  f"{entry.get('converged', entry.get('reached'))}", file=sys.stderr, flush=True)
            solvers[name].append(entry)
            if entry["seconds"] > args.budget:
                break
    residual = []
    if args.residual_grid and "minimisation_tension_field" in args.solvers:
        for e in RESIDUAL_STIFFNESSES:
            print(f"tension field e = {e:g}, N = {args.residual_grid} ...", file=sys.stderr,
                  flush=True)
            residual.append(dict(residual_stiffness=e, grid_size=args.residual_grid,
                                 **run_minimisation(args.residual_grid, args.fill, True, e)))
    measured_at = {name: commit() for name in solvers}
    graded = None
    if GRADING:
        graded = dict(band=GRADING["grading_band"], density=GRADING["grading_density"],
                      solvers=solvers, measured_at=measured_at)
        solvers, measured_at = {}, {}
    if args.smoke and graded is None:
        graded = _smoke_graded(max(args.grids), args.fill)
    if not args.smoke:
        solvers, measured_at = _with_earlier(solvers, measured_at, args.fill)
        earlier = _earlier(args.fill)
        graded = graded if graded is not None else earlier.get("graded")
        residual = residual or earlier.get("residual_stiffness", [])
    figure = output_dir(args.smoke) / FIGURE_NAME
    plot(solvers, figure)
    peer = {e["grid_size"]: e["seconds"] for e in solvers.get("shell", [])}
    ratio_to_shell = {name: {str(e["grid_size"]): e["seconds"] / peer[e["grid_size"]]
                             for e in solvers[name] if e["grid_size"] in peer}
                      for name in ("minimisation", "minimisation_tension_field")
                      if name in solvers}
    out = dict(fill=args.fill, solvers=solvers, measured_at=measured_at,
               residual_stiffness=residual, ratio_to_shell=ratio_to_shell,
               exponents={name: exponent(e) for name, e in solvers.items()},
               goals_seconds=GOALS_SECONDS, figure=str(figure))
    if graded is not None:
        out["graded"] = graded
    emit("structure_scaling", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
