"""Strains of the shell of revolution at a point of the meridian, with their first and second
derivatives with respect to the local variables u = (r, r', r'', z, z', z'') (primes d/dS).

The rest meridian (R(S), Z(S)) has metric A = |X'| (1 when S is its arc length), angle Phi
(X' = A (cos Phi, sin Phi)) and turning Phi' (1/m); the current one (r(S), z(S)) has angle phi,
(r', z') = |x'| (cos phi, sin phi). The measures are those of the large-rotation, torsionless
axisymmetric shell (E. Reissner, "On finite symmetrical deflections of thin shells of
revolution", J. Appl. Mech. 36, 1969, 267-270; Libai & Simmonds, *The Nonlinear Theory of
Elastic Shells*, 2nd ed., 1998, their axishells), the quantities q = (E_s, E_t, kappa_s,
kappa_t):

* E_s = (lambda_s^2 - 1) / 2, lambda_s^2 = (r'^2 + z'^2) / A^2, the meridional Green strain;
* E_t = (lambda_t^2 - 1) / 2, lambda_t = r / R, the hoop Green strain;
* kappa_s = (phi' - Phi') / A, the change of the meridian's turning per rest length (1/m),
  phi' = (r' z'' - z' r'') / (r'^2 + z'^2);
* kappa_t = (sin phi - sin Phi) / R (1/m), sin phi = z' / |x'|.

The Green strains are formed from the differences with the rest, E_s = ((r' - R')(r' + R') +
(z' - Z')(z' + Z')) / (2 A^2) and E_t = (r - R)(r + R) / (2 R^2), so that a small strain keeps
its digits (lambda^2 - 1 would lose them to cancellation). Both changes of curvature are per
rest length, conjugate to the moments per rest length:
an inflation x = lambda X (any lambda, any meridian) gives kappa_s = kappa_t = 0 exactly, a
rigid translation along the axis leaves all four unchanged. (The current curvatures are
kappa_s / lambda_s + Phi' / (A lambda_s) and sin phi / r.)

**The pole** (R -> 0, with r(0) = 0 and z'(0) = 0 imposed): lambda_t -> r'(0) / R'(0) =
lambda_s(0) and kappa_t -> (phi'(0) - Phi'(0)) / R'(0) = kappa_s(0) (l'Hopital; R'(0) = A(0)),
the equibiaxial limits of a smooth pole (E_t -> E_s). The energy integrand carries the area
2 pi R A, so it vanishes there; the Gauss points are interior to the elements, so none of
these quotients is ever evaluated at R = 0 in the energy (:func:`pole_limits` gives the pole's
values).
"""
from __future__ import annotations

import numpy as np

R, R1, R2, Z, Z1, Z2 = range(6)
"""The local variables' indices in u."""
ES, ET, KS, KT = range(4)
"""The strains' indices in q."""


def strains(u: np.ndarray, rest: dict, order: int = 2):
    """q (P, 4) and, for ``order`` >= 1, dq/du (P, 4, 6), for ``order`` 2, d2q/du2
    (P, 4, 6, 6), at local variables ``u`` (P, 6) on a rest geometry ``rest`` (arrays:
    u (P, 6) the rest's local variables, radius R m, metric A 1, sin_angle sin Phi 1,
    turning Phi' 1/m, each (P,); module doc). Units: E 1, kappa 1/m, per unit of the u entry
    differentiated."""
    p = u.shape[0]
    big_r, a, u0 = rest["radius"], rest["metric"], rest["u"]
    r, r1, r2, z1, z2 = u[:, R], u[:, R1], u[:, R2], u[:, Z1], u[:, Z2]
    c = r1 * r1 + z1 * z1
    norm = np.sqrt(c)
    turn = (r1 * z2 - z1 * r2) / c
    stretch = (r1 - u0[:, R1]) * (r1 + u0[:, R1]) + (z1 - u0[:, Z1]) * (z1 + u0[:, Z1])
    q = np.stack([0.5 * stretch / a**2, 0.5 * (r - big_r) * (r + big_r) / big_r**2,
                  (turn - rest["turning"]) / a, (z1 / norm - rest["sin_angle"]) / big_r],
                 axis=1)
    if order == 0:
        return q
    dc = np.zeros((p, 6))
    dc[:, R1], dc[:, Z1] = 2 * r1, 2 * z1
    dn = np.zeros((p, 6))                                   # d(r' z'' - z' r'')
    dn[:, R1], dn[:, R2], dn[:, Z1], dn[:, Z2] = z2, -z1, -r2, r1
    numer = turn * c
    dturn = dn / c[:, None] - numer[:, None] * dc / (c * c)[:, None]
    dsin = -0.5 * (z1 / (c * norm))[:, None] * dc
    dsin[:, Z1] += 1.0 / norm
    dq = np.zeros((p, 4, 6))
    dq[:, ES] = 0.5 * dc / (a * a)[:, None]
    dq[:, ET, R] = r / big_r**2
    dq[:, KS] = dturn / a[:, None]
    dq[:, KT] = dsin / big_r[:, None]
    if order == 1:
        return q, dq
    ddc = np.zeros((6, 6))
    ddc[R1, R1] = ddc[Z1, Z1] = 2.0
    ddn = np.zeros((6, 6))
    ddn[R1, Z2] = ddn[Z2, R1] = 1.0
    ddn[R2, Z1] = ddn[Z1, R2] = -1.0
    outer_dn_dc = dn[:, :, None] * dc[:, None, :]
    outer_dc = dc[:, :, None] * dc[:, None, :]
    ddturn = (ddn[None] / c[:, None, None]
              - (outer_dn_dc + np.swapaxes(outer_dn_dc, 1, 2)) / (c * c)[:, None, None]
              + 2 * (numer / c**3)[:, None, None] * outer_dc
              - (numer / (c * c))[:, None, None] * ddc[None])
    e_z1 = np.zeros(6)
    e_z1[Z1] = 1.0
    outer_ez_dc = e_z1[None, :, None] * dc[:, None, :]
    ddsin = (-0.5 / (c * norm))[:, None, None] * (outer_ez_dc + np.swapaxes(outer_ez_dc, 1, 2)) \
        + (0.75 * z1 / (c * c * norm))[:, None, None] * outer_dc \
        - (0.5 * z1 / (c * norm))[:, None, None] * ddc[None]
    ddq = np.zeros((p, 4, 6, 6))
    ddq[:, ES] = 0.5 * ddc[None] / (a * a)[:, None, None]
    ddq[:, ET, R, R] = 1 / big_r**2
    ddq[:, KS] = ddturn / a[:, None, None]
    ddq[:, KT] = ddsin / big_r[:, None, None]
    return q, dq, ddq


def pole_limits(u: np.ndarray, rest: dict) -> np.ndarray:
    """(P, 4): q at the pole (R = 0) from the local variables ``u`` (P, 6) there and the rest
    geometry (as in :func:`strains`, the radius unused): E_t = E_s and kappa_t = kappa_s
    (module doc)."""
    u0, a = rest["u"], rest["metric"]
    c = u[:, R1] ** 2 + u[:, Z1] ** 2
    es = 0.5 * ((u[:, R1] - u0[:, R1]) * (u[:, R1] + u0[:, R1])
                + (u[:, Z1] - u0[:, Z1]) * (u[:, Z1] + u0[:, Z1])) / a**2
    ks = ((u[:, R1] * u[:, Z2] - u[:, Z1] * u[:, R2]) / c - rest["turning"]) / a
    return np.stack([es, es, ks, ks], axis=1)
