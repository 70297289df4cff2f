"""Plate check of the thesis bending model: clamped flat disc under a tiny uniform pressure.

Oracle (thesis Eqn 3.2, Kirchhoff plate): w_max = q a^4 / (64 D), D = E t^3 / (12 (1 - nu^2)).

Finding: the thesis model does not bend like a plate. Its bending springs (App. F) push only
when a two-cell chord gets shorter than at rest, and a transverse deflection of a flat sheet
lengthens chords unless the in-plane strain limiter holds the edges; so the deflection is set
by the strain limiter, which in pseudo-time acts as an in-plane stiffness ~ m / dt^2. The disc
then deflects as a Hencky membrane (extensible, no bending): w ~ q^(1/3) (Hencky 1915; the
exponent is exact for the membrane), measured here, instead of w ~ q. At N = 14 and the default
relaxation time step the centre deflection is about 2.6 x the plate value at q = 0.01 Pa and
1.0 x at q = 0.04 Pa (docs/validation/membrane.md, 'Plate check'). The plate oracle is kept
as a strict expected failure for the thesis model; the calibrated bending of
structure/bending.py meets it (tests/test_bending.py: centre deflection within 2.5 % at N = 26).
Both tests are behind ``slow`` (their relaxation takes about 22 s): ``pytest -m slow``.
"""
from dataclasses import replace

import numpy as np
import pytest

from structure.load import Load
from structure.model import Material, MembraneState, disc_model
from structure.statics import RelaxationSettings, solve_equilibrium

A = 0.20955  # disc radius (m), the tank radius
LOADS = (0.01, 0.04)  # Pa: w_plate = 0.056 mm and 0.22 mm, below t/5 = 0.36 mm


def _centre_deflection(model, q, settings, max_rounds=12):
    centre = int(np.argmin(np.linalg.norm(model.node_rest_position[:, :2], axis=1)))
    state = MembraneState(model.node_rest_position)
    w_old = 0.0
    for _ in range(max_rounds):
        state, _ = solve_equilibrium(model, state,
                                     Load(lambda x: np.full(len(x), q), (0.0, 0.0, 0.0)),
                                     settings)
        w = state.node_position[centre, 2]
        if abs(w - w_old) <= 1e-4 * abs(w):
            return w
        w_old = w
    pytest.fail(f"plate solve did not settle at q = {q} Pa (last change {w - w_old:.3g} m)")


@pytest.fixture(scope="module")
def plate():
    material = Material(0.001778, 1070.0, 8.6e6, poisson_ratio=0.5)
    model = disc_model(14, A, material)
    s = RelaxationSettings(max_steps=20000, tolerance=1e-14)
    s = replace(s, constraints=replace(s.constraints, wall_slack=1e9))  # no tank wall
    w = np.array([_centre_deflection(model, q, s) for q in LOADS])
    w_plate = np.array(LOADS) * A**4 / (64 * material.flexural_rigidity)
    print(f"\nplate check N=14: w/w_plate = {w / w_plate} at q = {LOADS} Pa")
    return w, w_plate


@pytest.mark.slow
def test_deflection_is_downstream_of_the_load_and_follows_membrane_scaling(plate):
    w, _ = plate
    assert np.all(w > 0.0), "the disc deflects along the pressure (+z)"
    exponent = np.log(w[1] / w[0]) / np.log(LOADS[1] / LOADS[0])
    assert exponent == pytest.approx(1.0 / 3.0, abs=0.05)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="thesis bending springs are not a plate model: w ~ q^(1/3)")
def test_deflection_matches_kirchhoff_plate_within_3_percent(plate):
    w, w_plate = plate
    assert np.allclose(w / w_plate, 1.0, atol=0.03)
