"""``slosh``: lateral slosh in the spherical tank from rest at a tank fraction, port shut.

* Start: the liquid at rest at ``slosh.fill`` = V / (4/3 pi R^3) (the tank fraction), under
  ``liquid.body_acceleration``.
* Excitation: ``[motion]`` (:mod:`fsi.setup.motion`): ``impulse`` (a smooth lateral pulse, then
  free decay), ``sine`` (forced) or ``table``; the contents feel b(t) = g - a(t).
* Surface (``slosh.surface``, a registry): ``limp``, the diaphragm slack, massless and
  without bending, i.e. the liquid's free surface (:mod:`fsi.slosh.limp`, :mod:`fluid.free_surface`);
  ``linear``, the same linearised (the level fixed, its elevation a field on it: linear slosh
  theory, :mod:`.slosh_linear`); ``diaphragm``, the elastic membrane of ``[membrane]`` coupled to the liquid by
  ``[coupling]`` (:mod:`.slosh_diaphragm`).
* Liquid: incompressible flow on the 3-D immersed-boundary grid (``[fluid]``), one liquid
  step per window.
* Per window (group ``windows``): time, the tank's acceleration, the liquid's momentum and
  angular momentum, kinetic energy, viscous dissipation rate, the surface's gravitational
  potential energy, liquid volume; from them (:mod:`fsi.slosh.response`) the force and the
  moment about the tank centre that the contents put on the tank and their centre of mass.
* Analysis (impulse or table excitation): the first mode's frequency, damping ratio and
  lambda1 = omega^2 R / g from the centre of mass's free decay after ``slosh.analysis_start``,
  and the NASA SP-106 spring-mass equivalent from the force and moment; the start's static
  lateral compliance (:mod:`fsi.slosh.lateral_compliance`: the free surface's |z_c| / g, the
  diaphragm's from two tilted static solves), the first-mode bound it sets and the fitted
  modes' own sum m_n / (M omega_n^2) against it.
"""
from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from fluid.container import SphericalTank
from fluid.linear import single_blas_thread
from fluid.tank import tank_spacing
from structure.volume import tank_volume

from fsi.io.checkpoint import CheckpointDue, write as write_checkpoint
from fsi.slosh.lateral_compliance import first_mode_bound, modal_compliance
from fsi.lifecycle import Progress, Run, RunResult, stack
from fsi.setup.models import XPBD_COURANT_FRACTION, XPBD_DYNAMIC_SWEEPS
from fsi.setup.motion import body_acceleration, tank_acceleration
from fsi.registry import Key, Procedure, SceneError, Table, one_of, positive, register_procedure
from fsi.slosh.analysis import stokes_layer
from fsi.slosh.grid_bracket import grid_caveat
from fsi.slosh.response import contents_response, first_mode
from fsi.procedures.coupled import COUPLING, FLUID, MOTION, START_GRID, START_SOLVER
from fsi.procedures.coupled_fill import START_TOLERANCE
from fsi.procedures.slosh_limp import LimpWindows  # noqa: F401  (registers "limp", the default, first)
from fsi.procedures.slosh_diaphragm import DiaphragmWindows  # noqa: F401  (registers "diaphragm")
from fsi.procedures.slosh_linear import LinearWindows  # noqa: F401  (registers "linear")
from fsi.procedures.slosh_surfaces import SURFACES, Contents, Start

log = logging.getLogger(__name__)

MIN_DEPTH_CELLS = 2.0
"""Liquid and gas each at least this many fluid cells deep at the tank's axis."""


def _level(radius: float, fill: float) -> float:
    """The level z0 (m) at which the sphere of ``radius`` holds the tank fraction ``fill``."""
    return SphericalTank(radius).level_holding(fill * tank_volume(radius))


def _start(setup) -> Start:
    radius = setup.model.radius
    tank = SphericalTank(radius)
    level = _level(radius, setup.scene["slosh"]["fill"])
    return Start(tank, level, np.array([0.0, 0.0, tank.centroid_below(level)]))


def check_depth(setup) -> None:
    """Liquid and gas each span :data:`MIN_DEPTH_CELLS` cells of the fluid grid, gravity
    points down, and the surface model takes the scene (:meth:`SurfaceWindows.check`)."""
    scene = setup.scene
    SURFACES[scene["slosh"]["surface"]].check(scene)
    radius = scene["tank"]["radius"]
    h = tank_spacing(radius, scene["fluid"]["cells"], axisymmetric=False)
    fill = scene["slosh"]["fill"]
    level = _level(radius, fill)
    depth = min(radius + level, radius - level)
    if depth < MIN_DEPTH_CELLS * h:
        low = SphericalTank(radius).volume_below(-radius + MIN_DEPTH_CELLS * h) / \
            tank_volume(radius)
        raise SceneError(f"scene key 'slosh.fill' = {fill!r}: the liquid or the gas is "
                         f"{depth / h:.2f} fluid cells deep (cell {h:.4g} m at fluid.cells = "
                         f"{scene['fluid']['cells']}); allowed {low:.3f} < fill < "
                         f"{1 - low:.3f}, or more fluid cells")
    gravity = np.asarray(scene["liquid"]["body_acceleration"], dtype=float)
    if not (gravity[2] < 0 and np.allclose(gravity[:2], 0.0)):
        raise SceneError(f"scene key 'liquid.body_acceleration' = {gravity.tolist()!r}: a "
                         f"slosh run needs gravity along -z (0, 0, -g), g > 0")


def _check_slosh(table: dict) -> None:
    if table["analysis_start"] >= table["end_time"]:
        raise SceneError(f"scene key 'slosh.analysis_start' = {table['analysis_start']!r} s: "
                         f"allowed below slosh.end_time = {table['end_time']!r} s")


SLOSH = Table({
    "fill": Key(float, 0.5, lambda v: 0 < v < 1, "0 < value < 1",
                "tank fraction V / (4/3 pi R^3) of the liquid at rest"),
    "surface": Key(str, "limp", *one_of(SURFACES),
                   "the diaphragm model: limp (slack, massless, no bending: the free surface), "
                   "linear (the free surface linearised: linear slosh theory, needs "
                   "fluid.convection = none) or diaphragm (the [membrane] coupled to the "
                   "liquid by [coupling])"),
    "window": Key(float, 2e-3, lambda v: 0 < v <= 0.05, "0 < value <= 0.05 s",
                  "time window (s): one liquid step, one coupling window"),
    "substep_fraction": Key(float, XPBD_COURANT_FRACTION, lambda v: 0 < v <= 1,
                            "0 < value <= 1", "diaphragm: XPBD substep / explicit limit of "
                            "the load"),
    "constraint_sweeps": Key(int, XPBD_DYNAMIC_SWEEPS, lambda v: 1 <= v <= 1000, "1..1000",
                             "diaphragm: Gauss-Seidel sweeps of the XPBD constraints per "
                             "substep (too few leave the membrane soft, "
                             "docs/notes/slosh-diaphragm.md)"),
    "start_tolerance": Key(float, START_TOLERANCE, lambda v: 0 < v <= 1e-5, "0 < value <= 1e-5",
                           "diaphragm: the static start (and its tilted solves) converged when "
                           "no node moves more than this fraction of its size per substep "
                           "(looser: tilted solves stop before they move; "
                           "docs/notes/tension-field.md)"),
    "start_grid": replace(START_GRID, doc="diaphragm: " + START_GRID.doc),
    "start_solver": replace(START_SOLVER, doc="diaphragm: " + START_SOLVER.doc),
    "end_time": Key(float, 5.0, positive, "> 0 s", "simulated time (s)"),
    "frame_interval": Key(int, 25, lambda v: v >= 1, ">= 1",
                          "windows between recorded surface frames"),
    "analysis_start": Key(float, 0.15, lambda v: v >= 0, ">= 0 s",
                          "the free decay's fit starts here (s; after the impulse)"),
    "checkpoint_interval": Key(int, 0, lambda v: v >= 0, ">= 0",
                               "windows between checkpoints (fsi run --resume continues from "
                               "the last); 0: none by count"),
    "checkpoint_seconds": Key(float, 0.0, lambda v: v >= 0, ">= 0 s",
                              "wall seconds between checkpoints; 0: none by time"),
}, _check_slosh)
"""[slosh]: start, surface model, windows and analysis of a slosh run."""



def slosh(setup, progress: Progress) -> RunResult:
    """Slosh from rest at the tank fraction ``slosh.fill``, excited by ``[motion]``."""
    scene = setup.scene
    table = scene["slosh"]
    window = table["window"]
    n_windows = max(1, int(round(table["end_time"] / window)))
    run = Run(progress, n_windows, table["frame_interval"])
    start = _start(setup)
    body = body_acceleration(setup.liquid.body_acceleration, scene["motion"])
    acceleration = tank_acceleration(scene["motion"])
    surface_data, contents, start_facts = run_windows(setup, run, start, body, window,
                                                      n_windows)
    volume, mass = contents.volume, contents.mass
    windows = stack(run.groups.pop("windows"))
    time = windows["time"]
    windows["tank_acceleration"] = np.array([acceleration(t) for t in time])
    body_t = np.array([body(t) for t in time])
    windows.update(contents_response(time, body_t, windows["momentum"],
                                     windows["angular_momentum"], mass, contents.centre))
    windows["dissipated_energy"] = np.concatenate(
        [[0.0], np.cumsum(0.5 * np.diff(time) * (windows["dissipation_rate"][1:]
                                                 + windows["dissipation_rate"][:-1]))])
    radius = setup.model.radius
    tank = tank_volume(radius)
    windows["tank_fraction"] = windows["fluid_liquid_volume"] / tank
    gravity = -float(setup.liquid.body_acceleration[2])
    attrs = dict(
        surface=table["surface"], membrane_shape=scene["membrane"]["shape"],
        grid_size=setup.model.grid_size,
        target_tank_fraction=table["fill"],
        tank_fraction=volume / tank, level=start.level,
        liquid_mass=setup.liquid.density * volume, contents_mass=mass,
        centre_height=float(contents.centre[2]), window=window, windows_planned=n_windows,
        windows_done=len(time) - 1, fluid_cells=scene["fluid"]["cells"],
        viscosity=scene["fluid"]["viscosity"], excitation=scene["motion"]["kind"],
        analysis_start=table["analysis_start"],
        peak_force_x=float(np.max(np.abs(windows["force"][:, 0]))),
        peak_moment_y=float(np.max(np.abs(windows["moment"][:, 1]))),
        wall_seconds=run.elapsed(), **start_facts)
    if "converged" in windows:
        attrs.update(structure_model="xpbd",
                     windows_not_converged=int(np.sum(~windows["converged"].astype(bool))),
                     mean_coupling_iterations=float(np.mean(windows["coupling_iterations"][1:])))
    if scene["motion"]["kind"] in ("impulse", "table") and not run.failure:
        with single_blas_thread():  # the fit's last bits do not depend on the machine
            attrs.update(first_mode(time, windows["tank_acceleration"][:, 0],
                                    windows["centre_of_mass"][:, :2], windows["force"][:, 0],
                                    windows["moment"][:, 1], mass, float(contents.centre[2]),
                                    gravity, radius, table["analysis_start"]))
        if attrs.get("omega"):
            attrs["seconds_per_period"] = attrs["wall_seconds"] / (
                time[-1] * attrs["omega"] / (2 * np.pi))
            attrs.update(stokes_attrs(scene, radius, attrs["omega"]))
    attrs.update(compliance_attrs(contents, attrs))
    return run.result({"windows": windows, "surface": surface_data}, **attrs)


def run_windows(setup, run: Run, start: Start, body, window: float, n_windows: int):
    """The surface model's windows (:data:`SURFACES`), from ``setup.resume`` when given,
    writing checkpoints to ``setup.checkpoint`` (:mod:`fsi.io.checkpoint`). Returns the
    surface's data, the :class:`Contents` and the start's result attributes; the windows'
    records are in ``run``."""
    table = setup.scene["slosh"]
    if setup.resume is not None:
        windows = setup.resume["windows"]
        run.resumed(setup.resume)
    else:
        windows = SURFACES[table["surface"]](setup, start, body, run, window, n_windows)
    due = CheckpointDue(table["checkpoint_interval"], table["checkpoint_seconds"])
    while windows.advance(run):
        if setup.checkpoint is not None and not windows.done and due(windows.k):
            write_checkpoint(setup.checkpoint, dict(windows=windows, groups=run.groups,
                                                    elapsed=run.elapsed(),
                                                    scene=setup.scene.text))
    # a checkpoint written before the start facts were kept has none
    return (*windows.finish(), getattr(windows, "start_facts", {}))


def stokes_attrs(scene, radius: float, omega: float) -> dict:
    """The first mode's wall boundary layer (:func:`fsi.slosh.analysis.stokes_layer`, m) and
    its thickness in cells of the liquid's grid: a fitted zeta holds the wall's viscous
    damping only where the grid resolves that layer (docs/models/slosh.md, 'The liquid's
    damping')."""
    h = tank_spacing(radius, scene["fluid"]["cells"], axisymmetric=False)
    delta = stokes_layer(scene["fluid"]["viscosity"], scene["liquid"]["density"], omega)
    return dict(stokes_layer=delta, stokes_layer_cells=delta / h)


def _membrane_shape(a: dict) -> str:
    """The run's membrane shape: its attribute, or in a result written before it was one, the
    scene text's (the default hemisphere when the scene does not say)."""
    if "membrane_shape" in a:
        return str(a["membrane_shape"])
    import tomllib

    return tomllib.loads(str(a.get("scene", ""))).get("membrane", {}).get("shape", "hemisphere")


def _zeta_origin(a: dict) -> str:
    """What the fitted zeta holds, for the summary."""
    if "stokes_layer" not in a:
        return ""
    if a["viscosity"] == 0.0:
        return " (inviscid: the scheme's own)"
    if a["stokes_layer_cells"] < 1.0:
        return (f" (the grid's: the wall's Stokes layer (2 nu / omega)^1/2 = "
                f"{1e3 * a['stokes_layer']:.2g} mm is {a['stokes_layer_cells']:.2g} of a cell, "
                "so the physical boundary-layer damping is not in it)")
    return (f" (the wall's Stokes layer {1e3 * a['stokes_layer']:.2g} mm spans "
            f"{a['stokes_layer_cells']:.2g} cells)")


def compliance_attrs(contents: Contents, attrs: dict) -> dict:
    """The start's static lateral compliance (:mod:`fsi.slosh.lateral_compliance`), the first-mode
    bound it sets and, with fitted slosh masses, the modes' own sum_n m_n / (M omega_n^2)."""
    c = contents.compliance
    omega_bound = first_mode_bound(c.compliance)
    out = dict(static_compliance=c.compliance, static_compliance_asymmetry=c.asymmetry,
               static_compliance_converged=c.converged,
               first_mode_bound_hz=omega_bound / (2 * np.pi))
    if "mode_slosh_mass" in attrs:
        out["modal_compliance"] = modal_compliance(
            attrs["mode_slosh_mass"], 2 * np.pi * attrs["mode_frequency_hz"], contents.mass)
    if attrs.get("omega", 0.0) > omega_bound:
        log.warning("the fitted first mode (%.4g Hz) is above the static bound %.4g Hz: the "
                    "response is not linear, or the fit is not the first mode",
                    attrs["frequency_hz"], out["first_mode_bound_hz"])
    return out


def report(result) -> None:
    """The summary ``fsi run`` prints after a slosh run (and ``fsi show``); with the
    hemispherical diaphragm, the first mode is labelled its grid's, with the bracket
    (:func:`fsi.slosh.grid_bracket.grid_caveat`)."""
    a = result.attrs
    print(f"slosh ({a['surface']} surface): tank fraction {a['tank_fraction']:.4f} "
          f"(V / (4/3 pi R^3), target {a['target_tank_fraction']:.4f}), {a['windows_done']} "
          f"windows of {a['window']:g} s on {a['fluid_cells']}^3 cells, "
          f"{a['wall_seconds']:.1f} s")
    if "windows_not_converged" in a:
        print(f"  coupling: {a['mean_coupling_iterations']:.2f} iterations per window, "
              f"{a['windows_not_converged']} windows accepted unconverged "
              "(coupling.on_max_iterations)")
    print(f"  peak force on the tank F_x {a['peak_force_x']:.4g} N, peak moment M_y "
          f"{a['peak_moment_y']:.4g} N m")
    print(f"  static lateral compliance C = d x_c / d b_x {a['static_compliance']:.4e} s^2 "
          f"(first mode at most {a['first_mode_bound_hz']:.4g} Hz)"
          + ("" if a["static_compliance_converged"] else ", a tilted solve not converged")
          + (f"; the fitted modes' sum m_n / (M omega_n^2) {a['modal_compliance']:.4e} s^2"
             if "modal_compliance" in a else ""))
    if "lambda1" not in a:
        if a.get("analysis_failure"):
            print(f"  first mode: not analysed ({a['analysis_failure']})")
        return
    print(f"  first mode: {a['frequency_hz']:.4f} +- {a['frequency_hz_std']:.1e} Hz, "
          f"lambda1 = omega^2 R / g = {a['lambda1']:.4f}, zeta = {a['zeta']:.5f} +- "
          f"{a['zeta_std']:.1e}{_zeta_origin(a)}")
    if a["surface"] == "diaphragm" and _membrane_shape(a) == "hemisphere":
        print(f"  the first mode is {grid_caveat(int(a['grid_size']))}")
    for k in range(1, int(a.get("modes", 1))):
        mass = (f", x slosh mass {a['mode_slosh_mass'][k]:.3f} kg"
                if "mode_slosh_mass" in a else "")
        print(f"  mode {k + 1}: {a['mode_frequency_hz'][k]:.4f} Hz, zeta = "
              f"{a['mode_zeta'][k]:.5f}, along {a['mode_direction_deg'][k]:.0f} deg from x "
              f"(mode 1 along {a['mode_direction_deg'][0]:.0f} deg){mass}")
    if a.get("analysis_failure"):
        print(f"  {a['analysis_failure']}")
    else:
        print(f"  spring-mass equivalent: slosh mass {a['slosh_mass']:.3f} kg "
              f"({100 * a['slosh_mass_fraction']:.1f} % of {a['total_mass']:.3f} kg) at "
              f"z = {a['slosh_mass_height']:.4f} m, fixed mass {a['fixed_mass']:.3f} kg at "
              f"z = {a['fixed_mass_height']:.4f} m, pendulum {a['pendulum_length']:.4f} m "
              f"hinged at z = {a['hinge_height']:.4f} m; {a['seconds_per_period']:.1f} s "
              "per period")


PROCEDURE = register_procedure(Procedure(
    name="slosh",
    summary="lateral slosh from rest at a tank fraction, port shut: frequency, damping, "
            "spring-mass equivalent, force and moment on the tank",
    run=slosh,
    tables={"slosh": SLOSH, "fluid": FLUID, "motion": MOTION, "coupling": COUPLING},
    structure_model="xpbd",
    membrane_shapes=("hemisphere", "disc"),
    check_setup=check_depth,
    report=report,
    headline=report,
    holds_volume=True,
))
