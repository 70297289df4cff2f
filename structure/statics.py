"""Quasi-static equilibrium of the thesis membrane, pressure- or volume-controlled.

The equilibrium is found by damped pseudo-time stepping (dynamic relaxation) of the thesis
forces (Eqn 4.6: bending springs, pressure along node normals, gravity) and position
constraints (App. G-I and the tank wall), with the Verlet velocity correction
v = (x_new - x_old)/dt so that constraint moves act as forces, and a velocity damping factor.

Volume control carries the liquid volume as a hard constraint V(x) = V_target with a Lagrange
multiplier: each pseudo-step the free nodes are projected along W grad V onto the target volume
(:func:`structure.volume.project_volume`); the multiplier of that projection divided by dt^2 is a
uniform pressure, accumulated into the pressure level, so at convergence the level is the
uniform pressure that holds the volume (the thesis's "equivalent fluid height", found here
directly instead of by iteration).

A solve stops when the largest free-node move per pseudo-step, relative to its length scale,
stays below ``tolerance`` (and the volume matches its target) or after ``max_steps``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from .kernels import limit_in_plane_strain, wall_collision
from .model import MembraneModel, MembraneState
from .thesis import ConstraintSettings, CourantError, apply_constraints, external_force
from .volume import liquid_volume, project_volume

PressureField = Callable[[np.ndarray], np.ndarray]
"""Pressure (n,) Pa on the liquid side at node positions (n, 3) m, excluding the uniform level."""


@dataclass(frozen=True)
class RelaxationSettings:
    """Pseudo-time relaxation settings.

    dt : pseudo time step (s). damping : fraction of the velocity removed per step (-).
    tolerance : convergence when max |dx| / L_node per step < tolerance (-).
    volume_tolerance : |V - V_target| / V_target allowed at the end (-).
    ramp_steps : steps over which a volume target is moved from the start volume to the goal.
    max_steps : cap on pseudo-steps per solve.
    constraints : :class:`ConstraintSettings`.
    """

    dt: float = 1e-3
    damping: float = 0.1
    tolerance: float = 1e-5
    volume_tolerance: float = 1e-4
    ramp_steps: int = 100
    max_steps: int = 5000
    constraints: ConstraintSettings = field(default_factory=ConstraintSettings)

    def __post_init__(self):
        if not self.dt > 0:
            raise ValueError(f"dt must be > 0 s, got {self.dt!r}")
        if not 0 <= self.damping < 1:
            raise ValueError(f"damping must be in [0, 1), got {self.damping!r}")


@dataclass
class EquilibriumInfo:
    """Outcome of one solve: steps taken, whether it converged, final move ratio (-), final
    pressure level (Pa), liquid volume (m^3) and in-plane strain error (-)."""

    steps: int
    converged: bool
    move_ratio: float
    pressure_level: float
    liquid_volume: float
    strain_error: float


def solve_equilibrium(model: MembraneModel, state: MembraneState, pressure: PressureField,
                      body_acceleration, settings: RelaxationSettings,
                      volume_target: Optional[float] = None,
                      pressure_level: float = 0.0) -> tuple[MembraneState, EquilibriumInfo]:
    """Relax ``state`` to equilibrium under ``pressure(x) + pressure_level``.

    With ``volume_target`` (m^3) the liquid volume is constrained (ramped from the start volume
    over ``settings.ramp_steps``) and the uniform ``pressure_level`` (Pa) is solved for;
    without it the level is held fixed. Returns the new state and an :class:`EquilibriumInfo`.
    """
    dt = settings.dt
    x = state.node_position.copy()
    v = np.zeros_like(x)
    free = ~model.node_fixed
    start_volume = liquid_volume(model, x)
    level = float(pressure_level)
    applied_level = level if volume_target is None else 0.0
    move = np.inf
    converged = False
    steps = 0
    for steps in range(1, settings.max_steps + 1):
        force, _, _ = external_force(model, x, pressure(x) + applied_level, body_acceleration)
        v = (1.0 - settings.damping) * v + dt * model.node_inv_mass[:, None] * force
        x_old = x
        x = x + dt * v
        apply_constraints(model, x, settings.constraints)
        ramping = False
        if volume_target is not None:
            ramp = min(1.0, steps / max(settings.ramp_steps, 1))
            ramping = ramp < 1.0
            lam = project_volume(model, x, start_volume + ramp * (volume_target - start_volume))
            level = lam / dt**2
        v = (x - x_old) / dt
        move = float(np.max(np.linalg.norm(x - x_old, axis=1)[free] / model.node_length_scale[free]))
        if not np.isfinite(move) or move > 1.0:
            raise CourantError(
                f"pseudo-step {steps}: a node moved {move:.3g} of its length in one step; "
                f"reduce relaxation dt (now {dt:g} s) or raise damping")
        if not ramping and move < settings.tolerance:
            converged = True
            break
    strain = _finish(model, x, settings.constraints, volume_target)
    info = EquilibriumInfo(steps, converged, move, level, liquid_volume(model, x), strain)
    return MembraneState(x, np.zeros_like(x)), info


def _finish(model, x, cs: ConstraintSettings, volume_target, rounds: int = 20) -> float:
    """Alternate strain limiting and volume projection so both hold at the end; returns the
    final strain error."""
    args = (model.node_inv_mass, model.spring_nodes, model.spring_rest_length,
            model.spring_family_start, model.total_rest_length, cs.error_limit,
            cs.max_strain_passes, cs.gauss_seidel)
    error = np.inf
    for _ in range(rounds):
        _, error = limit_in_plane_strain(x, *args)
        wall_collision(x, model.node_inv_mass, model.radius, cs.wall_slack)
        if volume_target is None:
            break
        project_volume(model, x, volume_target)
        if strain_error(model, x)[0] <= cs.error_limit:
            break
    return strain_error(model, x)[0]


def strain_error(model: MembraneModel, node_position: np.ndarray) -> tuple[float, float]:
    """In-plane strain of the axial and shear springs: (thesis error sum |L - L0| / sum L0,
    largest single-spring |L - L0| / L0), both dimensionless."""
    a, b = model.spring_nodes[:, 0], model.spring_nodes[:, 1]
    length = np.linalg.norm(node_position[b] - node_position[a], axis=1)
    dev = np.abs(length - model.spring_rest_length)
    return float(dev.sum() / model.total_rest_length), float(np.max(dev / model.spring_rest_length))
