"""Quasi-static equilibrium of the thesis membrane, pressure- or volume-controlled.

The equilibrium is found by pseudo-time stepping (dynamic relaxation) of the thesis forces
(Eqn 4.6: bending springs, pressure along node normals, gravity) with the position constraints
(App. G strain limiting, the tank wall) and the Verlet velocity v = (x_new - x_old)/dt, so that
constraint moves act as forces.  Only dt^2/m matters for the equilibrium; dt sets how stiff the
in-plane springs are between strain passes.  Choices that differ from the thesis stepper, each
needed for the relaxation to settle (all are settings):

* kinetic damping: all velocities are zeroed when the kinetic energy stops growing (an energy
  peak), the classic dynamic-relaxation damping; it leaves the slow modes undamped until their
  peak and needs no tuning against the slowest mode;
* exactly ``strain_passes`` Gauss-Seidel strain passes per step instead of App. G's stopping
  rule (passes until the error is below the limit), which switches the in-plane response
  between soft and rigid as the error crosses the limit and then locks the shape against the
  volume constraint; when the relaxed shape still exceeds the limit, a second stage relaxes it
  again with ``stiff_strain_passes`` passes per step, and the limit is checked on the
  converged shape (finish below);
* the tank wall without slack (the 1.001 slack of App. I chatters);
* bending forces capped at K_eq times the middle node's offset from its chord
  (:func:`structure.kernels.bending_force`, ``offset_limited``): the thesis force flips between
  +-K_eq d on compressed, nearly straight triples;
* no bend limiting (App. H) unless ``bend_limiting``: it keeps every two-cell chord near its rest
  length and locks the fold at the rim (docs/models/thesis-membrane.md, 'How the static sweep
  is solved').

Volume control.  The liquid volume is a hard constraint V(x) = V_target whose multiplier is the
uniform pressure level l (Pa) added to the hydrostatic field (the thesis's equivalent fluid
height h = l / (rho g), found here instead of iterated).  Each pseudo-step

1. the pressure p(x) + l pushes the membrane along its node normals (the thesis load);
2. after the strain and wall constraints, the free nodes that are not held by the wall are
   projected along W grad V onto the target volume (:func:`structure.kernels.
   project_volume_masked`), with multiplier lambda; a node touching the wall is held when its
   pressure presses it onto the wall (p + l <= 0) or when the projection would peel it off the
   wall: only the pressure lifts the membrane off the wall (a projection spread over the whole
   membrane pulls the wall-supported part inwards, compresses it and crumples it);
3. the level is corrected by ``level_gain * lambda / dt^2`` (integral action).

At convergence the projection does nothing (lambda -> 0), so the level alone holds the volume
through the thesis's own pressure load: it is the Lagrange multiplier of the relaxed model, not
a pseudo-dynamic artefact (the in-plane response between passes is penalty-like, so where the
shape needs strain, at folds, the level depends somewhat on ``strain_passes`` and ``dt``).  The
volume target is ramped from the start volume at ``ramp_rate``; the projection keeps the volume
exact at every step.  When every free node lies
on the wall (the empty membrane) the volume is fixed by the wall, no pressure level is
determined, and the level is reported as NaN.

A solve has converged when, after the ramp, the largest free-node move in one pseudo-step over
the node's length scale is below ``tolerance`` and the level changes by less than
``level_tolerance`` per step.  A finish then repeats single App. G passes, each followed by
the volume projection, until the strain limit (``constraints.error_limit``) and the volume both
hold on the returned shape; where that local sweep cannot meet both (the fold pattern reached
needs more stretch than the limit allows) the relaxed shape is returned as it is and its strain
is reported.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .kernels import (limit_bending, limit_in_plane_strain, project_volume_masked,
                      self_collision, wall_collision)
from .load import Equilibrium, Load
from .model import MembraneModel, MembraneState
from .thesis import ConstraintSettings, CourantError, node_force
from .volume import liquid_volume, liquid_volume_gradient, lower_hemisphere_volume

_NEWTON_ITERATIONS = 3
"""Newton steps of each volume projection (the volume is cubic in a uniform move)."""


def _relaxation_constraints() -> ConstraintSettings:
    return ConstraintSettings(wall_slack=1.0, gauss_seidel=True)


@dataclass(frozen=True)
class RelaxationSettings:
    """Pseudo-time relaxation settings (defaults: the thesis scene, 26 x 26 grid).

    * dt : pseudo time step (s).
    * damping : fraction of the velocity removed per step (-), on top of kinetic damping.
    * kinetic_damping : zero all velocities when the kinetic energy stops growing.
    * tolerance : converged when max |dx| / L_node per step < tolerance (-).
    * level_tolerance : converged only when the level changes by less than this per step (Pa).
    * level_gain : fraction of the projection multiplier lambda / dt^2 added to the level (-).
    * volume_tolerance : |V - V_target| over the tank volume (4/3) pi R^3 allowed on the returned
      shape (-).
    * ramp_rate : the volume target moves from the start volume to the goal by at most this
      fraction of the tank volume (4/3) pi R^3 per step (-).
    * max_projection_move : the volume projection moves no node more than this times its length
      scale per step (-).
    * max_steps : cap on pseudo-steps per solve.
    * strain_passes : App. G passes per step (-).
    * contact_tolerance : a node within contact_tolerance * R of the wall touches it (-).
    * offset_limited_bending : cap bending forces at K_eq times the chord offset (see module doc).
    * bend_limiting : apply App. H bend limiting (``constraints.bend_limit_iterations`` passes).
    * strain_limit_stage : under volume control, when the relaxed shape exceeds the strain limit,
      relax again from it with ``stiff_strain_passes`` passes per step (App. G's stopping
      rule, passes until the error is below the limit, makes nodes jump by cells there).
    * stiff_strain_passes : strain passes per step of that second stage.
    * constraints : :class:`ConstraintSettings`: wall_slack and gauss_seidel are used in every
      step, error_limit and max_strain_passes by the finish, bend_limit_iterations only with
      ``bend_limiting``, self_collision and collision_buffer (App. I after every strain
      limiting, in the relaxation and in the finish).
    """

    dt: float = 2e-4
    damping: float = 0.0
    kinetic_damping: bool = True
    tolerance: float = 1e-5
    level_tolerance: float = 0.1
    level_gain: float = 0.1
    volume_tolerance: float = 1e-4
    ramp_rate: float = 5e-5
    max_projection_move: float = 0.05
    max_steps: int = 8000
    strain_passes: int = 10
    contact_tolerance: float = 1e-4
    offset_limited_bending: bool = True
    bend_limiting: bool = False
    strain_limit_stage: bool = True
    stiff_strain_passes: int = 48
    constraints: ConstraintSettings = field(default_factory=_relaxation_constraints)

    def __post_init__(self):
        if not self.dt > 0:
            raise ValueError(f"dt must be > 0 s, got {self.dt!r}")
        if not 0 <= self.damping < 1:
            raise ValueError(f"damping must be in [0, 1), got {self.damping!r}")
        if not 0 < self.level_gain <= 1:
            raise ValueError(f"level_gain must be in (0, 1], got {self.level_gain!r}")
        if self.strain_passes < 1:
            raise ValueError(f"strain_passes must be >= 1, got {self.strain_passes!r}")


def solve_equilibrium(model: MembraneModel, state: MembraneState, load: Load,
                      settings: RelaxationSettings) -> tuple[MembraneState, Equilibrium]:
    """Relax ``state`` to equilibrium under ``load``: node pressure p(x) + the level.

    With ``load.volume_target`` (m^3) the liquid volume is constrained (ramped from the start
    volume at ``settings.ramp_rate``) and the uniform level (Pa) is solved for, starting from
    ``load.pressure_level``; without it the level is held at ``load.pressure_level``. Returns
    the new state (velocities zero) and an :class:`structure.load.Equilibrium` (its
    pressure_level NaN when the wall alone fixes the volume; move_ratio, strain_error and
    strain_max measured).
    """
    s, cs = settings, settings.constraints
    pressure, body_acceleration = load.pressure, load.body_acceleration
    volume_target, pressure_level = load.volume_target, load.pressure_level
    x = state.node_position.copy()
    inv_mass = model.node_inv_mass
    # exactly ``strain_passes`` passes: App. G's stopping rule (error below the limit) would
    # switch the in-plane response between soft and rigid as the error crosses the limit
    strain_args = (inv_mass, model.spring_nodes, model.spring_rest_length,
                   model.spring_family_start, model.total_rest_length, 0.0, s.strain_passes,
                   cs.gauss_seidel, s.strain_passes)
    volume_args = (model.face_nodes, model.volume_sign, lower_hemisphere_volume(model.radius))
    contact_radius = model.radius * (1.0 - s.contact_tolerance)
    start_volume = liquid_volume(model, x)
    ramp_steps = 0
    if volume_target is not None:
        tank_volume = 2.0 * lower_hemisphere_volume(model.radius)
        ramp_steps = int(np.ceil(abs(volume_target - start_volume) / (s.ramp_rate * tank_volume)))
    max_move = s.max_projection_move * model.node_length_scale
    level = float(pressure_level)
    # stage 1: ``strain_passes`` passes; stage 2 (only when stage 1 ends above the strain
    # limit): ``stiff_strain_passes`` passes, a stiffer in-plane response, from the relaxed shape
    stage_2_args = strain_args[:6] + (s.stiff_strain_passes, cs.gauss_seidel,
                                      s.stiff_strain_passes)
    steps = 0
    for stage, stage_args in enumerate((strain_args, stage_2_args)):
        if stage == 1 and (volume_target is None or not s.strain_limit_stage
                           or strain_error(model, x)[0] <= cs.error_limit):
            break
        x, level, determined, move, converged, steps = _relax_stage(
            model, x, pressure, body_acceleration, s, stage_args, volume_target, start_volume,
            ramp_steps, volume_args, contact_radius, max_move, level, steps)
    volume_slack = s.volume_tolerance * 2.0 * lower_hemisphere_volume(model.radius)
    if volume_target is not None:
        x = _finish(model, x, volume_target, cs, contact_radius, pressure(x) + level,
                    volume_args, volume_slack)
    volume = liquid_volume(model, x)
    if volume_target is not None and abs(volume - volume_target) > volume_slack:
        converged = False
    mean, worst = strain_error(model, x)
    info = Equilibrium(steps, converged, level if determined else float("nan"), volume,
                       move_ratio=move, strain_error=mean, strain_max=worst)
    return MembraneState(x, np.zeros_like(x)), info


def _relax_stage(model, x, pressure, body_acceleration, s, strain_args, volume_target, start_volume,
                 ramp_steps, volume_args, contact_radius, max_move, level, first_step):
    """Pseudo-time loop of :func:`solve_equilibrium` from ``x`` (see module doc), at most
    ``s.max_steps`` steps numbered from ``first_step + 1``; returns (x, level, determined,
    move, converged, last step)."""
    cs, dt = s.constraints, s.dt
    free = ~model.node_fixed
    inv_mass = model.node_inv_mass
    v = np.zeros_like(x)
    determined = True
    kinetic_energy = 0.0
    move = np.inf
    converged = False
    steps = first_step
    for steps in range(first_step + 1, first_step + s.max_steps + 1):
        node_pressure = pressure(x) + level
        force = node_force(model, x, node_pressure, body_acceleration,
                           s.offset_limited_bending)
        v = (1.0 - s.damping) * v + dt * inv_mass[:, None] * force
        x_old = x
        x = x + dt * v
        wall_collision(x, inv_mass, model.radius, cs.wall_slack)
        limit_in_plane_strain(x, *strain_args)
        if s.bend_limiting and cs.bend_limit_iterations > 0:
            limit_bending(x, inv_mass, model.bend_chord_nodes, model.bend_rest_length,
                          model.bend_family_start, cs.bend_limit_iterations, cs.gauss_seidel)
            limit_in_plane_strain(x, *strain_args)
        _separate(model, x, cs)
        wall_collision(x, inv_mass, model.radius, cs.wall_slack)
        ramping = False
        level_step = 0.0
        if volume_target is not None:
            ramp = min(1.0, steps / max(ramp_steps, 1))
            ramping = ramp < 1.0
            target = start_volume + ramp * (volume_target - start_volume)
            radius = np.sqrt(np.einsum("ij,ij->i", x, x))
            touching = radius >= contact_radius
            determined = bool(np.any(free & ~touching))
            lam = _project_volume(model, x, target, touching, node_pressure, volume_args,
                                  max_move)
            if determined:
                level_step = s.level_gain * lam / dt**2
                level += level_step
        v = (x - x_old) / dt
        if s.kinetic_damping:
            energy = float(np.einsum("i,ij,ij->", model.node_mass, v, v))
            if energy < kinetic_energy:
                v[:] = 0.0
            kinetic_energy = energy
        move = float(np.max(np.sqrt(np.einsum("ij,ij->i", x - x_old, x - x_old))[free]
                            / model.node_length_scale[free]))
        if not np.isfinite(move) or move > 1.0:
            raise CourantError(
                f"pseudo-step {steps}: a node moved {move:.3g} of its length in one step; "
                f"reduce relaxation dt (now {dt:g} s)")
        if not ramping and move < s.tolerance and abs(level_step) < s.level_tolerance:
            converged = True
            break
    return x, level, determined, move, converged, steps


def _project_volume(model, x, target, touching, node_pressure, volume_args, max_move) -> float:
    """Volume projection of ``x`` (in place) over the free nodes not held by the wall (see
    module doc); returns the multiplier lambda (kg/m)."""
    grow = target > liquid_volume(model, x)
    # d V / d x points out of the liquid: growing the volume moves a node along it, shrinking
    # against it; the move peels the node off the wall when it points towards the centre
    outward = np.einsum("ij,ij->i", liquid_volume_gradient(model, x), x)
    peels = outward < 0.0 if grow else outward > 0.0
    held = touching & ((node_pressure <= 0.0) | peels)
    movable = ~model.node_fixed & ~held
    return project_volume_masked(x, model.node_inv_mass, movable, *volume_args, target,
                                 _NEWTON_ITERATIONS, max_move)


def _finish(model, x, volume_target, cs: ConstraintSettings, contact_radius, node_pressure,
            volume_args, volume_slack, max_passes: int = 3000) -> np.ndarray:
    """Bring the relaxed shape ``x`` within the strain limit ``cs.error_limit`` while keeping
    the volume: repeated single App. G passes (Gauss-Seidel), each followed by the wall and the
    volume projection, until both the strain limit and the volume (within ``volume_slack``
    m^3) hold, at most ``max_passes`` times (one joint Gauss-Seidel sweep over all constraints).

    Returns the polished copy, or ``x`` unchanged when the two cannot both be met (the volume
    then needs more stretch than the limit allows).
    """
    args = (model.node_inv_mass, model.spring_nodes, model.spring_rest_length,
            model.spring_family_start, model.total_rest_length, 0.0, 1, cs.gauss_seidel)
    unlimited = np.full(model.n_nodes, np.inf)
    y = x.copy()
    for _ in range(max_passes):
        if (strain_error(model, y)[0] <= cs.error_limit
                and abs(liquid_volume(model, y) - volume_target) <= volume_slack
                and not _separate(model, y.copy(), cs)):
            return y
        limit_in_plane_strain(y, *args)
        _separate(model, y, cs)
        wall_collision(y, model.node_inv_mass, model.radius, cs.wall_slack)
        touching = np.einsum("ij,ij->i", y, y) >= contact_radius**2
        _project_volume(model, y, volume_target, touching, node_pressure, volume_args, unlimited)
    return x


def _separate(model: MembraneModel, x: np.ndarray, cs: ConstraintSettings) -> int:
    """App. I self-collision in place when ``cs.self_collision``; returns the pairs moved."""
    if not cs.self_collision:
        return 0
    return self_collision(x, model.node_inv_mass, model.grid_size,
                          cs.collision_buffer * model.min_rest_edge)


def strain_error(model: MembraneModel, node_position: np.ndarray) -> tuple[float, float]:
    """In-plane strain of the axial and shear springs: (thesis error sum |L - L0| / sum L0,
    largest single-spring |L - L0| / L0), both dimensionless."""
    a, b = model.spring_nodes[:, 0], model.spring_nodes[:, 1]
    length = np.linalg.norm(node_position[b] - node_position[a], axis=1)
    dev = np.abs(length - model.spring_rest_length)
    return float(dev.sum() / model.total_rest_length), float(np.max(dev / model.spring_rest_length))
