"""The sheet's laws on the meridian's principal strains: the energy per unit rest volume
W(E_s, E_t) (Pa) of the Green strains E_i = (lambda_i^2 - 1) / 2, its gradient and its
Hessian; the bending energy per unit rest area.

An axisymmetric state has no in-plane shear, so C = diag(1 + 2 E_s, 1 + 2 E_t) in the
(meridian, parallel) frame and each law is the 3-D sheet's at that C
(:mod:`structure.tangent.membrane`, with c00 = 1 + 2 E_s, c11 = 1 + 2 E_t, c01 = 0), of the
same law objects (:mod:`structure.hyperelastic`):

* :class:`~structure.hyperelastic.SaintVenantKirchhoff` (E, nu): W = k/2 [nu (E_s + E_t)^2 +
  (1 - nu) (E_s^2 + E_t^2)], k = E / (1 - nu^2);
* :class:`~structure.hyperelastic.HyperelasticLaw` (Yeoh; neo-Hookean when C20 = C30 = 0),
  incompressible: W = sum_k Ck0 (I1 - 3)^k, I1 = c_s + c_t + 1 / (c_s c_t), c_i = 1 + 2 E_i
  (lambda_3 = 1 / (lambda_s lambda_t)).

I1 - 3 is of second order in the strains; it is formed without cancellation,
I1 - 3 = [2 (E_s + E_t) (P - 1) - 4 E_s E_t] / P with P - 1 = c_s c_t - 1 = 2 E_s + 2 E_t +
4 E_s E_t, and likewise its derivatives, so that the energy and the stresses keep their digits
at small strain.

**Tension field** (``tension_field``; Pipkin 1986): the sheet carries no compression. With
E_1 >= E_2 the larger and smaller of (E_s, E_t), a point is

* taut when its smaller principal stress is >= 0: the law as it is;
* wrinkled when the larger stretch exceeds 1 and the smaller stress would be compressive: the
  energy of uniaxial tension at the larger stretch, the smaller relaxed to its natural width.
  Incompressible: wrinkled when lambda_2 < lambda_1^(-1/2), energy W at
  I1 = lambda_1^2 + 2 / lambda_1 (the natural width lambda_2 = lambda_1^(-1/2) of
  :func:`structure.stress.incompressible_stress`); Saint Venant-Kirchhoff: wrinkled when
  E_2 < -nu E_1, energy E E_1^2 / 2 (the criterion of
  :func:`structure.xpbd.kernels.tension_field_regime`, on the Green strains);
* slack when the larger stretch is <= 1: no energy.

A sheet relaxed this way resists the hoop compression of a fold by its bending alone, and
Newton's tangent nearly loses rank where it goes slack: on the Table 4.1 diaphragm, Newton on
the pure relaxed energy does not converge from the full law's equilibrium, nor from rest on
256 elements. ``residual`` keeps a fraction e of the law, (1 - e) W_relaxed + e W (the
regularisation of tension-field computations), and the pure relaxed state is the limit
e -> 0 (:attr:`~structure.axisymmetric.model.ShellOfRevolution.residual_stiffness`).

The relaxed energy is C1 across the regimes (the relaxed stress vanishes at each boundary);
its Hessian jumps there.
"""
from __future__ import annotations

import numpy as np

from ..hyperelastic import HyperelasticLaw, SaintVenantKirchhoff
from ..model import Material
from ..shell import MEMBRANE_LAWS
from ..xpbd.kernels import SLACK, TAUT, WRINKLED

__all__ = ["membrane_density", "regimes", "uniaxial_density", "bending_density", "law_of", "TAUT",
           "WRINKLED", "SLACK"]


def law_of(material: Material, name: str):
    """The law ``name`` (one of :data:`structure.shell.MEMBRANE_LAWS`) of ``material``:
    ``neo-hookean`` takes mu = E / 3 (incompressible), ``saint-venant-kirchhoff`` (E, nu)."""
    if name not in MEMBRANE_LAWS:
        raise ValueError(f"membrane law must be one of {MEMBRANE_LAWS}, got {name!r}")
    if name == "neo-hookean":
        return HyperelasticLaw.from_youngs_modulus(material.youngs_modulus)
    return SaintVenantKirchhoff(material.youngs_modulus, material.poisson_ratio)


def _svk(law: SaintVenantKirchhoff, es, et):
    nu = law.poisson_ratio
    k = law.youngs_modulus / (1.0 - nu * nu)
    tr = es + et
    w = 0.5 * k * (nu * tr * tr + (1.0 - nu) * (es * es + et * et))
    g = np.stack([k * (nu * tr + (1 - nu) * es), k * (nu * tr + (1 - nu) * et)], -1)
    h = np.broadcast_to(k * np.array([[1.0, nu], [nu, 1.0]]), es.shape + (2, 2)).copy()
    return w, g, h


def _yeoh_of_i1(law: HyperelasticLaw, x):
    """W, dW/dI1 and d2W/dI1^2 (Pa) of the Yeoh law at I1 - 3 = ``x``."""
    c1, c2, c3 = law.coefficients
    return (c1 * x + c2 * x * x + c3 * x**3, c1 + 2 * c2 * x + 3 * c3 * x * x,
            2 * c2 + 6 * c3 * x)


def _yeoh(law: HyperelasticLaw, es, et):
    cs, ct = 1.0 + 2.0 * es, 1.0 + 2.0 * et
    area = 2.0 * (es + et) + 4.0 * es * et                     # P - 1, P = c_s c_t
    p = 1.0 + area
    w, w1, w2 = _yeoh_of_i1(law, (2.0 * (es + et) * area - 4.0 * es * et) / p)
    # dI1/dE_s = 2 (c_s P - 1) / (c_s P), c_s P - 1 = 2 E_s + (P - 1) + 2 E_s (P - 1)
    di = np.stack([2.0 * (2 * es + area + 2 * es * area) / (cs * p),
                   2.0 * (2 * et + area + 2 * et * area) / (ct * p)], -1)
    ddi = np.empty(es.shape + (2, 2))
    ddi[..., 0, 0] = 8.0 / (cs**3 * ct)
    ddi[..., 1, 1] = 8.0 / (cs * ct**3)
    ddi[..., 0, 1] = ddi[..., 1, 0] = 4.0 / p**2
    return w, w1[..., None] * di, w2[..., None, None] * di[..., :, None] * di[..., None, :] \
        + w1[..., None, None] * ddi


def uniaxial_density(law, e1):
    """(W, dW/dE_1, d2W/dE_1^2) (Pa) of uniaxial tension at the larger Green strain E_1
    (...), the smaller stretch relaxed to its natural width (module doc): the wrinkled
    energy. Complex-safe."""
    if isinstance(law, SaintVenantKirchhoff):
        y = law.youngs_modulus
        return 0.5 * y * e1 * e1, y * e1, y + 0.0 * e1
    # I1 - 3 = (s - 1)^2 (s + 2) / s, s = lambda_1 = sqrt(1 + 2 E_1); dI1/dE_1 = 2 (s^3 - 1) / s^3
    log_c = np.log1p(2.0 * e1)
    s, s_1 = np.exp(0.5 * log_c), np.expm1(0.5 * log_c)
    w, w1, w2 = _yeoh_of_i1(law, s_1 * s_1 * (s + 2.0) / s)
    di = 2.0 * np.expm1(1.5 * log_c) / s**3
    return w, w1 * di, w2 * di * di + w1 * 6.0 / s**5


def regimes(law, es: np.ndarray, et: np.ndarray) -> np.ndarray:
    """(...) int: the tension-field regime (TAUT, WRINKLED, SLACK of
    :mod:`structure.xpbd.kernels`) at the Green strains E_s, E_t (...) (module doc)."""
    e1, e2 = np.maximum(es, et), np.minimum(es, et)
    if isinstance(law, SaintVenantKirchhoff):
        compressed = e2 < -law.poisson_ratio * e1
    else:
        compressed = 2.0 * np.log1p(2.0 * e2) + np.log1p(2.0 * e1) < 0.0
    return np.where(e1 <= 0.0, SLACK, np.where(compressed, WRINKLED, TAUT))


def membrane_density(law, es: np.ndarray, et: np.ndarray, tension_field: bool = False,
                     residual: float = 0.0):
    """(W (...) Pa, dW/dE (..., 2) Pa, d2W/dE2 (..., 2, 2) Pa) of ``law`` at the Green
    strains E = (E_s, E_t) (...), relaxed when ``tension_field`` (module doc), with the
    fraction ``residual`` of the law kept: (1 - residual) W_relaxed + residual W."""
    es, et = np.asarray(es, dtype=float), np.asarray(et, dtype=float)
    if isinstance(law, SaintVenantKirchhoff):
        w, g, h = _svk(law, es, et)
    elif isinstance(law, HyperelasticLaw):
        w, g, h = _yeoh(law, es, et)
    else:
        raise TypeError(f"no axisymmetric membrane law for {type(law).__name__}")
    if not tension_field:
        return w, g, h
    relaxed = _relaxed(law, es, et, w, g, h)
    if residual > 0.0:
        return tuple((1.0 - residual) * r + residual * f for r, f in zip(relaxed, (w, g, h)))
    return relaxed


def _relaxed(law, es, et, w, g, h):
    """The tension field's relaxation (module doc) of the law's (W, dW/dE, d2W/dE2) at the
    Green strains (E_s, E_t)."""
    regime = regimes(law, es, et)
    wrinkled, slack = regime == WRINKLED, regime == SLACK
    with np.errstate(invalid="ignore", divide="ignore"):
        wu, gu, hu = uniaxial_density(law, np.maximum(es, et))
    w = np.where(wrinkled, wu, np.where(slack, 0.0, w))
    relaxed = (wrinkled | slack)
    major = np.stack([es >= et, es < et], -1) & wrinkled[..., None]
    g = np.where(relaxed[..., None], 0.0, g) + np.where(major, gu[..., None], 0.0)
    h = np.where(relaxed[..., None, None], 0.0, h) \
        + np.where(major[..., :, None] & major[..., None, :], hu[..., None, None], 0.0)
    return w, g, h


def bending_density(flexural_rigidity: float, poisson_ratio: float, kappa_s: np.ndarray,
                    kappa_t: np.ndarray):
    """(energy (...) J/m^2, gradient (..., 2) N, Hessian (..., 2, 2) N m) per unit rest area
    of the changes of curvature (kappa_s, kappa_t) (...) 1/m: D/2 [kappa_s^2 + 2 nu kappa_s
    kappa_t + kappa_t^2], D the flexural rigidity (N m), nu the Poisson ratio; the gradient
    is the moments per rest length (M_s, M_t) = D (kappa_s + nu kappa_t, kappa_t + nu kappa_s)."""
    d, nu = flexural_rigidity, poisson_ratio
    w = 0.5 * d * (kappa_s**2 + 2 * nu * kappa_s * kappa_t + kappa_t**2)
    g = d * np.stack([kappa_s + nu * kappa_t, kappa_t + nu * kappa_s], -1)
    h = np.broadcast_to(d * np.array([[1.0, nu], [nu, 1.0]]), np.shape(kappa_s) + (2, 2))
    return w, g, h
