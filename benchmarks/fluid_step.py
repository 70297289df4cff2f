"""Time one fluid step (interface update + pressure solve) on the benchmark tank grids.

    python benchmarks/fluid_step.py [--quick]

For each grid (axisymmetric 64 x 128, 3-D 32^3 and 48^3 over the spherical tank of radius
``TANK_RADIUS`` with its bottom port stub) and each pressure solver of
``fluid.linear.LINEAR_SOLVERS`` (the pressure equation is symmetric, so every name is valid;
the momentum solver stays ``MOMENTUM_SOLVER``), the tank is filled through its bottom flow
port at ``FLOW_RATE`` while the membrane, a paraboloid bowl z = -s (1 - r^2/R^2) with the
liquid below, rises at the matching rate: the liquid volume under the bowl is
V = V_hemisphere - (pi R^2 / 2) s, so ds/dt = -2 Q / (pi R^2), and every membrane point moves
vertically at v_z = -(ds/dt) (1 - r^2/R^2). The interface therefore changes every step.

After ``WARM_UP_STEPS`` steps (numba compilation, FiPy setup) the solver's own timings are
averaged over the timed steps (10 axisymmetric, 5 in 3-D; ``--quick``: 2 steps, the
axisymmetric grid and 3d-32^3 only, two pressure solvers) at dt = ``DT``. Per grid and solver
it records, in seconds per step:

- ``interface_and_pressure_s``: cut-cell geometry from the new interface + Rhie-Chow and
  pressure solve (the headline number, compared with ``GOALS``);
- ``full_step_s``: geometry + momentum predictor + pressure;

and, so that speed is never reported without accuracy, the largest |volume mismatch| / Q and
the largest cell divergence (1/s) over all steps, and the linear-solver divergence warnings
(count and the first few messages). A configuration whose step exceeds ``STEP_LIMIT_S`` is
stopped and recorded as null with the reason.

BLAS threads: numpy and scipy each load their own OpenBLAS, each with a thread per core; on a
machine with few cores the two pools compete with the main thread and the Krylov pressure
solves (vector reductions) and the momentum solves slow down erratically, by an order of
magnitude or more after a sparse LU has run in the same process. The benchmark therefore runs with
``OPENBLAS_NUM_THREADS=1`` unless that variable is already set (the value used is recorded).

Prints one JSON object on stdout (progress goes to stderr): the suite, the suites that cannot
be installed here, the goals, the per-grid results and the best pressure solver per grid
(fastest ``interface_and_pressure_s`` among the runs without solver warnings) with its ratio
to the goal (null where the grid has no goal).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings

# One BLAS thread unless the caller sets it (before numpy loads OpenBLAS): see the module doc.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from fipy.solvers.convergence import DivergenceWarning

from fluid.interface import Interface
from fluid.linear import LINEAR_SOLVERS
SUITE = "scipy"
from fluid.model import Port
from fluid.solver import FluidSolver, Timings
from fluid.tank import sphere_model, tank_grid
from fluid.validation import bowl_meridian, bowl_surface
from fsi.constants import STANDARD_GRAVITY, TANK_RADIUS

#: grid name -> (cells argument of ``tank_grid``, axisymmetric)
GRIDS = {"axisymmetric-64x128": (64, True), "3d-32^3": (32, False), "3d-48^3": (48, False)}
#: seconds per step of interface update + pressure solve to reach, per grid
GOALS = {"axisymmetric-64x128": 0.05, "3d-32^3": 0.5}
#: timed steps per grid kind (full run, --quick)
TIMED_STEPS = {True: 10, False: 5}
QUICK_STEPS = 2
QUICK_GRIDS = ("axisymmetric-64x128", "3d-32^3")
QUICK_SOLVERS = ("lu", "pcg-amg")
WARM_UP_STEPS = 2
DT = 1e-3  # s
#: inflow through the bottom port, m^3/s: 1 L/s fills the 38.5 L tank in about 40 s; the
#: membrane's pole rises at 14.5 mm/s (0.4 % of a cell per step on the axisymmetric grid) and
#: the jet through the port stub (radius 3.3 cells, so narrowest on the axisymmetric grid:
#: 2.6 m/s there) keeps the Courant number below 1 on every grid
FLOW_RATE = 1e-3
#: membrane sag at t = 0, m (bowl depth at the pole, half the tank radius)
INITIAL_SAG = 0.5 * TANK_RADIUS
#: membrane resolution: meridian points (axisymmetric), lattice cells per side (3-D)
MERIDIAN_POINTS = 41
SURFACE_CELLS = 24
MOMENTUM_SOLVER = "bicgstab-jacobi"
#: a configuration whose single step takes longer (s) is stopped and recorded as null
STEP_LIMIT_S = 60.0
#: linear-solver warnings kept per configuration (all are counted)
MAX_MESSAGES = 3

UNAVAILABLE_SUITES = {
    "petsc": "petsc4py has no wheel for this Python and its sdist does not build from the "
             "package registry",
    "trilinos": "PyTrilinos is not on PyPI for this Python",
    "pyamgx": "pyamgx is not on PyPI for this Python",
}
NOTE = (f"Only FiPy's '{SUITE}' solver suite installs here; PETSc, Trilinos and pyamgx cannot "
        "be installed from the package registry (see unavailable_suites), so their solvers "
        "are not timed.")


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def sag_rate(radius: float, flow_rate: float) -> float:
    """ds/dt (m/s) of the paraboloid bowl's sag for an inflow ``flow_rate`` (m^3/s) below it:
    V = V_hemisphere - (pi R^2 / 2) s, so ds/dt = -2 Q / (pi R^2)."""
    return -2.0 * flow_rate / (np.pi * radius**2)


def membrane(radius: float, time: float, axisymmetric: bool) -> Interface:
    """Bowl membrane at ``time`` (s): sag s(t) = INITIAL_SAG + (ds/dt) t (m), points moving
    vertically at v_z = -(ds/dt) (1 - r^2/R^2) (m/s), zero beyond the tank radius."""
    rate = sag_rate(radius, FLOW_RATE)
    sag = INITIAL_SAG + rate * time
    bowl = bowl_meridian(radius, sag, MERIDIAN_POINTS) if axisymmetric \
        else bowl_surface(radius, sag, SURFACE_CELLS)
    points = bowl.points
    r2 = np.minimum(points[:, 0] ** 2 + points[:, 1] ** 2, radius**2)
    velocities = np.zeros_like(points)
    velocities[:, 2] = -rate * (1.0 - r2 / radius**2)
    return bowl.with_state(points, velocities)


def build_solver(grid_name: str, pressure_solver: str) -> tuple[FluidSolver, bool]:
    """Fresh solver of the filling tank on ``grid_name``; returns it and whether the grid is
    axisymmetric."""
    cells, axisymmetric = GRIDS[grid_name]
    grid = tank_grid(TANK_RADIUS, cells, axisymmetric)
    model = sphere_model(TANK_RADIUS, grid, [Port("bottom", "flow", FLOW_RATE)],
                         body_acceleration=(0.0, 0.0, -STANDARD_GRAVITY),
                         momentum_solver=MOMENTUM_SOLVER, pressure_solver=pressure_solver)
    return FluidSolver(model, membrane(TANK_RADIUS, 0.0, axisymmetric)), axisymmetric


def _phase_seconds(before: Timings, after: Timings) -> dict:
    """Mean seconds per step of each phase between two snapshots of a solver's timings."""
    n = after.calls - before.calls
    return {phase: (getattr(after, phase) - getattr(before, phase)) / n
            for phase in ("geometry", "momentum", "pressure")}


def _snapshot(timings: Timings) -> Timings:
    return Timings(timings.geometry, timings.momentum, timings.pressure, timings.calls)


def _skipped(reason: str) -> dict:
    return {"interface_and_pressure_s": None, "full_step_s": None, "skipped": reason}


def time_configuration(grid_name: str, pressure_solver: str, timed_steps: int) -> dict:
    """Seconds per step (see module doc) and sanity figures of one grid and pressure solver;
    a null entry with the reason if a step exceeds ``STEP_LIMIT_S`` or fails."""
    solver, axisymmetric = build_solver(grid_name, pressure_solver)
    mismatch, divergence, messages = 0.0, 0.0, []
    start = None
    for k in range(WARM_UP_STEPS + timed_steps):
        if k == WARM_UP_STEPS:
            start = _snapshot(solver.timings)
        end_time = (k + 1) * DT
        tic = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", DivergenceWarning)
            report = solver.advance(DT, membrane(TANK_RADIUS, end_time, axisymmetric))
        seconds = time.perf_counter() - tic
        messages += [f"step {k + 1}: {w.message}" for w in caught
                     if issubclass(w.category, DivergenceWarning)]
        mismatch = max(mismatch, abs(float(report.volume_mismatch)) / FLOW_RATE)
        divergence = max(divergence, float(report.divergence))
        if seconds > STEP_LIMIT_S:
            return _skipped(f"step {k + 1} took {seconds:.1f} s > {STEP_LIMIT_S:.0f} s limit")
    phases = _phase_seconds(start, solver.timings)
    return {
        "interface_and_pressure_s": phases["geometry"] + phases["pressure"],
        "full_step_s": sum(phases.values()),
        "geometry_s": phases["geometry"],
        "momentum_s": phases["momentum"],
        "pressure_s": phases["pressure"],
        "timed_steps": timed_steps,
        "max_volume_mismatch_over_Q": mismatch,
        "max_divergence_per_s": divergence,
        "solver_divergence_warnings": len(messages),
        "solver_warning_messages": messages[:MAX_MESSAGES],
    }


def run_grid(grid_name: str, solvers, timed_steps: int) -> dict:
    """``{"scipy/<solver>": entry}`` of every pressure solver on one grid."""
    results = {}
    for name in solvers:
        _log(f"{grid_name}: pressure solver {name} ...")
        tic = time.perf_counter()
        try:
            entry = time_configuration(grid_name, name, timed_steps)
        except Exception as error:  # one failing solver must not hide the others
            entry = _skipped(f"{type(error).__name__}: {error}")
        results[f"{SUITE}/{name}"] = entry
        _log(f"  {time.perf_counter() - tic:.1f} s: interface+pressure "
             f"{entry['interface_and_pressure_s']}, full {entry['full_step_s']}"
             + (f" ({entry['skipped']})" if "skipped" in entry else ""))
    return results


def best_solver(grid_name: str, results: dict) -> dict:
    """Fastest ``interface_and_pressure_s`` among the runs without solver warnings, with its
    ratio to the grid's goal (null without a goal or without a usable run)."""
    usable = {k: v for k, v in results.items() if v["interface_and_pressure_s"] is not None
              and v["solver_divergence_warnings"] == 0}
    if not usable:
        return {"solver": None, "interface_and_pressure_s": None, "ratio_to_goal": None}
    name = min(usable, key=lambda k: usable[k]["interface_and_pressure_s"])
    seconds = usable[name]["interface_and_pressure_s"]
    goal = GOALS.get(grid_name)
    return {"solver": name, "interface_and_pressure_s": seconds,
            "ratio_to_goal": seconds / goal if goal else None}


def main() -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="smoke test: 2 timed steps, two grids, two pressure solvers")
    args = parser.parse_args()
    grids = QUICK_GRIDS if args.quick else tuple(GRIDS)
    solvers = QUICK_SOLVERS if args.quick else tuple(LINEAR_SOLVERS)
    tic = time.perf_counter()
    results = {}
    for grid_name in grids:
        steps = QUICK_STEPS if args.quick else TIMED_STEPS[GRIDS[grid_name][1]]
        results[grid_name] = run_grid(grid_name, solvers, steps)
    out = {
        "suite": SUITE,
        "unavailable_suites": UNAVAILABLE_SUITES,
        "note": NOTE,
        "goals": GOALS,
        "settings": {"dt_s": DT, "flow_rate_m3_per_s": FLOW_RATE,
                     "sag_rate_m_per_s": sag_rate(TANK_RADIUS, FLOW_RATE),
                     "initial_sag_m": INITIAL_SAG, "tank_radius_m": TANK_RADIUS,
                     "momentum_solver": f"{SUITE}/{MOMENTUM_SOLVER}",
                     "warm_up_steps": WARM_UP_STEPS, "quick": args.quick,
                     "step_limit_s": STEP_LIMIT_S,
                     "openblas_num_threads": os.environ.get("OPENBLAS_NUM_THREADS")},
        "grids": results,
        "best": {g: best_solver(g, r) for g, r in results.items()},
        "run_seconds": time.perf_counter() - tic,
    }
    print(json.dumps(out, indent=2))
    return out


if __name__ == "__main__":
    main()
