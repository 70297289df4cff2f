"""The tank wall as a smooth barrier on each free node's gap to the sphere (Incremental
Potential Contact: Li et al. 2020, "Incremental potential contact", ACM TOG 39(4)).

For a node at x with r = |x| inside a tank of radius R the gap is d = R - r, and the wall's
energy is

    B(x) = kappa sum_i A_i b(d_i),    b(d) = -(d - dhat)^2 ln(d / dhat)  for 0 < d < dhat,

b = 0 beyond ``dhat`` and +inf at or beyond the wall (IPC's barrier, as ``ipctk.barrier``
computes it; C2 at dhat), A_i the node's rest area (m^2) and kappa (Pa/m) the barrier's
stiffness. With x^ = x / r, dd/dx = -x^ and d2d/dx2 = -(I - x^ x^T) / r, so

    grad_i = -kappa A_i b'(d) x^,
    Hess_i = kappa A_i [b''(d) x^ x^T - b'(d) (I - x^ x^T) / r],

both positive semi-definite terms (b' < 0 < b'' inside dhat): the wall adds no negative
curvature and no contact set that changes between Newton iterations. A node never reaches
the wall, because every step is cut to :func:`largest_step` of the way there (the sphere is
convex: nodes inside mean edges and triangles inside).

The stiffness is set so that a node pressed on the wall by a pressure ``pressure`` (Pa)
rests at the gap ``rest_fraction`` dhat: kappa = pressure / |b'(rest_fraction dhat)|
(:func:`stiffness_for`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

JIT = dict(cache=True, nogil=True)

REST_FRACTION = 0.1
"""The gap, as a fraction of dhat, at which the barrier carries the pressing pressure."""


@njit(**JIT, inline="always")
def barrier(d, dhat):
    """IPC's b(d) (m^2) and its first two derivatives (m, -); (inf, 0, 0) at d <= 0."""
    if d <= 0.0:
        return np.inf, 0.0, 0.0
    if d >= dhat:
        return 0.0, 0.0, 0.0
    s = d - dhat
    log = np.log(d / dhat)
    return (-s * s * log, -2.0 * s * log - s * s / d,
            -2.0 * log - 4.0 * s / d + s * s / (d * d))


def barrier_slope(d: float, dhat: float) -> float:
    """b'(d) (m) (for the stiffness)."""
    return float(barrier(float(d), float(dhat))[1])


def stiffness_for(pressure: float, dhat: float, rest_fraction: float = REST_FRACTION) -> float:
    """kappa (Pa/m) at which the pressure ``pressure`` (Pa) is carried at the gap
    ``rest_fraction`` dhat (module doc)."""
    return float(pressure) / abs(barrier_slope(rest_fraction * dhat, dhat))


@njit(**JIT)
def wall_barrier(x, weight, radius, dhat, need_hessian):
    """sum_i weight_i b(R - |x_i|) (J for weights kappa A_i in N/m^3), gradient (n, 3) N and
    blocks (n, 1, 1, 3, 3) N/m; nodes with zero weight carry nothing."""
    n = x.shape[0]
    grad = np.zeros((n, 3))
    blocks = np.zeros((n, 1, 1, 3, 3)) if need_hessian else np.zeros((0, 1, 1, 3, 3))
    energy = 0.0
    for i in range(n):
        w = weight[i]
        if w == 0.0:
            continue
        r = np.sqrt(x[i, 0] ** 2 + x[i, 1] ** 2 + x[i, 2] ** 2)
        b, db, ddb = barrier(radius - r, dhat)
        if b == 0.0 and db == 0.0:
            continue
        if not np.isfinite(b):
            return np.inf, grad, blocks
        energy += w * b
        for a in range(3):
            grad[i, a] = -w * db * x[i, a] / r
        if need_hessian:
            for a in range(3):
                for c in range(3):
                    u = x[i, a] * x[i, c] / (r * r)
                    eye = 1.0 if a == c else 0.0
                    blocks[i, 0, 0, a, c] = w * (ddb * u - db * (eye - u) / r)
    return energy, grad, blocks


@njit(**JIT)
def _largest_step(x, dx, weight, radius, fraction):
    alpha = 1.0
    for i in range(x.shape[0]):
        if weight[i] == 0.0:
            continue
        a = dx[i, 0] ** 2 + dx[i, 1] ** 2 + dx[i, 2] ** 2
        if a == 0.0:
            continue
        b = x[i, 0] * dx[i, 0] + x[i, 1] * dx[i, 1] + x[i, 2] * dx[i, 2]
        r2 = x[i, 0] ** 2 + x[i, 1] ** 2 + x[i, 2] ** 2
        # |x + s dx| = r_goal: the node moves at most ``fraction`` of its gap outward
        r = np.sqrt(r2)
        goal = r + fraction * (radius - r)
        c = r2 - goal * goal
        disc = b * b - a * c
        s = (-b + np.sqrt(max(disc, 0.0))) / a
        if s < alpha:
            alpha = max(s, 0.0)
    return alpha


@dataclass(frozen=True)
class BarrierWall:
    """The tank wall's barrier (module doc) on nodes of weight ``weight`` (n,) N/m^3
    (kappa A_i; zero on the fixed nodes), radius ``radius`` m, activation gap ``dhat`` m."""

    weight: np.ndarray
    radius: float
    dhat: float

    @classmethod
    def build(cls, free: np.ndarray, node_area: np.ndarray, radius: float, dhat: float,
              pressure: float, rest_fraction: float = REST_FRACTION) -> "BarrierWall":
        """The barrier on the ``free`` (n,) bool nodes of rest areas ``node_area`` (n,) m^2,
        its stiffness such that ``pressure`` (Pa) rests at ``rest_fraction`` dhat."""
        if not dhat > 0:
            raise ValueError(f"barrier dhat must be > 0 m, got {dhat!r}")
        if not pressure > 0:
            raise ValueError(f"barrier pressure must be > 0 Pa, got {pressure!r}")
        kappa = stiffness_for(pressure, dhat, rest_fraction)
        weight = np.where(np.asarray(free, dtype=bool), kappa * np.asarray(node_area), 0.0)
        return cls(np.ascontiguousarray(weight, dtype=float), float(radius), float(dhat))

    @property
    def element_nodes(self) -> np.ndarray:
        return np.arange(len(self.weight), dtype=np.int64)[:, None]

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(energy J, gradient (n, 3) N, blocks (n, 1, 1, 3, 3) N/m) at ``x`` (n, 3) m;
        energy +inf where a weighted node is on or beyond the wall."""
        return wall_barrier(np.ascontiguousarray(x, dtype=float), self.weight, self.radius,
                            self.dhat, hessian)

    def largest_step(self, x: np.ndarray, dx: np.ndarray, fraction: float = 0.9) -> float:
        """The largest s in [0, 1] for which no weighted node of ``x + s dx`` (n, 3) m has
        closed more than ``fraction`` of its gap to the wall."""
        return float(_largest_step(np.ascontiguousarray(x, dtype=float),
                                   np.ascontiguousarray(dx, dtype=float), self.weight,
                                   self.radius, float(fraction)))

    def gaps(self, x: np.ndarray) -> np.ndarray:
        """(n,) m: each node's gap R - |x| (the fixed nodes' too)."""
        return self.radius - np.linalg.norm(np.asarray(x, dtype=float), axis=1)
