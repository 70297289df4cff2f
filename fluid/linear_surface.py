"""The liquid step with a linearised free surface: the mean surface fixed, its elevation a state.

Linear slosh theory (the theory of the closed forms a slosh code is checked against: Lamb's
cylinder, Budiansky's sphere, the free-surface elements of NASTRAN's demo problem d03031a)
keeps the liquid's region fixed at its rest shape and carries the surface's small
displacement eta along the outward normal n as a field on the mean surface::

    d eta / dt = u . n                       (kinematic condition, linearised)
    p = 0 at x_s + eta n,  i.e.  p_red(x_s) = -rho b(t) . (x_s + eta n)
                                             (dynamic condition, to first order in eta)

with p_red = p - rho b . x the reduced pressure of :mod:`fluid.projection` (b = g - a the
body acceleration in the tank frame, so -b . n = g on a level surface at rest).

This is :mod:`fluid.free_surface`'s step on a geometry that does not change (the caller passes
the mean surface once: no cell or face ever changes sides, so nothing is handed over between
layers), with one elevation per surface face in :attr:`fluid.model.FluidState.surface_height`:

* first the elevation moves by the last step's face velocities, eta^{n+1} = eta^n +
  dt (u^n . n) (each surface face's own flux: exact volume bookkeeping, sum A_f eta_f stays
  zero to round-off in a closed tank);
* then the liquid steps with the surface's reduced pressure from eta^{n+1}.

Without viscosity and convection the faces evolve as a staggered grid's (every face keeps its
history), u^{n+1} = u^n - dt/rho G p^{n+1}, and the pair (u, eta) is advanced by the
symplectic Euler (Stormer-Verlet) map of the linear Hamiltonian

    E = rho/2 sum_f beta_f A_f d_f u_f^2 + 1/2 sum_s rho (-b . n) A_s eta_s^2   (J),

so a free decay keeps E's period mean to round-off: no numerical damping, at any amplitude.
It is the model of the oracles, not of a large slosh: it does not see the surface tilt past a
cell or reach the wall's curvature, which :mod:`fluid.free_surface` does.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from .free_surface import Surface, advance, column_index, initial_pressure, surface_of
from .geometry import Geometry
from .model import FluidModel, FluidState
from .projection import ProjectionOperators, StepReport
from .steppers import register_stepper


def outward_normals(model: FluidModel, surface: Surface) -> np.ndarray:
    """(k, 3) unit vectors: each surface face's normal pointing out of the liquid (FiPy's
    normal points away from a face's first cell)."""
    g = model.grid
    axis = g.face_axis[surface.faces]
    sign = g.face_sign[surface.faces] * np.where(surface.first, 1.0, -1.0)
    normals = np.zeros((len(axis), g.dim))
    normals[np.arange(len(axis)), axis] = sign
    return model.grid_points(normals)


def outflow_velocity(surface: Surface, face_velocity: np.ndarray) -> np.ndarray:
    """(k,) m/s: the velocity out of the liquid through each surface face, u . n."""
    u = face_velocity[surface.faces]
    return np.where(surface.first, u, -u)


def surface_pressure(model: FluidModel, surface: Surface, height: np.ndarray,
                     time: float) -> np.ndarray:
    """(k,) Pa: the reduced pressure at the mean surface's crossings for an elevation
    ``height`` (k,) m along the outward normals, -rho b(t) . (x_s + eta n) (gas at gauge 0)."""
    displaced = surface.point + height[:, None] * outward_normals(model, surface)
    return -model.body_potential(displaced, time)


def surface_areas(model: FluidModel, surface: Surface) -> np.ndarray:
    """(k,) m^2: the wetted area of each surface face (the part of the mean surface it
    carries)."""
    return surface.view.face_fraction[surface.faces] * model.grid.face_area[surface.faces]


def surface_energy(model: FluidModel, state: FluidState) -> float:
    """The surface's gravitational potential energy (J) relative to the mean surface,
    1/2 sum_s rho (-b(t) . n_s) A_s eta_s^2."""
    if state.surface_height is None:
        return 0.0
    surface = surface_of(model, state.geometry)
    stiffness = -(outward_normals(model, surface) @ model.body_acceleration_at(state.time))
    return 0.5 * model.density * float(np.sum(stiffness * surface_areas(model, surface)
                                              * state.surface_height**2))


@register_stepper("free-linear", initial_pressure)
def step(model: FluidModel, ops: ProjectionOperators, state: FluidState, geometry: Geometry,
         dt: float) -> tuple[FluidState, StepReport]:
    """Advance ``state`` by ``dt`` (s) under the fixed mean surface ``geometry`` (the one the
    state was started with); see the module doc."""
    surface = surface_of(model, geometry)
    height = state.surface_height
    if height is None:
        height = np.zeros(len(surface.faces))
    old = surface_of(model, state.geometry)
    if not np.array_equal(old.faces, surface.faces):
        raise ValueError("a linearised free surface keeps its mean surface: advance it with "
                         "the interface it was started with")
    new_height = height + dt * outflow_velocity(surface, state.face_velocity)
    geometry = _extended(model, geometry, surface, state.cell_velocity)
    t0, t1 = state.time, state.time + dt
    new, report = advance(model, ops, state, geometry, dt, surface,
                          surface_pressure(model, surface, height, t0),
                          surface_pressure(model, surface, new_height, t1), old)
    return replace(new, surface_height=new_height), report


def _extended(model: FluidModel, geometry: Geometry, surface: Surface,
              cell_velocity: np.ndarray) -> Geometry:
    """``geometry`` with the gas-centre cells next to the surface holding the liquid's velocity
    (the mean of the liquid cells across their surface faces; the moving surface's are its
    nodes' velocity, the liquid's extended), not the mean surface's rest: a free surface is no
    wall."""
    g = model.grid
    gas = np.where(surface.first, g.face_cells[1][surface.faces],
                   g.face_cells[0][surface.faces])
    count = np.bincount(gas, minlength=g.n_cells)
    near = count > 0
    velocity = geometry.wall_velocity.copy()
    columns = [0, 2] if g.axisymmetric else list(range(3))
    for k, c in enumerate(columns):
        total = np.bincount(gas, cell_velocity[surface.cell, k], g.n_cells)
        velocity[near, c] = total[near] / count[near]
    return replace(geometry, wall_velocity=velocity)


def column_heights(model: FluidModel, state: FluidState) -> tuple[np.ndarray, np.ndarray]:
    """The elevation over each vertical column of cells of a 3-D grid: ((nx, ny) m, its
    vertical surface face's eta; (nx, ny) bool: the column has one)."""
    g = model.grid
    if g.axisymmetric:
        raise ValueError("column heights need a 3-D grid")
    surface = surface_of(model, state.geometry)
    height = (np.zeros(len(surface.faces)) if state.surface_height is None
              else state.surface_height)
    vertical = g.face_axis[surface.faces] == g.vertical_axis
    column = column_index(g, surface.cell[vertical])
    n = g.shape[0] * g.shape[1]
    total = np.bincount(column, height[vertical], n)
    count = np.bincount(column, minlength=n)
    has = count > 0
    out = np.where(has, total / np.maximum(count, 1), 0.0)
    return out.reshape(g.shape[:2]), has.reshape(g.shape[:2])
