"""Liquid volume (divergence theorem, App. J's sum) against an independent Monte-Carlo count."""
import matplotlib.tri as mtri
import numpy as np
import pytest

from fsi.constants import TANK_RADIUS as R
from structure.grid import triangles_from_quads
from structure.model import hemisphere_model
from structure.kernels import project_volume_masked
from structure.volume import (FillScale, liquid_volume, liquid_volume_gradient,
                              lower_hemisphere_volume, mirrored_rest_position)


def _graph_membrane(model, depth):
    """Membrane as the graph z = -depth * sqrt(R^2 - r^2) over the rest (x, y) (a shallower cap)."""
    p = model.node_rest_position.copy()
    r2 = np.sum(p[:, :2] ** 2, axis=1)
    p[:, 2] = -depth * np.sqrt(np.clip(R**2 - r2, 0.0, None))
    return p


def _monte_carlo_volume(model, pos, n_samples, seed):
    """Points in the tank are liquid if below the faceted membrane (linear on its triangles);
    outside the membrane footprint, if below the equator plane. Returns (volume, std error)."""
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-R, R, (n_samples, 3))
    pts = pts[np.sum(pts**2, axis=1) < R**2]
    tri = mtri.Triangulation(pos[:, 0], pos[:, 1], triangles_from_quads(model.face_nodes))
    zm = mtri.LinearTriInterpolator(tri, pos[:, 2])(pts[:, 0], pts[:, 1])
    below = np.where(np.ma.getmaskarray(zm), pts[:, 2] < 0.0, pts[:, 2] < np.ma.filled(zm, 0.0))
    frac = below.mean()
    ball = 4.0 / 3.0 * np.pi * R**3
    return frac * ball, ball * np.sqrt(frac * (1 - frac) / len(pts))


@pytest.mark.parametrize("depth", [0.9, 0.3, -0.5])
def test_volume_matches_monte_carlo(thesis_material, depth):
    model = hemisphere_model(26, R, thesis_material)
    pos = _graph_membrane(model, depth)
    v = liquid_volume(model, pos)
    v_mc, se = _monte_carlo_volume(model, pos, 2_000_000, seed=7)
    assert abs(v - v_mc) < 4 * se + 1e-3 * v_mc


def test_rest_is_empty_and_mirror_is_full(model26):
    ball = 4.0 / 3.0 * np.pi * R**3
    assert liquid_volume(model26, model26.node_rest_position) == pytest.approx(0.0, abs=5e-3 * ball)
    assert liquid_volume(model26, mirrored_rest_position(model26)) == pytest.approx(ball, rel=5e-3)
    scale = FillScale.mirrored(model26)
    assert scale.fill(scale.volume(0.37)) == pytest.approx(0.37, rel=1e-12)


def test_gradient_matches_finite_differences(model10):
    pos = _graph_membrane(model10, 0.4)
    pos += np.random.default_rng(3).normal(scale=1e-3, size=pos.shape)
    g = liquid_volume_gradient(model10, pos)
    eps = 1e-7
    for k in (11, 45, 57):
        for c in range(3):
            p1, p2 = pos.copy(), pos.copy()
            p1[k, c] += eps
            p2[k, c] -= eps
            fd = (liquid_volume(model10, p1) - liquid_volume(model10, p2)) / (2 * eps)
            assert g[k, c] == pytest.approx(fd, rel=1e-6, abs=1e-12)


def test_projection_hits_target_and_keeps_fixed_nodes(model10):
    pos = _graph_membrane(model10, 0.4)
    target = liquid_volume(model10, pos) * 1.02
    before = pos.copy()
    movable = ~model10.node_fixed
    project_volume_masked(pos, model10.node_inv_mass, movable, model10.face_nodes,
                          model10.volume_sign, lower_hemisphere_volume(R), target, 4,
                          np.full(model10.n_nodes, np.inf))
    assert liquid_volume(model10, pos) == pytest.approx(target, rel=1e-12)
    assert np.array_equal(pos[model10.node_fixed], before[model10.node_fixed])
