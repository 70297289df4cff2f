"""What the coupled procedures share: the ``[dynamics]``, ``[port]``, ``[fluid]``,
``[coupling]`` and ``[motion]`` tables, the coupling settings they map onto, the XPBD substep
of a window, and the port's setup check."""
from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from coupling import (ACCELERATIONS, EXTRAPOLATION_WEIGHTS, ON_MAX_ITERATIONS, SCHEMES,
                      SPLIT_UNCONVERGED, AccelerationSettings, ConvergenceMeasure,
                      CouplingSettings)
from fluid.model import FACE_MEMORIES
from fluid.sampling import CELL_WEIGHTS, FIT_KERNELS
from fluid.solver import FluidSolver
from fluid.tank import port_stub_volume, tank_spacing
from structure.newton.window import RHO_INF as WINDOW_RHO_INF
from structure.volume import liquid_volume

from fsi.coupled.adapters import (CENTRE_CELLS, INTERFACE_VELOCITIES, POINTS, PRESSURE,
                                  FluidParticipant, MembraneSurface)
from fsi.setup.limits import courant_time_step_limit
from fsi.setup.models import XPBD_COURANT_FRACTION, hydrostatic_load
from fsi.setup.static_start import START_SOLVERS
from fsi.coupled.pressure_maps import PRESSURE_MAPS
from fsi.setup.motion import MOTIONS
from fsi.registry import Key, SceneError, Table, is_vec3, one_of, positive, short_number

log = logging.getLogger(__name__)


def _history(v):
    """Rows [t, ax, ay, az] of finite numbers, times strictly increasing."""
    if not isinstance(v, list) or not all(isinstance(r, list) and len(r) == 4 and is_vec3(r[1:])
                                          and is_vec3(r[:3]) for r in v):
        return False
    times = [r[0] for r in v]
    return all(b > a for a, b in zip(times, times[1:]))


MAX_WINDOWS = 1e6
"""Coupling windows of one run at most (end_time / window)."""


def _check_dynamics(dyn: dict) -> None:
    if dyn["min_window"] > min(dyn["window"], dyn["max_window"]):
        raise SceneError(f"scene key 'dynamics.min_window' = {dyn['min_window']!r} s: must not "
                         f"exceed dynamics.window ({dyn['window']!r} s) or dynamics.max_window "
                         f"({dyn['max_window']!r} s)")
    windows = dyn["end_time"] / (dyn["max_window"] if dyn["window_tolerance"] > 0
                                 else dyn["window"])
    if windows > MAX_WINDOWS:
        raise SceneError(f"scene key 'dynamics.window' = {dyn['window']!r}: end_time/window = "
                         f"{windows:.3g} windows; allowed at most {short_number(MAX_WINDOWS)}")


def _check_motion(motion: dict) -> None:
    if motion["kind"] == "table" and len(motion["history"]) < 2:
        raise SceneError(f"scene key 'motion.history' = {motion['history']!r}: motion.kind = "
                         f"'table' needs at least two rows [t, ax, ay, az]")


QUASI_STATIC_SOLVERS = ("minimisation", "relaxation")
"""coupling.quasi_static_solver: how a quasi-static window's membrane is solved."""


def _check_coupling(c: dict) -> None:
    """The keys of a split window, refused away from their default unless
    ``on_max_iterations = "split"``; the quasi-static solver only with quasi-static windows."""
    if c["quasi_static_solver"] != "relaxation" and c["time_scheme"] != "quasi-static":
        raise SceneError(f"scene key 'coupling.quasi_static_solver' = "
                         f"{c['quasi_static_solver']!r} solves the quasi-static windows; with "
                         f"coupling.time_scheme = {c['time_scheme']!r} allowed: 'relaxation'")
    if c["rho_inf"] != WINDOW_RHO_INF and c["time_scheme"] != "generalised-alpha":
        raise SceneError(f"scene key 'coupling.rho_inf' = {c['rho_inf']!r} sets the "
                         f"generalised-alpha step; with coupling.time_scheme = "
                         f"{c['time_scheme']!r} allowed: {WINDOW_RHO_INF!r}")
    if c["on_max_iterations"] == "split":
        return
    if c["stall_iterations"]:
        raise SceneError(f"scene key 'coupling.stall_iterations' = {c['stall_iterations']!r}: "
                         f"a try stopped early is split; with coupling.on_max_iterations = "
                         f"{c['on_max_iterations']!r} allowed: 0")
    if c["split_unconverged"] != "parts":
        raise SceneError(f"scene key 'coupling.split_unconverged' = "
                         f"{c['split_unconverged']!r}: what a split window keeps; with "
                         f"coupling.on_max_iterations = {c['on_max_iterations']!r} allowed: "
                         f"'parts'")


START_GRID = Key(int, 0, lambda v: v == 0 or (v >= 4 and v % 2 == 0),
                 "0, or an even N0 >= 4 not above membrane.grid_size",
                 "0: the static start found on membrane.grid_size itself; N0: found on the "
                 "grid N0, carried to membrane.grid_size and polished there (by the shell "
                 "model after the relaxation, by the minimisation in the run's own law after "
                 "the minimisation's starts), so that runs on several grids start from one "
                 "fold state (docs/notes/one-fold-state.md)")
"""dynamics.start_grid and slosh.start_grid (:mod:`fsi.setup.carried_start`)."""

START_SOLVER_DOC = ("how the static start is found (docs/user-guide/procedures.md, 'The "
                    "static start'): relaxation (damped XPBD from the manufactured shape), "
                    "minimisation (the tension field's fill path from rest, then the full "
                    "law at the volume) or axisymmetric (the shell of revolution's fill "
                    "carried onto the grid, seeded with its critical harmonic past the onset "
                    "of folding, then minimised)")
"""What every ``start_solver`` key says; each adds how its run settles the start."""
START_SOLVER = Key(str, "relaxation", *one_of(sorted(START_SOLVERS)),
                   START_SOLVER_DOC + "; the last two settled under the windows' substeps")
"""dynamics.start_solver and slosh.start_solver (:mod:`fsi.setup.static_start`)."""

DYNAMICS = Table({
    "start_fill": Key(float, 0.5, lambda v: 0 < v < 1, "0 < value < 1",
                      "tank fraction V / (4/3 pi R^3) at t = 0, static equilibrium"),
    "window": Key(float, 2e-3, lambda v: 0 < v <= 1, "0 < value <= 1 s",
                  "coupling time window (s); the first one with window_tolerance"),
    "window_tolerance": Key(float, 0.0, lambda v: v >= 0, ">= 0 m",
                            "0: fixed windows; > 0: windows grow and shrink so that the local "
                            "error of the membrane's node positions per window stays near it "
                            "(m; docs/models/coupling.md, 'Windows sized by their error')"),
    "max_window": Key(float, 1.0, lambda v: 0 < v <= 100, "0 < value <= 100 s",
                      "largest window with window_tolerance (s)"),
    "min_window": Key(float, 0.0, lambda v: 0 <= v <= 100, "0 <= value <= 100 s",
                      "smallest window with window_tolerance (s), also for windows redone "
                      "after a coupling failure; 0: none (docs/notes/slow-fills.md)"),
    "end_time": Key(float, 0.2, positive, "> 0 s", "simulated time (s)"),
    "checkpoint_interval": Key(int, 0, lambda v: v >= 0, ">= 0",
                               "windows between checkpoints (fsi run --resume continues from "
                               "the last); 0: none by count"),
    "checkpoint_seconds": Key(float, 0.0, lambda v: v >= 0, ">= 0 s",
                              "wall seconds between checkpoints; 0: none by time"),
    "frame_interval": Key(int, 5, lambda v: v >= 1, ">= 1",
                          "windows between recorded frames"),
    "substep_fraction": Key(float, XPBD_COURANT_FRACTION, lambda v: 0 < v <= 1,
                            "0 < value <= 1", "XPBD substep / explicit limit of the load "
                            "(0.3: about 1 % stiffness bias, "
                            "docs/models/continuum-membranes.md, 'XPBD')"),
    "start_grid": START_GRID,
    "start_solver": START_SOLVER,
    "node_damping": Key(float, 0.0, lambda v: 0 <= v <= 10, "0 <= value <= 10 N s/m",
                        "coupling.time_scheme = euler, or quasi-static (its windows with the "
                        "membrane's inertia): c of the membrane substeps' damping of each "
                        "node's velocity relative to its neighbours', c sum_j (v_j - v_i) "
                        "(N); 0: none (docs/notes/node-damping.md)"),
}, _check_dynamics)
"""[dynamics]: start, windows and frames of a coupled run."""

MOTION = Table({
    "kind": Key(str, "none", *one_of(sorted(MOTIONS)),
                "tank acceleration a(t); the liquid feels liquid.body_acceleration - a(t) "
                "(docs/user-guide/procedures.md, 'Tank motion')"),
    "amplitude": Key(list, [0.0, 0.0, 0.0], is_vec3, "three finite numbers (m/s^2)",
                     "sine: a = amplitude sin(2 pi frequency t); impulse: the peak (m/s^2)"),
    "frequency": Key(float, 1.0, lambda v: v >= 0, ">= 0 Hz", "sine: frequency (Hz)"),
    "duration": Key(float, 0.1, positive, "> 0 s",
                    "impulse: a = amplitude sin^2(pi t / duration) while t < duration (s)"),
    "history": Key(list, [], _history, "rows [t, ax, ay, az], times increasing (s, m/s^2)",
                   "table: a(t) piecewise linear through the rows, held outside them"),
}, _check_motion)
"""[motion]: the tank's acceleration (:mod:`fsi.setup.motion`)."""

PORT = Table({
    "flow": Key(float, 5e-4, lambda v: abs(v) <= 1.0, "-1..1 m^3/s",
                "volume flow into the liquid through the bottom port (m^3/s; negative drains)"),
    "radius": Key(float, 0.06, lambda v: 0 < v < 1, "0 < value < 1 m, at least 1.5 cells of "
                  "the fluid grid", "radius of the port stub below the bottom pole (m)"),
    "length": Key(float, 0.065, lambda v: 0 < v < 1, "0 < value < 1 m, at least 2 cells of "
                  "the fluid grid", "length of the port stub below the bottom pole, where the "
                  "flow enters (m)"),
    "ramp_time": Key(float, 0.1, positive, "> 0 s",
                     "the flow rises linearly from 0 over this time (s); a valve opens in "
                     "finite time, an impulsive start has no solution"),
})
"""[port]: the bottom port and its stub."""

WINDOW_TIME_SCHEMES = {"euler": ("euler", "substeps"), "bdf2": ("bdf2", "bdf2"),
                       "quasi-static": ("euler", "quasi-static"),
                       "generalised-alpha": ("bdf2", "generalised-alpha")}
"""``coupling.time_scheme`` -> (the liquid's :data:`fluid.time_schemes.TIME_SCHEMES` name, the
membrane's :data:`fsi.coupled.adapters.MEMBRANE_WINDOWS` name): the two halves of one time
scheme."""

FLUID_CONVECTIONS = {"upwind": True, "none": False}
"""fluid.convection: whether the liquid keeps its convective term (first-order upwind)."""

FLUID_VOLUMES = {"cut-cells": False, "membrane": True}
"""fluid.volume: whether the cut cells are matched to the membrane's exact liquid volume."""

LEVEL_PLANES = {"anywhere": False, "faces": True}
"""fluid.level_plane: whether a free surface's grid has a plane of faces at the start level."""

FLUID = Table({
    "cells": Key(int, 16, lambda v: 8 <= v <= 128, "8..128",
                 "cells per axis of the 3-D grid over the tank"),
    "viscosity": Key(float, 1e-3, lambda v: v >= 0, ">= 0 Pa s",
                     "dynamic viscosity of the liquid (Pa s)"),
    "convection": Key(str, "upwind", *one_of(sorted(FLUID_CONVECTIONS)),
                      "the liquid's convective term rho (u . grad) u: upwind (implicit, first "
                      "order: a numerical viscosity of about |u| h / 2) or none (the "
                      "linearised liquid of small-amplitude slosh, whose closed forms are "
                      "linear; docs/validation/slosh.md, 'Energy and linearity')"),
    "volume": Key(str, "cut-cells", *one_of(sorted(FLUID_VOLUMES)),
                  "liquid volume the cut cells hold: cut-cells (the lattice level set's own, "
                  "off the membrane's by O(h^2), 1 % at 16 cells) or membrane (the interface "
                  "shifted along its normal so that they hold the membrane's exact volume; "
                  "docs/notes/slow-fills.md; a limp surface holds its volume itself)"),
    "face_memory": Key(str, "ring", *one_of(FACE_MEMORIES),
                       "which of the liquid's face velocities keep their own history from step "
                       "to step: ring (only the faces between two wall-centred cells; the rest "
                       "re-interpolated from the cells each step, Rhie-Chow, which damps the "
                       "diaphragm's inviscid slosh at zeta 0.0045 with 1 ms BDF2 windows) or "
                       "every-face (every face wetted before and after the step: zeta under "
                       "0.0003 there; the limp surface's step keeps every face's always; "
                       "docs/notes/second-order-window.md)"),
    "pressure_map": Key(str, "node-fit", *one_of(sorted(PRESSURE_MAPS)),
                        "how the cells' pressure reaches the membrane's nodes: node-fit (a "
                        "least-squares plane through the liquid cells around each node), "
                        "surface-mean (that plane's mean over the sheet around each node, hat "
                        "weights) or cell-mean (the same mean of each cut cell's own "
                        "pressure, the work of the cut cells' volume change; "
                        "docs/notes/second-order-window.md)"),
    "pressure_cells": Key(str, "iteration", *one_of(sorted(CELL_WEIGHTS)),
                          "which liquid cells the pressure map fits from: iteration (those "
                          "holding at least a quarter cell of liquid, chosen anew at every "
                          "coupling iteration) or window (those holding it at the window's "
                          "start, faded out below an eighth: the map is then continuous over "
                          "the window's iterations; docs/notes/pressure-cells.md)"),
    "pressure_fit": Key(str, "block", *one_of(sorted(FIT_KERNELS)),
                        "the weights of the pressure's least-squares plane around a point: "
                        "block (liquid fraction / (1 + d^2 / h^2) over the 4 x 4 x 4 cells "
                        "around it: the value jumps when the point crosses a plane of cell "
                        "centres) or tapered (the same times a factor that falls to zero at "
                        "the block's edge: continuous in the point's position; "
                        "docs/notes/stalled-windows.md)"),
    "level_plane": Key(str, "anywhere", *one_of(list(LEVEL_PLANES)),
                       "where the grid's planes of faces lie against a free surface's level "
                       "(slosh.surface = limp or linear): anywhere (the tank's own grid, the "
                       "level between two planes wherever the fill puts it: lambda1 scatters "
                       "by +-2 % with the fill on 24^3 cells) or faces (the grid moved down by "
                       "less than a cell so that a plane of faces lies at the start level, "
                       "the modes rung's grid: second order at every fill for the linear "
                       "surface; the limp surface then crosses that plane every half period, "
                       "and at tank fraction 0.2 a mode at the rim grows; "
                       "docs/notes/level-between-planes.md)"),
    "centre_cells": Key(str, "iteration", *one_of(list(CENTRE_CELLS)),
                        "which cells carry the liquid's velocity in a window's coupling "
                        "iterations: iteration (those whose centre is in the liquid, anew at "
                        "each iteration: a centre the membrane crosses makes the pressure jump) "
                        "or window (those of the window's start, held over its iterations; "
                        "docs/notes/stalled-windows.md)"),
})
"""[fluid]: the immersed-boundary liquid (:mod:`fluid`)."""


def fluid_convection(setup) -> bool:
    """Whether the liquid keeps its convective term (``fluid.convection``)."""
    return FLUID_CONVECTIONS[setup.scene["fluid"]["convection"]]


def fluid_pressure_map(setup):
    """The ``fluid.pressure_map`` function (:data:`fsi.coupled.pressure_maps.PRESSURE_MAPS`)."""
    return PRESSURE_MAPS[setup.scene["fluid"]["pressure_map"]]


def fluid_participant(setup, fluid: FluidSolver, surface: MembraneSurface) -> FluidParticipant:
    """The liquid as a coupling participant: its pressure at the membrane's nodes by
    ``fluid.pressure_map`` from the cells of ``fluid.pressure_cells``."""
    return FluidParticipant(fluid, surface=surface, pressure_map=fluid_pressure_map(setup),
                            pressure_cells=setup.scene["fluid"]["pressure_cells"],
                            centre_cells=setup.scene["fluid"]["centre_cells"])


def membrane_surface(setup, model, fluid_model) -> MembraneSurface:
    """The XPBD ``model``'s membrane closed for the liquid of ``fluid_model``
    (:class:`fsi.coupled.adapters.MembraneSurface`); with ``fluid.volume = "membrane"`` each interface
    carries the liquid volume on the grid: the membrane's exact enclosed volume
    (:func:`structure.volume.liquid_volume`) and the port stub below the sphere."""
    if not FLUID_VOLUMES[setup.scene["fluid"]["volume"]]:
        return MembraneSurface(model)
    stub = port_stub_volume(fluid_model)
    return MembraneSurface(model, lambda x: liquid_volume(setup.model, x) + stub)

COUPLING = Table({
    "scheme": Key(str, "implicit-serial", *one_of(sorted(SCHEMES)),
                  "coupling scheme (membrane first, liquid second)"),
    "time_scheme": Key(str, "euler", *one_of(sorted(WINDOW_TIME_SCHEMES)),
                       "time integration of a window: euler (liquid backward Euler, membrane "
                       "substeps under the window's end pressure: first order, damps a mode "
                       "at about omega dt / 2) or bdf2 (liquid and membrane one BDF2 step, "
                       "every force at the window's end: second order; "
                       "docs/notes/second-order-window.md) or quasi-static (liquid backward "
                       "Euler, the membrane in equilibrium at each window's end, no inertia: "
                       "slow fills with long windows; docs/notes/slow-fills.md) or "
                       "generalised-alpha (liquid BDF2, the membrane one implicit "
                       "generalised-alpha step by Newton on its tangent stiffness, no Courant "
                       "limit; docs/models/continuum-membranes.md)"),
    "rho_inf": Key(float, WINDOW_RHO_INF, lambda v: 0 <= v <= 1, "0 <= value <= 1",
                   "time_scheme = generalised-alpha: the membrane step's high-frequency "
                   "spectral radius (1: no numerical dissipation, the trapezoidal rule; 0: "
                   "the highest frequencies removed in one step, what a sheet whose folds "
                   "snap needs; docs/models/continuum-membranes.md)"),
    "quasi_static_solver": Key(str, "relaxation", *one_of(sorted(QUASI_STATIC_SOLVERS)),
                               "time_scheme = quasi-static: how the membrane's equilibrium "
                               "at each window's end is found: relaxation (damped XPBD "
                               "substeps, the static sweep's solve) or minimisation (the "
                               "minimisation statics through the folds' snaps, "
                               "structure/minimise/window.py)"),
    "interface_velocity": Key(str, "membrane", *one_of(sorted(INTERFACE_VELOCITIES)),
                              "the node velocities the liquid gets with the window's end "
                              "positions: membrane (the membrane's own at the window's end, "
                              "its last substep's) or window-mean ((x_end - x_start)/dt, the "
                              "backward Euler liquid's own: a sheet snapping inside a window "
                              "does not reach the liquid as one node's spike; "
                              "docs/notes/valve-drain.md, 'The velocity the liquid sees')"),
    "acceleration": Key(str, "iqn-ils", *one_of(sorted(ACCELERATIONS)),
                        "acceleration of the interface pressure"),
    "relaxation": Key(float, 0.01, lambda v: 0 < v <= 1, "0 < value <= 1",
                      "constant under-relaxation factor"),
    "initial_relaxation": Key(float, 0.01, lambda v: 0 < v <= 1, "0 < value <= 1",
                              "Aitken's first factor of a window, IQN's first step"),
    "reuse": Key(int, 8, lambda v: 0 <= v <= 100, "0..100", "IQN past windows reused"),
    "filter_limit": Key(float, 1e-2, lambda v: 0 < v < 1, "0 < value < 1", "IQN QR2 filter"),
    "max_columns": Key(int, 100, lambda v: v >= 1, ">= 1", "IQN secant columns at most"),
    "mixing": Key(float, 1.0, lambda v: 0 < v <= 1, "0 < value <= 1",
                  "IQN-ILS and IQN-IMVJ: relaxation of the residual outside the secants' "
                  "span (Anderson's beta; 1: IQN-ILS as published; docs/models/coupling.md, "
                  "'Mixing')"),
    "jacobian_windows": Key(int, 0, lambda v: 0 <= v <= 1000, "0..1000",
                            "iqn-imvj: past windows whose secants make the carried inverse "
                            "Jacobian (0: every window since the last restart; a window "
                            "accepted unconverged restarts it)"),
    "pressure_tolerance": Key(float, 1e-4, lambda v: 0 < v < 1, "0 < value < 1",
                              "relative change of the interface pressure per iteration at "
                              "convergence"),
    "position_tolerance": Key(float, 1e-6, lambda v: 0 < v < 1, "0 < value < 1",
                              "relative change of the node positions per iteration at "
                              "convergence"),
    "max_iterations": Key(int, 60, lambda v: 1 <= v <= 10_000, "1..10000",
                          "coupling iterations per window at most"),
    "on_max_iterations": Key(str, "error", *one_of(ON_MAX_ITERATIONS),
                             "stop with an error, accept the window's last iterate and log it, "
                             "accept its best iterate (smallest residuals, its solves repeated) "
                             "and log it, redo it once by the explicit scheme and log it, or "
                             "redo it from its start as two "
                             "windows of half its size, a half that does not converge halved "
                             "again, split_depth times at most, the smallest's best iterate "
                             "accepted (docs/notes/split-windows.md)"),
    "split_depth": Key(int, 3, lambda v: 1 <= v <= 20, "1..20",
                       "on_max_iterations = split: how many times a window may be halved "
                       "(its smallest parts 2^-split_depth of it)"),
    "stall_iterations": Key(int, 0, lambda v: 0 <= v <= 10_000, "0..10000",
                            "on_max_iterations = split: a try that is not the last level's "
                            "stops and is split once its best residual (the largest over its "
                            "tolerance) has not fallen to stall_reduction of itself in this "
                            "many iterations (0: it runs max_iterations; "
                            "docs/notes/split-windows.md, 'A stalled try stopped early')"),
    "stall_reduction": Key(float, 0.5, lambda v: 0 < v < 1, "0 < value < 1",
                           "on_max_iterations = split, with stall_iterations > 0: the fraction "
                           "of itself the best residual must fall to"),
    "split_unconverged": Key(str, "parts", *one_of(SPLIT_UNCONVERGED),
                             "on_max_iterations = split: what a split window keeps when some "
                             "of its smallest parts do not converge: parts (those parts' best "
                             "iterates) or window (the whole window redone from its start, its "
                             "best iterate kept as accept-best keeps it; "
                             "docs/notes/split-windows.md, 'A split that does not converge')"),
    "accept_residual": Key(float, float("inf"), lambda v: v > 0, "> 0 (inf: any)",
                           "on_max_iterations = accept: the largest residual (relative change "
                           "per iteration, pressure or positions) a window that did not "
                           "converge is accepted at; above it the window stops the run as with "
                           "error, or is redone smaller where dynamics.window_tolerance > 0 "
                           "(docs/notes/valve-drain.md)"),
    "extrapolation_order": Key(int, 0, *one_of(sorted(EXTRAPOLATION_WEIGHTS)),
                               "prediction of a window's start from past windows"),
}, _check_coupling)
"""[coupling]: every knob of :class:`coupling.CouplingSettings`."""

COUPLED_TABLES = {"dynamics": DYNAMICS, "motion": MOTION, "port": PORT, "fluid": FLUID,
                  "coupling": COUPLING}

def coupling_settings(c: dict) -> CouplingSettings:
    """:class:`coupling.CouplingSettings` from the scene's ``[coupling]`` table."""
    return CouplingSettings(
        scheme=c["scheme"], acceleration=c["acceleration"],
        acceleration_settings=AccelerationSettings(
            relaxation=c["relaxation"], initial_relaxation=c["initial_relaxation"],
            reuse=c["reuse"], filter_limit=c["filter_limit"], max_columns=c["max_columns"],
            mixing=c["mixing"], jacobian_windows=c["jacobian_windows"]),
        measures=[ConvergenceMeasure(PRESSURE, "relative", c["pressure_tolerance"]),
                  ConvergenceMeasure(POINTS, "relative", c["position_tolerance"])],
        max_iterations=c["max_iterations"], on_max_iterations=c["on_max_iterations"],
        accept_residual=c["accept_residual"],
        split_depth=c["split_depth"], stall_iterations=c["stall_iterations"],
        stall_reduction=c["stall_reduction"], split_unconverged=c["split_unconverged"],
        extrapolation_order=c["extrapolation_order"])


def implicit_window(scene) -> bool:
    """Whether the scene's membrane windows are the generalised-alpha step on the tangent
    stiffness (``coupling.time_scheme``), whose start and settings differ from XPBD's."""
    return WINDOW_TIME_SCHEMES[scene["coupling"]["time_scheme"]][1] == "generalised-alpha"


def window_settings(scene, settings):
    """The settings a coupled window's membrane step takes: ``settings`` (XPBD's) for the
    XPBD schemes; for ``coupling.time_scheme = "generalised-alpha"``, the
    :class:`structure.newton.dynamics.AlphaSettings` of ``coupling.rho_inf`` with the XPBD
    settings' node damping."""
    if not implicit_window(scene):
        return settings
    from structure.newton.dynamics import AlphaSettings

    return AlphaSettings(rho_inf=scene["coupling"]["rho_inf"],
                         node_damping=settings.node_damping)


def window_start(setup, scene, model, state, info, volume: float):
    """The coupled run's static start for its window scheme: as found (state, info) for the
    XPBD schemes; for generalised-alpha put at rest under the Newton model's energies
    (:func:`structure.newton.window.settled`, the liquid's hydrostatic field holding
    ``volume`` m^3), with a warning where that does not converge."""
    if not implicit_window(scene):
        return state, info
    from structure.newton.window import settled

    settled_state, equilibrium = settled(model, state, hydrostatic_load(
        setup.liquid, volume_target=volume, pressure_level=info.pressure_level))
    if not equilibrium.converged:
        log.warning("the start is not at rest under the generalised-alpha membrane (Newton "
                    "force ratio %.2e): the run starts from a membrane in motion",
                    equilibrium.force_ratio)
        return state, info
    return settled_state, replace(equilibrium, seed=info.seed)


def window_substep(setup, window: float, fraction: float) -> float:
    """XPBD substep (s): the ``window`` (s) cut into equal substeps no longer than
    ``fraction`` of the explicit limit of the largest hydrostatic load."""
    limit = fraction * courant_time_step_limit(setup.model, setup.liquid, setup.model.radius)
    return window / np.ceil(window / limit)


PORT_MIN_CELLS = {"radius": 1.5, "length": 2.0}
"""The port stub must span this many fluid cells in radius and in length to carry its flow."""


def check_interface_velocity(scene) -> None:
    """``coupling.interface_velocity = "window-mean"`` is the backward Euler liquid's own
    velocity: refused where the liquid steps by another scheme (BDF2's is not the mean)."""
    c = scene["coupling"]
    liquid_scheme = WINDOW_TIME_SCHEMES[c["time_scheme"]][0]
    if c["interface_velocity"] == "window-mean" and liquid_scheme != "euler":
        raise SceneError(f"scene key 'coupling.interface_velocity' = 'window-mean' is the "
                         f"backward Euler liquid's velocity; with coupling.time_scheme = "
                         f"{c['time_scheme']!r} allowed: 'membrane'")


def check_node_damping(scene) -> None:
    """``dynamics.node_damping`` > 0 damps the membrane's substeps: refused where the membrane
    never takes them (BDF2's one step); under quasi-static windows it acts in the windows done
    with the membrane's inertia (:class:`fsi.coupled.adapters.MembraneParticipant`)."""
    c, damping = scene["coupling"], scene["dynamics"]["node_damping"]
    if damping > 0 and WINDOW_TIME_SCHEMES[c["time_scheme"]][1] not in (
            "substeps", "quasi-static", "generalised-alpha"):
        raise SceneError(f"scene key 'dynamics.node_damping' = {damping!r} N s/m damps the "
                         f"membrane's substeps; with coupling.time_scheme = "
                         f"{c['time_scheme']!r} allowed: 0")


def check_port(setup) -> None:
    """The port stub spans :data:`PORT_MIN_CELLS` fluid cells and is narrower than the tank."""
    scene = setup.scene
    h = tank_spacing(scene["tank"]["radius"], scene["fluid"]["cells"], axisymmetric=False)
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


def check_coupled_fill(setup) -> None:
    """A coupled fill's scene before it runs: the port (:func:`check_port`), the interface
    velocity and the node damping against the window's time scheme
    (:func:`check_interface_velocity`, :func:`check_node_damping`), the start grid and the
    start solver (:func:`check_start_grid`, :func:`check_start_solver`)."""
    check_port(setup)
    check_interface_velocity(setup.scene)
    check_level_plane(setup.scene, "under the membrane of a coupled fill")
    check_node_damping(setup.scene)
    check_start_grid(setup.scene, "dynamics")
    check_start_solver(setup.scene, "dynamics")


def check_level_plane(scene, where: str) -> None:
    """``fluid.level_plane`` moves the grid under a free surface only: refused ``where`` the
    liquid is under a membrane."""
    value = scene["fluid"]["level_plane"]
    if LEVEL_PLANES[value]:
        raise SceneError(f"scene key 'fluid.level_plane' = {value!r} moves the grid under a "
                         f"free surface (slosh.surface = 'limp' or 'linear'); {where} allowed: "
                         f"'anywhere'")


def check_start_solver(scene, table: str) -> None:
    """``<table>.start_solver = "axisymmetric"`` carries a shell of revolution of the
    hemisphere: refused for another ``membrane.shape``."""
    solver, shape = scene[table]["start_solver"], scene["membrane"]["shape"]
    if solver == "axisymmetric" and shape != "hemisphere":
        raise SceneError(f"scene key '{table}.start_solver' = 'axisymmetric' carries the "
                         f"shell of revolution of a hemisphere; with membrane.shape = "
                         f"{shape!r} allowed: 'minimisation', 'relaxation'")


def check_start_grid(scene, table: str) -> None:
    """``<table>.start_grid`` N0 > 0: not above ``membrane.grid_size``, and the full law
    where the shell model polishes the carried start (it has no tension field; the
    minimisation's polish takes the run's own law)."""
    n0, membrane = scene[table]["start_grid"], scene["membrane"]
    if n0 > membrane["grid_size"]:
        raise SceneError(f"scene key '{table}.start_grid' = {n0!r}: allowed 0, or an even N0 "
                         f"from 4 to membrane.grid_size = {membrane['grid_size']!r}")
    if (n0 and membrane["wrinkling"] != "none"
            and not START_SOLVERS[scene[table]["start_solver"]].minimises):
        raise SceneError(f"scene key '{table}.start_grid' = {n0!r}: the carried start is "
                         f"polished by the shell model, which has no tension field "
                         f"(membrane.wrinkling = {membrane['wrinkling']!r}); allowed 0, or "
                         f"{table}.start_solver = 'minimisation' (its polish takes the run's "
                         "own law)")
