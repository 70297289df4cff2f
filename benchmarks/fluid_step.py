"""Seconds and microseconds per cell-step of the full liquid step on the benchmark tank grids.

    python benchmarks/fluid_step.py [--quick] [--smoke]

A full step is what ``FluidSolver.advance`` does: the cut-cell geometry of the new interface
(geometry), the momentum predictor (momentum: assembly and three component solves) and the
Rhie-Chow face velocities, pressure correction and update (pressure). Grids: axisymmetric
64 x 128 and 3-D 16^3, 32^3, 48^3 over the spherical tank of radius ``TANK_RADIUS`` with its
bottom port stub. The tank fills through its bottom flow port at ``FLOW_RATE`` while the
membrane, a paraboloid bowl z = -s (1 - r^2/R^2) with the liquid below, rises at the matching
rate: the liquid volume under the bowl is V = V_hemisphere - (pi R^2 / 2) s, so
ds/dt = -2 Q / (pi R^2), and every membrane point moves vertically at
v_z = -(ds/dt) (1 - r^2/R^2). The interface therefore changes every step.

After ``WARM_UP_STEPS`` steps (numba compilation, preconditioner set-up) the wall time of
``TIMED_STEPS`` steps at dt = ``DT`` is averaged, one process, one BLAS thread (the package
limits its solves to one). Per grid it records ``seconds_per_step``, ``us_per_cell_step``,
the share of geometry, momentum and pressure, the linear solvers with their relative
tolerances (FiPy's RHS criterion), iterations and largest residuals, and, so that speed is
never reported without accuracy, the largest |volume mismatch| / Q and the largest cell
divergence (1/s).

Peer in the same run: the same steps with ``assembly = "fipy"``, FiPy building both systems
from its terms every step (the discretisation the direct assembly reproduces; see
``tests/test_assembly.py``), on every grid but 48^3 (``PEER_STEPS`` steps):
``fipy_assembly_seconds_per_step`` and the speed-up. Anchor: OpenFOAM's interFoam (v1912,
serial, on this machine; two-phase VOF + PISO, so more work per step) at
``ANCHOR_US_PER_CELL_STEP``; ``ratio_to_anchor`` = ours / theirs. The growth of the cost with
the cell count over the 3-D grids is fitted (observed exponent) and charted with the phases in
``benchmarks/output/fluid_step.png``.

Prints one JSON object on stdout (progress goes to stderr); a full run also writes it to
``docs/data/fluid_step.json``. ``--quick``: 2 timed steps on the axisymmetric grid and 16^3, no
peer, no figure. ``--smoke``: one timed step (and one peer step) on :data:`SMOKE_GRIDS`, the
figure under ``benchmarks/output/smoke/``.
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from _report import SMOKE_HELP, emit, output_dir
from fluid.model import Port
from fluid.projection import MOMENTUM_TOLERANCE
from fluid.solver import FluidSolver, Timings
from fluid.tank import sphere_model, tank_grid
from fluid.validation import bowl_meridian, bowl_surface
from fsi.constants import STANDARD_GRAVITY, TANK_RADIUS

FIGURE_NAME = "fluid_step.png"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("goal_us_per_cell_step", "anchor", "grids", "growth_exponent_3d", "run_seconds")
#: grid name -> (cells argument of ``tank_grid``, axisymmetric)
GRIDS = {"axisymmetric-64x128": (64, True), "3d-16^3": (16, False), "3d-32^3": (32, False),
         "3d-48^3": (48, False)}
QUICK_GRIDS = ("axisymmetric-64x128", "3d-16^3")
#: --smoke: two 3-D grids, so that the growth exponent is fitted
SMOKE_GRIDS = ("axisymmetric-64x128", "3d-16^3", "3d-32^3")
#: timed steps per grid (full run; --quick: 2)
TIMED_STEPS = {"axisymmetric-64x128": 20, "3d-16^3": 20, "3d-32^3": 8, "3d-48^3": 4}
#: timed steps of the FiPy-assembly peer (None: not run on that grid)
PEER_STEPS = {"axisymmetric-64x128": 3, "3d-16^3": 3, "3d-32^3": 2, "3d-48^3": None}
WARM_UP_STEPS = 3
DT = 1e-3  # s
#: inflow through the bottom port, m^3/s: 1 L/s fills the 38.5 L tank in about 40 s; the
#: membrane's pole rises at 14.5 mm/s and the jet through the port stub keeps the Courant
#: number below 1 on every grid
FLOW_RATE = 1e-3
#: membrane sag at t = 0, m (bowl depth at the pole, half the tank radius)
INITIAL_SAG = 0.5 * TANK_RADIUS
#: membrane resolution: meridian points (axisymmetric), lattice cells per side (3-D)
MERIDIAN_POINTS = 41
SURFACE_CELLS = 24
#: the goal per cell-step, us (at 16^3 and 32^3)
GOAL_US_PER_CELL_STEP = 6.0
#: OpenFOAM interFoam v1912, serial, on this machine: us per cell-step at (cells)
ANCHOR_US_PER_CELL_STEP = {7664: 5.9, 34776: 5.7}


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def sag_rate(radius: float, flow_rate: float) -> float:
    """ds/dt (m/s) of the bowl's sag for an inflow ``flow_rate`` (m^3/s) below it."""
    return -2.0 * flow_rate / (np.pi * radius**2)


def membrane(radius: float, time: float, axisymmetric: bool):
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


def build_solver(grid_name: str, **options) -> FluidSolver:
    """Fresh solver of the filling tank on ``grid_name``; ``options`` go to the model."""
    cells, axisymmetric = GRIDS[grid_name]
    grid = tank_grid(TANK_RADIUS, cells, axisymmetric)
    model = sphere_model(TANK_RADIUS, grid, [Port("bottom", "flow", FLOW_RATE)],
                         body_acceleration=(0.0, 0.0, -STANDARD_GRAVITY), **options)
    return FluidSolver(model, membrane(TANK_RADIUS, 0.0, axisymmetric))


def time_steps(solver: FluidSolver, timed_steps: int) -> dict:
    """Seconds per step and per phase, iterations and accuracy over ``timed_steps`` steps
    after the warm-up."""
    axisymmetric = solver.model.grid.axisymmetric
    reports, seconds = [], 0.0
    for k in range(WARM_UP_STEPS + timed_steps):
        if k == WARM_UP_STEPS:
            solver.timings = Timings()
        tic = time.perf_counter()
        report = solver.advance(DT, membrane(TANK_RADIUS, (k + 1) * DT, axisymmetric))
        if k >= WARM_UP_STEPS:
            seconds += time.perf_counter() - tic
            reports.append(report)
    phases = solver.timings.per_call()
    step = seconds / timed_steps
    return {
        "seconds_per_step": step,
        "us_per_cell_step": step / solver.model.grid.n_cells * 1e6,
        "phase_seconds": phases,
        "share": {name: value / step for name, value in phases.items()},
        "momentum_iterations_mean": float(np.mean([r.momentum_iterations for r in reports])),
        "pressure_iterations_mean": float(np.mean([r.pressure_iterations for r in reports])),
        "pressure_residual_max": float(max(r.pressure_residual for r in reports)),
        "max_volume_mismatch_over_Q": float(max(abs(r.volume_mismatch) for r in reports))
        / FLOW_RATE,
        "max_divergence_per_s": float(max(r.divergence for r in reports)),
        "timed_steps": timed_steps,
    }


def run_grid(grid_name: str, timed_steps: int, peer_steps: int | None) -> dict:
    """The grid's figures with the default (direct) assembly and, if asked, the FiPy peer."""
    solver = build_solver(grid_name)
    model, ops = solver.model, solver._ops
    entry = {"cells": model.grid.n_cells,
             "solvers": {"momentum": model.momentum_solver,
                         "momentum_tolerance": MOMENTUM_TOLERANCE,
                         "pressure": ops.pressure_solver_name,
                         "pressure_tolerance": model.pressure_tolerance}}
    entry.update(time_steps(solver, timed_steps))
    entry["meets_goal"] = entry["us_per_cell_step"] <= GOAL_US_PER_CELL_STEP
    anchor = ANCHOR_US_PER_CELL_STEP[min(ANCHOR_US_PER_CELL_STEP,
                                         key=lambda n: abs(np.log(n / entry["cells"])))]
    entry["ratio_to_anchor"] = entry["us_per_cell_step"] / anchor
    # the peer where it runs; None (not run) on the grids it is too slow for
    entry["fipy_assembly_seconds_per_step"] = entry["speedup_over_fipy_assembly"] = None
    if peer_steps:
        peer = FluidSolver(dataclasses.replace(model, assembly="fipy"),
                           membrane(TANK_RADIUS, 0.0, model.grid.axisymmetric))
        seconds = time_steps(peer, peer_steps)["seconds_per_step"]
        entry["fipy_assembly_seconds_per_step"] = seconds
        entry["speedup_over_fipy_assembly"] = seconds / entry["seconds_per_step"]
    return entry


def growth_exponent(results: dict) -> float | None:
    """Observed exponent p of seconds per step ~ cells^p over the 3-D grids."""
    rows = [(v["cells"], v["seconds_per_step"]) for k, v in results.items()
            if k.startswith("3d")]
    if len(rows) < 2:
        return None
    cells, seconds = np.log(np.array(rows)).T
    return float(np.polyfit(cells, seconds, 1)[0])


def _plot(results: dict, exponent: float | None, figure: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = sorted((v["cells"], v) for k, v in results.items() if k.startswith("3d"))
    cells = np.array([c for c, _ in rows], dtype=float)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    ax.loglog(cells, [v["seconds_per_step"] for _, v in rows], "ko-",
              label=f"full step (exponent {exponent:.2f})" if exponent else "full step")
    for phase, style in (("geometry", "s--"), ("momentum", "^--"), ("pressure", "v--")):
        ax.loglog(cells, [v["phase_seconds"][phase] for _, v in rows], style, label=phase)
    ax.loglog(cells, cells * GOAL_US_PER_CELL_STEP * 1e-6, "r:",
              label=f"{GOAL_US_PER_CELL_STEP:g} us per cell-step (goal, interFoam)")
    peers = [(c, v["fipy_assembly_seconds_per_step"]) for c, v in rows
             if v.get("fipy_assembly_seconds_per_step") is not None]
    if peers:
        ax.loglog(*np.array(peers).T, "x", color="grey", ms=9, label="FiPy assembly (peer)")
    ax.set_xlabel("cells (3-D tank grid)")
    ax.set_ylabel("seconds per step")
    ax.set_title("Liquid step: cost by grid and phase (filling tank, dt = 1 ms)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(figure, dpi=110)
    plt.close(fig)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="2 timed steps, axisymmetric and 16^3, no peer, no figure")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    figure = output_dir(args.smoke) / FIGURE_NAME
    tic = time.perf_counter()
    results = {}
    for name in (SMOKE_GRIDS if args.smoke else QUICK_GRIDS if args.quick else GRIDS):
        _log(f"{name} ...")
        if args.smoke:
            timed, peer = 1, PEER_STEPS[name] and 1
        else:
            timed = 2 if args.quick else TIMED_STEPS[name]
            peer = None if args.quick else PEER_STEPS[name]
        results[name] = run_grid(name, timed, peer)
        _log(f"  {results[name]['seconds_per_step']:.4f} s per step, "
             f"{results[name]['us_per_cell_step']:.2f} us per cell-step")
    exponent = growth_exponent(results)
    if not args.quick:
        _plot(results, exponent, figure)
    out = {
        "goal_us_per_cell_step": GOAL_US_PER_CELL_STEP,
        "anchor": {"what": "OpenFOAM interFoam v1912, serial, this machine (us per cell-step "
                           "at cells)", "us_per_cell_step": ANCHOR_US_PER_CELL_STEP},
        "settings": {"dt_s": DT, "flow_rate_m3_per_s": FLOW_RATE,
                     "tank_radius_m": TANK_RADIUS, "initial_sag_m": INITIAL_SAG,
                     "warm_up_steps": WARM_UP_STEPS, "quick": args.quick,
                     "smoke": args.smoke},
        "grids": results,
        "growth_exponent_3d": exponent,
        "figure": None if args.quick else str(figure),
        "run_seconds": time.perf_counter() - tic,
    }
    emit("fluid_step", out, args.smoke or args.quick)
    return out


if __name__ == "__main__":
    main()
