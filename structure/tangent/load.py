"""The liquid's load and the tank wall: the enclosed volume, the liquid's first moment and
the wall contact, each with its gradient and Hessian.

The hydrostatic load is conservative: for a liquid of density rho under body acceleration b
below the membrane, with the pressure level p (Pa at the tank centre) the multiplier of the
volume V(x) = V*, the potential is (:mod:`structure.shell`)

    Pi_load(x) = -rho b . M1(x) - sum_i m_i b . x_i - p (V(x) - V*),

so the follower pressure's load stiffness is the Hessian of -rho b . M1 - p V. V and M1 are
sums over the membrane's triangles (divergence theorem, as :func:`structure.kernels.
closed_volume_term` and :func:`structure.kernels.first_moment`): with the area vector
A = (x1 - x0) x (x2 - x0) / 2 of a triangle, V_t = s A_z (z0 + z1 + z2) / 3 and
M1_t,k = s A_k q_k / 12, q_k = sum_i x_ik^2 + sum_{i<j} x_ik x_jk, s the grid's volume sign.
A is bilinear: dA_k/dx_p = (x_{p+1} - x_{p-1}) x e_k / 2 and d2A_k/dx_{p,i} dx_{p+1,j} =
eps_kij / 2 (the other order's sign reversed).

The wall is a one-sided quadratic penalty on each free node outside the tank's sphere,
1/2 k (r - R)^2 for r > R: gradient k (r - R) x^, Hessian k [x^ x^T + (r - R)/r (I - x^ x^T)].
A node on the sphere (r = R, as the rest shape's are) counts as in contact: its Hessian is
the outward one, k x^ x^T, so that a Newton step does not push it through the wall.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from ..grid import triangles_from_quads

JIT = dict(cache=True, nogil=True)


@njit(**JIT)
def element_hessians(x, triangles, sign, volume_weight, moment_weight, need_hessian):
    """w_V V + w . M1 over the triangles (J for weights in Pa and N/m^3), its gradient (n, 3)
    and element blocks (m, 3, 3, 3, 3): ``volume_weight`` w_V, ``moment_weight`` w (3,)."""
    n, m = x.shape[0], triangles.shape[0]
    grad = np.zeros((n, 3))
    blocks = np.zeros((m, 3, 3, 3, 3)) if need_hessian else np.zeros((0, 3, 3, 3, 3))
    total = 0.0
    area = np.empty(3)
    darea = np.empty((3, 3, 3))      # [k, node p, coordinate i]
    dq = np.empty(3)
    for t in range(m):
        tri = (triangles[t, 0], triangles[t, 1], triangles[t, 2])
        p0, p1, p2 = x[tri[0]], x[tri[1]], x[tri[2]]
        ab, ac = p1 - p0, p2 - p0
        area[0] = 0.5 * (ab[1] * ac[2] - ab[2] * ac[1])
        area[1] = 0.5 * (ab[2] * ac[0] - ab[0] * ac[2])
        area[2] = 0.5 * (ab[0] * ac[1] - ab[1] * ac[0])
        for p in range(3):
            nxt, prv = x[tri[(p + 1) % 3]], x[tri[(p + 2) % 3]]
            dv = nxt - prv
            for k in range(3):
                # (dv x e_k) / 2
                k1, k2 = (k + 1) % 3, (k + 2) % 3
                darea[k, p, k] = 0.0
                darea[k, p, k1] = 0.5 * dv[k2]
                darea[k, p, k2] = -0.5 * dv[k1]
        # volume: s A_z zbar
        zbar = (p0[2] + p1[2] + p2[2]) / 3.0
        total += volume_weight * sign * area[2] * zbar
        for p in range(3):
            for i in range(3):
                grad[tri[p], i] += volume_weight * sign * zbar * darea[2, p, i]
            grad[tri[p], 2] += volume_weight * sign * area[2] / 3.0
        # first moment: s A_k q_k / 12
        for k in range(3):
            w = moment_weight[k] * sign / 12.0
            if w == 0.0:
                continue
            a, b, c = p0[k], p1[k], p2[k]
            q = a * a + b * b + c * c + a * b + b * c + c * a
            total += w * area[k] * q
            ssum = a + b + c
            dq[0], dq[1], dq[2] = a + ssum, b + ssum, c + ssum
            for p in range(3):
                for i in range(3):
                    grad[tri[p], i] += w * q * darea[k, p, i]
                grad[tri[p], k] += w * area[k] * dq[p]
        if not need_hessian:
            continue
        for p in range(3):
            for r in range(3):
                # bilinear part of A: d2A_k / dx_{p,i} dx_{r,j} = +-eps_kij / 2 for r = p +- 1
                if r == (p + 1) % 3:
                    side = 0.5
                elif r == (p + 2) % 3:
                    side = -0.5
                else:
                    side = 0.0
                for i in range(3):
                    for j in range(3):
                        h = 0.0
                        for k in range(3):
                            eps = _levi_civita(k, i, j)
                            wk = moment_weight[k] * sign / 12.0
                            a, b, c = p0[k], p1[k], p2[k]
                            q = a * a + b * b + c * c + a * b + b * c + c * a
                            ssum = a + b + c
                            dqp = x[tri[p], k] + ssum
                            dqr = x[tri[r], k] + ssum
                            if eps != 0.0 and side != 0.0:
                                h += wk * q * side * eps
                                if k == 2:
                                    h += volume_weight * sign * zbar * side * eps
                            if wk != 0.0:
                                if i == k:
                                    h += wk * dqp * darea[k, r, j]
                                if j == k:
                                    h += wk * darea[k, p, i] * dqr
                                if i == k and j == k:
                                    h += wk * area[k] * (2.0 if p == r else 1.0)
                        # volume: dA_z (x) dzbar + dzbar (x) dA_z
                        if j == 2:
                            h += volume_weight * sign * darea[2, p, i] / 3.0
                        if i == 2:
                            h += volume_weight * sign * darea[2, r, j] / 3.0
                        blocks[t, p, r, i, j] = h
    return total, grad, blocks


@njit(**JIT, inline="always")
def _levi_civita(k, i, j):
    if k == i or i == j or j == k:
        return 0.0
    return 1.0 if (i - k) % 3 == 1 else -1.0


@dataclass(frozen=True)
class LiquidTerm:
    """``volume_weight`` V + ``moment_weight`` . M1 of the membrane's triangles (the
    membrane parts: constants of the tank wall left out). With volume_weight = -p and
    moment_weight = -rho b it is the hydrostatic load's potential but for the nodes' own
    weight, whose Hessian is zero.

    triangles (m, 3) int64 (the grid's quads split as :func:`structure.grid.
    triangles_from_quads` does, the split the volume kernels sum); sign (-) the grid's
    ``volume_sign``; volume_weight Pa; moment_weight (3,) N/m^3."""

    triangles: np.ndarray
    sign: float
    volume_weight: float = 0.0
    moment_weight: tuple = (0.0, 0.0, 0.0)

    @classmethod
    def of_model(cls, model, volume_weight: float = 0.0,
                 moment_weight=(0.0, 0.0, 0.0)) -> "LiquidTerm":
        """The term on a :class:`structure.model.MembraneModel`'s grid."""
        return cls(np.ascontiguousarray(triangles_from_quads(model.face_nodes), dtype=np.int64),
                   float(model.volume_sign),
                   float(volume_weight), tuple(float(w) for w in moment_weight))

    @property
    def element_nodes(self) -> np.ndarray:
        return self.triangles

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(value, gradient (n, 3), blocks (m, 3, 3, 3, 3)) at ``x`` (n, 3) m."""
        return element_hessians(np.ascontiguousarray(x, dtype=float), self.triangles,
                                self.sign, self.volume_weight,
                                np.asarray(self.moment_weight, dtype=float), hessian)


@njit(**JIT)
def wall_hessians(x, free, radius, stiffness, need_hessian):
    """The wall's energy (J), gradient (n, 3) N and blocks (n, 1, 1, 3, 3) N/m."""
    n = x.shape[0]
    grad = np.zeros((n, 3))
    blocks = np.zeros((n, 1, 1, 3, 3)) if need_hessian else np.zeros((0, 1, 1, 3, 3))
    energy = 0.0
    for i in range(n):
        if not free[i]:
            continue
        r = np.sqrt(x[i, 0] ** 2 + x[i, 1] ** 2 + x[i, 2] ** 2)
        if r < radius:
            continue
        over = r - radius
        energy += 0.5 * stiffness * over * over
        for a in range(3):
            grad[i, a] = stiffness * over * x[i, a] / r
        if need_hessian:
            for a in range(3):
                for b in range(3):
                    u = x[i, a] * x[i, b] / (r * r)
                    blocks[i, 0, 0, a, b] = stiffness * (u + over / r * ((a == b) - u))
    return energy, grad, blocks


@dataclass(frozen=True)
class WallTerm:
    """The tank wall's penalty on the ``free`` (n,) bool nodes: ``stiffness`` N/m beyond
    ``radius`` m (:func:`structure.shell._forces`'s wall)."""

    free: np.ndarray
    radius: float
    stiffness: float

    @property
    def element_nodes(self) -> np.ndarray:
        return np.arange(len(self.free), dtype=np.int64)[:, None]

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(energy J, gradient (n, 3) N, blocks (n, 1, 1, 3, 3) N/m) at ``x`` (n, 3) m."""
        return wall_hessians(np.ascontiguousarray(x, dtype=float),
                             np.asarray(self.free, dtype=np.bool_), float(self.radius),
                             float(self.stiffness), hessian)
