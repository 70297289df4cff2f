"""Thesis stepper (App. B): strain limit each step, fixed rim, Courant check (Eqn 4.7)."""
import numpy as np
import pytest

from fluid.hydrostatic import HydrostaticLiquid
from fsi.constants import TANK_RADIUS as R
from structure.load import Load
from structure.statics import strain_error
from structure.thesis import CourantError, ThesisSettings, ThesisState, step

G = (0.0, 0.0, -9.81)


def _ramp(model, settings, n_steps, dt=1e-4):
    liq = HydrostaticLiquid(1000.0, G)
    state = ThesisState(model.node_rest_position)
    for k in range(1, n_steps + 1):
        h = -1.05 * R + 2.1 * R * k / n_steps
        load = Load(liq.pressure(state.node_position, liq.reference_pressure(h)), G)
        state, _ = step(model, state, load, dt, settings)
        yield state


def test_strain_limit_and_fixed_rim_hold_every_step(model10):
    settings = ThesisSettings()
    fixed = model10.node_fixed
    moved = False
    for state in _ramp(model10, settings, 1500):
        assert strain_error(model10, state.node_position)[0] <= settings.constraints.error_limit
        assert np.array_equal(state.node_position[fixed], model10.node_rest_position[fixed])
        moved |= np.abs(state.node_position - model10.node_rest_position).max() > 0.005 * R
    assert moved, "the ramp must actually deform the membrane"


def test_courant_violation_raises(model10):
    with pytest.raises(CourantError, match="Courant number"):
        for _ in _ramp(model10, ThesisSettings(), 50, dt=0.05):
            pass


def test_bad_damping_mode_raises():
    with pytest.raises(ValueError, match="damping"):
        ThesisSettings(damping="viscous")
