"""XPBD statics: the membrane's equilibrium by damped dynamic substeps, or by warm-started
quasi-static substeps whose fixed point is the exact equilibrium (:mod:`structure.xpbd`)."""
from __future__ import annotations

import numpy as np

from ..load import Equilibrium, Load
from ..model import MembraneState
from ..volume import liquid_volume, lower_hemisphere_volume
from .model import XpbdDivergence, XpbdModel, XpbdMultipliers, XpbdSettings, XpbdState, \
    node_external_force
from .substep import substep


def solve_equilibrium(model: XpbdModel, state: MembraneState, load: Load,
                      settings: XpbdSettings) -> tuple[XpbdState, Equilibrium]:
    """Static equilibrium by damped XPBD substeps from ``state`` under ``load``.

    ``load.pressure(x)`` gives the liquid-side pressure (n,) Pa at the nodes without the
    uniform level.  With ``load.volume_target`` (m^3, ramped from the start volume at
    ``settings.ramp_rate``) the level is the volume multiplier, started from
    ``load.pressure_level``; without, it is held at ``load.pressure_level`` (Pa).  Returns
    (:class:`XpbdState` with zero velocities and the final multipliers,
    :class:`structure.load.Equilibrium` with its move_ratio).
    """
    s = settings
    pressure, body_acceleration = load.pressure, load.body_acceleration
    volume_target, pressure_level = load.volume_target, load.pressure_level
    s = settings
    base = model.base
    x = np.array(state.node_position, dtype=float)
    v = np.zeros_like(x)
    m = len(model.triangles)
    lam = getattr(state, "multipliers", None) or XpbdMultipliers.zeros(m)
    if not s.warm_start:
        lam = XpbdMultipliers.zeros(m)
    free = ~base.node_fixed
    tank = 2.0 * lower_hemisphere_volume(base.radius)
    start_volume = liquid_volume(base, x)
    ramp_steps = 0
    if volume_target is not None:
        ramp_steps = int(np.ceil(abs(volume_target - start_volume) / (s.ramp_rate * tank)))
        if lam.volume[0] == 0.0:
            lam.volume[0] = pressure_level * s.dt**2
    kinetic = 0.0
    level = pressure_level
    move = np.inf
    converged = False
    step = 0
    for step in range(1, s.max_steps + 1):
        node_pressure = pressure(x)
        if volume_target is None:
            node_pressure = node_pressure + pressure_level
        force = node_external_force(model, x, node_pressure, body_acceleration)
        target = None
        ramping = False
        if volume_target is not None:
            ramp = min(1.0, step / max(ramp_steps, 1))
            ramping = ramp < 1.0
            target = start_volume + ramp * (volume_target - start_volume)
        if not s.warm_start:
            lam = XpbdMultipliers.zeros(m)
        x_start = substep(model, x, v, force, lam, s, target, step)
        if s.warm_start:
            v[:] = 0.0
        elif s.kinetic_damping:
            energy = float(np.einsum("i,ij,ij->", base.node_mass, v, v))
            if energy < kinetic:
                v[:] = 0.0
            kinetic = energy
        dx = np.sqrt(np.einsum("ij,ij->i", x - x_start, x - x_start))
        move = float(np.max(dx[free] / base.node_length_scale[free]))
        if not np.isfinite(move) or move > 1.0:
            raise XpbdDivergence(f"xpbd substep {step}: a node moved {move:.3g} of its length "
                                 f"in one substep (dt = {s.dt:g} s, warm_start = "
                                 f"{s.warm_start})")
        new_level = lam.volume[0] / s.dt**2 if volume_target is not None else pressure_level
        level_change, level = abs(new_level - level), new_level
        if not ramping and move < s.tolerance and level_change < s.level_tolerance:
            converged = True
            break
    volume = liquid_volume(base, x)
    out = XpbdState(x, np.zeros_like(x), multipliers=lam)
    return out, Equilibrium(step, converged, float(level), float(volume), move_ratio=move)
