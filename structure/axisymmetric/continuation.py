"""The fill and drain of the shell of revolution by pseudo-arc-length continuation in the liquid's
volume (Keller, "Numerical solution of bifurcation and nonlinear eigenvalue problems", 1977;
Crisfield 1991, ch. 9).

The unknowns are X = (y, mu, f): the free coordinates y (:mod:`~structure.axisymmetric.supports`),
the net pressure mu (Pa; the liquid's pressure level is p - mu) and the tank fraction
f = V_liquid / (4/3 pi a^3). The equilibria are the zeros of

    F(X) = [ T^T dPi/dx (x; mu)              ]     (N: the stationarity of Pi(x; 0) - mu V_b)
           [ V_b(x) - (2/3 pi a^3 - f V_tank) ]     (m^3: the liquid's volume is f V_tank)

a curve in X. It is followed in its arc length s, measured in scaled unknowns (positions / a
and slopes, each divided by the root of their number k so that the state's part is a root
mean square; mu / p_s, p_s = rho g a, or E t / a without a liquid; f): from a point X_k with unit
tangent t_k the predictor is X_k + ds t_k, and Newton's method solves F(X) = 0 together with
t_k . (X - X_k) = ds (the pseudo-arc-length condition), whose bordered Jacobian stays regular
where dF/dX loses rank in f, at a limit point of the volume. The tangent at the new point
solves dF/dX t = 0 with t . t_k = 1. A Newton iterate beyond the tank wall's barrier
(:mod:`~structure.axisymmetric.wall`) is halved back toward the last iterate until it is
inside. The step grows by ``grow`` after a corrector of at most ``easy`` iterations and is
halved after a failed one, or one whose tangent turned by more than ``max_turn`` (rad) from
the last (so that the curve is not followed back along itself past a sharp turn), within
[min_step, max_step].

**Limit points.** Where df/ds changes sign the curve has turned in the volume: a filling (or
draining) tank reaching it cannot stay on the branch and jumps (snaps) at the same volume to
another stable part of the curve. The limit point is located as the extremum of the cubic
Hermite interpolant of f(s) through the two points that bracket it (their fractions and
slopes df/ds).

**Stability** (n = 0: axisymmetric perturbations that keep the volume). A point is stable when
K = T^T Pi_xx T is positive definite on the tangent space of the volume constraint,
{dy : v . dy = 0}, v = T^T dV_b/dx. The number of negative eigenvalues there is
neg(K) - 1 if v . K^-1 v < 0 and neg(K) otherwise (Haynsworth's inertia additivity on the
bordered matrix [[K, v], [v^T, 0]]); neg(K) is the count of negative pivots of K's symmetric
factorisation (SuperLU in symmetric mode: a diagonal pivot order, equal row and column
permutations, so the pivots' signs are K's inertia by Sylvester's law; :mod:`structure.inertia`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..inertia import constrained_negative
from .energy import evaluate
from .loads import AxisymmetricLoad, lower_hemisphere
from .meridian import DOFS_PER_NODE, DR, DZ
from .model import ShellOfRevolution
from .solve import FORCE_FLOOR


@dataclass(frozen=True)
class ContinuationSettings:
    """step, min_step, max_step : arc lengths (scaled, module doc) of the first, the smallest
    and the largest step; grow : the step's factor after an easy corrector, one of at most
    ``easy`` iterations; max_iterations : a corrector's Newton iterations; tolerance : the
    relative residual of an equilibrium (as :class:`~structure.axisymmetric.solve.NewtonSettings`);
    max_points : the curve's points before the trace gives up."""

    step: float = 0.002
    min_step: float = 1e-7
    max_step: float = 0.05
    grow: float = 1.5
    easy: int = 4
    max_iterations: int = 12
    max_turn: float = 0.5
    tolerance: float = 1e-9
    floor: float = 1e-6
    step_tolerance: float = 1e-11
    max_points: int = 5000


@dataclass(frozen=True)
class CurvePoint:
    """An equilibrium on the curve: state (4 n,); tank_fraction f (1); net_pressure mu (Pa);
    pressure_level p_ref (Pa); arc_length s (scaled); tangent (k + 2,), the scaled unit
    tangent (its last entry df/ds); negative : the negative eigenvalues of the second variation
    under the held volume (n = 0; 0 stable); iterations : the corrector's; residual."""

    state: np.ndarray
    tank_fraction: float
    net_pressure: float
    pressure_level: float
    arc_length: float
    tangent: np.ndarray
    negative: int
    iterations: int
    residual: float

    @property
    def stable(self) -> bool:
        return self.negative == 0


@dataclass(frozen=True)
class LimitPoint:
    """A limit point of the volume between curve points ``after`` - 1 and ``after``: its tank
    fraction (the extremum of the cubic through the two points' fractions and slopes) and net
    pressure (linear between them), ``kind`` "maximum" (a filling tank snaps
    here) or "minimum" (a draining one does)."""

    after: int
    tank_fraction: float
    net_pressure: float
    kind: str


@dataclass(frozen=True)
class EquilibriumCurve:
    """The traced curve: points in arc length, the limit points of the volume, and whether
    the trace reached its end fraction (``complete``; else ``reason``)."""

    points: tuple
    limit_points: tuple
    complete: bool
    reason: str = ""


def tank_volume(radius: float) -> float:
    """4/3 pi a^3 (m^3)."""
    return 2.0 * lower_hemisphere(radius)[0]


def pressure_scale(shell: ShellOfRevolution, load: AxisymmetricLoad) -> float:
    """p_s (Pa): rho g a with a liquid, else E t / a."""
    if load.liquid_density > 0 and load.gravity > 0:
        return load.liquid_density * load.gravity * shell.radius
    return shell.material.youngs_modulus * shell.material.thickness / shell.radius


def free_scales(shell: ShellOfRevolution) -> np.ndarray:
    """(k,): the scale of each free coordinate: a (m) for a position, 1 for a slope."""
    basis = shell.admissible.basis.tocsc()
    rows = np.array([basis.indices[basis.indptr[j]] for j in range(basis.shape[1])])
    slope = np.isin(rows % DOFS_PER_NODE, (DR, DZ))
    return np.where(slope, 1.0, shell.radius)


class _System:
    """F, its Jacobian and the scaled unknowns for ``shell`` under ``load`` (module doc)."""

    def __init__(self, shell: ShellOfRevolution, load: AxisymmetricLoad):
        self.shell, self.load = shell, load
        self.basis = shell.admissible.basis
        self.hemisphere = lower_hemisphere(shell.radius)[0]
        self.tank = tank_volume(shell.radius)
        free = free_scales(shell)
        self.scale = np.concatenate([free * np.sqrt(len(free)),
                                     [pressure_scale(shell, load), 1.0]])
        mat = shell.material
        self.floor = FORCE_FLOOR * mat.youngs_modulus * mat.thickness * shell.radius

    def split(self, x: np.ndarray):
        return x[:-2], x[-2], x[-1]

    def evaluate(self, x: np.ndarray, order: int = 2):
        y, mu, f = self.split(x)
        return evaluate(self.shell, self.load, self.shell.admissible.state(y), mu, order)

    def feasible(self, x: np.ndarray) -> bool:
        return bool(np.isfinite(self.evaluate(x, 0).energy))

    def residual(self, x: np.ndarray, ev) -> tuple[np.ndarray, float]:
        """(F (k + 1,), the relative residual)."""
        t = self.basis
        g = t.T @ ev.gradient
        gap = ev.volume - (self.hemisphere - x[-1] * self.tank)
        force = max(np.linalg.norm(t.T @ ev.internal), np.linalg.norm(t.T @ ev.external),
                    self.floor)
        return np.concatenate([g, [gap]]), float(np.hypot(np.linalg.norm(g) / force,
                                                          gap / self.hemisphere))

    def jacobian(self, ev) -> sp.csc_matrix:
        """dF/dX (k + 1, k + 2) in unscaled unknowns."""
        t = self.basis
        k = ev.free_hessian
        v = t.T @ ev.volume_gradient
        col = sp.csc_matrix(v[:, None])
        return sp.bmat([[k, -col, None], [col.T, None, sp.csc_matrix([[self.tank]])]],
                       format="csc")

    def tangent(self, jac: sp.csc_matrix, previous: np.ndarray) -> np.ndarray:
        """The scaled unit tangent t: (dF/dX) D t = 0, t . previous > 0."""
        scaled = jac @ sp.diags(self.scale)
        a = sp.vstack([scaled, sp.csc_matrix(previous[None, :])], format="csc")
        rhs = np.zeros(a.shape[0])
        rhs[-1] = 1.0
        t = splu(a).solve(rhs)
        return t / np.linalg.norm(t)


def _stability(system: _System, ev) -> int:
    t = system.basis
    return constrained_negative(ev.free_hessian, t.T @ ev.volume_gradient)


def _correct(system: _System, x0: np.ndarray, tangent: np.ndarray, ds: float,
             settings: ContinuationSettings):
    """Newton on F = 0 and t . (X - X0) = ds from the predictor; (x, ev, iterations,
    residual) or None."""
    scale = system.scale
    x = x0 + ds * tangent * scale
    if not system.feasible(x):
        return None
    small = False
    for iteration in range(settings.max_iterations + 1):
        ev = system.evaluate(x)
        if ev.hessian is None:
            return None
        f, res = system.residual(x, ev)
        if res < settings.tolerance or (small and res < settings.floor):
            return x, ev, iteration, res
        if iteration == settings.max_iterations:
            return None
        jac = system.jacobian(ev) @ sp.diags(scale)
        a = sp.vstack([jac, sp.csc_matrix(tangent[None, :])], format="csc")
        arc = tangent @ ((x - x0) / scale) - ds
        try:
            dx = splu(a).solve(-np.concatenate([f, [arc]])) * scale
        except RuntimeError:
            return None
        if not np.all(np.isfinite(dx)):
            return None
        for _ in range(30):
            if system.feasible(x + dx):
                break
            dx = 0.5 * dx
        else:
            return None
        small = np.abs(dx / scale).max() < settings.step_tolerance
        x = x + dx
    return None


def _extremum(f0: float, f1: float, d0: float, d1: float) -> tuple[float, float]:
    """(x, f(x)): the extremum in [0, 1] of the cubic with values f0, f1 and slopes d0, d1
    (per unit x) at its ends (d0 and d1 of opposite signs)."""
    # f(x) = f0 + d0 x + c2 x^2 + c3 x^3 on x in [0, 1]
    c2 = 3 * (f1 - f0) - 2 * d0 - d1
    c3 = 2 * (f0 - f1) + d0 + d1
    roots = np.roots([3 * c3, 2 * c2, d0]) if abs(c3) > 1e-300 else np.roots([2 * c2, d0])
    real = [r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 and 0 <= r.real <= 1]
    x = min(real, key=lambda r: abs(r - d0 / (d0 - d1))) if real else d0 / (d0 - d1)
    return float(x), float(f0 + d0 * x + c2 * x * x + c3 * x**3)


def _limit_point(a: CurvePoint, b: CurvePoint, after: int) -> LimitPoint:
    """The limit point between ``a`` and ``b``: the extremum of the cubic Hermite
    interpolant of f(s) from the two points' fractions and slopes df/ds."""
    h = b.arc_length - a.arc_length
    d0 = a.tangent[-1] * h
    x, f = _extremum(a.tank_fraction, b.tank_fraction, d0, b.tangent[-1] * h)
    mu = a.net_pressure + x * (b.net_pressure - a.net_pressure)
    return LimitPoint(after, f, float(mu), "maximum" if d0 > 0 else "minimum")


def pressure_limit(shell: ShellOfRevolution, load: AxisymmetricLoad,
                   curve: EquilibriumCurve) -> Optional[LimitPoint]:
    """The curve's first limit point of the net pressure (a snap under pressure control, as
    the tank fraction's are under volume control): the extremum of the cubic Hermite
    interpolant of mu(s) between the first two points where dmu/ds changes sign; its
    ``tank_fraction`` linear between them. None where mu is monotone."""
    scale = pressure_scale(shell, load)
    points = curve.points
    for k in range(1, len(points)):
        a, b = points[k - 1], points[k]
        da, db = a.tangent[-2], b.tangent[-2]
        if da != 0 and np.sign(da) != np.sign(db):
            h = b.arc_length - a.arc_length
            x, mu = _extremum(a.net_pressure, b.net_pressure, da * scale * h, db * scale * h)
            f = a.tank_fraction + x * (b.tank_fraction - a.tank_fraction)
            return LimitPoint(k, float(f), mu, "maximum" if da > 0 else "minimum")
    return None


def trace(shell: ShellOfRevolution, load: AxisymmetricLoad, start: np.ndarray,
          start_fraction: float, start_pressure: float, end_fraction: float,
          settings: ContinuationSettings = ContinuationSettings(),
          stop_at_limit: bool = False, progress=None) -> EquilibriumCurve:
    """The curve of equilibria of ``shell`` under ``load`` (its liquid, gravity and pressure
    p; its volume target unused) from the equilibrium ``start`` (4 n,) at ``start_fraction``
    with net pressure ``start_pressure`` (Pa), in the direction of ``end_fraction``, until the
    tank fraction reaches ``end_fraction`` (module doc), or, with ``stop_at_limit``, at the
    first limit point of the volume (the curve then ends with the point past it, and
    ``reason`` is "limit point"), or where a stable curve loses its stability without one
    (the step is halved to the smallest first, so that a limit point it stepped over is
    found). ``progress(fraction)`` is called after each point."""
    system = _System(shell, load)
    x = np.concatenate([shell.admissible.free(start), [start_pressure, start_fraction]])
    direction = np.sign(end_fraction - start_fraction) or 1.0
    previous = np.zeros(len(x))
    previous[-1] = direction
    ev = system.evaluate(x)
    _, res = system.residual(x, ev)
    if ev.hessian is None or res > 1e3 * settings.tolerance:
        raise ValueError(f"the start is not an equilibrium (relative residual {res:.2e})")
    tangent = system.tangent(system.jacobian(ev), previous)

    def point(x, ev, tangent, s, iterations, res):
        y, mu, f = system.split(x)
        return CurvePoint(shell.admissible.state(y), float(f), float(mu),
                          float(load.pressure - mu), float(s), tangent,
                          _stability(system, ev), iterations, float(res))

    points = [point(x, ev, tangent, 0.0, 0, res)]
    limits, ds, s = [], settings.step, 0.0
    while len(points) < settings.max_points:
        out = _correct(system, x, tangent, ds, settings)
        if out is None:
            if ds <= settings.min_step:
                return EquilibriumCurve(tuple(points), tuple(limits), False,
                                        f"the corrector failed at the smallest step near "
                                        f"tank fraction {points[-1].tank_fraction:.4f}")
            ds = max(0.5 * ds, settings.min_step)
            continue
        x_new, ev, iterations, res = out
        new_tangent = system.tangent(system.jacobian(ev), tangent)
        if new_tangent @ tangent < np.cos(settings.max_turn) and ds > settings.min_step:
            ds = max(0.5 * ds, settings.min_step)
            continue
        candidate = point(x_new, ev, new_tangent, s + ds, iterations, res)
        turned = np.sign(new_tangent[-1]) != np.sign(tangent[-1]) and tangent[-1] != 0
        if stop_at_limit and candidate.negative != 0 and points[-1].negative == 0 \
                and not turned:
            if ds > settings.min_step:         # stability lost with no limit: look closer
                ds = max(0.5 * ds, settings.min_step)
                continue
            points.append(candidate)
            return EquilibriumCurve(tuple(points), tuple(limits), False,
                                    "stability lost without a limit point (a bifurcation)")
        s += ds
        points.append(candidate)
        if turned:
            limits.append(_limit_point(points[-2], points[-1], len(points) - 1))
            if stop_at_limit:
                return EquilibriumCurve(tuple(points), tuple(limits), False, "limit point")
        x, tangent = x_new, new_tangent
        if progress is not None:
            progress(points[-1].tank_fraction)
        if direction * (points[-1].tank_fraction - end_fraction) >= 0:
            return EquilibriumCurve(tuple(points), tuple(limits), True)
        if iterations <= settings.easy:
            ds = min(settings.grow * ds, settings.max_step)
    return EquilibriumCurve(tuple(points), tuple(limits), False,
                            f"{settings.max_points} points did not reach tank fraction "
                            f"{end_fraction}")
