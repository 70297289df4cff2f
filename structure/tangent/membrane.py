"""The membrane's in-plane energy per triangle, its gradient and its Hessian, for every law
of the package, written once as a function of the in-plane right Cauchy-Green tensor.

A triangle (a, b, c) with rest-frame inverse D (2, 2) has the deformation gradient's columns
f_j = (x_b - x_a) D[0, j] + (x_c - x_a) D[1, j] (j = 0, 1) and C = F^T F, stored as
c = (c00, c11, c01) = (f0.f0, f1.f1, f0.f1). Every law is an energy psi(c) (J) with its
derivatives psi_c (3,) and psi_cc (3, 3); the chain rule through c(F) and F(x) gives the
9 x 9 element Hessian::

    dpsi/df0 = 2 psi_0 f0 + psi_2 f1,      dpsi/df1 = 2 psi_1 f1 + psi_2 f0,
    d2psi/dfj dfk = sum_ab psi_ab (dc_a/dfj)(dc_b/dfk)^T + 2 psi_0 I [j=k=0]
                    + 2 psi_1 I [j=k=1] + psi_2 I [j != k].

Laws (:data:`LAWS`):

* ``saint-venant-kirchhoff``: W = k/2 [nu (tr E)^2 + (1 - nu) E:E], k = Y / (1 - nu^2),
  E = (C - I)/2 (:func:`structure.hyperelastic.svk_energy_and_gradient`), times t A;
* ``yeoh`` (neo-Hookean when C20 = C30 = 0): W = sum_k Ck0 (I1 - 3)^k, I1 = tr C + 1/det C
  (incompressible; :func:`structure.hyperelastic.energy_and_gradient`), times t A;
* ``block`` and ``tension-field``: the XPBD membrane's energy 1/2 e^T K e of the strain
  e = (|f0| - 1, |f1| - 1, cos(f0, f1) / 2), K = t A x plane stress
  (:func:`structure.xpbd.kernels.membrane_energy`); ``tension-field`` relaxes it (Pipkin
  1986): taut triangles as ``block``, wrinkled ones e1^2 / (2 alpha_00) of the major
  principal strain e1 (its derivatives in closed form: e1 = m + r, m = (e00 + e11)/2,
  r = sqrt(((e00 - e11)/2)^2 + e01^2), r > 0 whenever a triangle is wrinkled), slack ones
  nothing. The relaxed energy is C1 across the regimes; its Hessian jumps there.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from ..xpbd.kernels import SLACK, WRINKLED, tension_field_regime

JIT = dict(cache=True, nogil=True)

SVK, YEOH, BLOCK, TENSION_FIELD = 0, 1, 2, 3
LAWS = {"saint-venant-kirchhoff": SVK, "yeoh": YEOH, "block": BLOCK,
        "tension-field": TENSION_FIELD}
"""Law name -> its code in the kernels."""


@njit(**JIT, inline="always")
def _svk(k, nu, c00, c11, c01, g, h):
    e00, e11, e01 = 0.5 * (c00 - 1.0), 0.5 * (c11 - 1.0), 0.5 * c01
    tr = e00 + e11
    g[0] = 0.5 * k * (nu * tr + (1.0 - nu) * e00)
    g[1] = 0.5 * k * (nu * tr + (1.0 - nu) * e11)
    g[2] = k * (1.0 - nu) * e01
    h[:, :] = 0.0
    h[0, 0] = h[1, 1] = 0.25 * k
    h[0, 1] = h[1, 0] = 0.25 * k * nu
    h[2, 2] = 0.5 * k * (1.0 - nu)
    return 0.5 * k * (nu * tr * tr + (1.0 - nu) * (e00 * e00 + e11 * e11 + 2.0 * e01 * e01))


@njit(**JIT, inline="always")
def _yeoh(coeff, c00, c11, c01, g, h):
    det = c00 * c11 - c01 * c01
    if det <= 0.0:
        g[:] = 0.0
        h[:, :] = 0.0
        return np.inf
    x = c00 + c11 + 1.0 / det - 3.0
    w = coeff[0] * x + coeff[1] * x * x + coeff[2] * x * x * x
    dw = coeff[0] + 2.0 * coeff[1] * x + 3.0 * coeff[2] * x * x
    ddw = 2.0 * coeff[1] + 6.0 * coeff[2] * x
    # I1 = c00 + c11 + 1/det: d det = (c11, c00, -2 c01), d2 det: (0,1) = 1, (2,2) = -2
    dd0, dd1, dd2 = c11, c00, -2.0 * c01
    i2 = 1.0 / (det * det)
    i3 = 2.0 / (det * det * det)
    d0, d1, d2 = 1.0 - dd0 * i2, 1.0 - dd1 * i2, -dd2 * i2
    g[0], g[1], g[2] = dw * d0, dw * d1, dw * d2
    dd = (dd0, dd1, dd2)
    di = (d0, d1, d2)
    for a in range(3):
        for b in range(3):
            second = i3 * dd[a] * dd[b]
            if (a == 0 and b == 1) or (a == 1 and b == 0):
                second -= i2
            elif a == 2 and b == 2:
                second += 2.0 * i2
            h[a, b] = ddw * di[a] * di[b] + dw * second
    return w


@njit(**JIT, inline="always")
def _strain(c00, c11, c01, e, je, he):
    """The XPBD block strain e (3,) of c, its Jacobian je[k, i] = de_k/dc_i and Hessians
    he[k] (3, 3)."""
    s0, s1 = np.sqrt(c00), np.sqrt(c11)
    e[0], e[1], e[2] = s0 - 1.0, s1 - 1.0, 0.5 * c01 / (s0 * s1)
    je[:, :] = 0.0
    he[:, :, :] = 0.0
    je[0, 0] = 0.5 / s0
    je[1, 1] = 0.5 / s1
    he[0, 0, 0] = -0.25 / (s0 * c00)
    he[1, 1, 1] = -0.25 / (s1 * c11)
    q = 0.5 / (s0 * s1)
    je[2, 2] = q
    je[2, 0] = -e[2] / (2.0 * c00)
    je[2, 1] = -e[2] / (2.0 * c11)
    he[2, 0, 0] = 0.75 * e[2] / (c00 * c00)
    he[2, 1, 1] = 0.75 * e[2] / (c11 * c11)
    he[2, 0, 1] = he[2, 1, 0] = 0.25 * e[2] / (c00 * c11)
    he[2, 0, 2] = he[2, 2, 0] = -0.5 * q / c00
    he[2, 1, 2] = he[2, 2, 1] = -0.5 * q / c11


@njit(**JIT, inline="always")
def _block_law(stiff, alpha00, relax, nu, c00, c11, c01, g, h, e, je, he, pe, pee):
    """The XPBD block energy (relaxed when ``relax``) of c; stiff (3, 3) J the block's
    stiffness, alpha00 1/J its compliance's first entry."""
    _strain(c00, c11, c01, e, je, he)
    regime = 0
    if relax:
        regime, e1, cn, sn = tension_field_regime(e, nu)
    if regime == SLACK:
        g[:] = 0.0
        h[:, :] = 0.0
        return 0.0
    if regime == WRINKLED:
        a, d, b = e[0], e[1], e[2]
        q = 0.5 * (a - d)
        r = np.sqrt(q * q + b * b)
        r3 = r * r * r
        grad1 = (0.5 + 0.5 * q / r, 0.5 - 0.5 * q / r, b / r)
        hess1 = np.empty((3, 3))
        hess1[0, 0] = hess1[1, 1] = 0.25 * b * b / r3
        hess1[0, 1] = hess1[1, 0] = -0.25 * b * b / r3
        hess1[0, 2] = hess1[2, 0] = -0.5 * q * b / r3
        hess1[1, 2] = hess1[2, 1] = 0.5 * q * b / r3
        hess1[2, 2] = q * q / r3
        energy = 0.5 * e1 * e1 / alpha00
        for i in range(3):
            pe[i] = e1 * grad1[i] / alpha00
            for j in range(3):
                pee[i, j] = (grad1[i] * grad1[j] + e1 * hess1[i, j]) / alpha00
    else:
        energy = 0.0
        for i in range(3):
            s = 0.0
            for j in range(3):
                s += stiff[i, j] * e[j]
                pee[i, j] = stiff[i, j]
            pe[i] = s
            energy += 0.5 * e[i] * s
    for i in range(3):
        s = 0.0
        for k in range(3):
            s += je[k, i] * pe[k]
        g[i] = s
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += pe[k] * he[k, i, j]
                for m in range(3):
                    s += je[k, i] * pee[k, m] * je[m, j]
            h[i, j] = s
    return energy


@njit(**JIT)
def element_hessians(x, triangles, rest_inverse, law, scale, params, stiffness, alpha00, nu,
                     need_hessian):
    """Energy (J), gradient (n, 3) N and element blocks (m, 3, 3, 3, 3) N/m of the
    membrane law ``law`` (a code of :data:`LAWS`) on the triangles.

    scale (m,) multiplies psi (t A for the laws per unit volume, 1 for the block laws);
    params: (k, nu) of Saint Venant-Kirchhoff or (C10, C20, C30) of Yeoh; stiffness
    (m, 3, 3) and alpha00 (m,) the block laws'; nu their Poisson ratio."""
    n, m = x.shape[0], triangles.shape[0]
    grad = np.zeros((n, 3))
    blocks = np.zeros((m, 3, 3, 3, 3)) if need_hessian else np.zeros((0, 3, 3, 3, 3))
    g, h = np.empty(3), np.empty((3, 3))
    e, je, he = np.empty(3), np.empty((3, 3)), np.empty((3, 3, 3))
    pe, pee = np.empty(3), np.empty((3, 3))
    f = np.empty((2, 3))
    beta = np.empty((2, 3))
    df = np.empty((2, 3))
    hf = np.empty((2, 2, 3, 3))
    energy = 0.0
    for t in range(m):
        d = rest_inverse[t]
        nodes = (triangles[t, 0], triangles[t, 1], triangles[t, 2])
        for j in range(2):
            beta[j, 0] = -(d[0, j] + d[1, j])
            beta[j, 1] = d[0, j]
            beta[j, 2] = d[1, j]
            for r in range(3):
                f[j, r] = (x[nodes[1], r] - x[nodes[0], r]) * d[0, j] \
                    + (x[nodes[2], r] - x[nodes[0], r]) * d[1, j]
        c00 = f[0, 0] * f[0, 0] + f[0, 1] * f[0, 1] + f[0, 2] * f[0, 2]
        c11 = f[1, 0] * f[1, 0] + f[1, 1] * f[1, 1] + f[1, 2] * f[1, 2]
        c01 = f[0, 0] * f[1, 0] + f[0, 1] * f[1, 1] + f[0, 2] * f[1, 2]
        if law == SVK:
            psi = _svk(params[0], params[1], c00, c11, c01, g, h)
        elif law == YEOH:
            psi = _yeoh(params, c00, c11, c01, g, h)
        else:
            psi = _block_law(stiffness[t], alpha00[t], law == TENSION_FIELD, nu, c00, c11,
                             c01, g, h, e, je, he, pe, pee)
        s = scale[t]
        energy += s * psi
        if not np.isfinite(psi):
            return np.inf, grad, blocks
        # dpsi/dF and d2psi/dF2 through c(F)
        for r in range(3):
            df[0, r] = s * (2.0 * g[0] * f[0, r] + g[2] * f[1, r])
            df[1, r] = s * (2.0 * g[1] * f[1, r] + g[2] * f[0, r])
        for p in range(3):
            for r in range(3):
                grad[nodes[p], r] += beta[0, p] * df[0, r] + beta[1, p] * df[1, r]
        if not need_hessian:
            continue
        # dc_a/df_j as vectors: dc0/df0 = 2 f0, dc1/df1 = 2 f1, dc2/df0 = f1, dc2/df1 = f0
        for j in range(2):
            for k in range(2):
                for r in range(3):
                    for q in range(3):
                        v = 0.0
                        for a in range(3):
                            da = _dc(a, j, r, f)
                            if da == 0.0:
                                continue
                            for b in range(3):
                                v += h[a, b] * da * _dc(b, k, q, f)
                        if r == q:
                            if j == k:
                                v += 2.0 * g[j]
                            else:
                                v += g[2]
                        hf[j, k, r, q] = s * v
        for p in range(3):
            for q in range(3):
                for j in range(2):
                    for k in range(2):
                        w = beta[j, p] * beta[k, q]
                        for r in range(3):
                            for c in range(3):
                                blocks[t, p, q, r, c] += w * hf[j, k, r, c]
    return energy, grad, blocks


@njit(**JIT)
def element_c_gradients(x, triangles, rest_inverse, law, scale, params, stiffness, alpha00,
                        nu):
    """(m, 3) J: each triangle's scale * dpsi/dc, c = (c00, c11, c01), at ``x`` (arguments
    as :func:`element_hessians`'): the triangle's second Piola-Kirchhoff stress times its
    rest volume is [[2 g0, g2], [g2, 2 g1]] in its rest frame."""
    m = triangles.shape[0]
    out = np.zeros((m, 3))
    g, h = np.empty(3), np.empty((3, 3))
    e, je, he = np.empty(3), np.empty((3, 3)), np.empty((3, 3, 3))
    pe, pee = np.empty(3), np.empty((3, 3))
    for t in range(m):
        d = rest_inverse[t]
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        f0 = (x[b] - x[a]) * d[0, 0] + (x[c] - x[a]) * d[1, 0]
        f1 = (x[b] - x[a]) * d[0, 1] + (x[c] - x[a]) * d[1, 1]
        c00, c11, c01 = f0 @ f0, f1 @ f1, f0 @ f1
        if law == SVK:
            _svk(params[0], params[1], c00, c11, c01, g, h)
        elif law == YEOH:
            _yeoh(params, c00, c11, c01, g, h)
        else:
            _block_law(stiffness[t], alpha00[t], law == TENSION_FIELD, nu, c00, c11, c01, g,
                       h, e, je, he, pe, pee)
        for i in range(3):
            out[t, i] = scale[t] * g[i]
    return out


@njit(**JIT, inline="always")
def _dc(a, j, r, f):
    """d c_a / d f_j[r] (c = (c00, c11, c01))."""
    if a == 0:
        return 2.0 * f[0, r] if j == 0 else 0.0
    if a == 1:
        return 2.0 * f[1, r] if j == 1 else 0.0
    return f[1, r] if j == 0 else f[0, r]


@dataclass(frozen=True)
class MembraneTerm:
    """The in-plane energy of ``triangles`` (m, 3) int64 under one law of :data:`LAWS`.

    rest_inverse (m, 2, 2) 1/m (see :class:`structure.hyperelastic.TriangleMembrane`);
    scale (m,) (t A, m^3, for the laws per unit volume; ones for the block laws); params
    (Pa or -, see :func:`element_hessians`); stiffness (m, 3, 3) J and alpha00 (m,) 1/J of
    the block laws; poisson_ratio (-)."""

    triangles: np.ndarray
    rest_inverse: np.ndarray
    law: str
    scale: np.ndarray
    params: np.ndarray
    stiffness: np.ndarray
    alpha00: np.ndarray
    poisson_ratio: float = 0.0

    def __post_init__(self):
        if self.law not in LAWS:
            raise ValueError(f"membrane law must be one of {sorted(LAWS)}, got {self.law!r}")

    @property
    def element_nodes(self) -> np.ndarray:
        return self.triangles

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(energy J, gradient (n, 3) N, blocks (m, 3, 3, 3, 3) N/m) at ``x`` (n, 3) m."""
        return element_hessians(np.ascontiguousarray(x, dtype=float), self.triangles,
                                self.rest_inverse, LAWS[self.law], self.scale, self.params,
                                self.stiffness, self.alpha00, float(self.poisson_ratio),
                                hessian)

    def c_gradients(self, x: np.ndarray) -> np.ndarray:
        """(m, 3) J: each triangle's scaled dpsi/dc at ``x`` (n, 3) m
        (:func:`element_c_gradients`)."""
        return element_c_gradients(np.ascontiguousarray(x, dtype=float), self.triangles,
                                   self.rest_inverse, LAWS[self.law], self.scale, self.params,
                                   self.stiffness, self.alpha00, float(self.poisson_ratio))

    @classmethod
    def from_triangle_membrane(cls, membrane, law) -> "MembraneTerm":
        """The term of a :class:`structure.hyperelastic.TriangleMembrane` under
        :class:`structure.hyperelastic.SaintVenantKirchhoff` or
        :class:`structure.hyperelastic.HyperelasticLaw` ``law``."""
        from ..hyperelastic import HyperelasticLaw, SaintVenantKirchhoff

        m = len(membrane.triangles)
        scale = membrane.thickness * membrane.rest_area
        empty = np.zeros((m, 3, 3)), np.zeros(m)
        if isinstance(law, SaintVenantKirchhoff):
            nu = law.poisson_ratio
            params = np.array([law.youngs_modulus / (1.0 - nu * nu), nu, 0.0])
            return cls(membrane.triangles, membrane.rest_inverse, "saint-venant-kirchhoff",
                       scale, params, *empty, nu)
        if isinstance(law, HyperelasticLaw):
            return cls(membrane.triangles, membrane.rest_inverse, "yeoh", scale,
                       law.coefficients.astype(float), *empty)
        raise TypeError(f"no tangent for membrane law {type(law).__name__}")

    @classmethod
    def from_xpbd(cls, model) -> "MembraneTerm":
        """The membrane blocks of a :class:`structure.xpbd.model.XpbdModel` (relaxed by the
        tension field when its material's ``wrinkling`` says so)."""
        m = len(model.triangles)
        return cls(model.triangles, model.rest_inverse,
                   "tension-field" if model.tension_field else "block", np.ones(m),
                   np.zeros(3), np.ascontiguousarray(np.linalg.inv(model.membrane_compliance)),
                   np.ascontiguousarray(model.membrane_compliance[:, 0, 0]),
                   float(model.base.material.poisson_ratio))


@njit(**JIT)
def _regimes(x, triangles, rest_inverse, nu):
    m = triangles.shape[0]
    out = np.empty(m, dtype=np.int64)
    e = np.empty(3)
    for t in range(m):
        d = rest_inverse[t]
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        f0 = (x[b] - x[a]) * d[0, 0] + (x[c] - x[a]) * d[1, 0]
        f1 = (x[b] - x[a]) * d[0, 1] + (x[c] - x[a]) * d[1, 1]
        s0, s1 = np.sqrt(f0 @ f0), np.sqrt(f1 @ f1)
        e[0], e[1], e[2] = s0 - 1.0, s1 - 1.0, 0.5 * (f0 @ f1) / (s0 * s1)
        out[t] = tension_field_regime(e, nu)[0]
    return out


def regimes(term: MembraneTerm, x: np.ndarray) -> np.ndarray:
    """(m,) int64: each triangle's tension-field regime at ``x`` (n, 3) m (0 taut,
    1 wrinkled, 2 slack; :data:`structure.xpbd.kernels.TAUT` ...), from the block strain."""
    return _regimes(np.ascontiguousarray(x, dtype=float), term.triangles, term.rest_inverse,
                    float(term.poisson_ratio))
