"""Block-structured isoparametric P2 meshes of a tank's meridional section (r >= 0, z), for
the potential flow of one circumferential harmonic (:mod:`~fluid.section.potential`).

Each block is a transfinite (Coons) map of the unit square onto four boundary curves, its
P2 nodes placed on the curves themselves, so the mesh follows a curved wall or sheet to
third order. Curves are callables from a parameter array s (k,) in [0, 1] to points (2, k).

* :func:`sphere_section`: the liquid in a sphere of radius a centred at (0, 0) below a top
  curve from the axis to the wall (the free surface, or a sheet): three blocks meeting at
  the section's centroid, graded towards the contact line (whose corner singularity
  otherwise lowers the order);
* :func:`cylinder_section`: an upright cylinder of radius a, its liquid of depth h below the
  flat top z = 0: four blocks.
"""
from __future__ import annotations

import logging
from typing import Callable, Optional

import numpy as np
from scipy.spatial import cKDTree
from skfem import MeshTri1, MeshTri2

logging.getLogger("skfem").setLevel(logging.ERROR)

Curve = Callable[[np.ndarray], np.ndarray]
"""s (k,) in [0, 1] -> points (2, k) (r, z) m."""
MERGE_TOLERANCE = 1e-11
"""Nodes of neighbouring blocks closer than this (m) are one node."""


def coons(bottom: Curve, right: Curve, top: Curve, left: Curve, p00, p10, p01, p11):
    """The transfinite map X(u, v) of the unit square with X(u, 0) = bottom(u),
    X(u, 1) = top(u), X(0, v) = left(v), X(1, v) = right(v) and corners p00 ... p11
    (each (2,))."""
    corners = [np.asarray(p, float) for p in (p00, p10, p01, p11)]

    def x(u, v):
        u, v = np.asarray(u, float), np.asarray(v, float)
        corner = sum(wt[None] * p[:, None] for wt, p in zip(
            ((1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v), corners))
        return (1 - v)[None] * bottom(u) + v[None] * top(u) + (1 - u)[None] * left(v) \
            + u[None] * right(v) - corner
    return x


def line(p, q, grade: Optional[Callable] = None) -> Curve:
    """The segment from ``p`` to ``q`` (each (2,)), its parameter graded by ``grade``."""
    p, q = np.asarray(p, float), np.asarray(q, float)

    def curve(s):
        s = np.asarray(s, float)
        if grade is not None:
            s = grade(s)
        return p[:, None] * (1 - s)[None] + q[:, None] * s[None]
    return curve


def arc(t0: float, t1: float, grade: Optional[Callable] = None, radius: float = 1.0) -> Curve:
    """The arc of the circle of ``radius`` about the origin from angle ``t0`` to ``t1``
    (angles in the (r, z) plane from the r axis)."""
    def curve(s):
        s = np.asarray(s, float)
        if grade is not None:
            s = grade(s)
        t = t0 + (t1 - t0) * s
        return radius * np.vstack([np.cos(t), np.sin(t)])
    return curve


def grading(power: float) -> Optional[Callable]:
    """g(s) = s^power, which concentrates nodes at s = 0; None (uniform) for power 1."""
    if power == 1:
        return None
    return lambda s: np.asarray(s, float) ** power


def _block_nodes(x, n, grade_u=None, grade_v=None):
    """The (2 n + 1)^2 P2 nodes (2, N) of a block of n x n cells and its triangles' six
    local nodes (6, 2 n^2), each cell split along its diagonal, in scikit-fem's order."""
    s = np.linspace(0.0, 1.0, 2 * n + 1)
    u, v = (a.ravel() for a in np.meshgrid(s, s, indexing="ij"))
    if grade_u is not None:
        u = grade_u(u)
    if grade_v is not None:
        v = grade_v(v)
    size = 2 * n + 1
    idx = lambda i, j: i * size + j                                   # noqa: E731
    triangles = []
    for i in range(0, 2 * n, 2):
        for j in range(0, 2 * n, 2):
            p00, p20, p02, p22 = idx(i, j), idx(i + 2, j), idx(i, j + 2), idx(i + 2, j + 2)
            triangles.append([p00, p20, p22, idx(i + 1, j), idx(i + 2, j + 1), idx(i + 1, j + 1)])
            triangles.append([p00, p22, p02, idx(i + 1, j + 1), idx(i + 1, j + 2), idx(i, j + 1)])
    return x(u, v), np.array(triangles).T


def _merged(points):
    """The representative (lowest index) of each point among those within
    :data:`MERGE_TOLERANCE` of it."""
    parent = np.arange(points.shape[1])

    def root(i):
        while parent[i] != i:
            i = parent[i]
        return i

    for i, j in cKDTree(points.T).query_pairs(MERGE_TOLERANCE, output_type="ndarray"):
        ri, rj = root(i), root(j)
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)
    return np.array([root(i) for i in range(len(parent))])


def assemble_mesh(blocks, n: int) -> MeshTri2:
    """The P2 mesh of ``blocks`` (each (map, grade_u, grade_v)), n x n cells each, their
    shared edges' nodes merged and every triangle counter-clockwise; its edge nodes lie on
    the blocks' maps (the curved boundary kept)."""
    points, triangles, offset = [], [], 0
    for x, grade_u, grade_v in blocks:
        xy, tri = _block_nodes(x, n, grade_u, grade_v)
        points.append(xy)
        triangles.append(tri + offset)
        offset += xy.shape[1]
    xy, tri6 = np.hstack(points), np.hstack(triangles)
    first, inverse = np.unique(_merged(xy), return_inverse=True)
    xy, tri6 = xy[:, first], inverse[tri6]
    a, b, c = tri6[0], tri6[1], tri6[2]
    det = (xy[0, b] - xy[0, a]) * (xy[1, c] - xy[1, a]) \
        - (xy[0, c] - xy[0, a]) * (xy[1, b] - xy[1, a])
    flip = det < 0
    tri6[:, flip] = tri6[[0, 2, 1, 5, 4, 3]][:, flip]
    vertices = np.unique(tri6[:3])
    vertex_of = -np.ones(xy.shape[1], dtype=np.int64)
    vertex_of[vertices] = np.arange(len(vertices))
    corners = xy[:, vertices]
    t = vertex_of[tri6[:3]]
    linear = MeshTri1(corners, t, sort_t=False)
    if not np.all(linear.t == t):
        raise RuntimeError("scikit-fem reordered the triangles")
    nv = corners.shape[1]
    keys, values = [], []
    for i, j, k in ((0, 1, 3), (1, 2, 4), (0, 2, 5)):
        vi, vj = t[i].astype(np.int64), t[j].astype(np.int64)
        keys.append(np.minimum(vi, vj) * nv + np.maximum(vi, vj))
        values.append(tri6[k])
    unique_keys, first_key = np.unique(np.concatenate(keys), return_index=True)
    edge_node = np.concatenate(values)[first_key]
    quadratic = MeshTri2.from_mesh(linear)
    doflocs = quadratic.doflocs.copy()
    facets = linear.facets.astype(np.int64)
    facet_keys = np.minimum(facets[0], facets[1]) * nv + np.maximum(facets[0], facets[1])
    position = np.minimum(np.searchsorted(unique_keys, facet_keys), len(unique_keys) - 1)
    if not np.all(unique_keys[position] == facet_keys):
        raise RuntimeError("a facet of the mesh has no edge node")
    doflocs[:, nv:] = xy[:, edge_node[position]]
    return MeshTri2(doflocs, linear.t, sort_t=False)


def _wall(c, t0: float, t1: float, radius: float, grade=None) -> Curve:
    """The wall from the point ``c`` (at angle t0, within a thin gap of the sphere) to the
    angle t1 on the sphere of ``radius``: the arc, its radius blended from |c| to ``radius``
    by (1 - s)^3 so that a top curve ending just off the wall closes smoothly (exactly the
    arc when c is on it)."""
    gap = radius - float(np.hypot(*c))

    def curve(s):
        s = np.asarray(s, float)
        if grade is not None:
            s = grade(s)
        t = t0 + (t1 - t0) * s
        rho = radius - gap * (1 - s) ** 3
        return rho * np.vstack([np.cos(t), np.sin(t)])
    return curve


def sphere_section(top: Curve, n: int, grade: float = 1.0, radius: float = 1.0) -> MeshTri2:
    """The liquid in the sphere of ``radius`` m about the origin below ``top``, the curve
    from the axis (top(0), r = 0) to the wall (top(1)): three blocks of n x n cells meeting
    at the centroid of the axis's, the top's and the wall's midpoints, graded by s^``grade``
    towards the contact point top(1)."""
    bottom = np.array([0.0, -radius])
    axis, contact, middle = (top(np.array([s]))[:, 0] for s in (0.0, 1.0, 0.5))
    if abs(axis[0]) > 1e-12 * radius:
        raise ValueError(f"the top curve must start on the axis, got r = {axis[0]:.3g} m")
    t_contact, t_bottom = np.arctan2(contact[1], contact[0]), -np.pi / 2
    t_mid = 0.5 * (t_contact + t_bottom)
    m_axis = 0.5 * (bottom + axis)
    m_wall = radius * np.array([np.cos(t_mid), np.sin(t_mid)])
    centre = (m_axis + middle + m_wall) / 3.0
    g = grading(grade)

    def top_from_contact(s):
        return top(1.0 - 0.5 * np.asarray(s, float))

    def top_from_middle(s):
        return top(0.5 - 0.5 * np.asarray(s, float))

    corner = coons(bottom=top_from_contact, right=line(middle, centre), top=line(m_wall, centre),
                   left=_wall(contact, t_contact, t_mid, radius), p00=contact, p10=middle,
                   p01=m_wall, p11=centre)
    axis_block = coons(bottom=line(middle, centre), right=line(centre, m_axis),
                       top=line(axis, m_axis), left=top_from_middle, p00=middle, p10=centre,
                       p01=axis, p11=m_axis)
    wall_block = coons(bottom=line(m_wall, centre), right=line(centre, m_axis),
                       top=line(bottom, m_axis), left=arc(t_mid, t_bottom, radius=radius),
                       p00=m_wall, p10=centre, p01=bottom, p11=m_axis)
    return assemble_mesh([(corner, g, g), (axis_block, g, None), (wall_block, g, None)], n)


def flat_top(level: float, radius: float = 1.0) -> Curve:
    """The free surface z = ``level`` (m) from the axis to the sphere of ``radius``."""
    return line([0.0, level], [np.sqrt(radius**2 - level**2), level])


def cylinder_section(depth: float, n: int, radius: float = 1.0) -> MeshTri2:
    """The liquid of ``depth`` h m in the upright cylinder of ``radius`` a m below z = 0:
    four uniform blocks of n x n cells (square for h = a)."""
    blocks = []
    for r0, r1 in ((0.0, 0.5 * radius), (0.5 * radius, radius)):
        for z0, z1 in ((-depth, -0.5 * depth), (-0.5 * depth, 0.0)):
            p00, p10, p01, p11 = (np.array(p, float) for p in ([r0, z0], [r1, z0], [r0, z1],
                                                                 [r1, z1]))
            blocks.append((coons(line(p00, p10), line(p10, p11), line(p01, p11),
                                 line(p00, p01), p00, p10, p01, p11), None, None))
    return assemble_mesh(blocks, n)
