"""A quasi-static coupled window by the minimisation statics
(:mod:`structure.minimise.window`): under the hydrostatic pressure it is the static
equilibrium at the window's volume, a constant added to the received pressure moves the level
by that constant and not the shape, the dead load is the follower force where the coupling
has converged, and a coupled fill runs on it."""
import numpy as np
import pytest

from fsi.scene import SceneError, load_scene
from fsi.setup.build import build
from fsi.setup.models import barrier_pressure, hydrostatic_load
from fsi.setup.static_start import START_SOLVERS
from structure.minimise import fill_path, inside, minimisation_model, xpbd_terms
from structure.minimise.window import QuasiStaticMinimiser
from structure.model import MembraneState
from structure.newton.system import linearise
from structure.volume import liquid_volume, tank_volume
from structure.xpbd import XpbdModel


@pytest.fixture(scope="module")
def window():
    setup = build(load_scene("thesis-fill").with_keys({"membrane": {"grid_size": 10}}))
    xpbd = XpbdModel.from_membrane(setup.model)
    volume = tank_volume(setup.model.radius)
    start, info = START_SOLVERS["minimisation"].solve(setup, xpbd, None, 0.1 * volume)
    return setup, xpbd, start, info, QuasiStaticMinimiser.from_xpbd(xpbd,
                                                                    barrier_pressure(setup))


def _solve(window, offset, target_fraction=0.102, sent=None):
    setup, _, start, info, q = window
    b = np.asarray(setup.liquid.body_acceleration, float)
    rho = setup.liquid.density
    x0 = start.node_position
    sent = x0 if sent is None else sent
    target = target_fraction * tank_volume(setup.model.radius)
    return q.solve(x0, rho * (sent @ b) + offset, sent, b, rho, target, info.pressure_level)


def test_under_the_hydrostatic_pressure_the_window_is_the_static_equilibrium(window):
    """Received p = rho b . x at the sent shape: the window's end is the minimisation
    statics' equilibrium at its volume from the same start, the volume held: positions to
    1e-8 m and level to 1e-4 Pa, the two solves' convergence (the window goes straight at
    the volume, the statics first correct at the start's own; 1.4e-9 m and 3.8e-5 Pa measured
    on this grid)."""
    setup, xpbd, start, info, _ = window
    state, eq, _ = _solve(window, 0.0)
    target = 0.102 * tank_volume(setup.model.radius)
    assert eq.converged
    assert liquid_volume(setup.model, state.node_position) == pytest.approx(target, rel=1e-8)
    model, wall = minimisation_model(setup.model, xpbd_terms(xpbd), barrier_pressure(setup))
    ((static, seq),), _ = fill_path(model, wall, MembraneState(inside(wall, start.node_position)),
                                    hydrostatic_load(setup.liquid, target, info.pressure_level),
                                    [target])
    assert seq.converged
    assert np.abs(static.node_position - state.node_position).max() <= 1e-8
    assert eq.pressure_level == pytest.approx(seq.pressure_level, abs=1e-4)


def test_a_constant_in_the_received_pressure_is_a_level_at_the_fixed_point(window):
    """+123 Pa on every node, received at the window's end shape (where the coupling has
    converged): the same shape (to 1e-9 m), the level 123 Pa lower (to the solve's
    convergence, 1e-4 Pa)."""
    plain, eq0, _ = _solve(window, 0.0)
    shifted, eq1, _ = _solve(window, 123.0, sent=plain.node_position)
    assert np.abs(plain.node_position - shifted.node_position).max() <= 1e-9
    assert eq1.pressure_level == pytest.approx(eq0.pressure_level - 123.0, abs=1e-4)


def test_the_dead_load_is_the_follower_force_at_the_sent_shape(window):
    """The window's potential's gradient at the sent shape equals the follower form's with
    the received pressure (the coupling's fixed point is the follower equilibrium)."""
    setup, xpbd, start, info, q = window
    b = np.asarray(setup.liquid.body_acceleration, float)
    rho = setup.liquid.density
    x = inside(q.wall, start.node_position)
    received = rho * (x @ b) + 50.0 * np.cos(7 * x[:, 0] / setup.model.radius)
    q.solve(x, received, x, b, rho, liquid_volume(setup.model, x), info.pressure_level)
    ours = linearise(q.model, x, 0.0, hydrostatic_load(setup.liquid, None), hessian=False)
    # the follower form's load on the same internal energy: p_i dV/dx_i lumped at the nodes
    _, gv, _ = q.model.volume.evaluate(x, False)
    dead = (received - rho * (x @ b))[:, None] * gv
    q.dead.force[:] = 0.0
    without = linearise(q.model, x, 0.0, hydrostatic_load(setup.liquid, None), hessian=False)
    free = ~setup.model.node_fixed
    np.testing.assert_allclose((without.residual - ours.residual)[free], dead[free],
                               atol=1e-12 * np.abs(dead).max())


def test_a_slow_fill_runs_on_minimisation_windows():
    """thesis-fill's first 20 s on N = 10 with the minimisation's start and windows: every
    window converged, none redone with inertia or explicitly, the membrane's volume the
    delivered one."""
    from fsi.registry import PROCEDURES

    setup = build(load_scene("thesis-fill").with_keys({
        "membrane": {"grid_size": 10}, "dynamics": {"end_time": 20.0,
                                                    "start_solver": "minimisation"},
        "coupling": {"quasi_static_solver": "minimisation"}}))
    result = PROCEDURES["coupled-fill"](setup, lambda fraction, message: None)
    w = result.groups["windows"]
    assert len(w["converged"]) >= 5 and np.all(w["converged"])
    assert result.attrs["windows_explicit"] == 0 and result.attrs["windows_with_inertia"] == 0
    frames = result.groups["frames"]
    port = setup.scene["port"]
    start = liquid_volume(setup.model, frames["node_position"][0])
    delivered = start + port["flow"] * (frames["time"][-1] - 0.5 * port["ramp_time"])
    assert liquid_volume(setup.model, frames["node_position"][-1]) == pytest.approx(
        delivered, rel=1e-6)


def test_the_minimisation_windows_need_quasi_static_windows():
    with pytest.raises(SceneError, match=r"coupling\.quasi_static_solver.*allowed: "
                                         r"'relaxation'"):
        build(load_scene("diaphragm-fill").with_keys(
            {"coupling": {"quasi_static_solver": "minimisation"}}))
