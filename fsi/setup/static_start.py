"""How a dynamic run's membrane reaches its static start: the equilibrium holding the start's
liquid volume under the hydrostatic liquid, before the run's own solver puts it at rest under
its windows. A registry (scene keys ``dynamics.start_solver`` and ``slosh.start_solver``).

* ``relaxation`` -- damped XPBD substeps from the manufactured shape at the volume, the
  run's own model and sweeps (:func:`structure.xpbd.solve_equilibrium`): the fold state a
  sudden fill lands in; its cost grows about as N^3 (16 min at N = 38 for half the tank).
* ``minimisation`` -- the minimisation statics (:mod:`structure.minimise`): the tension
  field's fill path (with its residual stiffness) from the rest shape to the volume, then, for
  a membrane that carries compression, the full law minimised at that volume from there. The
  tension field's equilibria converge with the grid (its level at half the tank within 0.7 %
  from N = 76 to 150, docs/notes/minimisation-statics.md), so the start does not depend on
  the grid's fold snaps along the way; about 20 s at N = 38. For the Newton window the nodes
  the wall barrier holds (a tenth of its gap inside) are then put on the wall
  (:func:`on_wall`).
* ``axisymmetric`` -- the shell of revolution's fill from rest to the volume
  (:mod:`structure.axisymmetric`, the scene's membrane on :data:`AXISYMMETRIC_ELEMENTS`
  meridian elements), carried onto the grid (:mod:`structure.axisymmetric.mapping`); where
  that branch is unstable to a harmonic (past the onset of folding) the carried state is
  seeded with the critical harmonic's mode, its largest displacement
  :data:`SEED_AMPLITUDE`, logged and kept with the wave number as the start's
  ``Equilibrium.seed`` (written to the result, :func:`seed_attrs`); then minimised with the
  scene's law at the volume, as the ``minimisation`` start's last stage. Below the onset
  the 3-D sheet then starts on the physical branch; past it, on the fold the axisymmetric
  rung predicts (docs/notes/axisymmetric-onset-vs-3d.md).

Each takes (setup, XPBD model, XPBD settings, volume m^3) and returns (MembraneState,
:class:`structure.load.Equilibrium`); a start that did not converge is logged.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from structure.minimise import DHAT, fill_path, inside, minimisation_model, xpbd_terms
from structure.model import MembraneState
from structure.volume import liquid_volume, tank_volume
from structure.xpbd import XpbdModel, XpbdSettings, solve_equilibrium

from fsi.setup.models import barrier_pressure, hydrostatic_load

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class StartSolver:
    """solve(setup, xpbd_model, settings, volume) -> (MembraneState, Equilibrium);
    ``at_rest``: whether that state is already at rest under the XPBD ``settings``' substeps
    (else a run with XPBD windows settles it there); ``minimises``: whether a start carried
    from a coarser grid is polished by the minimisation statics (:func:`polished`; else by
    the shell model, :func:`fsi.setup.carried_start.polish`)."""

    name: str
    description: str
    solve: Callable
    at_rest: bool
    minimises: bool = False


START_SOLVERS: dict[str, StartSolver] = {}


def register_start(name: str, description: str, at_rest: bool,
                   minimises: bool = False) -> Callable:
    """Decorator: register ``solve`` as the start solver ``name`` (:class:`StartSolver`)."""
    def add(solve: Callable) -> Callable:
        START_SOLVERS[name] = StartSolver(name, description, solve, at_rest, minimises)
        return solve
    return add


def _warn(name: str, volume: float, info) -> None:
    if not info.converged:
        log.warning("static start (%s) at liquid volume %.4g m^3 not converged after %d steps "
                    "(level %.4g Pa): the run starts from a membrane in motion", name, volume,
                    info.steps, info.pressure_level)


def static_equilibrium(setup, model: XpbdModel, settings: XpbdSettings, volume: float,
                       state=None):
    """The membrane's static equilibrium holding the liquid ``volume`` (m^3) under the
    hydrostatic liquid, by damped XPBD at the substep of ``settings`` from ``state`` (the
    manufactured shape when None): (state, Equilibrium); a start that did not converge is
    logged."""
    if state is None:
        state = MembraneState(setup.model.node_rest_position)
    start, info = solve_equilibrium(model, state, hydrostatic_load(setup.liquid, volume),
                                    settings)
    _warn("XPBD", volume, info)
    return start, info


@register_start("relaxation", "damped XPBD substeps from the manufactured shape", True)
def relaxed(setup, model: XpbdModel, settings: XpbdSettings, volume: float):
    """The ``relaxation`` start (module doc)."""
    return static_equilibrium(setup, model, settings, volume)


@register_start("minimisation", "the tension field's fill path from rest by the minimisation "
                "statics, then the full law at the volume", False, minimises=True)
def minimised(setup, model: XpbdModel, settings: XpbdSettings, volume: float):
    """The ``minimisation`` start (module doc); ``settings`` are not used."""
    stages = [True] if model.tension_field else [True, False]
    x, level, iterations, move_in = setup.model.node_rest_position, 0.0, 0, True
    for tension_field in stages:
        state, info, its = _minimum(setup, model, x, level, volume, tension_field, move_in)
        iterations += its
        if not info.converged:
            break
        x, level, move_in = state.node_position, info.pressure_level, False
    info = replace(info, steps=iterations)
    _warn("minimisation", volume, info)
    return state, info


def _minimum(setup, model: XpbdModel, x, level: float, volume: float,
             tension_field: bool | None = None, move_in: bool = True):
    """(state, Equilibrium, Newton iterations): the minimisation statics of ``model``'s
    energies (the tension field's or the full law's by ``tension_field``, the model's own by
    None) from ``x`` (n, 3) m (with ``move_in``, its nodes moved inside the barrier first:
    :func:`structure.minimise.inside`) to ``volume`` (m^3), the level ``level`` (Pa) the
    guess."""
    potential, wall = minimisation_model(setup.model,
                                         xpbd_terms(model, tension_field=tension_field),
                                         barrier_pressure(setup))
    load = hydrostatic_load(setup.liquid, volume_target=volume, pressure_level=level)
    start = MembraneState(inside(wall, x) if move_in else x)
    ((state, info),), report = fill_path(potential, wall, start, load, [volume])
    law = {True: "tension field", False: "full law", None: "its law"}[tension_field]
    log.info("minimisation (%s): %d iterations in %d volume steps, level %.4g Pa", law,
             report.iterations, len(report.steps), info.pressure_level)
    return MembraneState(state.node_position), info, report.iterations


def polished(setup, model: XpbdModel, x, volume: float, level: float):
    """(state, Equilibrium): the minimisation statics of ``model``'s own law from ``x`` (n, 3)
    m, its nodes moved inside the barrier first, to ``volume`` (m^3), the level ``level`` (Pa)
    the guess: a carried start's polish (:mod:`fsi.setup.carried_start`) for the starts that
    minimise (:attr:`StartSolver.minimises`)."""
    state, info, iterations = _minimum(setup, model, x, level, volume)
    info = replace(info, steps=iterations)
    _warn("carried start's polish", volume, info)
    return state, info


def carried_polish(setup, model: XpbdModel, start_solver: str, volume: float):
    """The ``minimised(x, level)`` polish of a start carried from a coarser grid whose start
    solver is ``start_solver`` (:func:`polished` at ``volume`` m^3 for one that minimises;
    None, the shell's polish, for XPBD's relaxation)."""
    if not START_SOLVERS[start_solver].minimises:
        return None
    return lambda x, level: polished(setup, model, x, volume, level)


AXISYMMETRIC_ELEMENTS = 128
"""Meridian elements of the ``axisymmetric`` start's shell of revolution (the onset of folding
moves by 1e-4 of the tank from 96 to 384, docs/notes/axisymmetric-onset-vs-3d.md)."""
AXISYMMETRIC_FILL_STEP = 0.005
"""Tank-fraction spacing of the shell of revolution's fill to the start (-)."""
SEED_AMPLITUDE = 2e-3
"""Largest displacement of the critical harmonic's seed past the onset of folding (m)."""


def _axisymmetric_fill(setup, volume: float):
    """(shell, load, equilibrium) of the scene's membrane as a shell of revolution, filled
    from rest to ``volume`` (m^3); None where its fill stops short."""
    from fsi.setup.shell_of_revolution import AXISYMMETRIC, build
    from structure.axisymmetric import equilibrium, leg

    tables = {name: setup.scene[name] for name in ("tank", "membrane", "structure", "liquid")}
    tables["axisymmetric"] = {name: key.default for name, key in AXISYMMETRIC.items()}
    shell, load = build(tables, elements=AXISYMMETRIC_ELEMENTS)
    fraction = volume / tank_volume(setup.model.radius)
    steps = np.union1d(np.arange(0.0, fraction, AXISYMMETRIC_FILL_STEP), [fraction])
    fill = leg(shell, load, equilibrium(shell, load), steps)
    last = fill.states[-1]
    return None if last is None else (shell, load, last.equilibrium)


@register_start("axisymmetric", "the shell of revolution's fill carried onto the grid (seeded "
                "with its critical harmonic past the onset of folding), then minimised",
                False, minimises=True)
def carried_axisymmetric(setup, model: XpbdModel, settings: XpbdSettings, volume: float):
    """The ``axisymmetric`` start (module doc); ``settings`` are not used."""
    from structure.axisymmetric.harmonics import stability
    from structure.axisymmetric.mapping import surface_points

    found = _axisymmetric_fill(setup, volume)
    if found is None:
        log.warning("the shell of revolution's fill stopped short of %.4g m^3: the "
                    "minimisation start instead", volume)
        return minimised(setup, model, settings, volume)
    shell, load, axi = found
    table = stability(shell, axi.state, load.liquid_density * load.gravity,
                      axi.pressure - axi.pressure_level)
    mode, n, amplitude = None, 0, 0.0
    if not table.stable:
        n = int(table.critical)
        mode = table.modes[list(table.wave_numbers).index(n)]
        mode = mode * np.sign(mode[np.argmax(np.abs(mode))])
        amplitude = SEED_AMPLITUDE / float(np.abs(mode.reshape(-1, 6)[:, [0, 2, 4]]).max())
    base = setup.model
    x = surface_points(shell, axi.state, base.node_rest_position, mode, n, amplitude)
    x[base.node_fixed] = base.node_rest_position[base.node_fixed]
    log.info("axisymmetric start: level %.4g Pa; %s", axi.pressure_level,
             f"seeded with n = {n}, {SEED_AMPLITUDE * 1e3:g} mm" if n else
             "stable to every harmonic, not seeded")
    state, info, iterations = _minimum(setup, model, x, axi.pressure_level, volume)
    info = replace(info, steps=iterations, seed=(n, SEED_AMPLITUDE) if n else ())
    _warn("axisymmetric", volume, info)
    return state, info


def seed_attrs(info) -> dict:
    """The result attributes of a start's seed (:attr:`structure.load.Equilibrium.seed`): its
    wave number (0: unseeded) and largest displacement (m; 0 unseeded)."""
    n, amplitude = info.seed if info.seed else (0, 0.0)
    return dict(start_seed_wave_number=int(n), start_seed_amplitude=float(amplitude))


def on_wall(setup, state, info, gap: float = DHAT):
    """(state, info) with every free node closer to the wall than ``gap`` (m; the barrier's
    dhat) put on it, the info's liquid volume the moved sheet's: a minimisation's start made
    ready for the Newton window, whose wall is a contact at r = R that holds a node only once
    it touches (measured at N = 38: from the barrier's state, a tenth of dhat inside, its
    settle stopped at a force ratio of 0.51 after 30 iterations; from this one it converged in
    10, moving no node more than 0.31 mm). The held volume moves by the contact's area times
    the barrier's stand-off, a few % of the liquid where most of the sheet lies on the wall
    (tank fraction 0.025, N = 14: 3-5 %); the Newton settle holds the volume again."""
    base = setup.model
    x = np.array(state.node_position, dtype=float)
    r = np.linalg.norm(x, axis=1)
    held = ~base.node_fixed & (r > base.radius - gap)
    x[held] *= (base.radius / r[held])[:, None]
    return MembraneState(x), replace(info, liquid_volume=liquid_volume(base, x))
