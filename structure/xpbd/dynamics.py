"""Dynamic XPBD: one time window of a coupled run in plain substeps, the membrane's inertia
kept (its stiffness bias ~ dt^2 sets the substep, :mod:`structure.xpbd`)."""
from __future__ import annotations

import numpy as np

from ..load import Load, StepInfo
from ..model import MembraneState
from ..volume import liquid_volume
from .model import XpbdDivergence, XpbdModel, XpbdMultipliers, XpbdSettings, XpbdState, \
    node_external_force
from .substep import substep


def step(model: XpbdModel, state: MembraneState, load: Load, dt: float,
         settings: XpbdSettings) -> tuple[XpbdState, StepInfo]:
    """Dynamic XPBD over one time window of ``dt`` (s).

    The window is cut into the fewest equal substeps no longer than ``settings.dt``; each is
    plain XPBD (multipliers from zero, velocities kept, no damping; ``settings.warm_start``
    and ``kinetic_damping`` are ignored), so the membrane keeps its inertia. The load's node
    pressure (n,) Pa (a field is evaluated at the window's start) acts on the liquid side
    throughout the window, on the current node area vectors. With ``load.volume_target``
    (m^3) the liquid volume is held on the straight line from its value at the window's
    start to the target, substep by substep (one linearised projection each, so to first
    order in the substep's volume change), and the uniform pressure level that holds it is
    the volume multiplier over the substep squared (Pa, added to the node pressure); without,
    ``load.pressure_level`` is added and held. Returns (:class:`XpbdState` at the window's end
    with its velocities, :class:`structure.load.StepInfo` with the substeps and the level of
    the last substep).
    """
    if not dt > 0:
        raise ValueError(f"xpbd window duration must be > 0 s, got {dt!r}")
    n_sub = max(1, int(np.ceil(dt / settings.dt * (1.0 - 1e-12))))
    s = XpbdSettings(dt=dt / n_sub, iterations=settings.iterations, warm_start=False,
                     bending=settings.bending, kinetic_damping=False)
    x = np.array(state.node_position, dtype=float)
    v = np.array(state.node_velocity, dtype=float)
    node_pressure = np.asarray(load.pressure(x), dtype=float)
    if node_pressure.shape != (len(x),):
        raise ValueError(f"node_pressure must have shape ({len(x)},) (Pa), got "
                         f"{node_pressure.shape}")
    if not np.all(np.isfinite(node_pressure)):
        raise ValueError(f"node_pressure has {int(np.sum(~np.isfinite(node_pressure)))} "
                         f"non-finite values (Pa)")
    volume = None
    if load.volume_target is not None:
        volume = (liquid_volume(model.base, x), float(load.volume_target))
    else:
        node_pressure = node_pressure + load.pressure_level
    for k in range(1, n_sub + 1):
        force = node_external_force(model, x, node_pressure, load.body_acceleration)
        target = None
        if volume is not None:
            target = volume[0] + (volume[1] - volume[0]) * k / n_sub
        lam = XpbdMultipliers.zeros(len(model.triangles))
        substep(model, x, v, force, lam, s, target, k)
        if not np.all(np.isfinite(x)):
            raise XpbdDivergence(f"xpbd window substep {k}: non-finite positions "
                                 f"(substep {s.dt:g} s)")
    level = lam.volume[0] / s.dt**2 if volume is not None else load.pressure_level
    return XpbdState(x, v, multipliers=None), StepInfo(n_sub, float(level))
