"""The potential flow of one circumferential harmonic on the meridional section.

An incompressible, inviscid liquid at rest in a rigid tank, moved by a boundary that
oscillates as cos(m theta) about the axis, flows with the potential phi = Phi(r, z)
cos(m theta). Laplace's equation on the section, weighted by r, has the weak form

    Int (Phi_r Psi_r + Phi_z Psi_z + m^2 Phi Psi / r^2) r dr dz = Int_Gamma q Psi r ds

for every test function Psi, q = dPhi/dn the boundary's normal velocity amplitude (m/s; no
flow through the tank wall) and Phi = 0 on the axis for m >= 1 (the regularity of
cos(m theta) there). Discretised with isoparametric P2 triangles (scikit-fem) on the meshes
of :mod:`~fluid.section.mesh`, the left side is the SPD matrix A (m, per unit Phi^2) on the
off-axis dofs.

**A moving boundary's trace.** Where a boundary curve X(S) moves with a normal velocity
q(S), the right side is the trace vector Int Psi_i q r ds over the curve's facets: on a facet
whose three P2 nodes sit on the curve at S_a, S_mid, S_b, the facet's own coordinate t in
[0, 1] follows S by the quadratic through the three, and the integral is taken in S by
Gauss's rule between the breakpoints the caller gives (where q is not smooth).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementTriP2, MeshTri2

AXIS_TOLERANCE = 1e-12
"""A node with r below this (m) lies on the axis."""


def harmonic_form(wave_number: int) -> BilinearForm:
    """The r-weighted Laplacian of harmonic ``wave_number`` m (module doc)."""
    m2 = float(wave_number) ** 2

    @BilinearForm
    def laplacian(u, v, w):
        r = w.x[0]
        return (u.grad[0] * v.grad[0] + u.grad[1] * v.grad[1]) * r + m2 * u * v / r
    return laplacian


@dataclass(frozen=True)
class SectionPotential:
    """The harmonic's Laplacian on a section (module doc): mesh, the P2 ``basis``,
    ``matrix`` A (N, N) CSR over every dof, ``free`` (k,) the dofs off the axis (every dof
    at m = 0)."""

    mesh: MeshTri2
    basis: Basis
    matrix: sp.csr_matrix
    free: np.ndarray

    @property
    def reduced(self) -> sp.csc_matrix:
        """A on the free dofs."""
        return self.matrix[self.free][:, self.free].tocsc()


def section_potential(mesh: MeshTri2, wave_number: int = 1, intorder: int = 6) -> SectionPotential:
    """A of harmonic ``wave_number`` on ``mesh`` by a Gauss rule of order ``intorder``."""
    basis = Basis(mesh, ElementTriP2(), intorder=intorder)
    matrix = harmonic_form(wave_number).assemble(basis).tocsr()
    if wave_number == 0:
        return SectionPotential(mesh, basis, matrix, np.arange(basis.N))
    axis = mesh.facets_satisfying(lambda x: np.abs(x[0]) < AXIS_TOLERANCE, boundaries_only=True)
    held = basis.get_dofs(axis).flatten()
    return SectionPotential(mesh, basis, matrix, np.setdiff1d(np.arange(basis.N), held))


def p2_trace(t: np.ndarray) -> np.ndarray:
    """(3, ...): the P2 shape functions of a facet's end, middle and other end at its
    coordinate t (...) in [0, 1]."""
    t = np.asarray(t, float)
    return np.array([(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)])


def boundary_facets(mesh: MeshTri2) -> tuple[np.ndarray, np.ndarray]:
    """(facets (k,), dofs (3, k)): the boundary facets of ``mesh`` and their end, middle and
    other end dofs."""
    facets = mesh.boundary_facets()
    ends = mesh.facets[:, facets]
    return facets, np.vstack([ends[0], mesh.nvertices + facets, ends[1]])


def facet_coordinate(arc: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """t (..., k) on each facet of the arc lengths ``arc`` (..., k) between its nodes'
    ``nodes`` (3, k) (end, middle, other end): the root in [0, 1] of the quadratic through
    (0, S_a), (1/2, S_mid), (1, S_b) (module doc), by Newton from the linear guess."""
    s_a, s_m, s_b = nodes
    t = (arc - s_a) / (s_b - s_a)
    for _ in range(6):
        value = s_a * (1 - t) * (1 - 2 * t) + s_m * 4 * t * (1 - t) + s_b * t * (2 * t - 1)
        slope = s_a * (4 * t - 3) + s_m * (4 - 8 * t) + s_b * (4 * t - 1)
        t = t - (value - arc) / slope
    return t
