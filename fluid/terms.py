"""The liquid step's equations as FiPy terms: the definition of its discretisation.

Momentum (one equation per component a, unknown u = velocity[a]):

    TransientTerm(rho) + UpwindConvectionTerm(F) - ImplicitSourceTerm(div F)
        == DiffusionTerm(mu_f) - ImplicitSourceTerm(pin) + pin u_wall - dp/dx_a
           [- ImplicitSourceTerm(mu / r^2) for u_r on the axisymmetric grid]

with u constrained to the inflow on flow-port faces; pressure correction (unknown dp):

    DiffusionTerm(c_f) - ImplicitSourceTerm(pin) == s,   dp constrained on pressure ports.

:class:`FipyTerms` fills the variables and lets FiPy build each system
(``_prepareLinearSystem``); :mod:`fluid.assembly` builds the same matrices directly, and the
tests hold the two equal.
"""
from __future__ import annotations

import fipy as fp
import numpy as np
from fipy.solvers.scipy import LinearLUSolver

from .model import FluidModel
from .systems import MomentumInputs, PressureInputs, register_assembly


def _system(equation, var, dt):
    """(CSR matrix, rhs) that FiPy builds for ``equation`` in ``var``."""
    holder = LinearLUSolver()
    with np.errstate(invalid="ignore", divide="ignore"):  # FiPy's Peclet number, 0/0 faces
        equation._prepareLinearSystem(var=var, solver=holder, boundaryConditions=(), dt=dt)
    return holder.matrix.matrix.tocsr(), np.asarray(holder.RHSvector, dtype=float).copy()


@register_assembly("fipy")
class FipyTerms:
    """FiPy variables and equations for one model, built once and refilled every step."""

    def __init__(self, model: FluidModel, flow_faces: np.ndarray, pressure_faces: np.ndarray):
        grid = model.grid
        mesh = grid.mesh
        dim = grid.dim
        rho = model.density
        self.dim = dim
        self.normals = np.asarray(mesh.faceNormals)
        self.velocity = [fp.CellVariable(mesh=mesh, value=0.0, hasOld=True) for _ in range(dim)]
        self.viscous_coeff = fp.FaceVariable(mesh=mesh, value=model.viscosity)
        self.flux_velocity = fp.FaceVariable(mesh=mesh, rank=1, value=0.0)
        self.flux_divergence = fp.CellVariable(mesh=mesh, value=0.0)
        self.pin = fp.CellVariable(mesh=mesh, value=0.0)
        self.pin_target = [fp.CellVariable(mesh=mesh, value=0.0) for _ in range(dim)]
        self.pressure_gradient = [fp.CellVariable(mesh=mesh, value=0.0) for _ in range(dim)]
        self.momentum_eq = []
        for a in range(dim):
            u = self.velocity[a]
            lhs = fp.TransientTerm(coeff=rho, var=u)
            if model.convection:
                lhs = lhs + fp.UpwindConvectionTerm(coeff=self.flux_velocity, var=u) \
                    - fp.ImplicitSourceTerm(coeff=self.flux_divergence, var=u)
            rhs = fp.DiffusionTerm(coeff=self.viscous_coeff, var=u) \
                - fp.ImplicitSourceTerm(coeff=self.pin, var=u) \
                + self.pin * self.pin_target[a] - self.pressure_gradient[a]
            if grid.axisymmetric and a == 0 and model.viscosity > 0:
                r = np.maximum(grid.cell_centre[:, 0], 0.5 * grid.spacing)
                rhs = rhs - fp.ImplicitSourceTerm(
                    coeff=fp.CellVariable(mesh=mesh, value=model.viscosity / r**2), var=u)
            self.momentum_eq.append(lhs == rhs)
        self.inflow = [fp.FaceVariable(mesh=mesh, value=0.0) for _ in range(dim)]
        if flow_faces.any():
            mask = fp.FaceVariable(mesh=mesh, value=flow_faces)
            for a in range(dim):
                self.velocity[a].constrain(self.inflow[a], where=mask)
        self.correction = fp.CellVariable(mesh=mesh, value=0.0)
        self.correction_bc = fp.FaceVariable(mesh=mesh, value=0.0)
        if pressure_faces.any():
            self.correction.constrain(self.correction_bc,
                                      where=fp.FaceVariable(mesh=mesh, value=pressure_faces))
        self.pressure_coeff = fp.FaceVariable(mesh=mesh, value=0.0)
        self.pressure_pin = fp.CellVariable(mesh=mesh, value=0.0)
        self.pressure_source = fp.CellVariable(mesh=mesh, value=0.0)
        self.pressure_eq = fp.DiffusionTerm(coeff=self.pressure_coeff, var=self.correction) \
            - fp.ImplicitSourceTerm(coeff=self.pressure_pin, var=self.correction) \
            == self.pressure_source

    def momentum(self, inputs: MomentumInputs) -> list:
        """[(matrix, rhs)] of each velocity component, as FiPy builds them."""
        self.viscous_coeff.value = inputs.face_viscosity
        self.flux_velocity.value = inputs.face_mass_flux[None, :] * self.normals
        self.flux_divergence.value = inputs.cell_flux_divergence
        self.pin.value = inputs.cell_pin
        systems = []
        for a in range(self.dim):
            self.pin_target[a].value = inputs.cell_pin_velocity[:, a]
            self.pressure_gradient[a].value = inputs.cell_pressure_gradient[:, a]
            self.inflow[a].value = inputs.face_inflow[:, a]
            self.velocity[a].value = inputs.cell_velocity_old[:, a]
            self.velocity[a].updateOld()
            systems.append(_system(self.momentum_eq[a], self.velocity[a], inputs.dt))
        return systems

    def pressure(self, inputs: PressureInputs):
        """(matrix, rhs) of the pressure correction, as FiPy builds it."""
        self.correction_bc.value = np.nan_to_num(inputs.face_boundary)
        self.pressure_coeff.value = inputs.face_coefficient
        self.pressure_pin.value = inputs.cell_pin
        self.pressure_source.value = inputs.cell_source
        self.correction.value = 0.0
        return _system(self.pressure_eq, self.correction, None)
