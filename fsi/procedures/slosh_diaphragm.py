"""``slosh.surface = "diaphragm"``: the elastic diaphragm in a slosh run, membrane and liquid
coupled in time.

* Start: the membrane's static equilibrium holding the liquid volume of the tank fraction
  ``slosh.fill`` under the hydrostatic load, by ``slosh.start_solver``
  (:mod:`fsi.setup.static_start`): the minimisation statics, or XPBD
  (:func:`fsi.setup.static_start.static_equilibrium`)
  relaxed from the manufactured shape at the statics' substep (so that the fold state it
  lands in does not depend on the window: at 1 / 2 / 4 ms it stored 3.10 / 3.07 / 3.20 J
  when relaxed at each window's substep, 3.1006 / 3.1009 / 3.1011 J this way, N = 10), or,
  with ``slosh.start_grid`` = N0, the grid N0's start carried here and polished
  (:mod:`fsi.setup.carried_start`), then settled at the windows' substep and sweeps so that it is
  at rest under them;
  the port is shut, so the membrane holds that volume throughout and the multiplier of the
  volume is the uniform pressure level (:mod:`fsi.coupled.adapters`). Its static lateral
  compliance comes from two more solves by the same XPBD settings, under b = (+-0.05, 0, -g)
  m/s^2 (:func:`start_compliance`).
* Structure: XPBD windows, substeps of ``slosh.substep_fraction`` of the explicit limit,
  ``slosh.constraint_sweeps`` Gauss-Seidel sweeps of the constraints per substep;
  the membrane feels the body acceleration g - a(t) of the moving tank.
* Liquid: the moving-wall projection step on the 3-D grid under the membrane closed by a can
  (:class:`fsi.coupled.adapters.MembraneSurface`), no ports.
* Coupling: the scene's ``[coupling]`` table, membrane first, liquid second.

The contents are liquid and membrane: the momentum, angular momentum and mass that the
force and moment on the tank come from are both parts' (the membrane's nodes as point
masses), so the rigid-body part of the force is the whole contents' mass times b.
Per window, beside the liquid's measures: the membrane's kinetic energy, its elastic energy
(the XPBD constraints' potential: Saint Venant-Kirchhoff plane stress plus the mid-edge
bending energy, J) and the gravitational potential energy of liquid and membrane against
the start, - sum m b(t_0) . (x - x_0), J.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from coupling import CouplingError, advance as advance_loop, start as start_loop
from fluid.container import SphericalTank
from fluid.measures import angular_momentum, dissipation_rate, kinetic_energy, momentum
from fluid.model import FluidModel
from fluid.solver import FluidSolver
from fluid.tank import tank_grid
from structure.hyperelastic import svk_energy_and_gradient
from structure.newton.window import settled
from structure.volume import liquid_volume, tank_volume
from structure.xpbd import XpbdDivergence, XpbdModel, XpbdSettings, solve_equilibrium

from fsi.coupled.adapters import PRESSURE, MembraneParticipant, MembraneSurface
from fsi.setup.carried_start import carried_start, carries, xpbd_settle
from fsi.slosh.lateral_compliance import (DEFAULT_TILT, Compliance, contents_centre,
                                          static_compliance)
from fsi.lifecycle import Run
from fsi.setup.models import hydrostatic_load, statics_substep
from fsi.procedures.coupled import (WINDOW_TIME_SCHEMES, check_interface_velocity,
                                    check_level_plane, check_start_grid, check_start_solver,
                                    coupling_settings,
                                    fluid_convection, fluid_participant, implicit_window,
                                    membrane_surface, window_settings, window_start,
                                    window_substep)
from fsi.procedures.coupled_fill import START_MAX_STEPS
from fsi.setup.static_start import (START_SOLVERS, carried_polish, on_wall, seed_attrs,
                                    static_equilibrium)
from fsi.procedures.slosh_surfaces import Contents, SurfaceWindows, register_surface


def elastic_energies(model: XpbdModel, node_position: np.ndarray) -> tuple[float, float]:
    """The membrane's stretching and bending energies (J) at ``node_position`` (n, 3) m: the
    Saint Venant-Kirchhoff plane-stress energy of its triangles (the tension field's relaxed
    energy of the XPBD blocks when ``model.tension_field``) and the mid-edge bending energy,
    the potentials of its XPBD constraints."""
    mat = model.base.material
    x = np.ascontiguousarray(node_position, dtype=float)
    if model.tension_field:
        stretch = model.membrane_energy(x)
    else:
        stretch, _ = svk_energy_and_gradient(x, model.triangles, model.rest_inverse,
                                             model.rest_area, mat.thickness,
                                             mat.youngs_modulus, mat.poisson_ratio)
    bend, _ = model.bending.energy_and_gradient(x)
    return float(stretch), float(bend)


def elastic_energy(model: XpbdModel, node_position: np.ndarray) -> float:
    """The membrane's elastic energy (J): stretching plus bending (:func:`elastic_energies`)."""
    return sum(elastic_energies(model, node_position))


def liquid_centroid(model: FluidModel, solver: FluidSolver) -> np.ndarray:
    """(3,) m: the centre of the liquid's cut cells (fraction-weighted cell centres)."""
    g = model.grid
    weight = solver.state.geometry.cell_fraction * g.cell_volume
    return np.average(model.grid_points(g.cell_centre), axis=0, weights=weight)


@dataclass
class _Parts:
    """The coupled diaphragm and liquid at the start: the XPBD model, the fluid model and
    solver, the closed surface, the membrane participant, the contents, the liquid's mass
    (kg) and centroid (3,) m."""

    xpbd: XpbdModel
    model: FluidModel
    fluid: FluidSolver
    surface: MembraneSurface
    membrane: MembraneParticipant
    contents: Contents
    liquid_mass: float
    liquid_centre: np.ndarray
    start_facts: dict


@dataclass
class StaticStart:
    """The diaphragm's static start: the XPBD model and the windows' settings, the liquid
    volume held (m^3), the membrane state and its :class:`structure.load.Equilibrium`."""

    xpbd: XpbdModel
    settings: XpbdSettings
    volume: float
    state: object
    info: object

    def as_pair(self) -> tuple:
        """(state, Equilibrium), as a static solve returns them."""
        return self.state, self.info


def static_start(setup, window: float) -> StaticStart:
    """The membrane's static equilibrium holding the tank fraction ``slosh.fill`` (module
    doc), at rest under the XPBD substeps of ``window`` (s); for the generalised-alpha
    window, the statics' equilibrium alone (settled afterwards under the Newton model's
    energies, :func:`fsi.procedures.coupled.window_start`)."""
    table = setup.scene["slosh"]
    xpbd = XpbdModel.from_membrane(setup.model)
    settings = XpbdSettings(dt=window_substep(setup, window, table["substep_fraction"]),
                            iterations=table["constraint_sweeps"], warm_start=False,
                            tolerance=table["start_tolerance"], max_steps=START_MAX_STEPS)
    volume = table["fill"] * tank_volume(setup.model.radius)
    # the fold state from a path that does not depend on the window: relaxed at the statics'
    # substep, then settled at the windows' (same sweeps) so that it is at rest under them
    statics = replace(settings, dt=statics_substep(setup))
    if carries(setup, table["start_grid"]):
        state, info = carried_start(setup, table["start_grid"], volume,
                                    lambda coarse: static_start(coarse, window).as_pair(),
                                    xpbd_settle(setup, xpbd, statics, volume),
                                    carried_polish(setup, xpbd, table["start_solver"], volume))
    else:
        solver = START_SOLVERS[table["start_solver"]]
        state, info = solver.solve(setup, xpbd, statics, volume)
        if not solver.at_rest and implicit_window(setup.scene):
            state, info = on_wall(setup, state, info)
    if implicit_window(setup.scene):
        # the implicit window's start is settled under its own energies (window_start)
        return StaticStart(xpbd, settings, volume, state, info)
    settled, at_rest = static_equilibrium(setup, xpbd, settings, volume, state)
    return StaticStart(xpbd, settings, volume, settled, replace(at_rest, seed=info.seed))


def _assemble(setup, body, run, window: float) -> _Parts:
    """The static start at the tank fraction ``slosh.fill`` and both participants."""
    scene = setup.scene
    table = scene["slosh"]
    radius = setup.model.radius
    start = static_start(setup, window)
    xpbd, settings = start.xpbd, start.settings
    state, info = window_start(setup, scene, xpbd, start.state, start.info, start.volume)
    run.progress(0, f"static start: tank fraction {table['fill']:.3f}, level "
                    f"{info.pressure_level:.1f} Pa")
    solve = None
    if state is not start.state:  # settled for the generalised-alpha window: its own statics
        start = replace(start, state=state, info=info)
        solve = partial(settled, xpbd)
    compliance = start_compliance(setup, start, solve=solve)
    liquid_scheme, membrane_scheme = WINDOW_TIME_SCHEMES[scene["coupling"]["time_scheme"]]
    grid = tank_grid(radius, scene["fluid"]["cells"], axisymmetric=False)
    model = FluidModel(grid=grid, container=SphericalTank(radius),
                       density=setup.liquid.density, viscosity=scene["fluid"]["viscosity"],
                       body_acceleration=body, time_scheme=liquid_scheme,
                       convection=fluid_convection(setup),
                       face_memory=scene["fluid"]["face_memory"],
                       pressure_fit=scene["fluid"]["pressure_fit"])
    surface = membrane_surface(setup, xpbd, model)
    fluid = FluidSolver(model, surface.of(state))
    held = liquid_volume(setup.model, state.node_position)
    membrane = MembraneParticipant(xpbd, state, window_settings(scene, settings),
                                   lambda t: held, body,
                                   info.pressure_level, membrane_scheme,
                                   velocity=scene["coupling"]["interface_velocity"])
    node_mass = setup.model.node_mass
    liquid_mass = setup.liquid.density * fluid.liquid_volume
    mass = liquid_mass + float(node_mass.sum())
    c0 = liquid_centroid(model, fluid)
    centre = (liquid_mass * c0 + node_mass @ state.node_position) / mass
    return _Parts(xpbd, model, fluid, surface, membrane,
                  Contents(held, mass, centre, compliance), liquid_mass, c0,
                  dict(start_solver=table["start_solver"], **seed_attrs(info)))


def start_compliance(setup, start: StaticStart, tilt: float = DEFAULT_TILT,
                     solve=None) -> Compliance:
    """The static lateral compliance of the ``start`` (:mod:`fsi.slosh.lateral_compliance`): the
    membrane's equilibria under b = (+-``tilt``, 0, -g) m/s^2 from the start's state, by
    ``solve(state, load)`` -> (state, Equilibrium) (the start's own XPBD settings when None),
    holding its liquid volume, its level (Pa) the guess."""
    liquid = setup.liquid
    g = np.asarray(liquid.body_acceleration, dtype=float)
    if solve is None:
        def solve(state, load):
            return solve_equilibrium(start.xpbd, state, load, start.settings)

    def centre_at(b_x):
        tilted = replace(liquid, body_acceleration=(b_x, g[1], g[2]))
        out, info = solve(start.state,
                          hydrostatic_load(tilted, start.volume, start.info.pressure_level))
        return (contents_centre(setup.model, out.node_position, liquid.density, start.volume),
                info.converged)

    return static_compliance(centre_at, tilt)


def _sampler(setup, parts: _Parts):
    """sample(run, t, **extra): records the window's ``windows`` record of the contents
    (module doc) in ``run``, with ``extra`` entries."""
    model, fluid, membrane = parts.model, parts.fluid, parts.membrane
    node_mass = setup.model.node_mass
    x0 = membrane.state.node_position.copy()
    c0, liquid_mass = parts.liquid_centre, parts.liquid_mass
    b0 = np.asarray(setup.liquid.body_acceleration, dtype=float)

    def sample(run, t, **extra):
        st, x, v = fluid.state, membrane.state.node_position, membrane.state.node_velocity
        c = liquid_centroid(model, fluid)
        run.record("windows", dict(
            time=t,
            momentum=momentum(model, st) + node_mass @ v,
            angular_momentum=angular_momentum(model, st) + np.sum(
                node_mass[:, None] * np.cross(x, v), axis=0),
            liquid_kinetic_energy=kinetic_energy(model, st),
            membrane_kinetic_energy=0.5 * float(node_mass @ np.sum(v * v, axis=1)),
            membrane_elastic_energy=elastic_energy(parts.xpbd, x),
            potential_energy=-float(liquid_mass * b0 @ (c - c0))
            - float(node_mass @ ((x - x0) @ b0)),
            dissipation_rate=dissipation_rate(model, st),
            fluid_liquid_volume=fluid.liquid_volume,
            membrane_liquid_volume=liquid_volume(setup.model, x),
            pressure_level=membrane.level, wall_seconds=run.elapsed(), **extra))

    return sample


@register_surface("diaphragm")
class DiaphragmWindows(SurfaceWindows):
    """The elastic diaphragm's windows (module doc): the coupling loop
    (:func:`coupling.start`, :func:`coupling.advance`) between the membrane and the liquid."""

    def __init__(self, setup, start, body, run: Run, window: float, n_windows: int):
        super().__init__(window, n_windows)
        self.parts = parts = _assemble(setup, body, run, window)
        self.start_facts = parts.start_facts
        self.fluid_side = fluid_participant(setup, parts.fluid, parts.surface)
        self.surface_data = dict(face_nodes=setup.model.face_nodes,
                                 node_mass=setup.model.node_mass)
        self.sample = _sampler(setup, parts)
        self.sample(run, 0.0, coupling_iterations=0, converged=True,
                    residual_pressure=0.0)
        self.set_energy_scale(parts.contents.mass, setup.model.radius, body,
                              stored=run.groups["windows"][0]["membrane_elastic_energy"])
        run.record("frames", dict(time=0.0,
                                  node_position=parts.membrane.state.node_position.copy()))
        self.loop = start_loop(parts.membrane, self.fluid_side,
                               coupling_settings(setup.scene["coupling"]), window, n_windows)

    @classmethod
    def check(cls, scene) -> None:
        check_interface_velocity(scene)
        check_level_plane(scene, "with slosh.surface = 'diaphragm'")
        check_start_grid(scene, "slosh")
        check_start_solver(scene, "slosh")

    def step(self, run: Run) -> None:
        membrane, window = self.parts.membrane, self.window

        def on_window(w, data):
            t = (w.index + 1) * window
            last = w.last_residuals
            self.sample(run, t, coupling_iterations=w.iterations,
                        converged=w.converged,
                        residual_pressure=float(last.get(PRESSURE, np.nan)))
            self.k = w.index + 1
            if run.frame_due(w.index + 1):
                run.record("frames", dict(time=t,
                                          node_position=membrane.state.node_position.copy()))
            run.progress(w.index + 1, f"t = {t:.3f} s, {w.iterations} it, contents "
                                      f"x-momentum {run.groups['windows'][-1]['momentum'][0]:.3e}"
                                      " kg m/s")

        try:
            advance_loop(self.loop, membrane, self.fluid_side, on_window)
        except (CouplingError, XpbdDivergence) as err:
            self.stop(run, str(err))

    def finish(self):
        return self.surface_data, self.parts.contents
