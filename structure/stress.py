"""Strain and stress of a triangulated membrane, per triangle, from the law it ran with.

Each triangle is a constant-strain element (:class:`structure.hyperelastic.TriangleMembrane`):
F (3 x 2) maps its rest edges to its current ones, C = F^T F (2 x 2, in the triangle's rest
frame) and the principal stretches lambda_1 >= lambda_2 are the square roots of C's
eigenvalues, along its eigenvectors V_i at rest and along the unit vectors F V_i /
lambda_i now. From them (all per triangle, principal values largest first):

- Green-Lagrange strains E_i = (lambda_i^2 - 1) / 2 and logarithmic strains ln lambda_i (1);
- the thickness stretch lambda_3 and the current thickness t lambda_3 (m);
- the Cauchy membrane resultants n_i (N/m, force per current length), the principal Cauchy
  stresses sigma_i = n_i / (t lambda_3) (Pa), and the plane-stress von Mises stress
  sqrt(sigma_1^2 - sigma_1 sigma_2 + sigma_2^2) (Pa).

The resultants come from the law's second Piola-Kirchhoff stress S (Pa, 2 x 2, rest frame)
pushed forward, n = t F S F^T / (lambda_1 lambda_2); for the laws here C and S share their
principal axes, so n_i = t lambda_i^2 S_i / (lambda_1 lambda_2). The laws
(:data:`STRESS_LAWS`, keyed by the law's class):

- :class:`structure.hyperelastic.HyperelasticLaw` (incompressible, W(I1)): lambda_3 =
  1 / (lambda_1 lambda_2) and sigma_i = 2 W'(I1) (lambda_i^2 - lambda_3^2)
  (:func:`incompressible_stress`; with the tension field, a wrinkled triangle takes its
  natural width lambda_2 = lambda_1^(-1/2), where sigma_2 = 0, and a slack one no stress);
- :class:`structure.hyperelastic.SaintVenantKirchhoff` (plane stress, linear in E):
  S = Y / (1 - nu^2) [nu tr E I + (1 - nu) E].

The current thickness of a compressible law is the plane-stress Hencky thickness
lambda_3 = (lambda_1 lambda_2)^(-nu / (1 - nu)) (:func:`thickness_stretch`): positive at every
stretch, equal to Saint Venant-Kirchhoff's own lambda_3^2 = 1 - 2 nu tr E / (1 - nu) to first
order in the strain and to the incompressible 1 / (lambda_1 lambda_2) at nu = 1/2. Saint
Venant-Kirchhoff's own thickness vanishes at tr E = (1 - nu) / (2 nu), 0.5 at nu = 1/2 (a
stretch of 1.41 with the other near 1), where it would divide the resultant by zero. A
sheet of rubber (nu at or above :data:`INCOMPRESSIBLE_POISSON_RATIO`) reports the stresses of
the incompressible neo-Hookean law of its E whatever law it ran with (the run's result names
the law in ``stress_law``).

Bending (:func:`bending_curvature`, :func:`bending_moments`): the midedge shape operator of
:mod:`structure.bending` per triangle and the Kirchhoff-Love moments M = D [(1 - nu) H +
nu tr(H) I] (N m/m), the bending stress at the two surfaces +-6 M / t^2.

Any law of the package, the XPBD membrane's blocks and their tension field included, also
gives its resultants from its own energy (:func:`term_resultants`, on a
:class:`structure.tangent.membrane.MembraneTerm`); for the two laws above that path agrees
with the closed forms to round-off. :func:`sheet_fields` gathers what a run writes per
triangle: the resultants rotated back to the rest frame, R^T n R = U G U / a (F = R U), where
the bending moments' tensor is added to give the stresses of the two surfaces.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .bending import MidedgeBending, _rest_geometry
from .hyperelastic import HyperelasticLaw, SaintVenantKirchhoff, TriangleMembrane


@dataclass(frozen=True)
class TriangleStrain:
    """Per triangle (m triangles): ``stretch`` (m, 2) principal stretches lambda_1 >=
    lambda_2 (1); ``rest_direction`` (m, 2, 3) their unit directions at rest and
    ``direction`` (m, 2, 3) now; ``green`` (m, 2) principal Green-Lagrange strains (1);
    ``log`` (m, 2) logarithmic strains (1); ``area_ratio`` (m,) lambda_1 lambda_2 (1)."""

    stretch: np.ndarray
    rest_direction: np.ndarray
    direction: np.ndarray

    @property
    def green(self) -> np.ndarray:
        return 0.5 * (self.stretch**2 - 1.0)

    @property
    def log(self) -> np.ndarray:
        return np.log(self.stretch)

    @property
    def area_ratio(self) -> np.ndarray:
        return self.stretch[:, 0] * self.stretch[:, 1]


@dataclass(frozen=True)
class TriangleStress:
    """Per triangle: ``resultant`` (m, 2) principal Cauchy membrane resultants n_i (N/m),
    along ``strain.direction``; ``thickness`` (m,) current thickness (m); ``strain`` the
    :class:`TriangleStrain` they come from."""

    resultant: np.ndarray
    thickness: np.ndarray
    strain: TriangleStrain

    @property
    def stress(self) -> np.ndarray:
        """(m, 2) Pa: principal Cauchy stresses sigma_i = n_i / thickness."""
        return self.resultant / self.thickness[:, None]

    @property
    def von_mises(self) -> np.ndarray:
        """(m,) Pa: the plane-stress von Mises stress."""
        s1, s2 = self.stress[:, 0], self.stress[:, 1]
        return np.sqrt(s1 * s1 - s1 * s2 + s2 * s2)


def _edges(pos: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(m, 3, 2) m: each triangle's two edges from its first vertex, as columns."""
    pos = np.asarray(pos, dtype=float)
    return np.stack([pos[tri[:, 1]] - pos[tri[:, 0]], pos[tri[:, 2]] - pos[tri[:, 0]]], axis=2)


def deformation_gradient(membrane: TriangleMembrane, pos: np.ndarray) -> np.ndarray:
    """(m, 3, 2): F of each triangle at positions ``pos`` (n, 3) m."""
    return _edges(pos, membrane.triangles) @ membrane.rest_inverse


def _rest_frame(x: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(m, 3, 2): the rest frame's unit axes of triangles ``tri`` (m, 3) on rest positions
    ``x`` (n, 3) m (the first edge, and in-plane normal to it)."""
    e1 = x[tri[:, 1]] - x[tri[:, 0]]
    e2 = x[tri[:, 2]] - x[tri[:, 0]]
    u = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    normal = np.cross(e1, e2)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    return np.stack([u, np.cross(normal, u)], axis=2)


def triangle_strain(membrane: TriangleMembrane, pos: np.ndarray) -> TriangleStrain:
    """The principal stretches and directions of every triangle at ``pos`` (n, 3) m."""
    F = deformation_gradient(membrane, pos)
    C = np.einsum("mki,mkj->mij", F, F)
    values, vectors = np.linalg.eigh(C)               # ascending
    values, vectors = values[:, ::-1], vectors[:, :, ::-1]
    stretch = np.sqrt(np.maximum(values, 0.0))
    rest = np.einsum("mki,mij->mjk", _rest_frame(membrane.rest, membrane.triangles), vectors)
    now = np.einsum("mki,mij->mjk", F, vectors)
    now /= np.maximum(stretch[:, :, None], np.finfo(float).tiny)
    return TriangleStrain(stretch, rest, now)


INCOMPRESSIBLE_POISSON_RATIO = 0.49
"""A law whose Poisson ratio is at or above this (rubbers: 0.49 to 0.5) reports the stresses of
the incompressible neo-Hookean law of its Young's modulus (module doc)."""


def thickness_stretch(stretch: np.ndarray, poisson_ratio: float) -> np.ndarray:
    """(m,) 1: the plane-stress Hencky thickness stretch lambda_3 = (lambda_1 lambda_2)^(-nu /
    (1 - nu)) of principal stretches ``stretch`` (m, 2) 1 (module doc); 1 / (lambda_1 lambda_2)
    at nu = 1/2."""
    area = stretch[:, 0] * stretch[:, 1]
    if poisson_ratio >= 0.5:
        return 1.0 / area
    return area ** (-poisson_ratio / (1.0 - poisson_ratio))


def incompressible_stress(law: HyperelasticLaw, stretch: np.ndarray,
                          tension_field: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Principal Cauchy stresses (m, 2) Pa and thickness stretches lambda_3 (m,) 1 of an
    incompressible sheet of ``law`` (Yeoh, neo-Hookean) at principal stretches ``stretch``
    (m, 2) 1, largest first: sigma_i = 2 W'(I1) (lambda_i^2 - lambda_3^2), lambda_3 = 1 /
    (lambda_1 lambda_2). With ``tension_field`` the sheet carries no compression (Pipkin 1986):
    a triangle with lambda_2 < lambda_1^(-1/2) is wrinkled and takes that natural width (uniaxial
    tension, sigma_2 = 0), one with lambda_1 <= 1 is slack (no stress, lambda_3 = 1)."""
    lam = np.array(stretch, dtype=float)
    slack = np.zeros(len(lam), dtype=bool)
    if tension_field:
        slack = lam[:, 0] <= 1.0
        lam[:, 1] = np.maximum(lam[:, 1], lam[:, 0] ** -0.5)
        lam[slack] = 1.0
    lam3 = 1.0 / (lam[:, 0] * lam[:, 1])
    i1 = (lam**2).sum(axis=1) + lam3**2
    c10, c20, c30 = law.coefficients
    slope = c10 + 2 * c20 * (i1 - 3) + 3 * c30 * (i1 - 3) ** 2
    sigma = 2 * slope[:, None] * (lam**2 - lam3[:, None] ** 2)
    sigma[slack] = 0.0
    return sigma, lam3


def _incompressible(law: HyperelasticLaw, strain: TriangleStrain, thickness: float):
    sigma, lam3 = incompressible_stress(law, strain.stretch)
    current = thickness * lam3
    return sigma * current[:, None], current


def _svk(law: SaintVenantKirchhoff, strain: TriangleStrain, thickness: float):
    e = strain.green
    nu, k = law.poisson_ratio, law.youngs_modulus / (1 - law.poisson_ratio**2)
    trace = e.sum(axis=1)
    piola = k * (nu * trace[:, None] + (1 - nu) * e)  # principal S_i (Pa)
    lam = strain.stretch
    resultant = thickness * lam**2 * piola / (lam[:, 0] * lam[:, 1])[:, None]
    return resultant, thickness * thickness_stretch(lam, nu)


def _law_stress(term, pos: np.ndarray):
    """(F (m, 3, 2), G (m, 2, 2) J, a (m,) m^2) of ``term``'s triangles at ``pos`` (n, 3) m:
    the deformation gradient, G = [[2 g0, g2], [g2, 2 g1]] the law's second Piola-Kirchhoff
    stress times the rest volume (g = d psi / dc,
    :meth:`~structure.tangent.membrane.MembraneTerm.c_gradients`) and the current area."""
    edges = _edges(pos, term.triangles)
    g = term.c_gradients(pos)
    G = np.stack([np.stack([2 * g[:, 0], g[:, 2]], -1), np.stack([g[:, 2], 2 * g[:, 1]], -1)],
                 axis=1)
    area = 0.5 * np.linalg.norm(np.cross(edges[:, :, 0], edges[:, :, 1]), axis=1)
    return edges @ term.rest_inverse, G, area


def term_resultants(term, pos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The principal Cauchy membrane resultants (m, 2) N/m and their directions (m, 2, 3) of
    every triangle of ``term`` (:class:`structure.tangent.membrane.MembraneTerm`: any law of
    the package, the XPBD membrane's blocks and their tension field included) at ``pos``
    (n, 3) m, from the law's own energy (G and a of :func:`_law_stress`): n = F G F^T / a;
    F = Q R in the current plane, so n's principal values are R G R^T / a's and its
    directions Q's images of their eigenvectors."""
    F, G, area = _law_stress(term, pos)
    Q, R = np.linalg.qr(F)
    values, vectors = _principal(R @ G @ np.swapaxes(R, 1, 2) / area[:, None, None])
    return values, np.einsum("mki,mij->mjk", Q, vectors)


def _right_stretch(F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues (m, 2), ascending, and eigenvectors (m, 2, 2) of C = F^T F."""
    return np.linalg.eigh(np.einsum("mki,mkj->mij", F, F))


def _stretch_power(values: np.ndarray, vectors: np.ndarray, power: float) -> np.ndarray:
    """U^(2 power) (m, 2, 2) from C's eigen pairs: power 1/2 is U, -1/2 its inverse."""
    return np.einsum("mik,mk,mjk->mij", vectors,
                     np.maximum(values, 1e-300 if power < 0 else 0.0) ** power, vectors)


def _principal(tensor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal values (m, 2), largest first, and unit vectors (m, 2, 2) (columns) of
    symmetric 2 x 2 tensors (m, 2, 2)."""
    values, vectors = np.linalg.eigh(tensor)
    return values[:, ::-1], vectors[:, :, ::-1]


def _von_mises(s: np.ndarray) -> np.ndarray:
    """(m,): the plane-stress von Mises value of 2 x 2 stress tensors (m, 2, 2)."""
    a, d, b = s[:, 0, 0], s[:, 1, 1], s[:, 0, 1]
    return np.sqrt(np.maximum(a * a - a * d + d * d + 3.0 * b * b, 0.0))


def sheet_fields(term, pos: np.ndarray, thickness: float,
                 stress_law: HyperelasticLaw | None = None, tension_field: bool = False,
                 bending: MidedgeBending | None = None, rest: np.ndarray | None = None,
                 flexural_rigidity: float = 0.0, poisson_ratio: float = 0.0) -> dict:
    """Per triangle at ``pos`` (n, 3) m: the membrane stresses of the incompressible
    ``stress_law`` at the sheet's stretches (:func:`incompressible_stress`, relaxed by the
    ``tension_field``), or without one, of ``term``'s own law (its resultant rotated back to the
    rest frame, R^T n R = U G U / a with F = R U and G, a of :func:`_law_stress`; the thickness
    of :func:`thickness_stretch` with ``poisson_ratio``); a direction w at rest is F U^-1 w
    now. With ``bending`` on ``rest`` (n, 3) m, the Kirchhoff-Love moments of
    :func:`bending_curvature` (flexural rigidity N m, Poisson ratio of the model). Every
    value is finite at every stretch in (0, inf):

    - ``principal_resultant`` (m, 2) N/m and ``principal_direction`` (m, 3), the first's unit
      direction now;
    - ``thickness`` (m,) m, the current thickness (m, rest ``thickness``);
    - ``principal_stress`` (m, 2) Pa, the mid-surface stresses n_i / t_now;
    - ``bending_stress`` (m, 2) Pa, the principal 6 M_i / t^2 on the surface the normal of
      the rest triangle points to (the other surface's are their negatives; zero without
      ``bending``);
    - ``surface_stress`` (m,) Pa, the largest principal stress of the two surfaces' membrane
      plus bending stress, and ``von_mises_stress`` (m,) Pa, the largest of their von Mises
      stresses (the two tensors added in the rest frame, rotated back);
    - ``green_strain`` and ``log_strain`` (m, 2) 1, principal, largest first;
    - ``curvature`` (m, 2, 2) 1/m, the change of curvature in the rest frame (zero without
      ``bending``)."""
    F = _edges(pos, term.triangles) @ term.rest_inverse
    c_values, c_vectors = _right_stretch(F)
    stretch = np.sqrt(np.maximum(c_values[:, ::-1], 0.0))
    axes = c_vectors[:, :, ::-1]                              # principal axes at rest, columns
    if stress_law is not None:
        sigma, lam3 = incompressible_stress(stress_law, stretch, tension_field)
        membrane = np.einsum("mik,mk,mjk->mij", axes, sigma, axes)
    else:
        _, G, area = _law_stress(term, pos)
        U = _stretch_power(c_values, c_vectors, 0.5)
        lam3 = thickness_stretch(stretch, poisson_ratio)
        membrane = U @ G @ U / (area * thickness * lam3)[:, None, None]
    t_now = thickness * lam3
    values, w = _principal(membrane)
    U_inv = _stretch_power(c_values, c_vectors, -0.5)
    direction = np.einsum("mki,mij,mj->mk", F, U_inv, w[:, :, 0])
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    green = 0.5 * (stretch**2 - 1.0)
    m = len(term.triangles)
    curvature = np.zeros((m, 2, 2))
    if bending is not None:
        curvature, _ = bending_curvature(bending, rest, pos, poisson_ratio)
    bend = 6.0 * _moment_tensor(curvature, flexural_rigidity, poisson_ratio) / thickness**2
    surfaces = np.stack([membrane + bend, membrane - bend])          # (2, m, 2, 2)
    top = np.stack([np.linalg.eigvalsh(s)[:, -1] for s in surfaces])
    return dict(principal_resultant=values * t_now[:, None], principal_direction=direction,
                thickness=t_now, principal_stress=values,
                bending_stress=np.linalg.eigvalsh(bend)[:, ::-1],
                surface_stress=top.max(axis=0),
                von_mises_stress=np.maximum(_von_mises(surfaces[0]), _von_mises(surfaces[1])),
                green_strain=green, log_strain=np.log(np.maximum(stretch, 1e-300)),
                curvature=curvature)


STRESS_LAWS: dict[type, Callable] = {HyperelasticLaw: _incompressible,
                                     SaintVenantKirchhoff: _svk}
"""law class -> (law, TriangleStrain, rest thickness m) -> (resultants (m, 2) N/m, current
thickness (m,) m)."""


def triangle_stress(membrane: TriangleMembrane, law, pos: np.ndarray) -> TriangleStress:
    """The principal membrane resultants and stresses of every triangle at ``pos`` (n, 3) m
    under ``law`` (module doc); ValueError naming the laws there are for another law."""
    rule = STRESS_LAWS.get(type(law))
    if rule is None:
        raise ValueError(f"no stress rule for the law {type(law).__name__}; allowed: "
                         f"{', '.join(sorted(k.__name__ for k in STRESS_LAWS))}")
    strain = triangle_strain(membrane, pos)
    resultant, thickness = rule(law, strain, membrane.thickness)
    return TriangleStress(resultant, thickness, strain)


def bending_curvature(bending: MidedgeBending, rest: np.ndarray, pos: np.ndarray,
                      poisson_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """Each triangle's curvature tensor at ``pos`` (n, 3) m, the midedge shape operator of
    :mod:`structure.bending`, H_T = sum_i s_i l_i d_i / (2 A) m_i m_i^T (d_i the change of
    the dihedral angle at edge i, s_i = 2 on a clamped boundary edge, whose face sees the
    whole angle to its ghost; a free boundary edge's change is the one that minimises the
    triangle's energy, as the model condenses it; ``poisson_ratio`` the model's): (m, 2, 2)
    1/m in the rest frame (m, 3, 2) of unit axes, which is returned with it."""
    rest = np.asarray(rest, dtype=float)
    tri = bending.triangles
    length, in_plane, area = _rest_geometry(rest, tri)
    change, _, _ = bending.angle_jacobian(pos)
    change = np.where(bending.active, change, 0.0)
    for t in np.nonzero(~bending.active.all(axis=1))[0]:
        on, off = bending.active[t], ~bending.active[t]
        if not on.any():
            continue
        cosine = in_plane[t] @ in_plane[t].T
        k = length[t][:, None] * length[t][None, :] * ((1 - poisson_ratio) * cosine**2
                                                       + poisson_ratio)
        change[t, off] = -np.linalg.solve(k[np.ix_(off, off)], k[np.ix_(off, on)] @ change[t, on])
    frame = _rest_frame(rest, tri)
    normals = np.einsum("tir,trk->tik", in_plane, frame)           # m_i in the frame
    weight = np.where(bending.flap < 0, 2.0, 1.0) * length * change / (2.0 * area[:, None])
    return np.einsum("ti,tir,tis->trs", weight, normals, normals), frame


def bending_moments(curvature: np.ndarray, frame: np.ndarray, flexural_rigidity: float,
                    poisson_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """The principal bending moments (m, 2) N m/m, largest first, and their unit directions
    (m, 2, 3) of a Kirchhoff-Love plate with the curvature tensors ``curvature`` (m, 2, 2)
    1/m in the triangles' rest ``frame`` (m, 3, 2) (:func:`bending_curvature`),
    M = D [(1 - nu) H + nu tr(H) I]; the bending stress at the two surfaces is
    +-6 M / t^2."""
    values, vectors = _principal(_moment_tensor(curvature, flexural_rigidity, poisson_ratio))
    return values, np.einsum("mki,mij->mjk", frame, vectors)


def _moment_tensor(curvature: np.ndarray, flexural_rigidity: float,
                   poisson_ratio: float) -> np.ndarray:
    """Kirchhoff-Love's M = D [(1 - nu) H + nu tr(H) I] (m, 2, 2) N m/m of curvature tensors
    H (m, 2, 2) 1/m."""
    trace = np.trace(curvature, axis1=1, axis2=2)
    return flexural_rigidity * ((1 - poisson_ratio) * curvature
                                + poisson_ratio * trace[:, None, None] * np.eye(2))
