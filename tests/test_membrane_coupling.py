"""The diaphragm coupled to the immersed-boundary liquid: XPBD membrane (structure.xpbd.step)
and FiPy fluid (fluid.solver) through the coupling library, serial-implicit with IQN-ILS, the
membrane holding the liquid volume the port delivers (its multiplier is the pressure level).

Oracles: (1) at rest the dynamic coupled problem must keep the static equilibrium of the same
membrane under the hydrostatic model (one mechanism, two fluids: the fluid's reduced pressure
makes the hydrostatic field exact) and find the same pressure level; (2) during a fill through
the bottom port the liquid volume, on both sides of the interface, follows the port's
delivered volume. Coarse on purpose (N = 14 membrane, 16^3 grid): seconds, not minutes.
"""
import numpy as np
import pytest

from coupling import AccelerationSettings, ConvergenceMeasure, CouplingSettings, run
from fluid.hydrostatic import HydrostaticLiquid
from fluid.model import Port
from fluid.solver import FluidSolver
from fluid.tank import sphere_model, tank_grid
from fsi.coupled.adapters import (POINTS, PRESSURE, VELOCITIES, FluidParticipant,
                                  MembraneParticipant, MembraneSurface)
from fsi.setup.limits import courant_time_step_limit
from fsi.constants import (MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS,
                           STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY)
from structure.load import Load
from structure.model import Material, MembraneState, hemisphere_model
from structure.volume import liquid_volume, lower_hemisphere_volume
from structure.xpbd import XpbdDivergence, XpbdModel, XpbdSettings, solve_equilibrium

WINDOW = 2e-3  # s
GRAVITY = (0.0, 0.0, -STANDARD_GRAVITY)


@pytest.fixture(scope="module")
def half_full():
    """(model, substep settings, static state at half the tank, static level Pa)."""
    material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, 0.5)
    base = hemisphere_model(14, TANK_RADIUS, material, "clamped")
    model = XpbdModel.from_membrane(base)
    liquid = HydrostaticLiquid(WATER_DENSITY, GRAVITY)
    limit = 0.3 * courant_time_step_limit(base, liquid, TANK_RADIUS)
    substep = WINDOW / np.ceil(WINDOW / limit)  # a whole number of substeps per window
    settings = XpbdSettings(dt=substep, warm_start=False, tolerance=1e-6, max_steps=40_000)
    state, info = solve_equilibrium(model, MembraneState(base.node_rest_position),
                                    Load(liquid.pressure, GRAVITY,
                                         volume_target=lower_hemisphere_volume(TANK_RADIUS)),
                                    settings)
    assert info.converged
    return model, settings, state, info.pressure_level


def _couple(half_full, flow, delivered, windows):
    model, settings, state, level = half_full
    grid = tank_grid(TANK_RADIUS, 16, axisymmetric=False)
    surface = MembraneSurface(model)
    fluid = FluidSolver(sphere_model(TANK_RADIUS, grid, [Port("bottom", "flow", flow)],
                                     density=WATER_DENSITY, body_acceleration=GRAVITY),
                        surface.of(state))
    v0 = liquid_volume(model.base, state.node_position)
    membrane = MembraneParticipant(model, state, settings, lambda t: v0 + delivered(t),
                                   GRAVITY, level)
    coupling = CouplingSettings(
        scheme="implicit-serial", acceleration="iqn-ils",
        acceleration_settings=AccelerationSettings(initial_relaxation=0.01, reuse=8,
                                                   filter_limit=1e-2, max_columns=100),
        measures=[ConvergenceMeasure(PRESSURE, "relative", 1e-4),
                  ConvergenceMeasure(POINTS, "relative", 1e-6)],
        max_iterations=60, on_max_iterations="error")
    log = run(membrane, FluidParticipant(fluid, surface=surface), coupling, WINDOW, windows)
    return membrane, fluid, log, v0


def test_coupled_membrane_at_rest_keeps_the_static_equilibrium(half_full):
    _, _, state, level = half_full
    membrane, fluid, log, _ = _couple(half_full, 0.0, lambda t: 0.0, 4)
    assert all(w.converged for w in log.windows)
    moved = np.abs(membrane.state.node_position - state.node_position).max()
    assert moved < 1e-5  # m, against 0.2 m of tank radius
    assert membrane.level == pytest.approx(level, abs=2.0)  # Pa; the level is ~250 Pa
    assert fluid.velocity_magnitude_max() < 1e-3  # m/s


def test_coupled_fill_follows_the_port_volume(half_full):
    """Port flow ramped smoothly from 0 to 0.5 L/s over 0.1 s (an impulsive start asks for an
    infinite pressure; a valve opens in finite time)."""
    q, ramp, windows = 5e-4, 0.1, 10

    def flow(t):
        return q * min(t / ramp, 1.0)

    def delivered(t):
        return q * t * t / (2 * ramp) if t <= ramp else q * (t - ramp / 2)

    model = half_full[0]
    membrane, fluid, log, v0 = _couple(half_full, flow, delivered, windows)
    end = windows * WINDOW
    assert all(w.converged for w in log.windows)
    assert log.mean_iterations <= 10
    membrane_volume = liquid_volume(model.base, membrane.state.node_position)
    assert membrane_volume - v0 == pytest.approx(delivered(end), rel=0.01)
    # the fluid's cut cells see the same volume change (its own discretisation of the
    # membrane, 16^3 cells)
    fluid_start = FluidSolver(fluid.model, MembraneSurface(model).of(half_full[2])).liquid_volume
    assert fluid.liquid_volume - fluid_start == pytest.approx(delivered(end), rel=0.15)


def test_a_membrane_out_of_the_tank_stops_the_run_by_name():
    """A surface told to carry its liquid volume raises XpbdDivergence, not a bare error deep
    in the fluid's geometry, when the membrane holds none (it has left the tank): the coupled
    procedures stop on it, record why and exit 1."""
    material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, 0.5)
    model = XpbdModel.from_membrane(hemisphere_model(6, TANK_RADIUS, material, "clamped"))
    rest = model.base.node_rest_position
    surface = MembraneSurface(model, lambda x: liquid_volume(model.base, x))
    assert surface(rest, np.zeros_like(rest)).liquid_volume == pytest.approx(
        liquid_volume(model.base, rest), rel=1e-15)
    with pytest.raises(XpbdDivergence, match="left the tank"):
        MembraneSurface(model, lambda x: -1e-4)(rest, np.zeros_like(rest))


def test_window_mean_velocity_is_the_positions_change_over_the_window(half_full):
    """``interface_velocity = "window-mean"`` sends (x_end - x_start)/dt, the velocity of a
    backward Euler liquid step whose boundary moves from the window's start to its end;
    ``membrane`` sends the membrane's own end velocity (its last substep's). The choice
    changes only what is sent: both membranes take the same step."""
    model, settings, state, level = half_full
    v0 = liquid_volume(model.base, state.node_position)
    sent = {}
    for name in ("membrane", "window-mean"):
        membrane = MembraneParticipant(model, state, settings, lambda t: v0, GRAVITY, level,
                                       velocity=name)
        # no liquid pressure: the sheet starts to fall under its weight and the level
        out = membrane.solve_window(0.0, WINDOW, {PRESSURE: np.zeros(len(state.node_position))})
        sent[name] = (out[POINTS].reshape(-1, 3), out[VELOCITIES].reshape(-1, 3),
                      membrane.state.node_velocity)
    (x_m, v_m, own_m), (x_w, v_w, own_w) = sent["membrane"], sent["window-mean"]
    np.testing.assert_array_equal(x_m, x_w)
    np.testing.assert_array_equal(own_m, own_w)
    np.testing.assert_array_equal(v_m, own_m)
    np.testing.assert_allclose(v_w, (x_w - state.node_position) / WINDOW, rtol=0, atol=1e-12)
    # uniformly accelerated from rest the mean is half the end velocity, not the end velocity
    assert np.abs(v_w).max() < 0.75 * np.abs(v_m).max()
    # a participant checkpointed before the choice existed resumes sending its own velocity
    older = MembraneParticipant(model, state, settings, lambda t: v0, GRAVITY, level,
                                velocity="window-mean")
    del older.__dict__["velocity"]
    out = older.solve_window(0.0, WINDOW, {PRESSURE: np.zeros(len(state.node_position))})
    np.testing.assert_array_equal(out[VELOCITIES].reshape(-1, 3), own_m)
    with pytest.raises(ValueError, match="unknown interface velocity 'end'.*window-mean"):
        MembraneParticipant(model, state, settings, lambda t: v0, GRAVITY, level,
                            velocity="end")
