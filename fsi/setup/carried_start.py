"""A static start whose fold state is found on a coarser membrane grid.

Each membrane grid relaxed from the manufactured shape lands in its own fold state, so runs on
several grids compare different states, not one state at different resolutions. With a start
grid N0 the start is relaxed on the grid N0 (the same scene otherwise), carried to the scene's
grid (:func:`structure.prolongation.prolong`) and polished there to a minimum holding the same
liquid volume: the N0 state, refined. Where the start is XPBD's relaxation the polish is the
shell model's exact minimum (:mod:`structure.shell`, :func:`polish`); where the start is one
of the minimisation's (``minimisation``, ``axisymmetric``) it is the minimisation statics in
the run's own law (:func:`fsi.setup.static_start.polished`): carried from N = 38 to 76 it
took 4 min (4.7 min with the N = 38 start) where the shell's polish took 36 min
(docs/notes/one-fold-state.md). The caller then settles
it under its own solver (its XPBD substeps), as it would any start. See
docs/notes/one-fold-state.md.
"""
from __future__ import annotations

import logging
from dataclasses import replace
from typing import Callable, Optional

import numpy as np

from structure.model import MembraneState
from structure.prolongation import prolong
from structure.shell import ShellModel, ShellSettings, solve_equilibrium
from structure.xpbd import solve_equilibrium as xpbd_equilibrium

from fsi.setup.build import build
from fsi.setup.models import hydrostatic_load

log = logging.getLogger(__name__)

SETTLE_SUBSTEPS = 2000
"""Substeps of the caller's XPBD that settle a carried state before a second polish, when the
first did not converge (-). Measured on diaphragm-fill carried from N = 14 to 38: the polish
alone stopped at a force ratio of 13 (level -27 kPa); after 2000 damped substeps (12.5 s) it
converged (2.4e-4, 118 Pa)."""


def carries(setup, start_grid: int) -> bool:
    """Whether a start grid of ``start_grid`` (0: none) asks for a carried start on the grid
    of ``setup``."""
    return bool(start_grid) and start_grid != setup.scene["membrane"]["grid_size"]


def xpbd_settle(setup, model, settings, volume: float) -> Callable:
    """``settle(state, level)`` for :func:`polish`: :data:`SETTLE_SUBSTEPS` of the XPBD
    ``model`` at ``settings`` toward ``volume`` (m^3) under the hydrostatic liquid."""
    capped = replace(settings, max_steps=SETTLE_SUBSTEPS)

    def settle(state, level):
        return xpbd_equilibrium(model, state, hydrostatic_load(setup.liquid, volume, level),
                                capped)
    return settle


def polish(setup, node_position: np.ndarray, volume: float, level: float,
           settle: Optional[Callable] = None,
           settings: ShellSettings = ShellSettings()) -> tuple[MembraneState, object]:
    """The shell model's minimum on the grid of ``setup`` from ``node_position`` (n, 3) m,
    holding ``volume`` (m^3) under the hydrostatic liquid, the level started at ``level``
    (Pa): (state, :class:`structure.load.Equilibrium`). When it does not converge and
    ``settle(state, level)`` -> (state, Equilibrium) is given (:data:`SETTLE_SUBSTEPS` of
    the caller's XPBD), the carried state is settled and polished again. ``settings``: the
    shell's solve."""
    shell = ShellModel.from_membrane(setup.model, settings)

    def minimum(state, guess):
        return solve_equilibrium(shell, state, hydrostatic_load(setup.liquid, volume, guess),
                                 settings)

    state, info = minimum(MembraneState(node_position), level)
    if not info.converged and settle is not None:
        settled, settled_info = settle(MembraneState(node_position), level)
        state, info = minimum(settled, settled_info.pressure_level)
    return state, info


def carried_start(setup, start_grid: int, volume: float, relax: Callable,
                  settle: Optional[Callable] = None,
                  minimised: Optional[Callable] = None) -> tuple[MembraneState, object]:
    """The start of ``setup`` holding ``volume`` (m^3) of liquid, its fold state found on the
    grid ``start_grid``: ``relax(coarse_setup)`` -> (state, Equilibrium) relaxes it there;
    returns the state carried to ``setup``'s grid and polished, and the polish's
    :class:`structure.load.Equilibrium` (a polish that did not converge is logged). The
    polish is ``minimised(x, level)`` -> (state, Equilibrium) where given (the minimisation
    statics), else the shell's (:func:`polish`, ``settle`` as there)."""
    coarse = build(setup.scene.with_keys({"membrane": {"grid_size": start_grid}}))
    state, info = relax(coarse)
    x = prolong(coarse.model, state.node_position, setup.model)
    if minimised is not None:
        polished, done = minimised(x, info.pressure_level)
    else:
        polished, done = polish(setup, x, volume, info.pressure_level, settle)
    if not done.converged:
        log.warning("the start carried from membrane grid %d to %d: its polish did not "
                    "converge (force ratio %.2e, level %.4g Pa)", start_grid,
                    setup.scene["membrane"]["grid_size"], done.force_ratio,
                    done.pressure_level)
    return polished, done
