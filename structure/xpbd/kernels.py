"""Numba kernels of the XPBD membrane: one block of three compliant constraints, the sweeps
over every triangle's Green-strain and bending blocks, and the hard volume constraint."""
from __future__ import annotations

import numpy as np
from numba import njit

from ..bending import _triangle
from ..kernels import closed_volume_gradient, closed_volume_term

JIT = dict(cache=True, nogil=True)


@njit(**JIT, inline="always")
def _solve3(a, r, out):
    """out = a^-1 r for a symmetric 3 x 3 a (Cramer); rows with a zero diagonal are skipped."""
    for i in range(3):
        if a[i, i] == 0.0:
            a[i, i] = 1.0
            r[i] = 0.0
    c00 = a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]
    c01 = a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]
    c02 = a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]
    det = a[0, 0] * c00 + a[0, 1] * c01 + a[0, 2] * c02
    if det == 0.0:
        out[:] = 0.0
        return
    c10 = a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]
    c11 = a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]
    c12 = a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]
    c20 = a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]
    c21 = a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]
    c22 = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
    out[0] = (c00 * r[0] + c10 * r[1] + c20 * r[2]) / det
    out[1] = (c01 * r[0] + c11 * r[1] + c21 * r[2]) / det
    out[2] = (c02 * r[0] + c12 * r[1] + c22 * r[2]) / det


@njit(**JIT, inline="always")
def _block(x, inv_mass, nodes, grads, value, compliance, lam, t, inv_dt2, apply_only, a, r,
           dlam):
    """One XPBD block update of three constraints: nodes (3, k) (-1: none), grads (3, k, 3),
    value (3,), compliance alpha (3, 3); lam[t] updated.  With apply_only, x += W J^T lam[t].
    a (3, 3), r (3,), dlam (3,) are scratch."""
    k = nodes.shape[1]
    if apply_only:
        for i in range(3):
            dlam[i] = lam[t, i]
    else:
        for i in range(3):
            for j in range(i, 3):
                s = 0.0
                for p in range(k):
                    n = nodes[i, p]
                    if n < 0:
                        continue
                    for q in range(k):
                        if nodes[j, q] == n:
                            s += inv_mass[n] * (grads[i, p, 0] * grads[j, q, 0]
                                                + grads[i, p, 1] * grads[j, q, 1]
                                                + grads[i, p, 2] * grads[j, q, 2])
                a[i, j] = s + compliance[t, i, j] * inv_dt2
                a[j, i] = a[i, j]
        for i in range(3):
            s = value[i]
            for j in range(3):
                s += compliance[t, i, j] * inv_dt2 * lam[t, j]
            r[i] = -s
        _solve3(a, r, dlam)
        for i in range(3):
            lam[t, i] += dlam[i]
    for i in range(3):
        for p in range(k):
            n = nodes[i, p]
            if n >= 0 and inv_mass[n] > 0.0:
                w = inv_mass[n] * dlam[i]
                x[n, 0] += w * grads[i, p, 0]
                x[n, 1] += w * grads[i, p, 1]
                x[n, 2] += w * grads[i, p, 2]


TAUT, WRINKLED, SLACK = 0, 1, 2
"""The tension field's regimes of a triangle (:func:`tension_field_regime`)."""


@njit(**JIT, inline="always")
def tension_field_regime(value, nu):
    """(regime, e1, cos, sin) of a triangle's strain (e00, e11, e01) (-), tensor shear e01:
    TAUT when e2 >= -nu e1, WRINKLED when e1 > 0 > e2 + nu e1, SLACK when e1 <= 0 (e1 >= e2
    its principal strains), and the major direction n1 = (cos, sin) in the triangle's rest
    frame (1, 0 unless wrinkled)."""
    a, d, b = value[0], value[1], value[2]
    mean = 0.5 * (a + d)
    rad = np.sqrt(0.25 * (a - d) * (a - d) + b * b)
    e1 = mean + rad
    e2 = mean - rad
    if e1 <= 0.0:
        return SLACK, e1, 1.0, 0.0
    if e2 < -nu * e1:
        theta = 0.5 * np.arctan2(2.0 * b, a - d)
        return WRINKLED, e1, np.cos(theta), np.sin(theta)
    return TAUT, e1, 1.0, 0.0


@njit(**JIT, inline="always")
def _uniaxial_block(x, inv_mass, nodes, grads, value, cn, sn, compliance, lam, t, inv_dt2):
    """A wrinkled triangle's one constraint: its major principal strain
    e1 = w . (e00, e11, e01), w = (cn^2, sn^2, 2 cn sn), compliance alpha_00 = 1 / (E t A)
    (the plane-stress compliance's first entry), so that its energy e1^2 / (2 alpha_00) is
    the relaxed energy, 1/2 E e1^2 per unit volume, and its gradient w . grad(e) that
    energy's (Pipkin 1986). Its multiplier mu is kept in the block's three as lam[t] = mu w,
    so that a warm start (lam[t] applied through the three strains' gradients) applies it
    whatever the triangle's regime then; mu is read back as w . lam[t] / |w|^2."""
    k = nodes.shape[1]
    w0, w1, w2 = cn * cn, sn * sn, 2.0 * cn * sn
    ww = w0 * w0 + w1 * w1 + w2 * w2
    mu = (w0 * lam[t, 0] + w1 * lam[t, 1] + w2 * lam[t, 2]) / ww
    alpha = compliance[t, 0, 0] * inv_dt2
    e1 = w0 * value[0] + w1 * value[1] + w2 * value[2]
    denom = alpha
    for p in range(k):
        n = nodes[0, p]
        if n < 0:
            continue
        for r in range(3):
            g = w0 * grads[0, p, r] + w1 * grads[1, p, r] + w2 * grads[2, p, r]
            denom += inv_mass[n] * g * g
    dmu = -(e1 + alpha * mu) / denom
    mu += dmu
    lam[t, 0] = mu * w0
    lam[t, 1] = mu * w1
    lam[t, 2] = mu * w2
    for p in range(k):
        n = nodes[0, p]
        if n >= 0 and inv_mass[n] > 0.0:
            w = inv_mass[n] * dmu
            for r in range(3):
                x[n, r] += w * (w0 * grads[0, p, r] + w1 * grads[1, p, r] + w2 * grads[2, p, r])


@njit(**JIT, inline="always")
def relax_strain(value, nu):
    """Tension-field relaxation in place of a triangle's strain (e00, e11, e01) (-), tensor
    shear e01, for a linear isotropic sheet of Poisson ratio ``nu`` (Pipkin 1986): its
    principal strains e1 >= e2 and the major direction n1 (n2 across it) give

    * taut, e2 >= -nu e1: unchanged;
    * wrinkled, e1 > 0 > e2 + nu e1: e1 (n1 n1 - nu n2 n2), uniaxial stress E e1 along n1
      and none across (the wrinkles take the rest of the contraction);
    * slack, e1 <= 0: zero.

    The plane-stress energy of the result is the relaxed energy (1/2 E e1^2 per unit volume
    when wrinkled): the sheet carries no compression. The sweep itself solves a wrinkled
    triangle as one uniaxial constraint (:func:`_uniaxial_block`) and a slack one with zero
    strain (:func:`membrane_sweep`); this function gives the energy
    (:func:`membrane_energy`)."""
    regime, e1, c, s = tension_field_regime(value, nu)
    if regime == SLACK:
        value[0] = 0.0
        value[1] = 0.0
        value[2] = 0.0
    elif regime == WRINKLED:
        value[0] = e1 * (c * c - nu * s * s)
        value[1] = e1 * (s * s - nu * c * c)
        value[2] = e1 * (1.0 + nu) * c * s


@njit(**JIT, inline="always")
def _triangle_strain(x, a, b, c, d, f0, f1, value):
    """The block's strain (s0 - 1, s1 - 1, cos01 / 2) of the triangle (a, b, c) with rest
    inverse d (2, 2) into value (3,); f0, f1 (3,) get the deformation gradient's columns.
    Returns their lengths s0, s1 and the cosine between them."""
    for r in range(3):
        e1 = x[b, r] - x[a, r]
        e2 = x[c, r] - x[a, r]
        f0[r] = e1 * d[0, 0] + e2 * d[1, 0]
        f1[r] = e1 * d[0, 1] + e2 * d[1, 1]
    s0 = np.sqrt(f0[0] * f0[0] + f0[1] * f0[1] + f0[2] * f0[2])
    s1 = np.sqrt(f1[0] * f1[0] + f1[1] * f1[1] + f1[2] * f1[2])
    cos01 = (f0[0] * f1[0] + f0[1] * f1[1] + f0[2] * f1[2]) / (s0 * s1)
    value[0] = s0 - 1.0
    value[1] = s1 - 1.0
    value[2] = 0.5 * cos01
    return s0, s1, cos01


@njit(**JIT)
def membrane_energy(x, triangles, rest_inverse, compliance, relax, nu):
    """Potential (J) of the membrane blocks at x (n, 3) m: sum of 1/2 C^T alpha^-1 C over the
    triangles, C their strain (:func:`relax_strain`-ed when ``relax``)."""
    value = np.empty(3)
    f0 = np.empty(3)
    f1 = np.empty(3)
    energy = 0.0
    for t in range(triangles.shape[0]):
        _triangle_strain(x, triangles[t, 0], triangles[t, 1], triangles[t, 2],
                         rest_inverse[t], f0, f1, value)
        if relax:
            relax_strain(value, nu)
        k = np.linalg.inv(compliance[t])
        for i in range(3):
            for j in range(3):
                energy += 0.5 * value[i] * k[i, j] * value[j]
    return energy


@njit(**JIT)
def membrane_sweep(x, inv_mass, triangles, rest_inverse, compliance, lam, inv_dt2, apply_only,
                   relax, nu):
    """Green-strain blocks of every triangle with a free node (Gauss-Seidel); with ``relax``
    the tension field's regimes (:func:`tension_field_regime`, Poisson ratio ``nu``): a taut
    triangle is the full block, a slack one the block at zero strain, a wrinkled one the
    single constraint on its major principal strain (:func:`_uniaxial_block`), whose energy
    and gradient are the relaxed energy's. (The relaxed strain in the three-constraint block
    with the unrelaxed strain's gradients has the same fixed point, but its steps put energy
    into a released sheet and ran away on the N = 26 diaphragm.)"""
    nodes = np.empty((3, 3), dtype=np.int64)
    grads = np.empty((3, 3, 3))
    value = np.empty(3)
    f0 = np.empty(3)
    f1 = np.empty(3)
    a3, r3, d3 = np.empty((3, 3)), np.empty(3), np.empty(3)
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        if inv_mass[a] == 0.0 and inv_mass[b] == 0.0 and inv_mass[c] == 0.0:
            continue
        d = rest_inverse[t]
        s0, s1, cos01 = _triangle_strain(x, a, b, c, d, f0, f1, value)
        regime, cn, sn = TAUT, 1.0, 0.0
        if relax and not apply_only:
            regime, _, cn, sn = tension_field_regime(value, nu)
            if regime == SLACK:
                value[0] = 0.0
                value[1] = 0.0
                value[2] = 0.0
        for i in range(3):
            nodes[i, 0], nodes[i, 1], nodes[i, 2] = b, c, a
        for r in range(3):
            u0 = f0[r] / s0
            u1 = f1[r] / s1
            g0 = 0.5 * (u1 - cos01 * u0) / s0      # d value[2] / d f0
            g1 = 0.5 * (u0 - cos01 * u1) / s1      # d value[2] / d f1
            grads[0, 0, r] = u0 * d[0, 0]
            grads[0, 1, r] = u0 * d[1, 0]
            grads[1, 0, r] = u1 * d[0, 1]
            grads[1, 1, r] = u1 * d[1, 1]
            grads[2, 0, r] = g0 * d[0, 0] + g1 * d[0, 1]
            grads[2, 1, r] = g0 * d[1, 0] + g1 * d[1, 1]
            for i in range(3):
                grads[i, 2, r] = -grads[i, 0, r] - grads[i, 1, r]
        if regime == WRINKLED:
            _uniaxial_block(x, inv_mass, nodes, grads, value, cn, sn, compliance, lam, t,
                            inv_dt2)
        else:
            _block(x, inv_mass, nodes, grads, value, compliance, lam, t, inv_dt2, apply_only,
                   a3, r3, d3)


@njit(**JIT)
def bending_sweep(x, inv_mass, triangles, flap, ghost, active, rest_angle, reference,
                  compliance, lam, inv_dt2, apply_only):
    """Angle blocks of every triangle whose stencil has a free node (Gauss-Seidel)."""
    nodes = np.empty((3, 4), dtype=np.int64)
    grads = np.empty((3, 4, 3))
    value = np.empty(3)
    a3, r3, d3 = np.empty((3, 3)), np.empty(3), np.empty(3)
    for t in range(triangles.shape[0]):
        free = False
        for i in range(3):
            if inv_mass[triangles[t, i]] > 0.0 or (flap[t, i] >= 0
                                                   and inv_mass[flap[t, i]] > 0.0):
                free = True
        if not free:
            continue
        _triangle(x, triangles, flap, ghost, active, rest_angle, reference, t, nodes, grads,
                  value)
        _block(x, inv_mass, nodes, grads, value, compliance, lam, t, inv_dt2, apply_only,
               a3, r3, d3)


@njit(**JIT)
def volume_constraint(x, inv_mass, faces, sign, base_volume, target, lam, apply_only):
    """Hard volume constraint V(x) = target (alpha = 0, one update); lam (1,) updated."""
    grad = closed_volume_gradient(x, faces, sign)
    if apply_only:
        dlam = lam[0]
    else:
        c = base_volume + closed_volume_term(x, faces, sign) - target
        denom = 0.0
        for n in range(x.shape[0]):
            denom += inv_mass[n] * (grad[n, 0] ** 2 + grad[n, 1] ** 2 + grad[n, 2] ** 2)
        dlam = -c / denom
        lam[0] += dlam
    for n in range(x.shape[0]):
        w = inv_mass[n] * dlam
        x[n, 0] += w * grad[n, 0]
        x[n, 1] += w * grad[n, 1]
        x[n, 2] += w * grad[n, 2]

