"""Projected Newton on the potential at a held volume: each step solves the bordered system

    [H   g] [dx ]   [-r      ]
    [g^T 0] [-dp] = [V* - V  ],

r the Lagrangian's gradient, g = dV/dx, and H the first matrix of a ladder that is positive
definite on the volume's tangent space: the exact Hessian K of the Lagrangian
(:func:`structure.newton.system.linearise`, energy form); then K with the membrane's element
blocks projected to positive semi-definite and the bending's Gauss-Newton blocks
(:mod:`structure.minimise.project`); then that matrix shifted by tau M (M the lumped
masses), tau growing. Whether a matrix will do is read from its factorisation: SuperLU in
symmetric mode gives its negative eigenvalues from the signs of its pivots
(:mod:`structure.inertia`), one fewer on the volume's tangent space where g^T H^-1 g < 0.
The step is then a descent direction of the merit

    phi(x) = Pi(x) + nu |V(x) - V*|,     nu > |p|

(an exact penalty: Nocedal & Wright, *Numerical Optimization*, 2006, sec. 15.5), cut to the
barrier's largest step (:meth:`structure.minimise.barrier.BarrierWall.largest_step`) and
backtracked until Armijo's condition holds; where the merit's predicted change is below its
round-off (at the minimum), Newton's full step is taken if it lowers the residual. Near a
minimum the exact Hessian serves and the convergence is quadratic. The shift is carried from
one iteration to the next, lowered fourfold after a full step and raised after a rejected one
(Levenberg-Marquardt's adaptive damping, with the inertia deciding instead of a trial step).

A step may also carry a pseudo-inertia, h: the term M / (2 h^2) |x - x_prev|^2 added to the
potential (an implicit Euler step of a sheet without damping, started at rest), which makes
the problem strictly convex in a small enough h and lets the iterates cross a snap along the
physical (descending) path rather than jump.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..inertia import factor_symmetric
from ..load import Load
from ..newton.statics import SolveScales, converged, force_ratio
from ..newton.system import Linearisation, NewtonModel, linearise
from .project import projected_tangent

log = logging.getLogger(__name__)

SHIFT_GROWTH = 8.0
"""The factor by which a shift is raised while the tangent is not positive definite."""
SHIFT_DECAY = 0.25
"""The factor by which it is lowered after an accepted step."""
ROUND_OFF = 1e-11
"""The merit's relative round-off: a step predicted to lower it by less is judged by the
residual instead (at the minimum the energy's change is below what it can resolve)."""
"""The factor by which it is lowered after an accepted step."""


@dataclass(frozen=True)
class MinimiseSettings:
    """Settings of the minimisation statics.

    * force_tolerance : converged when the largest free-node residual force is below this
      fraction of the pressure force rho |b| R A_node (-);
    * volume_tolerance : and |V - V*| below this fraction of the tank volume (-);
    * max_iterations : Newton iterations per corrector (-);
    * volume_step : the first volume step of a path, a fraction of the tank (-);
    * min_volume_step, max_volume_step : its bounds (-);
    * easy_iterations, hard_iterations : a step grows (x ``step_growth``) after a corrector of
      at most ``easy_iterations`` and shrinks (x ``step_shrink``) after one of more than
      ``hard_iterations``; a failed one is halved (-);
    * step_growth, step_shrink : (-);
    * pseudo_inertia : the time h (s) of the pseudo-inertia tried when a corrector fails at
      the smallest step (0: none);
    * pseudo_steps : pseudo-inertia steps per such crossing at most (-);
    * continuations : how many times a corrector that ran out of iterations is continued
      before its step is halved (-).
    """

    force_tolerance: float = 1e-6
    volume_tolerance: float = 1e-9
    max_iterations: int = 60
    volume_step: float = 0.01
    min_volume_step: float = 1e-5
    max_volume_step: float = 0.05
    easy_iterations: int = 20
    hard_iterations: int = 60
    step_growth: float = 1.5
    step_shrink: float = 0.7
    pseudo_inertia: float = 1e-2
    pseudo_steps: int = 200
    continuations: int = 3

    def __post_init__(self):
        for name in ("force_tolerance", "volume_tolerance", "volume_step", "min_volume_step",
                     "max_volume_step", "step_growth"):
            if not getattr(self, name) > 0:
                raise ValueError(f"minimise {name} must be > 0, got {getattr(self, name)!r}")
        if not 0 < self.step_shrink < 1:
            raise ValueError(f"minimise step_shrink must be in (0, 1), got {self.step_shrink!r}")
        if not self.min_volume_step <= self.volume_step <= self.max_volume_step:
            raise ValueError("minimise volume steps must satisfy min_volume_step <= "
                             "volume_step <= max_volume_step")
        if self.max_iterations < 1 or self.pseudo_steps < 0 or self.continuations < 0:
            raise ValueError("minimise max_iterations must be >= 1, pseudo_steps and "
                             "continuations >= 0")
        if not self.pseudo_inertia >= 0:
            raise ValueError(f"minimise pseudo_inertia must be >= 0 s, got "
                             f"{self.pseudo_inertia!r}")


@dataclass
class Counters:
    """Work done: Newton iterations, factorisations, and the seconds spent factorising."""

    iterations: int = 0
    factorisations: int = 0
    factor_seconds: float = 0.0


class Scales(SolveScales):
    """The Newton statics' units of a solve (force N, level Pa, tank volume m^3), with the
    shift's scale (1/s^2, the median of diag K / M on the free nodes, set by the first
    corrector)."""

    shift: float = 0.0


@dataclass
class Corrector:
    """The state a corrector carries between iterations and volume steps: the shift tau
    (1/s^2) last used and whether it was on the projected Hessian, the counters, and whether
    the last corrector's first step took the exact Hessian (its start was stable)."""

    shift: float = 0.0
    counters: Counters = field(default_factory=Counters)
    stable_start: bool = True
    projecting: bool = False


def evaluate(model: NewtonModel, obstacles, x: np.ndarray, level: float, load: Load,
             hessian: bool = True) -> Linearisation:
    """:func:`structure.newton.system.linearise` with the self-contact of ``obstacles`` (a
    :class:`structure.minimise.contact.Obstacles`; a bare wall has none) added: its energy,
    gradient, and Hessian as the linearisation's ``extra``."""
    lin = linearise(model, x, level, load, hessian)
    contact = getattr(obstacles, "contact", None)
    if contact is None:
        return lin
    energy, grad, matrix = contact.evaluate(x, hessian)
    lin.energy += energy
    lin.residual = lin.residual + grad
    if hessian:
        lin.extra = matrix
        lin.matrix = sp.csr_matrix(lin.matrix) + matrix
    return lin


def _factor(matrix, corrector: Corrector):
    tic = time.perf_counter()
    lu, negative = factor_symmetric(matrix)
    corrector.counters.factorisations += 1
    corrector.counters.factor_seconds += time.perf_counter() - tic
    return lu, negative


def kkt_step(model: NewtonModel, lin: Linearisation, target: float, scales: Scales,
             corrector: Corrector, extra_mass: float = 0.0, extra_gradient=None,
             projected: tuple = (), x: np.ndarray | None = None):
    """The bordered step (dx (n, 3) m, dp Pa) with the first matrix of the ladder that is
    positive definite on the volume's tangent space (module doc): the exact Hessian; then the
    Hessian with the element blocks of the terms ``projected`` (indices into ``model.terms``)
    made positive semi-definite (:mod:`structure.minimise.project`); then that one shifted
    by tau M, tau growing. ``extra_mass`` (1/s^2) adds that many M to every matrix and
    ``extra_gradient`` (n, 3) N to the residual (the pseudo-inertia). Returns (dx, dp, the
    factorisation) or None. ``x`` (n, 3) m: the positions of ``lin`` (for the projection)."""
    mass = model.dof_mass
    residual = lin.residual if extra_gradient is None else lin.residual + extra_gradient
    g = lin.volume_gradient.ravel()
    floor = 1e-8 * scales.shift
    tau = corrector.shift if corrector.shift >= floor else 0.0
    ladder = []
    if tau == 0.0 and not corrector.projecting:
        ladder.append(("exact", 0.0))
    matrix_of = {"exact": lin.matrix}
    rung = "projected" if projected else "exact"
    for _ in range(60):
        ladder.append((rung, tau))
        tau = max(SHIFT_GROWTH * tau, 1e-6 * scales.shift)
    for kind, shift in ladder:
        if kind not in matrix_of:
            matrix_of[kind] = projected_tangent(model, lin, x, projected)
        total = shift + extra_mass
        matrix = matrix_of[kind] if total == 0 else matrix_of[kind] + sp.diags(total * mass)
        lu, negative = _factor(matrix, corrector)
        if lu is None:
            continue
        a = lu.solve(-residual.ravel())
        b = lu.solve(g)
        gb = float(g @ b)
        finite = np.all(np.isfinite(a)) and np.all(np.isfinite(b)) and gb != 0.0
        if finite and negative is not None and negative - (1 if gb < 0 else 0) == 0:
            corrector.shift = shift
            corrector.projecting = kind == "projected"
            dp = (target - lin.volume - float(g @ a)) / gb
            return (a + dp * b).reshape(lin.residual.shape), dp, lu
    return None


def _residual_norm(model, lin: Linearisation, target: float, scales: Scales) -> float:
    """The force ratio and the volume error in one measure (-)."""
    return max(force_ratio(model, lin, scales), abs(lin.volume - target) / scales.volume * 1e3)


def merit(lin: Linearisation, target: float, weight: float, proximal: float = 0.0) -> float:
    """phi = Pi + weight |V - V*| (+ the pseudo-inertia's energy ``proximal``) (J)."""
    return lin.energy + proximal + weight * abs(lin.volume - target)


def minimise_at_volume(model: NewtonModel, wall, x: np.ndarray, level: float,
                       load: Load, target: float, settings: MinimiseSettings, scales: Scales,
                       corrector: Corrector, lin: Linearisation | None = None,
                       pseudo_inertia: float = 0.0, max_iterations: int | None = None,
                       projected: tuple = ()):
    """The potential's minimum at the volume ``target`` (m^3) from positions ``x`` (n, 3) m and
    level ``level`` (Pa) (module doc); with ``pseudo_inertia`` h > 0 s the pseudo-inertia's
    minimum about ``x`` instead (its residual with the term). Returns (x, level, iterations,
    converged, linearisation at x)."""
    x = np.array(x, dtype=float)
    lin = lin or evaluate(model, wall, x, level, load)
    anchor = x.copy()
    mass = model.dof_mass.reshape(x.shape)
    c = 1.0 / pseudo_inertia**2 if pseudo_inertia > 0 else 0.0
    limit = max_iterations or settings.max_iterations
    if scales.shift == 0.0:
        diag = lin.matrix.diagonal()
        free = mass.ravel() > 0
        scales.shift = float(np.median(np.abs(diag[free]) / mass.ravel()[free]))

    def proximal(y):
        return 0.5 * c * float(np.sum(mass * (y - anchor) ** 2)) if c else 0.0

    def done(x, lin):
        """Converged: with the pseudo-inertia, its residual with the term."""
        if not c:
            return converged(model, lin, target, settings, scales)
        r = (lin.residual + c * mass * (x - anchor))[model.free]
        return (float(np.abs(r).max()) <= settings.force_tolerance * scales.force
                and abs(lin.volume - target) <= settings.volume_tolerance * scales.volume)

    for it in range(1, limit + 1):
        extra = c * mass * (x - anchor) if c else None
        if done(x, lin):
            return x, level, it - 1, True, lin
        corrector.counters.iterations += 1
        step = kkt_step(model, lin, target, scales, corrector, c, extra, projected, x)
        if step is None:
            return x, level, it, False, lin
        dx, dp, _ = step
        if it == 1:
            corrector.stable_start = corrector.shift == 0.0 and not corrector.projecting
        weight = 2.0 * max(abs(level), abs(level + dp)) + scales.level
        start = merit(lin, target, weight, proximal(x))
        gradient = lin.residual + level * lin.volume_gradient
        if c:
            gradient = gradient + extra
        slope = float(np.sum(gradient * dx)) - weight * abs(lin.volume - target)
        alpha = min(1.0, wall.largest_step(x, dx))
        accepted = False
        if alpha == 1.0 and -slope <= ROUND_OFF * abs(start):
            # the merit cannot tell the step's decrease from its own round-off: near the
            # minimum, accept Newton's full step where it lowers the residual instead
            trial = evaluate(model, wall, x + dx, level + dp, load, hessian=False)
            accepted = (np.isfinite(trial.energy)
                        and _residual_norm(model, trial, target, scales)
                        < _residual_norm(model, lin, target, scales))
        if not accepted and slope < 0 and alpha > 0:
            for _ in range(30):
                trial = evaluate(model, wall, x + alpha * dx, level + alpha * dp, load,
                                 hessian=False)
                value = merit(trial, target, weight, proximal(x + alpha * dx))
                if np.isfinite(value) and value <= start + 1e-4 * alpha * slope:
                    accepted = True
                    break
                alpha *= 0.5
        if not accepted:
            corrector.shift = max(SHIFT_GROWTH * corrector.shift, 1e-3 * scales.shift)
            continue
        log.debug("iteration %d: force ratio %.3g, volume error %.3g, %s tau %.3g, alpha %.3g",
                  it, force_ratio(model, lin, scales), (lin.volume - target) / scales.volume,
                  "projected" if corrector.projecting else "exact", corrector.shift, alpha)
        x = x + alpha * dx
        level = level + alpha * dp
        model.follow(x)
        lin = evaluate(model, wall, x, level, load)
        if alpha == 1.0:
            corrector.shift *= SHIFT_DECAY
            corrector.projecting = corrector.projecting and corrector.shift >= 1e-8 * scales.shift
    return x, level, limit, done(x, lin), lin
