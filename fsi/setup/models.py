"""Structure models a static scene can use, in a registry (scene key ``structure.model``).

Each model solves the membrane's equilibrium holding a liquid volume under the hydrostatic
load of the scene; all share the thesis's grid, masses and fixed rings (:class:`Setup.model`).

* ``thesis`` -- the thesis's particle membrane (bending springs, App. G strain limiting),
  relaxed in pseudo-time (:mod:`structure.statics`).
* ``xpbd`` -- plane-stress membrane (E, nu) with calibrated bending (D = E t^3 / 12 (1 - nu^2))
  as XPBD constraints (:mod:`structure.xpbd`): dynamic substeps with kinetic damping reach
  the volume, then warm-started quasi-static substeps remove the time-step bias.  Where the
  quasi-static polish diverges (compressed, buckling membrane) the damped result is returned
  and marked not converged.
* ``shell`` -- the same membrane and bending energies (or a neo-Hookean membrane), whose
  potential-energy minimum under the volume constraint is found by L-BFGS
  (:mod:`structure.shell`), started from the XPBD relaxation.

* ``minimisation`` -- the XPBD model's energies (the tension field with its residual stiffness
  where the scene's material wrinkles) minimised under the volume constraint by projected
  Newton, the tank wall a smooth barrier (:mod:`structure.minimise`): every fill reached by
  adaptive volume steps from the state before it, through the folds' snaps.

``auto`` picks, at the scene's grid size, the cheapest model whose measured Eqn 6.1 error
(``MODEL_TABLE``, from ``benchmarks/structure_convergence.py``) is within ``structure.accuracy``.
"""
from __future__ import annotations

import logging
import json
from dataclasses import dataclass, replace
from importlib import resources
from typing import Callable, Optional

import numpy as np

from fluid.hydrostatic import HydrostaticLiquid
from structure.load import Load
from structure.minimise import fill_path as minimisation_path
from structure.minimise import inside, minimisation_model, xpbd_terms
from structure.model import MembraneState
from structure.shell import ShellModel, ShellSettings, solve_equilibrium as shell_solve
from structure.statics import solve_equilibrium as thesis_solve
from structure.xpbd import (XpbdDivergence, XpbdModel, XpbdSettings,
                            solve_equilibrium as xpbd_solve)

from fsi.setup.limits import courant_time_step_limit

log = logging.getLogger(__name__)


def hydrostatic_load(liquid: HydrostaticLiquid, volume_target: Optional[float] = None,
                     pressure_level: float = 0.0) -> Load:
    """The membrane's :class:`structure.load.Load` under the hydrostatic ``liquid``: the field
    p = rho b . x, the body acceleration b, the liquid density, and the volume to hold (m^3)
    or the level to hold (Pa, the starting guess with a volume)."""
    return Load(liquid.pressure, liquid.body_acceleration, volume_target=volume_target,
                pressure_level=pressure_level, liquid_density=liquid.density)


@dataclass(frozen=True)
class StructureModel:
    """prepare(setup) -> solver data, built once per run; solve(data, setup, state, load) ->
    (MembraneState, :class:`structure.load.Equilibrium`), the load's volume target held and
    its level the starting guess (Pa)."""

    name: str
    description: str
    prepare: Callable
    solve: Callable


STRUCTURE_MODELS: dict[str, StructureModel] = {}


def register_model(model: StructureModel) -> StructureModel:
    STRUCTURE_MODELS[model.name] = model
    return model


def _thesis_solve(_, setup, state, load: Load):
    # the thesis relaxation finds its level by integral action from zero at every fill
    return thesis_solve(setup.model, state, replace(load, pressure_level=0.0), setup.relaxation)


XPBD_RELAX = XpbdSettings(warm_start=False, tolerance=1e-5, max_steps=20_000)
"""Damped dynamic substeps: robust, reach the volume, in-plane stiffness biased by dt."""
XPBD_POLISH = XpbdSettings(warm_start=True, max_steps=50_000)
"""Warm-started quasi-static substeps: the dt-independent equilibrium where they converge."""
XPBD_COURANT_FRACTION = 0.3
"""Substep as a fraction of the explicit limit of the pressure load (:mod:`fsi.setup.limits`), per
grid: about 1 % stiffness bias (docs/models/continuum-membranes.md, 'XPBD'); the statics'
substep and the dynamics' default."""
XPBD_DYNAMIC_SWEEPS = 64
"""Gauss-Seidel sweeps of the XPBD constraints per substep of a slosh run's diaphragm, its
start included: fewer leave the constraints unconverged, the membrane soft and its folds
elsewhere (half fill, N = 14, 16^3, single damped cosine fitted to x: 4.28 / 6.78 / 7.73 /
7.031 / 7.032 Hz with 1 / 16 / 32 / 64 / 128 sweeps; docs/notes/slosh-diaphragm.md)."""


def statics_substep(setup) -> float:
    """The XPBD substep (s) of the statics: XPBD_COURANT_FRACTION of the explicit limit."""
    return XPBD_COURANT_FRACTION * courant_time_step_limit(setup.model, setup.liquid,
                                                           setup.model.radius)


SHELL_START_STEPS = 3000
"""Damped XPBD substeps at most before the shell's L-BFGS takes over: a start, not a solution
(measured at N = 38: 3.2x faster than relaxing to the XPBD tolerance, every fill converged)."""


def _xpbd_relax(model: XpbdModel, setup, state, load: Load,
                settings: XpbdSettings = XPBD_RELAX):
    """Damped XPBD to the load's volume target; the substep is halved (up to three times) when
    a substep moves a node by more than its length."""
    dt = statics_substep(setup)
    for attempt in range(4):
        try:
            return xpbd_solve(model, state, load, replace(settings, dt=dt))
        except XpbdDivergence as err:
            if attempt == 3:
                raise
            log.info("xpbd relaxation diverged at dt = %.3g s (%s); halving dt", dt, err)
            dt *= 0.5


def _xpbd_solve(model: XpbdModel, setup, state, load: Load):
    relaxed, info = _xpbd_relax(model, setup, state, load)
    try:
        polished, pinfo = xpbd_solve(model, relaxed,
                                     replace(load, pressure_level=info.pressure_level),
                                     replace(XPBD_POLISH, dt=statics_substep(setup)))
    except XpbdDivergence as err:
        log.warning("xpbd: the quasi-static polish diverged (%s); returning the damped "
                    "relaxation, whose in-plane stiffness depends on dt", err)
        return MembraneState(relaxed.node_position), replace(info, converged=False)
    return polished, replace(pinfo, steps=info.steps + pinfo.steps)


def _shell_prepare(setup):
    settings = ShellSettings(law=setup.scene["structure"]["shell_law"])
    xpbd_model = XpbdModel.from_membrane(setup.model)
    return (xpbd_model, ShellModel.from_membrane(setup.model, settings, xpbd_model.bending),
            settings)


def _shell_solve(data, setup, state, load: Load):
    xpbd_model, shell_model, settings = data
    relaxed, info = _xpbd_relax(xpbd_model, setup, state, load,
                                replace(XPBD_RELAX, max_steps=SHELL_START_STEPS))
    out, sinfo = shell_solve(shell_model, relaxed,
                             replace(load, pressure_level=info.pressure_level), settings)
    return out, replace(sinfo, steps=info.steps + sinfo.steps)


def barrier_pressure(setup) -> float:
    """rho max(|b|, 1 m/s^2) R (Pa): the pressure the minimisation's wall barrier is
    calibrated to carry (:func:`structure.minimise.minimisation_model`)."""
    body = float(np.linalg.norm(setup.liquid.body_acceleration))
    return setup.liquid.density * max(body, 1.0) * setup.model.radius


def _minimisation_prepare(setup):
    xpbd = XpbdModel.from_membrane(setup.model)
    return minimisation_model(setup.model, xpbd_terms(xpbd), barrier_pressure(setup))


def _minimisation_solve(data, setup, state, load: Load):
    model, wall = data
    start = MembraneState(inside(wall, state.node_position))
    ((out, info),), report = minimisation_path(model, wall, start, load, [load.volume_target])
    log.info("minimisation: %d iterations in %d volume steps, %d snaps", report.iterations,
             len(report.steps), len(report.snaps))
    return out, info


register_model(StructureModel(
    "thesis", "thesis particle membrane: bending springs + App. G strain limiting",
    lambda setup: None, _thesis_solve))
register_model(StructureModel(
    "xpbd", "XPBD plane-stress membrane + calibrated bending, warm-started statics",
    lambda setup: XpbdModel.from_membrane(setup.model), _xpbd_solve))
register_model(StructureModel(
    "shell", "membrane + calibrated bending, potential-energy minimum (L-BFGS)",
    _shell_prepare, _shell_solve))
register_model(StructureModel(
    "minimisation", "XPBD model's energies, constrained minimum by projected Newton "
    "(barrier wall)", _minimisation_prepare, _minimisation_solve))


MODEL_TABLE_FILE = "model_table.json"


def _load_table() -> dict[str, dict[int, tuple[float, float, bool]]]:
    path = resources.files("fsi.setup").joinpath(MODEL_TABLE_FILE)
    if not path.is_file():
        return {}
    raw = json.loads(path.read_text())
    return {name: {int(n): (float(v["seconds_per_fill"]), float(v["eqn_6_1_error_percent"]),
                            bool(v["all_converged"]))
                   for n, v in grids.items()}
            for name, grids in raw["models"].items()}


MODEL_TABLE: dict[str, dict[int, tuple[float, float, bool]]] = _load_table()
"""{model: {grid_size: (seconds per fill, mean Eqn 6.1 error %, every fill converged)}},
measured by ``benchmarks/structure_convergence.py --write-table`` (``fsi/model_table.json``)."""


def choose_model(requested: str, grid_size: int, accuracy: float) -> str:
    """The model to run: ``requested`` unless it is ``auto``; then the cheapest model in
    :data:`MODEL_TABLE` at ``grid_size`` (the nearest measured grid) that converged there and
    whose error is at most ``accuracy`` (Eqn 6.1 %), or the most accurate converged one when
    none is (among all measured ones when none converged there; the thesis model without a
    table)."""
    if requested != "auto":
        if requested not in STRUCTURE_MODELS:
            raise ValueError(f"unknown structure model {requested!r}; allowed "
                             f"{sorted(STRUCTURE_MODELS)} or 'auto'")
        return requested
    rows, unconverged = [], []
    for name, table in MODEL_TABLE.items():
        if not table:
            continue
        grids = np.array(sorted(table))
        nearest = int(grids[np.argmin(np.abs(grids - grid_size))])
        seconds, error, converged = table[nearest]
        (rows if converged else unconverged).append((seconds, error, name))
    if not rows:
        if not unconverged:
            log.warning("no measured model table (%s); using the thesis model",
                        MODEL_TABLE_FILE)
            return "thesis"
        log.warning("no model converged at every fill of the measured table near N = %d; "
                    "choosing among the unconverged measurements", grid_size)
        rows = unconverged
    meeting = [r for r in rows if r[1] <= accuracy]
    if meeting:
        return min(meeting)[2]
    best = min(rows, key=lambda r: r[1])
    log.warning("no structure model meets %.3g %% at N = %d; using the most accurate, %s "
                "(%.3g %%)", accuracy, grid_size, best[2], best[1])
    return best[2]
