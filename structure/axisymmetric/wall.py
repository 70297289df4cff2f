"""The tank wall as a smooth barrier on the shell of revolution (incremental potential contact:
Li et al., "Incremental Potential Contact", ACM Trans. Graph. 39(4), 2020, its barrier).

The tank is the sphere of radius a centred on the rim's centre; the sheet lies inside it, and
at rest the hemisphere lies on it. A barrier needs a positive distance at every admissible
state, the rest included, so the barrier's wall is the sphere of radius a + d_hat: a point of
the meridian at distance rho = sqrt(r^2 + z^2) from the centre has the distance

    d = a + d_hat - rho                                                            (m)

to it, and the barrier acts where d < d_hat, in the band a < rho < a + d_hat: the sheet
touches the tank when it reaches radius a and may enter the band by less than d_hat (the
contact's tolerance). The energy per unit rest area is

    kappa b(d),   b(d) = -(d - d_hat)^2 ln(d / d_hat) for d < d_hat, 0 beyond      (m^2)

C2 at d = d_hat (b, b' and b'' vanish there) and infinite at d = 0, so no state a line search
accepts has a point outside the barrier's wall; the contact pressure on the sheet is
-kappa b'(d) (Pa, per rest area) along the wall's inward normal. Newton crosses the
contact's onset and release with no active set to change: the Hessian is continuous.

The barrier is evaluated at the Gauss points, each carrying its rest area.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MID_BAND_SLOPE = np.log(2.0) + 0.5
"""-b'(d_hat / 2) / d_hat: the barrier's slope at the middle of its band."""


@dataclass(frozen=True)
class BarrierWall:
    """The tank wall (module doc): ``radius`` a (m) of the tank, ``tolerance`` d_hat (m) the
    band beyond a in which the barrier acts, ``stiffness`` kappa (Pa/m)."""

    radius: float
    tolerance: float
    stiffness: float

    def __post_init__(self):
        for name in ("radius", "tolerance", "stiffness"):
            if not getattr(self, name) > 0:
                raise ValueError(f"wall {name} must be > 0, got {getattr(self, name)!r}")

    def contact_pressure(self, distance: np.ndarray) -> np.ndarray:
        """-kappa b'(d) (Pa) at distances ``distance`` (...) m to the barrier's wall."""
        d = np.asarray(distance, dtype=float)
        return -self.stiffness * barrier(d, self.tolerance, 1)[1]


def barrier_wall(radius: float, pressure: float, tolerance: float = 1e-5) -> BarrierWall:
    """The wall of the tank of ``radius`` a (m) with the band d_hat = ``tolerance`` a, stiff
    enough that a contact pressure ``pressure`` (Pa) holds the sheet in the middle of its
    band (kappa = pressure / (MID_BAND_SLOPE d_hat))."""
    d_hat = tolerance * radius
    return BarrierWall(radius, d_hat, pressure / (MID_BAND_SLOPE * d_hat))


def barrier(d: np.ndarray, d_hat: float, order: int):
    """b(d) (m^2) and, by ``order``, b' (m) and b'' (1) (module doc); inf for d <= 0."""
    inside = d < d_hat
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(inside, d, d_hat)
        gap = x - d_hat
        log = np.where(x > 0, np.log(x / d_hat), -np.inf)
        b = np.where(d <= 0, np.inf, np.where(inside, -gap * gap * log, 0.0))
        if order == 0:
            return (b,)
        b1 = np.where(inside, -2.0 * gap * log - gap * gap / x, 0.0)
        if order == 1:
            return b, b1
        b2 = np.where(inside, -2.0 * log - 4.0 * gap / x + gap * gap / (x * x), 0.0)
    return b, b1, b2


def wall_density(wall: BarrierWall, u: np.ndarray, area: np.ndarray, order: int = 2):
    """The barrier energy per unit S (P,) J/m at local variables ``u`` (P, 6) (the points'
    rest area per unit S ``area`` (P,) m) and, by ``order``, its gradient (P, 6) and Hessian
    (P, 6, 6) in u; inf where a point is beyond the barrier's wall."""
    r, z = u[:, 0], u[:, 3]
    rho = np.hypot(r, z)
    d = wall.radius + wall.tolerance - rho
    out = barrier(d, wall.tolerance, order)
    scale = wall.stiffness * area
    f = scale * out[0]
    if order == 0:
        return f
    unit = np.stack([r, z], -1) / np.where(rho > 0, rho, 1.0)[:, None]     # d d / d(r, z) = -unit
    g = np.zeros(u.shape)
    g[:, [0, 3]] = -(scale * out[1])[:, None] * unit
    if order == 1:
        return f, g
    # d2 d / d(r, z)^2 = -(I - unit unit^T) / rho
    proj = np.eye(2)[None] - unit[:, :, None] * unit[:, None, :]
    block = (scale * out[2])[:, None, None] * unit[:, :, None] * unit[:, None, :] \
        - (scale * out[1] / np.where(rho > 0, rho, 1.0))[:, None, None] * proj
    h = np.zeros(u.shape + (6,))
    h[:, 0, 0], h[:, 0, 3], h[:, 3, 0], h[:, 3, 3] = (block[:, 0, 0], block[:, 0, 1],
                                                      block[:, 1, 0], block[:, 1, 1])
    return f, g, h


def distance(wall: BarrierWall, u: np.ndarray) -> np.ndarray:
    """d (P,) m: the distance of the points of local variables ``u`` (P, 6) to the barrier's
    wall (module doc)."""
    return wall.radius + wall.tolerance - np.hypot(u[:, 0], u[:, 3])


def pulled_inside(wall: BarrierWall, state: np.ndarray) -> np.ndarray:
    """(4 n,): ``state`` with each node beyond the middle of the barrier's band pulled along
    its radius to the middle (rho = a + d_hat / 2) and the slope of each node in the band
    turned tangent to the wall where it points out of it (its outward radial part removed):
    a predicted state for a sheet sliding along the wall, which a linear predictor carries out
    of the sphere by its curvature."""
    out = np.array(state, dtype=float).reshape(-1, 4)
    rho = np.hypot(out[:, 0], out[:, 2])
    unit = out[:, [0, 2]] / np.where(rho > 0, rho, 1.0)[:, None]
    limit = wall.radius + 0.5 * wall.tolerance
    beyond = rho > limit
    out[np.ix_(beyond, [0, 2])] = limit * unit[beyond]
    band = rho > wall.radius
    slope = out[band][:, [1, 3]]
    radial = np.maximum(np.sum(slope * unit[band], axis=1), 0.0)
    out[np.ix_(band, [1, 3])] = slope - radial[:, None] * unit[band]
    return out.ravel()
