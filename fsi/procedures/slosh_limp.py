"""``slosh.surface = "limp"``: the limp diaphragm in a slosh run, i.e. the liquid's free
surface.

* Surface: a height surface over the fluid grid's columns (:class:`fsi.slosh.limp.HeightSurface`),
  slack, massless and without bending, moved each window by the last liquid step's column
  fluxes, the liquid volume held by a uniform shift (:func:`fsi.slosh.limp.advance_heights`).
* Liquid: one free-surface step on the 3-D grid under it per window
  (:mod:`fluid.free_surface`).
* Per window, beside the liquid's measures: the surface's gravitational potential energy
  1/2 rho g sum A_i (h_i - z0)^2 (J), A_i the part of node i's column inside the tank.
* ``fluid.level_plane = "faces"``: the grid moved so that a plane of faces lies at the start
  level, and the measures taken on the step's own face fractions with each surface face
  carrying the liquid below the surface only (:func:`fluid.free_surface.measured_state`).
"""
from __future__ import annotations

import logging

import numpy as np

from fluid.free_surface import column_rates, measured_state, surface_of
from fluid.measures import angular_momentum, dissipation_rate, kinetic_energy, momentum
from fluid.model import FluidModel
from fluid.solver import FluidSolver
from fluid.tank import tank_grid

from fsi.slosh.lateral_compliance import Compliance, free_surface_compliance
from fsi.slosh.limp import HeightSurface, advance_heights
from fsi.lifecycle import Run
from fsi.registry import SceneError
from fsi.procedures.coupled import FLUID, LEVEL_PLANES, fluid_convection
from fsi.procedures.slosh_surfaces import Contents, Start, SurfaceWindows, register_surface

log = logging.getLogger(__name__)

MEMBRANE_FLUID_KEYS = ("volume", "face_memory", "pressure_map", "pressure_cells",
                       "pressure_fit", "centre_cells")
"""[fluid] keys of the liquid under a membrane that a limp (or linear) surface has no use for:
it holds its volume itself, its step keeps every face's history, and it has no nodes to map
a pressure to. Set away from their defaults they are named in a warning
(:func:`ignored_fluid_keys`)."""


def ignored_fluid_keys(scene) -> list[str]:
    """The :data:`MEMBRANE_FLUID_KEYS` that ``scene`` sets away from their defaults."""
    return [f"fluid.{k} = {scene['fluid'][k]!r}" for k in MEMBRANE_FLUID_KEYS
            if scene["fluid"][k] != FLUID[k].default]


def node_areas(surface: HeightSurface, spacing: float, radius: float, level: float,
               subdivisions: int = 8) -> np.ndarray:
    """(n_nodes,) m^2: the part of each node's column (a cell's cross-section around it)
    inside the tank's circle at the level (midpoint rule on a subdivided square)."""
    offsets = (np.arange(subdivisions) + 0.5) / subdivisions - 0.5
    dx, dy = np.meshgrid(offsets * spacing, offsets * spacing, indexing="ij")
    x = surface.plan[:, 0, None] + dx.ravel()
    y = surface.plan[:, 1, None] + dy.ravel()
    inside = x**2 + y**2 < radius**2 - level**2
    return inside.mean(axis=1) * spacing**2


@register_surface("limp")
class LimpWindows(SurfaceWindows):
    """The limp diaphragm's windows (module doc): the height surface and the free-surface
    liquid under it."""

    #: the liquid step's interface condition (:data:`fluid.steppers.STEPPERS`)
    interface_condition = "free"

    @classmethod
    def check(cls, scene) -> None:
        shape = scene["membrane"]["shape"]
        if shape != "hemisphere":
            raise SceneError(f"scene key 'membrane.shape' = {shape!r}: slosh.surface = "
                             f"{scene['slosh']['surface']!r} has no membrane; allowed "
                             f"'hemisphere' (the default), or slosh.surface = 'diaphragm'")
        ignored = ignored_fluid_keys(scene)
        if ignored:
            log.warning("slosh.surface = %r ignores %s (keys of the liquid under a membrane)",
                        scene["slosh"]["surface"], ", ".join(ignored))

    def __init__(self, setup, start: Start, body, run: Run, window: float, n_windows: int):
        super().__init__(window, n_windows)
        scene = setup.scene
        radius = setup.model.radius
        self.on_faces = LEVEL_PLANES[scene["fluid"]["level_plane"]]
        grid = tank_grid(radius, scene["fluid"]["cells"], axisymmetric=False,
                         face_at=start.level if self.on_faces else None)
        self.model = FluidModel(grid=grid, container=start.tank, density=setup.liquid.density,
                                viscosity=scene["fluid"]["viscosity"], body_acceleration=body,
                                interface_condition=self.interface_condition,
                                convection=fluid_convection(setup))
        self.surface = HeightSurface(grid, bottom=-2.0 * radius)
        self.heights = self.surface.flat(start.level)
        self.fluid = FluidSolver(self.model, self.surface.interface(self.heights))
        self.volume = self.fluid.liquid_volume
        self.level = start.level
        self.plan_area = np.pi * (radius**2 - start.level**2)
        self.node_area = node_areas(self.surface, grid.spacing, radius, start.level)
        self.density = setup.liquid.density
        self.gravity = -float(setup.liquid.body_acceleration[2])
        self.centre = start.centre
        self.set_energy_scale(self.density * self.volume, radius, body)
        self.sample(run, 0.0)
        run.record("frames", dict(time=0.0, surface_height=self.heights.copy()))

    def sample(self, run: Run, t: float) -> None:
        """Records the ``windows`` record at time ``t`` (s) in ``run``."""
        model, state = self.model, self.fluid.state
        surface = surface_of(model, state.geometry) \
            if model.viscosity > 0 or self.on_faces else None
        free = surface.faces if model.viscosity > 0 else None
        if self.on_faces:
            state = measured_state(model, state, surface)
        run.record("windows", dict(
            time=t, momentum=momentum(model, state),
            angular_momentum=angular_momentum(model, state),
            liquid_kinetic_energy=kinetic_energy(model, state),
            potential_energy=self.potential_energy(),
            dissipation_rate=dissipation_rate(model, state, free),
            fluid_liquid_volume=self.fluid.liquid_volume, wall_seconds=run.elapsed()))

    def potential_energy(self) -> float:
        """The surface's gravitational potential energy (J), 1/2 rho g sum A_i (h_i - z0)^2."""
        rise = self.heights.ravel() - self.level
        return 0.5 * self.density * self.gravity * float(np.sum(self.node_area * rise**2))

    def step(self, run: Run) -> None:
        k, surface, window = self.k, self.surface, self.window
        t = (k + 1) * window
        rate = surface.node_rates(*column_rates(self.model, self.fluid.state))
        shift = (self.volume - self.fluid.liquid_volume) / self.plan_area
        self.heights = advance_heights(self.heights, rate, window, shift)
        velocity = self.fluid.velocity_at(surface.points(self.heights))
        velocity[:, 2] = rate.ravel()
        self.fluid.advance(window, surface.interface(self.heights, velocity))
        if not np.all(np.isfinite(self.heights)):
            self.stop(run, f"the surface is not finite at t = {t:.4f} s")
            return
        self.sample(run, t)
        self.k += 1
        if run.frame_due(k + 1):
            run.record("frames", dict(time=t, surface_height=self.heights.copy()))
        moment = float(np.sum(self.node_area * self.heights.ravel() * surface.plan[:, 0]))
        run.progress(k + 1, f"t = {t:.3f} s, surface x-moment {moment:.3e} m^4")

    def finish(self):
        compliance = Compliance(free_surface_compliance(float(self.centre[2]), self.gravity),
                                0.0, True)
        contents = Contents(self.volume, self.density * self.volume, self.centre, compliance)
        return dict(node_plan=self.surface.plan, node_area=self.node_area), contents
