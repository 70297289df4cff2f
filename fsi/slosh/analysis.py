"""Slosh analysis of a tank's force and moment records: the first slosh mode from a free
decay, and the NASA SP-106 spring-mass equivalent of that mode.

Conventions (SI units): tank frame, spherical tank centred at the origin, gravity along -z,
lateral tank acceleration a(t) along x. The records are the force the contents put on the
tank, F = sum_i m_i (b - xdd_i), and its moment about the tank centre,
M_O = sum_i m_i x_i x (b - xdd_i), with b = (-a, 0, -g) the body acceleration in the tank
frame and xdd_i the particle accelerations relative to the tank; hence M_y = z F_x - x F_z.

References: Y. Hua & T. K. Sarkar, "Matrix pencil method for estimating parameters of
exponentially damped/undamped sinusoids in noise", IEEE Trans. ASSP 38(5), 814-824 (1990);
T. K. Sarkar & O. Pereira, "Using the matrix pencil method to estimate the parameters of a
sum of complex exponentials", IEEE Antennas Propag. Mag. 37(1), 48-55 (1995);
H. N. Abramson (ed.), "The dynamic behavior of liquids in moving containers", NASA SP-106
(1966), ch. 6 (mechanical models).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm
from scipy.optimize import least_squares

MIN_SAMPLES = 20
"""Fewest samples :func:`fit_free_decay` accepts in [start, stop]."""
MIN_PERIODS = 1.5
"""Fewest periods of the fitted mode :func:`fit_free_decay` accepts in [start, stop]."""
SPACING_RTOL = 1e-6
"""Largest relative deviation of a time step from the mean step for 'uniform' sampling."""
PENCIL_MAX_SAMPLES = 1024
"""Longer records are block-averaged to about this many samples for the pencil guess."""
PENCIL_MIN_SAMPLES_PER_PERIOD = 10
"""Block averaging keeps at least this many samples per period of the spectral peak."""
PENCIL_SINGULAR_RTOL = 1e-2
"""Pencil model order: singular values above this fraction of the largest."""
PENCIL_MIN_ORDER = 3
PENCIL_MAX_ORDER = 12
ZETA_BOUNDS = (-0.5, 0.999)
"""Bounds of the damping ratio in the least-squares refinement."""


# ------------------------------------------------------------------ input checks

def _series(name: str, value, length: int | None = None) -> np.ndarray:
    """``value`` as a finite 1-D float array (of ``length`` samples when given)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be a 1-D array of real numbers") from None
    if arr.ndim != 1:
        raise ValueError(f"{name}: must be 1-D, got shape {arr.shape}")
    if length is not None and arr.size != length:
        raise ValueError(f"{name}: has {arr.size} samples but time has {length}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains non-finite values")
    return arr


def checked_time(name: str, value, minimum: int = 2) -> np.ndarray:
    """``value`` as a strictly increasing finite 1-D float array of at least ``minimum``."""
    t = _series(name, value)
    if t.size < minimum:
        raise ValueError(f"{name}: needs at least {minimum} samples, got {t.size}")
    if np.any(np.diff(t) <= 0.0):
        raise ValueError(f"{name}: must be strictly increasing")
    return t


def uniform_step(name: str, t: np.ndarray) -> float:
    """The step (s) of uniformly spaced times ``t`` (n,) s; ValueError when not uniform."""
    dt = (t[-1] - t[0]) / (t.size - 1)
    deviation = float(np.max(np.abs(np.diff(t) - dt)) / dt)
    if deviation > SPACING_RTOL:
        raise ValueError(f"{name}: samples must be uniformly spaced (relative step deviation "
                         f"{deviation:.1e} > {SPACING_RTOL:.0e})")
    return dt


def checked_scalar(name: str, value, positive: bool = False) -> float:
    """``value`` as a finite float (> 0 when ``positive``)."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be a real number, got {value!r}") from None
    if not np.isfinite(x):
        raise ValueError(f"{name}: must be finite, got {x!r}")
    if positive and x <= 0.0:
        raise ValueError(f"{name}: must be positive, got {x!r}")
    return x


# ------------------------------------------------------------------ free decay

@dataclass(frozen=True)
class DecayFit:
    """First mode of a free decay:
    signal(t) = offset + amplitude exp(-zeta omega (t - t0)) cos(omega_d (t - t0) + phase),
    omega_d = omega sqrt(1 - zeta^2).

    ``frequency_hz`` and ``omega`` are the undamped natural frequency (Hz, rad/s); ``zeta``
    the damping ratio (-); ``amplitude`` and ``offset`` in the signal's unit; ``phase`` (rad)
    at ``t0`` (s), the first time used. The ``*_std`` fields are standard errors from the
    least-squares Jacobian; ``rms_residual`` is in the signal's unit; ``samples`` the number
    of samples used.
    """

    frequency_hz: float
    omega: float
    zeta: float
    amplitude: float
    phase: float
    offset: float
    t0: float
    frequency_hz_std: float
    omega_std: float
    zeta_std: float
    amplitude_std: float
    phase_std: float
    offset_std: float
    rms_residual: float
    samples: int

    @property
    def damped_omega(self) -> float:
        """Damped angular frequency omega_d (rad/s)."""
        return self.omega * np.sqrt(1.0 - self.zeta**2)

    @property
    def damped_frequency_hz(self) -> float:
        """Damped frequency omega_d / (2 pi) (Hz)."""
        return self.damped_omega / (2.0 * np.pi)

    def phase_at(self, t):
        """Unwrapped phase omega_d (t - t0) + phase (rad) at times ``t`` (s; scalar or array,
        result of the same shape)."""
        return self.damped_omega * (np.asarray(t, dtype=float) - self.t0) + self.phase

    def evaluate(self, t):
        """The fitted signal at times ``t`` (s; scalar or array, result of the same shape, in
        the signal's unit)."""
        tau = np.asarray(t, dtype=float) - self.t0
        envelope = self.amplitude * np.exp(-self.zeta * self.omega * tau)
        return self.offset + envelope * np.cos(self.phase_at(t))


def fit_free_decay(time, signal, start: float | None = None,
                   stop: float | None = None) -> DecayFit:
    """Fit the first mode of a free decay to the samples with start <= time <= stop.

    ``time`` (n,) s, strictly increasing and uniformly spaced over [start, stop];
    ``signal`` (n,) any unit; ``start``, ``stop`` (s) default to the record's ends.
    The initial guess comes from the matrix pencil (Hua & Sarkar 1990): of the poles with a
    positive frequency of at least one cycle per record, the one whose exponential carries
    the most energy over the record (the zero-frequency pole models the offset and is never
    picked); the 5 parameters are then refined by ``scipy.optimize.least_squares`` and their
    standard errors taken from cov = s^2 (J^T J)^-1, s^2 = residual sum of squares / (n - 5).

    Raises ValueError with fewer than MIN_SAMPLES samples or MIN_PERIODS periods in
    [start, stop], non-uniform sampling, or when no oscillating pole is found.
    """
    t_all = checked_time("time", time)
    t, y, dt = record_window(t_all, _series("signal", signal, t_all.size), start, stop)
    guess = _pencil_guess(y, dt)
    _check_periods(guess[2], guess[1], t[-1] - t[0])
    params, std, residual = _refine(t - t[0], y, guess)
    amplitude, zeta, omega, phase, offset = params
    _check_periods(omega, zeta, t[-1] - t[0])
    return DecayFit(
        frequency_hz=float(omega / (2.0 * np.pi)), omega=float(omega), zeta=float(zeta),
        amplitude=float(amplitude), phase=float((phase + np.pi) % (2.0 * np.pi) - np.pi),
        offset=float(offset), t0=float(t[0]),
        frequency_hz_std=float(std[2] / (2.0 * np.pi)), omega_std=float(std[2]),
        zeta_std=float(std[1]), amplitude_std=float(std[0]), phase_std=float(std[3]),
        offset_std=float(std[4]), rms_residual=float(np.sqrt(np.mean(residual**2))),
        samples=int(t.size))


def record_window(t_all: np.ndarray, y_all: np.ndarray, start, stop):
    """(t, y, dt): the samples of ``t_all`` (n,) s and ``y_all`` (n, ...) with
    start <= t <= stop (s; None for the record's ends), and their uniform step (s);
    ValueError naming what is wrong."""
    lo = t_all[0] if start is None else checked_scalar("start", start)
    hi = t_all[-1] if stop is None else checked_scalar("stop", stop)
    if hi <= lo:
        raise ValueError(f"stop: must be greater than start ({hi!r} <= {lo!r})")
    keep = (t_all >= lo) & (t_all <= hi)
    if np.count_nonzero(keep) < MIN_SAMPLES:
        raise ValueError(f"time: {np.count_nonzero(keep)} samples in [start, stop], need at "
                         f"least {MIN_SAMPLES}")
    t = t_all[keep]
    return t, y_all[keep], uniform_step("time", t)


def _check_periods(omega: float, zeta: float, duration: float) -> None:
    """ValueError when fewer than MIN_PERIODS damped periods fit in ``duration`` (s)."""
    periods = omega * np.sqrt(max(1.0 - zeta**2, 0.0)) * duration / (2.0 * np.pi)
    if periods < MIN_PERIODS:
        raise ValueError(f"time: [start, stop] holds {periods:.2f} periods of the fitted mode, "
                         f"need at least {MIN_PERIODS}")


def _pencil_guess(y: np.ndarray, dt: float) -> tuple[float, float, float, float, float]:
    """(amplitude, zeta, omega rad/s, phase rad, offset) of the dominant oscillating pole of
    the uniformly sampled ``y`` (n,) with step ``dt`` (s), time measured from the first
    sample. Records longer than PENCIL_MAX_SAMPLES are block-averaged first, which keeps
    every exponential an exponential (pole z -> z^q, amplitude times the block gain)."""
    mean = float(np.mean(y))
    centred = y - mean
    q = block_size(centred)
    m = centred.size // q
    blocks = centred[:m * q].reshape(m, q).mean(axis=1)
    pole, coefficient = _dominant_pole(blocks, pencil_poles(blocks))
    s = np.log(pole) / (q * dt)  # -zeta omega + i omega_d, 1/s
    omega = float(np.abs(s))
    zeta = float(-s.real / omega)
    gain = np.mean(np.exp(s * dt * np.arange(q)))
    c0 = coefficient / gain
    return 2.0 * float(np.abs(c0)), zeta, omega, float(np.angle(c0)), mean


def block_size(y: np.ndarray) -> int:
    """Samples per block so that the pencil sees at most ~PENCIL_MAX_SAMPLES samples and at
    least PENCIL_MIN_SAMPLES_PER_PERIOD per period of the spectral peak of ``y`` (n,)."""
    n = y.size
    wanted = int(np.ceil(n / PENCIL_MAX_SAMPLES))
    if wanted <= 1:
        return 1
    spectrum = np.abs(np.fft.rfft(y))
    peak = int(np.argmax(spectrum[1:])) + 1  # cycles per record
    return max(1, min(wanted, n // (peak * PENCIL_MIN_SAMPLES_PER_PERIOD)))


def pencil_poles(y: np.ndarray) -> np.ndarray:
    """Poles z_k (complex, (order,)) of y[n] ~ sum_k c_k z_k^n, ``y`` (n,) or (n, channels)
    sharing the poles, by the SVD matrix pencil (Sarkar & Pereira 1995, eqs. 21-24; the
    channels' Hankel matrices stacked), pencil parameter L = n / 3."""
    y = y[:, None] if y.ndim == 1 else y
    n = y.shape[0]
    pencil = max(n // 3, 2)
    hankel = np.concatenate([np.lib.stride_tricks.sliding_window_view(column, pencil + 1)
                             for column in y.T])  # (channels (n - L), L + 1)
    _, singular, vh = np.linalg.svd(hankel, full_matrices=False)
    if singular[0] <= 0.0:
        raise ValueError("signal: no oscillating pole found (constant signal)")
    order = int(np.count_nonzero(singular > PENCIL_SINGULAR_RTOL * singular[0]))
    order = min(max(order, PENCIL_MIN_ORDER), PENCIL_MAX_ORDER, pencil, singular.size)
    v = vh[:order]  # (order, L + 1): the signal row space
    # v[:, 1:] = T D T^-1 v[:, :-1] with D = diag(z_k) (shift invariance of the Vandermonde)
    return np.linalg.eigvals(v[:, 1:] @ np.linalg.pinv(v[:, :-1]))


def _dominant_pole(y: np.ndarray, poles: np.ndarray) -> tuple[complex, complex]:
    """(z, c) of the oscillating pole (positive frequency, at least one cycle per record)
    whose term c z^n carries the most energy over ``y`` (n,); c by linear least squares."""
    n = y.size
    magnitude = np.abs(poles)
    poles = poles[(magnitude > 1e-12) & (magnitude < np.exp(5.0 / n))]
    if poles.size == 0:
        raise ValueError("signal: no oscillating pole found")
    powers = poles[None, :] ** np.arange(n)[:, None]  # (n, order)
    coefficients = np.linalg.lstsq(powers, y.astype(complex), rcond=None)[0]
    energy = np.abs(coefficients)**2 * np.sum(np.abs(powers)**2, axis=0)
    angle = np.angle(poles)
    oscillating = (angle >= 2.0 * np.pi / n) & (angle < np.pi * (1.0 - 1e-6))
    if not np.any(oscillating):
        raise ValueError("signal: no oscillating pole found")
    best = int(np.argmax(np.where(oscillating, energy, -1.0)))
    return complex(poles[best]), complex(coefficients[best])


def _model(p: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Damped cosine (n,) at ``tau`` (n,) s, p = (amplitude, zeta, omega, phase, offset)."""
    amplitude, zeta, omega, phase, offset = p
    wd = omega * np.sqrt(1.0 - zeta**2)
    return offset + amplitude * np.exp(-zeta * omega * tau) * np.cos(wd * tau + phase)


def _jacobian(p: np.ndarray, tau: np.ndarray, y: np.ndarray | None = None) -> np.ndarray:
    """d model / d p (n, 5) at ``tau`` (n,) s (``y`` unused; least_squares passes it)."""
    amplitude, zeta, omega, phase, _ = p
    root = np.sqrt(1.0 - zeta**2)
    envelope = np.exp(-zeta * omega * tau)
    theta = omega * root * tau + phase
    cos, sin = envelope * np.cos(theta), envelope * np.sin(theta)
    return np.column_stack([
        cos,
        amplitude * tau * omega * (-cos + zeta / root * sin),
        amplitude * tau * (-zeta * cos - root * sin),
        -amplitude * sin,
        np.ones_like(tau)])


def _refine(tau: np.ndarray, y: np.ndarray, guess) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares (params (5,), standard errors (5,), residuals (n,)) of the damped cosine
    on ``y`` (n,) at ``tau`` (n,) s from ``guess`` (amplitude, zeta, omega, phase, offset)."""
    x0 = np.array(guess, dtype=float)
    x0[0] = max(x0[0], 1e-300)
    x0[1] = np.clip(x0[1], ZETA_BOUNDS[0] + 1e-9, ZETA_BOUNDS[1] - 1e-9)
    lower = [0.0, ZETA_BOUNDS[0], 0.0, -np.inf, -np.inf]
    upper = [np.inf, ZETA_BOUNDS[1], np.inf, np.inf, np.inf]
    result = least_squares(lambda p: _model(p, tau) - y, x0, jac=lambda p: _jacobian(p, tau),
                           bounds=(lower, upper), method="trf", x_scale="jac",
                           xtol=1e-12, ftol=1e-12, gtol=1e-12)
    residual = result.fun
    jac = _jacobian(result.x, tau)
    scale = np.linalg.norm(jac, axis=0)
    scale[scale == 0.0] = 1.0
    scaled = jac / scale
    s2 = float(residual @ residual) / (y.size - 5)
    try:
        cov = s2 * np.linalg.inv(scaled.T @ scaled) / np.outer(scale, scale)
        std = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:
        std = np.full(5, np.nan)
    return result.x, std, residual


# ------------------------------------------------------------------ slosh oscillator

def pulse_response(time, acceleration, omega: float,
                   zeta: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Relative motion of a unit slosh mass on a spring driven by the tank acceleration,
    xdd + 2 zeta omega xd + omega^2 x = -a(t), from rest at time[0].

    ``time`` (n,) s strictly increasing (uniform steps share one discretisation);
    ``acceleration`` a (n,) m/s^2, taken piecewise linear between samples (first-order hold,
    exact for that input); ``omega`` (rad/s) > 0; ``zeta`` (-) finite.
    Returns x (n,) m, xdot (n,) m/s and xddot (n,) m/s^2, the last from the ODE itself.
    """
    t = checked_time("time", time)
    a = _series("acceleration", acceleration, t.size)
    w = checked_scalar("omega", omega, positive=True)
    z = checked_scalar("zeta", zeta)
    system = np.array([[0.0, 1.0], [-w * w, -2.0 * z * w]])
    steps = np.diff(t)
    mean_step = (t[-1] - t[0]) / (t.size - 1)
    uniform = np.max(np.abs(steps - mean_step)) <= SPACING_RTOL * mean_step
    shared = _first_order_hold(system, mean_step) if uniform else None
    state = np.zeros((t.size, 2))
    for i in range(1, t.size):
        phi, g0, g1 = shared if uniform else _first_order_hold(system, steps[i - 1])
        state[i] = phi @ state[i - 1] + g0 * a[i - 1] + g1 * a[i]
    x, xdot = state[:, 0], state[:, 1]
    return x, xdot, -a - 2.0 * z * w * xdot - w * w * x


def _first_order_hold(system: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray,
                                                              np.ndarray]:
    """(Phi (2, 2), g0 (2,), g1 (2,)) with s_{k+1} = Phi s_k + g0 u_k + g1 u_{k+1} for
    sd = system s + (0, -1) u, u linear over the step ``dt`` (s) (Franklin, Powell &
    Workman, Digital Control of Dynamic Systems, triangle-hold equivalent)."""
    block = np.zeros((4, 4))
    block[:2, :2] = system * dt
    block[:2, 2] = np.array([0.0, -1.0]) * dt
    block[2, 3] = 1.0
    e = expm(block)
    return e[:2, :2], e[:2, 2] - e[:2, 3], e[:2, 3]


# ------------------------------------------------------------------ mechanical model

@dataclass(frozen=True)
class MechanicalModel:
    """NASA SP-106 (Abramson 1966, ch. 6) spring-mass equivalent of the first slosh mode.

    Masses in kg, heights (z in the tank frame, tank centre at 0) in m: the fixed mass
    ``fixed_mass`` at ``fixed_mass_height`` moves with the tank; the slosh mass
    ``slosh_mass`` at ``slosh_mass_height`` rides a spring of stiffness ``spring_stiffness``
    (N/m) with natural frequency ``omega`` (rad/s) = 2 pi ``frequency_hz`` and damping ratio
    ``zeta``. The pendulum equivalent has length ``pendulum_length`` = g / omega^2 (m),
    hinged at ``hinge_height`` = slosh_mass_height + pendulum_length (m).
    ``slosh_mass_std`` (kg) and ``slosh_mass_height_std`` (m) are standard errors from the
    regression residuals; ``force_residual`` and ``moment_residual`` are the rms residuals
    of the two regressions over the rms of their targets (-).
    """

    total_mass: float
    centre_height: float
    slosh_mass: float
    slosh_mass_fraction: float
    slosh_mass_height: float
    fixed_mass: float
    fixed_mass_height: float
    spring_stiffness: float
    pendulum_length: float
    hinge_height: float
    omega: float
    frequency_hz: float
    zeta: float
    slosh_mass_std: float
    slosh_mass_height_std: float
    force_residual: float
    moment_residual: float
    other_slosh_mass: tuple = ()
    other_slosh_mass_height: tuple = ()


def equivalent_model(time, acceleration, force_x, moment_y, total_mass: float,
                     centre_height: float, gravity: float, fit, others=()) -> MechanicalModel:
    """Spring-mass equivalent of the first slosh mode from a lateral-excitation record.

    ``time`` (n,) s strictly increasing; ``acceleration`` a (n,) m/s^2 the tank's lateral
    acceleration along x; ``force_x`` F_x (n,) N and ``moment_y`` M_y (n,) N m the contents'
    force on the tank and its moment about the tank centre; ``total_mass`` (kg) > 0;
    ``centre_height`` (m) z of the contents' centre of mass at rest; ``gravity`` g (m/s^2)
    > 0; ``fit`` the first mode (a :class:`DecayFit` or :class:`fsi.slosh.modes.Mode`: its
    omega and zeta are used); ``others`` further modes of the same record, each with its
    own slosh mass (SP-106's m_n) regressed together with the first.

    With x_j the unit response of mode j (:func:`pulse_response`),
    F_x = -M a - sum_j m_j xdd_j and M_y = -a M z_c - sum_j m_j (h_j xdd_j - g x_j): the
    m_j by linear least squares of (F_x + M a) on (-xdd_j), then the m_j h_j of
    (M_y + a M z_c - g sum_j m_j x_j) on (-xdd_j), over all samples; the fixed mass is
    M - sum_j m_j. For a mode whose motion is along a direction phi from x, m_j is its x
    share, m cos^2 phi. Raises ValueError on bad input or a first slosh mass outside
    (0, total_mass), or slosh masses summing above it.
    """
    t = checked_time("time", time, minimum=3)
    a = _series("acceleration", acceleration, t.size)
    fx = _series("force_x", force_x, t.size)
    my = _series("moment_y", moment_y, t.size)
    mass = checked_scalar("total_mass", total_mass, positive=True)
    zc = checked_scalar("centre_height", centre_height)
    g = checked_scalar("gravity", gravity, positive=True)
    for name, mode in [("fit", fit)] + [("others", m) for m in others]:
        if not (hasattr(mode, "omega") and hasattr(mode, "zeta")):
            raise ValueError(f"{name}: must be a fitted mode (omega, zeta), got "
                             f"{type(mode).__name__}")
    responses = [pulse_response(t, a, mode.omega, mode.zeta) for mode in [fit, *others]]
    x = np.column_stack([r[0] for r in responses])
    xdd = np.column_stack([r[2] for r in responses])
    masses, mass_std, force_residual = _regress(fx + mass * a, -xdd)
    m1 = masses[0]
    if not 0.0 < m1 < mass or masses.sum() >= mass:
        raise ValueError(f"force_x: fitted slosh mass {m1:.6g} kg (all modes "
                         f"{masses.sum():.6g} kg) is not in (0, total_mass = {mass:.6g} kg)")
    moments, moment_std, moment_residual = _regress(my + a * mass * zc - g * (x @ masses),
                                                    -xdd)
    heights = moments / masses
    h1 = heights[0]
    m0 = mass - masses.sum()
    length = g / fit.omega**2
    return MechanicalModel(
        total_mass=mass, centre_height=zc, slosh_mass=m1, slosh_mass_fraction=m1 / mass,
        slosh_mass_height=h1, fixed_mass=m0,
        fixed_mass_height=(mass * zc - masses @ heights) / m0,
        spring_stiffness=m1 * fit.omega**2, pendulum_length=length, hinge_height=h1 + length,
        omega=fit.omega, frequency_hz=fit.frequency_hz, zeta=fit.zeta,
        slosh_mass_std=float(mass_std[0]), slosh_mass_height_std=float(moment_std[0] / abs(m1)),
        force_residual=force_residual, moment_residual=moment_residual,
        other_slosh_mass=tuple(float(v) for v in masses[1:]),
        other_slosh_mass_height=tuple(float(v) for v in heights[1:]))


def _regress(target: np.ndarray, regressors: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                   float]:
    """(coefficients (m,), their standard errors (m,), rms residual / rms target) of
    target (n,) ~ regressors (n, m) @ c; ValueError when a regressor is zero (no slosh
    excited)."""
    regressors = regressors.reshape(target.size, -1)
    if np.any(np.sum(regressors**2, axis=0) <= 0.0):
        raise ValueError("acceleration: excites no slosh response (unit response is zero)")
    coefficients = np.linalg.lstsq(regressors, target, rcond=None)[0]
    residual = target - regressors @ coefficients
    rss = float(residual @ residual)
    dof = max(target.size - regressors.shape[1], 1)
    std = np.sqrt(np.clip(np.diag(rss / dof * np.linalg.pinv(regressors.T @ regressors)),
                          0.0, None))
    total = float(target @ target)
    relative = float(np.sqrt(rss / total)) if total > 0.0 else 0.0
    return coefficients, std, relative


def stokes_layer(viscosity: float, density: float, omega: float) -> float:
    """Thickness (m) of the oscillating boundary layer on a wall, delta = (2 nu / omega)^1/2
    (Stokes' second problem; Landau & Lifshitz, Fluid Mechanics, section 24), for a dynamic
    viscosity (Pa s), a density (kg/m^3) and an angular frequency (rad/s). A slosh mode's
    physical damping at low viscosity is the dissipation in this layer (NASA SP-106, ch. 4);
    a grid whose cells are much thicker than it does not resolve that damping."""
    viscosity = checked_scalar("viscosity", viscosity)
    if viscosity < 0.0:
        raise ValueError(f"viscosity: must be >= 0 Pa s, got {viscosity!r}")
    density = checked_scalar("density", density, positive=True)
    omega = checked_scalar("omega", omega, positive=True)
    return float(np.sqrt(2.0 * viscosity / (density * omega)))
