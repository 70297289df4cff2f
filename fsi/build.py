"""Turn a validated scene into solver objects: membrane Model, liquid, settings.

Also the a-priori time-step check: before a run, the first-step Courant number (thesis Eqn 4.7)
under the largest load the run can apply must stay below 1,

    C0 = dt^2 (p_max / (rho_m t) + |b|) / L_min < 1,

with p_max = rho_l |b| (h_max + R) the largest hydrostatic pressure on the membrane. This is a
necessary condition only: the stepper still checks the Courant number every step.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from fluid.hydrostatic import HydrostaticLiquid
from fluid.validation import tank_grid
from structure.model import Material, MembraneModel, hemisphere_model
from structure.statics import RelaxationSettings
from structure.thesis import ConstraintSettings, ThesisSettings

from .models import choose_model
from .scene import Scene, SceneError


PROCEDURE_MODEL = {"thesis-ramp": "thesis", "coupled-fill": "xpbd"}
"""Procedures that run one structure model only (the scene check allows it or 'auto')."""


@dataclass(frozen=True)
class Setup:
    """Everything a procedure needs: scene, model, liquid and solver settings."""

    scene: Scene
    model: MembraneModel
    liquid: HydrostaticLiquid
    constraints: ConstraintSettings
    relaxation: RelaxationSettings
    thesis: ThesisSettings
    structure_model: str = "thesis"


def courant_time_step_limit(model: MembraneModel, liquid: HydrostaticLiquid,
                            largest_height: float) -> float:
    """Largest dt (s) with a first-step Courant number below 1 (see module docstring);
    ``largest_height`` is the largest |equivalent height| (m) the run applies."""
    g = liquid.acceleration_magnitude
    p_max = liquid.density * g * (abs(largest_height) + model.radius)
    areal_mass = model.material.density * model.material.thickness
    accel = p_max / areal_mass + g
    if accel == 0.0:
        return float("inf")
    return float(np.sqrt(model.node_length_scale.min() / accel))


def build(scene: Scene) -> Setup:
    """Build the :class:`Setup` of ``scene``; raises :class:`SceneError` on a bad time step."""
    m, c = scene["membrane"], scene["constraints"]
    material = Material(m["thickness"], m["density"], m["youngs_modulus"], m["poisson_ratio"])
    model = hemisphere_model(m["grid_size"], scene["tank"]["radius"], material, m["support"])
    liquid = HydrostaticLiquid(scene["liquid"]["density"],
                               tuple(scene["liquid"]["body_acceleration"]))
    constraints = ConstraintSettings(
        error_limit=c["error_limit"] / 100.0, bend_limit_iterations=c["bend_limit_iterations"],
        self_collision=c["self_collision"], collision_buffer=c["collision_buffer"],
        constraint_iterations=c["constraint_iterations"])
    th = scene["thesis"]
    thesis = ThesisSettings(dt=th["dt"], steady_state=th["steady_state"], damping=th["damping"],
                            constraints=constraints)
    relaxation = RelaxationSettings()
    given = {k: v for k, v in scene["relaxation"].items() if v is not None}
    relaxation = replace(relaxation, **given,
                         constraints=replace(relaxation.constraints,
                                             error_limit=constraints.error_limit,
                                             self_collision=constraints.self_collision,
                                             collision_buffer=constraints.collision_buffer))
    if scene["scene"]["procedure"] == "thesis-ramp":
        h = max(abs(th["height_start"]), abs(th["height_end"])) * model.radius
        _check_dt("thesis.dt", th["dt"], courant_time_step_limit(model, liquid, h))
    else:
        _check_dt("relaxation.dt", relaxation.dt,
                  courant_time_step_limit(model, liquid, model.radius))
    if scene["scene"]["procedure"] == "coupled-fill":
        _check_port(scene)
    structure = scene["structure"]
    chosen = PROCEDURE_MODEL.get(scene["scene"]["procedure"]) or choose_model(
        structure["model"], model.grid_size, structure["accuracy"])
    return Setup(scene, model, liquid, constraints, relaxation, thesis, chosen)


PORT_MIN_CELLS = {"radius": 1.5, "length": 2.0}
"""The port stub must span this many fluid cells in radius and in length to carry its flow."""


def _check_port(scene: Scene) -> None:
    h = tank_grid(scene["tank"]["radius"], scene["fluid"]["cells"], axisymmetric=False).spacing
    for key, cells in PORT_MIN_CELLS.items():
        value = scene["port"][key]
        if value < cells * h:
            raise SceneError(f"scene key 'port.{key}' = {value!r} m is under {cells} cells of the "
                             f"fluid grid (cell {h:.4g} m at fluid.cells = "
                             f"{scene['fluid']['cells']}); allowed {cells * h:.4g} m and up, "
                             f"or more fluid cells")
    radius = scene["port"]["radius"]
    if radius >= scene["tank"]["radius"]:
        raise SceneError(f"scene key 'port.radius' = {radius!r} m: allowed below the tank "
                         f"radius {scene['tank']['radius']!r} m")


def _check_dt(key: str, dt: float, limit: float) -> None:
    if dt >= limit:
        raise SceneError(f"scene key '{key}' = {dt!r} breaks the Courant limit (thesis Eqn 4.7) "
                         f"for this membrane and load; allowed 0 < dt < {limit:.3g} s")
