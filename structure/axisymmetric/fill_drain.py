"""Fill and drain of the diaphragm as a tank fills through its port and empties again.

A leg passes through requested tank fractions in order. From an equilibrium it steps to the
next fraction by the held-volume Newton (:func:`~structure.axisymmetric.solve.equilibrium`)
from the tangent's predictor (x + df dx/df, dx/df from the bordered tangent; nodes it carries
beyond the tank wall pulled back, :func:`~structure.axisymmetric.wall.pulled_inside`, and the
whole halved toward x until it is inside), and accepts the step where Newton converged,
the state is stable (n = 0, under the held volume) and its pressure is the predictor's
(within half the predicted change, or 1e-3 p_s, p_s = rho g a: a snap to another branch
changes the pressure at once); else the step is halved, down to ``smallest``. Below that the
curve is followed by arc length (:func:`~structure.axisymmetric.continuation.trace`)
to its limit point of the volume, where a filling (draining) sheet cannot stay on its branch
and snaps: just past the limit (by ``jump``) the held-volume Newton, descending its merit,
finds the stable state the sheet lands in, and the leg goes on from there. The fill leg runs
from the rest toward the full tank, the drain leg back from the fill's end; where their snaps
differ, so do the legs between them (hysteresis).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..inertia import constrained_negative
from .continuation import ContinuationSettings, pressure_scale, _System, tank_volume, trace
from .energy import evaluate
from .loads import AxisymmetricLoad
from .model import ShellOfRevolution
from .solve import AxisymmetricEquilibrium, NewtonSettings, equilibrium
from .wall import pulled_inside


GROW_AFTER = 2
"""A leg's step doubles (up to the fractions' spacing) after this many successes in a row at
its size: a step that had to be halved is not retried at once at the size that failed."""


@dataclass(frozen=True)
class Snap:
    """A snap at a limit point of the volume: ``direction`` (fill or drain); the limit's
    ``tank_fraction``; the states ``before`` (the last on the curve before the limit) and
    ``after`` (where the sheet lands, at ``landing_fraction``), each (4 n,), with their
    pressure levels (Pa)."""

    direction: str
    tank_fraction: float
    landing_fraction: float
    before: np.ndarray
    after: np.ndarray
    level_before: float
    level_after: float


@dataclass(frozen=True)
class LegState:
    """A leg's state at a requested tank fraction: the equilibrium, the number of snaps
    before it (``piece``), and its stability under the held volume (``negative``, 0
    stable)."""

    tank_fraction: float
    equilibrium: AxisymmetricEquilibrium
    piece: int
    negative: int


@dataclass(frozen=True)
class Leg:
    """One leg: ``direction``; ``states``, the :class:`LegState` at the requested fractions
    (None at one the leg jumped over in a snap); ``snaps``; ``complete`` when it reached its
    last fraction (else ``reason``)."""

    direction: str
    states: tuple
    snaps: tuple
    complete: bool
    reason: str = ""


def volume_load(load: AxisymmetricLoad, radius: float, fraction: float) -> AxisymmetricLoad:
    """``load`` holding the liquid at tank ``fraction`` of the tank of ``radius`` m."""
    return replace(load, volume_target=fraction * tank_volume(radius), controlled="liquid")


def _tangent(shell, load, result: AxisymmetricEquilibrium):
    """(dx/df (4 n,), dmu/df Pa, negative) at an equilibrium of the held volume: the bordered
    system [[K, -v], [v^T, 0]] (dy, dmu) = (0, -V_tank), and its stability (n = 0)."""
    system = _System(shell, load)
    mu = result.pressure - result.pressure_level
    x = np.concatenate([shell.admissible.free(result.state), [mu, 0.0]])
    ev = system.evaluate(x)
    t = shell.admissible.basis
    k, v = ev.free_hessian, t.T @ ev.volume_gradient
    negative = constrained_negative(k, v)
    col = sp.csc_matrix(v[:, None])
    try:
        out = splu(sp.bmat([[k, -col], [col.T, None]], format="csc")).solve(
            np.concatenate([np.zeros(len(v)), [-system.tank]]))
    except RuntimeError:
        return None, None, negative
    return t @ out[:-1], out[-1], negative


def _solve(shell, load, fraction, start, mu, newton):
    result = equilibrium(shell, volume_load(load, shell.radius, fraction), start, mu, newton)
    return result if result.converged else None


def leg(shell: ShellOfRevolution, load: AxisymmetricLoad, start: AxisymmetricEquilibrium,
        fractions: Sequence[float], settings: ContinuationSettings = ContinuationSettings(),
        newton: NewtonSettings = NewtonSettings(max_iterations=20), smallest: float = 1e-4,
        jump: float = 1e-5, progress=None) -> Leg:
    """The leg through the tank ``fractions`` (monotone; the first is ``start``'s) under
    ``load`` (its liquid, gravity and pressure) from the equilibrium ``start`` (module doc).
    The held-volume Newton steps from the tangent's predictor, by at most the fractions'
    spacing, halving the step where it fails or lands on an unstable state and doubling it
    after a success; below ``smallest`` (tank fraction) the curve is followed by arc length
    to the limit point, where the sheet snaps, ``jump`` past it."""
    fractions = np.asarray(fractions, dtype=float)
    direction = "fill" if fractions[-1] > fractions[0] else "drain"
    sign = 1.0 if direction == "fill" else -1.0
    tangent = _tangent(shell, load, start)          # of ``here``, while it is known
    states = [LegState(float(fractions[0]), start, 0, tangent[2])]
    snaps = []
    here, f_here, negative = start, float(fractions[0]), states[0].negative
    spacing = float(np.abs(np.diff(fractions)).max()) if len(fractions) > 1 else 0.0
    size, successes = spacing, 0
    for target in fractions[1:]:
        while sign * (target - f_here) > 1e-15:
            f = f_here + sign * min(size, abs(target - f_here))
            result, after = _next_state(shell, load, here, f, newton, tangent)
            if result is not None:
                here, f_here, negative = result, f, 0       # next_state's are stable
                tangent = after
                successes += 1
                if successes >= GROW_AFTER:
                    size, successes = min(2.0 * size, spacing), 0
                continue
            size, successes = 0.5 * size, 0
            if size >= smallest:
                continue
            landed = _snap(shell, load, here, f_here, target, sign, settings, newton, jump)
            if isinstance(landed, str):
                return Leg(direction, tuple(states), tuple(snaps), False, landed)
            size, tangent = spacing, None
            if landed[0] is None:
                here, f_here = landed[1], target
                tangent = _tangent(shell, load, here)
                negative = tangent[2]
                continue
            snaps.append(landed[0])
            here, f_here, negative = landed[1], landed[0].landing_fraction, 0   # stable
            if sign * (f_here - target) > 0:       # landed past the target
                break
        states.append(LegState(float(target), here, len(snaps), negative)
                      if abs(f_here - target) < 1e-12 else None)
        if progress is not None:
            progress(f_here)
    return Leg(direction, tuple(states), tuple(snaps), True)


def next_state(shell: ShellOfRevolution, load: AxisymmetricLoad, here: AxisymmetricEquilibrium,
               fraction: float, newton: NewtonSettings = NewtonSettings(max_iterations=20)):
    """The stable equilibrium at tank ``fraction`` on ``here``'s branch, stepped to from
    ``here`` (module doc), or None."""
    return _next_state(shell, load, here, fraction, newton)[0]


def _next_state(shell, load, here, fraction, newton, tangent=None):
    """(:func:`next_state`'s result, its :func:`_tangent`), from ``here``'s ``tangent`` when
    known; (None, None) where there is none."""
    dxdf, dmudf, _ = _tangent(shell, load, here) if tangent is None else tangent
    mu = here.pressure - here.pressure_level
    f_here = here.liquid_volume / tank_volume(shell.radius)
    ahead = None if dxdf is None else here.state + (fraction - f_here) * dxdf
    if ahead is not None and shell.wall is not None:
        ahead = shell.admissible.state(shell.admissible.free(pulled_inside(shell.wall, ahead)))
    if ahead is None:
        ahead, dmudf = here.state, 0.0
    for _ in range(12):                        # back toward ``here`` until inside the wall
        if np.isfinite(evaluate(shell, load, ahead, 0.0, 0).energy):
            break
        ahead = 0.5 * (here.state + ahead)
    predicted = mu + (fraction - f_here) * dmudf
    result = _solve(shell, load, fraction, ahead, predicted, newton)
    if result is None:
        return None, None
    after = _tangent(shell, load, result)
    if after[2] != 0:
        return None, None
    corrected = abs(result.pressure - result.pressure_level - predicted)
    scale = pressure_scale(shell, load)
    if corrected > max(0.5 * abs(predicted - mu), 1e-3 * scale):
        return None, None
    return result, after


def _snap(shell, load, here, fraction, target, sign, settings, newton, jump):
    """(Snap, landed equilibrium) past the limit point between ``here`` and ``target``, (None,
    the equilibrium at ``target``) where the curve reaches it with none, or why not."""
    mu = here.pressure - here.pressure_level
    curve = trace(shell, load, here.state, fraction, mu, target, settings, stop_at_limit=True)
    if curve.complete:                         # no limit point before the target
        end = curve.points[-1]
        reached = _solve(shell, load, target, end.state, end.net_pressure, newton)
        if reached is not None:
            return None, reached
    if curve.reason != "limit point":
        return (f"no limit point ahead of tank fraction {fraction:.5f}: "
                f"{curve.reason or 'the curve went on'}")
    limit = curve.limit_points[0]
    before = curve.points[limit.after - 1]
    step = jump
    for _ in range(4):
        target = limit.tank_fraction + sign * step
        landed = _solve(shell, load, target, before.state, before.net_pressure,
                        replace(newton, max_iterations=400))
        if landed is not None and np.abs(landed.state - before.state).max() \
                > 1e-3 * shell.radius and _tangent(shell, load, landed)[2] == 0:
            snap = Snap("fill" if sign > 0 else "drain", limit.tank_fraction, target,
                        before.state, landed.state, before.pressure_level,
                        landed.pressure_level)
            return snap, landed
        step *= 10
    return f"no stable landing found past the limit point at tank fraction " \
           f"{limit.tank_fraction:.5f}"


