"""Dynamic XPBD: one time window of a coupled run, the membrane's inertia kept. Two window
schemes (:data:`WINDOW_SCHEMES`): ``substeps`` (:func:`step`: plain substeps, the stiffness
bias ~ dt^2 of unconverged sweeps sets the substep, :mod:`structure.xpbd`) and ``bdf2``
(:func:`bdf2_step`: the window as one implicit BDF2 step, its sweeps converged) and
``quasi-static`` (:func:`quasi_static_step`: the window's end in equilibrium, no inertia)."""
from __future__ import annotations

import copy
from dataclasses import replace

import numpy as np

from ..load import Load, StepInfo
from ..model import MembraneState
from ..volume import liquid_volume
from .damping import relative_damping
from .model import XpbdDivergence, XpbdModel, XpbdMultipliers, XpbdSettings, XpbdState, \
    node_external_force
from .statics import solve_equilibrium
from .substep import substep


def _checked_pressure(load: Load, x: np.ndarray) -> np.ndarray:
    """The load's node pressure (n,) Pa at positions x (n, 3) m, checked."""
    node_pressure = np.asarray(load.pressure(x), dtype=float)
    if node_pressure.shape != (len(x),):
        raise ValueError(f"node_pressure must have shape ({len(x)},) (Pa), got "
                         f"{node_pressure.shape}")
    if not np.all(np.isfinite(node_pressure)):
        raise ValueError(f"node_pressure has {int(np.sum(~np.isfinite(node_pressure)))} "
                         f"non-finite values (Pa)")
    return node_pressure


def step(model: XpbdModel, state: MembraneState, load: Load, dt: float,
         settings: XpbdSettings) -> tuple[XpbdState, StepInfo]:
    """Dynamic XPBD over one time window of ``dt`` (s).

    The window is cut into the fewest equal substeps no longer than ``settings.dt``; each is
    plain XPBD (multipliers from zero, velocities kept; ``settings.warm_start`` and
    ``kinetic_damping`` are ignored), so the membrane keeps its inertia, damped only by
    ``settings.node_damping`` (:mod:`.damping`, before each substep's forces; 0: none). The
    load's node pressure (n,) Pa (a field is evaluated at the window's start) acts on the
    liquid side throughout the window, on the current node area vectors. With
    ``load.volume_target`` (m^3) the liquid volume is held on the straight line from its
    value at the window's start to the target, substep by substep (one linearised
    projection each, so to first order in the substep's volume change), and the uniform
    pressure level that holds it is the volume multiplier over the substep squared (Pa,
    added to the node pressure); without, ``load.pressure_level`` is added and held.
    Returns (:class:`XpbdState` at the window's end with its velocities,
    :class:`structure.load.StepInfo` with the substeps and the level of the last substep).
    """
    if not dt > 0:
        raise ValueError(f"xpbd window duration must be > 0 s, got {dt!r}")
    n_sub = max(1, int(np.ceil(dt / settings.dt * (1.0 - 1e-12))))
    s = XpbdSettings(dt=dt / n_sub, iterations=settings.iterations, warm_start=False,
                     bending=settings.bending, kinetic_damping=False)
    x = np.array(state.node_position, dtype=float)
    v = np.array(state.node_velocity, dtype=float)
    node_pressure = _checked_pressure(load, x)
    volume = None
    if load.volume_target is not None:
        volume = (liquid_volume(model.base, x), float(load.volume_target))
    else:
        node_pressure = node_pressure + load.pressure_level
    damp = (relative_damping(model, s.dt, settings.node_damping)
            if settings.node_damping > 0 else None)
    for k in range(1, n_sub + 1):
        if damp is not None:
            damp(v)
        force = node_external_force(model, x, node_pressure, load.body_acceleration)
        target = None
        if volume is not None:
            target = volume[0] + (volume[1] - volume[0]) * k / n_sub
        lam = XpbdMultipliers.zeros(len(model.triangles))
        substep(model, x, v, force, lam, s, target, k)
        if not np.all(np.isfinite(x)):
            raise XpbdDivergence(f"xpbd window substep {k}: non-finite positions "
                                 f"(substep {s.dt:g} s)")
    level = lam.volume[0] / s.dt**2 if volume is not None else load.pressure_level
    return XpbdState(x, v, multipliers=None), StepInfo(n_sub, float(level))


def bdf2_weights(dt: float, dt_previous: float) -> tuple[float, float, float]:
    """(a0, a1, a2) of the variable-step BDF2 derivative y'(t^{n+1}) ~ (a0 y^{n+1} + a1 y^n
    + a2 y^{n-1}) / dt, r = dt / dt_previous (the liquid's time scheme uses the same,
    :mod:`fluid.time_schemes`)."""
    if not (dt > 0 and dt_previous > 0):
        raise ValueError(f"bdf2 steps must be > 0 s, got {dt!r} after {dt_previous!r}")
    r = dt / dt_previous
    return (1 + 2 * r) / (1 + r), -(1 + r), r * r / (1 + r)


def bdf2_step(model: XpbdModel, state: MembraneState, load: Load, dt: float,
              settings: XpbdSettings, history: tuple[MembraneState, float] | None = None
              ) -> tuple[XpbdState, StepInfo]:
    """The window of ``dt`` (s) as one implicit step, every force at the window's end.

    BDF2 for x' = v and M v' = f(x) from the state one window back, ``history`` =
    (state at t^{n-1}, its window dt_prev in s), written as backward Euler from a blended
    start (a0, a1, a2 of :func:`bdf2_weights`): x~ = -(a1 x^n + a2 x^{n-1}) / a0, the same
    for v~, step h = dt / a0; then x^{n+1} = x~ + h v^{n+1} with M (v^{n+1} - v~) / h =
    f(x^{n+1}), which is one XPBD substep of h from (x~, v~) whose sweeps are converged
    (``settings.iterations``; no history: backward Euler, h = dt). The load's pressure acts
    on the node area vectors at x~. With ``load.volume_target`` the step ends on it and the
    level is the volume multiplier over h^2 (Pa).

    Why: a coupled liquid step collocated at the window's end (:mod:`fluid.time_schemes`)
    hands the membrane its end pressure. Plain substeps (:func:`step`) integrate the
    membrane's inertia through the window under that pressure held from the window's start,
    so the light membrane feels the liquid's force early; with a BDF2 liquid the coupled
    slosh mode then grows (zeta -0.009 at 2 ms, half-full diaphragm, N = 10). Every force
    at the end of one step keeps the pair one BDF2 scheme."""
    if not dt > 0:
        raise ValueError(f"xpbd window duration must be > 0 s, got {dt!r}")
    x = np.array(state.node_position, dtype=float)
    v = np.array(state.node_velocity, dtype=float)
    a0 = 1.0
    if history is not None:
        previous, dt_previous = history
        a0, a1, a2 = bdf2_weights(dt, dt_previous)
        x = -(a1 * x + a2 * previous.node_position) / a0
        v = -(a1 * v + a2 * previous.node_velocity) / a0
    h = dt / a0
    s = XpbdSettings(dt=h, iterations=settings.iterations, warm_start=False,
                     bending=settings.bending, kinetic_damping=False)
    node_pressure = _checked_pressure(load, state.node_position)
    if load.volume_target is None:
        node_pressure = node_pressure + load.pressure_level
    force = node_external_force(model, x, node_pressure, load.body_acceleration)
    lam = XpbdMultipliers.zeros(len(model.triangles))
    target = None if load.volume_target is None else float(load.volume_target)
    substep(model, x, v, force, lam, s, target, 1)
    if not np.all(np.isfinite(x)):
        raise XpbdDivergence(f"xpbd bdf2 window: non-finite positions (step {h:g} s)")
    level = lam.volume[0] / h**2 if target is not None else load.pressure_level
    return XpbdState(x, v, multipliers=None), StepInfo(1, float(level))


def quasi_static_step(model: XpbdModel, state: MembraneState, load: Load, dt: float,
                      settings: XpbdSettings, history=None, relaxed: bool = False,
                      guess: MembraneState | None = None) -> tuple[XpbdState, StepInfo]:
    """The window's end as the membrane's static equilibrium under ``load``, its inertia
    dropped: warm-started quasi-static XPBD substeps of ``settings.dt``
    (:func:`structure.xpbd.solve_equilibrium`, ``settings.tolerance`` and ``max_steps``) from
    the window's start, the multipliers carried from the last window; ``relaxed``: damped
    dynamic relaxation instead (no warm start, kinetic damping, the volume ramped at
    ``settings.ramp_rate``), the static sweep's solve, slower but robust where the
    warm-started substeps blow up at a fold.  ``guess``: where the substeps start (with its
    multipliers) instead of the window's start, e.g. the last coupling iteration's end: the
    same equilibrium is sought, from nearer.  The load's field is
    evaluated at every substep, so a position-dependent part (the hydrostatic pressure) acts
    implicitly.  Velocities are the window's mean, (x_end - x_start) / dt, what a liquid
    sees of the moving wall.

    Where it holds: fills slow against the membrane's own periods (the membrane's kinetic
    energy negligible), where a window many times the explicit limit is wanted; the liquid
    keeps its inertia (docs/notes/slow-fills.md).  Raises :class:`XpbdDivergence` when the
    substeps do not reach the equilibrium."""
    if not dt > 0:
        raise ValueError(f"xpbd window duration must be > 0 s, got {dt!r}")
    start = np.array(state.node_position, dtype=float)
    first = state if guess is None else guess
    lam = getattr(first, "multipliers", None)
    warm = XpbdState(np.array(first.node_position, dtype=float), np.zeros_like(start),
                     multipliers=None if lam is None else copy.deepcopy(lam))
    s = replace(settings, warm_start=True, kinetic_damping=False, ramp_rate=1.0)
    if relaxed:
        s = replace(settings, warm_start=False, kinetic_damping=True)
    end, info = solve_equilibrium(model, warm, load, s)
    if not info.converged:
        raise XpbdDivergence(f"xpbd quasi-static window: no equilibrium after {info.steps} "
                             f"substeps of {s.dt:g} s (move ratio {info.move_ratio:.2e})")
    velocity = (end.node_position - start) / dt
    return XpbdState(end.node_position, velocity, multipliers=end.multipliers), \
        StepInfo(info.steps, info.pressure_level)


def _substeps(model, state, load, dt, settings, history=None):
    return step(model, state, load, dt, settings)


WINDOW_SCHEMES = {"substeps": _substeps, "bdf2": bdf2_step, "quasi-static": quasi_static_step}
"""name -> ``f(model, state, load, dt, settings, history)`` -> (state, StepInfo); ``history``
is (the state one window back, that window's dt in s) or None."""
