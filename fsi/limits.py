"""The a-priori time-step check of the membrane steppers.

Before a run, the first-step Courant number (thesis Eqn 4.7) under the largest load the run
can apply must stay below 1,

    C0 = dt^2 (p_max / (rho_m t) + |b|) / L_min < 1,

with p_max = rho_l |b| (h_max + R) the largest hydrostatic pressure on the membrane. This is a
necessary condition only: the stepper still checks the Courant number every step.
"""
from __future__ import annotations

import numpy as np

from fluid.hydrostatic import HydrostaticLiquid
from structure.model import MembraneModel

from .registry import SceneError


def courant_time_step_limit(model: MembraneModel, liquid: HydrostaticLiquid,
                            largest_height: float) -> float:
    """Largest dt (s) with a first-step Courant number below 1 (see module docstring);
    ``largest_height`` is the largest |equivalent height| (m) the run applies."""
    g = liquid.acceleration_magnitude
    p_max = liquid.density * g * (abs(largest_height) + model.radius)
    areal_mass = model.material.density * model.material.thickness
    accel = p_max / areal_mass + g
    if accel == 0.0:
        return float("inf")
    return float(np.sqrt(model.node_length_scale.min() / accel))


def check_time_step(key: str, dt: float, limit: float) -> None:
    """Raise :class:`SceneError` naming scene key ``key`` when ``dt`` (s) is not below
    ``limit`` (s)."""
    if dt >= limit:
        raise SceneError(f"scene key '{key}' = {dt!r} breaks the Courant limit (thesis Eqn 4.7) "
                         f"for this membrane and load; allowed 0 < dt < {limit:.3g} s")
