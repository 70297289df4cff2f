"""Static equilibrium by Newton's method: the pressure level is the multiplier of the volume
(a bordered, KKT, solve), fills are reached by pseudo-arc-length continuation, and each
converged fill reports its iterations and the lowest eigenvalues of the constrained tangent.

**The bordered Newton step.** With K the tangent and g = dV/dx, one factorisation of K gives
K a = -r and K b = g; the step is dx = a + dp b with the level's change dp from the
constraint's linearisation (Riks 1979; Crisfield, *Non-linear finite element analysis of
solids and structures*, 1991, ch. 9):

* at a fixed volume V*: g . dx = V* - V, so dp = (V* - V - g . a) / (g . b);
* along the path, with V* free and the arc-length equation t . (u - u0) = ds in scaled
  unknowns u = (x / R, p / (rho |b| R), V* / V_tank): two scalar equations in (dp, dV*).

A backtracking line search and a cap on the largest node move per step (``max_move`` of the
node's length) keep the step inside the region where the linearisation holds. In the energy
form the line search is on the l1 merit Pi(x) + nu |V(x) - V*| (nu above the level's size;
Nocedal & Wright, *Numerical Optimization*, 2006, sec. 15.5): Pi is C1 even where a node
meets the wall, where the residual is not. Where the step is not a descent direction of the
merit (the constrained tangent is not positive definite: a saddle, a fold) the tangent is
shifted by tau M (M the lumped masses, tau growing tenfold) until it is (Levenberg). In the
follower form, whose load has no potential, the merit is the residual's norm.

**Continuation.** The path's tangent at a converged point is (b, 1, g . b) per unit of level,
scaled and normalised, oriented along the last one. Where its volume component changes sign
the path has passed a limit point of the volume (a snap-through under volume control); it is
recorded as an event (volume, level, path length) and followed, not stalled on. A fill target
is taken where the path crosses it in the direction of the fill, then polished by Newton at
that volume.

**Stability.** The lowest eigenvalues omega^2 (1/s^2) of K phi = omega^2 M phi on the
constraint's tangent space (g . phi = 0; M the lumped masses), by ARPACK in shift-invert mode
about zero with the bordered matrix: a negative one flags an unstable equilibrium.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, eigs, splu

from ..inertia import constrained_negative
from ..load import Equilibrium, Load
from ..model import MembraneState
from ..volume import tank_volume
from .linear import Factorisation, SingularTangent
from .system import Linearisation, NewtonModel, linearise

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class NewtonSettings:
    """Settings of the Newton statics.

    * force_tolerance : converged when the largest free-node residual force is below this
      fraction of the pressure force scale rho |b| R A_node (-);
    * volume_tolerance : and |V - V*| below this fraction of the tank volume (-);
    * max_iterations : Newton iterations per corrector (-);
    * max_move : the largest node move of one step, as a fraction of its length scale (-);
    * arc_step : the first path step, in scaled units (about a fraction of R) (-);
    * min_arc_step, max_arc_step : its bounds (-);
    * max_path_steps : path steps per solve at most (-);
    * eigenvalues : how many of the constrained tangent's lowest eigenvalues to report (0:
      none).
    """

    force_tolerance: float = 1e-6
    volume_tolerance: float = 1e-9
    max_iterations: int = 30
    max_move: float = 0.5
    arc_step: float = 0.05
    min_arc_step: float = 1e-5
    max_arc_step: float = 0.3
    max_path_steps: int = 2000
    eigenvalues: int = 0

    def __post_init__(self):
        for name in ("force_tolerance", "volume_tolerance", "max_move", "arc_step",
                     "min_arc_step", "max_arc_step"):
            if not getattr(self, name) > 0:
                raise ValueError(f"newton {name} must be > 0, got {getattr(self, name)!r}")
        if not self.min_arc_step <= self.arc_step <= self.max_arc_step:
            raise ValueError("newton arc steps must satisfy min_arc_step <= arc_step <= "
                             "max_arc_step")


@dataclass
class PathEvent:
    """A limit point of the volume passed along the path: volume (m^3), level (Pa), path
    length (scaled units)."""

    kind: str
    volume: float
    pressure_level: float
    path_length: float


@dataclass
class NewtonReport:
    """What a Newton static solve did: iterations in total, path steps, events, and the
    lowest eigenvalues omega^2 (1/s^2) of the constrained tangent at the end (empty unless
    asked)."""

    iterations: int = 0
    path_steps: int = 0
    events: list = field(default_factory=list)
    eigenvalues: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def stable(self) -> bool:
        """No negative eigenvalue among those computed."""
        return bool(np.all(np.real(self.eigenvalues) >= 0.0))


class SolveScales:
    """Units of the solve: force (N), length (m), level (Pa), volume (m^3)."""

    def __init__(self, model: NewtonModel, load: Load):
        base = model.base
        body = np.linalg.norm(np.asarray(load.body_acceleration, dtype=float))
        density = load.liquid_density or 1000.0
        area = base.node_mass / (base.material.density * base.material.thickness)
        self.level = max(density * max(body, 1.0) * base.radius, abs(load.pressure_level))
        self.force = self.level * float(area.max())
        self.length = base.radius
        self.volume = tank_volume(base.radius)
        self.node_length = base.node_length_scale


def force_ratio(model: NewtonModel, lin: Linearisation, scales: SolveScales) -> float:
    r = lin.residual[model.free]
    return float(np.abs(r).max() / scales.force) if r.size else 0.0


def _capped(model: NewtonModel, dx: np.ndarray, settings: NewtonSettings,
            scales: SolveScales) -> float:
    """The largest step fraction (<= 1) keeping every node's move within max_move of its
    length scale."""
    move = np.sqrt(np.einsum("ij,ij->i", dx, dx)) / scales.node_length
    worst = float(move.max()) if move.size else 0.0
    return min(1.0, settings.max_move / worst) if worst > 0 else 1.0


def _merit(model, lin: Linearisation, target, scales, weight: float) -> float:
    """The l1 merit Pi + weight |V - V*| (J) in the energy form; the squared scaled
    residual and volume error in the follower form."""
    if model.load_form == "energy":
        return lin.energy + weight * abs(lin.volume - target)
    r = lin.residual[model.free] / scales.force
    c = (lin.volume - target) / scales.volume * 1e3
    return float(np.sum(r * r) + c * c)


def _bordered_step(model, lin: Linearisation, target, scales, shift: float):
    """The Newton step (dx (n, 3), dp) at the fixed volume ``target`` with the tangent
    shifted by ``shift`` M (1/s^2 times the lumped masses); None when singular."""
    matrix = lin.matrix
    if shift:
        matrix = matrix + sp.diags(shift * model.dof_mass)
    try:
        lu = Factorisation(matrix)
        a = lu.solve(-lin.residual)
        b = lu.solve(lin.volume_gradient)
    except SingularTangent:
        return None
    gb = float(np.sum(lin.volume_gradient * b))
    if gb == 0.0:
        return None
    dp = (target - lin.volume - float(np.sum(lin.volume_gradient * a))) / gb
    return a + dp * b, dp


def newton_at_volume(model: NewtonModel, x: np.ndarray, level: float, load: Load,
                     target: float, settings: NewtonSettings, scales: SolveScales | None = None):
    """Newton's method at the fixed volume ``target`` (m^3) from positions ``x`` (n, 3) m and
    level ``level`` (Pa). Returns (x, level, iterations, converged, last linearisation)."""
    scales = scales or SolveScales(model, load)
    x = np.array(x, dtype=float)
    lin = linearise(model, x, level, load)
    shifts = _shifts(model, scales)
    k = 0  # index of the Levenberg shift in use: raised on a rejected step, lowered after
    for it in range(1, settings.max_iterations + 1):
        if converged(model, lin, target, settings, scales):
            return x, level, it - 1, True, lin
        ok = False
        while k < len(shifts):
            step = _bordered_step(model, lin, target, scales, shifts[k])
            if step is not None:
                dx, dp = step
                x_new, level_new, lin_new, ok = _line_search(
                    model, x, level, dx, dp, lin, load, target, settings, scales,
                    backtracks=20 if k == len(shifts) - 1 else 4)
            if ok:
                x, level, lin = x_new, level_new, lin_new
                model.follow(x)
                k = max(k - 1, 0)
                break
            k += 1
        if not ok:
            return x, level, it, False, lin
    return x, level, settings.max_iterations, converged(model, lin, target, settings,
                                                          scales), lin


def converged(model, lin, target, settings, scales) -> bool:
    return (force_ratio(model, lin, scales) <= settings.force_tolerance
            and abs(lin.volume - target) <= settings.volume_tolerance * scales.volume)


def _shifts(model, scales):
    """The Levenberg shifts tau (1/s^2): none, then growing tenfold from a millionth of the
    pressure's stiffness per unit mass. A step is tried with at most four halvings; where
    the merit does not fall the next shift is used, and after an accepted step the previous
    one (Levenberg-Marquardt's adaptive damping, so that an indefinite tangent's poor
    direction is not followed in tiny steps)."""
    base = model.base
    mass = float(base.node_mass[model.free].mean()) if model.free.any() else 1.0
    first = 1e-6 * scales.force / scales.length / mass
    return [0.0] + [first * 10.0**k for k in range(0, 13)]


def _line_search(model, x, level, dx, dp, lin, load, target, settings, scales,
                 backtracks: int = 20):
    """Backtracking from the capped step until the merit falls (Armijo, 1e-4 of the
    directional derivative); the new (x, level, linearisation, whether it fell). False
    at once when the step is not a descent direction of the merit."""
    weight = 2.0 * max(abs(level), abs(level + dp)) + scales.level
    start = _merit(model, lin, target, scales, weight)
    if model.load_form == "energy":
        # D = grad Pi . dx - weight |c| with grad Pi = r + p g on the free nodes
        slope = float(np.sum((lin.residual + level * lin.volume_gradient) * dx)) \
            - weight * abs(lin.volume - target)
        if not slope < 0:
            return x, level, lin, False
    else:
        slope = -2.0 * start
    alpha = _capped(model, dx, settings, scales)
    for _ in range(backtracks):
        x_new = x + alpha * dx
        level_new = level + alpha * dp
        trial = linearise(model, x_new, level_new, load, hessian=False)
        if np.isfinite(trial.energy) and _merit(model, trial, target, scales, weight) <= \
                start + 1e-4 * alpha * slope:
            return x_new, level_new, linearise(model, x_new, level_new, load), True
        alpha *= 0.5
    return x, level, lin, False


def newton_at_level(model: NewtonModel, x: np.ndarray, load: Load,
                    settings: NewtonSettings = NewtonSettings()):
    """Newton's method under the held level ``load.pressure_level`` (Pa), no volume
    constraint, from positions ``x`` (n, 3) m; the energy form's merit is Pi - p V. Returns
    (x, iterations, converged, last linearisation)."""
    scales = SolveScales(model, load)
    level = float(load.pressure_level)
    x = np.array(x, dtype=float)
    lin = linearise(model, x, level, load)
    for it in range(1, settings.max_iterations + 1):
        if force_ratio(model, lin, scales) <= settings.force_tolerance:
            return x, it - 1, True, lin
        ok = False
        for shift in _shifts(model, scales):
            matrix = lin.matrix
            if shift:
                matrix = matrix + sp.diags(shift * model.dof_mass)
            try:
                dx = Factorisation(matrix).solve(-lin.residual)
            except SingularTangent:
                continue
            x_new, lin_new, ok = _level_line_search(model, x, dx, lin, load, level, settings,
                                                    scales)
            if ok:
                x, lin = x_new, lin_new
                model.follow(x)
                break
        if not ok:
            return x, it, False, lin
    return x, settings.max_iterations, force_ratio(model, lin, scales) <= \
        settings.force_tolerance, lin


def _level_line_search(model, x, dx, lin, load, level, settings, scales):
    """Backtracking on Pi - p V (energy form) or on the residual's norm (follower form)."""
    def merit(state):
        if model.load_form == "energy":
            return state.energy - level * state.volume
        r = state.residual[model.free] / scales.force
        return float(np.sum(r * r))

    start = merit(lin)
    slope = float(np.sum(lin.residual * dx)) if model.load_form == "energy" else -2 * start
    if not slope < 0:
        return x, lin, False
    alpha = _capped(model, dx, settings, scales)
    for _ in range(20):
        trial = linearise(model, x + alpha * dx, level, load, hessian=False)
        if np.isfinite(trial.energy) and merit(trial) <= start + 1e-4 * alpha * slope:
            x_new = x + alpha * dx
            return x_new, linearise(model, x_new, level, load), True
        alpha *= 0.5
    return x, lin, False


def fill_path(model: NewtonModel, state: MembraneState, load: Load, targets,
              settings: NewtonSettings = NewtonSettings(), volume_step: float = 0.02):
    """Equilibria at the volumes ``targets`` (m^3, in order) by natural continuation in the
    volume from ``state``: steps of at most ``volume_step`` of the tank volume, each predicted
    along the path's tangent dx/dV = b / (g . b) and corrected by Newton at its volume (the
    l1-merit line search and Levenberg shifts let a corrector that meets a snap descend to
    the equilibrium beyond it); a step whose corrector fails is halved down to a hundredth.
    Returns one (:class:`MembraneState`, :class:`structure.load.Equilibrium`,
    :class:`NewtonReport`) per target; after a target is missed every later one is returned
    not converged."""
    scales = SolveScales(model, load)
    s = settings
    x = np.array(state.node_position, dtype=float)
    level = float(load.pressure_level)
    x, level, its, ok, lin = newton_at_volume(model, x, level, load, model.liquid_volume(x),
                                              s, scales)
    total, steps, results = its, 0, []
    volume = lin.volume
    for target in targets:
        while ok and abs(target - volume) > s.volume_tolerance * scales.volume:
            step = min(volume_step * scales.volume, abs(target - volume))
            while True:
                goal = volume + np.sign(target - volume) * step
                try:
                    b = Factorisation(lin.matrix).solve(lin.volume_gradient)
                    gb = float(np.sum(lin.volume_gradient * b))
                except SingularTangent:
                    b, gb = np.zeros_like(x), 0.0
                xp, lp = (x + b * (goal - volume) / gb, level + (goal - volume) / gb) \
                    if gb else (x, level)
                xn, ln, its, ok_n, lin_n = newton_at_volume(model, xp, lp, load, goal, s,
                                                            scales)
                total += its
                if ok_n:
                    x, level, lin, volume = xn, ln, lin_n, goal
                    steps += 1
                    break
                step *= 0.5
                if step < 0.01 * volume_step * scales.volume:
                    ok = False
                    log.warning("newton: no equilibrium found beyond V = %.6g m^3", volume)
                    break
        results.append(_result(model, x, level, lin, ok, NewtonReport(total, steps), scales, s))
    return results


def solve_equilibrium(model: NewtonModel, state: MembraneState, load: Load,
                      settings: NewtonSettings = NewtonSettings()):
    """The equilibrium holding ``load.volume_target`` (m^3) from ``state``, by
    :func:`fill_path` from the state's own volume (level started at ``load.pressure_level``,
    Pa). Returns (:class:`MembraneState`, :class:`structure.load.Equilibrium` with ``steps``
    the Newton iterations and its force ratio, :class:`NewtonReport`)."""
    if load.volume_target is None:
        raise ValueError("the Newton statics needs a volume target (load.volume_target, m^3)")
    return fill_path(model, state, load, [load.volume_target], settings)[-1]


def continuation(model: NewtonModel, state: MembraneState, load: Load, targets,
                 settings: NewtonSettings = NewtonSettings()):
    """Equilibria at the volumes ``targets`` (m^3, in the order given, each beyond the last in
    the path's direction) by pseudo-arc-length continuation from ``state`` (module doc).
    Returns one (:class:`MembraneState`, :class:`structure.load.Equilibrium`,
    :class:`NewtonReport`) per target; a target the path does not reach is returned not
    converged, and so is every one after it."""
    scales = SolveScales(model, load)
    s = settings
    x = np.array(state.node_position, dtype=float)
    level = float(load.pressure_level)
    v0 = model.liquid_volume(x)
    # the start: equilibrium at its own volume
    x, level, its, ok, lin = newton_at_volume(model, x, level, load, v0, s, scales)
    total_its = its
    results = []
    if not ok:
        log.warning("newton: the start is not an equilibrium at its own volume")
        return [_result(model, x, level, lin, False, NewtonReport(total_its), scales, s)
                for _ in targets]
    volume = v0
    tangent = None
    step = s.arc_step
    path = 0.0
    steps = 0
    report = NewtonReport()
    pending = list(targets)
    while pending:
        target = pending[0]
        direction = np.sign(target - volume)
        if direction == 0 or abs(target - volume) <= s.volume_tolerance * scales.volume:
            results.append(_result(model, x, level, lin, True,
                                   _report(report, total_its, steps), scales, s))
            pending.pop(0)
            continue
        tangent = _path_tangent(model, lin, scales, tangent, direction)
        if tangent is None:
            break
        if steps >= s.max_path_steps:
            break
        accepted = False
        while step >= s.min_arc_step:
            trial = _arc_step(model, x, level, volume, tangent, step, load, s, scales)
            if trial is not None:
                accepted = True
                break
            step *= 0.5
        if not accepted:
            log.warning("newton: path step below %.3g at V = %.6g m^3", s.min_arc_step, volume)
            break
        x_new, level_new, volume_new, its, lin_new = trial
        total_its += its
        steps += 1
        path += step
        new_tangent = _path_tangent(model, lin_new, scales, tangent, None)
        if new_tangent is not None and np.sign(new_tangent[-1]) != np.sign(tangent[-1]):
            report.events.append(PathEvent("volume limit point", volume_new, level_new, path))
            log.info("newton: volume limit point at V = %.6g m^3, level %.4g Pa",
                     volume_new, level_new)
        crossed = (volume_new - target) * direction >= 0 and \
            (volume_new - volume) * direction > 0
        if crossed:
            w = (target - volume) / (volume_new - volume)
            xt = x + w * (x_new - x)
            lt = level + w * (level_new - level)
            xt, lt, its, ok, lin_t = newton_at_volume(model, xt, lt, load, target, s, scales)
            total_its += its
            if ok:
                x, level, volume, lin = xt, lt, target, lin_t
                tangent = _path_tangent(model, lin, scales, new_tangent, None)
                results.append(_result(model, x, level, lin, True,
                                       _report(report, total_its, steps), scales, s))
                pending.pop(0)
                continue
        x, level, volume, lin, tangent = x_new, level_new, volume_new, lin_new, new_tangent
        step = min(step * (1.5 if its <= 4 else 1.0 if its <= 8 else 0.5), s.max_arc_step)
    while pending:
        results.append(_result(model, x, level, lin, False, _report(report, total_its, steps),
                               scales, s))
        pending.pop(0)
    return results


def _report(report: NewtonReport, iterations: int, steps: int) -> NewtonReport:
    return NewtonReport(iterations, steps, list(report.events))


def _shift_below(k: sp.csr_matrix, mass: np.ndarray, g: np.ndarray) -> float:
    """A shift sigma (1/s^2) with K - sigma M positive definite on {g . dy = 0}, by its
    inertia (:func:`structure.inertia.constrained_negative`): -1e-9 s first (s the median of
    diag K / M), where the tangent is stable; else from -1e-3 s, fourfold lower until no
    negative eigenvalue is left. Zero where the inertia cannot be read (a singular or
    pivoted factorisation)."""
    scale = float(np.median(np.abs(k.diagonal()) / mass))
    sigma = -1e-9 * scale
    for _ in range(40):
        negative = constrained_negative(k - sigma * sp.diags(mass), g)
        if negative == 0:
            return sigma
        if negative < 0:
            return 0.0
        sigma = min(4.0 * sigma, -1e-3 * scale)
    return 0.0


def _result(model, x, level, lin, ok, report, scales, settings):
    if settings.eigenvalues and ok:
        report.eigenvalues = constrained_eigenvalues(model, lin, settings.eigenvalues)
    equilibrium = Equilibrium(report.iterations, bool(ok), float(level),
                              float(lin.volume), force_ratio=force_ratio(model, lin, scales))
    return MembraneState(x), equilibrium, report


def _path_tangent(model, lin: Linearisation, scales: SolveScales, previous, direction):
    """The unit tangent (scaled dx (3n,), dp, dV) of the path at a converged linearisation,
    oriented along ``previous`` (or so that the volume moves along ``direction``)."""
    try:
        b = Factorisation(lin.matrix).solve(lin.volume_gradient)
    except SingularTangent:
        return None
    gb = float(np.sum(lin.volume_gradient * b))
    t = np.concatenate([b.ravel() / scales.length, [1.0 / scales.level],
                        [gb / scales.volume]])
    t /= np.linalg.norm(t)
    if previous is not None:
        if float(t @ previous) < 0:
            t = -t
    elif direction is not None and np.sign(t[-1]) != direction:
        t = -t
    return t


def _arc_step(model, x0, level0, volume0, tangent, step, load, settings, scales):
    """Predictor along ``tangent`` by ``step``, then Newton on the equilibrium, the volume
    and the arc-length equation; (x, level, volume, iterations, linearisation) or None."""
    n3 = x0.size
    x = x0 + step * scales.length * tangent[:n3].reshape(x0.shape)
    level = level0 + step * scales.level * tangent[n3]
    target = volume0 + step * scales.volume * tangent[n3 + 1]
    t_x = tangent[:n3].reshape(x0.shape) / scales.length
    t_p, t_v = tangent[n3] / scales.level, tangent[n3 + 1] / scales.volume
    for it in range(1, settings.max_iterations + 1):
        lin = linearise(model, x, level, load)
        if not np.isfinite(lin.energy):
            return None
        arc = (float(np.sum(t_x * (x - x0))) + t_p * (level - level0)
               + t_v * (target - volume0) - step)
        if converged(model, lin, target, settings, scales) and abs(arc) <= 1e-8 * step:
            return x, level, target, it - 1, lin
        try:
            lu = Factorisation(lin.matrix)
            a = lu.solve(-lin.residual)
            b = lu.solve(lin.volume_gradient)
        except SingularTangent:
            return None
        g = lin.volume_gradient
        # g.(a + dp b) - dV = target - V ; t_x.(a + dp b) + t_p dp + t_v dV = -arc
        m = np.array([[float(np.sum(g * b)), -1.0],
                      [float(np.sum(t_x * b)) + t_p, t_v]])
        rhs = np.array([target - lin.volume - float(np.sum(g * a)),
                        -arc - float(np.sum(t_x * a))])
        try:
            dp, dv = np.linalg.solve(m, rhs)
        except np.linalg.LinAlgError:
            return None
        dx = a + dp * b
        alpha = _capped(model, dx, settings, scales)
        x = x + alpha * dx
        model.follow(x)
        level += alpha * dp
        target += alpha * dv
    return None


def constrained_eigenvalues(model: NewtonModel, lin: Linearisation, count: int) -> np.ndarray:
    """The ``count`` lowest eigenvalues omega^2 (1/s^2) of K phi = omega^2 M phi on the volume
    constraint's tangent space (g . phi = 0), M the lumped node masses, on the free degrees of
    freedom; sorted by real part. Shift-invert about a shift below the lowest
    (:func:`_shift_below`): about zero, a strongly negative eigenvalue is not among those
    nearest it. A tangent that is not symmetric (a follower load's) has no inertia to read:
    there the shift is zero and the eigenvalues are those nearest zero."""
    free = np.repeat(model.free, 3)
    k = sp.csr_matrix(lin.matrix)[free][:, free]
    g = lin.volume_gradient[model.free].ravel()
    mass = np.repeat(model.base.node_mass[model.free], 3)
    n = k.shape[0]
    if count >= n - 1:
        raise ValueError(f"{count} eigenvalues asked of {n} degrees of freedom")
    sigma = _shift_below(k, mass, g) if model.load_form == "energy" else 0.0
    bordered = sp.bmat([[k - sigma * sp.diags(mass), sp.csr_matrix(g[:, None])],
                        [sp.csr_matrix(g[None, :]), None]], format="csc")
    lu = splu(bordered)

    def solve(v):
        rhs = np.concatenate([np.asarray(v).ravel(), [0.0]])
        return lu.solve(rhs)[:n]

    opinv = LinearOperator((n, n), matvec=solve, dtype=float)
    values = eigs(k, k=count, M=sp.diags(mass), sigma=sigma, OPinv=opinv,
                  return_eigenvectors=False, which="LM")
    values = np.real_if_close(values, tol=1e6)
    return np.sort_complex(values) if np.iscomplexobj(values) else np.sort(values)
