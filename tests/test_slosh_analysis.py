"""Slosh analysis: free-decay fit, unit slosh oscillator, SP-106 spring-mass equivalent."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fsi.slosh.analysis import (DecayFit, MechanicalModel, equivalent_model, fit_free_decay,
                                pulse_response)

G = 9.81


def damped_cosine(t, amplitude, zeta, omega, phase, offset):
    wd = omega * np.sqrt(1.0 - zeta**2)
    return offset + amplitude * np.exp(-zeta * omega * t) * np.cos(wd * t + phase)


F1, ZETA1 = 1.3, 0.02  # Hz, -
W1 = 2.0 * np.pi * F1
T_DECAY = np.arange(800) * 0.01  # s, ~10 periods


def noisy_decay(seed):
    rng = np.random.default_rng(seed)
    clean = damped_cosine(T_DECAY, 1.0, ZETA1, W1, 0.7, 0.3)
    return clean + 0.01 * rng.standard_normal(T_DECAY.size)  # 1 % of the amplitude


# ------------------------------------------------------------------ fit_free_decay

def test_fit_recovers_noisy_damped_sinusoid_within_its_standard_errors():
    fit = fit_free_decay(T_DECAY, noisy_decay(seed=12))
    assert isinstance(fit, DecayFit)
    assert abs(fit.frequency_hz - F1) < 3.0 * fit.frequency_hz_std
    assert abs(fit.frequency_hz - F1) < 2e-3 * F1
    assert abs(fit.zeta - ZETA1) < 3.0 * fit.zeta_std
    assert fit.amplitude == pytest.approx(1.0, abs=3.0 * fit.amplitude_std + 1e-12)
    assert fit.offset == pytest.approx(0.3, abs=0.01)
    assert fit.rms_residual == pytest.approx(0.01, rel=0.15)
    assert fit.samples == T_DECAY.size and fit.t0 == 0.0
    assert fit.omega == pytest.approx(2.0 * np.pi * fit.frequency_hz)


def test_reported_standard_errors_match_the_scatter_over_noise_realisations():
    fits = [fit_free_decay(T_DECAY, noisy_decay(seed)) for seed in range(100, 120)]
    for value, std in (("frequency_hz", "frequency_hz_std"), ("zeta", "zeta_std"),
                       ("amplitude", "amplitude_std")):
        scatter = np.std([getattr(f, value) for f in fits], ddof=1)
        reported = np.mean([getattr(f, std) for f in fits])
        assert 1.0 / 3.0 < reported / scatter < 3.0, (value, reported, scatter)


def test_two_mode_signal_gives_the_first_mode():
    second = damped_cosine(T_DECAY, 0.1, 0.03, 3.0 * W1, 1.9, 0.0)
    fit = fit_free_decay(T_DECAY, damped_cosine(T_DECAY, 1.0, ZETA1, W1, 0.7, 0.0) + second)
    assert fit.frequency_hz == pytest.approx(F1, rel=5e-3)
    assert fit.zeta == pytest.approx(ZETA1, rel=0.1)


def test_window_and_phase_are_consistent():
    """A fit over a later window carries the same mode: its phase at its own t0 is the full
    fit's unwrapped phase there (mod 2 pi), and both evaluate to the same curve."""
    y = damped_cosine(T_DECAY, 1.0, ZETA1, W1, 0.7, 0.3)
    full = fit_free_decay(T_DECAY, y)
    late = fit_free_decay(T_DECAY, y, start=2.0, stop=6.0)
    assert late.t0 == pytest.approx(2.0) and late.samples == 401
    wrapped = np.angle(np.exp(1j * (full.phase_at(late.t0) - late.phase)))
    assert abs(wrapped) < 1e-6
    assert late.amplitude == pytest.approx(np.exp(-ZETA1 * W1 * late.t0), rel=1e-6)
    t = np.linspace(2.0, 6.0, 50)
    np.testing.assert_allclose(late.evaluate(t), full.evaluate(t), atol=1e-7)
    np.testing.assert_allclose(full.evaluate(T_DECAY), y, atol=1e-7)


def test_fit_rejects_short_nonuniform_and_non_oscillating_records():
    y = damped_cosine(T_DECAY, 1.0, ZETA1, W1, 0.7, 0.0)
    with pytest.raises(ValueError, match="periods"):  # 1 period of 1.3 Hz
        fit_free_decay(T_DECAY, y, stop=1.0 / F1)
    with pytest.raises(ValueError, match="^time: .*samples"):
        fit_free_decay(T_DECAY, y, start=0.0, stop=0.15)
    jittered = T_DECAY + 1e-4 * np.sin(np.arange(T_DECAY.size))
    with pytest.raises(ValueError, match="^time: .*uniformly"):
        fit_free_decay(jittered, y)
    with pytest.raises(ValueError, match="^signal: no oscillating pole"):
        fit_free_decay(T_DECAY, 2.0 + np.exp(-0.5 * T_DECAY))
    with pytest.raises(ValueError, match="^signal: "):
        fit_free_decay(T_DECAY, y[:-1])
    with pytest.raises(ValueError, match="^stop: "):
        fit_free_decay(T_DECAY, y, start=3.0, stop=2.0)


# ------------------------------------------------------------------ pulse_response

def test_undamped_pulse_response_matches_closed_form():
    """x'' + w^2 x = -A sin^2(pi t / T) for t < T, then 0, from rest. With
    sin^2 = (1 - cos W t) / 2, W = 2 pi / T, undetermined coefficients give for t < T
    x = A/2 [(cos w t - 1) / w^2 + (cos W t - cos w t) / (w^2 - W^2)]
    (harmonic plus constant forcing of an undamped oscillator from rest, e.g. S. S. Rao,
    Mechanical Vibrations, ch. 3-4), and free oscillation x(T) cos w s + x'(T)/w sin w s,
    s = t - T, afterwards."""
    amp, pulse, w = 1.5, 0.4, 7.0
    big = 2.0 * np.pi / pulse
    t = np.arange(0.0, 3.0, 1e-3)

    def inside(t):
        x = 0.5 * amp * ((np.cos(w * t) - 1) / w**2
                         + (np.cos(big * t) - np.cos(w * t)) / (w**2 - big**2))
        v = 0.5 * amp * (-np.sin(w * t) / w
                         + (-big * np.sin(big * t) + w * np.sin(w * t)) / (w**2 - big**2))
        return x, v

    xT, vT = inside(pulse)
    s = t - pulse
    x_ref, v_ref = inside(t)
    after = t >= pulse
    x_ref[after] = xT * np.cos(w * s[after]) + vT / w * np.sin(w * s[after])
    v_ref[after] = -xT * w * np.sin(w * s[after]) + vT * np.cos(w * s[after])
    a = np.where(t < pulse, amp * np.sin(np.pi * t / pulse)**2, 0.0)
    x, xd, xdd = pulse_response(t, a, w, 0.0)
    scale_x, scale_v = np.max(np.abs(x_ref)), np.max(np.abs(v_ref))
    np.testing.assert_allclose(x, x_ref, atol=1e-5 * scale_x)
    np.testing.assert_allclose(xd, v_ref, atol=1e-5 * scale_v)
    np.testing.assert_allclose(xdd, -a - w**2 * x_ref, atol=1e-5 * w**2 * scale_x)


def test_damped_pulse_response_matches_solve_ivp_on_nonuniform_times():
    amp, pulse, w, zeta = 1.0, 0.3, 9.0, 0.05
    t = np.sort(np.concatenate([[0.0], np.random.default_rng(3).uniform(0.0, 2.0, 3000)]))
    a = np.where(t < pulse, amp * np.sin(np.pi * t / pulse)**2, 0.0)

    def rhs(tt, s):
        acc = amp * np.sin(np.pi * tt / pulse)**2 if tt < pulse else 0.0
        return [s[1], -acc - 2 * zeta * w * s[1] - w * w * s[0]]

    ref = solve_ivp(rhs, (0.0, 2.0), [0.0, 0.0], t_eval=t, method="DOP853",
                    rtol=1e-11, atol=1e-14, max_step=pulse / 50)
    x, xd, xdd = pulse_response(t, a, w, zeta)
    np.testing.assert_allclose(x, ref.y[0], atol=1e-4 * np.max(np.abs(ref.y[0])))
    np.testing.assert_allclose(xd, ref.y[1], atol=1e-4 * np.max(np.abs(ref.y[1])))
    np.testing.assert_allclose(xdd, -a - 2 * zeta * w * xd - w * w * x, atol=1e-12)


def test_pulse_response_rejects_bad_input():
    t = np.linspace(0.0, 1.0, 11)
    with pytest.raises(ValueError, match="^acceleration: "):
        pulse_response(t, np.zeros(10), 5.0, 0.01)
    with pytest.raises(ValueError, match="^omega: "):
        pulse_response(t, np.zeros(11), 0.0, 0.01)
    with pytest.raises(ValueError, match="^time: "):
        pulse_response(t[::-1], np.zeros(11), 5.0, 0.01)


# ------------------------------------------------------------------ equivalent_model

M_TOTAL, Z_CENTRE = 19.4, -0.0786  # kg, m: about a half-full 0.21 m radius water sphere
M1, H1 = 7.76, -0.10  # kg, m
M0 = M_TOTAL - M1
H0 = (M_TOTAL * Z_CENTRE - M1 * H1) / M0
OMEGA, ZETA = 8.5, 0.01  # rad/s, -
PULSE, AMP = 0.4, 1.0  # s, m/s^2


def model_records():
    """Tank records synthesised by the spring-mass model itself: the slosh mass integrated
    by solve_ivp (independent of pulse_response), the force and moment summed over the two
    particles as F = sum m (b - xdd), M_O = sum m r x (b - xdd), b = (-a, 0, -g)."""
    t = np.arange(0.0, 5 * 2 * np.pi / OMEGA, 2e-3)
    a = np.where(t < PULSE, AMP * np.sin(np.pi * t / PULSE)**2, 0.0)

    def rhs(tt, s):
        acc = AMP * np.sin(np.pi * tt / PULSE)**2 if tt < PULSE else 0.0
        return [s[1], -acc - 2 * ZETA * OMEGA * s[1] - OMEGA**2 * s[0]]

    x1 = np.empty_like(t)
    xd1 = np.empty_like(t)
    state = [0.0, 0.0]
    for lo, hi in ((0.0, PULSE), (PULSE, t[-1])):  # the forcing's derivative jumps at PULSE
        seg = (t >= lo) & (t <= hi) if lo == 0.0 else (t > lo) & (t <= hi)
        sol = solve_ivp(rhs, (lo, hi), state, t_eval=t[seg], method="DOP853",
                        rtol=1e-11, atol=1e-14, dense_output=True)
        x1[seg], xd1[seg] = sol.y
        state = sol.sol(hi)
    xdd1 = -a - 2 * ZETA * OMEGA * xd1 - OMEGA**2 * x1
    body = np.stack([-a, np.zeros_like(t), np.full_like(t, -G)], axis=1)
    force = np.zeros((t.size, 3))
    moment = np.zeros((t.size, 3))
    for mass, r, rel_acc in ((M0, np.array([0.0, 0.0, H0]) + 0 * body, 0 * body),
                             (M1, np.stack([x1, 0 * t, np.full_like(t, H1)], axis=1),
                              np.stack([xdd1, 0 * t, 0 * t], axis=1))):
        f = mass * (body - rel_acc)
        force += f
        moment += np.cross(r, f)
    return t, a, force[:, 0], moment[:, 1]


def check_model(model, rel):
    assert isinstance(model, MechanicalModel)
    assert model.slosh_mass == pytest.approx(M1, rel=rel)
    assert model.slosh_mass_height == pytest.approx(H1, rel=rel)
    assert model.fixed_mass_height == pytest.approx(H0, rel=rel)
    assert model.fixed_mass + model.slosh_mass == pytest.approx(M_TOTAL, rel=1e-12)
    assert (model.fixed_mass * model.fixed_mass_height + model.slosh_mass
            * model.slosh_mass_height) == pytest.approx(M_TOTAL * Z_CENTRE, rel=1e-10)
    assert model.slosh_mass_fraction == pytest.approx(model.slosh_mass / M_TOTAL)
    assert model.pendulum_length == pytest.approx(G / model.omega**2)
    assert model.hinge_height == pytest.approx(model.slosh_mass_height + model.pendulum_length)
    assert model.spring_stiffness == pytest.approx(model.slosh_mass * model.omega**2)


def test_equivalent_model_recovers_the_model_that_made_the_records():
    t, a, fx, my = model_records()
    fit = fit_free_decay(t, fx, start=PULSE)
    assert fit.omega == pytest.approx(OMEGA, rel=1e-5)
    assert fit.zeta == pytest.approx(ZETA, rel=1e-3)
    model = equivalent_model(t, a, fx, my, M_TOTAL, Z_CENTRE, G, fit)
    check_model(model, rel=5e-3)
    assert model.force_residual < 1e-3 and model.moment_residual < 1e-3
    assert model.zeta == fit.zeta and model.frequency_hz == fit.frequency_hz


def test_equivalent_model_with_noisy_records():
    t, a, fx, my = model_records()
    rng = np.random.default_rng(7)
    fx = fx + 0.005 * np.sqrt(np.mean(fx**2)) * rng.standard_normal(t.size)
    my = my + 0.005 * np.sqrt(np.mean(my**2)) * rng.standard_normal(t.size)
    fit = fit_free_decay(t, fx, start=PULSE)
    model = equivalent_model(t, a, fx, my, M_TOTAL, Z_CENTRE, G, fit)
    check_model(model, rel=2e-2)
    assert abs(model.slosh_mass - M1) < 4.0 * model.slosh_mass_std
    assert 0.0 < model.slosh_mass_std < 0.02 * M1


def test_equivalent_model_rejects_bad_input():
    t, a, fx, my = model_records()
    fit = fit_free_decay(t, fx, start=PULSE)
    with pytest.raises(ValueError, match="^force_x: "):
        equivalent_model(t, a, fx[:-1], my, M_TOTAL, Z_CENTRE, G, fit)
    with pytest.raises(ValueError, match="^moment_y: "):
        equivalent_model(t, a, fx, my[1:], M_TOTAL, Z_CENTRE, G, fit)
    with pytest.raises(ValueError, match="^acceleration: "):
        equivalent_model(t, a[:-1], fx, my, M_TOTAL, Z_CENTRE, G, fit)
    for bad in (0.0, -1.0, np.nan):
        with pytest.raises(ValueError, match="^total_mass: "):
            equivalent_model(t, a, fx, my, bad, Z_CENTRE, G, fit)
    with pytest.raises(ValueError, match="^gravity: "):
        equivalent_model(t, a, fx, my, M_TOTAL, Z_CENTRE, 0.0, fit)
    with pytest.raises(ValueError, match="^fit: "):
        equivalent_model(t, a, fx, my, M_TOTAL, Z_CENTRE, G, None)
    with pytest.raises(ValueError, match="^force_x: fitted slosh mass"):  # m1 > total mass
        equivalent_model(t, a, fx, my, 0.5 * M1, Z_CENTRE, G, fit)


def test_failed_spring_mass_keeps_the_decay():
    """A force record no spring-mass model explains (its slosh mass would exceed the
    contents') fails the equivalent only: the decay's frequency and damping are still
    reported, and the failure names the equivalent."""
    from fsi.slosh.response import first_mode
    t = np.arange(0.0, 5.0, 0.002)
    omega, zeta = 2 * np.pi * 1.36, 0.01
    x = 1e-3 * np.exp(-zeta * omega * t) * np.cos(omega * t)
    a = np.where(t < 0.1, 0.5 * np.sin(np.pi * t / 0.1) ** 2, 0.0)
    out = first_mode(t, a, x, 1e5 * x, np.zeros_like(t), 20.0, -0.1, 9.81, 0.20955, 0.15)
    assert out["analysis_failure"].startswith("spring-mass equivalent:")
    assert "slosh_mass" not in out
    natural = omega / np.sqrt(1 - zeta**2)  # the signal oscillates at the damped frequency
    assert out["frequency_hz"] == pytest.approx(natural / (2 * np.pi), rel=1e-6)
    assert out["zeta"] == pytest.approx(zeta, rel=1e-4)
    assert out["lambda1"] == pytest.approx(natural**2 * 0.20955 / 9.81, rel=1e-6)


def test_stokes_layer_is_the_oscillating_walls_and_says_when_a_grid_misses_it():
    """delta = (2 nu / omega)^1/2 (Stokes' second problem, Landau & Lifshitz section 24):
    water (nu = 1e-6 m^2/s) at the diaphragm's 6.8243 Hz is 0.216 mm thick, 0.0067 of a 16^3
    cell of the 0.20955 m tank (32 mm); the summary says that such a zeta is the grid's."""
    from fluid.tank import tank_spacing
    from fsi.procedures.slosh import _zeta_origin
    from fsi.slosh.analysis import stokes_layer
    omega = 2 * np.pi * 6.8243
    delta = stokes_layer(1e-3, 1000.0, omega)
    assert delta == pytest.approx(np.sqrt(2e-6 / omega), rel=1e-12)
    assert delta == pytest.approx(2.160e-4, rel=1e-3)
    assert stokes_layer(0.0, 1000.0, omega) == 0.0
    with pytest.raises(ValueError, match="viscosity"):
        stokes_layer(-1e-3, 1000.0, omega)
    with pytest.raises(ValueError, match="omega"):
        stokes_layer(1e-3, 1000.0, 0.0)
    h = tank_spacing(0.20955, 16, axisymmetric=False)
    assert delta / h == pytest.approx(0.0067, abs=1e-4)
    coarse = dict(stokes_layer=delta, stokes_layer_cells=delta / h, viscosity=1e-3)
    assert "not in it" in _zeta_origin(coarse) and "0.22 mm" in _zeta_origin(coarse)
    assert "scheme's" in _zeta_origin(dict(coarse, viscosity=0.0))
    assert "spans 2 cells" in _zeta_origin(dict(coarse, stokes_layer_cells=2.0))
    assert _zeta_origin({}) == ""


def test_the_hemispherical_diaphragms_first_mode_is_labelled_its_grids():
    """The bundled diaphragm slosh runs the folded hemisphere (shape, surface), whose first
    mode is not converged in the membrane grid: its summary names the grid and the notes'
    bracket, the tension field's 1.34 Hz below the finest grid's one-fold-state bound, which
    falls with N (docs/notes/one-fold-state.md)."""
    from fsi.scene import load_scene
    from fsi.slosh.grid_bracket import FOLD_STATE_BOUND_HZ, TENSION_FIELD_HZ, grid_caveat

    scene = load_scene("slosh-diaphragm")
    assert scene["slosh"]["surface"] == "diaphragm" and scene["membrane"]["shape"] == "hemisphere"
    text = grid_caveat(scene["membrane"]["grid_size"])
    assert "N = 14 membrane grid's value, not converged" in text
    assert "1.34 Hz" in text and "3.44 Hz" in text and "N = 76" in text
    bounds = [FOLD_STATE_BOUND_HZ[n] for n in sorted(FOLD_STATE_BOUND_HZ)]
    assert TENSION_FIELD_HZ < bounds[-1] and bounds == sorted(bounds, reverse=True)
