"""Grid checks: App. C hemisphere and the flat disc (Levine 2014, App. C)."""
import numpy as np
import pytest

from fsi.constants import TANK_RADIUS as R
from structure.grid import (boundary_ring, disc_grid, grid_quality, hemisphere_grid,
                            quad_faces)


@pytest.mark.parametrize("n", [4, 6, 10, 26, 40])
def test_every_node_on_sphere_and_rim_on_equator(n):
    p = hemisphere_grid(n, R)
    assert p.shape == (n * n, 3)
    assert np.max(np.abs(np.linalg.norm(p, axis=1) - R)) <= 1e-12 * R
    rim = boundary_ring(n, 0)
    assert len(rim) == 4 * (n - 1)
    assert np.max(np.abs(p[rim, 2])) <= 1e-12 * R
    inner = np.setdiff1d(np.arange(n * n), rim)
    assert np.all(p[inner, 2] < 0.0), "rest shape is the lower hemisphere"
    # the pole is reached: the lowest node is within one cell of -R
    assert p[:, 2].min() < -R * np.cos(np.pi / n)


@pytest.mark.parametrize("n", [10, 26, 40])
def test_grid_quality_bounded(n):
    q = grid_quality(hemisphere_grid(n, R), n)
    # the gnomonic cube-face corners flatten onto the equator: skewness approaches but stays below 1
    assert q.aspect_ratio_max < 3.0
    assert q.skewness_max < 0.98
    assert q.smoothness_max < 2.0


def test_quads_do_not_fold():
    n = 26
    p = hemisphere_grid(n, R)
    q = quad_faces(n)
    normal = np.cross(p[q[:, 1]] - p[q[:, 0]], p[q[:, 3]] - p[q[:, 0]])
    centroid = p[q].mean(axis=1)
    # every quad is oriented the same way relative to the outward radial direction
    s = np.sign(np.sum(normal * centroid, axis=1))
    assert np.all(s == s[0])


@pytest.mark.parametrize("n", [3, 5, 2, 0])
def test_bad_grid_size_raises(n):
    with pytest.raises(ValueError, match="grid_size"):
        hemisphere_grid(n, R)


def test_disc_grid_is_flat_with_rim_on_circle():
    n, a = 14, 0.1
    p = disc_grid(n, a)
    assert np.all(p[:, 2] == 0.0)
    rim = boundary_ring(n, 0)
    assert np.allclose(np.linalg.norm(p[rim, :2], axis=1), a, rtol=1e-12)
    assert np.linalg.norm(p[:, :2], axis=1).max() <= a * (1 + 1e-12)


def _ring_polar_fractions(p: np.ndarray, n: int) -> np.ndarray:
    """Mean polar angle of each square ring over pi/2, rim (ring 0) first."""
    return np.array([np.mean(np.arccos(-p[boundary_ring(n, d), 2] / R)) / (np.pi / 2)
                     for d in range(n // 2)])


def test_a_graded_grid_puts_density_times_the_rings_in_its_band_and_keeps_app_c_elsewhere():
    """The default Grading is App. C bit for bit. A band of density 3 holds about three
    times the rings per unit of meridian of the rest of the grid (the tanh edges take a
    little); every node stays on the sphere, the rim on the equator, no quad folds, and a
    node keeps its azimuth."""
    from structure.grid import Grading

    n = 38
    app_c = hemisphere_grid(n, R)
    assert np.array_equal(hemisphere_grid(n, R, Grading()), app_c)
    band = (0.55, 0.85)
    graded = hemisphere_grid(n, R, Grading(band, 3.0))
    assert np.max(np.abs(np.linalg.norm(graded, axis=1) - R)) <= 1e-12 * R
    rim = boundary_ring(n, 0)
    assert np.array_equal(graded[rim], app_c[rim])
    inner = np.setdiff1d(np.arange(n * n), rim)
    azimuth = np.arctan2(graded[inner, 1], graded[inner, 0])
    assert np.allclose(azimuth, np.arctan2(app_c[inner, 1], app_c[inner, 0]), atol=1e-12)
    s = _ring_polar_fractions(graded, n)
    spacing = -np.diff(s) / -np.diff(_ring_polar_fractions(app_c, n))  # graded over App. C's
    inside = ((s > band[0] + 0.05) & (s < band[1] - 0.05))[:-1]
    outside = ((s < band[0] - 0.1) & (s > 0.2))[:-1]
    assert 2.5 < np.mean(spacing[outside]) / np.mean(spacing[inside]) < 3.3
    q = quad_faces(n)
    normal = np.cross(graded[q[:, 1]] - graded[q[:, 0]], graded[q[:, 3]] - graded[q[:, 0]])
    orientation = np.sign(np.sum(normal * graded[q].mean(axis=1), axis=1))
    assert np.all(orientation == orientation[0])


@pytest.mark.parametrize("band, density, match", [((0.5, 0.5), 2.0, "band"),
                                                  ((-0.1, 0.5), 2.0, "band"),
                                                  ((0.2, 0.5), 0.5, "density")])
def test_a_bad_grading_is_refused_by_name(band, density, match):
    from structure.grid import Grading

    with pytest.raises(ValueError, match=match):
        Grading(band, density)
