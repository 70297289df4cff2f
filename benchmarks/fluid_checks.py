"""The fluid's verification numbers, printed as one JSON object (about 2 minutes).

    python benchmarks/fluid_checks.py

Each entry is measured against a closed-form oracle (see tests/test_fluid.py for the same
cases as pass/fail tests): hydrostatics with a membrane in the immersed sphere (axisymmetric
and 3-D), the added-mass pressure under an accelerating piston, liquid-volume bookkeeping
with port inflow, Hagen-Poiseuille flow through an immersed pipe wall and its grid
convergence.
"""
from __future__ import annotations

import json
import sys
import time

import numpy as np
from scipy.optimize import brentq

from fluid.model import Port
from fluid.solver import FluidSolver
from fluid.validation import (PistonCase, PoiseuilleCase, bowl_meridian, bowl_surface,
                              flat_interface, sphere_cross_section, sphere_model,
                              spherical_cap_volume, tank_grid)
from fsi.constants import STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY

R, RHO, G = TANK_RADIUS, WATER_DENSITY, STANDARD_GRAVITY


def hydrostatics(axisymmetric: bool, cells: int, steps: int = 100) -> dict:
    """Largest relative error of p = rho g (h - z) at the membrane points, largest speed."""
    grid = tank_grid(R, cells, axisymmetric)
    level = 0.05
    model = sphere_model(R, grid, [Port("bottom", "pressure", RHO * G * (level - grid.lower[-1]))],
                         momentum_solver="bicgstab-jacobi", pressure_solver="pcg-jacobi")
    itf = bowl_meridian(R, 0.3 * R) if axisymmetric else bowl_surface(R, 0.3 * R, 16)
    solver = FluidSolver(model, itf)
    for _ in range(steps):
        solver.advance(1e-3, itf)
    inside = np.hypot(itf.points[:, 0], itf.points[:, 1]) < R
    p = solver.pressure_at(itf.points[inside])
    exact = RHO * G * (level - itf.points[inside, 2])
    return {"grid": list(grid.shape), "steps": steps,
            "max_relative_error": float(np.max(np.abs(p - exact) / np.abs(exact))),
            "max_speed_m_s": solver.velocity_magnitude_max()}


def piston(cells: int) -> dict:
    """Relative error of rho (g + a) h at the piston after 50 steps of 1 ms."""
    case = PistonCase(cells_across=cells)
    model = case.model()
    solver = FluidSolver(model, case.piston(0.0))
    for k in range(1, 51):
        solver.advance(1e-3, case.piston(k * 1e-3))
    z = solver.interface.points[0, 2]
    pts = np.stack([np.linspace(0, 0.9 * case.radius, 8), np.zeros(8), np.full(8, z)], axis=1)
    err = solver.pressure_at(pts) / case.oracle(model, 0.05) - 1
    added = case.acceleration / (case.gravity + case.acceleration)
    return {"cells_across": cells, "max_relative_error": float(np.max(np.abs(err))),
            "max_error_of_added_mass_part": float(np.max(np.abs(err)) / added)}


def volume(cells: int = 32, steps: int = 200) -> dict:
    """Liquid volume against V0 + Q t with a plane membrane rising at Q / A(z)."""
    grid = tank_grid(R, cells, True)
    Q, dt, z0 = 1.0e-3, 5e-3, -0.05
    model = sphere_model(R, grid, [Port("bottom", "flow", Q)],
                         momentum_solver="bicgstab-jacobi", pressure_solver="pcg-jacobi")
    v_start = spherical_cap_volume(R, z0)

    def plane(t):
        z = brentq(lambda zz: spherical_cap_volume(R, zz) - v_start - Q * t, -R, R)
        return flat_interface(z, 1.1 * R, Q / sphere_cross_section(R, z), True, False)

    solver = FluidSolver(model, plane(0.0))
    v0 = solver.liquid_volume
    mismatch = divergence = 0.0
    for k in range(1, steps + 1):
        report = solver.advance(dt, plane(k * dt))
        mismatch = max(mismatch, abs(report.volume_mismatch))
        divergence = max(divergence, report.divergence)
    return {"steps": steps, "relative_volume_error": float((solver.liquid_volume - v0)
                                                           / (Q * steps * dt) - 1),
            "max_volume_mismatch_over_Q": mismatch / Q,
            "max_divergence_over_Q_per_V": divergence / (Q / v0)}


def poiseuille(cells: int) -> float:
    """Largest error of the Hagen-Poiseuille profile over its maximum, at mid-length."""
    case = PoiseuilleCase(cells_across=cells)
    model = case.model()
    solver = FluidSolver(model)
    for _ in range(int(6 * case.viscous_time / 0.01)):
        solver.advance(0.01)
    g = model.grid
    mid = g.centre_axes[1][g.shape[1] // 2]
    sel = (np.abs(g.cell_centre[:, 1] - mid) < 0.25 * g.spacing) & \
        solver.state.geometry.fluid_centre
    exact = case.profile(model, g.cell_centre[sel, 0])
    return float(np.max(np.abs(solver.state.cell_velocity[sel, 1] - exact)) / exact.max())


def main() -> dict:
    tic = time.perf_counter()
    out = {}
    for name, job in [("hydrostatics_axisymmetric", lambda: hydrostatics(True, 32)),
                      ("hydrostatics_3d", lambda: hydrostatics(False, 16)),
                      ("piston", lambda: [piston(n) for n in (16, 32, 64)]),
                      ("volume_bookkeeping", volume)]:
        print(f"{name} ...", file=sys.stderr, flush=True)
        out[name] = job()
    errors = [poiseuille(n) for n in (8, 16, 32)]
    out["poiseuille"] = {"cells_across": [8, 16, 32], "max_relative_error": errors,
                         "observed_order": [float(np.log2(a / b))
                                            for a, b in zip(errors[:-1], errors[1:])]}
    out["seconds"] = time.perf_counter() - tic
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
