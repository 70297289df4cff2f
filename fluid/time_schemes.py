"""Time schemes of the moving-wall liquid step: what the step takes as its "old" state.

Every scheme here is a one-step backward difference in disguise: the time derivative of a
quantity y at t^{n+1} is written (y^{n+1} - y_old) / dt_eff, so the projection step of
:mod:`fluid.projection` (written for backward Euler) runs unchanged with its old velocities,
old cell fractions and step replaced by y_old and dt_eff:

* ``euler`` (backward Euler, first order): y_old = y^n, dt_eff = dt;
* ``bdf2`` (second-order backward differences on a variable step, r = dt / dt_prev)::

      dy/dt(t^{n+1}) ~ [a0 y^{n+1} + a1 y^n + a2 y^{n-1}] / dt,
      a0 = (1 + 2r)/(1 + r), a1 = -(1 + r), a2 = r^2/(1 + r),

  so dt_eff = dt / a0 and y_old = -(a1 y^n + a2 y^{n-1}) / a0 (r = 1: (4 y^n - y^{n-1})/3,
  dt_eff = 2 dt/3). It applies to the momentum (cell and face velocities) and to the
  continuity equation's cell volumes alike (the geometric conservation law: with the
  interface moving, the liquid volume of each cell changes at the BDF2 rate of its wetted
  fraction), so a rigid column behind a moving wall sees the BDF2 acceleration of the wall.
  Its first step, with no state behind it, is backward Euler.

Backward Euler damps an oscillation of angular frequency omega at zeta ~ omega dt / 2 when
the restoring force is taken at the step's end (a membrane in equilibrium under the liquid's
end pressure); BDF2 at zeta ~ (omega dt)^3 / 4.

The pressure stays incremental (its old gradient at t^n, the correction scaled by dt_eff):
the BDF2 incremental projection of Guermond, Minev & Shen (2006), second order in velocity.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from .model import FluidState


@dataclass(frozen=True)
class OldState:
    """What a step takes as its old state: ``state`` (the y_old of every time derivative,
    at t^n: velocities (n_cells, dim) and (n_faces,) m/s, cell fractions (n_cells,)) and
    ``dt`` (s) the effective step dt_eff."""

    state: FluidState
    dt: float


TIME_SCHEMES: dict[str, Callable[[FluidState, float], OldState]] = {}


def register_time_scheme(name: str):
    """Decorator: register ``old_state(state, dt) -> OldState`` under ``name``."""
    def register(func):
        TIME_SCHEMES[name] = func
        return func
    return register


@register_time_scheme("euler")
def _euler(state: FluidState, dt: float) -> OldState:
    return OldState(state, dt)


@register_time_scheme("bdf2")
def _bdf2(state: FluidState, dt: float) -> OldState:
    previous = state.previous
    if previous is None:
        return OldState(state, dt)
    dt_prev = state.time - previous.time
    if not dt_prev > 0:
        raise ValueError(f"bdf2: the state behind t = {state.time} s is not earlier "
                         f"(t = {previous.time} s)")
    r = dt / dt_prev
    a0, a1, a2 = (1 + 2 * r) / (1 + r), -(1 + r), r * r / (1 + r)

    def blend(now: np.ndarray, before: np.ndarray) -> np.ndarray:
        return -(a1 * now + a2 * before) / a0

    geometry = replace(state.geometry, cell_fraction=blend(state.geometry.cell_fraction,
                                                           previous.geometry.cell_fraction))
    old = replace(state, cell_velocity=blend(state.cell_velocity, previous.cell_velocity),
                  face_velocity=blend(state.face_velocity, previous.face_velocity),
                  geometry=geometry)
    return OldState(old, dt / a0)
