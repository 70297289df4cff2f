"""The implicit generalised-alpha dynamics (structure.newton.dynamics) on the two flat-sheet
oracles, in time:

* the pre-tensioned circular membrane released from its fundamental mode: the period against
  the closed form omega = (2.4048 / a) sqrt(S / rho) within 1 % at N = 38 (a step of a fortieth
  of the period), and against the grid's own eigenfrequency at second order in the step
  (the trapezoidal rule's period error (omega dt)^2 / 12; e.g. Hughes, *The Finite Element
  Method*, 2000, sec. 9.3);
* the clamped circular plate's fundamental, lambda^2 = 10.2158 (Leissa 1969), within 1 % at
  N = 38;
* rho_inf < 1 damps a mode the step does not resolve and rho_inf = 1 keeps it.

References and the setups as in tests/test_vibration_oracles.py.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from fsi.constants import MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, \
    TANK_RADIUS
from structure.load import Load
from structure.model import Material, disc_model
from structure.newton.dynamics import AlphaSettings, AlphaState, step
from structure.newton.system import NewtonModel
from structure.plate import FlatDiaphragm, ShellDisc
from structure.tangent import Tangent
from structure.tangent.bending import BendingTerm
from structure.tangent.membrane import MembraneTerm

POISSON = 0.3
PLATE = FlatDiaphragm(TANK_RADIUS, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS, POISSON)
STRETCH = 1.01
J0_FIRST_ZERO = 2.404826
CLAMPED_PLATE_LAMBDA2 = 10.2158


def _sheet(grid_size: int, bending: bool):
    """(model, stretched or flat start (n, 3), discrete omega, its mode (n,), centre node)."""
    disc = ShellDisc.build(PLATE, grid_size)
    base = disc_model(grid_size, PLATE.radius, Material(
        PLATE.thickness, MEMBRANE_DENSITY, PLATE.youngs_modulus, POISSON), "simply-supported")
    terms = [MembraneTerm.from_triangle_membrane(disc.membrane, disc.law)]
    if bending:
        terms.append(BendingTerm(disc.bending))
    stretch = 1.0 if bending else STRETCH
    x = base.node_rest_position * np.array([stretch, stretch, 1.0])
    matrix = Tangent.build(len(x), terms).evaluate(x)[2]
    z = np.repeat(~base.node_fixed, 3) & (np.arange(3 * len(x)) % 3 == 2)
    values, vectors = eigsh(sp.csr_matrix(matrix)[z][:, z].tocsc(), k=1,
                            M=sp.diags(base.node_mass[~base.node_fixed]), sigma=0.0)
    mode = np.zeros(len(x))
    mode[~base.node_fixed] = vectors[:, 0] / np.abs(vectors[:, 0]).max()
    return NewtonModel.build(base, terms, "follower"), x, float(np.sqrt(values[0])), mode, \
        disc.centre


def _period(model, x, mode, centre, period_guess, steps_per_period, periods=2.0,
            rho_inf=1.0, amplitude=1e-4):
    """The period (s) of the centre's free oscillation released from ``mode`` and the ratio
    of its last to its first swing."""
    dt = period_guess / steps_per_period
    start = x.copy()
    start[:, 2] += amplitude * PLATE.radius * mode
    state = AlphaState(start, np.zeros_like(start))
    load = Load(np.zeros(len(x)), np.zeros(3), None, 0.0, None)
    z = [start[centre, 2]]
    for _ in range(int(round(periods * steps_per_period))):
        state, _ = step(model, state, load, dt, AlphaSettings(rho_inf=rho_inf))
        z.append(state.node_position[centre, 2])
    z = np.asarray(z)
    t = dt * np.arange(len(z))
    k = np.flatnonzero(np.sign(z[:-1]) != np.sign(z[1:]))
    crossings = t[k] - z[k] * dt / (z[k + 1] - z[k])
    return 2.0 * float(np.mean(np.diff(crossings))), abs(z[-1]) / abs(z[0])


def test_membrane_period_is_second_order_in_the_step():
    model, x, omega, mode, centre = _sheet(26, bending=False)
    period = 2 * np.pi / omega
    errors = [abs(_period(model, x, mode, centre, period, n)[0] / period - 1)
              for n in (20, 40)]
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1)
    # the trapezoidal rule's period elongation, (omega dt)^2 / 12
    assert errors[0] == pytest.approx((2 * np.pi / 20) ** 2 / 12, rel=0.05)


def test_membrane_free_vibration_matches_the_closed_form():
    model, x, omega, mode, centre = _sheet(38, bending=False)
    s = PLATE.youngs_modulus * (STRETCH**2 - 1) / (2 * (1 - POISSON))
    exact = J0_FIRST_ZERO / PLATE.radius * np.sqrt(s / MEMBRANE_DENSITY)
    period, _ = _period(model, x, mode, centre, 2 * np.pi / exact, 40)
    assert 2 * np.pi / period == pytest.approx(exact, rel=0.01)


def test_clamped_plate_free_vibration_matches_leissa():
    model, x, omega, mode, centre = _sheet(38, bending=True)
    period, _ = _period(model, x, mode, centre, 2 * np.pi / omega, 60, periods=1.25)
    scale = PLATE.radius**2 * np.sqrt(MEMBRANE_DENSITY * PLATE.thickness
                                      / PLATE.flexural_rigidity)
    assert 2 * np.pi / period * scale == pytest.approx(CLAMPED_PLATE_LAMBDA2, rel=0.01)


def _modal_energy_ratio(rho_inf: float, steps_per_period: float, periods: float) -> float:
    """The fundamental's energy 1/2 m (v^2 + omega^2 z^2) (the motion stays in the mode: a
    linear problem) after ``periods`` over its start, N = 14 membrane."""
    model, x, omega, mode, centre = _sheet(14, bending=False)
    dt = 2 * np.pi / omega / steps_per_period
    start = x.copy()
    start[:, 2] += 1e-4 * PLATE.radius * mode
    state = AlphaState(start, np.zeros_like(start))
    load = Load(np.zeros(len(x)), np.zeros(3), None, 0.0, None)
    mass = model.base.node_mass

    def energy(s):
        z = s.node_position[:, 2] - x[:, 2]
        return float(mass @ (s.node_velocity[:, 2] ** 2 + omega**2 * z**2))

    first = energy(state)
    for _ in range(int(round(periods * steps_per_period))):
        state, _ = step(model, state, load, dt, AlphaSettings(rho_inf=rho_inf))
    return energy(state) / first


def test_spectral_radius_damps_what_the_step_does_not_resolve():
    # three steps a period (omega dt = 2.1): beyond what the step resolves
    assert _modal_energy_ratio(1.0, 3, 6) == pytest.approx(1.0, abs=1e-6)
    assert _modal_energy_ratio(0.5, 3, 6) < 0.1
    # a resolved mode (40 steps a period) keeps most of its energy at rho_inf = 0.5
    assert _modal_energy_ratio(0.5, 40, 2) > 0.9


def test_bad_settings_name_the_key():
    with pytest.raises(ValueError, match="rho_inf"):
        AlphaSettings(rho_inf=1.5)


def test_a_failed_step_leaves_the_hinges_where_it_began():
    """A step whose Newton does not converge raises NewtonDivergence with every hinge's
    reference turn as before the step (its iterates followed them), so that the window's
    retry with a smaller step picks each hinge's turn from the state it starts at; the
    retry then gives what a fresh model gives."""
    from structure.newton.dynamics import NewtonDivergence

    model, x, omega, mode, centre = _sheet(6, bending=True)
    start = x.copy()
    start[:, 2] += 0.05 * PLATE.radius * mode
    state = AlphaState(start, np.zeros_like(start))
    load = Load(np.zeros(len(x)), np.zeros(3), None, 0.0, None)
    model.follow(start)
    before = [s.copy() for s in model.path_state()]
    dt = 2 * np.pi / omega / 4
    with pytest.raises(NewtonDivergence):
        step(model, state, load, dt, AlphaSettings(max_iterations=1))
    assert all(np.array_equal(a, b) for a, b in zip(model.path_state(), before))
    assert any(np.abs(b).max() > 0 for b in before)
    fresh, *_ = _sheet(6, bending=True)
    fresh.follow(start)
    retried, _ = step(model, state, load, dt / 2)
    reference, _ = step(fresh, state, load, dt / 2)
    assert np.array_equal(retried.node_position, reference.node_position)
