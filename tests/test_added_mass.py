"""The added-mass model problem of Causin, Gerbeau & Nobile (2005), "Added-mass effect in the
design of partitioned algorithms for fluid-structure problems", CMAME 194, 4506-4527, driven
through the coupling library (cases/added_mass.py).

An elastic wall (mass per area rho_s h, kg/m^2; stiffness k, Pa/m) on an inviscid incompressible
channel whose added-mass eigenvalues are mu_i = L / (i pi tanh(i pi R / L)) (m). Checks:
Gauss-Seidel with constant relaxation converges up to omega_max = 2 rho_s h / (rho_s h +
rho_f mu_max) (measured within 10 %); the explicit scheme (backward Euler, lagged pressure)
diverges iff q = rho_f mu_max / (rho_s h) > 1 + k dt^2 / (4 rho_s h); Aitken and IQN-ILS converge
at the largest mass ratio, to the monolithic solution.
"""
import numpy as np
import pytest

from cases import added_mass as am

PROBLEM = am.Problem()


def test_added_mass_eigenvalues_and_mass_ratio():
    p = PROBLEM
    assert p.mu[0] == pytest.approx(p.length / (np.pi * np.tanh(np.pi * p.height / p.length)))
    assert np.all(np.diff(p.mu) < 0)  # mu_max = mu_1
    for q in (0.1, 10.0, 100.0):
        assert p.with_mass_ratio(q).mass_ratio == pytest.approx(q)
        # the theory's inertia-dominated assumption holds on the whole map
        assert p.with_mass_ratio(q).beta < 1e-3


@pytest.mark.parametrize("q", [0.5, 5.0, 50.0])
def test_largest_stable_constant_omega_matches_causin_bound(q):
    p = PROBLEM.with_mass_ratio(q)
    measured = am.largest_stable_omega(p, n_windows=1, max_iterations=300, rel_width=3e-3)
    assert measured == pytest.approx(p.omega_max, rel=0.10)
    assert measured < p.omega_max * (1 + 1e-3)  # never above the bound (finite iterations)
    # just above the bound it must fail, well below it converge
    assert not am.constant_converges(p, 1.02 * p.omega_max, n_windows=1, max_iterations=300)
    assert am.constant_converges(p, 0.8 * p.omega_max, n_windows=1, max_iterations=300)


@pytest.mark.parametrize("q,diverges", [(0.5, False), (0.95, False), (1.05, True),
                                        (3.0, True), (100.0, True)])
def test_explicit_scheme_diverges_above_its_bound_only(q, diverges):
    p = PROBLEM.with_mass_ratio(q)
    assert (p.mass_ratio > p.explicit_critical_mass_ratio) == diverges  # theory
    e = am.explicit_run(p, n_windows=600)
    assert e["diverged"] == diverges
    if diverges:  # the measured growth per window is the parasitic root -q
        assert e["growth_per_window"] == pytest.approx(p.explicit_spectral_radius, rel=1e-3)


@pytest.mark.parametrize("acceleration", ["aitken", "iqn-ils"])
def test_aitken_and_iqn_ils_converge_at_the_largest_mass_ratio(acceleration):
    p = PROBLEM.with_mass_ratio(100.0)
    assert not am.constant_converges(p, 1.0)  # plain Gauss-Seidel diverges here
    r = am.accelerated_run(p, acceleration, n_windows=10, max_iterations=100)
    assert r["converged"]
    assert r["error_vs_monolithic"] < 1e-8  # relative to the initial amplitude
