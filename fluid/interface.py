"""The moving interface (membrane) as the fluid sees it: points, faces, point velocities.

Orientation: face normals point out of the liquid. For a triangle (a, b, c) the normal is
(b - a) x (c - a); for a segment a -> b of an axisymmetric meridian, drawn in the (r, z) plane,
the normal is (dz, -dr), i.e. walking along the meridian the liquid lies on the left.

:func:`lattice_distance` evaluates, on a uniform lattice, the signed distance to the interface
(positive on the normal side, i.e. outside the liquid) inside a band around it, the interface
velocity at the closest point, and the sign everywhere else by flood fill from the band
(kept inside the tank by a barrier mask where the caller gives one).
Signs near edges and vertices use angle-weighted pseudo-normals (Baerentzen & Aanaes 2005).
On a *closed* triangulated surface (every oriented edge cancelled by its reverse, e.g. the
membrane closed by a can outside the tank) every sign, in the band and out of it, comes from
the generalized winding number instead (Jacobson, Kavan & Sorkine-Hornung 2013: the solid
angle of the surface over 4 pi, 1 inside, 0 outside), and neither pseudo-normals nor a flood
fill are computed: it stays exact next to folds whose sheets touch or cross, where the
closest point, and with it the pseudo-normal sign, jumps between sheets. On a closed surface
that number is an integer, counted exactly by the signed crossings of a vertical ray
(:func:`_winding_columns`, one pass over the faces for the whole lattice).
Past the open rim of the surface (the membrane's clamped edge on the tank wall) the surface is
continued flat: the value is the distance to the last face's plane (segment's line), so the
level set stays linear where the rim meets the wall and the cut fractions there stay exact.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numba import njit
from scipy import ndimage

JIT = dict(cache=True, nogil=True)


@dataclass(frozen=True)
class Interface:
    """points (n, 3) m, faces (m, 3) vertex ids of triangles (3-D) or (m, 2) of segments (an
    axisymmetric meridian in the x-z plane, x = r >= 0), velocities (n, 3) m/s.

    ``liquid_volume`` (m^3): the liquid volume the interface and the container hold on the
    grid, exactly, where the caller knows it (e.g. a membrane's enclosed volume); the cut cells
    are then made to hold it (:func:`fluid.geometry.compute_geometry`). None: the cut cells'
    own volume stands."""

    points: np.ndarray
    faces: np.ndarray
    velocities: np.ndarray
    liquid_volume: float | None = None

    def __post_init__(self):
        points = np.ascontiguousarray(self.points, dtype=float)
        faces = np.ascontiguousarray(self.faces, dtype=np.int64)
        velocities = np.ascontiguousarray(self.velocities, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3:
            raise ValueError(f"interface points must be (n, 3) m, got shape {points.shape}")
        if velocities.shape != points.shape:
            raise ValueError(f"interface velocities must be (n, 3) m/s like the points "
                             f"{points.shape}, got {velocities.shape}")
        if faces.ndim != 2 or faces.shape[1] not in (2, 3) or faces.shape[0] == 0:
            raise ValueError("interface faces must be (m, 3) triangles or (m, 2) meridian "
                             f"segments, got shape {faces.shape}")
        if faces.min() < 0 or faces.max() >= len(points):
            raise ValueError(f"interface faces must index 0..{len(points) - 1}")
        if not (np.all(np.isfinite(points)) and np.all(np.isfinite(velocities))):
            raise ValueError("interface points and velocities must be finite")
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "faces", faces)
        object.__setattr__(self, "velocities", velocities)
        if self.liquid_volume is not None:
            volume = float(self.liquid_volume)
            if not (np.isfinite(volume) and volume > 0):
                raise ValueError(f"interface liquid volume must be a finite number > 0 m^3, "
                                 f"got {self.liquid_volume}")
            object.__setattr__(self, "liquid_volume", volume)

    @property
    def is_meridian(self) -> bool:
        """True for an axisymmetric meridian (segments), False for a triangulated surface."""
        return self.faces.shape[1] == 2

    @cached_property
    def face_normals(self) -> np.ndarray:
        """Of a triangulated surface: unit face normals (m, 3), computed once per interface."""
        return _face_normals(self.points, self.faces)

    @cached_property
    def pseudo_normals(self) -> tuple:
        """Of a triangulated surface: face, vertex and edge normals and the rim (see
        :func:`_pseudo_normals_3d`), computed once per interface."""
        return _pseudo_normals_3d(self.points, self.faces, self.face_normals)

    def with_state(self, points: np.ndarray, velocities: np.ndarray,
                   liquid_volume: float | None = None) -> "Interface":
        """Same connectivity, new positions (n, 3) m and velocities (n, 3) m/s (and the
        liquid volume they hold, m^3, if known)."""
        return Interface(points, self.faces, velocities, liquid_volume)

    def enclosed_change_rate(self) -> float:
        """d/dt of the volume on the liquid side (m^3/s) implied by the point velocities: the
        flux of the velocity through the surface along its normals (which point out of the
        liquid, so moving along them makes room for liquid); trapezoidal in each face."""
        p, v, f = self.points, self.velocities, self.faces
        if self.is_meridian:
            a, b = p[f[:, 0]][:, [0, 2]], p[f[:, 1]][:, [0, 2]]
            va, vb = v[f[:, 0]][:, [0, 2]], v[f[:, 1]][:, [0, 2]]
            d = b - a
            normal = np.stack([d[:, 1], -d[:, 0]], axis=1)  # length-weighted
            # integral of 2 pi r v.n over the segment, v and r linear
            ra, rb = a[:, 0], b[:, 0]
            una, unb = (va * normal).sum(1), (vb * normal).sum(1)
            flux = 2 * np.pi * (ra * una / 3 + ra * unb / 6 + rb * una / 6 + rb * unb / 3)
            return float(flux.sum())
        a, b, c = p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]
        normal2 = np.cross(b - a, c - a)
        vmean = (v[f[:, 0]] + v[f[:, 1]] + v[f[:, 2]]) / 3
        return float(0.5 * (vmean * normal2).sum())


#: connectivity data kept per distinct face array (a membrane keeps its faces for a run)
_TOPOLOGY_CACHE: dict = {}
_TOPOLOGY_CACHE_SIZE = 8


def _edge_topology(faces):
    """Of the triangles (m, 3): for each face edge k (joining face vertices k and k + 1,
    flattened (3 m,)) its index among the distinct undirected edges, the number of faces on
    each distinct edge, the rim-edge mask (m, 3), the rim vertex ids, and whether the
    surface is closed (:func:`is_closed`). Kept per face array (it depends on the
    connectivity only)."""
    key = (faces.shape, faces.tobytes())
    if key not in _TOPOLOGY_CACHE:
        pairs = np.sort(np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2),
                        axis=1)
        _, inverse, count = np.unique(pairs, axis=0, return_inverse=True, return_counts=True)
        inverse = inverse.ravel()
        rim = count[inverse] == 1
        if len(_TOPOLOGY_CACHE) >= _TOPOLOGY_CACHE_SIZE:
            _TOPOLOGY_CACHE.pop(next(iter(_TOPOLOGY_CACHE)))
        _TOPOLOGY_CACHE[key] = (inverse, count, rim.reshape(len(faces), 3),
                                np.unique(pairs[rim].ravel()), _is_closed(faces))
    return _TOPOLOGY_CACHE[key]


def _scatter_rows(index, values, rows):
    """(rows, 3) sums of ``values`` (k, 3) into rows ``index`` (k,)."""
    return np.stack([np.bincount(index, values[:, c], rows) for c in range(3)], axis=1)


def _face_normals(points, faces):
    """Unit normals (m, 3) of the triangles (m, 3): (b - a) x (c - a) normalised."""
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    return n


def _pseudo_normals_3d(points, faces, n):
    """With the unit face normals ``n`` (m, 3): those, the angle-weighted vertex normals
    (n, 3), per-face-edge normals (m, 3, 3) (edge k joins face vertices k and k+1; sum of the
    adjacent faces), and the rim: edges with one face (m, 3) and their vertices (n,)."""
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    vertex = np.zeros_like(points)
    corners = (a, b, c)
    for k in range(3):
        e1 = corners[(k + 1) % 3] - corners[k]
        e2 = corners[(k + 2) % 3] - corners[k]
        cosang = (e1 * e2).sum(1) / np.maximum(
            np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1), 1e-300)
        vertex += _scatter_rows(faces[:, k], n * np.arccos(np.clip(cosang, -1, 1))[:, None],
                                len(points))
    inverse, count, rim_edge, rim_ids, _ = _edge_topology(faces)
    sums = _scatter_rows(inverse, np.repeat(n, 3, axis=0), len(count))
    edge = sums[inverse].reshape(len(faces), 3, 3)
    rim_vertex = np.zeros(len(points), dtype=bool)
    rim_vertex[rim_ids] = True
    return n, vertex, edge, rim_edge, rim_vertex


def _pseudo_normals_2d(points2, segments):
    """Segment normals (m, 2) (dz, -dr, unit) and vertex normals (n, 2) (sum of adjacent)."""
    d = points2[segments[:, 1]] - points2[segments[:, 0]]
    n = np.stack([d[:, 1], -d[:, 0]], axis=1)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    vertex = np.zeros_like(points2)
    np.add.at(vertex, segments[:, 0], n)
    np.add.at(vertex, segments[:, 1], n)
    return n, vertex


@njit(**JIT)
def _band_segments(origin, spacing, shape, band, p2, v2, seg, seg_n, vert_n, is_end, dist,
                   vel):
    """Signed distance and closest-point velocity on the 2-D lattice within ``band`` (m).
    ``is_end``: vertices with one segment (open ends of the meridian)."""
    for s in range(seg.shape[0]):
        a = seg[s, 0]
        b = seg[s, 1]
        lo0 = min(p2[a, 0], p2[b, 0]) - band
        hi0 = max(p2[a, 0], p2[b, 0]) + band
        lo1 = min(p2[a, 1], p2[b, 1]) - band
        hi1 = max(p2[a, 1], p2[b, 1]) + band
        i0 = max(0, int(np.ceil((lo0 - origin[0]) / spacing[0])))
        i1 = min(shape[0] - 1, int(np.floor((hi0 - origin[0]) / spacing[0])))
        j0 = max(0, int(np.ceil((lo1 - origin[1]) / spacing[1])))
        j1 = min(shape[1] - 1, int(np.floor((hi1 - origin[1]) / spacing[1])))
        dx = p2[b, 0] - p2[a, 0]
        dy = p2[b, 1] - p2[a, 1]
        ll = dx * dx + dy * dy
        for i in range(i0, i1 + 1):
            qx = origin[0] + i * spacing[0]
            for j in range(j0, j1 + 1):
                qy = origin[1] + j * spacing[1]
                t = ((qx - p2[a, 0]) * dx + (qy - p2[a, 1]) * dy) / ll if ll > 0 else 0.0
                open_end = False
                if t <= 0.0:
                    t = 0.0
                    nx, ny = vert_n[a, 0], vert_n[a, 1]
                    open_end = is_end[a]
                elif t >= 1.0:
                    t = 1.0
                    nx, ny = vert_n[b, 0], vert_n[b, 1]
                    open_end = is_end[b]
                else:
                    nx, ny = seg_n[s, 0], seg_n[s, 1]
                cx = p2[a, 0] + t * dx
                cy = p2[a, 1] + t * dy
                rx = qx - cx
                ry = qy - cy
                d = np.sqrt(rx * rx + ry * ry)
                if d < abs(dist[i, j]):
                    if open_end:
                        # past an open end: distance to the end segment's line, so that the
                        # level set stays linear across the rim (exact cut fractions there)
                        dist[i, j] = (qx - p2[a, 0]) * seg_n[s, 0] + (qy - p2[a, 1]) * seg_n[s, 1]
                        if abs(dist[i, j]) < 1e-300:
                            dist[i, j] = 1e-300
                    else:
                        dist[i, j] = d if rx * nx + ry * ny >= 0.0 else -d
                    for c in range(2):
                        vel[i, j, c] = (1 - t) * v2[a, c] + t * v2[b, c]


@njit(**JIT, inline="always")
def _closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz):
    """Closest point of triangle abc to p: (barycentric u, v, w, region) with region 0 = face,
    1..3 = edge ab, bc, ca, 4..6 = vertex a, b, c (Ericson, Real-Time Collision Detection).
    Corners and point as scalars (m), so that the kernel keeps them in registers."""
    abx, aby, abz = bx - ax, by - ay, bz - az
    acx, acy, acz = cx - ax, cy - ay, cz - az
    apx, apy, apz = px - ax, py - ay, pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        return 1.0, 0.0, 0.0, 4
    bpx, bpy, bpz = px - bx, py - by, pz - bz
    d3 = abx * bpx + aby * bpy + abz * bpz
    d4 = acx * bpx + acy * bpy + acz * bpz
    if d3 >= 0.0 and d4 <= d3:
        return 0.0, 1.0, 0.0, 5
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = d1 / (d1 - d3)
        return 1.0 - v, v, 0.0, 1
    cpx, cpy, cpz = px - cx, py - cy, pz - cz
    d5 = abx * cpx + aby * cpy + abz * cpz
    d6 = acx * cpx + acy * cpy + acz * cpz
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 0.0, 1.0, 6
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        return 1.0 - w, 0.0, w, 3
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 0.0, 1.0 - w, w, 2
    denom = 1.0 / (va + vb + vc)
    v = vb * denom
    w = vc * denom
    return 1.0 - v - w, v, w, 0


@njit(**JIT)
def _band_triangles(origin, spacing, shape, band, p, vel_pts, tri, face_n, vert_n, edge_n,
                    rim_edge, rim_vertex, signed, dist, vel):
    """Signed distance and closest-point velocity on the 3-D lattice within ``band`` (m).
    ``rim_edge`` (m, 3) / ``rim_vertex`` (n,): on the open boundary of the surface.
    ``signed`` False: the distance only, unsigned (a closed surface, whose signs the winding
    number gives; ``vert_n``, ``edge_n``, ``rim_edge`` and ``rim_vertex`` are not read)."""
    # a lattice point is skipped where a lower bound of its distance to the triangle (to the
    # triangle's plane, to its bounding sphere) exceeds the distance it already holds by
    # more than round-off: the closest-point test would not have replaced it either
    margin = 1e-9 * min(spacing[0], spacing[1], spacing[2])
    for f in range(tri.shape[0]):
        ia, ib, ic = tri[f, 0], tri[f, 1], tri[f, 2]
        ax, ay, az = p[ia, 0], p[ia, 1], p[ia, 2]
        bx, by, bz = p[ib, 0], p[ib, 1], p[ib, 2]
        cx, cy, cz = p[ic, 0], p[ic, 1], p[ic, 2]
        n0, n1, n2 = face_n[f, 0], face_n[f, 1], face_n[f, 2]
        m0 = (ax + bx + cx) / 3.0
        m1 = (ay + by + cy) / 3.0
        m2 = (az + bz + cz) / 3.0
        radius = np.sqrt(max((ax - m0) ** 2 + (ay - m1) ** 2 + (az - m2) ** 2,
                             (bx - m0) ** 2 + (by - m1) ** 2 + (bz - m2) ** 2,
                             (cx - m0) ** 2 + (cy - m1) ** 2 + (cz - m2) ** 2))
        i0 = max(0, int(np.ceil((min(ax, bx, cx) - band - origin[0]) / spacing[0])))
        i1 = min(shape[0] - 1, int(np.floor((max(ax, bx, cx) + band - origin[0]) / spacing[0])))
        j0 = max(0, int(np.ceil((min(ay, by, cy) - band - origin[1]) / spacing[1])))
        j1 = min(shape[1] - 1, int(np.floor((max(ay, by, cy) + band - origin[1]) / spacing[1])))
        k0 = max(0, int(np.ceil((min(az, bz, cz) - band - origin[2]) / spacing[2])))
        k1 = min(shape[2] - 1, int(np.floor((max(az, bz, cz) + band - origin[2]) / spacing[2])))
        for i in range(i0, i1 + 1):
            q0 = origin[0] + i * spacing[0]
            for j in range(j0, j1 + 1):
                q1 = origin[1] + j * spacing[1]
                for k in range(k0, k1 + 1):
                    q2 = origin[2] + k * spacing[2]
                    held = abs(dist[i, j, k]) + margin
                    if abs((q0 - ax) * n0 + (q1 - ay) * n1 + (q2 - az) * n2) > held:
                        continue
                    s0, s1, s2 = q0 - m0, q1 - m1, q2 - m2
                    reach = radius + held
                    if s0 * s0 + s1 * s1 + s2 * s2 > reach * reach:
                        continue
                    u, v, w, region = _closest_on_triangle(q0, q1, q2, ax, ay, az, bx, by, bz,
                                                           cx, cy, cz)
                    r0 = q0 - (u * ax + v * bx + w * cx)
                    r1 = q1 - (u * ay + v * by + w * cy)
                    r2 = q2 - (u * az + v * bz + w * cz)
                    d = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
                    if not d < abs(dist[i, j, k]):
                        continue
                    if not signed:
                        dist[i, j, k] = d
                    else:
                        on_rim = False
                        if region == 0:
                            n = face_n[f]
                        elif region <= 3:
                            n = edge_n[f, region - 1]
                            on_rim = rim_edge[f, region - 1]
                        else:
                            n = vert_n[tri[f, region - 4]]
                            on_rim = rim_vertex[tri[f, region - 4]]
                        if on_rim:
                            # past the open rim: distance to this face's plane (the surface
                            # continued flat), keeping the level set linear across the rim
                            dd = (q0 - ax) * n0 + (q1 - ay) * n1 + (q2 - az) * n2
                            dist[i, j, k] = dd if abs(dd) > 1e-300 else 1e-300
                        else:
                            side = r0 * n[0] + r1 * n[1] + r2 * n[2]
                            dist[i, j, k] = d if side >= 0.0 else -d
                    for cc in range(3):
                        vel[i, j, k, cc] = (u * vel_pts[ia, cc] + v * vel_pts[ib, cc]
                                            + w * vel_pts[ic, cc])


def is_closed(faces: np.ndarray) -> bool:
    """True when every oriented edge (u, v) of the triangles is matched by as many (v, u):
    the surface has no boundary and the winding number is an integer off the surface."""
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] != 3:
        return False
    return _edge_topology(faces)[4]


def _is_closed(faces: np.ndarray) -> bool:
    """:func:`is_closed` computed (uncached)."""
    edges = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    forward, nf = np.unique(edges, axis=0, return_counts=True)
    backward, nb = np.unique(edges[:, ::-1], axis=0, return_counts=True)
    return forward.shape == backward.shape and bool(
        np.array_equal(forward, backward) and np.array_equal(nf, nb))


@njit(**JIT, inline="always")
def _edge_function(p, u, v, qx, qy):
    """(x_v - x_u)(q_y - y_u) - (y_v - y_u)(q_x - x_u) in the x-y plane, evaluated from the
    lower vertex id so that the edge taken the other way gives exactly the negated value."""
    lo, hi, sign = (v, u, -1.0) if u > v else (u, v, 1.0)
    return sign * ((p[hi, 0] - p[lo, 0]) * (qy - p[lo, 1])
                   - (p[hi, 1] - p[lo, 1]) * (qx - p[lo, 0]))


@njit(**JIT, inline="always")
def _owns(p, u, v, w):
    """A point with edge function ``w`` on the counter-clockwise edge u -> v belongs to the
    triangle: inside (w > 0), or on the edge and the edge is a top or left one (the top-left
    rule: of two triangles sharing the edge exactly one owns its points, and each point of a
    plane tiled by triangles has exactly one owner)."""
    if w != 0.0:
        return w > 0.0
    dx = p[v, 0] - p[u, 0]
    dy = p[v, 1] - p[u, 1]
    return dy < 0.0 or (dy == 0.0 and dx < 0.0)


@njit(**JIT)
def _winding_columns(origin, spacing, shape, p, tri):
    """Winding number (int, ``shape``) of the closed surface (p, tri) on the 3-D lattice, by
    signed crossings of the upward ray from below the surface to each lattice point: a face
    whose normal points down is entered (+1), one whose normal points up is left (-1). Each
    face adds its crossing to the first lattice point above it in every lattice column its
    x-y projection owns (top-left rule, exact on shared edges and vertices); a running sum up
    each column gives the number. Faces seen edge-on (no projected area) cross no ray."""
    ni, nj, nk = shape[0], shape[1], shape[2]
    delta = np.zeros((ni, nj, nk + 1), dtype=np.int32)
    for f in range(tri.shape[0]):
        a, b, c = tri[f, 0], tri[f, 1], tri[f, 2]
        area2 = (p[b, 0] - p[a, 0]) * (p[c, 1] - p[a, 1]) \
            - (p[b, 1] - p[a, 1]) * (p[c, 0] - p[a, 0])
        if area2 == 0.0:
            continue
        crossing = 1 if area2 < 0.0 else -1
        if area2 < 0.0:  # walk the projection counter-clockwise
            b, c = c, b
        lo_i = max(0, int(np.ceil((min(p[a, 0], p[b, 0], p[c, 0]) - origin[0]) / spacing[0])))
        hi_i = min(ni - 1, int(np.floor((max(p[a, 0], p[b, 0], p[c, 0]) - origin[0])
                                        / spacing[0])))
        lo_j = max(0, int(np.ceil((min(p[a, 1], p[b, 1], p[c, 1]) - origin[1]) / spacing[1])))
        hi_j = min(nj - 1, int(np.floor((max(p[a, 1], p[b, 1], p[c, 1]) - origin[1])
                                        / spacing[1])))
        for i in range(lo_i, hi_i + 1):
            qx = origin[0] + i * spacing[0]
            for j in range(lo_j, hi_j + 1):
                qy = origin[1] + j * spacing[1]
                wc = _edge_function(p, a, b, qx, qy)
                wa = _edge_function(p, b, c, qx, qy)
                wb = _edge_function(p, c, a, qx, qy)
                if not (_owns(p, a, b, wc) and _owns(p, b, c, wa) and _owns(p, c, a, wb)):
                    continue
                total = wa + wb + wc
                z = (wa * p[a, 2] + wb * p[b, 2] + wc * p[c, 2]) / total if total > 0.0 \
                    else (p[a, 2] + p[b, 2] + p[c, 2]) / 3.0
                k = int(np.floor((z - origin[2]) / spacing[2])) + 1
                k = min(max(k, 0), nk)
                while k > 0 and origin[2] + (k - 1) * spacing[2] > z:
                    k -= 1
                while k < nk and origin[2] + k * spacing[2] <= z:
                    k += 1
                delta[i, j, k] += crossing
    wind = np.empty((ni, nj, nk), dtype=np.int32)
    for i in range(ni):
        for j in range(nj):
            run = 0
            for k in range(nk):
                run += delta[i, j, k]
                wind[i, j, k] = run
    return wind


def _flood_fill_sign(dist: np.ndarray, barrier: np.ndarray | None = None) -> np.ndarray:
    """Give the out-of-band entries (inf) the sign of the band entries they touch; the
    magnitude stays inf. Components touching no band entry keep +inf (outside the liquid).
    The fill does not pass through out-of-band entries where ``barrier`` is True; those take
    the sign of the nearest other entry (so that cut cells across the barrier's edge see
    the sign of their side)."""
    out = ~np.isfinite(dist)
    if not out.any():
        return dist
    held = out & barrier if barrier is not None else np.zeros_like(out)
    fill = out & ~held
    labels, count = ndimage.label(fill)
    votes = np.zeros(count + 1)
    ndim = dist.ndim
    for axis in range(ndim):
        for shift in (1, -1):
            nb = np.roll(dist, shift, axis=axis)
            # forbid wrap-around
            edge = [slice(None)] * ndim
            edge[axis] = 0 if shift == 1 else -1
            nb_valid = np.ones_like(out)
            nb_valid[tuple(edge)] = False
            pair = (labels > 0) & np.isfinite(nb) & nb_valid
            # the votes are sums of +-1: exact in any order
            votes += np.bincount(labels[pair], weights=np.sign(nb[pair]), minlength=count + 1)
    sign = np.where(votes >= 0, 1.0, -1.0)
    result = dist.copy()
    result[fill] = sign[labels[fill]] * np.inf
    if held.any() and not held.all():
        nearest = ndimage.distance_transform_edt(held, return_distances=False,
                                                 return_indices=True)
        result[held] = np.where(result[tuple(nearest[:, held])] >= 0.0, np.inf, -np.inf)
    elif held.any():
        result[held] = np.inf
    return result


def lattice_distance(interface: Interface, origin, spacing, shape, band: float,
                     barrier: np.ndarray | None = None):
    """Signed distance (m) to the interface on a uniform lattice and the interface velocity
    (m/s) at the closest point.

    origin, spacing: lattice point 0 and step per axis (m); shape: points per axis. A 2-D
    lattice is (r, z) and needs a meridian interface; a 3-D lattice needs triangles.
    Returns (dist shape, vel shape + (3,)); outside ``band`` dist is +-inf (sign by flood
    fill, or on a closed surface by its winding number) and vel is zero. ``barrier`` (bool,
    ``shape``): lattice points the flood fill must not pass through, e.g. those outside the
    tank: an open membrane whose rim lies on the tank wall separates liquid from gas only
    inside the tank, and outside it both sides connect (a closed surface needs none)."""
    shape = tuple(int(s) for s in shape)
    origin = np.asarray(origin, dtype=float)
    spacing = np.asarray(spacing, dtype=float)
    dist = np.full(shape, np.inf)
    if len(shape) == 2:
        if not interface.is_meridian:
            raise ValueError("an axisymmetric grid needs a meridian interface ((m, 2) segments)")
        p2 = np.ascontiguousarray(interface.points[:, [0, 2]])
        v2 = np.ascontiguousarray(interface.velocities[:, [0, 2]])
        seg_n, vert_n = _pseudo_normals_2d(p2, interface.faces)
        vel2 = np.zeros(shape + (2,))
        valence = np.bincount(interface.faces.ravel(), minlength=len(p2))
        _band_segments(origin, spacing, np.array(shape), band, p2, v2, interface.faces,
                       seg_n, vert_n, valence == 1, dist, vel2)
        vel = np.zeros(shape + (3,))
        vel[..., 0] = vel2[..., 0]
        vel[..., 2] = vel2[..., 1]
    else:
        if interface.is_meridian:
            raise ValueError("a 3-D grid needs a triangulated interface ((m, 3) faces)")
        vel = np.zeros(shape + (3,))
        if _edge_topology(interface.faces)[4]:
            # closed: the winding number signs every lattice point, in the band and out of
            # it, so neither the pseudo-normals nor the flood fill are needed
            _band_triangles(origin, spacing, np.array(shape), band, interface.points,
                            interface.velocities, interface.faces, interface.face_normals,
                            np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros((0, 3), dtype=bool),
                            np.zeros(0, dtype=bool), False, dist, vel)
            inside = _winding_columns(origin, spacing, np.array(shape), interface.points,
                                      interface.faces) >= 1
            return np.where(inside, -dist, dist), vel
        face_n, vert_n, edge_n, rim_edge, rim_vertex = interface.pseudo_normals
        _band_triangles(origin, spacing, np.array(shape), band, interface.points,
                        interface.velocities, interface.faces, face_n, vert_n, edge_n, rim_edge,
                        rim_vertex, True, dist, vel)
    return _flood_fill_sign(dist, barrier), vel
