"""Damping of each node's velocity relative to its neighbours' in the dynamic substeps.

    m_i dv_i/dt = ... + c sum_{j ~ i} (v_j - v_i)          (N),

over the triangle edges j ~ i, with c (N s/m) = ``XpbdSettings.node_damping``. It is taken
implicitly once per substep of h (s), before the substep's forces (operator splitting):

    (M - h c L) v_new = M v,

L (n, n) the edges' graph Laplacian, the fixed nodes held at zero velocity. Each
generalised eigenvector phi of L phi = -mu M phi (mu >= 0, 1/kg) is multiplied by
1 / (1 + h c mu) per substep: unconditionally stable and dissipative, the faster the finer
the mode. A node-scale zigzag (mu about 12 / m_node) is damped at a rate of about
12 c / m_node (1/s); the sheet's smooth modes, whose mu is smaller by (node spacing / their
wavelength)^2, hardly at all, and less still once the liquid's added mass moves with them.

Why it is there: the liquid's grid (a cell about one node spacing across) cannot resist a
single node's oscillation, so a node snapping inside a window moves as the dry sheet would,
at metres per second, and the coupling's fixed point is lost (docs/notes/node-damping.md).
The term is an artificial viscosity of the sheet, not a measured property of the rubber.
"""
from __future__ import annotations

import weakref
from collections import OrderedDict

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..grid import triangle_edges
from .model import XpbdModel


def edge_laplacian(triangles: np.ndarray, n: int) -> sp.csr_matrix:
    """Graph Laplacian (n, n) of the triangles' (m, 3) edges: (L v)_i = sum_{j ~ i} (v_j - v_i)."""
    edges = triangle_edges(triangles)
    adjacency = sp.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    adjacency = (adjacency + adjacency.T).tocsr()
    return (adjacency - sp.diags(np.asarray(adjacency.sum(axis=1)).ravel())).tocsr()


class RelativeDamping:
    """``damp(v)``: one substep's implicit relative damping of v (n, 3) m/s, in place."""

    def __init__(self, model: XpbdModel, dt: float, coefficient: float):
        if not coefficient >= 0:
            raise ValueError(f"node damping must be >= 0 N s/m, got {coefficient!r}")
        base = model.base
        self.free = np.flatnonzero(base.node_inv_mass > 0.0)
        laplacian = edge_laplacian(model.triangles, len(base.node_mass))
        block = laplacian[self.free][:, self.free]
        self.mass = base.node_mass[self.free]
        self._lu = splu((sp.diags(self.mass) - dt * coefficient * block).tocsc())

    def __call__(self, v: np.ndarray) -> None:
        v[self.free] = self._lu.solve(self.mass[:, None] * v[self.free])


#: factorisations kept by :func:`relative_damping`, most recently used last
_KEPT: OrderedDict = OrderedDict()
#: how many (model, substep, coefficient) factorisations are kept
KEPT_FACTORISATIONS = 4


def relative_damping(model: XpbdModel, dt: float, coefficient: float) -> RelativeDamping:
    """The :class:`RelativeDamping` of ``model`` at substep ``dt`` (s) and ``coefficient``
    (N s/m), factorised once and kept: a coupled window asks for the same one at every
    iteration, and building it (the Laplacian and its sparse LU) took as long as a quarter
    of the membrane's substeps on the N = 14 sheet."""
    key = (id(model), float(dt), float(coefficient))
    kept = _KEPT.get(key)
    if kept is not None and kept[0]() is model:
        _KEPT.move_to_end(key)
        return kept[1]
    damp = RelativeDamping(model, dt, coefficient)
    _KEPT[key] = (weakref.ref(model), damp)
    while len(_KEPT) > KEPT_FACTORISATIONS:
        _KEPT.popitem(last=False)
    return damp
