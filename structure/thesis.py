"""The thesis stepper (Levine 2014, App. B main loop), faithfully.

One step:

1. node areas (App. D) and normals (surfnorm rule) on the current shape;
2. forces, Eqn 4.6: F = F_bend + A p n + m g - c v (bending springs of App. F, pressure
   along node normals, gravity on free nodes, optional damping);
3. explicit Euler: a = F/m (+ the measured acceleration when ``steady_state`` is off), v += a dt,
   x += v dt;
4. Courant check, Eqn 4.7: max |v| dt / L_node must stay below 1, else :class:`CourantError`;
5. tank-wall collision, then ``constraint_iterations`` rounds of in-plane strain limiting
   (App. G), bend limiting (App. H), self-collision (App. I), and the wall again.

With ``steady_state`` on (the printed setting) the velocity is *not* corrected for the
constraint moves; off, the step opens with the Verlet correction v = (x - x_prev)/dt,
a = (v - v_prev)/dt as App. B does.  Damping modes: ``none`` (c = 0), ``critical``
(c = 2 sqrt(m k), k the node's bending stiffness) and ``courant-drag`` (c = the node's Courant
number of the previous step, which is what the printed code does because its Courant loop
overwrites ``c``; docs/user-guide/scenes.md, 'Thesis damping modes').
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .kernels import (bending_force, limit_bending, limit_in_plane_strain,
                      node_area_and_normal, self_collision, wall_collision)
from .load import Load, StepInfo, external_force
from .model import MembraneModel, MembraneState

DAMPING_MODES = ("none", "critical", "courant-drag")


class CourantError(RuntimeError):
    """Raised when a step's Courant number |v| dt / L_node exceeds 1 (thesis Eqn 4.7)."""


@dataclass(frozen=True)
class ConstraintSettings:
    """Position constraints applied after each integration step.

    * error_limit : in-plane strain limit as a fraction (thesis ErrorLimit/100).
    * bend_limit_iterations : App. H passes (thesis BendDamping); 0 switches bend limiting off.
    * self_collision : App. I self-collision on/off.
    * collision_buffer : collision distance as a fraction of the shortest rest edge (Cbuffer).
    * constraint_iterations : rounds of the constraint sequence per step.
    * wall_slack : a free node is put back on the tank wall when |x| > wall_slack * R (1.001).
    * max_strain_passes : cap on App. G passes per call.
    * gauss_seidel : relax springs one after another (True) instead of the thesis's Jacobi pass
      per family (False); see :func:`structure.kernels._relax_family`.
    """

    error_limit: float = 0.01
    bend_limit_iterations: int = 10
    self_collision: bool = False
    collision_buffer: float = 1.0
    constraint_iterations: int = 1
    wall_slack: float = 1.001
    max_strain_passes: int = 10_000
    gauss_seidel: bool = False


def apply_constraints(model: MembraneModel, pos: np.ndarray, cs: ConstraintSettings) -> float:
    """The App. B constraint sequence on ``pos`` (n, 3) m, in place; returns the last strain error."""
    args = (model.node_inv_mass, model.spring_nodes, model.spring_rest_length,
            model.spring_family_start, model.total_rest_length, cs.error_limit,
            cs.max_strain_passes, cs.gauss_seidel)
    wall_collision(pos, model.node_inv_mass, model.radius, cs.wall_slack)
    error = np.inf
    for _ in range(cs.constraint_iterations):
        _, error = limit_in_plane_strain(pos, *args)
        if cs.bend_limit_iterations > 0:
            limit_bending(pos, model.node_inv_mass, model.bend_chord_nodes, model.bend_rest_length,
                          model.bend_family_start, cs.bend_limit_iterations, cs.gauss_seidel)
            _, error = limit_in_plane_strain(pos, *args)
        if cs.self_collision:
            self_collision(pos, model.node_inv_mass, model.grid_size,
                           cs.collision_buffer * model.min_rest_edge)
            _, error = limit_in_plane_strain(pos, *args)
        wall_collision(pos, model.node_inv_mass, model.radius, cs.wall_slack)
    return error


def node_force(model: MembraneModel, pos: np.ndarray, node_pressure: np.ndarray,
               body_acceleration, offset_limited_bending: bool = False) -> np.ndarray:
    """Pressure + gravity (:func:`structure.load.external_force` on the App. D areas and
    normals) + bending forces (n, 3) N on the current shape (Eqn 4.6 less damping);
    ``offset_limited_bending`` see :func:`structure.kernels.bending_force`."""
    area, normal = node_area_and_normal(pos, model.grid_size, model.normal_sign)
    force = external_force(node_pressure, normal, model.node_free_mass, body_acceleration,
                           node_area=area)
    bending_force(pos, normal, model.bend_nodes, model.bend_rest_length, model.bend_stiffness,
                  force, offset_limited_bending)
    return force


@dataclass(frozen=True)
class ThesisSettings:
    """Settings of the thesis stepper (App. B names in brackets).

    steady_state : reset acceleration each step [SteadyState]; damping : one of DAMPING_MODES;
    constraints : :class:`ConstraintSettings`. The time step [dt] is the stepper's argument.
    """

    steady_state: bool = True
    damping: str = "courant-drag"
    constraints: ConstraintSettings = field(default_factory=ConstraintSettings)

    def __post_init__(self):
        if self.damping not in DAMPING_MODES:
            raise ValueError(f"damping must be one of {DAMPING_MODES}, got {self.damping!r}")


@dataclass
class ThesisState(MembraneState):
    """MembraneState plus what App. B carries between steps: previous position (n, 3) m,
    previous velocity (n, 3) m/s, and the per-node damping coefficient (n,) kg/s."""

    previous_position: np.ndarray = None  # type: ignore[assignment]
    previous_velocity: np.ndarray = None  # type: ignore[assignment]
    node_damping: np.ndarray = None  # type: ignore[assignment]

    def __post_init__(self):
        super().__post_init__()
        if self.previous_position is None:
            self.previous_position = self.node_position.copy()
        if self.previous_velocity is None:
            self.previous_velocity = self.node_velocity.copy()
        if self.node_damping is None:
            self.node_damping = np.zeros(self.node_position.shape[0])

    def copy(self) -> "ThesisState":
        return ThesisState(self.node_position.copy(), self.node_velocity.copy(),
                           self.previous_position.copy(), self.previous_velocity.copy(),
                           self.node_damping.copy())


def node_bending_stiffness(model: MembraneModel) -> np.ndarray:
    """Sum of K_eq (N/m) of the bending springs centred on each node, (n,)."""
    k = np.zeros(model.n_nodes)
    np.add.at(k, model.bend_nodes[:, 1], model.bend_stiffness)
    return k


def step(model: MembraneModel, state: ThesisState, load: Load, dt: float,
         settings: ThesisSettings) -> tuple[ThesisState, StepInfo]:
    """Advance ``state`` by one thesis step of ``dt`` (s) under ``load``: its node pressure
    (liquid side, gauge) plus its held ``pressure_level`` (Pa), and its body acceleration
    (3,) m/s^2 (the thesis stepper holds no volume). Returns the new state and its
    :class:`structure.load.StepInfo`."""
    if load.volume_target is not None:
        raise ValueError("the thesis stepper holds a pressure level, not a volume: "
                         "load.volume_target must be None")
    if not dt > 0:
        raise ValueError(f"dt must be > 0 s, got {dt!r}")
    x = state.node_position.copy()
    v = state.node_velocity.copy()
    node_pressure = load.pressure(x) + load.pressure_level
    force = node_force(model, x, node_pressure, load.body_acceleration)
    if settings.steady_state:
        acc = np.zeros_like(x)
        prev_x, prev_v = state.previous_position, state.previous_velocity
    else:
        v = (x - state.previous_position) / dt
        acc = (v - state.previous_velocity) / dt
        prev_x, prev_v = x.copy(), v.copy()
    if settings.damping == "critical":
        c = 2.0 * np.sqrt(model.node_free_mass * node_bending_stiffness(model))
    elif settings.damping == "courant-drag":
        c = state.node_damping
    else:
        c = np.zeros(model.n_nodes)
    force -= c[:, None] * v
    acc += model.node_inv_mass[:, None] * force
    v = v + acc * dt
    x = x + v * dt
    courant = np.linalg.norm(v, axis=1) * dt / model.node_length_scale
    if not np.all(np.isfinite(courant)) or courant.max() > 1.0:
        worst = int(np.nanargmax(np.where(np.isfinite(courant), courant, np.inf)))
        raise CourantError(
            f"Courant number {courant[worst]:.3g} > 1 at node {worst} (|v| = "
            f"{np.linalg.norm(v[worst]):.3g} m/s, dt = {dt:g} s, L = "
            f"{model.node_length_scale[worst]:.3g} m): reduce dt (thesis Eqn 4.7)")
    apply_constraints(model, x, settings.constraints)
    damping = courant if settings.damping == "courant-drag" else state.node_damping
    return ThesisState(x, v, prev_x, prev_v, damping), StepInfo(1, load.pressure_level)
