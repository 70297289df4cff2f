"""The two linear systems of the liquid step, what fills them, and who assembles them.

Momentum predictor, one system per velocity component u (FiPy terms, see :mod:`fluid.terms`):

    rho (u - u_old)/dt + div(F u) - (div F) u
        = div(mu_f grad u) - pin (u - u_wall) - dp/dx_a [- mu u / r^2 for u_r, axisymmetric]

with u fixed on flow-port faces, zero flux through the other boundary faces; pressure
correction (unknown dp):

    div(c_f grad dp) - pin dp = s,   dp fixed on pressure-port faces.

Both are assembled as FiPy assembles them: FiPy's sign convention (the diffusion operator
enters with a negative diagonal), first-order upwind convection, FiPy's treatment of the
source term -(div F) u (implicit where it adds to the diagonal, lagged where it would take
from it) and of the fixed boundary values. An assembly is registered by name in
:data:`ASSEMBLIES` and returns, for given inputs, SciPy CSR matrices and right-hand sides.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class MomentumInputs:
    """What fills the momentum systems of one step.

    dt: s; face_viscosity (n_faces,) Pa s, mu_f; face_mass_flux (n_faces,) kg/(m^2 s),
    rho times the old wetted face velocity along FiPy's face normal; cell_flux_divergence
    (n_cells,) kg/(m^3 s), div of that flux; cell_pin (n_cells,) kg/(m^3 s), pull towards
    cell_pin_velocity (n_cells, dim) m/s; cell_pressure_gradient (n_cells, dim) Pa/m;
    face_inflow (n_faces, dim) m/s, the velocity on flow-port faces; cell_velocity_old
    (n_cells, dim) m/s."""

    dt: float
    face_viscosity: np.ndarray
    face_mass_flux: np.ndarray
    cell_flux_divergence: np.ndarray
    cell_pin: np.ndarray
    cell_pin_velocity: np.ndarray
    cell_pressure_gradient: np.ndarray
    face_inflow: np.ndarray
    cell_velocity_old: np.ndarray


@dataclass(frozen=True)
class PressureInputs:
    """What fills the pressure-correction system of one step.

    face_coefficient (n_faces,) m^3 s/kg, c_f = beta dt / rho; cell_pin (n_cells,)
    m^3 s/kg per m^2, holding cells outside the liquid (and gauge cells) at 0; cell_source
    (n_cells,) 1/s; face_boundary (n_faces,) Pa, dp on pressure-port faces (ignored
    elsewhere)."""

    face_coefficient: np.ndarray
    cell_pin: np.ndarray
    cell_source: np.ndarray
    face_boundary: np.ndarray


#: name -> class(model, flow_faces, pressure_faces) with ``momentum(MomentumInputs)`` ->
#: [(matrix, rhs)] per component and ``pressure(PressureInputs)`` -> (matrix, rhs)
ASSEMBLIES: dict[str, Callable] = {}


def register_assembly(name: str):
    """Class decorator: register an assembly under ``name``."""
    def register(cls):
        ASSEMBLIES[name] = cls
        return cls
    return register
