"""The liquid step's systems assembled directly into a fixed sparsity pattern.

The same matrices and right-hand sides as FiPy builds from the terms of :mod:`fluid.terms`
(held equal to round-off by ``tests/test_assembly.py``), from the same mesh geometry (FiPy's
face areas, cell-centre distances and cell volumes), without FiPy's per-step rebuild: the CSR
pattern (the diagonal and the two cells of every inner face) is laid out once and each step
writes its values with a few vector operations. The momentum matrix is one for the three
components (on the axisymmetric grid u_r adds mu / r^2 on the diagonal); only the right-hand
sides differ.

Per inner face f between cells P (FiPy's first cell) and N, with area A, centre distance d and
F = (rho u_f beta) A along FiPy's normal (P -> N), in FiPy's convention (rows of L x = b)::

    momentum, upwind (alpha = 1 if F > 0):  L_PP += alpha F + k,  L_PN += (1 - alpha) F - k,
                                            L_NN += (alpha - 1) F + k,  L_NP += -alpha F - k,
    with k = mu_f A / d (F = 0 and div F = 0 without convection);  L_PP += rho V / dt + pin V + max(-div F, 0) V;
    b_P = rho V / dt u_old + max(div F, 0) V u_old + V (pin u_wall - dp/dx_a);
    a flow-port face (u fixed to u_in) adds alpha F + k_b to L_PP and (1 - alpha) (-F) u_in
    + k_b u_in to b_P (k_b = mu A / d_b, d_b from the centre to the face);
    pressure: L_PP -= k, L_PN += k (k = c_f A / d), L_PP -= pin V, b_P = s V; a pressure-port
    face adds -k_b to L_PP and -k_b dp_b to b_P.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .model import FluidModel
from .systems import MomentumInputs, PressureInputs, register_assembly


class Pattern:
    """CSR layout of a cell-to-cell operator on the grid: the diagonal and, per inner face,
    the entries (P, N) and (N, P); ``diagonal``, ``upper``, ``lower`` are their slots in
    the data array."""

    def __init__(self, model: FluidModel):
        g = model.grid
        n = g.n_cells
        p_cell, n_cell = g.face_cells
        self.inner = np.flatnonzero(n_cell >= 0)
        self.first = p_cell[self.inner]
        self.second = n_cell[self.inner]
        m = len(self.inner)
        rows = np.concatenate([np.arange(n), self.first, self.second])
        cols = np.concatenate([np.arange(n), self.second, self.first])
        order = sp.csr_matrix((np.arange(1, n + 2 * m + 1, dtype=float), (rows, cols)),
                              shape=(n, n))
        order.sort_indices()
        slot = np.empty(n + 2 * m, dtype=np.int64)
        slot[order.data.astype(np.int64) - 1] = np.arange(n + 2 * m)
        self.diagonal, self.upper, self.lower = slot[:n], slot[n:n + m], slot[n + m:]
        self.indices, self.indptr, self.n = order.indices, order.indptr, n

    def matrix(self, diagonal: np.ndarray, upper: np.ndarray, lower: np.ndarray):
        """CSR matrix with these diagonal (n,), (P, N) and (N, P) (per inner face) values."""
        data = np.empty(len(self.indices))
        data[self.diagonal] = diagonal
        data[self.upper] = upper
        data[self.lower] = lower
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))


@register_assembly("direct")
class DirectAssembly:
    """Momentum and pressure systems of one model on a pattern laid out once."""

    def __init__(self, model: FluidModel, flow_faces: np.ndarray, pressure_faces: np.ndarray):
        g = model.grid
        self.model = model
        self.pattern = Pattern(model)
        inner = self.pattern.inner
        self.volume = g.cell_volume
        self.area = g.face_area
        self.inner_conductance = g.face_area[inner] / g.face_distance[inner]  # m (A / d)
        self.flow_faces = np.flatnonzero(flow_faces)
        self.flow_cells = g.face_cells[0][self.flow_faces]
        self.pressure_faces = np.flatnonzero(pressure_faces)
        self.pressure_cells = g.face_cells[0][self.pressure_faces]
        self.boundary_conductance = g.face_area / g.face_distance
        self.hoop = None
        if g.axisymmetric and model.viscosity > 0:
            r = np.maximum(g.cell_centre[:, 0], 0.5 * g.spacing)
            self.hoop = model.viscosity / r**2 * g.cell_volume

    def _scatter(self, first_values, second_values):
        """(n_cells,) sums of per-inner-face values onto the faces' first and second cells."""
        n = self.pattern.n
        return np.bincount(self.pattern.first, first_values, minlength=n) + \
            np.bincount(self.pattern.second, second_values, minlength=n)

    def momentum(self, inputs: MomentumInputs) -> list:
        """[(matrix, rhs)] of each velocity component (shared matrix where equal)."""
        model, pattern, volume = self.model, self.pattern, self.volume
        rho_v_dt = model.density * volume / inputs.dt
        k = inputs.face_viscosity[pattern.inner] * self.inner_conductance
        convection = 1.0 if model.convection else 0.0
        flux = convection * inputs.face_mass_flux * self.area
        f_in = flux[pattern.inner]
        out_p, out_n = np.maximum(f_in, 0.0), np.maximum(-f_in, 0.0)
        divergence = convection * inputs.cell_flux_divergence
        diagonal = rho_v_dt + inputs.cell_pin * volume + np.maximum(-divergence, 0.0) * volume \
            + self._scatter(out_p + k, out_n + k)
        upper = -out_n - k
        lower = -out_p - k
        explicit = (rho_v_dt + np.maximum(divergence, 0.0) * volume)[:, None] \
            * inputs.cell_velocity_old
        rhs = explicit + volume[:, None] * (inputs.cell_pin[:, None] * inputs.cell_pin_velocity
                                            - inputs.cell_pressure_gradient)
        if len(self.flow_faces):
            faces, cells = self.flow_faces, self.flow_cells
            f_b = flux[faces]
            k_b = inputs.face_viscosity[faces] * self.boundary_conductance[faces]
            np.add.at(diagonal, cells, np.maximum(f_b, 0.0) + k_b)
            gain = np.maximum(-f_b, 0.0) + k_b
            np.add.at(rhs, cells, gain[:, None] * inputs.face_inflow[faces])
        matrix = pattern.matrix(diagonal, upper, lower)
        systems = [(matrix, rhs[:, a].copy()) for a in range(rhs.shape[1])]
        if self.hoop is not None:
            systems[0] = (pattern.matrix(diagonal + self.hoop, upper, lower), systems[0][1])
        return systems

    def pressure(self, inputs: PressureInputs):
        """(matrix, rhs) of the pressure correction."""
        pattern, volume = self.pattern, self.volume
        k = inputs.face_coefficient[pattern.inner] * self.inner_conductance
        diagonal = -self._scatter(k, k) - inputs.cell_pin * volume
        rhs = inputs.cell_source * volume
        if len(self.pressure_faces):
            faces, cells = self.pressure_faces, self.pressure_cells
            k_b = inputs.face_coefficient[faces] * self.boundary_conductance[faces]
            np.add.at(diagonal, cells, -k_b)
            np.add.at(rhs, cells, -k_b * np.nan_to_num(inputs.face_boundary[faces]))
        return pattern.matrix(diagonal, k, k), rhs
