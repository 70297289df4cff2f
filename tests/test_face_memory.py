"""Which face velocities of the moving-wall step keep their history (FluidModel.face_memory).

Oracle: without viscosity, convection and body force, a face that keeps its history evolves
as a staggered grid's, u_f^{n+1} = u_f^n - dt/rho grad_f p^{n+1} (Choi 1999); a face field
that is already divergence-free then needs no pressure and stays as it is, whatever the cell
velocities say (the module doc of fluid.projection, _memory_faces). Rhie-Chow's faces,
re-interpolated from the cells each step, do not: they take the cells' field.
"""
from dataclasses import replace

import numpy as np
import pytest

from fluid.model import FACE_MEMORIES
from fluid.projection import step
from fluid.solver import FluidSolver
from fluid.tank import sphere_model, tank_grid
from fsi.constants import TANK_RADIUS, WATER_DENSITY

DT = 1e-3  # s


def _solver(face_memory: str) -> FluidSolver:
    grid = tank_grid(TANK_RADIUS, 10, axisymmetric=False)
    model = sphere_model(TANK_RADIUS, grid, [], (0.0, 0.0, 0.0), density=WATER_DENSITY,
                         viscosity=0.0, convection=False, face_memory=face_memory)
    return FluidSolver(model)


def _divergence_free_faces(solver: FluidSolver) -> np.ndarray:
    """A divergence-free face field (n_faces,) m/s: one step from random cell velocities."""
    g = solver.model.grid
    rng = np.random.default_rng(7)
    start = solver.state
    solver.state = replace(start, cell_velocity=rng.normal(0.0, 0.1, (g.n_cells, g.dim)))
    ring = replace(solver.model, face_memory="ring")
    state, _ = step(ring, solver._ops, solver.state, start.geometry, DT)
    return state.face_velocity


@pytest.mark.parametrize("face_memory", FACE_MEMORIES)
def test_a_divergence_free_face_field_is_kept_only_by_faces_with_memory(face_memory):
    solver = _solver(face_memory)
    faces = _divergence_free_faces(solver)
    assert np.abs(faces).max() > 1e-3
    # the cells say nothing of that field: at rest
    solver.state = replace(solver.state, face_velocity=faces,
                           cell_velocity=np.zeros_like(solver.state.cell_velocity))
    for _ in range(3):
        solver.advance(DT)
    change = np.abs(solver.state.face_velocity - faces).max() / np.abs(faces).max()
    if face_memory == "every-face":
        assert change < 1e-6
    else:
        assert change > 0.5  # the faces followed the cells at rest


def test_an_unknown_face_memory_is_refused_by_name():
    grid = tank_grid(TANK_RADIUS, 10, axisymmetric=False)
    with pytest.raises(ValueError, match="face_memory must be one of"):
        sphere_model(TANK_RADIUS, grid, [], (0.0, 0.0, -9.81), face_memory="all")
