"""Hyperelastic in-plane response of a triangulated membrane (incompressible plane stress).

Each triangle is a constant-strain element of reference area A0 and thickness t. With the
in-plane right Cauchy-Green tensor C = F^T F (F: 3 x 2, deformed edges over reference edges),
incompressibility gives the thickness stretch lambda_3 = det(C)^(-1/2) and

    I1 = tr C + 1 / det C,      element energy = t A0 W(I1)                         (J)

with W a strain-energy density of I1 alone (Pa): neo-Hookean W = C10 (I1 - 3),
C10 = mu / 2 = E / 6 for an incompressible solid; Yeoh W = sum_k C_k0 (I1 - 3)^k, k = 1..3
(Yeoh 1993). Thin-shell inflation of a sphere then gives the classical balloon law
p = 2 mu (H / R) (lambda^-1 - lambda^-7) for neo-Hookean rubber (e.g. Ogden, Non-Linear
Elastic Deformations, 1984, Sec. 5.3).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.optimize import minimize

JIT = dict(cache=True, nogil=True)


@dataclass(frozen=True)
class HyperelasticLaw:
    """Yeoh coefficients C10, C20, C30 (Pa); neo-Hookean when C20 = C30 = 0."""

    c10: float
    c20: float = 0.0
    c30: float = 0.0

    def __post_init__(self):
        if not self.c10 > 0:
            raise ValueError(f"hyperelastic C10 must be > 0 Pa, got {self.c10}")

    @classmethod
    def neo_hookean(cls, shear_modulus: float) -> "HyperelasticLaw":
        """Neo-Hookean of shear modulus mu (Pa): C10 = mu / 2."""
        return cls(0.5 * shear_modulus)

    @classmethod
    def from_youngs_modulus(cls, youngs_modulus: float) -> "HyperelasticLaw":
        """Neo-Hookean matching the small-strain Young's modulus E (Pa) of an incompressible
        solid: mu = E / 3."""
        return cls.neo_hookean(youngs_modulus / 3.0)

    @property
    def coefficients(self) -> np.ndarray:
        return np.array([self.c10, self.c20, self.c30])

    @property
    def stiffness_scale(self) -> float:
        """A modulus (Pa) to scale energies by."""
        return self.c10

    def energy_and_gradient(self, membrane: "TriangleMembrane", pos: np.ndarray):
        return energy_and_gradient(pos, membrane.triangles, membrane.rest_inverse,
                                   membrane.rest_area, membrane.thickness, self.coefficients)


@dataclass(frozen=True)
class SaintVenantKirchhoff:
    """Compressible plane-stress law linear in the Green strain E = (C - I)/2:
    W = Y / (2 (1 - nu^2)) [nu (tr E)^2 + (1 - nu) tr(E^2)] (Pa). Small strains, large
    rotations: the von Karman / Hencky membrane regime. youngs_modulus Y (Pa), poisson_ratio
    nu in [0, 0.5)."""

    youngs_modulus: float
    poisson_ratio: float

    def __post_init__(self):
        if not self.youngs_modulus > 0:
            raise ValueError(f"youngs_modulus must be > 0 Pa, got {self.youngs_modulus}")
        if not 0 <= self.poisson_ratio < 0.5:
            raise ValueError(f"poisson_ratio must be in [0, 0.5), got {self.poisson_ratio}")

    @property
    def stiffness_scale(self) -> float:
        return self.youngs_modulus

    def energy_and_gradient(self, membrane: "TriangleMembrane", pos: np.ndarray):
        return svk_energy_and_gradient(pos, membrane.triangles, membrane.rest_inverse,
                                       membrane.rest_area, membrane.thickness,
                                       self.youngs_modulus, self.poisson_ratio)


@njit(**JIT, inline="always")
def _deformation(pos, a, b, c, rest_inverse, t, F):
    """Fill F (3, 2) = [e1 e2] Dm^-1 for triangle t (vertices a, b, c); return the in-plane
    right Cauchy-Green tensor (c00, c11, c01)."""
    for r in range(3):
        e1 = pos[b, r] - pos[a, r]
        e2 = pos[c, r] - pos[a, r]
        F[r, 0] = e1 * rest_inverse[t, 0, 0] + e2 * rest_inverse[t, 1, 0]
        F[r, 1] = e1 * rest_inverse[t, 0, 1] + e2 * rest_inverse[t, 1, 1]
    c00 = F[0, 0] ** 2 + F[1, 0] ** 2 + F[2, 0] ** 2
    c11 = F[0, 1] ** 2 + F[1, 1] ** 2 + F[2, 1] ** 2
    c01 = F[0, 0] * F[0, 1] + F[1, 0] * F[1, 1] + F[2, 0] * F[2, 1]
    return c00, c11, c01


@njit(**JIT, inline="always")
def _scatter(grad, a, b, c, F, s00, s01, s11, scale, rest_inverse, t):
    """Add scale * dW/dx to the vertices, dW/dF = F S with S = [[s00, s01], [s01, s11]]."""
    for r in range(3):
        g0 = F[r, 0] * s00 + F[r, 1] * s01
        g1 = F[r, 0] * s01 + F[r, 1] * s11
        gb = scale * (g0 * rest_inverse[t, 0, 0] + g1 * rest_inverse[t, 0, 1])
        gc = scale * (g0 * rest_inverse[t, 1, 0] + g1 * rest_inverse[t, 1, 1])
        grad[b, r] += gb
        grad[c, r] += gc
        grad[a, r] -= gb + gc


@njit(**JIT)
def energy_and_gradient(pos, triangles, rest_inverse, rest_area, thickness, coeff):
    """Total strain energy (J) and its gradient (n, 3) N of the triangles.

    pos (n, 3) m; triangles (m, 3); rest_inverse (m, 2, 2): inverse of the reference edge
    matrix in a local 2-D frame; rest_area (m,) m^2; coeff: (C10, C20, C30) Pa."""
    grad = np.zeros_like(pos)
    energy = 0.0
    F = np.empty((3, 2))
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        c00, c11, c01 = _deformation(pos, a, b, c, rest_inverse, t, F)
        det = c00 * c11 - c01 * c01
        if det <= 0.0:
            return np.inf, grad
        i1m3 = c00 + c11 + 1.0 / det - 3.0
        w = coeff[0] * i1m3 + coeff[1] * i1m3**2 + coeff[2] * i1m3**3
        dw = coeff[0] + 2.0 * coeff[1] * i1m3 + 3.0 * coeff[2] * i1m3**2
        scale = thickness * rest_area[t]
        energy += scale * w
        # dI1/dF = F (2 I - 2 C^-1 / det C),  C^-1 = [[c11, -c01], [-c01, c00]] / det
        k = 2.0 / (det * det)
        _scatter(grad, a, b, c, F, dw * (2.0 - k * c11), dw * k * c01, dw * (2.0 - k * c00),
                 scale, rest_inverse, t)
    return energy, grad


@njit(**JIT)
def svk_energy_and_gradient(pos, triangles, rest_inverse, rest_area, thickness, youngs, nu):
    """Saint Venant-Kirchhoff plane-stress energy (J) and gradient (n, 3) N; arguments as
    :func:`energy_and_gradient`, youngs (Pa), nu (-)."""
    grad = np.zeros_like(pos)
    energy = 0.0
    F = np.empty((3, 2))
    k = youngs / (1.0 - nu * nu)
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        c00, c11, c01 = _deformation(pos, a, b, c, rest_inverse, t, F)
        e00, e11, e01 = 0.5 * (c00 - 1.0), 0.5 * (c11 - 1.0), 0.5 * c01
        tr = e00 + e11
        scale = thickness * rest_area[t]
        energy += scale * 0.5 * k * (nu * tr * tr + (1.0 - nu) * (e00 * e00 + e11 * e11
                                                                   + 2.0 * e01 * e01))
        # second Piola-Kirchhoff stress S = k [nu tr E I + (1 - nu) E]; dW/dF = F S
        _scatter(grad, a, b, c, F, k * (nu * tr + (1.0 - nu) * e00), k * (1.0 - nu) * e01,
                 k * (nu * tr + (1.0 - nu) * e11), scale, rest_inverse, t)
    return energy, grad


@dataclass(frozen=True)
class TriangleMembrane:
    """Reference configuration: rest positions (n, 3) m, triangles (m, 3), thickness m; the
    reference edge-matrix inverses (m, 2, 2) and areas (m,) m^2 are derived."""

    rest: np.ndarray
    triangles: np.ndarray
    thickness: float

    def __post_init__(self):
        if not self.thickness > 0:
            raise ValueError(f"membrane thickness must be > 0 m, got {self.thickness}")
        x = np.asarray(self.rest, dtype=float)
        tri = np.asarray(self.triangles, dtype=np.int64)
        e1 = x[tri[:, 1]] - x[tri[:, 0]]
        e2 = x[tri[:, 2]] - x[tri[:, 0]]
        u = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
        n = np.cross(e1, e2)
        area = 0.5 * np.linalg.norm(n, axis=1)
        if np.any(area <= 0):
            raise ValueError("membrane has degenerate triangles (zero reference area)")
        v = np.cross(n / (2 * area[:, None]), u)
        dm = np.empty((len(tri), 2, 2))
        dm[:, 0, 0] = (e1 * u).sum(1)
        dm[:, 1, 0] = (e1 * v).sum(1)
        dm[:, 0, 1] = (e2 * u).sum(1)
        dm[:, 1, 1] = (e2 * v).sum(1)
        # F = [e1 e2] Dm^-1; store Dm^-1 transposed so that F[:, j] = sum_i e_i Dm^-1[i, j]
        inv = np.linalg.inv(dm)
        object.__setattr__(self, "rest", x)
        object.__setattr__(self, "triangles", tri)
        object.__setattr__(self, "rest_inverse", np.ascontiguousarray(inv))
        object.__setattr__(self, "rest_area", area)

    def energy_and_gradient(self, pos: np.ndarray, law):
        """Strain energy (J) and gradient (n, 3) N at positions ``pos`` (n, 3) m under
        ``law`` (:class:`HyperelasticLaw` or :class:`SaintVenantKirchhoff`)."""
        return law.energy_and_gradient(self, np.ascontiguousarray(pos, dtype=float))


def icosphere(radius: float, subdivisions: int):
    """Closed triangulated sphere: points (n, 3) m on the sphere and outward-wound triangles
    (20 * 4^subdivisions)."""
    t = (1 + 5**0.5) / 2
    pts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
           (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
            (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
            (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    points = [np.array(p, dtype=float) / np.linalg.norm(p) for p in pts]
    for _ in range(subdivisions):
        cache = {}

        def midpoint(i, j):
            key = (min(i, j), max(i, j))
            if key not in cache:
                m = points[i] + points[j]
                points.append(m / np.linalg.norm(m))
                cache[key] = len(points) - 1
            return cache[key]

        new = []
        for a, b, c in tris:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = new
    return radius * np.array(points), np.array(tris, dtype=np.int64)


def enclosed_volume(pos: np.ndarray, triangles: np.ndarray):
    """Volume (m^3) enclosed by outward-wound triangles and its gradient (n, 3) m^2."""
    a, b, c = pos[triangles[:, 0]], pos[triangles[:, 1]], pos[triangles[:, 2]]
    volume = float(np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0)
    grad = np.zeros_like(pos)
    np.add.at(grad, triangles[:, 0], np.cross(b, c) / 6.0)
    np.add.at(grad, triangles[:, 1], np.cross(c, a) / 6.0)
    np.add.at(grad, triangles[:, 2], np.cross(a, b) / 6.0)
    return volume, grad


def equilibrium_at_volume(membrane: TriangleMembrane, law: HyperelasticLaw,
                          target_volume: float, start: np.ndarray, tolerance: float = 1e-10,
                          rounds: int = 30):
    """Equilibrium of a closed membrane holding ``target_volume`` (m^3): minimises the strain
    energy subject to V(x) = V*, by an augmented Lagrangian with L-BFGS inner solves.

    Returns (positions (n, 3) m, inflation pressure p (Pa): the Lagrange multiplier,
    grad W = p grad V)."""
    x = np.asarray(start, dtype=float).ravel().copy()
    n = len(membrane.rest)
    scale_e = law.stiffness_scale * membrane.thickness * membrane.rest_area.sum()
    pressure = 0.0
    stiffness = 10.0 * scale_e / target_volume**2

    def objective(flat):
        pos = flat.reshape(n, 3)
        w, gw = membrane.energy_and_gradient(pos, law)
        if not np.isfinite(w):
            return np.inf, np.zeros_like(flat)
        v, gv = enclosed_volume(pos, membrane.triangles)
        c = v - target_volume
        value = w - pressure * c + 0.5 * stiffness * c * c
        grad = gw - (pressure - stiffness * c) * gv
        return value / scale_e, grad.ravel() / scale_e

    for _ in range(rounds):
        result = minimize(objective, x, jac=True, method="L-BFGS-B",
                          options={"maxiter": 5000, "ftol": 1e-15, "gtol": 1e-12})
        x = result.x
        v, _ = enclosed_volume(x.reshape(n, 3), membrane.triangles)
        pressure -= stiffness * (v - target_volume)
        if abs(v - target_volume) < tolerance * target_volume:
            break
    return x.reshape(n, 3), float(pressure)


def equilibrium_under_pressure(membrane: TriangleMembrane, law, pressure: float,
                               fixed: np.ndarray, start: np.ndarray | None = None,
                               bending=None, energy_scale: float | None = None) -> np.ndarray:
    """Equilibrium (n, 3) m of a membrane with nodes ``fixed`` held, loaded by a uniform
    follower pressure ``pressure`` (Pa) on the side its triangle normals point away from:
    minimises W(x) + W_bending(x) - p V(x), V the volume swept between the surface and its
    fixed rim; ``bending`` (e.g. :class:`structure.bending.MidedgeBending`, with
    ``energy_and_gradient(pos)``) adds its energy, None a bare membrane.  ``energy_scale`` (J)
    normalises the objective (default E t A, the membrane's; a load far below E t, in the
    plate regime, needs the load's own, e.g. p t A)."""
    x0 = np.asarray(membrane.rest if start is None else start, dtype=float)
    n = len(x0)
    free = np.ones(n, dtype=bool)
    free[np.asarray(fixed)] = False
    scale_e = energy_scale or law.stiffness_scale * membrane.thickness * membrane.rest_area.sum()

    def objective(flat):
        pos = x0.copy()
        pos[free] = flat.reshape(-1, 3)
        w, gw = membrane.energy_and_gradient(pos, law)
        if not np.isfinite(w):
            return np.inf, np.zeros_like(flat)
        if bending is not None:
            wb, gb = bending.energy_and_gradient(pos)
            w, gw = w + wb, gw + gb
        v, gv = enclosed_volume(pos, membrane.triangles)
        return (w - pressure * v) / scale_e, (gw - pressure * gv)[free].ravel() / scale_e

    def follow(flat):  # each hinge's turn along the iterates (structure.bending)
        if hasattr(bending, "follow"):
            pos = x0.copy()
            pos[free] = flat.reshape(-1, 3)
            bending.follow(pos)

    result = minimize(objective, x0[free].ravel(), jac=True, method="L-BFGS-B", callback=follow,
                      options={"maxiter": 50000, "ftol": 1e-16, "gtol": 1e-13,
                               "maxcor": 30})
    out = x0.copy()
    out[free] = result.x.reshape(-1, 3)
    return out
