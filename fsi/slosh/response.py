"""What the tank feels from a slosh record: force, moment and centre of mass from the liquid's
momentum, and the first mode's analysis (:mod:`fsi.slosh.analysis`).

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

from fsi.slosh.analysis import equivalent_model
from fsi.slosh.modes import fit_modes

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


def first_mode(time: np.ndarray, acceleration_x: np.ndarray, centre: np.ndarray,
               force_x: np.ndarray, moment_y: np.ndarray, mass: float, centre_height: float,
               gravity: float, radius: float, start: float) -> dict:
    """The lateral modes from a free decay after ``start`` (s): the fit of the centre of
    mass's x and y, ``centre`` (n, 2) m (or (n,) for x alone; :func:`fsi.slosh.modes.fit_modes`),
    the first mode's (the lowest slosh mode, :attr:`fsi.slosh.modes.ModeFit.first`) frequency,
    damping ratio, their standard errors and
    lambda1 = omega^2 R / g, every mode's as ``mode_*`` arrays (ascending frequency, with
    its direction from x in degrees and its x slosh mass), and the spring-mass equivalent
    (NASA SP-106) from the force and moment over the whole record, every fitted mode with
    a slosh mass of its own. Returns the attrs; ``analysis_failure`` says what failed: no
    fittable decay (no values), or the spring-mass equivalent only (the decay's values
    kept)."""
    try:
        fit = fit_modes(time, centre, start=start)
    except ValueError as err:
        log.warning("no first-mode analysis: %s", err)
        return dict(analysis_failure=str(err))
    first = fit.first
    modes = fit.modes
    index = next(i for i, mode in enumerate(modes) if mode is first)
    out = dict(omega=first.omega, frequency_hz=first.frequency_hz, zeta=first.zeta,
               lambda1=float(first.omega**2 * radius / gravity),
               lambda1_std=float(2 * first.omega * first.omega_std * radius / gravity),
               frequency_hz_std=first.frequency_hz_std, zeta_std=first.zeta_std,
               centre_of_mass_amplitude=float(first.amplitude[0]),
               centre_of_mass_amplitude_std=float(first.amplitude_std[0]),
               modes=len(modes), first_mode_index=index,
               mode_frequency_hz=np.array([m.frequency_hz for m in modes]),
               mode_frequency_hz_std=np.array([m.frequency_hz_std for m in modes]),
               mode_zeta=np.array([m.zeta for m in modes]),
               mode_zeta_std=np.array([m.zeta_std for m in modes]),
               mode_direction_deg=np.array([m.direction_deg for m in modes]),
               fit_samples=fit.samples, fit_rms_residual=fit.rms_residual,
               analysis_failure="")
    try:
        model = equivalent_model(time, acceleration_x, force_x, moment_y, mass, centre_height,
                                 gravity, first, others=[m for m in modes if m is not first])
    except ValueError as err:
        log.warning("no spring-mass equivalent (the decay's frequency and damping are kept): "
                    "%s", err)
        out["analysis_failure"] = f"spring-mass equivalent: {err}"
        return out
    values = asdict(model)
    others, heights = values.pop("other_slosh_mass"), values.pop("other_slosh_mass_height")
    out.update({k: float(v) for k, v in values.items()})
    # the mode_* arrays keep ascending frequency
    out.update(mode_slosh_mass=np.insert(np.asarray(others, float), index, model.slosh_mass),
               mode_slosh_mass_height=np.insert(np.asarray(heights, float), index,
                                                model.slosh_mass_height))
    return out
