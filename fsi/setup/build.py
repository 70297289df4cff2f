"""Turn a validated scene into the solver objects every procedure shares: the membrane
Model, the hydrostatic liquid, the constraint and relaxation settings, the structure model.

What only one procedure needs (the thesis stepper's settings, the fluid grid, the coupling)
its own module builds from its own tables; its setup checks (stability limits, grid spacings)
run here, before anything is computed or written.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Optional

from fluid.hydrostatic import HydrostaticLiquid
from structure.grid import Grading
from structure.model import MEMBRANE_SHAPES, Material, MembraneModel
from structure.statics import RelaxationSettings
from structure.thesis import ConstraintSettings

from fsi.setup.limits import check_memory
from fsi.setup.models import choose_model
from fsi.registry import PROCEDURES, Procedure, SceneError

WRINKLING_MODELS = ("xpbd", "minimisation")
"""Structure models that run the XPBD model's energies, and so its wrinkling laws."""


@dataclass(frozen=True)
class Setup:
    """Everything a procedure needs: scene (:class:`fsi.scene.Scene`), membrane model, liquid
    and solver settings, and the structure model it runs."""

    scene: object
    model: MembraneModel
    liquid: HydrostaticLiquid
    constraints: ConstraintSettings
    relaxation: RelaxationSettings
    structure_model: str
    checkpoint: Optional[Path] = None
    """Where a time-dependent procedure writes its checkpoints (None: it does not)."""
    resume: Optional[dict] = None
    """A checkpoint's payload to continue from (:mod:`fsi.io.checkpoint`), or None."""

    @property
    def procedure(self) -> Procedure:
        return PROCEDURES[self.scene["scene"]["procedure"]]


def relaxation_settings(scene, constraints: ConstraintSettings) -> RelaxationSettings:
    """The static relaxation's settings: the scene's ``[relaxation]`` keys that are given, the
    solver's defaults for the others, and the scene's strain limit and self-collision."""
    relaxation = RelaxationSettings()
    given = {k: v for k, v in scene["relaxation"].items() if v is not None}
    return replace(relaxation, **given,
                   constraints=replace(relaxation.constraints,
                                       error_limit=constraints.error_limit,
                                       self_collision=constraints.self_collision,
                                       collision_buffer=constraints.collision_buffer))


def grading(scene) -> Grading:
    """The membrane grid's :class:`structure.grid.Grading` of ``scene``."""
    m = scene["membrane"]
    return Grading(tuple(float(v) for v in m["grading_band"]), float(m["grading_density"]))


def membrane_model(scene) -> MembraneModel:
    """The :class:`structure.model.MembraneModel` of ``scene``'s ``membrane`` and ``tank``
    tables (shape, grid and its grading, support, material), without the procedure's
    checks."""
    m = scene["membrane"]
    material = Material(m["thickness"], m["density"], m["youngs_modulus"], m["poisson_ratio"],
                        m["wrinkling"])
    return MEMBRANE_SHAPES[m["shape"]](m["grid_size"], scene["tank"]["radius"], material,
                                       m["support"], grading(scene))


def build(scene) -> Setup:
    """Build the :class:`Setup` of ``scene`` and run its procedure's setup checks (raising
    :class:`fsi.registry.SceneError` naming the key)."""
    procedure = PROCEDURES[scene["scene"]["procedure"]]
    m, c = scene["membrane"], scene["constraints"]
    check_memory(m["grid_size"])
    model = membrane_model(scene)
    if model.node_fixed.all():
        raise SceneError(f"scene keys 'membrane.grid_size' = {m['grid_size']} and "
                         f"'membrane.support' = '{m['support']}': every node is held by the "
                         "support, none is free; allowed: a larger grid_size")
    liquid = HydrostaticLiquid(scene["liquid"]["density"],
                               tuple(scene["liquid"]["body_acceleration"]))
    constraints = ConstraintSettings(
        error_limit=c["error_limit"] / 100.0, bend_limit_iterations=c["bend_limit_iterations"],
        self_collision=c["self_collision"], collision_buffer=c["collision_buffer"],
        constraint_iterations=c["constraint_iterations"])
    structure = scene["structure"]
    chosen = procedure.structure_model or choose_model(structure["model"], model.grid_size,
                                                       structure["accuracy"])
    if m["wrinkling"] != "none" and chosen not in WRINKLING_MODELS:
        raise SceneError(f"scene key 'membrane.wrinkling' = '{m['wrinkling']}' needs the xpbd "
                         f"model's energies, and this scene runs '{chosen}'; allowed: 'none', "
                         f"or structure.model one of {list(WRINKLING_MODELS)}")
    setup = Setup(scene, model, liquid, constraints, relaxation_settings(scene, constraints),
                  chosen)
    procedure.check_setup(setup)
    return setup
