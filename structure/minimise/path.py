"""The fill path by minimisation: volume steps from a start to each target, every step a
constrained minimisation (:mod:`structure.minimise.newton`) started from the tangent
predictor.

**Steps.** The volume step grows after an easy corrector and shrinks after a hard one
(:class:`structure.minimise.newton.MinimiseSettings`). A corrector that runs out of
iterations is continued from where it stopped (up to ``continuations`` times: in a snap it
is still descending); one that still fails is retried at half the step, and below the
smallest step the path crosses with the pseudo-inertia (a sequence of implicit-Euler steps of
the undamped sheet from rest, each a strictly convex minimisation, until the residual without
it is met), so that a snap does not end the path.

**Events.** A step whose corrector needed a shift (the predicted state was not stable on
the volume's tangent space) or the pseudo-inertia has crossed a snap: it is recorded with its
volume, the levels before and after, and how it was crossed.

**Predictor.** dx/dV = b / (g . b) with (K + tau M) b = g at the converged state, cut so that
no node closes more than 90 % of its gap to the wall.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from ..load import Equilibrium, LimitPoint, Load
from ..model import MembraneState
from ..newton.system import NewtonModel
from .model import projectable
from .newton import (Corrector, MinimiseSettings, Scales, evaluate, force_ratio, kkt_step,
                     minimise_at_volume)

log = logging.getLogger(__name__)


@dataclass
class PathStep:
    """One accepted volume step: the volume reached (m^3), the level (Pa), Newton iterations,
    how it was reached (``newton``, or ``pseudo-inertia``), and whether the predicted state
    was stable (its exact Hessian positive definite on the volume's tangent space)."""

    volume: float
    pressure_level: float
    iterations: int
    how: str
    stable_start: bool


@dataclass
class PathReport:
    """What a path did: its accepted steps, rejected step attempts, Newton iterations,
    factorisations and the seconds they took, and the wall-clock seconds."""

    steps: list = field(default_factory=list)
    rejected: int = 0
    iterations: int = 0
    factorisations: int = 0
    factor_seconds: float = 0.0
    seconds: float = 0.0

    def iterations_per_step(self) -> np.ndarray:
        return np.array([s.iterations for s in self.steps], dtype=float)

    @property
    def snaps(self) -> list:
        """The steps that crossed an unstable state (events)."""
        return [s for s in self.steps if not s.stable_start or s.how != "newton"]

    def limit_points(self, first: int, level: float) -> tuple:
        """The :class:`structure.load.LimitPoint` of the snaps from step ``first`` on, the
        level before that step ``level`` (Pa)."""
        out = []
        for step in self.steps[first:]:
            if not step.stable_start or step.how != "newton":
                how = "shifted Newton" if step.how == "newton" else step.how
                out.append(LimitPoint(step.volume, level, step.pressure_level, how))
            level = step.pressure_level
        return tuple(out)


def _predict(model: NewtonModel, wall, x, level, lin, dv, scales, corrector):
    """The tangent predictor (module doc) for a volume change ``dv`` (m^3) from the converged
    state ``x`` (n, 3) m, ``level`` (Pa); (x, level) unchanged where it cannot be formed."""
    step = kkt_step(model, lin, lin.volume, scales, corrector, x=x)
    if step is None:
        return x, level
    _, _, lu = step
    g = lin.volume_gradient.ravel()
    b = lu.solve(g).reshape(x.shape)
    gb = float(g @ b.ravel())
    if gb == 0 or not np.isfinite(gb):
        return x, level
    dx = b * (dv / gb)
    s = min(1.0, wall.largest_step(x, dx))
    return x + s * dx, level + s * dv / gb


def _correct(model, wall, x, level, load, goal, settings, scales, corrector, projected,
             lin=None):
    """The corrector at the volume ``goal``, continued from where it stopped (up to
    ``settings.continuations`` times) while it runs out of iterations: in a snap it is still
    descending, and its iterations are not thrown away with the step. (x, level, iterations,
    converged, linearisation)."""
    x, level, its, ok, lin = minimise_at_volume(model, wall, x, level, load, goal, settings,
                                                scales, corrector, lin, projected=projected)
    for _ in range(settings.continuations):
        if ok or not np.isfinite(lin.energy):
            break
        x, level, more, ok, lin = minimise_at_volume(model, wall, x, level, load, goal,
                                                     settings, scales, corrector, lin,
                                                     projected=projected)
        its += more
    return x, level, its, ok, lin


def _cross(model, wall, x, level, load, target, settings, scales, corrector, projected):
    """Pseudo-inertia steps from ``x`` until the potential's residual at ``target`` is met;
    (x, level, iterations, converged, linearisation)."""
    h = settings.pseudo_inertia
    total = 0
    lin = None
    for _ in range(settings.pseudo_steps):
        x, level, its, ok, lin = minimise_at_volume(model, wall, x, level, load, target,
                                                    settings, scales, corrector, lin,
                                                    pseudo_inertia=h, projected=projected)
        total += its
        if not ok:
            h *= 0.5
            continue
        x2, level2, its2, ok2, lin2 = minimise_at_volume(
            model, wall, x, level, load, target, settings, scales, corrector, lin,
            max_iterations=5, projected=projected)
        total += its2
        if ok2:
            return x2, level2, total, True, lin2
        h = min(2.0 * h, 100.0 * settings.pseudo_inertia)
    return x, level, total, False, lin


def _begin(model: NewtonModel, wall, state: MembraneState, load: Load):
    """(scales, corrector, x (n, 3) m, level Pa, linearisation) at ``state``, the bending's
    hinges following it; refused where a node is on or beyond the wall."""
    x = np.array(state.node_position, dtype=float)
    level = float(load.pressure_level)
    lin = evaluate(model, wall, x, level, load)
    if not np.isfinite(lin.energy):
        raise ValueError("the start has a node on or beyond the tank wall: move it inside "
                         "(structure.minimise.model.inside)")
    model.follow(x)
    return Scales(model, load), Corrector(), x, level, lin


def fill_path(model: NewtonModel, wall, state: MembraneState, load: Load,
              targets, settings: MinimiseSettings = MinimiseSettings(), progress=None):
    """Equilibria at the volumes ``targets`` (m^3, in order) from ``state`` (its nodes inside
    the barrier: :func:`structure.minimise.model.inside`), by the minimisation statics (module
    doc); ``wall`` the tank wall's :class:`structure.minimise.barrier.BarrierWall`, or a
    :class:`structure.minimise.contact.Obstacles` with the sheet's self-contact. Returns (one
    (:class:`MembraneState`, :class:`structure.load.Equilibrium`) per target, the
    :class:`PathReport`); after a target is missed every later one is returned not converged.
    ``progress``: called with each accepted step's volume (m^3)."""
    tic = time.perf_counter()
    s = settings
    scales, corrector, x, level, lin = _begin(model, wall, state, load)
    report = PathReport()
    projected = projectable(model)
    start = lin.volume
    x, level, its, ok, lin = _correct(model, wall, x, level, load, start, s, scales,
                                      corrector, projected, lin)
    if not ok and s.pseudo_inertia:
        x, level, _, ok, lin = _cross(model, wall, x, level, load, start, s, scales,
                                      corrector, projected)
    volume = lin.volume
    step = s.volume_step * scales.volume
    results = []
    for target in targets:
        first, level_before = len(report.steps), level
        while ok and abs(target - volume) > s.volume_tolerance * scales.volume:
            sign = np.sign(target - volume)
            dv = sign * min(step, abs(target - volume))
            goal = volume + dv
            xp, lp = _predict(model, wall, x, level, lin, dv, scales, corrector)
            corrector.shift, corrector.projecting = 0.0, False
            xn, ln, its, ok_n, lin_n = _correct(model, wall, xp, lp, load, goal, s, scales,
                                                corrector, projected)
            how = "newton"
            if not ok_n and abs(dv) <= s.min_volume_step * scales.volume and s.pseudo_inertia:
                model.follow(x)
                xn, ln, its2, ok_n, lin_n = _cross(model, wall, xp, lp, load, goal, s, scales,
                                                   corrector, projected)
                its += its2
                how = "pseudo-inertia"
            if not ok_n:
                report.rejected += 1
                model.follow(x)
                if abs(dv) <= s.min_volume_step * scales.volume:
                    ok = False
                    log.warning("minimise: no equilibrium found beyond V = %.6g m^3", volume)
                    break
                step = max(0.5 * abs(dv), s.min_volume_step * scales.volume)
                continue
            x, level, lin, volume = xn, ln, lin_n, goal
            report.steps.append(PathStep(volume, level, its, how, corrector.stable_start))
            if progress is not None:
                progress(volume)
            if its <= s.easy_iterations:
                step = min(s.step_growth * abs(dv), s.max_volume_step * scales.volume)
            elif its > s.hard_iterations:
                step = max(s.step_shrink * abs(dv), s.min_volume_step * scales.volume)
            else:
                step = abs(dv)
        eq = Equilibrium(corrector.counters.iterations, bool(ok), float(level),
                         float(lin.volume), force_ratio=force_ratio(model, lin, scales),
                         limit_points=report.limit_points(first, level_before))
        results.append((MembraneState(x.copy()), eq))
    report.iterations = corrector.counters.iterations
    report.factorisations = corrector.counters.factorisations
    report.factor_seconds = corrector.counters.factor_seconds
    report.seconds = time.perf_counter() - tic
    return results, report


def equilibrium_near(model: NewtonModel, wall, state: MembraneState, load: Load, target: float,
                     settings: MinimiseSettings = MinimiseSettings()):
    """The equilibrium at the volume ``target`` (m^3) from a ``state`` near it (a small change
    of volume and load, as a coupled window's from the last one's end): one corrector straight
    at ``target`` (continued as the path's), and where that does not converge the path from
    ``state`` (:func:`fill_path`, which first corrects at the state's own volume). Returns
    ((:class:`MembraneState`, :class:`structure.load.Equilibrium`), :class:`PathReport`)."""
    tic = time.perf_counter()
    scales, corrector, x, level, lin = _begin(model, wall, state, load)
    x, level, _, ok, lin = _correct(model, wall, x, level, load, target, settings, scales,
                                    corrector, projectable(model), lin)
    if not ok:
        model.follow(state.node_position)
        (result,), report = fill_path(model, wall, state, load, [target], settings)
        report.iterations += corrector.counters.iterations
        return result, report
    report = PathReport(iterations=corrector.counters.iterations,
                        factorisations=corrector.counters.factorisations,
                        factor_seconds=corrector.counters.factor_seconds,
                        seconds=time.perf_counter() - tic)
    eq = Equilibrium(corrector.counters.iterations, True, float(level), float(lin.volume),
                     force_ratio=force_ratio(model, lin, scales))
    return (MembraneState(x.copy()), eq), report
