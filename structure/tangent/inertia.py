"""The membrane's mass and its node damping as tangent terms.

Both are quadratic forms of the node velocities v (n, 3) m/s, so their "Hessians" are the
mass matrix and the damping matrix an implicit integrator needs:

* kinetic energy T = 1/2 sum_i m_i |v_i|^2: gradient m_i v_i (N s), blocks m_i I (kg);
* the node damping of :mod:`structure.xpbd.damping` as Rayleigh's dissipation function
  R = c/2 sum over edges |v_i - v_j|^2: gradient -c L v (N), blocks c [[I, -I], [-I, I]]
  (N s/m), L the edges' graph Laplacian.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class KineticTerm:
    """1/2 v^T M v of the lumped node masses ``node_mass`` (n,) kg."""

    node_mass: np.ndarray

    @property
    def element_nodes(self) -> np.ndarray:
        return np.arange(len(self.node_mass), dtype=np.int64)[:, None]

    def evaluate(self, v: np.ndarray, hessian: bool = True):
        """(kinetic energy J, momentum (n, 3) N s, blocks (n, 1, 1, 3, 3) kg) at ``v``."""
        m = np.asarray(self.node_mass, dtype=float)
        v = np.asarray(v, dtype=float)
        blocks = (m[:, None, None, None, None] * np.eye(3)) if hessian else None
        return 0.5 * float(m @ np.einsum("ij,ij->i", v, v)), m[:, None] * v, blocks


@dataclass(frozen=True)
class DampingTerm:
    """Rayleigh's dissipation of the relative node damping: ``coefficient`` c (N s/m) on
    ``edges`` (e, 2) int64."""

    edges: np.ndarray
    coefficient: float

    @property
    def element_nodes(self) -> np.ndarray:
        return np.asarray(self.edges, dtype=np.int64)

    def evaluate(self, v: np.ndarray, hessian: bool = True):
        """(dissipation W, gradient (n, 3) N, blocks (e, 2, 2, 3, 3) N s/m) at ``v``."""
        v = np.asarray(v, dtype=float)
        i, j = self.edges[:, 0], self.edges[:, 1]
        dv = v[i] - v[j]
        c = float(self.coefficient)
        grad = np.zeros_like(v)
        np.add.at(grad, i, c * dv)
        np.add.at(grad, j, -c * dv)
        blocks = None
        if hessian:
            sign = np.array([[1.0, -1.0], [-1.0, 1.0]])
            blocks = np.broadcast_to(c * sign[None, :, :, None, None] * np.eye(3),
                                     (len(self.edges), 2, 2, 3, 3))
        return 0.5 * c * float(np.einsum("ij,ij->", dv, dv)), grad, blocks
