"""Static against dynamic: a coupled fill or drain against the static sweep of the same
membrane model and grid, at the same tank fraction V / (4/3 pi R^3).

At each tank fraction asked for, the dynamic run's frame nearest to it and the static
sweep's frame nearest to it are compared by

* the shape, thesis Eqn 6.1 (%), the static frame as reference (:mod:`fsi.analysis.compare`);
* the pressure level, dynamic minus static (Pa, the uniform level at the tank centre);
* the liquid's centre of mass, the distance between the two (mm), from the membrane's
  enclosed volume and first moment (:func:`structure.volume.liquid_first_moment`);
* with a stress rule (:func:`against_static`: the run's XPBD law), the dynamic
  amplification ``stress_ratio``: the largest surface stress on the free sheet
  (:func:`structure.topology.free_triangles`) of the dynamic
  frame over the static equilibrium's (:mod:`fsi.analysis.membrane_fields`), and both
  (``peak_stress_dynamic``, ``peak_stress_static``, Pa).

Each row also carries both frames' tank fractions, so a pair further apart than
``pairing_tolerance`` is visible (``paired``: False).

Three references: a static sweep's frames (:func:`compare`: the static model's own path);
the static equilibrium holding each frame's liquid volume, continued frame to frame from the
run's own static start by the same solve (:func:`against_static` ``along_path``); or that
equilibrium sought from the frame's own shape (:func:`against_static`, the default: the
same fold state, so the difference is what the dynamics add).  On the N = 14 diaphragm the
first two differ from the third by the fold states: the equilibria are not unique, and a
path settles into one or another (docs/validation/static-vs-dynamic.md).

The flow study (:func:`flow_case`, :data:`FLOWS`): from the static start at tank fraction
``START_FILL``, ``FILL_STEP`` of the tank filled through the port at each flow, slow to a
valve opening, and the end against the static path.
"""
from __future__ import annotations

import numpy as np

from structure.model import MembraneModel
from structure.volume import liquid_first_moment, liquid_volume, tank_volume
from structure.xpbd import XpbdModel

from fsi.analysis.compare import eqn_6_1_error

PAIRING_TOLERANCE = 0.01
"""Frames whose tank fractions are further apart than this are not the same fill (-)."""


def centre_of_mass(model: MembraneModel, node_position: np.ndarray) -> np.ndarray:
    """The liquid's centre of mass (3,) m below the membrane at ``node_position`` (n, 3) m."""
    return liquid_first_moment(model, node_position) / liquid_volume(model, node_position)


def compare(dynamic_frames: dict, static_frames: dict, model: MembraneModel, fills,
            pairing_tolerance: float = PAIRING_TOLERANCE) -> list[dict]:
    """Rows, one per tank fraction in ``fills``: fill, tank_dynamic, tank_static (-),
    eqn_6_1 (%), level_difference (Pa), centre_distance_mm (mm), paired (bool).

    ``dynamic_frames`` and ``static_frames``: a result's ``frames`` group (node_position
    (k, n, 3) m, tank_fraction (k,), pressure_level (k,) Pa), both on ``model``'s grid."""
    rows = []
    for fill in fills:
        k = int(np.argmin(np.abs(dynamic_frames["tank_fraction"] - fill)))
        j = int(np.argmin(np.abs(static_frames["tank_fraction"] - fill)))
        rows.append(_row(model, fill, dynamic_frames["node_position"][k],
                         dynamic_frames["pressure_level"][k], static_frames["node_position"][j],
                         static_frames["pressure_level"][j], pairing_tolerance))
    return rows


def _row(model, fill, x_dyn, level_dyn, x_sta, level_sta, pairing_tolerance,
         peak_stress=None) -> dict:
    tank = tank_volume(model.radius)
    tank_dyn, tank_sta = liquid_volume(model, x_dyn) / tank, liquid_volume(model, x_sta) / tank
    stress = {}
    if peak_stress is not None:
        dynamic, static = peak_stress(x_dyn), peak_stress(x_sta)
        stress = dict(peak_stress_dynamic=dynamic, peak_stress_static=static,
                      stress_ratio=dynamic / static)
    return dict(**stress,
        fill=float(fill), tank_dynamic=float(tank_dyn), tank_static=float(tank_sta),
        eqn_6_1=eqn_6_1_error(x_sta, model.face_nodes, x_dyn, model.radius),
        level_difference=float(level_dyn - level_sta),
        centre_distance_mm=1e3 * float(np.linalg.norm(centre_of_mass(model, x_dyn)
                                                      - centre_of_mass(model, x_sta))),
        paired=bool(abs(tank_dyn - fill) <= pairing_tolerance
                    and abs(tank_sta - fill) <= pairing_tolerance))


def against_static(setup, frames: dict, along_path: bool = False) -> list[dict]:
    """Each of a coupled fill's ``frames`` (of ``setup``'s scene) against a static
    equilibrium holding its liquid volume, by the solve of the run's own quasi-static windows
    (:func:`_static_solve`: damped XPBD at its substep, or the minimisation statics): started from
    the frame's own shape (the equilibrium in the same fold state: what the dynamics alone
    add), or with ``along_path`` from the run's static start, continued frame to frame (the
    static model's own path, whose folds may settle otherwise). Rows as :func:`compare`'s,
    ``fill`` the frame's tank fraction, with ``static_converged`` and the stresses (module
    doc, the XPBD law both ran with)."""
    from structure.model import MembraneState

    from fsi.analysis.membrane_fields import FIELD_RULES
    from structure.topology import free_triangles
    from fsi.procedures.coupled_fill import membrane_settings, static_start

    rule = FIELD_RULES["xpbd"](setup.model, setup.scene)
    sheet = free_triangles(setup.model.node_fixed, rule.term.triangles)

    def peak(x):
        return float(rule.sheet(x)["surface_stress"][sheet].max())

    model = XpbdModel.from_membrane(setup.model)
    settings = membrane_settings(setup)
    solve = _static_solve(setup, model, settings)
    state, _ = static_start(setup, model, settings) if along_path else (None, None)
    rows = []
    for x, level in zip(frames["node_position"], frames["pressure_level"]):
        volume = liquid_volume(setup.model, x)
        state, info = solve(volume, state if along_path else MembraneState(x), level)
        tank = volume / tank_volume(setup.model.radius)
        rows.append(dict(_row(setup.model, tank, x, level, state.node_position,
                              info.pressure_level, PAIRING_TOLERANCE, peak),
                         static_converged=bool(info.converged)))
    return rows


def _static_solve(setup, model: XpbdModel, settings):
    """solve(volume m^3, state, level Pa) -> (state, Equilibrium): the static equilibrium by
    the solver of the scene's quasi-static windows (``coupling.quasi_static_solver``): the
    minimisation statics (:mod:`structure.minimise`, the XPBD model's energies, the wall a
    barrier), or the coupled fill's damped XPBD at its substep
    (:func:`fsi.setup.static_start.static_equilibrium`) for every other scene."""
    from structure.minimise import fill_path, inside, minimisation_model, xpbd_terms
    from structure.model import MembraneState

    from fsi.procedures.coupled_fill import minimised_windows
    from fsi.setup.models import barrier_pressure, hydrostatic_load
    from fsi.setup.static_start import static_equilibrium

    if not minimised_windows(setup.scene):
        return lambda volume, state, level: static_equilibrium(setup, model, settings, volume,
                                                               state)
    potential, wall = minimisation_model(setup.model, xpbd_terms(model),
                                         barrier_pressure(setup))

    def solve(volume, state, level):
        start = MembraneState(inside(wall, state.node_position))
        ((out, info),), _ = fill_path(potential, wall, start,
                                      hydrostatic_load(setup.liquid, volume, level), [volume])
        return out, info
    return solve


START_FILL = 0.5
"""Tank fraction of the flow study's static start (-)."""
FILL_STEP = 0.02
"""Tank fraction each flow case fills (-)."""
FLOWS = {
    "slow": dict(flow=2e-5, ramp_time=0.1, time_scheme="quasi-static"),
    "pump": dict(flow=2e-4, ramp_time=0.1, time_scheme="quasi-static"),
    "fast": dict(flow=2e-3, ramp_time=0.1, time_scheme="euler"),
    "valve-open": dict(flow=1e-2, ramp_time=0.02, time_scheme="euler"),
}
"""The flow study's cases, slow to a valve opening (m^3/s, s): 2e-5 m^3/s is the thesis
scenes' (two 22 N thrusters' draw), 1e-2 m^3/s opened in 20 ms a valve-open transfer."""
TIME_SCHEME_KEYS = {
    "quasi-static": {"dynamics": dict(window=0.2, window_tolerance=1e-4, max_window=2.0,
                                      min_window=0.2, frame_interval=5),
                     "coupling": dict(time_scheme="quasi-static", position_tolerance=1e-4,
                                      max_iterations=20, on_max_iterations="explicit")},
    "euler": {"dynamics": dict(window=1e-3, frame_interval=20),
              "coupling": dict(time_scheme="euler", max_iterations=100,
                               on_max_iterations="accept")},
}
"""Scene keys of each window time scheme in the flow study (the quasi-static's as the thesis
fill's).  The inertial windows are 1 ms: at 2 ms the valve opening's window 11 stalls at a
relative pressure change of 0.15 after 60 iterations; at 1 ms window 28 stalls at 2.7e-4
(tolerance 1e-4) after 100, so a window that stalls is accepted and counted
(``windows_unconverged``)."""
LATERAL_DURATION = 0.1
"""s: a lateral case's impulse, a = amplitude sin^2(pi t / duration)."""


def flow_case(flow: float, ramp_time: float, time_scheme: str, lateral: float = 0.0,
              base: str = "diaphragm-fill", fill_step: float = FILL_STEP,
              changes: dict | None = None) -> dict:
    """One case of the flow study: ``base`` from its static start at START_FILL filled by
    ``fill_step`` of the tank at ``flow`` (m^3/s, ramped over ``ramp_time`` s), windows by
    ``time_scheme`` (TIME_SCHEME_KEYS), a lateral impulse of peak ``lateral`` (m/s^2) along x
    when not zero, ``changes`` to any other keys; every frame against the static path
    (:func:`against_static`, from each frame's shape, and along the static path). Returns
    the case's keys, its :class:`fsi.analysis.regime.Regime` numbers, rows, the largest difference
    of each measure over the frames (``path_``: against the static path), wall seconds,
    failure ('' when none) and explicit windows."""
    import time

    from fsi.setup.build import build
    from fsi.procedures import PROCEDURES
    from fsi.analysis.regime import regime
    from fsi.scene import load_scene

    radius = load_scene(base)["tank"]["radius"]
    end_time = 0.5 * ramp_time + fill_step * 4.0 / 3.0 * np.pi * radius**3 / flow
    keys = {table: dict(values) for table, values in TIME_SCHEME_KEYS[time_scheme].items()}
    keys["dynamics"].update(start_fill=START_FILL, end_time=end_time)
    keys["port"] = dict(flow=flow, ramp_time=ramp_time)
    if lateral:
        keys["motion"] = dict(kind="impulse", amplitude=[lateral, 0.0, 0.0],
                              duration=LATERAL_DURATION)
    for table, values in (changes or {}).items():
        keys.setdefault(table, {}).update(values)
    setup = build(load_scene(base).with_keys(keys))
    t0 = time.perf_counter()
    result = PROCEDURES["coupled-fill"](setup, lambda fraction, message: None)
    seconds = time.perf_counter() - t0
    rows = against_static(setup, result.groups["frames"])
    path = against_static(setup, result.groups["frames"], along_path=True)
    r = regime(setup.scene)
    measures = ("eqn_6_1", "level_difference", "centre_distance_mm", "stress_ratio")
    return dict(flow=flow, ramp_time=ramp_time, time_scheme=time_scheme, lateral=lateral,
                end_time=end_time, pressure_ratio=r.pressure_ratio, time_ratio=r.time_ratio,
                dynamic_pressure=r.dynamic_pressure, rows=rows,
                **{key: max(abs(row[key]) for row in rows) for key in measures},
                **{f"path_{key}": max(abs(row[key]) for row in path) for key in measures},
                seconds=seconds, failure=result.attrs["failure"],
                windows=int(result.attrs["windows_done"]),
                windows_explicit=int(result.attrs["windows_explicit"]),
                windows_unconverged=int(result.attrs["windows_unconverged"]))
