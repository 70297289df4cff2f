"""Cut-cell geometry from a level set on the grid's vertex lattice (numba).

The liquid is the region where two level sets are both negative (phi_a: the container,
phi_b: the liquid side of the interface), each given at the vertices of a uniform lattice and
taken linear on each simplex of the cells (two triangles per rectangle, the six Kuhn
tetrahedra per cube). Each simplex is clipped by one level set and then by the other (a
tetrahedron's pieces by closed forms in the edge crossings, :func:`_tet_fraction2`), so
corners where the interface meets the tank wall are exact too (max(phi_a, phi_b) is not
linear there). On that piecewise-linear surface the liquid volume of every cell and the open (wetted)
fraction of every face are exact, so the discrete liquid volume changes by exactly the flux the
faces and the moving boundary carry (geometric conservation).

Axisymmetric lattices weight by the radius (first coordinate): fractions are of r dr dz, as
FiPy's ``CylindricalGrid2D`` measures cell volumes and face areas.

Lattice arrays are indexed [i, j] (2-D, i along r or x) or [i, j, k] (3-D), with vertex spacing
``h`` (m) per axis.
"""
from __future__ import annotations

import numpy as np
from numba import njit

JIT = dict(cache=True, nogil=True)


@njit(**JIT, inline="always")
def _crossing(a, b):
    """Parameter t in (0, 1) where the linear function with end values a, b vanishes."""
    return a / (a - b)


@njit(**JIT)
def _interval_wet(fa0, fa1, fb0, fb1):
    """(lo, hi) parameters of the part of [0, 1] where both linear functions are < 0."""
    lo = 0.0
    hi = 1.0
    for f0, f1 in ((fa0, fa1), (fb0, fb1)):
        if f0 >= 0.0 and f1 >= 0.0:
            return 0.0, 0.0
        if f0 < 0.0 and f1 >= 0.0:
            hi = min(hi, _crossing(f0, f1))
        elif f0 >= 0.0 and f1 < 0.0:
            lo = max(lo, _crossing(f0, f1))
    return lo, max(lo, hi)


@njit(**JIT)
def _segment_wet(x0, x1, fa0, fa1, fb0, fb1, weighted):
    """Wetted fraction of the segment x0 -> x1 (coordinates along it); ``weighted``: the
    measure is x dx (x = radius), else dx."""
    lo, hi = _interval_wet(fa0, fa1, fb0, fb1)
    if hi <= lo:
        return 0.0
    a = x0 + lo * (x1 - x0)
    b = x0 + hi * (x1 - x0)
    if weighted:
        full = x1 * x1 - x0 * x0
        return (b * b - a * a) / full if full != 0.0 else 0.0
    return hi - lo


@njit(**JIT)
def _clip_polygon(n, px, py, f, g, ox, oy, og):
    """Keep the part f < 0 of polygon (px, py)[:n] (Sutherland-Hodgman); ``g`` is a second
    function linear on the polygon, carried to the new vertices. Writes (ox, oy, og); returns
    the new vertex count."""
    m = 0
    for a in range(n):
        b = (a + 1) % n
        if f[a] < 0.0:
            ox[m] = px[a]
            oy[m] = py[a]
            og[m] = g[a]
            m += 1
        if (f[a] < 0.0) != (f[b] < 0.0):
            t = _crossing(f[a], f[b])
            ox[m] = px[a] + t * (px[b] - px[a])
            oy[m] = py[a] + t * (py[b] - py[a])
            og[m] = g[a] + t * (g[b] - g[a])
            m += 1
    return m


@njit(**JIT)
def _triangle_wet(px, py, fa, fb):
    """Area and first moment (integral of x dA) of the part of a triangle where both linear
    functions fa, fb (vertex values (3,)) are negative."""
    qx = np.empty(4)
    qy = np.empty(4)
    qg = np.empty(4)
    n = _clip_polygon(3, px, py, fa, fb, qx, qy, qg)
    if n == 0:
        return 0.0, 0.0
    rx = np.empty(5)
    ry = np.empty(5)
    rg = np.empty(5)
    n = _clip_polygon(n, qx, qy, qg, qg, rx, ry, rg)
    area = 0.0
    moment = 0.0
    for a in range(n):
        b = (a + 1) % n
        cross = rx[a] * ry[b] - rx[b] * ry[a]
        area += cross
        moment += (rx[a] + rx[b]) * cross
    return 0.5 * abs(area), abs(moment) / 6.0


@njit(**JIT)
def cell_fractions_2d(x, y, phi_a, phi_b, weighted):
    """Liquid fraction (nx, ny) of every rectangle of the lattice x (nx+1,), y (ny+1,) where
    phi_a and phi_b (nx+1, ny+1) are both negative; ``weighted``: axisymmetric (r dr dz)."""
    nx = x.shape[0] - 1
    ny = y.shape[0] - 1
    out = np.empty((nx, ny))
    px = np.empty(3)
    py = np.empty(3)
    fa = np.empty(3)
    fb = np.empty(3)
    corners = ((0, 0, 1, 0, 1, 1), (0, 0, 1, 1, 0, 1))
    for i in range(nx):
        for j in range(ny):
            inside = 0
            out_a = 0
            out_b = 0
            for di in range(2):
                for dj in range(2):
                    a = phi_a[i + di, j + dj]
                    b = phi_b[i + di, j + dj]
                    if a < 0.0 and b < 0.0:
                        inside += 1
                    out_a += a >= 0.0
                    out_b += b >= 0.0
            if inside == 4:
                out[i, j] = 1.0
                continue
            if out_a == 4 or out_b == 4:
                out[i, j] = 0.0
                continue
            area = 0.0
            moment = 0.0
            for tri in corners:
                for v in range(3):
                    di = tri[2 * v]
                    dj = tri[2 * v + 1]
                    px[v] = x[i + di]
                    py[v] = y[j + dj]
                    fa[v] = phi_a[i + di, j + dj]
                    fb[v] = phi_b[i + di, j + dj]
                ar, mo = _triangle_wet(px, py, fa, fb)
                area += ar
                moment += mo
            dy = y[j + 1] - y[j]
            if weighted:
                out[i, j] = moment / (0.5 * (x[i + 1] ** 2 - x[i] ** 2) * dy)
            else:
                out[i, j] = area / ((x[i + 1] - x[i]) * dy)
    return out


@njit(**JIT)
def face_fractions_2d(x, y, phi_a, phi_b, weighted):
    """Wetted fractions of the lattice's faces (edges): (along_x (nx, ny+1): faces normal to
    y spanning x[i]..x[i+1]; along_y (nx+1, ny): faces normal to x). ``weighted``:
    axisymmetric, faces normal to z are annuli (measure r dr)."""
    nx = x.shape[0] - 1
    ny = y.shape[0] - 1
    along_x = np.empty((nx, ny + 1))
    along_y = np.empty((nx + 1, ny))
    for i in range(nx):
        for j in range(ny + 1):
            along_x[i, j] = _segment_wet(x[i], x[i + 1], phi_a[i, j], phi_a[i + 1, j],
                                         phi_b[i, j], phi_b[i + 1, j], weighted)
    for i in range(nx + 1):
        for j in range(ny):
            along_y[i, j] = _segment_wet(y[j], y[j + 1], phi_a[i, j], phi_a[i, j + 1],
                                         phi_b[i, j], phi_b[i, j + 1], False)
    return along_x, along_y


# Kuhn triangulation of the unit cube: corners as bit triples (dx, dy, dz)
_KUHN = np.array([
    [0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]],
    dtype=np.int64)


@njit(**JIT, inline="always")
def _signs(f):
    """(negatives, i0, i1, j0, j1) of a tetrahedron's vertex values f (4-tuple): how many are
    negative, the first two negative vertices and the first two others (-1: none). The
    vertex apart in sign is i0 when one is negative, j0 when three are."""
    negatives = 0
    i0 = -1
    i1 = -1
    j0 = -1
    j1 = -1
    for a in range(4):
        if f[a] < 0.0:
            negatives += 1
            if i0 < 0:
                i0 = a
            elif i1 < 0:
                i1 = a
        elif j0 < 0:
            j0 = a
        elif j1 < 0:
            j1 = a
    return negatives, i0, i1, j0, j1


@njit(**JIT, inline="always")
def _tet_fraction(f0, f1, f2, f3):
    """The fraction of a tetrahedron where the linear function with vertex values f0 .. f3
    is negative. One vertex apart from the others in sign: the corner tetrahedron at it,
    the product of the three edge crossings (or one minus it). Two negative vertices a0, a1
    and two others b0, b1: the prism between them, split into three tetrahedra, is
    s u + u v (1 - s) + v w (1 - u) with s, u the crossings from a0 toward b0, b1 and v, w
    from a1."""
    f = (f0, f1, f2, f3)
    neg, a0, a1, b0, b1 = _signs(f)
    if neg == 0:
        return 0.0
    if neg == 4:
        return 1.0
    if neg == 1 or neg == 3:
        lone = a0 if neg == 1 else b0
        corner = 1.0
        for b in range(4):
            if b != lone:
                corner *= _crossing(f[lone], f[b])
        return corner if neg == 1 else 1.0 - corner
    s = _crossing(f[a0], f[b0])
    u = _crossing(f[a0], f[b1])
    v = _crossing(f[a1], f[b0])
    w = _crossing(f[a1], f[b1])
    return s * u + u * v * (1.0 - s) + v * w * (1.0 - u)


@njit(**JIT, inline="always")
def _tet_fraction2(a0, a1, a2, a3, b0, b1, b2, b3):
    """The fraction of a tetrahedron where both linear functions, vertex values a0 .. a3 and
    b0 .. b3, are negative: the part where a < 0 is one tetrahedron or a prism of three, each
    a known fraction of the whole in a's edge crossings (:func:`_tet_fraction`'s prism; the
    tetrahedron less a corner: t0, (1 - t0) t1, (1 - t0)(1 - t1) t2), and b, linear, is
    interpolated to their corners and taken by :func:`_tet_fraction` in each."""
    fa = (a0, a1, a2, a3)
    fb = (b0, b1, b2, b3)
    neg, i0, i1, j0, j1 = _signs(fa)
    if neg == 0:
        return 0.0
    if neg == 4:
        return _tet_fraction(b0, b1, b2, b3)
    if neg == 1 or neg == 3:
        lone = i0 if neg == 1 else j0
        o0 = (lone + 1) % 4
        o1 = (lone + 2) % 4
        o2 = (lone + 3) % 4
        if neg == 1:
            # the corner tetrahedron at the lone vertex
            t0 = _crossing(fa[lone], fa[o0])
            t1 = _crossing(fa[lone], fa[o1])
            t2 = _crossing(fa[lone], fa[o2])
            g = fb[lone]
            return t0 * t1 * t2 * _tet_fraction(g, g + t0 * (fb[o0] - g), g + t1 * (fb[o1] - g),
                                                 g + t2 * (fb[o2] - g))
        # the prism of the three negative vertices and their crossings toward the lone one
        t0 = _crossing(fa[o0], fa[lone])
        t1 = _crossing(fa[o1], fa[lone])
        t2 = _crossing(fa[o2], fa[lone])
        g0 = fb[o0]
        g1 = fb[o1]
        g2 = fb[o2]
        g3 = g0 + t0 * (fb[lone] - g0)
        g4 = g1 + t1 * (fb[lone] - g1)
        g5 = g2 + t2 * (fb[lone] - g2)
        return (t0 * _tet_fraction(g0, g1, g2, g3)
                + (1.0 - t0) * t1 * _tet_fraction(g1, g2, g3, g4)
                + (1.0 - t0) * (1.0 - t1) * t2 * _tet_fraction(g2, g3, g4, g5))
    s = _crossing(fa[i0], fa[j0])
    u = _crossing(fa[i0], fa[j1])
    v = _crossing(fa[i1], fa[j0])
    w = _crossing(fa[i1], fa[j1])
    g0 = fb[i0]
    g1 = g0 + s * (fb[j0] - g0)
    g2 = g0 + u * (fb[j1] - g0)
    g3 = fb[i1]
    g4 = g3 + v * (fb[j0] - g3)
    g5 = g3 + w * (fb[j1] - g3)
    return (s * u * _tet_fraction(g0, g1, g2, g3)
            + u * v * (1.0 - s) * _tet_fraction(g1, g2, g3, g4)
            + v * w * (1.0 - u) * _tet_fraction(g2, g3, g4, g5))


def cell_fractions_3d(x, y, z, phi_a, phi_b, known=None):
    """Liquid fraction (nx, ny, nz) of every hexahedron of the lattice where phi_a and phi_b
    (nx+1, ny+1, nz+1) are both negative. ``known`` (nx, ny, nz): the fractions with phi_a
    alone (NaN: not known), used where phi_b is negative at all eight corners."""
    if known is None:
        known = np.full((len(x) - 1, len(y) - 1, len(z) - 1), np.nan)
    return _cell_fractions_3d(x, y, z, phi_a, phi_b, known)


@njit(**JIT)
def _cell_fractions_3d(x, y, z, phi_a, phi_b, known):
    nx = x.shape[0] - 1
    ny = y.shape[0] - 1
    nz = z.shape[0] - 1
    out = np.empty((nx, ny, nz))
    ca = np.empty(8)
    cb = np.empty(8)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                inside = 0
                out_a = 0
                out_b = 0
                for c in range(8):
                    di, dj, dk = c & 1, (c >> 1) & 1, (c >> 2) & 1
                    ca[c] = phi_a[i + di, j + dj, k + dk]
                    cb[c] = phi_b[i + di, j + dj, k + dk]
                    if ca[c] < 0.0 and cb[c] < 0.0:
                        inside += 1
                    out_a += ca[c] >= 0.0
                    out_b += cb[c] >= 0.0
                if inside == 8:
                    out[i, j, k] = 1.0
                    continue
                if out_a == 8 or out_b == 8:
                    out[i, j, k] = 0.0
                    continue
                if out_b == 0 and np.isfinite(known[i, j, k]):
                    out[i, j, k] = known[i, j, k]
                    continue
                # the six Kuhn tetrahedra of a box each hold a sixth of it
                frac = 0.0
                for t in range(6):
                    frac += _tet_fraction2(ca[_KUHN[t, 0]], ca[_KUHN[t, 1]], ca[_KUHN[t, 2]],
                                           ca[_KUHN[t, 3]], cb[_KUHN[t, 0]], cb[_KUHN[t, 1]],
                                           cb[_KUHN[t, 2]], cb[_KUHN[t, 3]])
                out[i, j, k] = frac / 6.0
    return out


@njit(**JIT)
def _square_wet(u0, u1, v0, v1, a00, a10, a01, a11, b00, b10, b01, b11):
    """Wetted fraction of the rectangle [u0,u1]x[v0,v1] with corner values of phi_a and
    phi_b (two triangles)."""
    if max(a00, a10, a01, a11) < 0.0 and max(b00, b10, b01, b11) < 0.0:
        return 1.0
    if min(a00, a10, a01, a11) >= 0.0 or min(b00, b10, b01, b11) >= 0.0:
        return 0.0
    px = np.empty(3)
    py = np.empty(3)
    fa = np.empty(3)
    fb = np.empty(3)
    px[0], py[0], fa[0], fb[0] = u0, v0, a00, b00
    px[1], py[1], fa[1], fb[1] = u1, v0, a10, b10
    px[2], py[2], fa[2], fb[2] = u1, v1, a11, b11
    s1, _ = _triangle_wet(px, py, fa, fb)
    px[1], py[1], fa[1], fb[1] = u0, v1, a01, b01
    s2, _ = _triangle_wet(px, py, fa, fb)
    return (s1 + s2) / ((u1 - u0) * (v1 - v0))


def face_fractions_3d(x, y, z, phi_a, phi_b, known=None):
    """Wetted fractions of the faces normal to x (nx+1, ny, nz), y (nx, ny+1, nz) and
    z (nx, ny, nz+1). ``known``: the three arrays with phi_a alone (NaN: not known), used
    where phi_b is negative at all four corners."""
    nx, ny, nz = len(x) - 1, len(y) - 1, len(z) - 1
    if known is None:
        known = tuple(np.full(shape, np.nan) for shape in
                      ((nx + 1, ny, nz), (nx, ny + 1, nz), (nx, ny, nz + 1)))
    return _face_fractions_3d(x, y, z, phi_a, phi_b, known[0], known[1], known[2])


@njit(**JIT, inline="always")
def _face_wet(known, u0, u1, v0, v1, a00, a10, a01, a11, b00, b10, b01, b11):
    if max(b00, b10, b01, b11) < 0.0 and np.isfinite(known):
        return known
    return _square_wet(u0, u1, v0, v1, a00, a10, a01, a11, b00, b10, b01, b11)


@njit(**JIT)
def _face_fractions_3d(x, y, z, phi_a, phi_b, kx, ky, kz):
    nx = x.shape[0] - 1
    ny = y.shape[0] - 1
    nz = z.shape[0] - 1
    fx = np.empty((nx + 1, ny, nz))
    fy = np.empty((nx, ny + 1, nz))
    fz = np.empty((nx, ny, nz + 1))
    A = phi_a
    B = phi_b
    for i in range(nx + 1):
        for j in range(ny):
            for k in range(nz):
                fx[i, j, k] = _face_wet(
                    kx[i, j, k], y[j], y[j + 1], z[k], z[k + 1],
                    A[i, j, k], A[i, j + 1, k], A[i, j, k + 1], A[i, j + 1, k + 1],
                    B[i, j, k], B[i, j + 1, k], B[i, j, k + 1], B[i, j + 1, k + 1])
    for i in range(nx):
        for j in range(ny + 1):
            for k in range(nz):
                fy[i, j, k] = _face_wet(
                    ky[i, j, k], x[i], x[i + 1], z[k], z[k + 1],
                    A[i, j, k], A[i + 1, j, k], A[i, j, k + 1], A[i + 1, j, k + 1],
                    B[i, j, k], B[i + 1, j, k], B[i, j, k + 1], B[i + 1, j, k + 1])
    for i in range(nx):
        for j in range(ny):
            for k in range(nz + 1):
                fz[i, j, k] = _face_wet(
                    kz[i, j, k], x[i], x[i + 1], y[j], y[j + 1],
                    A[i, j, k], A[i + 1, j, k], A[i, j + 1, k], A[i + 1, j + 1, k],
                    B[i, j, k], B[i + 1, j, k], B[i, j + 1, k], B[i + 1, j + 1, k])
    return fx, fy, fz
