"""What the tank feels from a slosh record: force, moment and centre of mass from the liquid's
momentum, and the first mode's analysis (:mod:`fsi.slosh_analysis`).

For the contents of mass M in the tank frame, with body acceleration b(t) = g - a(t),
momentum P(t) and angular momentum L(t) about the tank centre (:mod:`fluid.measures`):

    F(t)     = M b(t) - dP/dt                          force on the tank (N)
    M_c(t)   = x_c(t) x M b(t) - dL/dt                 moment about the tank centre (N m)
    x_c(t)   = x_c(0) + (1/M) int_0^t P dt             centre of mass (m)

(Newton's second law for the contents: the tank's force on them is dP/dt - M b). The
derivatives are central differences of the per-window samples (one-sided at the ends), the
integral the trapezoidal rule; x_c(0) is the static start's centre of mass.
"""
from __future__ import annotations

import logging
from dataclasses import asdict

import numpy as np

from .slosh_analysis import equivalent_model, fit_free_decay

log = logging.getLogger(__name__)


def contents_response(time: np.ndarray, body: np.ndarray, momentum: np.ndarray,
                      angular_momentum: np.ndarray, mass: float,
                      centre_start: np.ndarray) -> dict:
    """{"force" (n, 3) N, "moment" (n, 3) N m, "centre_of_mass" (n, 3) m} from the samples at
    ``time`` (n,) s (t = 0 first) of b (n, 3) m/s^2, P (n, 3) kg m/s and L (n, 3) kg m^2/s
    of contents of ``mass`` (kg) whose centre of mass starts at ``centre_start`` (3,) m."""
    time = np.asarray(time, dtype=float)
    if len(time) < 2:
        raise ValueError("a slosh response needs at least two samples")
    rate_p = np.gradient(momentum, time, axis=0)
    rate_l = np.gradient(angular_momentum, time, axis=0)
    steps = np.diff(time)[:, None]
    shift = np.concatenate([np.zeros((1, 3)),
                            np.cumsum(0.5 * steps * (momentum[1:] + momentum[:-1]), axis=0)])
    centre = np.asarray(centre_start, dtype=float) + shift / mass
    force = mass * body - rate_p
    moment = np.cross(centre, mass * body) - rate_l
    return dict(force=force, moment=moment, centre_of_mass=centre)


def first_mode(time: np.ndarray, acceleration_x: np.ndarray, centre_x: np.ndarray,
               force_x: np.ndarray, moment_y: np.ndarray, mass: float, centre_height: float,
               gravity: float, radius: float, start: float) -> dict:
    """The first lateral mode from a free decay after ``start`` (s): the fit of the centre
    of mass's x (frequency, damping ratio, their standard errors), lambda1 = omega^2 R / g
    and the spring-mass equivalent (NASA SP-106) from the force and moment over the whole
    record. Returns the attrs; ``analysis_failure`` says what failed: no fittable decay (no
    values), or the spring-mass equivalent only (the decay's values kept)."""
    try:
        fit = fit_free_decay(time, centre_x, start=start)
    except ValueError as err:
        log.warning("no first-mode analysis: %s", err)
        return dict(analysis_failure=str(err))
    out = dict(omega=float(fit.omega), frequency_hz=float(fit.frequency_hz),
               zeta=float(fit.zeta), lambda1=float(fit.omega**2 * radius / gravity),
               lambda1_std=float(2 * fit.omega * fit.omega_std * radius / gravity),
               frequency_hz_std=float(fit.frequency_hz_std), zeta_std=float(fit.zeta_std),
               centre_of_mass_amplitude=abs(float(fit.amplitude)),
               centre_of_mass_amplitude_std=float(fit.amplitude_std),
               fit_samples=int(fit.samples), fit_rms_residual=float(fit.rms_residual),
               analysis_failure="")
    try:
        model = equivalent_model(time, acceleration_x, force_x, moment_y, mass, centre_height,
                                 gravity, fit)
    except ValueError as err:
        log.warning("no spring-mass equivalent (the decay's frequency and damping are kept): "
                    "%s", err)
        out["analysis_failure"] = f"spring-mass equivalent: {err}"
        return out
    out.update({k: float(v) for k, v in asdict(model).items()})
    return out
