"""numba kernels of the particle membrane (hot loops; compiled once, cached on disk).

All kernels work on flat row-major structured grids: node (i, j) of an N x N grid has index
i*N + j; ``pos`` is (n, 3) float64 in m and is updated in place where stated.
"""
from __future__ import annotations

import numpy as np
from numba import njit

JIT = dict(cache=True, nogil=True, fastmath=False)
JIT_FAST = dict(cache=True, nogil=True, fastmath=True, error_model="numpy")


@njit(**JIT, inline="always")
def _tangent(pos, k, step, at_start, at_end, c):
    """Component c of d pos / d(grid index) at node k along a grid direction of stride ``step``:
    central inside, second-order one-sided at the border (MATLAB ``surfnorm``'s quadratic
    extrapolation past the border followed by a central difference, written out)."""
    if at_start:
        return 0.5 * (-3.0 * pos[k, c] + 4.0 * pos[k + step, c] - pos[k + 2 * step, c])
    if at_end:
        return 0.5 * (3.0 * pos[k, c] - 4.0 * pos[k - step, c] + pos[k - 2 * step, c])
    return 0.5 * (pos[k + step, c] - pos[k - step, c])


@njit(**JIT)
def node_area_and_normal(pos, n, sign):
    """Node areas (App. D) and unit node normals (surfnorm rule, times ``sign``).

    Returns ``node_area`` (n*n,) m^2: a quarter of each adjacent quad's area, the quad area being
    the two triangles split along the (i,j)-(i+1,j+1) diagonal; and ``node_normal`` (n*n, 3).
    """
    nn = n * n
    area = np.zeros(nn)
    for i in range(n - 1):
        for j in range(n - 1):
            k = i * n + j
            ax, ay, az = pos[k + 1, 0] - pos[k, 0], pos[k + 1, 1] - pos[k, 1], pos[k + 1, 2] - pos[k, 2]
            bx, by, bz = pos[k + n, 0] - pos[k, 0], pos[k + n, 1] - pos[k, 1], pos[k + n, 2] - pos[k, 2]
            cx = pos[k + n + 1, 0] - pos[k, 0]
            cy = pos[k + n + 1, 1] - pos[k, 1]
            cz = pos[k + n + 1, 2] - pos[k, 2]
            q = 0.125 * (np.sqrt((ay * cz - az * cy) ** 2 + (az * cx - ax * cz) ** 2
                                 + (ax * cy - ay * cx) ** 2)
                         + np.sqrt((by * cz - bz * cy) ** 2 + (bz * cx - bx * cz) ** 2
                                   + (bx * cy - by * cx) ** 2))
            area[k] += q
            area[k + 1] += q
            area[k + n] += q
            area[k + n + 1] += q
    normal = np.empty((nn, 3))
    for i in range(n):
        for j in range(n):
            k = i * n + j
            jx = _tangent(pos, k, 1, j == 0, j == n - 1, 0)
            jy = _tangent(pos, k, 1, j == 0, j == n - 1, 1)
            jz = _tangent(pos, k, 1, j == 0, j == n - 1, 2)
            ix = _tangent(pos, k, n, i == 0, i == n - 1, 0)
            iy = _tangent(pos, k, n, i == 0, i == n - 1, 1)
            iz = _tangent(pos, k, n, i == 0, i == n - 1, 2)
            c0 = jy * iz - jz * iy
            c1 = jz * ix - jx * iz
            c2 = jx * iy - jy * ix
            s = sign / max(np.sqrt(c0 * c0 + c1 * c1 + c2 * c2), 1e-300)
            normal[k, 0] = c0 * s
            normal[k, 1] = c1 * s
            normal[k, 2] = c2 * s
    return area, normal


@njit(**JIT)
def bending_force(pos, normal, bend_nodes, bend_rest, bend_k, force, offset_limited=False):
    """Add the thesis bending-spring forces (App. F) to ``force`` (n, 3) N.

    For each triple (P1, Pm, P2) the sagitta d = sqrt((L_B/2)^2 - (|P2-P1|/2)^2) (0 when the chord
    is longer than at rest) gives a force K_eq d on the middle node along its normal, pointing
    back towards the chord.  Returns the largest force magnitude (N).

    ``offset_limited`` (not in the thesis) caps the magnitude at K_eq |u|, u the middle node's
    offset from the chord midpoint along its normal (m): f = K_eq clip(-u, -d, d).  With
    unstretched half-segments |u| = d and nothing changes; on a nearly straight triple whose
    chord is shortened by in-plane compression the thesis force jumps between +-K_eq d as the
    node crosses the chord (d is 14 % of L_B/2 at 1 % compression), which makes quasi-static
    relaxation chatter; the capped force goes through zero there instead.
    """
    fmax = 0.0
    for s in range(bend_nodes.shape[0]):
        a, m, b = bend_nodes[s, 0], bend_nodes[s, 1], bend_nodes[s, 2]
        dx = pos[b, 0] - pos[a, 0]
        dy = pos[b, 1] - pos[a, 1]
        dz = pos[b, 2] - pos[a, 2]
        half_chord2 = 0.25 * (dx * dx + dy * dy + dz * dz)
        d2 = 0.25 * bend_rest[s] ** 2 - half_chord2
        if d2 <= 0.0:
            continue
        d = np.sqrt(d2)
        # (Pm - Pc) . N < 0  -> middle node on the -N side -> push along +N (App. F's sign test)
        u = 0.0
        for c in range(3):
            u += (pos[m, c] - 0.5 * (pos[a, c] + pos[b, c])) * normal[m, c]
        if offset_limited:
            f = -bend_k[s] * min(max(u, -d), d)
        else:
            f = bend_k[s] * d if u < 0.0 else -bend_k[s] * d
        for c in range(3):
            force[m, c] += f * normal[m, c]
        if abs(f) > fmax:
            fmax = abs(f)
    return fmax


@njit(**JIT_FAST, inline="always")
def _pair_correction(out, a, b, dx, dy, dz, g, wa, wb):
    """Add the mass-weighted pair correction: out[a] += g wa d, out[b] -= g wb d (d = x_b - x_a)."""
    out[a, 0] += dx * g * wa
    out[a, 1] += dy * g * wa
    out[a, 2] += dz * g * wa
    out[b, 0] -= dx * g * wb
    out[b, 1] -= dy * g * wb
    out[b, 2] -= dz * g * wb


@njit(**JIT_FAST)
def _relax_family(pos, inv_mass, nodes, rest, lo, hi, delta, gauss_seidel):
    """One pass over one spring family (App. G/H); returns sum |L - L0| before it (m).

    ``gauss_seidel`` False is the thesis's Jacobi pass (every spring of the family sees the
    positions before the pass); True applies each correction at once (Gauss-Seidel), which
    damps the alternating mode that a Jacobi pass leaves undamped.
    """
    err = 0.0
    for s in range(lo, hi):
        a, b = nodes[s, 0], nodes[s, 1]
        wa, wb = inv_mass[a], inv_mass[b]
        if wa + wb == 0.0:
            continue
        dx = pos[b, 0] - pos[a, 0]
        dy = pos[b, 1] - pos[a, 1]
        dz = pos[b, 2] - pos[a, 2]
        length = np.sqrt(dx * dx + dy * dy + dz * dz)
        err += abs(length - rest[s])
        if length == 0.0:
            continue
        g = (length - rest[s]) / (length * (wa + wb))
        _pair_correction(pos if gauss_seidel else delta, a, b, dx, dy, dz, g, wa, wb)
    if not gauss_seidel:
        for s in range(lo, hi):
            for k in (nodes[s, 0], nodes[s, 1]):
                for c in range(3):
                    pos[k, c] += delta[k, c]
                    delta[k, c] = 0.0
    return err


@njit(**JIT)
def limit_in_plane_strain(pos, inv_mass, nodes, rest, family_start, total_rest, error_limit,
                          max_passes, gauss_seidel, min_passes=1):
    """App. G strain limiting, in place: passes over the four families until the thesis error
    sum |L - L0| / sum L0 (measured as each family is relaxed) is below ``error_limit``
    (a fraction, ErrorLimit/100).  At least ``min_passes`` passes are made (1 in App. G).

    Returns (passes, error).  ``passes == max_passes`` with error above the limit means the
    limit was not reached.
    """
    delta = np.zeros_like(pos)
    passes = 0
    error = np.inf
    while (error > error_limit or passes < min_passes) and passes < max_passes:
        passes += 1
        e = 0.0
        for f in range(family_start.size - 1):
            e += _relax_family(pos, inv_mass, nodes, rest, family_start[f], family_start[f + 1],
                               delta, gauss_seidel)
        error = e / total_rest
    return passes, error


@njit(**JIT)
def limit_bending(pos, inv_mass, pairs, bend_rest, family_start, iterations, gauss_seidel):
    """App. H bend limiting, in place: ``iterations`` passes pulling each two-cell chord
    (``pairs`` (b, 2): the end nodes of each bending triple) to its rest length."""
    delta = np.zeros_like(pos)
    for _ in range(iterations):
        for f in range(family_start.size - 1):
            _relax_family(pos, inv_mass, pairs, bend_rest, family_start[f], family_start[f + 1],
                          delta, gauss_seidel)


@njit(**JIT)
def wall_collision(pos, inv_mass, radius, slack):
    """App. I ``ContainerCollisionCheck``, in place: a free node farther than slack*radius from
    the tank centre is put back on the sphere of radius ``radius`` (m). Returns nodes moved."""
    moved = 0
    for k in range(pos.shape[0]):
        if inv_mass[k] == 0.0:
            continue
        r = np.sqrt(pos[k, 0] ** 2 + pos[k, 1] ** 2 + pos[k, 2] ** 2)
        if r > radius * slack:
            for c in range(3):
                pos[k, c] *= radius / r
            moved += 1
    return moved


@njit(**JIT)
def self_collision(pos, inv_mass, n, min_distance):
    """App. I self-collision, in place, with a spatial hash instead of the O(n^2) loop.

    Pairs of nodes closer than ``min_distance`` (m) that are not grid neighbours (the thesis's
    six-neighbour exclusion) are pushed apart to ``min_distance``, the correction split by
    inverse mass (fixed nodes do not move). Returns the number of pairs corrected.
    """
    nn = pos.shape[0]
    table = 2 * nn
    cell = np.empty((nn, 3), dtype=np.int64)
    key = np.empty(nn, dtype=np.int64)
    inv_h = 1.0 / min_distance
    count = np.zeros(table + 1, dtype=np.int64)
    for k in range(nn):
        for c in range(3):
            cell[k, c] = np.int64(np.floor(pos[k, c] * inv_h))
        h = (cell[k, 0] * 92837111) ^ (cell[k, 1] * 689287499) ^ (cell[k, 2] * 283923481)
        key[k] = abs(h) % table
        count[key[k]] += 1
    start = np.zeros(table + 1, dtype=np.int64)
    for t in range(table):
        start[t + 1] = start[t] + count[t]
    fill = start.copy()
    sorted_nodes = np.empty(nn, dtype=np.int64)
    for k in range(nn):
        sorted_nodes[fill[key[k]]] = k
        fill[key[k]] += 1
    delta = np.zeros_like(pos)
    pairs = 0
    d2min = min_distance * min_distance
    for a in range(nn):
        ia, ja = a // n, a % n
        for ox in range(-1, 2):
            for oy in range(-1, 2):
                for oz in range(-1, 2):
                    cx, cy, cz = cell[a, 0] + ox, cell[a, 1] + oy, cell[a, 2] + oz
                    h = abs((cx * 92837111) ^ (cy * 689287499) ^ (cz * 283923481)) % table
                    for q in range(start[h], start[h + 1]):
                        b = sorted_nodes[q]
                        if b <= a:
                            continue
                        di, dj = b // n - ia, b % n - ja
                        if (di == 0 and abs(dj) <= 1) or (dj == 0 and abs(di) <= 1) or \
                                (di == dj and abs(di) == 1):
                            continue
                        wa, wb = inv_mass[a], inv_mass[b]
                        if wa + wb == 0.0:
                            continue
                        dx = pos[b, 0] - pos[a, 0]
                        dy = pos[b, 1] - pos[a, 1]
                        dz = pos[b, 2] - pos[a, 2]
                        d2 = dx * dx + dy * dy + dz * dz
                        if d2 >= d2min or d2 == 0.0:
                            continue
                        d = np.sqrt(d2)
                        g = (d - min_distance) / (d * (wa + wb))
                        _pair_correction(delta, a, b, dx, dy, dz, g, wa, wb)
                        pairs += 1
    for k in range(nn):
        for c in range(3):
            pos[k, c] += delta[k, c]
    return pairs


@njit(**JIT)
def closed_volume_term(pos, faces, sign):
    """sign * sum over triangles of zbar * A_xy (m^3): the membrane part of the divergence-theorem
    volume integral of F = (0, 0, z), quads split along their first diagonal."""
    v = 0.0
    for f in range(faces.shape[0]):
        for t in range(2):
            a = faces[f, 0]
            b = faces[f, 1 + t]
            c = faces[f, 2 + t]
            axy = 0.5 * ((pos[b, 0] - pos[a, 0]) * (pos[c, 1] - pos[a, 1])
                         - (pos[c, 0] - pos[a, 0]) * (pos[b, 1] - pos[a, 1]))
            v += (pos[a, 2] + pos[b, 2] + pos[c, 2]) / 3.0 * axy
    return sign * v


@njit(**JIT)
def closed_volume_gradient(pos, faces, sign):
    """Gradient (n, 3) m^2 of :func:`closed_volume_term` with respect to node positions."""
    g = np.zeros_like(pos)
    for f in range(faces.shape[0]):
        for t in range(2):
            tri = (faces[f, 0], faces[f, 1 + t], faces[f, 2 + t])
            zbar = (pos[tri[0], 2] + pos[tri[1], 2] + pos[tri[2], 2]) / 3.0
            axy = 0.5 * ((pos[tri[1], 0] - pos[tri[0], 0]) * (pos[tri[2], 1] - pos[tri[0], 1])
                         - (pos[tri[2], 0] - pos[tri[0], 0]) * (pos[tri[1], 1] - pos[tri[0], 1]))
            for r in range(3):
                k = tri[r]
                k1 = tri[(r + 1) % 3]
                k2 = tri[(r + 2) % 3]
                # d A_xy / d x_k = (y_k1 - y_k2)/2 ; d A_xy / d y_k = (x_k2 - x_k1)/2
                g[k, 0] += sign * zbar * 0.5 * (pos[k1, 1] - pos[k2, 1])
                g[k, 1] += sign * zbar * 0.5 * (pos[k2, 0] - pos[k1, 0])
                g[k, 2] += sign * axy / 3.0
    return g


@njit(**JIT)
def first_moment(pos, faces, sign):
    """Membrane part of the liquid's first moment M1 (3,) m^4 and its gradient (n, 3, 3)
    [node, coordinate of the node, component of M1], quads split as closed_volume_term."""
    m1 = np.zeros(3)
    grad = np.zeros((pos.shape[0], 3, 3))
    for f in range(faces.shape[0]):
        for t in range(2):
            i0, i1, i2 = faces[f, 0], faces[f, 1 + t], faces[f, 2 + t]
            ab = pos[i1] - pos[i0]
            ac = pos[i2] - pos[i0]
            area_vec = 0.5 * np.cross(ab, ac)
            for k in range(3):
                a, b, c = pos[i0, k], pos[i1, k], pos[i2, k]
                q = a * a + b * b + c * c + a * b + b * c + c * a
                m1[k] += sign * area_vec[k] * q / 12.0
                # d q / d x_node[k]
                grad[i0, k, k] += sign * area_vec[k] * (2 * a + b + c) / 12.0
                grad[i1, k, k] += sign * area_vec[k] * (2 * b + a + c) / 12.0
                grad[i2, k, k] += sign * area_vec[k] * (2 * c + a + b) / 12.0
                # d area_vec[k] / d positions: area_vec = 0.5 (x1 - x0) x (x2 - x0)
                k1, k2 = (k + 1) % 3, (k + 2) % 3
                s = sign * q / 12.0 * 0.5
                # area_vec[k] = 0.5 (ab[k1] ac[k2] - ab[k2] ac[k1])
                grad[i1, k1, k] += s * ac[k2]
                grad[i1, k2, k] -= s * ac[k1]
                grad[i2, k2, k] += s * ab[k1]
                grad[i2, k1, k] -= s * ab[k2]
                grad[i0, k1, k] -= s * (ac[k2] - ab[k2])
                grad[i0, k2, k] -= s * (ab[k1] - ac[k1])
    return m1, grad


@njit(**JIT)
def project_volume_masked(pos, inv_mass, movable, faces, sign, volume_offset, target,
                          iterations, max_move):
    """Move the ``movable`` nodes along W grad V so that the liquid volume
    ``volume_offset + closed_volume_term`` (m^3) equals ``target`` (m^3), in place.

    W is the inverse node mass (least mass-weighted move, a position-based-dynamics volume
    constraint); ``iterations`` Newton steps on the multiplier, which is clipped so that no node
    moves more than ``max_move`` (n,) m. Returns the multiplier lambda (kg/m) of
    ``dx = lambda W grad V``; 0 when no movable node can change the volume.
    """
    grad = closed_volume_gradient(pos, faces, sign)
    direction = np.zeros_like(pos)
    slope = 0.0
    for k in range(pos.shape[0]):
        if movable[k]:
            for c in range(3):
                direction[k, c] = inv_mass[k] * grad[k, c]
                slope += direction[k, c] * grad[k, c]
    if slope <= 0.0:
        return 0.0
    lam_max = np.inf
    for k in range(pos.shape[0]):
        size = np.sqrt(direction[k, 0] ** 2 + direction[k, 1] ** 2 + direction[k, 2] ** 2)
        if size > 0.0:
            lam_max = min(lam_max, max_move[k] / size)
    base = pos.copy()
    lam = 0.0
    for _ in range(iterations):
        residual = volume_offset + closed_volume_term(pos, faces, sign) - target
        grad = closed_volume_gradient(pos, faces, sign)
        slope = 0.0
        for k in range(pos.shape[0]):
            for c in range(3):
                slope += grad[k, c] * direction[k, c]
        if slope <= 0.0:
            break
        lam = min(max(lam - residual / slope, -lam_max), lam_max)
        for k in range(pos.shape[0]):
            for c in range(3):
                pos[k, c] = base[k, c] + lam * direction[k, c]
    return lam
