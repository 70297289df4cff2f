"""The fill scales: the tank fraction, and the thesis's full-inversion scale.

An engineer reads the **tank fraction** phi_tank = V / ((4/3) pi R^3): every frame of every
result records it (``tank_fraction``), plots and ``fsi compare`` speak it, and the dynamic
procedures take their fills on it.  A static sweep may instead ask for the thesis's scale
(``sweep.scale = "full-inversion"``), registered with the tank's in :data:`FILL_SCALES`:
0 % = rest shape, 100 % = the fully inverted equilibrium.

Levine's App. J divides by the volume of the last frame of the height ramp (the membrane under
the final equivalent height +1.05 R). We keep that definition but take the *converged*
equilibrium under that load, found from a fully inverted start, instead of whatever the ramp
reached (the thesis's last frame held only about 70 % of the tank):

    V_empty = V_liquid(rest shape)
    V_full  = V_liquid(equilibrium under h = sweep.full_height * R, started inverted)
    phi     = (V - V_empty) / (V_full - V_empty)

The inverted start is the rest shape mirrored through the plane at the mean height of the
innermost fixed ring (for a simply supported rim: the equator, i.e. the exact mirror image).
With the thesis's clamped rim (two fixed rings) that ring lies a cell below the equator, so the
band between it and the equator cannot invert and the fully inverted membrane holds less than
the mirrored volume within the strain limit (0.80 of it at N = 26, 0.90 at N = 54); the ratio
is recorded in every result (``full_volume / mirrored_volume``) and each frame's
``tank_fraction`` is V / ((4/3) pi R^3).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from structure.grid import boundary_ring
from structure.load import Equilibrium
from structure.model import MembraneModel, MembraneState
from structure.statics import solve_equilibrium
from structure.thesis import CourantError
from structure.volume import FillScale, liquid_volume, mirrored_rest_position, tank_volume

from fsi.setup.build import Setup
from fsi.setup.models import hydrostatic_load
from fsi.registry import SceneError
from fsi.registry import SceneError

log = logging.getLogger(__name__)


@dataclass
class FullInversion:
    """The 100 % reference: scale, equilibrium state and its solve info, mirrored volume (m^3)."""

    scale: FillScale
    state: MembraneState
    info: Equilibrium
    mirrored_volume: float


def check_reachable(full: FullInversion, scale: FillScale, fills, key: str) -> None:
    """Refuse fills outside what the membrane can hold, naming ``key``: below its rest shape's
    volume (the slivers between its facets and the wall: the tank fraction 0 is not a shape)
    or above the fully inverted membrane's (a membrane clamped a cell below the equator cannot
    hold more)."""
    bottom = float(scale.fill(full.scale.empty_volume))
    top = float(scale.fill(full.scale.full_volume))
    outside = [f for f in fills if not bottom - 1e-9 <= f <= top + 1e-9]
    if outside:
        raise SceneError(f"{key}: fill {outside[0]} is outside what the membrane can hold on "
                         f"this scale at this grid and support: allowed [{bottom:.4f}, "
                         f"{top:.4f}] (rest shape to full inversion)")


FILL_SCALES = {
    "tank": lambda setup, full: FillScale.tank(setup.model.radius),
    "full-inversion": lambda setup, full: full.scale,
}
"""Scale name -> (setup, :class:`FullInversion`) -> :class:`FillScale` of a static sweep."""


def inverted_start(model: MembraneModel) -> np.ndarray:
    """Rest shape with its free nodes mirrored through z = mean height of the innermost fixed
    ring, (n, 3) m."""
    ring = boundary_ring(model.grid_size, _fixed_ring_count(model) - 1)
    z0 = float(model.node_rest_position[ring, 2].mean())
    pos = model.node_rest_position.copy()
    free = ~model.node_fixed
    pos[free, 2] = 2.0 * z0 - pos[free, 2]
    return pos


def _fixed_ring_count(model: MembraneModel) -> int:
    """Number of whole grid rings, from the border in, whose nodes are all fixed (>= 1)."""
    count = 0
    while count < model.grid_size // 2 and np.all(
            model.node_fixed[boundary_ring(model.grid_size, count)]):
        count += 1
    return count


def _full_load(setup: Setup):
    """The hydrostatic load of the full inversion: equivalent height sweep.full_height * R."""
    height = setup.scene["sweep"]["full_height"] * setup.model.radius
    return hydrostatic_load(setup.liquid,
                            pressure_level=setup.liquid.reference_pressure(height))


def check_first_step(setup: Setup) -> None:
    """A priori: the full inversion's first pseudo-step, the sweep's largest load on its
    farthest start, moves no node more than its length (the relaxation's own limit,
    :func:`structure.statics.solve_equilibrium`); else :class:`SceneError` naming
    ``relaxation.dt`` and ``membrane.grid_size``. One step, run before anything is written:
    the mirrored start's first projection moves nodes about 0.8 of their length whatever the
    step (0.80 / 0.90 / 1.03 at N = 26 / 100 / 400, dt = 2e-4 s), so the load's Courant
    number (:func:`fsi.setup.limits.courant_time_step_limit`) alone does not predict it."""
    model = setup.model
    try:
        solve_equilibrium(model, MembraneState(inverted_start(model)), _full_load(setup),
                          replace(setup.relaxation, max_steps=1))
    except CourantError as err:
        density = setup.scene["membrane"]["grading_density"]
        graded = (f" or membrane.grading_density (now {density:g}; the mirrored start's first "
                  "projection on the band's smaller cells does not shrink with dt)"
                  if density > 1 else "")
        raise SceneError(f"scene keys 'relaxation.dt' = {setup.relaxation.dt!r} s and "
                         f"'membrane.grid_size' = {model.grid_size}: the full inversion's "
                         f"first step fails ({err}); allowed: a smaller relaxation.dt or "
                         f"grid_size{graded}") from None


def full_inversion(setup: Setup) -> FullInversion:
    """Solve the fully inverted equilibrium of ``setup`` and build the fill scale from it."""
    model = setup.model
    state, info = solve_equilibrium(model, MembraneState(inverted_start(model)),
                                    _full_load(setup), setup.relaxation)
    if not info.converged:
        log.warning("full inversion not converged after %d steps (move ratio %.2e): the 100 %% "
                    "volume is approximate", info.steps, info.move_ratio)
    scale = FillScale(liquid_volume(model, model.node_rest_position), info.liquid_volume)
    mirrored = liquid_volume(model, mirrored_rest_position(model))
    log.info("the full inversion (under an equivalent liquid height of %.4f m) holds tank "
             "fraction %.4f, %.4f of the mirrored rest shape",
             setup.scene["sweep"]["full_height"] * model.radius,
             info.liquid_volume / tank_volume(model.radius), info.liquid_volume / mirrored)
    return FullInversion(scale, state, info, mirrored)
