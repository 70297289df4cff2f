"""Windows of varying size: the local error estimate, the controller and the coupling's redo
of a window that does not converge.

Oracle: for backward Euler the local error of a window of h is (h^2 / 2) |x''| to leading
order (Hairer, Norsett & Wanner, Solving ODEs I, Sec. II.4); a trajectory quadratic in time
has x'' constant, and the estimate e = h / (h + h_prev) |x - x_p| (linear extrapolation x_p
from the two windows before) equals (h^2 / 2) |x''| exactly for any h_prev.
"""
import numpy as np
import pytest

from coupling import CouplingError, run
from fsi.coupled.window_control import (GROW, RETRIES, RETRY_FACTOR, SHRINK, WindowController,
                                        local_error)
from tests.test_coupling import _pair, _settings


@pytest.mark.parametrize("h, h_prev", [(0.1, 0.1), (0.3, 0.1), (0.05, 0.2)])
def test_local_error_is_the_backward_euler_leading_term_on_a_parabola(h, h_prev):
    accel = np.array([[0.3, -1.2, 2.0]])  # m/s^2
    x = lambda t: 0.5 * accel * t**2 + np.array([[1.0, 0.5, -0.2]]) * t  # noqa: E731
    t = 2.0
    e = local_error(x(t + h), x(t), x(t - h_prev), h, h_prev)
    assert e == pytest.approx(0.5 * h**2 * np.linalg.norm(accel), rel=1e-9)


class Window:
    def __init__(self, time, size):
        self.time, self.size = time, size


def _drive(controller, trajectory, dt, t_end):
    """Feed the controller the positions of ``trajectory`` at each window's end; the sizes."""
    t, sizes = 0.0, []
    while dt is not None:
        sizes.append(dt)
        dt = controller(Window(t, dt), {"p": trajectory(t + dt).ravel()})
        t += sizes[-1]
        assert len(sizes) < 10_000
    return t, sizes


def test_controller_grows_to_the_tolerance_and_ends_on_end_time():
    accel = 2.0  # m/s^2 along x: e = h^2 at every window
    trajectory = lambda t: np.array([[0.5 * accel * t**2, 0.0, 0.0]])  # noqa: E731
    tol = 1e-4
    c = WindowController(tol, 1.0, 3.0, "p", trajectory(0.0))
    t, sizes = _drive(c, trajectory, 1e-4, 3.0)
    assert t == pytest.approx(3.0, rel=1e-12)
    ratios = np.array(sizes[1:]) / np.array(sizes[:-1])
    assert ratios.max() <= GROW * (1 + 1e-12) and ratios.min() >= SHRINK * (1 - 1e-12)
    # the settled windows put e near the tolerance (0.9^2 of it) and never far above it
    errors = np.array(c.errors[2:])
    assert np.all(errors < 1.3 * tol)
    assert np.median(errors[len(errors) // 2:]) == pytest.approx(0.81 * tol, rel=0.2)


def test_controller_shrinks_at_a_snap_and_caps_the_window():
    def trajectory(t):  # at rest, a jump of 1 cm at t = 1 s, then at rest
        return np.array([[0.01 if t > 1.0 else 0.0, 0.0, 0.0]])
    c = WindowController(1e-4, 0.05, 2.0, "p", trajectory(0.0))
    t, sizes = _drive(c, trajectory, 0.01, 2.0)
    assert max(sizes) <= 0.05 + 1e-15
    k = int(np.argmax(np.array(c.errors) > 1e-4))
    assert c.over_tolerance >= 1 and sizes[k + 1] == pytest.approx(SHRINK * sizes[k])


def test_controller_keeps_the_floor_at_a_snap_and_does_not_retry_below_it():
    def trajectory(t):  # at rest, a jump of 1 cm at t = 1 s, then at rest
        return np.array([[0.01 if t > 1.0 else 0.0, 0.0, 0.0]])
    c = WindowController(1e-4, 0.5, 3.0, "p", trajectory(0.0), min_window=0.1)
    t, sizes = _drive(c, trajectory, 0.1, 3.0)
    assert t == pytest.approx(3.0, rel=1e-12)
    assert c.over_tolerance >= 1  # the jump's window is over the tolerance ...
    assert min(sizes) == pytest.approx(0.1, rel=1e-12)  # ... and the next is the floor
    assert c.retry(Window(0.0, 0.3)) == pytest.approx(0.15)
    assert c.retry(Window(0.0, 0.15)) is None  # half of it would be below the floor


def test_controller_retries_shrink_then_give_up():
    c = WindowController(1e-4, 1.0, 10.0, "p", np.zeros((1, 3)))
    sizes = [c.retry(Window(0.0, 0.4 * RETRY_FACTOR**k)) for k in range(RETRIES)]
    assert sizes == pytest.approx([0.4 * RETRY_FACTOR**(k + 1) for k in range(RETRIES)])
    assert c.retry(Window(0.0, 0.1)) is None and c.redone == RETRIES


def test_coupling_redoes_a_window_that_does_not_converge_from_its_start():
    """A window longer than 0.25 s cannot converge (one iteration allowed, raised in the
    participant's place): it is redone at half its size from the restored start."""
    s, f = _pair()
    settings = _settings("implicit-serial", "iqn-ils")

    class Limited:
        def __init__(self):
            self.retries = []

        def __call__(self, window, data):
            t = window.time + window.size
            return None if t >= 1.0 - 1e-12 else min(0.5, 1.0 - t)

        def retry(self, window):
            self.retries.append(window.size)
            return window.size / 2  # this test's own rule

    original = s.solve_window

    def solve(time, dt, data_in):
        if dt > 0.25:
            raise CouplingError(f"window of {dt} s", None)
        return original(time, dt, data_in)

    s.solve_window = solve
    limited = Limited()
    log = run(s, f, settings, 0.5, 100, next_window=limited)
    assert [w.size for w in log.windows] == pytest.approx([0.25] * 4)
    assert limited.retries == [0.5, 0.5, 0.5]
    # the failed attempts left no trace: the integrators equal a run of four 0.25 s windows
    s_ref, f_ref = _pair()
    run(s_ref, f_ref, settings, 0.25, 4)
    assert s.state == pytest.approx(s_ref.state, rel=1e-12)
    assert f.state == pytest.approx(f_ref.state, rel=1e-12)
