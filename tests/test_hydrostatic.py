"""Hydrostatic liquid: p = p_ref + rho b . x (thesis Eqn 4.5 for b = (0, 0, -g))."""
import numpy as np
import pytest

from fluid.hydrostatic import HydrostaticLiquid


def test_upright_matches_thesis_eqn_4_5():
    liq = HydrostaticLiquid(1000.0, (0.0, 0.0, -9.81))
    z = np.linspace(-0.2, 0.2, 9)
    pts = np.stack([np.full_like(z, 0.05), np.full_like(z, -0.03), z], axis=1)
    h = 0.07
    p = liq.pressure(pts, liq.reference_pressure(h))
    assert np.allclose(p, 1000.0 * 9.81 * (h - z), rtol=1e-14, atol=1e-12)
    assert liq.equivalent_height(liq.reference_pressure(h)) == pytest.approx(h, rel=1e-14)


def test_lateral_and_tilted_acceleration():
    b = np.array([3.0, 0.0, -9.81])
    liq = HydrostaticLiquid(800.0, tuple(b))
    pts = np.random.default_rng(1).uniform(-0.2, 0.2, (50, 3))
    p = liq.pressure(pts, 10.0)
    assert np.allclose(p, 10.0 + 800.0 * pts @ b)
    # the gradient is rho b: pressure difference between two points
    assert p[1] - p[0] == pytest.approx(800.0 * (pts[1] - pts[0]) @ b, rel=1e-12)


def test_zero_g_is_uniform_and_height_undefined():
    liq = HydrostaticLiquid(1000.0, (0.0, 0.0, 0.0))
    p = liq.pressure(np.random.default_rng(2).normal(size=(10, 3)), 123.0)
    assert np.all(p == 123.0)
    assert np.isnan(liq.equivalent_height(123.0))


@pytest.mark.parametrize("kw", [dict(density=0.0, body_acceleration=(0, 0, -9.81)),
                                dict(density=1000.0, body_acceleration=(0, 0)),
                                dict(density=1000.0, body_acceleration=(0, np.nan, 0))])
def test_bad_input_raises(kw):
    with pytest.raises(ValueError):
        HydrostaticLiquid(**kw)
