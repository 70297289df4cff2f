"""Self-contact of the sheet: ipc-toolkit's barrier potential between its non-adjacent
triangles, edges and nodes (Li et al. 2020), so that a fold cannot pass through itself.

ipc-toolkit builds the set of element pairs closer than ``dhat`` (a bounding-volume broad
phase), gives the barrier potential's energy, gradient and exact Hessian on that set, and
the largest collision-free fraction of a step by continuous collision detection
(Tight-Inclusion CCD along the straight path). The Hessian is not projected per pair: where
it is indefinite the minimiser's ladder shifts it (:mod:`structure.minimise.newton`), and a
per-pair projection (``PSDProjectionMethod.CLAMP``) stalled the N = 10 sheet's path at tank
fraction 0.3 with a pair pressed to a force residual of 2e5 of the pressure force, where the
exact Hessian converges in 8 iterations. Each pair is
weighted by its area (``use_area_weighting``), so the stiffness is a pressure per unit
barrier: it is set, by a probe of two parallel triangles, so that ``pressure`` (Pa) is carried
at a tenth of ``dhat`` as the wall's barrier does (:mod:`structure.minimise.barrier`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .barrier import REST_FRACTION

CCD_MAX_ITERATIONS = 1000
"""Tight-Inclusion CCD's iterations per pair at most (its default, 1e7, spent 57 ms a step on
the N = 14 sheet's pressed folds; 1,000 took 16 ms, and conservative advancement,
``AdditiveCCD``, took small steps that doubled the path's iterations)."""


def _ipctk():
    import ipctk  # the self-contact's library; imported where self-contact is asked for

    return ipctk


def _pressure_per_stiffness(dhat: float, gap: float) -> float:
    """The pressure (Pa) a unit stiffness carries between two parallel triangles ``gap`` m
    apart (module doc)."""
    ipctk = _ipctk()
    lower = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    upper = lower + np.array([0.1, 0.1, gap])
    points = np.asfortranarray(np.vstack([lower, upper]))
    faces = np.asfortranarray(np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int32))
    mesh = ipctk.CollisionMesh(points, np.asfortranarray(ipctk.edges(faces)), faces)
    collisions = ipctk.NormalCollisions()
    collisions.use_area_weighting = True
    collisions.build(mesh, points, dhat)
    force = ipctk.BarrierPotential(dhat, 1.0).gradient(collisions, mesh, points)
    return abs(float(force.reshape(-1, 3)[3:, 2].sum())) / 0.5


@dataclass
class SelfContact:
    """The sheet's self-contact (module doc) on ``triangles`` of the rest points, the
    ``free`` (n,) bool nodes moving; ``dhat`` m the activation distance, ``stiffness`` the
    barrier's."""

    mesh: object
    potential: object
    dhat: float
    free: np.ndarray

    @classmethod
    def build(cls, rest: np.ndarray, triangles: np.ndarray, free: np.ndarray, dhat: float,
              pressure: float, rest_fraction: float = REST_FRACTION) -> "SelfContact":
        """Self-contact of the sheet with rest points ``rest`` (n, 3) m and ``triangles``
        (m, 3), its stiffness such that ``pressure`` (Pa) rests at ``rest_fraction`` dhat."""
        if not dhat > 0 or not pressure > 0:
            raise ValueError(f"self-contact dhat (m) and pressure (Pa) must be > 0, got "
                             f"{dhat!r}, {pressure!r}")
        ipctk = _ipctk()
        faces = np.asfortranarray(np.asarray(triangles, dtype=np.int32))
        mesh = ipctk.CollisionMesh(np.asfortranarray(rest, dtype=float),
                                   np.asfortranarray(ipctk.edges(faces)), faces)
        stiffness = pressure / _pressure_per_stiffness(dhat, rest_fraction * dhat)
        return cls(mesh, ipctk.BarrierPotential(dhat, stiffness), float(dhat),
                   np.asarray(free, dtype=bool))

    def _collisions(self, x: np.ndarray):
        collisions = _ipctk().NormalCollisions()
        collisions.use_area_weighting = True
        collisions.build(self.mesh, x, self.dhat)
        return collisions

    def evaluate(self, x: np.ndarray, hessian: bool = True):
        """(energy J, gradient (n, 3) N, Hessian (3n, 3n) CSC N/m or None) at ``x`` (n, 3) m,
        zero on the fixed nodes."""
        x = np.asfortranarray(x, dtype=float)
        collisions = self._collisions(x)
        n = len(x)
        if len(collisions) == 0:
            return 0.0, np.zeros((n, 3)), (sp.csc_matrix((3 * n, 3 * n)) if hessian else None)
        energy = float(self.potential(collisions, self.mesh, x))
        grad = np.asarray(self.potential.gradient(collisions, self.mesh, x)).reshape(n, 3)
        grad[~self.free] = 0.0
        matrix = None
        if hessian:
            ipctk = _ipctk()
            keep = sp.diags(np.repeat(self.free, 3).astype(float))
            matrix = sp.csc_matrix(keep @ self.potential.hessian(
                collisions, self.mesh, x, ipctk.PSDProjectionMethod.NONE) @ keep)
        return energy, grad, matrix

    def largest_step(self, x: np.ndarray, dx: np.ndarray) -> float:
        """The largest fraction in [0, 1] of the step ``dx`` (n, 3) m from ``x`` along which
        no two non-adjacent elements meet (CCD, conservative)."""
        ipctk = _ipctk()
        x0 = np.asfortranarray(x, dtype=float)
        x1 = np.asfortranarray(x0 + dx)
        return float(ipctk.compute_collision_free_stepsize(
            self.mesh, x0, x1, 0.0, ipctk.LBVH(),
            ipctk.TightInclusionCCD(1e-6, CCD_MAX_ITERATIONS)))

    def intersecting(self, x: np.ndarray) -> bool:
        """Whether the sheet at ``x`` (n, 3) m intersects itself."""
        return bool(_ipctk().has_intersections(self.mesh, np.asfortranarray(x, dtype=float)))


@dataclass(frozen=True)
class Obstacles:
    """The tank wall's barrier and, optionally, the sheet's self-contact: what bounds a step
    (:meth:`largest_step`) and what the potential adds beyond its fixed-pattern terms."""

    wall: object
    contact: SelfContact | None = None

    def largest_step(self, x: np.ndarray, dx: np.ndarray) -> float:
        """The largest fraction in [0, 1] of ``dx`` that keeps every node inside the wall and
        no two non-adjacent elements meeting."""
        alpha = self.wall.largest_step(x, dx)
        if self.contact is not None and alpha > 0:
            alpha = min(alpha, self.contact.largest_step(x, alpha * dx) * alpha)
        return alpha
