"""The calibrated bending energy's Hessian (:class:`structure.bending.MidedgeBending`).

Per triangle the energy is 1/2 d^T K d, d (3,) the changes of the dihedral angles at its
edges, so that

    Hessian = sum_ij K_ij grad(theta_i) grad(theta_j)^T + sum_i (K d)_i Hessian(theta_i).

The dihedral angle's gradient is Bridson, Marino & Fedkiw's (2003), as
:func:`structure.bending._dihedral` computes it: with e = b - a, l = |e|, e^ = e / l,
n1 = (c - a) x (c - b), n2 = (d - b) x (d - a), w = n / |n|^2 and sigma the angle's sign,

    g_c = sigma l w1,   g_d = sigma l w2,
    g_a = sigma (alpha1 w1 + alpha2 w2),     alpha1 = (c - b).e^, alpha2 = (d - b).e^,
    g_b = -sigma (beta1 w1 + beta2 w2),      beta1 = (c - a).e^,  beta2 = (d - a).e^.

Its Hessian follows by the product rule with dw/dn = (I - 2 n^ n^T) / |n|^2, dn1/dc = [e]x,
dn1/da = [c - b]x, dn1/db = -[c - a]x, dn2/dd = -[e]x, dn2/db = [d - a]x, dn2/da = -[d - b]x
([v]x u = v x u), dl/db = -dl/da = e^ and de^/db = -de^/da = (I - e^ e^T) / l (the same
derivation as Tamstorf & Grinspun 2013, "Discrete bending forces and their Jacobians",
written for this angle's gradient). A clamped edge's ghost vertex is fixed: its rows are not
assembled.

Element nodes per triangle: its three vertices, then the three flap vertices across its
edges (-1 on a boundary edge).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from ..bending import SIGN, MidedgeBending, _triangle

JIT = dict(cache=True, nogil=True)


@njit(**JIT, inline="always")
def _cross_matrix(v, out):
    """out (3, 3) = [v]x, so that out @ u = v x u."""
    out[0, 0], out[0, 1], out[0, 2] = 0.0, -v[2], v[1]
    out[1, 0], out[1, 1], out[1, 2] = v[2], 0.0, -v[0]
    out[2, 0], out[2, 1], out[2, 2] = -v[1], v[0], 0.0


@njit(**JIT)
def dihedral_hessian(pc, pd, pa, pb, hess):
    """Fill hess (4, 4, 3, 3) with the Hessian of the signed dihedral angle of
    :func:`structure.bending._dihedral` with respect to (c, d, a, b) (1/m^2)."""
    e = pb - pa
    le = np.sqrt(e @ e)
    eh = e / le
    n1 = np.cross(pc - pa, pc - pb)
    n2 = np.cross(pd - pb, pd - pa)
    s1, s2 = n1 @ n1, n2 @ n2
    w1, w2 = n1 / s1, n2 / s2
    eye = np.eye(3)
    wn1 = (eye - 2.0 * np.outer(n1, n1) / s1) / s1
    wn2 = (eye - 2.0 * np.outer(n2, n2) / s2) / s2
    pe = (eye - np.outer(eh, eh)) / le
    alpha1, alpha2 = (pc - pb) @ eh, (pd - pb) @ eh
    beta1, beta2 = (pc - pa) @ eh, (pd - pa) @ eh
    # derivatives with respect to (c, d, a, b): dn (4, 3, 3), scalars' gradients (4, 3)
    dn1 = np.zeros((4, 3, 3))
    dn2 = np.zeros((4, 3, 3))
    m = np.empty((3, 3))
    _cross_matrix(e, m)
    dn1[0] = m
    dn2[1] = -m
    _cross_matrix(pc - pb, m)
    dn1[2] = m
    _cross_matrix(pc - pa, m)
    dn1[3] = -m
    _cross_matrix(pd - pa, m)
    dn2[3] = m
    _cross_matrix(pd - pb, m)
    dn2[2] = -m
    dle = np.zeros((4, 3))
    dle[2], dle[3] = -eh, eh
    dal1, dal2, dbe1, dbe2 = np.zeros((4, 3)), np.zeros((4, 3)), np.zeros((4, 3)), np.zeros((4, 3))
    dal1[0] = eh
    dal1[3] = -eh + pe @ (pc - pb)
    dal1[2] = -(pe @ (pc - pb))
    dal2[1] = eh
    dal2[3] = -eh + pe @ (pd - pb)
    dal2[2] = -(pe @ (pd - pb))
    dbe1[0] = eh
    dbe1[2] = -eh - pe @ (pc - pa)
    dbe1[3] = pe @ (pc - pa)
    dbe2[1] = eh
    dbe2[2] = -eh - pe @ (pd - pa)
    dbe2[3] = pe @ (pd - pa)
    for y in range(4):
        dw1 = wn1 @ dn1[y]
        dw2 = wn2 @ dn2[y]
        hess[0, y] = SIGN * (np.outer(w1, dle[y]) + le * dw1)
        hess[1, y] = SIGN * (np.outer(w2, dle[y]) + le * dw2)
        hess[2, y] = SIGN * (np.outer(w1, dal1[y]) + alpha1 * dw1
                             + np.outer(w2, dal2[y]) + alpha2 * dw2)
        hess[3, y] = -SIGN * (np.outer(w1, dbe1[y]) + beta1 * dw1
                              + np.outer(w2, dbe2[y]) + beta2 * dw2)


@njit(**JIT)
def element_hessians(x, triangles, flap, ghost, active, rest_angle, stiffness, need_hessian):
    """Energy (J), gradient (n, 3) N and element blocks (m, 6, 6, 3, 3) N/m of the bending
    (arguments as :class:`structure.bending.MidedgeBending`'s fields)."""
    n, m = x.shape[0], triangles.shape[0]
    grad = np.zeros((n, 3))
    blocks = np.zeros((m, 6, 6, 3, 3)) if need_hessian else np.zeros((0, 6, 6, 3, 3))
    nodes = np.empty((3, 4), dtype=np.int64)
    grads = np.empty((3, 4, 3))
    delta = np.empty(3)
    force = np.empty(3)
    local = np.empty((3, 4), dtype=np.int64)
    hess = np.empty((4, 4, 3, 3))
    energy = 0.0
    for t in range(m):
        _triangle(x, triangles, flap, ghost, active, rest_angle, t, nodes, grads, delta)
        for i in range(3):
            # element slots of hinge i's (c, d, a, b)
            local[i, 0], local[i, 1] = i, 3 + i
            local[i, 2], local[i, 3] = (i + 1) % 3, (i + 2) % 3
            s = 0.0
            for j in range(3):
                s += stiffness[t, i, j] * delta[j]
            force[i] = s
            energy += 0.5 * delta[i] * s
            if not active[t, i]:
                continue
            for k in range(4):
                if nodes[i, k] >= 0:
                    for r in range(3):
                        grad[nodes[i, k], r] += s * grads[i, k, r]
        if not need_hessian:
            continue
        for i in range(3):
            if not active[t, i]:
                continue
            for j in range(3):
                kij = stiffness[t, i, j]
                if kij == 0.0 or not active[t, j]:
                    continue
                for p in range(4):
                    for q in range(4):
                        if nodes[i, p] < 0 or nodes[j, q] < 0:
                            continue
                        for r in range(3):
                            for c in range(3):
                                blocks[t, local[i, p], local[j, q], r, c] += \
                                    kij * grads[i, p, r] * grads[j, q, c]
            if force[i] == 0.0:
                continue
            c_, a_, b_, d_ = (triangles[t, i], triangles[t, (i + 1) % 3],
                              triangles[t, (i + 2) % 3], flap[t, i])
            pd = x[d_] if d_ >= 0 else ghost[t, i]
            dihedral_hessian(x[c_], pd, x[a_], x[b_], hess)
            for p in range(4):
                for q in range(4):
                    if nodes[i, p] < 0 or nodes[i, q] < 0:
                        continue
                    for r in range(3):
                        for c in range(3):
                            blocks[t, local[i, p], local[i, q], r, c] += force[i] * hess[p, q, r, c]
    return energy, grad, blocks


@dataclass(frozen=True)
class BendingTerm:
    """The tangent of a :class:`structure.bending.MidedgeBending`."""

    bending: MidedgeBending

    @property
    def element_nodes(self) -> np.ndarray:
        """(m, 6) int64: each triangle's vertices, then its flap vertices (-1: none)."""
        b = self.bending
        return np.ascontiguousarray(np.hstack([b.triangles, b.flap]))

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(energy J, gradient (n, 3) N, blocks (m, 6, 6, 3, 3) N/m) at ``x`` (n, 3) m."""
        b = self.bending
        return element_hessians(np.ascontiguousarray(x, dtype=float), b.triangles, b.flap,
                                b.ghost, b.active, b.rest_angle, b.stiffness, hessian)
