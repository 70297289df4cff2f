"""A static start whose fold state is found on a coarser membrane grid.

Each membrane grid relaxed from the manufactured shape lands in its own fold state, so runs on
several grids compare different states, not one state at different resolutions. With a start
grid N0 the start is relaxed on the grid N0 (the same scene otherwise), carried to the scene's
grid (:func:`structure.prolongation.prolong`) and polished there to the shell model's exact
minimum holding the same liquid volume (:mod:`structure.shell`): the N0 state, refined. The
caller then settles it under its own solver (its XPBD substeps), as it would any start.
README, 'One fold state through the grids'.
"""
from __future__ import annotations

import logging
from typing import Callable

from structure.model import MembraneState
from structure.prolongation import prolong
from structure.shell import ShellModel, ShellSettings, solve_equilibrium

from .build import build
from .models import hydrostatic_load

log = logging.getLogger(__name__)


def carried_start(setup, start_grid: int, volume: float,
                  relax: Callable) -> tuple[MembraneState, object]:
    """The start of ``setup`` holding ``volume`` (m^3) of liquid, its fold state found on the
    grid ``start_grid``: ``relax(coarse_setup)`` -> (state, Equilibrium) relaxes it there;
    returns the state carried to ``setup``'s grid and polished by the shell model, and the
    shell's :class:`structure.load.Equilibrium` (a polish that did not converge is logged)."""
    coarse = build(setup.scene.with_keys({"membrane": {"grid_size": start_grid}}))
    state, info = relax(coarse)
    x = prolong(coarse.model, state.node_position, setup.model)
    settings = ShellSettings()
    shell = ShellModel.from_membrane(setup.model, settings)
    polished, polish = solve_equilibrium(
        shell, MembraneState(x), hydrostatic_load(setup.liquid, volume, info.pressure_level),
        settings)
    if not polish.converged:
        log.warning("the start carried from membrane grid %d to %d: its shell polish did not "
                    "converge (force ratio %.2e, level %.4g Pa)", start_grid,
                    setup.scene["membrane"]["grid_size"], polish.force_ratio,
                    polish.pressure_level)
    return polished, polish
