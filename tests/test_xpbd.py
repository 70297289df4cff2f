"""XPBD membrane (structure/xpbd.py): stiffness independent of the time step.

Oracle: Hencky's clamped circular membrane, w0 = c a (q a / (E h))^(1/3), c = 0.6534 at
nu = 0.3 (Hencky 1915; Fichter, NASA TP-3658, 1997), a case with one equilibrium.  The shape
metric is the thesis's Eqn 6.1 (fsi/compare.py), taken relative to the same metric of the
deflection itself (the disc's Eqn 6.1 against the flat disc), since Eqn 6.1 divides by the
sphere volume.
"""
import numpy as np
import pytest

from fsi.analysis.compare import eqn_6_1_error
from fsi.constants import (MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS,
                           STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY)
from structure.grid import triangles_from_quads
from structure.model import Material, MembraneState, disc_model
from structure.volume import liquid_volume
from structure.load import Load
from structure.xpbd import XpbdModel, XpbdSettings, solve_equilibrium, step

Q = 100.0  # Pa: w0 = 15 mm, about 8 membrane thicknesses (membrane regime)
GRID = 14


@pytest.fixture(scope="module")
def disc():
    material = Material(MEMBRANE_THICKNESS, 1070.0, MEMBRANE_YOUNGS_MODULUS, 0.3)
    return XpbdModel.from_membrane(disc_model(GRID, TANK_RADIUS, material,
                                              support="simply-supported"))


def _inflate(model, dt, warm_start):
    base = model.base
    settings = XpbdSettings(dt=dt, warm_start=warm_start, tolerance=1e-7)
    state, info = solve_equilibrium(model, MembraneState(base.node_rest_position),
                                    Load(lambda x: np.zeros(len(x)), (0.0, 0.0, 0.0),
                                         pressure_level=Q), settings)
    assert info.converged
    return state.node_position


def _relative_eqn_6_1(model, a, b):
    faces = triangles_from_quads(model.base.face_nodes)
    flat = model.base.node_rest_position
    return eqn_6_1_error(a, faces, b, TANK_RADIUS) / eqn_6_1_error(a, faces, flat, TANK_RADIUS)


def test_equilibrium_does_not_depend_on_the_time_step(disc):
    coarse = _inflate(disc, 2e-3, warm_start=True)
    fine = _inflate(disc, 5e-4, warm_start=True)
    assert _relative_eqn_6_1(disc, fine, coarse) <= 0.01
    centre = np.argmin(np.linalg.norm(disc.base.node_rest_position[:, :2], axis=1))
    mat = disc.base.material
    stiffness = mat.youngs_modulus * mat.thickness
    hencky = 0.6534 * TANK_RADIUS * (Q * TANK_RADIUS / stiffness) ** (1 / 3)
    assert abs(fine[centre, 2]) == pytest.approx(hencky, rel=0.03)


def test_plain_xpbd_with_one_sweep_is_softer_at_larger_steps(disc):
    """Why the multipliers are carried: with lambda reset every substep and one sweep, the
    equilibrium carries a bias ~ dt^2 k / m and the membrane looks softer at larger dt."""
    coarse = _inflate(disc, 2e-3, warm_start=False)
    fine = _inflate(disc, 5e-4, warm_start=False)
    assert _relative_eqn_6_1(disc, fine, coarse) > 0.2


def test_settings_reject_bad_values():
    with pytest.raises(ValueError, match="dt"):
        XpbdSettings(dt=0.0)
    with pytest.raises(ValueError, match="iterations"):
        XpbdSettings(iterations=0)


# ------------------------------------------------------------------ dynamic windows

@pytest.fixture(scope="module")
def half_full():
    """Hemisphere (N = 14) relaxed by plain XPBD to half the tank under water, the substep
    of the window tests: (model, liquid, settings, state, static level Pa)."""
    from fluid.hydrostatic import HydrostaticLiquid
    from structure.model import hemisphere_model
    from structure.volume import lower_hemisphere_volume

    material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, 0.5)
    model = XpbdModel.from_membrane(hemisphere_model(GRID, TANK_RADIUS, material, "clamped"))
    liquid = HydrostaticLiquid(WATER_DENSITY, (0.0, 0.0, -STANDARD_GRAVITY))
    settings = XpbdSettings(dt=5e-4, warm_start=False, tolerance=1e-7, max_steps=40_000)
    state, info = solve_equilibrium(model, MembraneState(model.base.node_rest_position),
                                    Load(liquid.pressure, liquid.body_acceleration,
                                         volume_target=lower_hemisphere_volume(TANK_RADIUS)),
                                    settings)
    assert info.converged
    return model, liquid, settings, state, info.pressure_level


def test_window_step_holds_an_equilibrium_and_returns_its_level(half_full):
    """An equilibrium is a fixed point of the dynamic window stepper, and the multiplier of
    the volume held there is the static pressure level."""
    model, liquid, settings, state, level = half_full
    x = state.node_position
    volume = liquid_volume(model.base, x)
    out, info = step(model, state, Load(liquid.pressure(x), liquid.body_acceleration,
                                        volume_target=volume), 4 * settings.dt, settings)
    window_level, n_sub = info.pressure_level, info.substeps
    assert n_sub == 4
    assert np.abs(out.node_position - x).max() < 1e-6  # m, against ~0.1 m of deflection
    assert window_level == pytest.approx(level, rel=0.01)


def test_window_step_composes_and_follows_the_volume_line(half_full):
    """Two windows of one substep are one window of two substeps (the state carries the
    velocities), and the liquid volume ends on the prescribed value (to the accuracy of the
    one linearised volume projection per substep)."""
    model, liquid, settings, state, _ = half_full
    x = state.node_position
    p = liquid.pressure(x)
    g = liquid.body_acceleration
    v0 = liquid_volume(model.base, x)
    dv = 1e-4 * v0
    one, info_one = step(model, state, Load(p, g, volume_target=v0 + dv), 2 * settings.dt,
                         settings)
    half, _ = step(model, state, Load(p, g, volume_target=v0 + dv / 2), settings.dt, settings)
    two, _ = step(model, half, Load(p, g, volume_target=v0 + dv), settings.dt, settings)
    assert info_one.substeps == 2
    assert np.abs(one.node_position - two.node_position).max() < 1e-12
    assert np.abs(one.node_velocity - two.node_velocity).max() < 1e-9
    # one linearised projection per substep: on the line to a small part of the step
    assert abs(liquid_volume(model.base, one.node_position) - (v0 + dv)) < 0.01 * dv
    with pytest.raises(ValueError, match="duration"):
        step(model, state, Load(p, g), 0.0, settings)


def test_quasi_static_window_ends_in_the_static_equilibrium(half_full):
    """The quasi-static window is the warm-started static solve from the window's start: its
    end equals solve_equilibrium's (same settings), its level is the multiplier there, its
    velocities the window's mean; too few substeps raise XpbdDivergence."""
    import copy
    from dataclasses import replace

    from structure.xpbd import XpbdDivergence, quasi_static_step

    model, liquid, settings, state, _ = half_full
    x = state.node_position
    v0 = liquid_volume(model.base, x)
    load = Load(liquid.pressure, liquid.body_acceleration, volume_target=v0 * (1 + 1e-3))
    quasi = replace(settings, tolerance=1e-8)
    out, info = quasi_static_step(model, state, load, 0.5, quasi)
    fresh = replace(state, multipliers=copy.deepcopy(state.multipliers))  # fixture untouched
    static, eq = solve_equilibrium(model, fresh, load,
                                   replace(quasi, warm_start=True, kinetic_damping=False,
                                           ramp_rate=1.0))
    assert eq.converged and info.substeps == eq.steps
    assert np.array_equal(out.node_position, static.node_position)
    assert info.pressure_level == eq.pressure_level
    assert np.allclose(out.node_velocity, (out.node_position - x) / 0.5, rtol=0, atol=1e-15)
    assert liquid_volume(model.base, out.node_position) == pytest.approx(v0 * (1 + 1e-3),
                                                                         rel=1e-9)
    with pytest.raises(XpbdDivergence, match="no equilibrium"):
        quasi_static_step(model, state, load, 0.5, replace(quasi, max_steps=3))
