"""Structured membrane grids: the thesis hemisphere (App. C) and a flat disc.

Both grids are ``N x N`` structured grids stored row-major: node ``(i, j)`` has flat index
``i * N + j``. Row index ``i`` is the thesis's first MATLAB index, column ``j`` its second.

The hemisphere follows Levine (2014) App. C: a gnomonic projection of one cube face onto the
sphere with the parameter range limited to ``+-pi/2.01``, then the "spiral" azimuthal angle
equalisation that rotates each turn of a spiral through the grid towards evenly spaced
azimuths.  Two things are added and documented here:

* the thesis limit ``pi/2.01`` leaves the outer ring up to ``R/128`` above the equator; the
  outer ring is moved radially onto the equator (``z = 0``, ``|x| = R``) so that the clamped rim
  is where the tank clamps it;
* the surface is mirrored to the lower hemisphere (the thesis driver's ``Z = -Z``).

A :class:`Grading` moves the App. C nodes along their meridians so that a band of the meridian
holds more of them (the fold band the shell of revolution predicts; docs/notes/graded-grid.md):
the grid keeps its N x N topology, its azimuths and its rim.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

THESIS_PARAMETER_LIMIT = np.pi / 2.01
"""Gnomonic parameter range of App. C (rad): the cube face spans ``[-pi/2.01, pi/2.01]``."""


GRADING_EDGE = 0.02
"""Width (fraction of the meridian) over which a :class:`Grading`'s node density passes from
the outside's to the band's, a tanh edge. Measured with density 3 in the band 0.6-0.85:
neighbouring rings differ in spacing by up to 2.1x at N = 38 and 1.6x at N = 76 (App. C's own
grid: 1.13x and 1.21x), where a jump would be the density ratio, 3x."""


@dataclass(frozen=True)
class Grading:
    """Node density along the meridian: ``density`` times as many rings per unit of meridian
    inside ``band`` as outside it.

    Attributes
    ----------
    band : (start, stop), fractions of the rest meridian's arc from the pole (0) to the rim
        (1), 0 <= start < stop <= 1.
    density : >= 1 (-); 1 is the App. C grid unchanged.
    """

    band: tuple[float, float] = (0.0, 1.0)
    density: float = 1.0

    def __post_init__(self):
        start, stop = (float(v) for v in self.band)
        if not 0.0 <= start < stop <= 1.0:
            raise ValueError(f"grading band must be 0 <= start < stop <= 1 (fractions of the "
                             f"meridian from the pole), got {self.band!r}")
        if not (np.isfinite(self.density) and self.density >= 1.0):
            raise ValueError(f"grading density must be >= 1, got {self.density!r}")

    @property
    def uniform(self) -> bool:
        """Whether the grid is App. C's unchanged."""
        return self.density == 1.0

    def fraction(self, app_c_fraction: np.ndarray) -> np.ndarray:
        """The graded meridian fraction (0 pole, 1 rim) of nodes at ``app_c_fraction`` of
        the App. C grid: the inverse of the cumulative node density, normalised to 1."""
        s = np.linspace(0.0, 1.0, 20001)
        start, stop = self.band
        weight = 0.5 * (np.tanh((s - start) / GRADING_EDGE) - np.tanh((s - stop) / GRADING_EDGE))
        density = 1.0 + (self.density - 1.0) * weight
        cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]))])
        return np.interp(app_c_fraction, cumulative / cumulative[-1], s)


def _check_grid_size(grid_size: int) -> None:
    if not isinstance(grid_size, (int, np.integer)) or grid_size < 4 or grid_size % 2:
        raise ValueError(f"grid_size must be an even integer >= 4, got {grid_size!r}")


def _gnomonic_cube_face(grid_size: int, radius: float):
    """App. C projection: returns X, Y, Z (N, N) on the *upper* hemisphere (m)."""
    s = np.linspace(-THESIS_PARAMETER_LIMIT, THESIS_PARAMETER_LIMIT, grid_size)
    aa = radius * np.sqrt(3.0) / 3.0
    xa = aa * np.tan(s)[:, None] * np.ones((1, grid_size))  # varies with row i (outer loop)
    ya = aa * np.tan(s)[None, :] * np.ones((grid_size, 1))  # varies with column j
    ra = np.sqrt(aa**2 + xa**2 + ya**2)
    X = radius * ya / ra
    Y = radius * xa / ra
    Z = radius * aa / ra
    return X, Y, Z


def _spiral_order(grid_size: int) -> np.ndarray:
    """App. C spiral through the grid: (k, 2) array of 0-based (i, j), in visiting order."""
    i = round(grid_size / 2)  # MATLAB round(N/2), 1-based
    j = i + 1
    order = [(i, j)]
    j -= 1
    order.append((i, j))
    b = 0
    n_stop = grid_size**2 - 2 * grid_size

    def walk(di, dj, count):
        nonlocal i, j
        for _ in range(count):
            i += di
            j += dj
            order.append((i, j))

    while len(order) < n_stop:
        b += 1
        walk(1, 0, b)
        b += 1
        walk(0, 1, b)
        b -= 1
        walk(-1, 0, b + 1)
        b += 1
        walk(0, -1, b + 1)
    b += 1
    walk(1, 0, b)
    walk(0, 1, b)
    return np.asarray(order, dtype=np.int64) - 1


def _azimuth_degrees(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Azimuth in [0, 360) degrees, as App. C's quadrant-wise ``atand``."""
    return np.mod(np.degrees(np.arctan2(Y, X)), 360.0)


def _spiral_equalise(X, Y, Z, radius):
    """App. C angle equalisation along the spiral; returns new X, Y (Z unchanged)."""
    grid_size = X.shape[0]
    order = _spiral_order(grid_size)
    ki, kj = order[:, 0], order[:, 1]
    beta = _azimuth_degrees(X, Y)
    x_sp = X[ki, kj].copy()
    y_sp = Y[ki, kj].copy()
    z_sp = Z[ki, kj]
    # spiral turns ("arcs"): lengths 6, 14, 22, ... (1-based [c, d] in App. C)
    arcs = []
    a, b, c = -1, 0, 1
    for _ in range(grid_size // 2):
        a += 2
        b += 2
        d = a * 2 + b * 2 + c - 1
        arcs.append((c - 1, d))  # 0-based half-open
        c = d + 1

    def rotate(sl, change_deg):
        cs, sn = np.cos(np.radians(change_deg)), np.sin(np.radians(change_deg))
        xo, yo = X[ki[sl], kj[sl]], Y[ki[sl], kj[sl]]
        x_sp[sl] = xo * cs - yo * sn
        y_sp[sl] = xo * sn + yo * cs

    for start, stop in arcs[:-1]:
        sl = slice(start, stop)
        angle = beta[ki[sl], kj[sl]]
        n = angle.size
        required = 360.0 - 360.0 / n * np.arange(n)
        g = 0
        for m in range(n - 1):
            if angle[m] < angle[m + 1]:
                g = m + 1  # MATLAB's 1-based index of the wrap
        ordered = np.concatenate([required[n - g:], required[: n - g]])
        rotate(sl, (ordered - angle) * (radius - z_sp[sl]) / radius)
    # last arm: three quarters of a turn, full correction
    sl = slice(arcs[-1][0], order.shape[0])
    angle = beta[ki[sl], kj[sl]]
    n = angle.size
    required = 315.0 - 270.0 / n * np.arange(n)
    rotate(sl, required - angle)
    X, Y = X.copy(), Y.copy()
    X[ki, kj] = x_sp
    Y[ki, kj] = y_sp
    return X, Y


def hemisphere_grid(grid_size: int, radius: float,
                    grading: Grading = Grading()) -> np.ndarray:
    """Lower-hemisphere grid of App. C with the rim ring on the equator.

    Parameters
    ----------
    grid_size : even int >= 4, nodes per grid side (thesis ``GridSize``).
    radius : sphere radius (m).
    grading : each node's polar angle moved along its meridian by :class:`Grading` (the
        default leaves App. C's grid bit for bit).

    Returns
    -------
    node_position : (N*N, 3) float64, m. Every node lies on the sphere ``|x| = radius``;
        the outer ring lies on the equator ``z = 0``; the pole is at ``z = -radius``.
    """
    _check_grid_size(grid_size)
    if not radius > 0:
        raise ValueError(f"radius must be > 0 m, got {radius!r}")
    X, Y, Z = _gnomonic_cube_face(grid_size, radius)
    X, Y = _spiral_equalise(X, Y, Z, radius)
    Z = -Z  # thesis driver: rest shape is the lower hemisphere
    node_position = np.stack([X, Y, Z], axis=-1).reshape(-1, 3)
    rim = boundary_ring(grid_size, 0)
    if not grading.uniform:
        inner = np.setdiff1d(np.arange(grid_size * grid_size), rim)
        node_position[inner] = _graded(node_position[inner], radius, grading)
    xy = node_position[rim, :2]
    node_position[rim, :2] = radius * xy / np.linalg.norm(xy, axis=1)[:, None]
    node_position[rim, 2] = 0.0
    # renormalise (rotation about z keeps |x| to round-off; make it exact to 1e-16 R)
    node_position *= radius / np.linalg.norm(node_position, axis=1)[:, None]
    return node_position


def _graded(node_position: np.ndarray, radius: float, grading: Grading) -> np.ndarray:
    """``node_position`` (n, 3) m on the lower hemisphere, each node's polar angle from the
    pole mapped by ``grading`` at its azimuth and radius."""
    unit = node_position / np.linalg.norm(node_position, axis=1)[:, None]
    polar = np.arccos(np.clip(-unit[:, 2], -1.0, 1.0))
    azimuth = np.arctan2(unit[:, 1], unit[:, 0])
    graded = 0.5 * np.pi * grading.fraction(polar / (0.5 * np.pi))
    return radius * np.stack([np.sin(graded) * np.cos(azimuth),
                              np.sin(graded) * np.sin(azimuth), -np.cos(graded)], axis=1)


def disc_grid(grid_size: int, radius: float, grading: Grading = Grading()) -> np.ndarray:
    """Flat disc grid of radius ``radius`` (m) in the plane z = 0, same topology as the hemisphere.

    The hemisphere grid (graded by ``grading``, its band then a band of r / radius) is
    unrolled by the azimuthal equidistant map ``r = radius * theta / (pi/2)`` (``theta`` the
    polar angle from the pole), which keeps node spacing nearly uniform.
    Returns ``node_position`` (N*N, 3) float64, m; the outer ring lies on ``r = radius``.
    """
    sphere = hemisphere_grid(grid_size, 1.0, grading)
    theta = np.arccos(np.clip(-sphere[:, 2], -1.0, 1.0))
    phi = np.arctan2(sphere[:, 1], sphere[:, 0])
    r = radius * theta / (np.pi / 2)
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.zeros_like(r)], axis=1)


def boundary_ring(grid_size: int, depth: int) -> np.ndarray:
    """Flat indices of the square ring ``depth`` nodes in from the grid border (0 = outer ring)."""
    idx = np.arange(grid_size * grid_size).reshape(grid_size, grid_size)
    lo, hi = depth, grid_size - 1 - depth
    ring = np.zeros((grid_size, grid_size), dtype=bool)
    ring[lo, lo:hi + 1] = ring[hi, lo:hi + 1] = True
    ring[lo:hi + 1, lo] = ring[lo:hi + 1, hi] = True
    inner = np.zeros_like(ring)
    inner[lo + 1:hi, lo + 1:hi] = True
    return idx[ring & ~inner]


def quad_faces(grid_size: int) -> np.ndarray:
    """Quad faces of the structured grid, (n_faces, 4) int64, corners (i,j),(i,j+1),(i+1,j+1),(i+1,j)."""
    i, j = np.meshgrid(np.arange(grid_size - 1), np.arange(grid_size - 1), indexing="ij")
    a = (i * grid_size + j).ravel()
    return np.stack([a, a + 1, a + grid_size + 1, a + grid_size], axis=1)


def triangles_from_quads(face_nodes: np.ndarray) -> np.ndarray:
    """Split quads along their (i,j)-(i+1,j+1) diagonal, as App. D does: (2 n_faces, 3) int64."""
    q = np.asarray(face_nodes)
    return np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]], axis=0)


def triangle_edges(triangles: np.ndarray) -> np.ndarray:
    """(e, 2) int64: the triangles' (m, 3) edges, each once, its nodes sorted."""
    t = np.asarray(triangles, dtype=np.int64)
    return np.unique(np.sort(np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1),
                     axis=0)


@dataclass(frozen=True)
class GridQuality:
    """Quad-grid quality metrics (dimensionless).

    aspect_ratio_max : largest ratio of a quad's longest to shortest edge.
    skewness_max : largest equiangle skewness, max((a_max - 90)/90, (90 - a_min)/90), a in degrees.
    smoothness_max : largest area ratio between edge-adjacent quads (>= 1).
    """

    aspect_ratio_max: float
    skewness_max: float
    smoothness_max: float


def grid_quality(node_position: np.ndarray, grid_size: int) -> GridQuality:
    """Quality metrics of a structured quad grid (see :class:`GridQuality`)."""
    q = quad_faces(grid_size)
    p = node_position[q]  # (f, 4, 3)
    edges = np.roll(p, -1, axis=1) - p
    length = np.linalg.norm(edges, axis=2)
    aspect = length.max(axis=1) / length.min(axis=1)
    e_in = -np.roll(edges, 1, axis=1)
    cosang = np.sum(edges * e_in, axis=2) / (length * np.roll(length, 1, axis=1))
    ang = np.degrees(np.arccos(np.clip(cosang, -1, 1)))
    skew = np.maximum((ang.max(axis=1) - 90) / 90, (90 - ang.min(axis=1)) / 90)
    area = 0.5 * (np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
                  + np.linalg.norm(np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]), axis=1))
    a = area.reshape(grid_size - 1, grid_size - 1)
    ratios = np.concatenate([(a[1:, :] / a[:-1, :]).ravel(), (a[:, 1:] / a[:, :-1]).ravel()])
    smooth = np.maximum(ratios, 1 / ratios).max()
    return GridQuality(float(aspect.max()), float(skew.max()), float(smooth))
