"""Topology of a deformed membrane: folds, the inversion front, wall contact, self-contact.

Pure geometry on a triangulated sheet (no law, no time):

- :func:`rest_angles`: each point's polar angle from the pole of the rest shape and its
  azimuth (deg) -- on the hemisphere the angle at the tank centre from the pole (-z), on the
  flat disc the same angle unrolled (r / R x 90 deg, :func:`structure.grid.disc_grid`);
- :func:`fold_clusters`: the folds, the connected clusters (triangles sharing a node) of
  triangles marked folded; a triangle is folded on the wrinkled or slack branch of the tension
  field, or where its curvature across an edge exceeds :data:`FOLD_CURVATURE` / R (a crease,
  radius of curvature under R / 5: the rest hemisphere is 1 / R, the inverted cap -1 / R);
- :func:`inverted_area_fraction`: the share of the free sheet's rest area whose nodes have
  crossed the rim's plane (the hemisphere turned inside out), and the inversion front's rest
  polar angle, the cap of that area;
- :func:`wall_contact_area`: the rest area of the free nodes on the tank wall;
- :func:`self_contact_nodes`: the nodes closer than the contact distance to a node that was
  not near them at rest.
"""
from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

FOLD_CURVATURE = 5.0
"""A crease: |principal curvature| above this many times 1 / R (1)."""
WALL_GAP = 0.05
"""A node touches the wall within this fraction of the shortest rest edge of it (1)."""
SELF_CONTACT_GAP = 0.5
"""Two nodes touch within this fraction of the shortest rest edge (1)."""
SELF_CONTACT_REST = 3.0
"""... unless they were within this many shortest rest edges at rest (neighbours) (1)."""


def rest_angles(rest_point: np.ndarray, radius: float, flat: bool) -> tuple[np.ndarray, np.ndarray]:
    """(polar, azimuth) (k,) deg of points ``rest_point`` (k, 3) m on the rest shape (module
    doc): polar from the pole, azimuth from +x towards +y in [0, 360)."""
    p = np.asarray(rest_point, dtype=float)
    azimuth = np.degrees(np.arctan2(p[:, 1], p[:, 0])) % 360.0
    if flat:
        polar = np.hypot(p[:, 0], p[:, 1]) / radius * 90.0
    else:
        r = np.maximum(np.linalg.norm(p, axis=1), np.finfo(float).tiny)
        polar = np.degrees(np.arccos(np.clip(-p[:, 2] / r, -1.0, 1.0)))
    return polar, azimuth


def free_triangles(node_fixed: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(m,) bool: the triangles of the free sheet, those with a free node (``node_fixed``
    (n,) bool); a triangle between two support rings lies inside the clamp."""
    return ~np.asarray(node_fixed, dtype=bool)[np.asarray(triangles)].all(axis=1)


def triangle_adjacency(triangles: np.ndarray) -> np.ndarray:
    """(p, 2) int64: the pairs of triangles that share a node (a crease along a diagonal
    runs through triangles that touch at their corners)."""
    tri = np.asarray(triangles, dtype=np.int64)
    m = len(tri)
    incidence = coo_matrix((np.ones(3 * m), (np.repeat(np.arange(m), 3), tri.ravel())),
                           shape=(m, int(tri.max()) + 1)).tocsr()
    pairs = (incidence @ incidence.T).tocoo()
    upper = pairs.row < pairs.col
    return np.stack([pairs.row[upper], pairs.col[upper]], axis=1).astype(np.int64)


def fold_clusters(folded: np.ndarray, adjacency: np.ndarray) -> list[np.ndarray]:
    """The folds: connected clusters (sharing a node, ``adjacency`` of
    :func:`triangle_adjacency`) of the triangles where ``folded`` (m,) bool holds, each an
    index array, largest first."""
    folded = np.asarray(folded, dtype=bool)
    m = len(folded)
    keep = folded[adjacency[:, 0]] & folded[adjacency[:, 1]]
    a = adjacency[keep]
    graph = coo_matrix((np.ones(len(a)), (a[:, 0], a[:, 1])), shape=(m, m))
    _, label = connected_components(graph, directed=False)
    clusters = [np.nonzero((label == lab) & folded)[0] for lab in np.unique(label[folded])]
    return sorted(clusters, key=len, reverse=True)


def creased(curvature: np.ndarray, radius: float) -> np.ndarray:
    """(m,) bool: triangles whose curvature tensor (m, 2, 2) 1/m has a principal value beyond
    :data:`FOLD_CURVATURE` / ``radius`` (m) in magnitude."""
    values = np.linalg.eigvalsh(curvature)
    return np.abs(values).max(axis=1) > FOLD_CURVATURE / radius


def inverted_area_fraction(rest: np.ndarray, pos: np.ndarray, node_area: np.ndarray,
                           free: np.ndarray, rim_height: float) -> tuple[float, float]:
    """(fraction (1), front (deg)): the share of the free nodes' rest area ``node_area`` (n,)
    m^2 on the other side of the rim's plane z = ``rim_height`` (m) from where they were at
    rest (nodes within 1e-9 R of the plane at rest are left out), and the rest polar angle of
    the cap of that area on the hemisphere, 1 - cos(front) = fraction (module doc); NaN for a
    flat sheet."""
    side0 = rest[:, 2] - rim_height
    scale = np.abs(side0).max()
    if scale == 0:
        return np.nan, np.nan
    counted = free & (np.abs(side0) > 1e-9 * scale)
    crossed = counted & (np.sign(pos[:, 2] - rim_height) == -np.sign(side0))
    fraction = float(node_area[crossed].sum() / node_area[counted].sum())
    return fraction, float(np.degrees(np.arccos(1.0 - fraction)))


def wall_contact_area(pos: np.ndarray, node_area: np.ndarray, free: np.ndarray, radius: float,
                      min_edge: float) -> float:
    """The rest area (m^2) of the free nodes within :data:`WALL_GAP` x ``min_edge`` (m) of the
    tank wall |x| = ``radius`` (m) or beyond it."""
    on = free & (np.linalg.norm(pos, axis=1) >= radius - WALL_GAP * min_edge)
    return float(node_area[on].sum())


def self_contact_nodes(rest: np.ndarray, pos: np.ndarray, min_edge: float) -> np.ndarray:
    """Indices of the nodes within :data:`SELF_CONTACT_GAP` x ``min_edge`` (m) of a node
    that was more than :data:`SELF_CONTACT_REST` x ``min_edge`` from it at rest."""
    pairs = cKDTree(pos).query_pairs(SELF_CONTACT_GAP * min_edge, output_type="ndarray")
    if len(pairs) == 0:
        return np.zeros(0, dtype=np.int64)
    apart = np.linalg.norm(rest[pairs[:, 0]] - rest[pairs[:, 1]], axis=1) > SELF_CONTACT_REST \
        * min_edge
    return np.unique(pairs[apart].ravel())
