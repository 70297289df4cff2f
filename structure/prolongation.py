"""A membrane state carried from one grid to a finer one of the same surface.

A fold state found on a coarse grid is one equilibrium of many; a grid convergence study that
starts every grid from its own relaxation compares different fold states, not one state at
different resolutions. Carried to the finer grid and polished there (the shell model's
minimum, :mod:`structure.shell`), the coarse state stays the same fold state, refined.

Each fine node's rest position is located on the coarse grid's rest triangulation (its
triangles split from the quads as :func:`structure.grid.triangles_from_quads` splits them):
projected onto the plane of the nearest candidate triangles (by centroid) and given the
barycentric weights w of the one it lies most inside (the weights clamped to >= 0 and
renormalised where it lies just outside every one, e.g. a sphere's point beyond the chordal
rim). Its carried position is

    x_fine = sum_k w_k x_coarse[k]        (the coarse triangle's three deformed nodes),

exact for any affine map of a flat rest grid and within the chordal sag (h^2 / 8R) of one on
a sphere. Fixed nodes keep their own rest positions.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .grid import triangles_from_quads
from .model import MembraneModel

CANDIDATE_TRIANGLES = 12
"""Coarse triangles (nearest by centroid) tried for each fine node (-)."""


def locate(coarse: MembraneModel, point_rest: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For ``point_rest`` (m, 3) rest positions (m): the coarse triangle of each, (m, 3) node
    indices, and its barycentric weights (m, 3), >= 0 and summing to 1."""
    rest = coarse.node_rest_position
    tri = triangles_from_quads(coarse.face_nodes)
    a, b, c = rest[tri[:, 0]], rest[tri[:, 1]], rest[tri[:, 2]]
    k = min(CANDIDATE_TRIANGLES, len(tri))
    _, cand = cKDTree((a + b + c) / 3.0).query(point_rest, k=k)
    cand = cand.reshape(len(point_rest), k)
    # barycentric weights of each point's projection onto each candidate's plane
    e1, e2 = b[cand] - a[cand], c[cand] - a[cand]                 # (m, k, 3)
    d = point_rest[:, None, :] - a[cand]
    g11, g12, g22 = (np.einsum("mki,mki->mk", e1, e1), np.einsum("mki,mki->mk", e1, e2),
                     np.einsum("mki,mki->mk", e2, e2))
    r1, r2 = np.einsum("mki,mki->mk", d, e1), np.einsum("mki,mki->mk", d, e2)
    det = g11 * g22 - g12 * g12
    flat = det <= 1e-12 * g11 * g22                               # a degenerate triangle
    det = np.where(flat, 1.0, det)
    u = (g22 * r1 - g12 * r2) / det
    v = (g11 * r2 - g12 * r1) / det
    w = np.stack([1.0 - u - v, u, v], axis=-1)                     # (m, k, 3)
    best = np.argmax(np.where(flat, -np.inf, w.min(axis=-1)), axis=1)
    rows = np.arange(len(point_rest))
    weights = np.clip(w[rows, best], 0.0, None)
    weights /= weights.sum(axis=1, keepdims=True)
    return tri[cand[rows, best]], weights


def prolong(coarse: MembraneModel, node_position: np.ndarray,
            fine: MembraneModel) -> np.ndarray:
    """(n_fine, 3) m: the coarse state ``node_position`` (n_coarse, 3) m carried to the
    ``fine`` grid's nodes (module doc); its fixed nodes at their rest positions."""
    node_position = np.asarray(node_position, dtype=float)
    if node_position.shape != coarse.node_rest_position.shape:
        raise ValueError(f"node_position has shape {node_position.shape}; the coarse grid "
                         f"has {coarse.node_rest_position.shape}")
    nodes, weights = locate(coarse, fine.node_rest_position)
    out = np.einsum("mk,mki->mi", weights, node_position[nodes])
    out[fine.node_fixed] = fine.node_rest_position[fine.node_fixed]
    return out
