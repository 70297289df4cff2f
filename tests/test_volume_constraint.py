"""The incompressibility dilemma (Kuettler, Foerster & Wall 2006) on a liquid column with
prescribed inflow closed by an elastic lid: the volume constraint on the structure side makes
plain Gauss-Seidel converge where it diverges without it (cases/volume_constraint.py)."""
import numpy as np
import pytest

from cases import volume_constraint as vc


def test_constrained_lid_returns_the_level_of_the_monolithic_solution():
    log, err, data = vc.couple(constrained=True, bulk_modulus=None, n_windows=3, dt=0.1)
    assert err == "" and all(w.converged for w in log.windows)
    assert max(w.iterations for w in log.windows) <= 15  # plain Gauss-Seidel, omega = 1
    lid, column = vc.Lid(), vc.Column()
    w_ref, level_ref = vc.monolithic(lid, column, 0.2, 0.1)
    assert data["pressure_level"][0] == pytest.approx(level_ref, rel=1e-9)
    assert np.allclose(data["displacement"], w_ref, rtol=1e-8, atol=1e-12)
    assert lid.h * data["displacement"].sum() == pytest.approx(column.target(0.2, 0.1), rel=1e-12)


@pytest.mark.parametrize("bulk", [1e5, vc.WATER_BULK_MODULUS])
def test_without_constraint_relaxed_gauss_seidel_diverges(bulk):
    log, err, _ = vc.couple(constrained=False, bulk_modulus=bulk, acceleration="constant",
                            relaxation=0.5, n_windows=1)
    assert log is None and "not converged" in err


def test_without_constraint_aitken_fails_at_water_stiffness():
    log, err, _ = vc.couple(constrained=False, bulk_modulus=vc.WATER_BULK_MODULUS,
                            acceleration="aitken", relaxation=0.5, n_windows=3)
    assert log is None and "not converged" in err
