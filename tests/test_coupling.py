"""Coupling library: schemes x accelerations on fixed points with known solutions."""
import logging

import numpy as np
import pytest

from coupling import (ACCELERATIONS, SCHEMES, AccelerationSettings, ConvergenceMeasure,
                      CouplingError, CouplingSettings, run)


class Affine:
    """Participant out = f(A in + b) (f = identity or a mild nonlinearity), with an integrator
    state s += dt * mean(out) to check checkpoints."""

    def __init__(self, name, write, read, A, b, nonlinear=False):
        self.name, self.write_fields, self.read = name, (write,), read
        self.A, self.b, self.nonlinear = A, b, nonlinear
        self.state = 0.0
        self.calls = 0

    def initial_data(self):
        return {self.write_fields[0]: np.zeros(self.A.shape[0])}

    def solve_window(self, time, dt, data_in):
        self.calls += 1
        y = self.A @ data_in[self.read] + self.b
        if self.nonlinear:
            y = y + 0.1 * np.sin(y)
        self.state += dt * float(np.mean(y))
        return {self.write_fields[0]: y}

    def store_checkpoint(self):
        return self.state

    def restore_checkpoint(self, checkpoint):
        self.state = checkpoint


def _pair(n=6, gain=0.4, seed=0, nonlinear=False):
    rng = np.random.default_rng(seed)
    A1 = rng.normal(size=(n, n))
    A2 = rng.normal(size=(n, n))
    A1 *= np.sqrt(gain) / np.linalg.norm(A1, 2)
    A2 *= np.sqrt(gain) / np.linalg.norm(A2, 2)
    s = Affine("structure", "d", "p", A1, rng.normal(size=n), nonlinear)
    f = Affine("fluid", "p", "d", A2, rng.normal(size=n), nonlinear)
    return s, f


def _fixed_point(s, f):
    n = s.A.shape[0]
    # d = A1 p + b1, p = A2 d + b2  ->  p = A2 (A1 p + b1) + b2
    p = np.linalg.solve(np.eye(n) - f.A @ s.A, f.A @ s.b + f.b)
    return s.A @ p + s.b, p


def _settings(scheme, acceleration, tol=1e-10, **kw):
    acc = AccelerationSettings(relaxation=0.5, initial_relaxation=0.5, **kw)
    return CouplingSettings(scheme=scheme, acceleration=acceleration, acceleration_settings=acc,
                            measures=[ConvergenceMeasure("d", "absolute", tol),
                                      ConvergenceMeasure("p", "absolute", tol)],
                            max_iterations=200)


@pytest.mark.parametrize("scheme", ["implicit-serial", "implicit-parallel"])
@pytest.mark.parametrize("acceleration", sorted(ACCELERATIONS))
@pytest.mark.parametrize("nonlinear", [False, True])
def test_every_implicit_scheme_and_acceleration_converges(scheme, acceleration, nonlinear):
    s, f = _pair(nonlinear=nonlinear)
    out = {}
    log = run(s, f, _settings(scheme, acceleration), dt=0.1, n_windows=3,
              on_window=lambda w, data: out.update(data))
    assert all(w.converged for w in log.windows)
    # the converged data satisfy both participants' equations
    d, p = out["d"], out["p"]
    g = (lambda y: y + 0.1 * np.sin(y)) if nonlinear else (lambda y: y)
    assert np.allclose(d, g(s.A @ p + s.b), atol=1e-8)
    assert np.allclose(p, g(f.A @ d + f.b), atol=1e-8)
    if not nonlinear:
        d_star, p_star = _fixed_point(s, f)
        assert np.allclose(d, d_star, atol=1e-8) and np.allclose(p, p_star, atol=1e-8)


def test_explicit_scheme_is_one_staggered_pass_per_window():
    s, f = _pair()
    log = run(s, f, _settings("explicit", "constant"), dt=0.1, n_windows=4)
    assert [w.iterations for w in log.windows] == [1, 1, 1, 1]
    assert s.calls == f.calls == 4


@pytest.mark.parametrize("n", [3, 6, 10])
def test_iqn_ils_solves_affine_map_after_n_plus_1_evaluations(n):
    # non-contractive map (|A2 A1| = 1.5): plain iteration diverges, IQN-ILS solves it
    s, f = _pair(n=n, gain=1.5, seed=3)
    settings = _settings("implicit-serial", "iqn-ils", tol=1e-9)
    settings.measures = [ConvergenceMeasure("p", "absolute", 1e-9)]  # the accelerated field
    log = run(s, f, settings, dt=0.1, n_windows=1)
    # evaluation k has k - 1 secant columns; with n of them (evaluation n + 1) the update is
    # exact, and the next evaluation (number n + 2) confirms it
    assert log.windows[0].converged
    assert log.windows[0].iterations <= n + 2
    assert log.windows[0].residuals[n]["p"] > 1e-9  # and not before: exactly n + 2


@pytest.mark.parametrize("mixing,extra", [(0.3, 0), (0.1, 0), (0.01, 3)])
@pytest.mark.parametrize("n", [3, 6])
def test_iqn_ils_with_mixing_still_solves_affine_map_after_n_plus_1_evaluations(n, mixing,
                                                                                  extra):
    # Anderson mixing: beta scales the step outside the secants' span but not the space they
    # span on an affine map (the same Krylov space), so n secants still make the update exact;
    # at beta = 0.01 the short steps make near-parallel secants and round-off costs up to
    # ``extra`` more evaluations (measured: 9 for n = 6)
    s, f = _pair(n=n, gain=1.5, seed=3)
    settings = _settings("implicit-serial", "iqn-ils", tol=1e-9, mixing=mixing)
    settings.measures = [ConvergenceMeasure("p", "absolute", 1e-9)]
    out = {}
    log = run(s, f, settings, dt=0.1, n_windows=1, on_window=lambda w, data: out.update(data))
    assert log.windows[0].converged
    assert log.windows[0].iterations <= n + 2 + extra
    assert np.allclose(out["p"], _fixed_point(s, f)[1], atol=1e-8)


@pytest.mark.parametrize("beta", [1.0, 0.2])
def test_iqn_ils_mixing_relaxes_only_the_residual_outside_the_secants(beta):
    # second update of a window, one secant v = r1 - r0, w = x~1 - x~0: a = -(v . r1) / |v|^2
    # and x+ = x1 + (w - v) a + beta (r1 + v a); beta = 1 is IQN-ILS's x~1 + w a
    rng = np.random.default_rng(1)
    x0, xt0, x1, xt1 = rng.normal(size=(4, 5))
    acc = ACCELERATIONS["iqn-ils"](AccelerationSettings(mixing=beta))
    acc.start_window()
    acc.update(x0, xt0)
    out = acc.update(x1, xt1)
    r1 = xt1 - x1
    v, w = r1 - (xt0 - x0), xt1 - xt0
    a = -(v @ r1) / (v @ v)
    assert np.allclose(out, x1 + (w - v) * a + beta * (r1 + v * a))
    if beta == 1.0:
        assert np.allclose(out, xt1 + w * a)


@pytest.mark.parametrize("beta", [1.0, 0.1])
def test_iqn_imvj_with_mixing_takes_iqn_ils_steps_in_its_first_window(beta):
    # J_prev = (1 - beta) I before any window: x~ - J r with J = J_prev + (W - J_prev V)
    # (V^T V)^-1 V^T is x + (W - V) a + beta (r + V a), IQN-ILS's mixed update without reuse
    # (Lindner et al. 2015 for beta = 1)
    rng = np.random.default_rng(2)
    xs, xts = rng.normal(size=(2, 5, 7))
    ils = ACCELERATIONS["iqn-ils"](AccelerationSettings(mixing=beta))
    imvj = ACCELERATIONS["iqn-imvj"](AccelerationSettings(mixing=beta))
    for acc in (ils, imvj):
        acc.start_window()
    for x, xt in zip(xs, xts):
        assert np.allclose(ils.update(x, xt), imvj.update(x, xt), rtol=0, atol=1e-12)


@pytest.mark.parametrize("mixing", [1.0, 0.1])
def test_iqn_imvj_carries_its_jacobian_so_a_second_window_of_the_same_map_is_short(mixing):
    # the same linear part in every window, the offset moved after the first: the first
    # window's n secants give the whole inverse Jacobian, so the next window's first
    # quasi-Newton step is exact, where IQN-ILS without reuse learns it anew (n + 2
    # evaluations, test above)
    n = 6
    iterations = {}
    for name in ("iqn-ils", "iqn-imvj"):
        s, f = _pair(n=n, gain=1.5, seed=3)
        settings = _settings("implicit-serial", name, tol=1e-9, mixing=mixing)
        settings.measures = [ConvergenceMeasure("p", "absolute", 1e-9)]
        shift = np.random.default_rng(4).normal(size=n)
        log = run(s, f, settings, dt=0.1, n_windows=2,
                  on_window=lambda w, data, s=s: setattr(s, "b", s.b + shift))
        assert all(w.converged for w in log.windows)
        iterations[name] = [w.iterations for w in log.windows]
    assert iterations["iqn-imvj"][0] == iterations["iqn-ils"][0]
    assert iterations["iqn-ils"][1] >= n + 1
    assert iterations["iqn-imvj"][1] <= 3


def _imvj_windows(acc, windows):
    """Feed ``acc`` the windows' (x, x_tilde) iterates, each window closed by end_window."""
    for xs, xts in windows:
        acc.start_window()
        for x, xt in zip(xs, xts):
            acc.update(x, xt)
        acc.end_window()


def test_iqn_imvj_jacobian_windows_forgets_what_older_windows_taught():
    # K = 1: the Jacobian carried out of two windows is the one the last window alone builds
    # from (1 - beta) I; K = 0 (as published) keeps the first window's too
    rng = np.random.default_rng(5)
    windows = [tuple(rng.normal(size=(2, 3, 8))) for _ in range(2)]
    last = ACCELERATIONS["iqn-imvj"](AccelerationSettings(mixing=0.2))
    _imvj_windows(last, windows[1:])
    one = ACCELERATIONS["iqn-imvj"](AccelerationSettings(mixing=0.2, jacobian_windows=1))
    _imvj_windows(one, windows)
    every = ACCELERATIONS["iqn-imvj"](AccelerationSettings(mixing=0.2))
    _imvj_windows(every, windows)
    assert np.allclose(one.jacobian, last.jacobian, rtol=0, atol=1e-12)
    assert not np.allclose(every.jacobian, last.jacobian, rtol=0, atol=1e-6)


def test_iqn_imvj_restarts_its_jacobian_after_a_window_accepted_unconverged(monkeypatch):
    # a stalled window's secants come from an iteration that did not settle: the next window
    # starts from (1 - beta) I, its first step beta r (the first window's after one secant)
    rng = np.random.default_rng(6)
    acc = ACCELERATIONS["iqn-imvj"](AccelerationSettings(mixing=0.3))
    _imvj_windows(acc, [tuple(rng.normal(size=(2, 3, 5)))])
    assert acc.jacobian is not None
    acc.start_window()
    for x, xt in zip(*rng.normal(size=(2, 3, 5))):
        acc.update(x, xt)
    acc.stalled()
    acc.end_window()
    assert acc.jacobian is None
    # the scheme tells it: every accepted unconverged window, and no converged one
    calls = []
    cls = ACCELERATIONS["iqn-imvj"]
    monkeypatch.setattr(cls, "stalled", lambda self: calls.append(1) or cls.forget(self))
    for iterations, stalls in ((3, 2), (200, 0)):
        calls.clear()
        s, f = _pair(n=4, gain=1.5, seed=3)
        settings = _settings("implicit-serial", "iqn-imvj", tol=1e-9, mixing=0.3)
        settings.max_iterations = iterations
        settings.on_max_iterations = "accept"
        log = run(s, f, settings, dt=0.1, n_windows=2)
        assert sum(not w.converged for w in log.windows) == stalls == len(calls)


def test_mixing_outside_zero_one_raises():
    for bad in (0.0, 1.5):
        with pytest.raises(ValueError, match="mixing"):
            AccelerationSettings(mixing=bad)


def test_iqn_ils_keeps_the_secant_of_the_converged_iteration_for_reuse():
    # as preCICE's iterationsConverged: the last (x, x_tilde) of a window, for which no update
    # is asked, still gives a secant column to the reused windows
    acc = ACCELERATIONS["iqn-ils"](AccelerationSettings(reuse=1))
    rng = np.random.default_rng(0)
    xs, xts = rng.normal(size=(3, 4)), rng.normal(size=(3, 4))
    acc.start_window()
    acc.update(xs[0], xts[0])
    acc.update(xs[1], xts[1])
    acc.converged(xs[2], xts[2])
    acc.end_window()
    v_cols, w_cols = acc.past[0]
    assert len(v_cols) == len(w_cols) == 2
    r = xts - xs
    assert np.allclose(v_cols[0], r[2] - r[1]) and np.allclose(w_cols[0], xts[2] - xts[1])


def test_constant_relaxation_diverges_on_the_non_contractive_map():
    s, f = _pair(n=6, gain=1.5, seed=3)
    settings = _settings("implicit-serial", "constant")
    settings.acceleration_settings.relaxation = 1.0
    settings.max_iterations = 30
    with pytest.raises(CouplingError, match="not converged") as err:
        run(s, f, settings, dt=0.1, n_windows=1)
    assert err.value.window.iterations == 30 and len(err.value.window.residuals) == 30


class Blowing(Affine):
    """An :class:`Affine` fluid whose output turns non-finite from its ``after``-th call (at
    that call only, with ``once``)."""

    def __init__(self, *args, after=3, once=False, **kw):
        super().__init__(*args, **kw)
        self.after, self.once = after, once

    def solve_window(self, time, dt, data_in):
        out = super().solve_window(time, dt, data_in)
        if self.calls == self.after or (self.calls > self.after and not self.once):
            out = {k: np.full_like(v, np.nan) for k, v in out.items()}
        return out


@pytest.mark.parametrize("on_max", ["accept", "explicit", "error"])
def test_a_non_finite_window_stops_the_run_whatever_the_settings(on_max):
    """A participant's non-finite output (a diverged liquid) is never iterated on or
    accepted: the run stops with a CouplingError naming the window, the iteration and the
    field."""
    s, f0 = _pair()
    f = Blowing("fluid", "p", "d", f0.A, f0.b, after=3)
    settings = _settings("implicit-serial", "iqn-ils")
    settings.on_max_iterations = on_max
    with pytest.raises(CouplingError, match=r"window 0 .* not converged: at iteration 3 a "
                                            r"participant returned non-finite p \(the window "
                                            r"diverged\)"):
        run(s, f, settings, dt=0.1, n_windows=2)


def test_checkpoint_restores_state_exactly():
    s, f = _pair()
    run(s, f, _settings("implicit-serial", "aitken"), dt=0.5, n_windows=1)
    d_star, p_star = _fixed_point(s, f)
    # the integrator saw only the final iterate, not the sum over iterations
    assert s.state == pytest.approx(0.5 * np.mean(d_star), abs=1e-9)
    assert f.state == pytest.approx(0.5 * np.mean(p_star), abs=1e-9)
    assert s.calls > 3


def test_max_iterations_accept_logs_and_continues(caplog):
    s, f = _pair()
    settings = _settings("implicit-serial", "constant")
    settings.max_iterations = 2
    settings.on_max_iterations = "accept"
    with caplog.at_level(logging.WARNING):
        log = run(s, f, settings, dt=0.1, n_windows=2)
    assert [w.converged for w in log.windows] == [False, False]
    assert [w.iterations for w in log.windows] == [2, 2]
    assert "accepted" in caplog.text


def test_accept_residual_caps_what_a_stalled_window_may_keep():
    """on_max_iterations = "accept" with accept_residual: a window stopped at max_iterations
    is kept while its last residuals are at most the cap, and raises (so that a run redoes it
    smaller, or stops) above it; the default keeps any."""
    s, f = _pair()
    settings = _settings("implicit-serial", "constant")
    settings.max_iterations = 2
    settings.on_max_iterations = "accept"
    last = max(run(s, f, settings, dt=0.1, n_windows=1).windows[0].residuals[-1].values())
    assert last > 0 and settings.accept_residual == float("inf")
    settings.accept_residual = 2.0 * last
    s, f = _pair()
    assert not run(s, f, settings, dt=0.1, n_windows=1).windows[0].converged
    settings.accept_residual = 0.5 * last
    s, f = _pair()
    with pytest.raises(CouplingError, match="above accept_residual"):
        run(s, f, settings, dt=0.1, n_windows=1)
    with pytest.raises(ValueError, match="accept_residual must be > 0"):
        CouplingSettings(measures=settings.measures, accept_residual=0.0)


def test_max_iterations_explicit_redoes_the_window_as_the_explicit_scheme_does(caplog):
    """on_max_iterations = "explicit": the unconverged window is redone from its restored
    start by the explicit scheme, so its data and the integrators' states equal a plain
    explicit run's; the log says unconverged and explicit, with the failed iterations + 1."""
    s, f = _pair()
    settings = _settings("implicit-serial", "iqn-ils")
    settings.max_iterations = 2
    settings.on_max_iterations = "explicit"
    out = []
    with caplog.at_level(logging.WARNING):
        log = run(s, f, settings, dt=0.1, n_windows=2,
                  on_window=lambda w, data: out.append({k: v.copy() for k, v in data.items()}))
    assert [(w.converged, w.explicit, w.iterations) for w in log.windows] == \
        [(False, True, 3), (False, True, 3)]
    assert "redone explicitly" in caplog.text
    s2, f2 = _pair()
    out2 = []
    run(s2, f2, _settings("explicit", "constant"), dt=0.1, n_windows=2,
        on_window=lambda w, data: out2.append({k: v.copy() for k, v in data.items()}))
    for a, b in zip(out, out2):
        assert np.array_equal(a["d"], b["d"]) and np.array_equal(a["p"], b["p"])
    assert s.state == s2.state and f.state == f2.state


def test_sufficient_measure_ends_window_early():
    s, f = _pair()
    settings = _settings("implicit-serial", "iqn-ils")
    settings.measures = [ConvergenceMeasure("d", "absolute", 1e-12),
                         ConvergenceMeasure("p", "absolute", 1e-2, sufficient=True)]
    loose = run(s, f, settings, dt=0.1, n_windows=1).windows[0]
    s2, f2 = _pair()
    settings.measures[1] = ConvergenceMeasure("p", "absolute", 1e-2)
    strict = run(s2, f2, settings, dt=0.1, n_windows=1).windows[0]
    assert loose.converged and strict.converged
    assert loose.iterations < strict.iterations


def test_log_records_residuals_relaxation_and_time():
    s, f = _pair()
    w = run(s, f, _settings("implicit-serial", "aitken"), dt=0.1, n_windows=1).windows[0]
    assert len(w.residuals) == len(w.relaxation) == w.iterations
    assert w.relaxation[0] == 0.5  # initial relaxation
    assert set(w.seconds) == {"structure", "fluid"} and all(v >= 0 for v in w.seconds.values())
    assert w.residuals[-1]["d"] <= 1e-10 < w.residuals[0]["d"]


class Drifting(Affine):
    """Affine participant whose offset grows linearly in time: out = A in + b + (t + dt) c,
    so the coupled solution at the window ends is linear in time."""

    def __init__(self, *args, drift):
        super().__init__(*args)
        self.b0, self.drift = self.b, drift

    def solve_window(self, time, dt, data_in):
        self.b = self.b0 + (time + dt) * self.drift
        return super().solve_window(time, dt, data_in)


@pytest.mark.parametrize("order,first_exact_window", [(0, None), (1, 2), (2, 3)])
def test_extrapolation_predicts_linear_in_time_data_exactly(order, first_exact_window):
    s, f = _pair()
    rng = np.random.default_rng(1)
    s = Drifting(s.name, "d", "p", s.A, s.b, drift=rng.normal(size=6))
    f = Drifting(f.name, "p", "d", f.A, f.b, drift=rng.normal(size=6))
    settings = _settings("implicit-serial", "iqn-ils")
    settings.extrapolation_order = order
    its = [w.iterations for w in run(s, f, settings, dt=0.1, n_windows=6).windows]
    # the initial data (zeros) are off the line: the prediction is exact once `order + 1`
    # converged windows feed it, and then the first iteration already converges
    if first_exact_window is None:
        assert all(i > 1 for i in its)
    else:
        assert all(i > 1 for i in its[:first_exact_window])
        assert its[first_exact_window:] == [1] * (6 - first_exact_window)


@pytest.mark.parametrize("kw,match", [(dict(scheme="gauss"), "scheme"),
                                      (dict(acceleration="broyden"), "acceleration"),
                                      (dict(on_max_iterations="ignore"), "on_max_iterations"),
                                      (dict(max_iterations=0), "max_iterations"),
                                      (dict(extrapolation_order=3), "extrapolation_order")])
def test_bad_settings_raise(kw, match):
    with pytest.raises(ValueError, match=match):
        CouplingSettings(**kw)


@pytest.mark.parametrize("scheme", ["implicit-serial", "implicit-parallel"])
def test_implicit_scheme_without_measures_raises(scheme):
    with pytest.raises(ValueError, match="measures"):
        CouplingSettings(scheme=scheme, measures=[])
    CouplingSettings(scheme="explicit", measures=[])  # one pass per window: nothing to measure


def test_registries_list_required_names():
    assert {"explicit", "implicit-serial", "implicit-parallel"} <= set(SCHEMES)
    assert {"constant", "aitken", "iqn-ils"} <= set(ACCELERATIONS)


def test_accept_best_keeps_the_window_s_smallest_residual_iterate():
    """on_max_iterations = "accept-best": a window stopped at max_iterations keeps the
    iteration whose residuals were smallest, not the last. On a diverging iteration (gain
    9, constant relaxation) the residuals grow, so the best is not the last; the kept
    window's solves are repeated from its start with the best iteration's input, so that its
    residual is the best one's exactly and the participants' states (integrated over the
    window) are those of a run stopped at that iteration."""
    def stalled(on_max, max_iterations):
        s, f = _pair(gain=9.0, seed=1)
        settings = _settings("implicit-serial", "constant")
        settings.max_iterations = max_iterations
        settings.on_max_iterations = on_max
        window = run(s, f, settings, dt=0.1, n_windows=1).windows[0]
        return window, s.state, f.state

    last, _, _ = stalled("accept", 6)
    scores = [max(r.values()) for r in last.residuals]
    best = int(np.argmin(scores)) + 1
    assert best < 6 and scores[-1] > 2 * min(scores)
    kept, s_state, f_state = stalled("accept-best", 6)
    assert not kept.converged and kept.iterations == 7
    assert kept.residuals[-1] == last.residuals[best - 1]
    _, s_ref, f_ref = stalled("accept", best)
    assert (s_state, f_state) == (s_ref, f_ref)


def _drifting(scale=50.0):
    """The pair of :func:`_pair` drifting fast in time (its fixed point moves by about 30
    per second): a window starts farther from its fixed point the longer it is."""
    s, f = _pair()
    rng = np.random.default_rng(1)
    return (Drifting(s.name, "d", "p", s.A, s.b, drift=scale * rng.normal(size=6)),
            Drifting(f.name, "p", "d", f.A, f.b, drift=scale * rng.normal(size=6)))


def _drift_settings(on_max, split_depth=3):
    settings = _settings("implicit-serial", "constant", tol=1e-6)
    settings.measures = [ConvergenceMeasure("d", "absolute", 1e-6),
                         ConvergenceMeasure("p", "absolute", 1e-6)]
    settings.max_iterations, settings.on_max_iterations = 24, on_max
    settings.split_depth = split_depth
    return settings


def test_split_redoes_a_stalled_window_in_halves_as_windows_of_that_size_would_run():
    """on_max_iterations = "split": on the drifting pair with constant relaxation and 24
    iterations allowed, windows of 0.4, 0.2 and 0.1 s stop short of the tolerance (their
    start lies too far from their fixed point: measured) and windows of 0.05 s converge
    (but the first, from zeros). Two windows of 0.4 s, each halved three times, then run
    as sixteen windows of 0.05 s with "accept-best" (to round-off in the parts' start
    times): the same fields at 0.4 and 0.8 s, the same integrated participant states; each window counts every try's
    iterations (24 for each of the 1 + 2 + 4 tries that stalled) and says it was done in 8
    parts, converged if every part converged."""
    s, f = _drifting()
    ends = []
    ref = run(s, f, _drift_settings("accept-best"), dt=0.05, n_windows=16,
              on_window=lambda w, data: ends.append({k: v.copy() for k, v in data.items()}))
    assert [w.converged for w in ref.windows] == [False] + [True] * 15
    s2, f2 = _drifting()
    split_ends = []
    log = run(s2, f2, _drift_settings("split"), dt=0.4, n_windows=2,
              on_window=lambda w, data: split_ends.append({k: v.copy() for k, v in data.items()}))
    for w, parts in zip(log.windows, (ref.windows[:8], ref.windows[8:])):
        assert w.parts == 8 and w.size == 0.4
        assert w.converged == all(p.converged for p in parts)
        assert w.iterations == len(w.residuals) == 24 * 7 + sum(p.iterations for p in parts)
        assert w.last_residuals == pytest.approx(  # the parts' times differ in round-off
            {k: max(p.residuals[-1][k] for p in parts) for k in "dp"}, rel=1e-6)
    assert [w.converged for w in log.windows] == [False, True]
    for got, want in zip(split_ends, (ends[7], ends[15])):
        for k in "dp":
            assert np.allclose(got[k], want[k], rtol=1e-12, atol=1e-12)
    assert s2.state == pytest.approx(s.state, rel=1e-12)
    assert f2.state == pytest.approx(f.state, rel=1e-12)


@pytest.mark.parametrize("reduction,stalled_try", [(0.6, 24), (0.4, 2)])
def test_a_stalled_try_stopped_early_is_split_with_the_same_fields(reduction, stalled_try):
    """stall_iterations = 1: a try to be split stops once its best score (largest residual
    over the limit) has not fallen to stall_reduction of itself in one iteration. The
    drifting pair's tries contract by 0.485-0.525 per iteration (measured): with 0.6 none stops
    early, every try runs its 24 iterations as without the key; with 0.4 each of a window's
    seven tries to be split stops at its second iteration. Either way the window's parts
    start from the window's start, so the fields at its end and the participants' states
    are those of the run without the key, and only the stalled tries' iterations change."""
    s, f = _drifting()
    ref = run(s, f, _drift_settings("split"), dt=0.4, n_windows=2)
    s2, f2 = _drifting()
    settings = _drift_settings("split")
    settings.stall_iterations, settings.stall_reduction = 1, reduction
    log = run(s2, f2, settings, dt=0.4, n_windows=2)
    for w, w_ref in zip(log.windows, ref.windows):
        assert w.parts == w_ref.parts == 8 and w.converged == w_ref.converged
        assert w.part_residuals == w_ref.part_residuals
        assert w.iterations == w_ref.iterations - 7 * (24 - stalled_try)
    assert s2.state == s.state and f2.state == f.state


def test_a_split_whose_smallest_parts_stall_can_be_redone_whole_keeping_its_best_iterate():
    """split_unconverged = "window": with split_depth = 2 the 0.4 s windows' 0.1 s parts
    stall; each window is then redone from its start as one window whose best iterate is
    kept, and ends where a run with "accept-best" at 0.4 s does (fields and both
    participants' states), done in 1 part, marked split_undone, unconverged, its log
    counting the first try, the split's tries and the whole window's (24: its best iterate is
    its last, not repeated)."""
    s, f = _drifting()
    ends = []
    ref = run(s, f, _drift_settings("accept-best"), dt=0.4, n_windows=2,
              on_window=lambda w, data: ends.append({k: v.copy() for k, v in data.items()}))
    s2, f2 = _drifting()
    settings = _drift_settings("split", split_depth=2)
    settings.split_unconverged = "window"
    got = []
    log = run(s2, f2, settings, dt=0.4, n_windows=2,
              on_window=lambda w, data: got.append({k: v.copy() for k, v in data.items()}))
    s3, f3 = _drifting()
    parts_kept = run(s3, f3, _drift_settings("split", split_depth=2), dt=0.4, n_windows=2)
    for w, w_ref, w_parts in zip(log.windows, ref.windows, parts_kept.windows):
        assert w.split_undone and w.parts == 1 and not w.converged
        assert w_parts.parts == 4 and not w_parts.split_undone
        assert w.iterations == w_parts.iterations + w_ref.iterations == w_parts.iterations + 24
        assert w.last_residuals == w_ref.residuals[-1]
    for a, b in zip(got, ends):
        for k in "dp":
            assert np.array_equal(a[k], b[k])
    assert (s2.state, f2.state) == (s.state, f.state)
    with pytest.raises(ValueError, match="split_unconverged"):
        CouplingSettings(split_unconverged="best")


@pytest.mark.parametrize("kw,match", [
    (dict(stall_iterations=5, on_max_iterations="accept-best"), "stall_iterations"),
    (dict(stall_iterations=-1, on_max_iterations="split"), "stall_iterations"),
    (dict(stall_iterations=5, on_max_iterations="split", stall_reduction=1.0),
     "stall_reduction")])
def test_bad_stall_settings_raise(kw, match):
    with pytest.raises(ValueError, match=match):
        CouplingSettings(**kw)


def test_split_depth_bounds_the_halving_and_keeps_the_smallest_parts_best_iterates():
    """With split_depth = 2 the 0.4 s window's parts are 0.1 s windows, which stall: each
    keeps its best iterate (as "accept-best"), the window is not converged, and its last
    residuals are the largest of its four parts'."""
    s, f = _drifting()
    log = run(s, f, _drift_settings("split", split_depth=2), dt=0.4, n_windows=2)
    w = log.windows[1]
    assert w.parts == 4 and not w.converged
    assert max(w.last_residuals.values()) > 1e-6
    assert len(w.part_residuals) == 4
    with pytest.raises(ValueError, match="split_depth"):
        CouplingSettings(split_depth=0)
