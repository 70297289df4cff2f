"""A-priori checks of a scene against the machine and the membrane steppers' time step.

Memory: a membrane of grid size N has N^2 nodes; a run holds about BYTES_PER_NODE per node
(measured: the model alone peaks at 522 B per node at N = 80; states, frames and the XPBD
constraints take the rest), which must fit in the memory available now.

Time step:
Before a run, the first-step Courant number (thesis Eqn 4.7) under the largest load the run
can apply must stay below 1,

    C0 = dt^2 (p_max / (rho_m t) + |b|) / L_min < 1,

with p_max = rho_l |b| (h_max + R) the largest hydrostatic pressure on the membrane. This is a
necessary condition only: the stepper still checks the Courant number every step.
"""
from __future__ import annotations

import os

import numpy as np

from fluid.hydrostatic import HydrostaticLiquid
from structure.model import MembraneModel

from fsi.registry import SceneError


BYTES_PER_NODE = 2048
"""Memory a run holds per membrane node, about (B)."""


def available_memory() -> float:
    """Bytes of memory available now (Linux: free pages; elsewhere: infinite)."""
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return float("inf")


def check_memory(grid_size: int) -> None:
    """Raise :class:`SceneError` naming ``membrane.grid_size`` when its N^2 nodes would not
    fit in the memory available."""
    need = grid_size**2 * BYTES_PER_NODE
    have = available_memory()
    if need > have:
        raise SceneError(f"scene key 'membrane.grid_size' = {grid_size}: {grid_size**2:,} nodes "
                         f"need about {need / 2**30:.3g} GiB, more than the "
                         f"{have / 2**30:.3g} GiB available")


def courant_time_step_limit(model: MembraneModel, liquid: HydrostaticLiquid,
                            largest_height: float) -> float:
    """Largest dt (s) with a first-step Courant number below 1 (see module docstring);
    ``largest_height`` is the largest |equivalent height| (m) the run applies. Without a body
    acceleration there is no hydrostatic load to set it: :class:`SceneError` naming
    ``liquid.body_acceleration``."""
    g = liquid.acceleration_magnitude
    if g == 0.0:
        raise SceneError("scene key 'liquid.body_acceleration' = [0, 0, 0]: this run's time "
                         "step comes from the hydrostatic load, which needs a body "
                         "acceleration; allowed: |b| > 0 m/s^2")
    p_max = liquid.density * g * (abs(largest_height) + model.radius)
    areal_mass = model.material.density * model.material.thickness
    accel = p_max / areal_mass + g
    return float(np.sqrt(model.node_length_scale.min() / accel))


def check_time_step(key: str, dt: float, limit: float) -> None:
    """Raise :class:`SceneError` naming scene key ``key`` when ``dt`` (s) is not below
    ``limit`` (s)."""
    if dt >= limit:
        raise SceneError(f"scene key '{key}' = {dt!r} breaks the Courant limit (thesis Eqn 4.7) "
                         f"for this membrane and load; allowed 0 < dt < {limit:.3g} s")
