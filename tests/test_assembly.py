"""The directly assembled systems of the liquid step equal what FiPy's terms build.

For a state reached by a few steps of a moving interface (the filling bowl of
``benchmarks/fluid_step.py``: the interface and its velocity change every step), the momentum
matrices and right-hand sides of every component and the pressure-correction matrix and
right-hand side that :class:`fluid.assembly.DirectAssembly` writes into its fixed pattern are
compared with those FiPy assembles from the terms of :mod:`fluid.terms`
(``_prepareLinearSystem``): axisymmetric and 3-D, flow and pressure ports, with and without
convection and viscosity. Round-off only: the two sum the same face terms in different
orders.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from fluid.assembly import DirectAssembly
from fluid.model import Port
from fluid.projection import step_inputs
from fluid.solver import FluidSolver
from fluid.tank import sphere_model, tank_grid
from fluid.terms import FipyTerms
from fluid.validation import PoiseuilleCase, bowl_meridian, bowl_surface

RADIUS = 0.2  # m
G = 9.81  # m/s^2
DT = 1e-3  # s
FLOW = 1e-4  # m^3/s into the tank
ROUND_OFF = 1e-13  # largest |difference| / largest |entry|


def bowl(time: float, axisymmetric: bool):
    """Paraboloid bowl over the liquid, sagging less as liquid comes in (m, m/s)."""
    rate = -2.0 * FLOW / (np.pi * RADIUS**2)
    surface = bowl_meridian(RADIUS, 0.5 * RADIUS + rate * time, 21) if axisymmetric \
        else bowl_surface(RADIUS, 0.5 * RADIUS + rate * time, 10)
    r2 = np.minimum(surface.points[:, 0] ** 2 + surface.points[:, 1] ** 2, RADIUS**2)
    velocities = np.zeros_like(surface.points)
    velocities[:, 2] = -rate * (1.0 - r2 / RADIUS**2)
    return surface.with_state(surface.points, velocities)


def tank_solver(axisymmetric: bool, port: Port, **options) -> FluidSolver:
    grid = tank_grid(RADIUS, 20 if axisymmetric else 11, axisymmetric)
    model = sphere_model(RADIUS, grid, [port], body_acceleration=(0.0, 0.0, -G), **options)
    return FluidSolver(model, bowl(0.0, axisymmetric))


def moved(solver: FluidSolver, steps: int = 3) -> FluidSolver:
    axisymmetric = solver.model.grid.axisymmetric
    for k in range(steps):
        solver.advance(DT, bowl((k + 1) * DT, axisymmetric))
    return solver


def _relative(a, b) -> float:
    scale = max(float(np.max(np.abs(a))), 1e-300)
    return float(np.max(np.abs(a - b))) / scale


def assert_same_systems(solver: FluidSolver, interface) -> None:
    model, ops = solver.model, solver._ops
    geometry = solver.geometry_for(interface)
    momentum, pressure = step_inputs(model, ops, solver.state, geometry, DT)
    fipy = FipyTerms(model, ops.flow_faces, ops.pressure_faces)
    direct = DirectAssembly(model, ops.flow_faces, ops.pressure_faces)
    assert np.any(momentum.face_mass_flux != 0) or not model.convection
    for (a_f, b_f), (a_d, b_d) in zip(fipy.momentum(momentum), direct.momentum(momentum)):
        assert a_f.shape == a_d.shape
        assert _relative(a_f.toarray(), a_d.toarray()) < ROUND_OFF
        assert _relative(b_f, b_d) < ROUND_OFF
    (a_f, b_f), (a_d, b_d) = fipy.pressure(pressure), direct.pressure(pressure)
    assert _relative(a_f.toarray(), a_d.toarray()) < ROUND_OFF
    assert _relative(b_f, b_d) < ROUND_OFF
    assert np.any(b_f != 0)


@pytest.mark.parametrize("axisymmetric", [True, False])
def test_direct_systems_equal_fipy_terms_with_a_flow_port(axisymmetric):
    solver = moved(tank_solver(axisymmetric, Port("bottom", "flow", FLOW)))
    assert_same_systems(solver, bowl(4 * DT, axisymmetric))


@pytest.mark.parametrize("axisymmetric", [True, False])
def test_direct_systems_equal_fipy_terms_with_a_pressure_port_inviscid(axisymmetric):
    solver = moved(tank_solver(axisymmetric, Port("bottom", "pressure", 50.0), viscosity=0.0))
    assert_same_systems(solver, bowl(4 * DT, axisymmetric))


def test_direct_systems_equal_fipy_terms_without_convection():
    """Poiseuille pipe: two pressure ports, Stokes flow (no convection term in FiPy's
    equation, so none in the direct one)."""
    case = PoiseuilleCase(cells_across=8)
    solver = FluidSolver(case.model())
    for _ in range(5):
        solver.advance(0.01)
    model, ops = solver.model, solver._ops
    momentum, pressure = step_inputs(model, ops, solver.state, solver.geometry_for(None), 0.01)
    fipy = FipyTerms(model, ops.flow_faces, ops.pressure_faces)
    direct = DirectAssembly(model, ops.flow_faces, ops.pressure_faces)
    assert np.any(momentum.face_mass_flux != 0)  # the flux is there, the term is not
    for (a_f, b_f), (a_d, b_d) in zip(fipy.momentum(momentum), direct.momentum(momentum)):
        assert _relative(a_f.toarray(), a_d.toarray()) < ROUND_OFF
        assert _relative(b_f, b_d) < ROUND_OFF
    (a_f, b_f), (a_d, b_d) = fipy.pressure(pressure), direct.pressure(pressure)
    assert _relative(a_f.toarray(), a_d.toarray()) < ROUND_OFF
    assert _relative(b_f, b_d) < ROUND_OFF


@pytest.mark.parametrize("axisymmetric", [True, False])
def test_steps_with_either_assembly_agree_to_the_solver_tolerance(axisymmetric):
    """Ten filling steps with each assembly: the same velocities and pressures, to the
    linear solvers' relative tolerance (1e-10) amplified by at most a few hundred."""
    runs = []
    for assembly in ("direct", "fipy"):
        solver = tank_solver(axisymmetric, Port("bottom", "flow", FLOW))
        solver.model = dataclasses.replace(solver.model, assembly=assembly)
        solver.__post_init__()
        runs.append(moved(solver, steps=10).state)
    direct, fipy = runs
    assert _relative(fipy.cell_velocity, direct.cell_velocity) < 1e-7
    assert _relative(fipy.face_velocity, direct.face_velocity) < 1e-7
    assert _relative(fipy.pressure, direct.pressure) < 1e-7
