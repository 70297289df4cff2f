"""The dynamic procedure ``coupled-fill``: the diaphragm filled (or drained) through the bottom
port, the membrane and the liquid's flow coupled in time.

* Start: the membrane's static equilibrium at ``dynamics.start_fill`` under the hydrostatic
  model (XPBD relaxation with the same substep as the dynamics, so the start is at rest).
* Structure: XPBD windows (:func:`structure.xpbd.advance`, plain substeps of
  ``dynamics.substep_fraction`` of the explicit limit), the liquid volume held at what the
  port has delivered; the multiplier of that volume is the uniform pressure level
  (incompressibility dilemma, :mod:`fsi.adapters`).
* Fluid: incompressible Navier-Stokes on the 3-D immersed-boundary grid (:mod:`fluid`), the
  membrane's triangles and node velocities as the moving interface (closed by a can outside
  the tank, :class:`fsi.adapters.MembraneSurface`), a port stub of ``port.radius`` and
  ``port.length`` below the bottom pole with Q(t) = ``port.flow`` min(t / ``port.ramp_time``, 1)
  entering at its end.
* Tank motion: ``[motion]`` (:mod:`fsi.motion`), the body acceleration g - a(t) in the tank
  frame, felt by the liquid and by the membrane's mass.
* Coupling: ``[coupling]`` (:mod:`coupling`), membrane first, liquid second, the interface
  pressure accelerated; convergence on the pressure and the node positions.

Groups written: ``frames`` (every ``dynamics.frame_interval`` windows and t = 0) and
``windows`` (every window: iterations, residuals, level, volumes, seconds per participant).
"""
from __future__ import annotations

import logging
import time

import numpy as np

from coupling import (AccelerationSettings, ConvergenceMeasure, CouplingError,
                      CouplingSettings, run)
from fluid.model import Port
from fluid.solver import FluidSolver
from fluid.validation import sphere_model, tank_grid
from structure.model import MembraneState
from structure.volume import FillScale, liquid_volume
from structure.xpbd import XpbdDivergence, XpbdModel, XpbdSettings, solve_equilibrium

from .adapters import (POINTS, PRESSURE, FluidParticipant, MembraneParticipant,
                       MembraneSurface)
from .build import Setup, courant_time_step_limit
from .motion import body_acceleration
from .procedures import Progress, RunResult, _stack, register_procedure

log = logging.getLogger(__name__)

START_TOLERANCE = 1e-6
"""Static start converged when no node moves more than this fraction of its size per
substep."""
START_MAX_STEPS = 100_000


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


def coupling_settings(c: dict) -> CouplingSettings:
    """:class:`coupling.CouplingSettings` from the scene's ``[coupling]`` table."""
    return CouplingSettings(
        scheme=c["scheme"], acceleration=c["acceleration"],
        acceleration_settings=AccelerationSettings(
            relaxation=c["relaxation"], initial_relaxation=c["initial_relaxation"],
            reuse=c["reuse"], filter_limit=c["filter_limit"], max_columns=c["max_columns"]),
        measures=[ConvergenceMeasure(PRESSURE, "relative", c["pressure_tolerance"]),
                  ConvergenceMeasure(POINTS, "relative", c["position_tolerance"])],
        max_iterations=c["max_iterations"], on_max_iterations=c["on_max_iterations"],
        extrapolation_order=c["extrapolation_order"])


def window_substep(setup: Setup) -> float:
    """XPBD substep (s): the window cut into equal substeps no longer than
    ``substep_fraction`` of the explicit limit of the largest hydrostatic load."""
    dyn = setup.scene["dynamics"]
    limit = dyn["substep_fraction"] * courant_time_step_limit(setup.model, setup.liquid,
                                                              setup.model.radius)
    return dyn["window"] / np.ceil(dyn["window"] / limit)


def _frame(setup, scale, state, pressure, level, t, seconds, converged, fluid) -> dict:
    x = state.node_position
    volume = liquid_volume(setup.model, x)
    tank = 4.0 / 3.0 * np.pi * setup.model.radius**3
    return dict(node_position=x.copy(), node_velocity=state.node_velocity.copy(),
                interface_pressure=np.asarray(pressure, dtype=float) + level, time=float(t),
                fill_fraction=float(scale.fill(volume)), target_fill_fraction=np.nan,
                liquid_volume=volume, fluid_liquid_volume=fluid.liquid_volume,
                tank_fraction=volume / tank, pressure_reference=float(level),
                pressure_level=setup.liquid.equivalent_height(level),
                node_speed_max=float(np.linalg.norm(state.node_velocity, axis=1).max()),
                fluid_speed_max=fluid.velocity_magnitude_max(),
                wall_seconds=float(seconds), converged=bool(converged))


@register_procedure("coupled-fill")
def coupled_fill(setup: Setup, progress: Progress) -> RunResult:
    """Fill (or drain) through the port from a static start, membrane and liquid coupled."""
    scene, liquid = setup.scene, setup.liquid
    dyn, port, fl = scene["dynamics"], scene["port"], scene["fluid"]
    window = dyn["window"]
    n_windows = max(1, int(round(dyn["end_time"] / window)))
    substep = window_substep(setup)
    model = XpbdModel.from_membrane(setup.model)
    scale = FillScale.mirrored(setup.model)
    t_start = time.perf_counter()

    settings = XpbdSettings(dt=substep, warm_start=False, tolerance=START_TOLERANCE,
                            max_steps=START_MAX_STEPS)
    start, info = solve_equilibrium(model, MembraneState(setup.model.node_rest_position),
                                    liquid.pressure, liquid.body_acceleration, settings,
                                    volume_target=float(scale.volume(dyn["start_fill"])))
    if not info.converged:
        log.warning("static start at fill %.3f not converged after %d substeps (move ratio "
                    "%.2e): the run starts from a membrane in motion", dyn["start_fill"],
                    info.steps, info.move_ratio)
    progress(0.0, f"static start: fill {dyn['start_fill']:.2f}, level "
                  f"{info.pressure_level:.1f} Pa")

    flow = PortFlow(port["flow"], port["ramp_time"])
    body = body_acceleration(liquid.body_acceleration, scene["motion"])
    if not np.allclose(body(0.0), liquid.body_acceleration):
        log.warning("the tank accelerates at t = 0 (motion.history's first row): the static "
                    "start, under liquid.body_acceleration, is not at rest in the moving tank")
    grid = tank_grid(setup.model.radius, fl["cells"], axisymmetric=False,
                     stub_length=port["length"])
    surface = MembraneSurface(model)
    fluid = FluidSolver(sphere_model(setup.model.radius, grid, [Port("bottom", "flow", flow)],
                                     density=liquid.density, viscosity=fl["viscosity"],
                                     body_acceleration=body,
                                     port_radius_cells=port["radius"] / grid.spacing),
                        surface.of(start))
    start_volume = liquid_volume(setup.model, start.node_position)
    membrane = MembraneParticipant(model, start, settings,
                                   lambda t: start_volume + flow.delivered(t), body,
                                   info.pressure_level)
    fluid_side = FluidParticipant(fluid, surface=surface)

    frames = [_frame(setup, scale, start, fluid_side.initial_data()[PRESSURE],
                     info.pressure_level, 0.0, time.perf_counter() - t_start, info.converged,
                     fluid)]
    windows: list[dict] = []

    def record(w, data):
        t = (w.index + 1) * window
        last = w.residuals[-1] if w.residuals else {}
        windows.append(dict(
            time=t, coupling_iterations=w.iterations, converged=w.converged,
            residual_pressure=float(last.get(PRESSURE, np.nan)),
            residual_points=float(last.get(POINTS, np.nan)),
            seconds_structure=float(w.seconds.get(membrane.name, 0.0)),
            seconds_fluid=float(w.seconds.get(fluid_side.name, 0.0)),
            pressure_reference=membrane.level,
            liquid_volume=liquid_volume(setup.model, membrane.state.node_position),
            fluid_liquid_volume=fluid.liquid_volume, port_flow=flow(t),
            delivered_volume=flow.delivered(t)))
        if (w.index + 1) % dyn["frame_interval"] == 0 or w.index + 1 == n_windows:
            frames.append(_frame(setup, scale, membrane.state, data[PRESSURE], membrane.level,
                                 t, time.perf_counter() - t_start, w.converged, fluid))
        progress((w.index + 1) / n_windows,
                 f"t = {t:.4f} s, {w.iterations} it, level {membrane.level:.1f} Pa")

    failure = ""
    try:
        run(membrane, fluid_side, coupling_settings(scene["coupling"]), window, n_windows,
            on_window=record)
    except (CouplingError, XpbdDivergence) as err:
        failure = str(err)
        log.error("coupled-fill stopped: %s; writing the %d windows done", err, len(windows))
    result = RunResult(groups=dict(frames=_stack(frames)))
    if windows:
        result.groups["windows"] = _stack(windows)
    iterations = [w["coupling_iterations"] for w in windows]
    result.attrs.update(
        structure_model="xpbd", substep=substep, window=window, windows_done=len(windows),
        windows_planned=n_windows, failure=failure,
        mean_coupling_iterations=float(np.mean(iterations)) if iterations else np.nan,
        start_fill=dyn["start_fill"], start_pressure_reference=info.pressure_level,
        start_converged=info.converged, start_volume=start_volume,
        empty_volume=scale.empty_volume, full_volume=scale.full_volume,
        fill_scale="mirrored", fluid_cells=fl["cells"])
    return result
