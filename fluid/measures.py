"""Integral measures of the liquid on a 3-D grid: momentum, angular momentum, kinetic energy,
viscous dissipation rate (tank frame, SI units).

The face velocities are the liquid's divergence-free field (one normal component per face),
so the integrals are sums over faces of the volume each face carries: its wetted fraction of
the liquid region (container and liquid side of the interface) times its area times the
distance between the centres it joins, V_f = beta_f A_f d_f (m^3). Summed over the faces of
one axis these volumes tile the liquid once, so

    P = rho sum_f V_f u_f e_a(f)                       momentum (kg m/s)
    L = rho sum_f V_f x_f x (u_f e_a(f))               angular momentum about the origin
    K = rho / 2 sum_f V_f u_f^2                        kinetic energy (J)

with u_f the velocity along +axis a(f) and x_f the face centre. The viscous dissipation rate
is the one of the discrete viscous operator of the momentum predictor,

    Phi = sum_inner faces mu_f A_f / d_f |u_P - u_N|^2   (W)

over faces with a liquid-centre cell on at least one side (mu_f / theta at the immersed wall,
where the other cell holds the wall's velocity; no stress on a free surface's faces), plus
the wall's shear on the ring of faces between two wall-centred cells, which the predictor
holds back towards the wall's velocity at the rate r_f = nu / l_f^2
(:func:`fluid.projection.ring_drag_rate`),

    Phi_ring = rho sum_ring V_f r_f (u_f - u_wall,f)^2   (W).
"""
from __future__ import annotations

import numpy as np

from .model import FluidModel, FluidState
from .projection import interpolate_to_faces, ring_drag_rate, viscous_face_coefficient, wall_ring


def _check(model: FluidModel) -> None:
    if model.grid.axisymmetric:
        raise ValueError("the liquid's integral measures are computed on a 3-D grid")


def face_volumes(model: FluidModel, state: FluidState) -> np.ndarray:
    """(n_faces,) m^3: V_f = beta_f A_f d_f, the liquid volume each face carries."""
    _check(model)
    g = model.grid
    return state.geometry.face_fraction * g.face_area * g.face_distance


def _along_axes(model: FluidModel, state: FluidState) -> np.ndarray:
    """(n_faces,) m/s: each face's velocity along +its axis."""
    return state.face_velocity * model.grid.face_sign


def momentum(model: FluidModel, state: FluidState) -> np.ndarray:
    """P (3,) kg m/s: the liquid's momentum in the tank frame."""
    g = model.grid
    m = model.density * face_volumes(model, state) * _along_axes(model, state)
    return np.bincount(g.face_axis, m, 3)


def angular_momentum(model: FluidModel, state: FluidState) -> np.ndarray:
    """L (3,) kg m^2/s: the liquid's angular momentum about the origin (tank centre)."""
    g = model.grid
    m = model.density * face_volumes(model, state) * _along_axes(model, state)
    vector = np.zeros((g.n_faces, 3))
    vector[np.arange(g.n_faces), g.face_axis] = m
    return np.cross(g.face_centre, vector).sum(axis=0)


def kinetic_energy(model: FluidModel, state: FluidState) -> float:
    """K (J): the liquid's kinetic energy in the tank frame."""
    return float(0.5 * model.density
                 * np.sum(face_volumes(model, state) * state.face_velocity**2))


def dissipation_rate(model: FluidModel, state: FluidState,
                     free_faces: np.ndarray | None = None) -> float:
    """Phi (W): the viscous dissipation rate of the discrete viscous operator (module doc);
    ``free_faces`` (k,) faces without stress (a free surface's)."""
    _check(model)
    if model.viscosity == 0:
        return 0.0
    g = model.grid
    geometry = state.geometry
    mu = viscous_face_coefficient(model, geometry)
    if free_faces is not None:
        mu = mu.copy()
        mu[free_faces] = 0.0
    p_cell, n_cell = g.face_cells
    inner = np.flatnonzero(n_cell >= 0)
    a, b = p_cell[inner], n_cell[inner]
    fluid = geometry.fluid_centre
    use = fluid[a] | fluid[b]
    wall = geometry.wall_velocity
    u = np.where(fluid[:, None], state.cell_velocity, wall)
    jump = np.sum((u[a[use]] - u[b[use]]) ** 2, axis=1)
    faces = inner[use]
    cells = float(np.sum(mu[faces] * g.face_area[faces] / g.face_distance[faces] * jump))
    ring = wall_ring(model, geometry)
    slip = (state.face_velocity - interpolate_to_faces(model, wall, fluid))[ring]
    rate = ring_drag_rate(model, geometry.face_fraction[ring])
    return cells + float(model.density * np.sum(face_volumes(model, state)[ring] * rate
                                                 * slip**2))
