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
def _cross_difference(u, v, out):
    """out (3, 3) = [u - v]x."""
    out[0, 0], out[0, 1], out[0, 2] = 0.0, v[2] - u[2], u[1] - v[1]
    out[1, 0], out[1, 1], out[1, 2] = u[2] - v[2], 0.0, v[0] - u[0]
    out[2, 0], out[2, 1], out[2, 2] = v[1] - u[1], u[0] - v[0], 0.0


@njit(**JIT, inline="always")
def _cross(u, v, out):
    out[0] = u[1] * v[2] - u[2] * v[1]
    out[1] = u[2] * v[0] - u[0] * v[2]
    out[2] = u[0] * v[1] - u[1] * v[0]


@njit(**JIT)
def dihedral_hessian(pc, pd, pa, pb, hess, work=None):
    """Fill hess (4, 4, 3, 3) with the Hessian of the signed dihedral angle of
    :func:`structure.bending._dihedral` with respect to (c, d, a, b) (1/m^2). ``work``: a
    scratch array (64, 3) (allocated when None)."""
    if work is None:
        work = np.empty((64, 3))
    e, eh, n1, n2 = work[0], work[1], work[2], work[3]
    w1, w2, t0, t1 = work[4], work[5], work[6], work[7]
    # dn1, dn2 (4 nodes x 3 x 3): rows 8..19 and 20..31; wn1, wn2, pe: rows 32..40
    dn1 = work[8:20].reshape((4, 3, 3))
    dn2 = work[20:32].reshape((4, 3, 3))
    wn1, wn2, pe = work[32:35], work[35:38], work[38:41]
    dle, dal1, dal2 = work[41:45], work[45:49], work[49:53]
    dbe1, dbe2 = work[53:57], work[57:61]
    dw1, dw2 = work[61:64], np.empty((3, 3))
    for r in range(3):
        e[r] = pb[r] - pa[r]
    le = np.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    for r in range(3):
        eh[r] = e[r] / le
        t0[r] = pc[r] - pa[r]
        t1[r] = pc[r] - pb[r]
    _cross(t0, t1, n1)
    for r in range(3):
        t0[r] = pd[r] - pb[r]
        t1[r] = pd[r] - pa[r]
    _cross(t0, t1, n2)
    s1 = n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]
    s2 = n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]
    for r in range(3):
        w1[r] = n1[r] / s1
        w2[r] = n2[r] / s2
    for r in range(3):
        for c in range(3):
            eye = 1.0 if r == c else 0.0
            wn1[r, c] = (eye - 2.0 * n1[r] * n1[c] / s1) / s1
            wn2[r, c] = (eye - 2.0 * n2[r] * n2[c] / s2) / s2
            pe[r, c] = (eye - eh[r] * eh[c]) / le
    alpha1 = alpha2 = beta1 = beta2 = 0.0
    for r in range(3):
        alpha1 += (pc[r] - pb[r]) * eh[r]
        alpha2 += (pd[r] - pb[r]) * eh[r]
        beta1 += (pc[r] - pa[r]) * eh[r]
        beta2 += (pd[r] - pa[r]) * eh[r]
    dn1[:, :, :] = 0.0
    dn2[:, :, :] = 0.0
    _cross_difference(pb, pa, dn1[0])    # dn1/dc = [b - a]x
    _cross_difference(pc, pb, dn1[2])    # dn1/da = [c - b]x
    _cross_difference(pa, pc, dn1[3])    # dn1/db = [a - c]x
    _cross_difference(pa, pb, dn2[1])    # dn2/dd = [a - b]x
    _cross_difference(pb, pd, dn2[2])    # dn2/da = [b - d]x
    _cross_difference(pd, pa, dn2[3])    # dn2/db = [d - a]x
    dle[:, :] = 0.0
    dal1[:, :] = 0.0
    dal2[:, :] = 0.0
    dbe1[:, :] = 0.0
    dbe2[:, :] = 0.0
    for r in range(3):
        dle[2, r], dle[3, r] = -eh[r], eh[r]
        dal1[0, r] = dbe1[0, r] = eh[r]
        dal2[1, r] = dbe2[1, r] = eh[r]
    for r in range(3):
        pcb = pdb = pca = pda = 0.0
        for c in range(3):
            pcb += pe[r, c] * (pc[c] - pb[c])
            pdb += pe[r, c] * (pd[c] - pb[c])
            pca += pe[r, c] * (pc[c] - pa[c])
            pda += pe[r, c] * (pd[c] - pa[c])
        dal1[3, r] = -eh[r] + pcb
        dal1[2, r] = -pcb
        dal2[3, r] = -eh[r] + pdb
        dal2[2, r] = -pdb
        dbe1[2, r] = -eh[r] - pca
        dbe1[3, r] = pca
        dbe2[2, r] = -eh[r] - pda
        dbe2[3, r] = pda
    for y in range(4):
        for r in range(3):
            for c in range(3):
                a1 = 0.0
                a2 = 0.0
                for k in range(3):
                    a1 += wn1[r, k] * dn1[y, k, c]
                    a2 += wn2[r, k] * dn2[y, k, c]
                dw1[r, c] = a1
                dw2[r, c] = a2
        for r in range(3):
            for c in range(3):
                hess[0, y, r, c] = SIGN * (w1[r] * dle[y, c] + le * dw1[r, c])
                hess[1, y, r, c] = SIGN * (w2[r] * dle[y, c] + le * dw2[r, c])
                hess[2, y, r, c] = SIGN * (w1[r] * dal1[y, c] + alpha1 * dw1[r, c]
                                           + w2[r] * dal2[y, c] + alpha2 * dw2[r, c])
                hess[3, y, r, c] = -SIGN * (w1[r] * dbe1[y, c] + beta1 * dw1[r, c]
                                            + w2[r] * dbe2[y, c] + beta2 * dw2[r, c])


@njit(**JIT)
def element_hessians(x, triangles, flap, ghost, active, rest_angle, reference, stiffness,
                     need_hessian, gauss_newton=False):
    """Energy (J), gradient (n, 3) N and element blocks (m, 6, 6, 3, 3) N/m of the bending
    (arguments as :class:`structure.bending.MidedgeBending`'s fields); with ``gauss_newton``
    the blocks leave out the angles' own curvature, sum_i (K d)_i Hessian(theta_i), and are
    positive semi-definite (K_T is)."""
    n, m = x.shape[0], triangles.shape[0]
    grad = np.zeros((n, 3))
    blocks = np.zeros((m, 6, 6, 3, 3)) if need_hessian else np.zeros((0, 6, 6, 3, 3))
    nodes = np.empty((3, 4), dtype=np.int64)
    grads = np.empty((3, 4, 3))
    delta = np.empty(3)
    force = np.empty(3)
    local = np.empty((3, 4), dtype=np.int64)
    hess = np.empty((4, 4, 3, 3))
    work = np.empty((64, 3))
    energy = 0.0
    for t in range(m):
        _triangle(x, triangles, flap, ghost, active, rest_angle, reference, t, nodes, grads,
                  delta)
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
            if force[i] == 0.0 or gauss_newton:
                continue
            c_, a_, b_, d_ = (triangles[t, i], triangles[t, (i + 1) % 3],
                              triangles[t, (i + 2) % 3], flap[t, i])
            pd = x[d_] if d_ >= 0 else ghost[t, i]
            dihedral_hessian(x[c_], pd, x[a_], x[b_], hess, work)
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

    def follow(self, x: np.ndarray) -> None:
        """Move each hinge's reference turn to ``x`` (n, 3) m
        (:meth:`structure.bending.MidedgeBending.follow`)."""
        self.bending.follow(x)

    def path_state(self) -> np.ndarray:
        """A copy of the hinges' reference turns (m, 3) rad, for :meth:`restore_path`."""
        return self.bending.reference_change.copy()

    def restore_path(self, saved: np.ndarray) -> None:
        """The hinges' reference turns back to ``saved`` (:meth:`path_state`)."""
        self.bending.reference_change[:] = saved

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(energy J, gradient (n, 3) N, blocks (m, 6, 6, 3, 3) N/m) at ``x`` (n, 3) m."""
        b = self.bending
        return element_hessians(np.ascontiguousarray(x, dtype=float), b.triangles, b.flap,
                                b.ghost, b.active, b.rest_angle, b.reference_change,
                                b.stiffness, hessian)

    def convex_blocks(self, x: np.ndarray) -> np.ndarray:
        """The Gauss-Newton blocks (m, 6, 6, 3, 3) N/m, sum_ij K_ij grad(theta_i)
        grad(theta_j)^T: positive semi-definite, the Hessian's where every angle is at its
        reference (a projected Newton's convex part)."""
        b = self.bending
        return element_hessians(np.ascontiguousarray(x, dtype=float), b.triangles, b.flap,
                                b.ghost, b.active, b.rest_angle, b.reference_change,
                                b.stiffness, True, True)[2]
