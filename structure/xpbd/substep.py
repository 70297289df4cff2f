"""One XPBD substep (explicit velocity update, prediction, constraint sweeps), shared by the
statics and the dynamics."""
from __future__ import annotations

from typing import Optional

import numpy as np

from ..kernels import wall_collision
from ..volume import lower_hemisphere_volume
from .kernels import bending_sweep, membrane_sweep, volume_constraint
from .model import XpbdDivergence, XpbdModel, XpbdMultipliers, XpbdSettings


def sweep(model: XpbdModel, x, lam: XpbdMultipliers, settings: XpbdSettings, target,
          apply_only: bool) -> None:
    """One Gauss-Seidel sweep over every block, volume and wall (in place); with
    ``apply_only`` the warm-start displacement W J^T lambda instead.

    The bending's angles are read on the circle, each change in (-pi, pi] (a zero reference,
    :mod:`structure.bending`), not along a followed turn: XPBD's projections pass the sheet
    through itself (12 hinges of the N = 14 hemisphere's relaxation to half the tank pass
    +-pi, some by nearly a full turn), and a followed turn would load those hinges with the
    energy of a sheet wound through itself where the geometry is nearly flat."""
    base = model.base
    inv_dt2 = 1.0 / settings.dt**2
    membrane_sweep(x, base.node_inv_mass, model.triangles, model.rest_inverse,
                    model.membrane_compliance, lam.membrane, inv_dt2, apply_only,
                    model.tension_field, base.material.poisson_ratio)
    if settings.bending:
        b = model.bending
        bending_sweep(x, base.node_inv_mass, b.triangles, b.flap, b.ghost, b.active,
                      b.rest_angle, model.angle_on_circle, model.bending_compliance,
                      lam.bending, inv_dt2, apply_only)
    if not apply_only:
        wall_collision(x, base.node_inv_mass, base.radius, 1.0)
    if target is not None:  # last, so that each substep ends on the volume
        volume_constraint(x, base.node_inv_mass, base.face_nodes, base.volume_sign,
                lower_hemisphere_volume(base.radius), target, lam.volume, apply_only)


def substep(model: XpbdModel, x: np.ndarray, v: np.ndarray, force: np.ndarray,
             lam: XpbdMultipliers, s: XpbdSettings, target: Optional[float],
             step: int) -> np.ndarray:
    """One substep in place on x (n, 3) m and v (n, 3) m/s under ``force`` (n, 3) N: explicit
    velocity update, prediction, the constraint sweeps (warm-started when ``s.warm_start``)
    and v = (x - x_start) / dt. Returns x_start; raises :class:`XpbdDivergence` when a triangle
    collapses."""
    v += s.dt * model.base.node_inv_mass[:, None] * force
    x_start = x.copy()
    x += s.dt * v
    try:
        if s.warm_start:
            sweep(model, x, lam, s, target, apply_only=True)
        for _ in range(s.iterations):
            sweep(model, x, lam, s, target, apply_only=False)
    except ZeroDivisionError as err:  # a collapsed triangle or edge
        raise XpbdDivergence(f"xpbd substep {step}: a triangle collapsed "
                             f"(dt = {s.dt:g} s, warm_start = {s.warm_start})") from err
    v[:] = (x - x_start) / s.dt
    return x_start

