"""Equilibria of the shell of revolution by Newton's method on the exact Hessian.

**Pressure control** (no volume target: mu = p - p_ref held). The equilibrium is a stationary
point of Pi(x; mu) over the admissible states x = x_held + T y
(:mod:`~structure.axisymmetric.supports`): Newton steps K dy = -g (K = T^T Pi_xx T,
g = T^T Pi_x, one SuperLU factorisation each) with a backtracking (Armijo) line search on Pi;
where the step is not a descent direction (K not positive definite: a start far from the
equilibrium, a flat membrane without bending) K is shifted by tau diag|K|, tau growing tenfold,
until it is (Levenberg-Marquardt).

**Volume control** (a volume target: the liquid's, or the enclosed V_b). The multiplier mu is
an unknown, and (y, mu) a stationary point of L = Pi(x; 0) - mu (V_b(x) - V_b*). The bordered
Newton step

    [ K      -v ] [dy]   = -[ g      ]      v = T^T dV_b/dx,
    [ -v^T    0 ] [dmu]     [ V_b* - V_b ]

is solved by SuperLU of the bordered matrix itself (Crisfield, *Non-linear finite element
analysis of solids and structures*, 1991, ch. 9, borders K the same way): it stays regular
where K is singular, at a limit point of the pressure, and near one, where the Schur
complement's two solves with K (K a = -g, K b = v, dmu = (V_b* - V_b - v . a) / (v . b))
would lose the step to cancellation. The line search backtracks on the l1 merit
Pi(x; 0) + nu |V_b - V_b*|, nu = 2 |mu| (Nocedal & Wright, *Numerical Optimization*, 2006,
sec. 18.3), as the 3-D Newton statics do (:mod:`structure.newton.statics`); where the step does
not descend it (the Hessian is not positive definite on the constraint's tangent space), K is
shifted by tau diag|K| as above. A constrained minimum is stable under volume control even
where K is indefinite, so volume control passes the pressure's limit points (a balloon beyond
its pressure maximum).

**Convergence.** The residual ||g|| is measured against the larger of the internal and the
external force vectors' norms (their difference is the residual), with |V_b - V_b*| /
(2/3 pi a^3) beside it under volume control; a start beyond the tank wall's barrier is not
converged (its energy is infinite); a solve has converged when that is below
``tolerance``, or, once it is below ``floor``, when a full step moved no node by more than
``step_tolerance`` a: the state is stored in absolute coordinates, so the residual has a
round-off floor of about 1e-16 E / q for a load q per area (1e-7 for a plate at w0 / t =
1e-2), which a small load reaches before ``tolerance``. Quadratic convergence is the exact
Hessian's: the recorded residuals fall as r_(k+1) ~ C r_k^2.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .energy import Evaluation, evaluate
from .loads import AxisymmetricLoad, enclosed_target, lower_hemisphere
from .meridian import R, Z
from .model import ShellOfRevolution

FORCE_FLOOR = 1e-12
"""The residual's scale never falls below this fraction of E t a (N): a load-free shell at
rest has converged."""


@dataclass(frozen=True)
class NewtonSettings:
    """tolerance : the relative residual to reach (module doc); step_tolerance : or, below
    ``floor`` the relative residual, a full step that moves no node by more than this fraction
    of a (the residual's round-off floor reached: the next step would change no digit that
    matters); max_move : the largest node move of one step, as a fraction of a (a longer step
    is scaled down before the line search); max_iterations : Newton steps; max_halvings :
    line-search halvings of a step; armijo : the line search's sufficient decrease (-)."""

    tolerance: float = 1e-10
    step_tolerance: float = 1e-11
    floor: float = 1e-6
    max_move: float = 0.1
    max_iterations: int = 60
    max_halvings: int = 40
    armijo: float = 1e-4


@dataclass(frozen=True)
class AxisymmetricEquilibrium:
    """An equilibrium: state (4 n,) (:mod:`~structure.axisymmetric.meridian`); pressure p and
    pressure_level p_ref (Pa), held or found; enclosed_volume V_b and liquid_volume
    (m^3); energy Pi (J); iterations; residuals, the relative residual before each step
    (module doc); converged."""

    state: np.ndarray
    pressure: float
    pressure_level: float
    enclosed_volume: float
    liquid_volume: float
    energy: float
    iterations: int
    residuals: tuple
    converged: bool


def _reduced(shell: ShellOfRevolution, ev: Evaluation):
    t = shell.admissible.basis
    scale = max(np.linalg.norm(t.T @ ev.internal), np.linalg.norm(t.T @ ev.external),
                FORCE_FLOOR * shell.material.youngs_modulus * shell.material.thickness
                * shell.radius)
    return t.T @ ev.gradient, scale


def _factor(matrix):
    """SuperLU of ``matrix`` (CSC), or None where it is singular or not finite."""
    try:
        lu = splu(sp.csc_matrix(matrix))
    except RuntimeError:
        return None
    return lu


def _move(shell: ShellOfRevolution, step: np.ndarray) -> float:
    """The largest change of r or z (as a fraction of a) of a free-coordinate ``step``."""
    dx = shell.admissible.basis @ step
    return float(np.abs(dx.reshape(-1, 4)[:, [R, Z]]).max() / shell.radius)


def _capped(shell: ShellOfRevolution, step: np.ndarray, settings: NewtonSettings):
    """(``step`` scaled so that it moves no node by more than ``max_move``, its move)."""
    move = _move(shell, step)
    if move > settings.max_move:
        return step * (settings.max_move / move), settings.max_move
    return step, move


def _done(residuals: list, small_step: bool, settings: NewtonSettings) -> bool:
    return residuals[-1] < settings.tolerance or (small_step and residuals[-1] < settings.floor)


def _descent(hessian: sp.csr_matrix, gradient: np.ndarray) -> np.ndarray:
    """A Newton step, shifted (module doc) until it descends."""
    diagonal = np.abs(hessian.diagonal()) + 1e-300
    tau = 0.0
    for _ in range(40):
        lu = _factor(hessian + tau * sp.diags(diagonal))
        if lu is not None:
            step = lu.solve(-gradient)
            if np.all(np.isfinite(step)) and gradient @ step < 0:
                return step
        tau = 1e-8 if tau == 0 else 10 * tau
    return -gradient / diagonal


def _result(shell, load, state, ev, mu, iterations, residuals, converged):
    hemisphere, _ = lower_hemisphere(shell.radius)
    if load.volume_target is None or load.controlled == "liquid":
        pressure = load.pressure
        level = load.pressure - mu
    else:
        pressure, level = load.pressure_level + mu, load.pressure_level
    return AxisymmetricEquilibrium(state, float(pressure), float(level), ev.volume,
                                   hemisphere - ev.volume, ev.energy, iterations,
                                   tuple(residuals), converged)


def _pressure_controlled(shell, load, state, settings):
    adm, mu = shell.admissible, load.net_pressure
    y = adm.free(state)
    residuals, small_step, converged = [], False, False
    for iteration in range(settings.max_iterations + 1):
        ev = evaluate(shell, load, adm.state(y), mu)
        if ev.hessian is None:                   # beyond the wall's barrier: no equilibrium
            converged = False
            break
        g, scale = _reduced(shell, ev)
        residuals.append(float(np.linalg.norm(g) / scale))
        converged = _done(residuals, small_step, settings)
        if converged or iteration == settings.max_iterations:
            break
        step, move = _capped(shell, _descent(ev.free_hessian, g), settings)
        slope = g @ step
        alpha = 1.0
        if -slope > 1e-12 * max(abs(ev.energy), 1e-300):
            for _ in range(settings.max_halvings):
                trial = evaluate(shell, load, adm.state(y + alpha * step), mu, 0).energy
                if trial <= ev.energy + settings.armijo * alpha * slope:
                    break
                alpha *= 0.5
        y = y + alpha * step
        small_step = alpha == 1.0 and move < settings.step_tolerance
    return _result(shell, load, adm.state(y), ev, mu, iteration, residuals, converged)


def _bordered_step(k, g, v, gap):
    """(dy, dmu) of the bordered system (module doc), ``gap`` = V_b* - V_b, by SuperLU of
    the bordered matrix."""
    vc = sp.csc_matrix(v[:, None])
    lu = _factor(sp.bmat([[k, -vc], [vc.T, None]], format="csc"))
    if lu is None:
        raise np.linalg.LinAlgError("the bordered tangent is singular")
    out = lu.solve(-np.concatenate([g, [-gap]]))
    return out[:-1], out[-1]


def _constrained_step(shell, ev, g, mu, gap, settings):
    """(dy, dmu, nu, slope): the bordered step, shifted (module doc) until it descends the l1
    merit Pi(x; 0) + nu |V_b - V_b*|, nu = 2 |mu + dmu| (its directional derivative is
    ``slope``, Nocedal & Wright sec. 18.3), and capped to ``max_move``."""
    t = shell.admissible.basis
    k, v = ev.free_hessian, t.T @ ev.volume_gradient
    diagonal = sp.diags(np.abs(k.diagonal()) + 1e-300)
    grad0 = g + mu * v                                   # dPi(x; 0)/dy
    tau = 0.0
    for _ in range(40):
        step, dmu = _bordered_step(k + tau * diagonal, g, v, gap)
        nu = 2.0 * abs(mu + dmu) + 1e-300
        slope = grad0 @ step - nu * abs(gap)
        if np.all(np.isfinite(step)) and slope < 0:
            break
        tau = 1e-8 if tau == 0 else 10 * tau
    move = _move(shell, step)
    if move > settings.max_move:
        scale = settings.max_move / move
        step, dmu, slope, move = step * scale, dmu * scale, slope * scale, settings.max_move
    return step, dmu, nu, slope, move


def _volume_controlled(shell, load, state, mu, settings):
    adm = shell.admissible
    target = enclosed_target(load, shell.radius)
    v_scale = lower_hemisphere(shell.radius)[0]
    y = adm.free(state)

    def merit(y, nu):
        ev = evaluate(shell, load, adm.state(y), 0.0, 0)
        return ev.energy + nu * abs(ev.volume - target)

    residuals, small_step, converged = [], False, False
    for iteration in range(settings.max_iterations + 1):
        ev = evaluate(shell, load, adm.state(y), mu)
        if ev.hessian is None:
            converged = False
            break
        g, scale = _reduced(shell, ev)
        residuals.append(float(np.hypot(np.linalg.norm(g) / scale,
                                        (ev.volume - target) / v_scale)))
        converged = _done(residuals, small_step, settings)
        if converged or iteration == settings.max_iterations:
            break
        step, dmu, nu, slope, move = _constrained_step(shell, ev, g, mu, target - ev.volume,
                                                       settings)
        here = merit(y, nu)
        alpha = 1.0
        if -slope > 1e-12 * max(abs(here), 1e-300):
            for _ in range(settings.max_halvings):
                if merit(y + alpha * step, nu) <= here + settings.armijo * alpha * slope:
                    break
                alpha *= 0.5
        y, mu = y + alpha * step, mu + alpha * dmu
        small_step = alpha == 1.0 and move < settings.step_tolerance
    return _result(shell, load, adm.state(y), ev, mu, iteration, residuals, converged)


def equilibrium(shell: ShellOfRevolution, load: AxisymmetricLoad,
                start: Optional[np.ndarray] = None, multiplier: Optional[float] = None,
                settings: NewtonSettings = NewtonSettings()) -> AxisymmetricEquilibrium:
    """The equilibrium of ``shell`` under ``load`` from ``start`` (4 n,) (the rest state by
    default; its held entries are taken from the rest): pressure control without a volume
    target, volume control with one (module doc), ``multiplier`` the starting net pressure mu
    (Pa; the load's by default)."""
    adm = shell.admissible
    state = shell.meridian.rest_state if start is None else adm.state(adm.free(start))
    if load.volume_target is None:
        return _pressure_controlled(shell, load, state, settings)
    mu = load.net_pressure if multiplier is None else multiplier
    return _volume_controlled(shell, load, state, mu, settings)


def _parameter(load: AxisymmetricLoad) -> float:
    return load.net_pressure if load.volume_target is None else load.volume_target


def path(shell: ShellOfRevolution, loads: Sequence[AxisymmetricLoad],
         start: Optional[np.ndarray] = None,
         settings: NewtonSettings = NewtonSettings()) -> list[AxisymmetricEquilibrium]:
    """The equilibria along ``loads`` (held pressures or volume targets), each solved from the
    last two by linear extrapolation in the load's parameter (net pressure, or volume target)."""
    out: list[AxisymmetricEquilibrium] = []
    for load in loads:
        state, mu = start, None
        if out:
            last = out[-1]
            state, mu = last.state, last.pressure - last.pressure_level
        if len(out) >= 2:
            a, b = out[-2], out[-1]
            da = _parameter(loads[len(out) - 1]) - _parameter(loads[len(out) - 2])
            ratio = (_parameter(load) - _parameter(loads[len(out) - 1])) / da if da else 0.0
            ahead = b.state + ratio * (b.state - a.state)
            if np.isfinite(evaluate(shell, load, ahead, 0.0, 0).energy):
                state = ahead                # else from the last (beyond the tank wall)
                mu = (b.pressure - b.pressure_level) + ratio * (
                    (b.pressure - b.pressure_level) - (a.pressure - a.pressure_level))
        out.append(equilibrium(shell, load, state, mu, settings))
    return out
