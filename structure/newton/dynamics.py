"""Implicit dynamics of the membrane: the generalised-alpha method (Chung & Hulbert 1993),
Newton in each step, no Courant limit.

For M a + C v + r(x, p0) = 0, r the residual of :mod:`.system` (internal forces minus the
load, the level p0 the multiplier of the volume where the load holds one), the step from
t_n to t_n+1 satisfies

    M a_{n+1-am} + C v_{n+1-af} + r(x_{n+1-af}, p0) = 0,
    x_{n+1} = x_n + dt v_n + dt^2 [(1/2 - beta) a_n + beta a_{n+1}],
    v_{n+1} = v_n + dt [(1 - gamma) a_n + gamma a_{n+1}],

with y_{n+1-a} = (1 - a) y_{n+1} + a y_n and, for the high-frequency spectral radius rho_inf
in [0, 1], am = (2 rho_inf - 1)/(rho_inf + 1), af = rho_inf/(rho_inf + 1), gamma = 1/2 - am + af,
beta = (1 - am + af)^2 / 4: second order, unconditionally stable, and without numerical
dissipation at rho_inf = 1 (the trapezoidal rule). The unknown is x_{n+1} (with p0 where the
volume is held: V(x_{n+1}) = V*); its Jacobian is

    M (1 - am)/(beta dt^2) + C gamma (1 - af)/(beta dt) + (1 - af) K(x_{n+1-af}),

solved with the volume's border as in the statics, its factorisation kept across the step's
iterations while they contract (modified Newton). M is the lumped node masses, C the node
damping's edge Laplacian (:mod:`structure.tangent.inertia`) when ``node_damping`` > 0.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
import scipy.sparse as sp

from ..load import Load, StepInfo
from ..model import MembraneState
from ..grid import triangle_edges
from ..tangent.inertia import DampingTerm
from ..tangent.pattern import Tangent
from ..volume import liquid_volume, liquid_volume_gradient
from .linear import Factorisation, SingularTangent
from .system import NewtonModel, linearise


CONTRACTION = 0.25
"""Modified Newton keeps its factorisation while each iteration's residual is at most this
fraction of the last (-)."""
STAGNATION = 1e-13
"""A step's Newton also converges when its correction is below this fraction of the tank
radius (round-off; -)."""


class NewtonDivergence(RuntimeError):
    """A step's Newton iteration did not converge (the caller may shorten the step)."""


@dataclass(frozen=True)
class AlphaSettings:
    """Settings of the generalised-alpha steps.

    * rho_inf : the high-frequency spectral radius in [0, 1] (1: no numerical dissipation);
    * force_tolerance : a step's Newton converges when the largest free-node residual force is
      below this fraction of the largest inertial, residual or load force of the step (the
      load: the pressure on a node's area and its weight) (-);
    * max_iterations : Newton iterations per step;
    * node_damping : c (N s/m) of the relative node damping (0: none);
    * reuse_factorisation : modified Newton: keep the step's factorised Jacobian while each
      iteration cuts the residual to at most ``CONTRACTION`` of the last, refactorise when
      one does not.
    """

    rho_inf: float = 1.0
    force_tolerance: float = 1e-8
    max_iterations: int = 25
    node_damping: float = 0.0
    reuse_factorisation: bool = True

    def __post_init__(self):
        if not 0.0 <= self.rho_inf <= 1.0:
            raise ValueError(f"rho_inf must be in [0, 1], got {self.rho_inf!r}")
        if not self.force_tolerance > 0:
            raise ValueError(f"force_tolerance must be > 0, got {self.force_tolerance!r}")
        if self.max_iterations < 1:
            raise ValueError(f"max_iterations must be >= 1, got {self.max_iterations!r}")
        if not self.node_damping >= 0:
            raise ValueError(f"node_damping must be >= 0 N s/m, got {self.node_damping!r}")

    @property
    def coefficients(self) -> tuple[float, float, float, float]:
        """(alpha_m, alpha_f, gamma, beta) of Chung & Hulbert (1993)."""
        r = self.rho_inf
        am = (2.0 * r - 1.0) / (r + 1.0)
        af = r / (r + 1.0)
        gamma = 0.5 - am + af
        beta = 0.25 * (1.0 - am + af) ** 2
        return am, af, gamma, beta


@dataclass
class AlphaState(MembraneState):
    """Positions (n, 3) m, velocities (n, 3) m/s and accelerations (n, 3) m/s^2 (None: found
    from the equations of motion at the first step); ``jacobian``: the last step's factorised
    Jacobian and its step (s), which the next step of the same length starts from (modified
    Newton across steps; None: none); ``node_load_pressure``: the held node pressure (n,) Pa
    of the step that ended here, which the next step blends to its alpha level (None: the
    next step's pressure alone)."""

    node_acceleration: Optional[np.ndarray] = None
    jacobian: Optional[tuple] = None
    node_load_pressure: Optional[np.ndarray] = None

    def __getstate__(self):
        """Pickled (a checkpoint) without the factorisation, which SuperLU cannot pickle and
        the next step rebuilds."""
        return {**self.__dict__, "jacobian": None}


def _damping(model: NewtonModel, coefficient: float):
    if coefficient <= 0:
        return None
    edges = triangle_edges(model.terms[0].element_nodes)
    return DampingTerm(edges, coefficient)


def initial_acceleration(model: NewtonModel, state: MembraneState, load: Load,
                         level: float, damping=None) -> np.ndarray:
    """a_0 = -M^-1 (r(x_0, p0) + C v_0) on the free nodes, zero on the fixed ones; where the
    load holds a volume, with the level p0 that keeps it, dV/dx . a_0 = 0 (the level given
    is only a guess: a wrong one would accelerate the whole sheet through the tank)."""
    x = np.asarray(state.node_position, dtype=float)
    v = np.asarray(state.node_velocity, dtype=float)
    lin = linearise(model, x, level, load, hessian=False)
    force = lin.residual
    if damping is not None:
        force = force + damping.evaluate(v, False)[1]
    inverse_mass = np.zeros(len(x))
    free = ~model.base.node_fixed
    inverse_mass[free] = 1.0 / model.base.node_mass[free]
    a = -force * inverse_mass[:, None]
    if load.volume_target is not None:
        # r(p) = r(p0) - (p - p0) g: the level's shift that makes g . a vanish
        g = lin.volume_gradient
        gmg = float(np.sum(g * g * inverse_mass[:, None]))
        if gmg > 0:
            a = a + g * inverse_mass[:, None] * (-float(np.sum(g * a)) / gmg)
    a[model.base.node_fixed] = 0.0
    return a


def step(model: NewtonModel, state: MembraneState, load: Load, dt: float,
         settings: AlphaSettings = AlphaSettings()) -> tuple[AlphaState, StepInfo]:
    """One generalised-alpha step of ``dt`` (s) from ``state`` under ``load`` (its node
    pressure, a field of the positions or an array (n,) Pa: the step's end value, taken at
    the alpha level (1 - af) p_n+1 + af p_n where ``state`` carries the last step's
    ``node_load_pressure`` p_n; with ``load.volume_target`` the volume reaches it at the
    step's end and the level is its multiplier, started at ``load.pressure_level``; without,
    the level ``load.pressure_level`` is held). Returns (:class:`AlphaState` at t + dt,
    :class:`structure.load.StepInfo` with the Newton iterations and the level). Raises
    :class:`NewtonDivergence` when the step's Newton does not converge (an iterate whose
    triangles degenerate included), the hinges' references then back where the step began
    (a retry from ``state`` picks each hinge's turn as before it)."""
    if not dt > 0:
        raise ValueError(f"time step must be > 0 s, got {dt!r}")
    saved = model.path_state()
    try:
        return _step(model, state, load, dt, settings)
    except NewtonDivergence:
        model.restore_path(saved)
        raise


def _step(model: NewtonModel, state: MembraneState, load: Load, dt: float,
          settings: AlphaSettings) -> tuple[AlphaState, StepInfo]:
    """:func:`step`, the hinges' references left where its last iterate took them."""
    am, af, gamma, beta = settings.coefficients
    base = model.base
    fixed = base.node_fixed
    mass = base.node_mass[:, None]
    damping = _damping(model, settings.node_damping)
    level = float(load.pressure_level)
    x0 = np.array(state.node_position, dtype=float)
    v0 = np.array(state.node_velocity, dtype=float)
    a0 = getattr(state, "node_acceleration", None)
    a0 = initial_acceleration(model, state, load, level, damping) if a0 is None else \
        np.array(a0, dtype=float)
    # predictor: the step's end at constant acceleration (a_{n+1} = a_n)
    x = x0 + dt * v0 + dt * dt * 0.5 * a0
    held = load.volume_target is not None
    end_pressure = None if callable(load.node_pressure) else \
        np.asarray(load.node_pressure, dtype=float)
    last_pressure = getattr(state, "node_load_pressure", None)
    if end_pressure is not None and last_pressure is not None and af:
        load = replace(load, node_pressure=(1.0 - af) * end_pressure + af * last_pressure)
    c_m = (1.0 - am) / (beta * dt * dt)
    c_c = gamma * (1.0 - af) / (beta * dt)
    mass_diag = model.dof_mass
    damping_matrix = None
    scale = None
    lu, previous = None, None
    kept = getattr(state, "jacobian", None)
    if settings.reuse_factorisation and kept is not None and kept[1] == dt:
        lu, previous = kept[0], np.inf
    for it in range(1, settings.max_iterations + 1):
        a = (x - x0 - dt * v0 - dt * dt * (0.5 - beta) * a0) / (beta * dt * dt)
        v = v0 + dt * ((1.0 - gamma) * a0 + gamma * a)
        xa = (1.0 - af) * x + af * x0
        va = (1.0 - af) * v + af * v0
        aa = (1.0 - am) * a + am * a0
        lin = _linearise(model, xa, level, load, dt, hessian=False)
        inertia = mass * aa
        residual = inertia + lin.residual
        if damping is not None:
            residual = residual + damping.evaluate(va, False)[1]
        residual[fixed] = 0.0
        if scale is None:
            scale = max(float(np.abs(inertia[~fixed]).max(initial=0.0)),
                        float(np.abs(lin.residual[~fixed] + inertia[~fixed]).max(initial=0.0)),
                        float(np.abs(lin.residual[~fixed]).max(initial=0.0)),
                        _load_scale(model, load, lin, xa, level), 1e-30)
        volume_error = 0.0
        if held:
            volume_error = load.volume_target - liquid_volume(base, x)
        if float(np.abs(residual).max()) <= settings.force_tolerance * scale and \
                abs(volume_error) <= 1e-12 * max(abs(load.volume_target or 1.0), 1e-30):
            return _done(x, v, a, fixed, level, it - 1, (lu, dt) if lu is not None else None,
                         end_pressure)
        norm = float(np.abs(residual).max())
        if lu is None or not settings.reuse_factorisation or norm > CONTRACTION * previous:
            matrix = (1.0 - af) * _linearise(model, xa, level, load, dt).matrix \
                + sp.diags(c_m * mass_diag)
            if damping is not None:
                if damping_matrix is None:
                    damping_matrix = Tangent.build(len(x), [damping]).evaluate(v)[2]
                matrix = matrix + c_c * damping_matrix
            try:
                lu = Factorisation(matrix)
            except SingularTangent as error:
                raise NewtonDivergence(f"generalised-alpha step of {dt:g} s: {error}") \
                    from error
        previous = norm
        try:
            dx_a = lu.solve(-residual)
            if held:
                # dR/dp0 = -g(x_a); the constraint's gradient is g(x_{n+1})
                g_end = liquid_volume_gradient(base, x)
                g_end[fixed] = 0.0
                b = lu.solve(lin.volume_gradient)
                gb = float(np.sum(g_end * b))
                dp = (volume_error - float(np.sum(g_end * dx_a))) / gb
                dx = dx_a + dp * b
                level += dp
            else:
                dx = dx_a
        except SingularTangent as error:
            raise NewtonDivergence(f"generalised-alpha step of {dt:g} s: {error}") from error
        dx[fixed] = 0.0
        x = x + dx
        if not np.all(np.isfinite(x)):
            break
        try:
            model.follow(x)
        except (ZeroDivisionError, FloatingPointError) as error:
            raise NewtonDivergence(f"generalised-alpha step of {dt:g} s: the iterate "
                                   f"degenerates ({error})") from error
        if float(np.abs(dx).max()) <= STAGNATION * base.radius and \
                abs(volume_error) <= 1e-9 * max(abs(load.volume_target or 0.0), 1e-30):
            # the correction is at round-off: the residual's floor is the cancellation of
            # the element forces, not a lack of convergence
            a = (x - x0 - dt * v0 - dt * dt * (0.5 - beta) * a0) / (beta * dt * dt)
            v = v0 + dt * ((1.0 - gamma) * a0 + gamma * a)
            return _done(x, v, a, fixed, level, it, (lu, dt), end_pressure)
    raise NewtonDivergence(f"generalised-alpha step of {dt:g} s: Newton did not converge in "
                           f"{settings.max_iterations} iterations")


def _linearise(model: NewtonModel, x, level: float, load: Load, dt: float, hessian=True):
    """:func:`structure.newton.system.linearise`, an iterate whose triangles degenerate (a zero division in
    the element kernels) raised as :class:`NewtonDivergence`."""
    try:
        return linearise(model, x, level, load, hessian=hessian)
    except (ZeroDivisionError, FloatingPointError) as error:
        raise NewtonDivergence(f"generalised-alpha step of {dt:g} s: the iterate degenerates "
                               f"({error})") from error


def _load_scale(model: NewtonModel, load: Load, lin, x: np.ndarray, level: float) -> float:
    """The largest free-node load (N): the pressure's |p + p0| |dV/dx_i| (the gradient
    ``lin``'s, at ``x``) and the weight m_i |b|. A step that starts in equilibrium (a slow
    fill's window) has no residual or inertia to measure its tolerance against; the load it
    carries is the force scale."""
    base = model.base
    free = ~base.node_fixed
    body = float(np.linalg.norm(np.asarray(load.body_acceleration, dtype=float)))
    weight = float(base.node_mass[free].max(initial=0.0)) * body
    gradient = lin.volume_gradient[free]
    pressure = np.asarray(load.pressure(x), dtype=float)[free] + level
    return max(weight, float(np.max(np.abs(pressure) * np.linalg.norm(gradient, axis=1),
                                    initial=0.0)))


def _done(x, v, a, fixed, level, iterations, jacobian=None, pressure=None):
    v = v.copy()
    a = a.copy()
    v[fixed] = 0.0
    a[fixed] = 0.0
    return AlphaState(x, v, node_acceleration=a, jacobian=jacobian,
                      node_load_pressure=None if pressure is None else pressure.copy()), \
        StepInfo(iterations, float(level))
