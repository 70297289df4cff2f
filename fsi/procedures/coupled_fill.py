"""``coupled-fill``: the diaphragm filled (or drained) through the bottom port, the membrane
and the liquid's flow coupled in time.

* Start: the membrane's static equilibrium at ``dynamics.start_fill`` (tank fraction
  V / (4/3 pi R^3), every frame's ``tank_fraction``) under the hydrostatic model, by
  ``dynamics.start_solver`` (:mod:`fsi.setup.static_start`: XPBD relaxation with the same
  substep as the dynamics, or the minimisation statics settled under those substeps), so
  that the start is at rest.
* Structure: XPBD windows (:func:`structure.xpbd.step`, plain substeps of
  ``dynamics.substep_fraction`` of the explicit limit), the liquid volume held at what the
  port has delivered; the multiplier of that volume is the uniform pressure level
  (incompressibility dilemma, :mod:`fsi.coupled.adapters`).
* Fluid: incompressible Navier-Stokes on the 3-D immersed-boundary grid (:mod:`fluid`), the
  membrane's triangles and node velocities as the moving interface (closed by a can outside
  the tank, :class:`fsi.coupled.adapters.MembraneSurface`), a port stub of ``port.radius`` and
  ``port.length`` below the bottom pole with Q(t) = ``port.flow`` min(t / ``port.ramp_time``, 1)
  entering at its end.
* Tank motion: ``[motion]`` (:mod:`fsi.setup.motion`), the body acceleration g - a(t) in the tank
  frame, felt by the liquid and by the membrane's mass.
* Coupling: ``[coupling]`` (:mod:`coupling`), membrane first, liquid second, the interface
  pressure accelerated; convergence on the pressure and the node positions.

Groups written: ``frames`` (every ``dynamics.frame_interval`` windows and t = 0) and
``windows`` (every window: iterations, residuals, level, volumes, seconds per participant).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from coupling import CouplingError, advance, start as start_loop
from fluid.model import Port
from fluid.solver import FluidSolver
from fluid.tank import port_stub_volume, sphere_model, tank_grid
from structure.load import Equilibrium
from structure.minimise.window import QuasiStaticMinimiser
from structure.volume import FillScale, liquid_volume, tank_volume
from structure.xpbd import XpbdDivergence, XpbdModel, XpbdSettings

from fsi.coupled.adapters import POINTS, PRESSURE, FluidParticipant, MembraneParticipant
from fsi.setup.carried_start import carried_start, carries, xpbd_settle
from fsi.setup.models import barrier_pressure
from fsi.setup.static_start import (START_SOLVERS, carried_polish, on_wall, seed_attrs,
                                    static_equilibrium)
from fsi.io.checkpoint import CheckpointDue, write as write_checkpoint
from fsi.lifecycle import Progress, Run, RunResult, membrane_frame
from fsi.setup.motion import body_acceleration
from fsi.registry import Procedure, register_procedure
from fsi.coupled.window_control import END_TOLERANCE, WindowController
from fsi.procedures.coupled import (COUPLED_TABLES, MAX_WINDOWS, WINDOW_TIME_SCHEMES,
                                    check_coupled_fill, coupling_settings, fluid_convection,
                                    fluid_participant, implicit_window, membrane_surface,
                                    window_settings, window_start, window_substep)

log = logging.getLogger(__name__)

START_TOLERANCE = 1e-6
"""Static start converged when no node moves more than this fraction of its size per
substep."""
START_MAX_STEPS = 250_000
"""Substeps of a static start at most: a tension-field diaphragm's slack sheet creeps to
START_TOLERANCE (diaphragm-fill, half full: 33,000 substeps at N = 14, 35,000 at N = 20,
172,000 at N = 26, the last 111 s)."""


class PortFlow:
    """Q(t) = flow min(t / ramp_time, 1) (m^3/s) and the volume it has delivered (m^3)."""

    def __init__(self, flow: float, ramp_time: float):
        self.flow, self.ramp_time = float(flow), float(ramp_time)

    def __call__(self, t: float) -> float:
        return self.flow * min(t / self.ramp_time, 1.0)

    def delivered(self, t: float) -> float:
        if t <= self.ramp_time:
            return self.flow * t * t / (2.0 * self.ramp_time)
        return self.flow * (t - 0.5 * self.ramp_time)


@dataclass
class Coupled:
    """The parts of a coupled fill, built at its start: the fill scale, the port flow, the
    static start's solve and liquid volume (m^3), the liquid solver and both participants."""

    scale: FillScale
    flow: PortFlow
    start_info: Equilibrium
    start_volume: float
    fluid: FluidSolver
    membrane: MembraneParticipant
    fluid_side: FluidParticipant


def membrane_settings(setup) -> XpbdSettings:
    """The XPBD settings of a coupled fill: the substep of ``dynamics.window`` at
    ``dynamics.substep_fraction``, the static start's tolerance and cap, the windows' node
    damping (``dynamics.node_damping``)."""
    dyn = setup.scene["dynamics"]
    return XpbdSettings(dt=window_substep(setup, dyn["window"], dyn["substep_fraction"]),
                        warm_start=False, tolerance=START_TOLERANCE, max_steps=START_MAX_STEPS,
                        node_damping=dyn["node_damping"])


def static_start(setup, model: XpbdModel, settings: XpbdSettings):
    """The membrane's static equilibrium at ``dynamics.start_fill`` (tank fraction) under the
    hydrostatic liquid by ``dynamics.start_solver`` (:mod:`fsi.setup.static_start`), at rest
    under the dynamics' XPBD substeps (settled there where the solver's state is not; the
    generalised-alpha window settles it under its own energies instead, its wall contacts
    put on the wall first; quasi-static windows by the minimisation take it as it is): (state,
    Equilibrium); from the start of the grid ``dynamics.start_grid`` carried here
    (:mod:`fsi.setup.carried_start`) when that is set."""
    dyn = setup.scene["dynamics"]
    volume = float(FillScale.tank(setup.model.radius).volume(dyn["start_fill"]))
    if carries(setup, dyn["start_grid"]):
        state, _ = carried_start(setup, dyn["start_grid"], volume, lambda coarse: static_start(
            coarse, XpbdModel.from_membrane(coarse.model), membrane_settings(coarse)),
            xpbd_settle(setup, model, settings, volume),
            carried_polish(setup, model, dyn["start_solver"], volume))
        return static_equilibrium(setup, model, settings, volume, state)
    solver = START_SOLVERS[dyn["start_solver"]]
    state, info = solver.solve(setup, model, settings, volume)
    if solver.at_rest or minimised_windows(setup.scene):
        return state, info
    if implicit_window(setup.scene):
        return on_wall(setup, state, info)
    settled, at_rest = static_equilibrium(setup, model, settings, volume, state)
    return settled, replace(at_rest, seed=info.seed)


def minimised_windows(scene) -> bool:
    """Whether the scene's quasi-static windows are solved by the minimisation statics (a
    minimisation's start is then at rest under them as it is)."""
    c = scene["coupling"]
    return c["time_scheme"] == "quasi-static" and c["quasi_static_solver"] == "minimisation"


def assemble(setup, model: XpbdModel, settings: XpbdSettings, start, info) -> Coupled:
    """Port, tank motion, fluid grid and solver, and both participants around ``start``."""
    scene, liquid = setup.scene, setup.liquid
    port, fl = scene["port"], scene["fluid"]
    flow = PortFlow(port["flow"], port["ramp_time"])
    body = body_acceleration(liquid.body_acceleration, scene["motion"])
    if not np.allclose(body(0.0), liquid.body_acceleration):
        log.warning("the tank accelerates at t = 0 (motion.history's first row): the static "
                    "start, under liquid.body_acceleration, is not at rest in the moving tank")
    grid = tank_grid(setup.model.radius, fl["cells"], axisymmetric=False,
                     stub_length=port["length"])
    liquid_scheme, membrane_scheme = WINDOW_TIME_SCHEMES[scene["coupling"]["time_scheme"]]
    fluid_model = sphere_model(setup.model.radius, grid, [Port("bottom", "flow", flow)], body,
                               density=liquid.density, viscosity=fl["viscosity"],
                               port_radius_cells=port["radius"] / grid.spacing,
                               time_scheme=liquid_scheme, convection=fluid_convection(setup),
                               face_memory=fl["face_memory"], pressure_fit=fl["pressure_fit"])
    surface = membrane_surface(setup, model, fluid_model)
    fluid = FluidSolver(fluid_model, surface.of(start))
    start_volume = liquid_volume(setup.model, start.node_position)
    minimiser = (QuasiStaticMinimiser.from_xpbd(model, barrier_pressure(setup))
                 if minimised_windows(scene) else None)
    membrane = MembraneParticipant(model, start, window_settings(scene, settings),
                                   lambda t: start_volume + flow.delivered(t), body,
                                   info.pressure_level, membrane_scheme,
                                   liquid_density=liquid.density
                                   if membrane_scheme == "quasi-static" else None,
                                   velocity=scene["coupling"]["interface_velocity"],
                                   minimiser=minimiser)
    return Coupled(FillScale.tank(setup.model.radius), flow, info, start_volume, fluid,
                   membrane, fluid_participant(setup, fluid, surface))


def frame(setup, parts: Coupled, state, pressure, level, t, seconds, converged) -> dict:
    """A frame of the coupled run at time ``t`` (s): the membrane frame, its node velocities,
    the interface pressure (Pa, with the level) and the liquid's volume and largest speed."""
    return dict(membrane_frame(setup, state.node_position, level),
                node_velocity=state.node_velocity.copy(),
                interface_pressure=np.asarray(pressure, dtype=float) + level, time=float(t),
                target_fill=np.nan, fluid_liquid_volume=parts.fluid.liquid_volume,
                node_speed_max=float(np.linalg.norm(state.node_velocity, axis=1).max()),
                fluid_speed_max=parts.fluid.velocity_magnitude_max(),
                wall_seconds=float(seconds), converged=bool(converged))


FRAME_FILL_STEP = 0.1
"""Besides every ``dynamics.frame_interval`` windows, a frame is recorded at the end of each
window in which the tank fraction crosses a multiple of this (-): the fills at which a fill or
drain is compared with the static sweep (:mod:`fsi.analysis.static_vs_dynamic`)."""


def window_recorder(setup, parts: Coupled, run: Run, controller=None):
    """on_window(window log, data) of :func:`coupling.run`: a ``windows`` record every
    window (with its size and, under ``controller``, its local error), a frame when one is
    due or the tank fraction crossed a multiple of FRAME_FILL_STEP, progress by simulated
    time."""
    dyn = setup.scene["dynamics"]
    membrane, fluid = parts.membrane, parts.fluid
    step = FRAME_FILL_STEP * tank_volume(setup.model.radius)  # m^3
    done = run.groups.get("windows")  # a resumed run: the band its last window was in
    band = [np.floor((done[-1]["liquid_volume"] if done else parts.start_volume) / step)]

    def record(w, data):
        t = (w.index + 1) * w.size if controller is None else w.time + w.size
        last = w.last_residuals
        error = controller.errors[-1] if controller is not None and controller.errors \
            else np.nan
        volume = liquid_volume(setup.model, membrane.state.node_position)
        run.record("windows", dict(
            time=t, window_size=w.size, window_error=error,
            coupling_iterations=w.iterations, converged=w.converged, explicit=w.explicit,
            window_parts=w.parts,
            split_undone=w.split_undone,
            residual_pressure=float(last.get(PRESSURE, np.nan)),
            residual_points=float(last.get(POINTS, np.nan)),
            seconds_structure=float(w.seconds.get(membrane.name, 0.0)),
            seconds_fluid=float(w.seconds.get(parts.fluid_side.name, 0.0)),
            pressure_level=membrane.level,
            liquid_volume=volume, fluid_liquid_volume=fluid.liquid_volume,
            fluid_interface_shift=fluid.state.geometry.interface_shift,
            port_flow=parts.flow(t), delivered_volume=parts.flow.delivered(t)))
        done = t >= dyn["end_time"] * (1 - END_TOLERANCE)
        now = np.floor(volume / step)
        crossed, band[0] = now != band[0], now
        if (w.index + 1) % dyn["frame_interval"] == 0 or done or crossed:
            run.record("frames", frame(setup, parts, membrane.state, data[PRESSURE],
                                       membrane.level, t, run.elapsed(), w.converged))
        run.progress(run.total * min(t / dyn["end_time"], 1.0),
                     f"t = {t:.4f} s, window {w.size:.3g} s, {w.iterations} it, level "
                     f"{membrane.level:.1f} Pa")

    return record


def coupled_fill(setup, progress: Progress) -> RunResult:
    """Fill (or drain) through the port from a static start, membrane and liquid coupled;
    from ``setup.resume`` when given, writing checkpoints to ``setup.checkpoint``
    (:mod:`fsi.io.checkpoint`)."""
    dyn = setup.scene["dynamics"]
    planned = max(1, int(round(dyn["end_time"] / dyn["window"])))
    run = Run(progress, planned, dyn["frame_interval"])
    n_windows = int(MAX_WINDOWS) if dyn["window_tolerance"] > 0 else planned
    state = setup.resume or fresh_start(setup, run, n_windows)
    run.resumed(state)
    parts, loop, controller = state["parts"], state["loop"], state["controller"]
    recorder = window_recorder(setup, parts, run, controller)
    due = CheckpointDue(dyn["checkpoint_interval"], dyn["checkpoint_seconds"])
    try:
        while advance(loop, parts.membrane, parts.fluid_side, recorder, controller):
            if setup.checkpoint is not None and not loop.done and due(loop.k):
                write_checkpoint(setup.checkpoint, dict(
                    state, parts=parts, loop=loop, controller=controller, groups=run.groups,
                    elapsed=run.elapsed(), scene=setup.scene.text))
    except (CouplingError, XpbdDivergence) as err:
        run.stop(str(err))
    attrs = fill_attrs(setup, parts, run, state["substep"], n_windows if controller is None
                       else len(run.groups.get("windows", [])))
    if controller is not None:
        attrs["windows_over_tolerance"] = controller.over_tolerance
        attrs["windows_redone"] = controller.redone
    attrs["windows_with_inertia"] = len(parts.membrane.dynamic_windows)
    attrs["windows_explicit"] = sum(r["explicit"] for r in run.groups.get("windows", []))
    attrs["windows_unconverged"] = sum(not r["converged"] for r in run.groups.get("windows", []))
    attrs["windows_split"] = sum(r.get("window_parts", 1) > 1
                                 for r in run.groups.get("windows", []))
    attrs["windows_split_undone"] = sum(r.get("split_undone", False)
                                        for r in run.groups.get("windows", []))
    return run.result(**attrs)


def fresh_start(setup, run: Run, n_windows: int) -> dict:
    """What a coupled fill continues from at its start: the static start, both participants,
    the coupling loop before its first window, the window controller and the first frame."""
    dyn = setup.scene["dynamics"]
    model = XpbdModel.from_membrane(setup.model)
    settings = membrane_settings(setup)
    start_state, info = static_start(setup, model, settings)
    start_state, info = window_start(
        setup, setup.scene, model, start_state, info,
        float(FillScale.tank(setup.model.radius).volume(dyn["start_fill"])))
    run.progress(0, f"static start: tank fraction {dyn['start_fill']:.2f}, level "
                    f"{info.pressure_level:.1f} Pa")
    parts = assemble(setup, model, settings, start_state, info)
    run.record("frames", frame(setup, parts, start_state,
                               parts.fluid_side.initial_data()[PRESSURE], info.pressure_level,
                               0.0, run.elapsed(), info.converged))
    controller = None
    if dyn["window_tolerance"] > 0:
        controller = WindowController(dyn["window_tolerance"], dyn["max_window"],
                                      dyn["end_time"], POINTS, start_state.node_position,
                                      on_retry=lambda w: parts.membrane.with_inertia(w.time),
                                      min_window=dyn["min_window"])
    loop = start_loop(parts.membrane, parts.fluid_side,
                      coupling_settings(setup.scene["coupling"]), dyn["window"], n_windows)
    return dict(parts=parts, loop=loop, controller=controller, groups=run.groups,
                substep=settings.dt)


def fill_attrs(setup, parts: Coupled, run: Run, substep: float, n_windows: int) -> dict:
    """Run facts of a coupled fill: windows, substep, start, fill scale, fluid grid."""
    dyn = setup.scene["dynamics"]
    iterations = [w["coupling_iterations"] for w in run.groups.get("windows", [])]
    return dict(
        structure_model="xpbd", start_solver=dyn["start_solver"],
        **seed_attrs(parts.start_info),
        quasi_static_solver=setup.scene["coupling"]["quasi_static_solver"],
        substep=substep, window=dyn["window"],
        windows_done=len(iterations), windows_planned=n_windows,
        mean_coupling_iterations=float(np.mean(iterations)) if iterations else np.nan,
        start_fill=dyn["start_fill"], start_pressure_level=parts.start_info.pressure_level,
        start_converged=parts.start_info.converged, start_volume=parts.start_volume,
        empty_volume=parts.scale.empty_volume, full_volume=parts.scale.full_volume,
        fill_scale="tank", fluid_cells=setup.scene["fluid"]["cells"],
        port_stub_volume=port_stub_volume(parts.fluid.model))


REPORT_ROWS = 40
"""The window table ``fsi run`` prints has at most about this many rows (every k-th window
and the last); the result holds every window."""


def report(result) -> None:
    """The window table ``fsi run`` prints after a coupled fill."""
    a = result.attrs
    w = result.groups.get("windows")
    print(f"coupled fill: {a['windows_done']} of {a['windows_planned']} windows of "
          f"{a['window']:g} s, xpbd substep {a['substep']:.3g} s, mean "
          f"{a['mean_coupling_iterations']:.2f} coupling iterations per window")
    if w is None:
        return
    print(f"  windows not converged: {a['windows_unconverged']} (of which redone by the "
          f"explicit scheme: {a['windows_explicit']}); redone in halves: "
          f"{a.get('windows_split', 0)} (redone whole: {a.get('windows_split_undone', 0)}); "
          f"with the membrane's inertia: "
          f"{a['windows_with_inertia']}")
    print("  t(s)     Q(m^3/s)    delivered   membrane dV  fluid dV     level(Pa)  iters")
    v0, f0 = a["start_volume"], result.groups["frames"]["fluid_liquid_volume"][0]
    n = len(w["time"])
    for k in sorted(set(range(0, n, max(1, n // REPORT_ROWS))) | {n - 1}):
        print(f"  {w['time'][k]:7.4f} {w['port_flow'][k]:11.3e} {w['delivered_volume'][k]:11.3e} "
              f"{w['liquid_volume'][k] - v0:11.3e} {w['fluid_liquid_volume'][k] - f0:11.3e} "
              f"{w['pressure_level'][k]:11.2f} {int(w['coupling_iterations'][k]):5d}")


PROCEDURE = register_procedure(Procedure(
    name="coupled-fill",
    summary="the dynamic fill or drain through the port, membrane and liquid coupled in time",
    run=coupled_fill,
    tables=COUPLED_TABLES,
    structure_model="xpbd",
    membrane_shapes=("hemisphere", "disc"),
    check_setup=check_coupled_fill,
    report=report,
))
