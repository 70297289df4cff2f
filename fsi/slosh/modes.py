"""Several lateral modes at once from a free decay of two channels (the contents' centre of
mass along x and y): a folded diaphragm is not axisymmetric, so the pair of lateral modes
that a symmetric tank holds at one frequency splits in two, each along its own direction,
and an x pulse excites both. A single damped cosine fitted to such a beat returns a
frequency between the two and a damping ratio inflated by the beat (measured: N = 14, half
fill, 7.03 Hz and zeta 0.094 where the modes are 7.00 and 8.92 Hz with zeta 0.037 and 0.041).

Model, for channels c = 1..k and modes j = 1..m, tau = t - t0:

    y_c(t) = o_c + sum_j exp(-zeta_j omega_j tau) (C_jc cos(omega_dj tau) + S_jc sin(omega_dj tau))

with omega_dj = omega_j sqrt(1 - zeta_j^2): every channel shares the modes' poles. The poles
come from the multi-channel matrix pencil (the channels' Hankel matrices stacked; Hua &
Sarkar 1990), the modes kept are the oscillating poles whose amplitude over the channels is
at least ``MODE_MIN_FRACTION`` of the largest; all parameters are then refined together by
``scipy.optimize.least_squares`` and their standard errors taken from s^2 (J^T J)^-1.
A mode's direction is the angle of its motion in the x-y plane from +x (degrees, in
(-90, 90]); its x amplitude sqrt(C_x^2 + S_x^2).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from fsi.slosh.analysis import (MIN_PERIODS, ZETA_BOUNDS, block_size, checked_time,
                                pencil_poles, record_window)

MODE_MIN_FRACTION = 0.2
"""A pole is a mode when its amplitude (over the channels) is at least this fraction of the
largest oscillating pole's."""
MODE_MAX = 4
"""Most modes fitted together."""
MODE_MAX_ZETA = 0.3
"""A fitted pole damped more than this loses 85 % of its amplitude within one period: the
centre of mass settling to a new offset (a diaphragm's folds after the pulse), not a slosh
mode. It stays in the fit and in :attr:`ModeFit.modes`; the first mode is the lowest below it
(measured: the Table 4.1 diaphragm with E / 10, N = 14, half fill, a pole at 1.47 Hz with
zeta = 0.75 under the 2.18 Hz mode with zeta = 0.010)."""


@dataclass(frozen=True)
class Mode:
    """One mode of a :class:`ModeFit`: natural frequency ``frequency_hz`` (Hz) and ``omega``
    (rad/s), damping ratio ``zeta`` (-), with standard errors; ``amplitude`` (k,) and
    ``phase`` (k,) rad per channel at t0 (signal units), ``amplitude_std`` (k,) their
    standard errors; ``direction_deg`` the direction of its motion from the first channel's
    axis towards the second's (degrees)."""

    frequency_hz: float
    omega: float
    zeta: float
    frequency_hz_std: float
    omega_std: float
    zeta_std: float
    amplitude: np.ndarray
    phase: np.ndarray
    amplitude_std: np.ndarray
    direction_deg: float


@dataclass(frozen=True)
class ModeFit:
    """The modes of a free decay by ascending frequency, the channels' ``offset`` (k,),
    ``t0`` (s), ``rms_residual`` (signal units) and the number of ``samples`` used."""

    modes: tuple[Mode, ...]
    offset: np.ndarray
    t0: float
    rms_residual: float
    samples: int

    @property
    def first(self) -> Mode:
        """The lowest-frequency slosh mode: damping ratio under ``MODE_MAX_ZETA``."""
        return next(mode for mode in self.modes if _is_slosh(mode))


def fit_modes(time, signals, start: float | None = None, stop: float | None = None) -> ModeFit:
    """The modes of the free decay ``signals`` (n, k) (or (n,)) sampled at ``time`` (n,) s,
    uniformly spaced over [start, stop] (s, default the record's ends).

    Raises ValueError with fewer than MIN_SAMPLES samples or MIN_PERIODS periods of the
    first (slosh) mode in [start, stop] (stop after start), non-uniform sampling, no
    oscillating pole, or none damped less than ``MODE_MAX_ZETA``."""
    t_all = checked_time("time", time)
    y_all = np.asarray(signals, dtype=float)
    y_all = y_all[:, None] if y_all.ndim == 1 else y_all
    if y_all.ndim != 2 or y_all.shape[0] != t_all.size or not np.all(np.isfinite(y_all)):
        raise ValueError(f"signals: must be finite, (n,) or (n, k) with n = {t_all.size} "
                         f"samples, got shape {np.shape(signals)}")
    t, y, dt = record_window(t_all, y_all, start, stop)
    tau = t - t[0]
    poles = _mode_poles(y, dt)
    params, std, residual = _refine(tau, y, poles)
    m = len(poles)
    modes = sorted((_mode(params, std, j, m, y.shape[1]) for j in range(m)),
                   key=lambda mode: mode.omega)
    slosh = [mode for mode in modes if _is_slosh(mode)]
    if not slosh:
        raise ValueError(f"signals: no slosh mode, every fitted pole is damped at zeta >= "
                         f"{MODE_MAX_ZETA} ({', '.join(f'{m.zeta:.2f}' for m in modes)})")
    duration = tau[-1]
    periods = slosh[0].omega * np.sqrt(1 - slosh[0].zeta**2) * duration / (2 * np.pi)
    if periods < MIN_PERIODS:
        raise ValueError(f"time: [start, stop] holds {periods:.2f} periods of the first mode, "
                         f"need at least {MIN_PERIODS}")
    return ModeFit(tuple(modes), params[2 * m + 2 * m * y.shape[1]:], float(t[0]),
                   float(np.sqrt(np.mean(residual**2))), int(t.size))


def _is_slosh(mode: Mode) -> bool:
    """A slosh mode, not the centre of mass settling: damped at zeta < ``MODE_MAX_ZETA``."""
    return mode.zeta < MODE_MAX_ZETA


def _mode_poles(y: np.ndarray, dt: float) -> list[complex]:
    """Continuous poles s = -zeta omega + i omega_d (1/s) of the modes of ``y`` (n, k)."""
    centred = y - y.mean(axis=0)
    q = block_size(centred[:, int(np.argmax(np.ptp(centred, axis=0)))])
    n = centred.shape[0] // q
    blocks = centred[:n * q].reshape(n, q, -1).mean(axis=1)
    z = pencil_poles(blocks)
    magnitude = np.abs(z)
    z = z[(magnitude > 1e-12) & (magnitude < np.exp(5.0 / n))]
    angle = np.angle(z)
    z = z[(angle >= 2 * np.pi / n) & (angle < np.pi * (1 - 1e-6))]
    if z.size == 0:
        raise ValueError("signals: no oscillating pole found")
    powers = z[None, :] ** np.arange(n)[:, None]
    everything = np.concatenate([powers, powers.conj(), np.ones((n, 1))], axis=1)
    coefficients = np.linalg.lstsq(everything, blocks.astype(complex), rcond=None)[0]
    size = np.sqrt(np.sum(np.abs(coefficients[:z.size])**2, axis=1)
                   * np.sum(np.abs(powers)**2, axis=0))
    order = np.argsort(-size)
    kept = [j for j in order if size[j] >= MODE_MIN_FRACTION * size[order[0]]][:MODE_MAX]
    return [complex(np.log(z[j]) / (q * dt)) for j in kept]


def _unpack(p: np.ndarray, m: int, k: int):
    omega, zeta = p[:m], p[m:2 * m]
    c = p[2 * m:2 * m + m * k].reshape(m, k)
    s = p[2 * m + m * k:2 * m + 2 * m * k].reshape(m, k)
    return omega, zeta, c, s, p[2 * m + 2 * m * k:]


def _basis(omega, zeta, tau):
    """(envelope * cos, envelope * sin, omega_d) of every mode, (n, m)."""
    wd = omega * np.sqrt(1.0 - zeta**2)
    envelope = np.exp(-np.outer(tau, zeta * omega))
    phase = np.outer(tau, wd)
    return envelope * np.cos(phase), envelope * np.sin(phase), wd


def _model(p, tau, m, k):
    omega, zeta, c, s, offset = _unpack(p, m, k)
    cos, sin, _ = _basis(omega, zeta, tau)
    return (cos @ c + sin @ s + offset).ravel()


def _jacobian(p, tau, m, k):
    """d model / d p ((n k), len(p)), channels fastest."""
    omega, zeta, c, s, _ = _unpack(p, m, k)
    cos, sin, wd = _basis(omega, zeta, tau)
    root = np.sqrt(1.0 - zeta**2)
    n = tau.size
    jac = np.zeros((n, k, p.size))
    for j in range(m):
        shape = np.outer(cos[:, j], c[j]) + np.outer(sin[:, j], s[j])  # (n, k)
        turn = np.outer(-sin[:, j], c[j]) + np.outer(cos[:, j], s[j])  # d/d(phase)
        t = tau[:, None]
        jac[:, :, j] = -zeta[j] * t * shape + root[j] * t * turn
        jac[:, :, m + j] = -omega[j] * t * shape - zeta[j] / root[j] * omega[j] * t * turn
        for ch in range(k):
            jac[:, ch, 2 * m + j * k + ch] = cos[:, j]
            jac[:, ch, 2 * m + m * k + j * k + ch] = sin[:, j]
    for ch in range(k):
        jac[:, ch, 2 * m + 2 * m * k + ch] = 1.0
    return jac.reshape(n * k, p.size)


def _refine(tau, y, poles):
    """Least squares of every parameter from the pencil's ``poles``: (params, standard
    errors, residuals (n k,))."""
    n, k = y.shape
    m = len(poles)
    omega = np.array([abs(s) for s in poles])
    zeta = np.clip([-s.real / abs(s) for s in poles], ZETA_BOUNDS[0] + 1e-9,
                   ZETA_BOUNDS[1] - 1e-9)
    cos, sin, _ = _basis(omega, zeta, tau)
    linear = np.linalg.lstsq(np.hstack([cos, sin, np.ones((n, 1))]), y, rcond=None)[0]
    x0 = np.concatenate([omega, zeta, linear[:m].ravel(), linear[m:2 * m].ravel(), linear[-1]])
    lower = np.full(x0.size, -np.inf)
    upper = np.full(x0.size, np.inf)
    lower[:m], lower[m:2 * m], upper[m:2 * m] = 0.0, ZETA_BOUNDS[0], ZETA_BOUNDS[1]
    target = y.ravel()
    result = least_squares(lambda p: _model(p, tau, m, k) - target, x0,
                           jac=lambda p: _jacobian(p, tau, m, k), bounds=(lower, upper),
                           method="trf", x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12)
    jac = _jacobian(result.x, tau, m, k)
    scale = np.linalg.norm(jac, axis=0)
    scale[scale == 0.0] = 1.0
    s2 = float(result.fun @ result.fun) / max(target.size - x0.size, 1)
    try:
        scaled = jac / scale
        cov = s2 * np.linalg.inv(scaled.T @ scaled) / np.outer(scale, scale)
        std = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:
        std = np.full(x0.size, np.nan)
    return result.x, std, result.fun


def _mode(p, std, j, m, k) -> Mode:
    omega, zeta, c, s, _ = _unpack(p, m, k)
    _, _, c_std, s_std, _ = _unpack(std, m, k)
    amplitude = np.hypot(c[j], s[j])
    amplitude_std = np.hypot(c[j] * c_std[j], s[j] * s_std[j]) / np.maximum(amplitude, 1e-300)
    phase = np.arctan2(-s[j], c[j])
    direction = 0.0
    if k >= 2:
        along = np.sign(np.cos(phase[1] - phase[0])) or 1.0
        direction = float(np.degrees(np.arctan2(along * amplitude[1], amplitude[0])))
        direction = direction - 180.0 if direction > 90.0 else direction
        direction = direction + 180.0 if direction <= -90.0 else direction
    return Mode(frequency_hz=float(omega[j] / (2 * np.pi)), omega=float(omega[j]),
                zeta=float(zeta[j]), frequency_hz_std=float(std[j] / (2 * np.pi)),
                omega_std=float(std[j]), zeta_std=float(std[m + j]), amplitude=amplitude,
                phase=phase, amplitude_std=amplitude_std, direction_deg=direction)
