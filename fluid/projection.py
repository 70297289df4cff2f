"""Incremental pressure-correction (projection) step on the immersed-boundary grid, with FiPy.

One step t -> t + dt, given the liquid geometry at t + dt (Van Kan 1986 incremental scheme
with Rhie-Chow face velocities on FiPy's collocated grid):

1. momentum predictor, implicit (FiPy ``TransientTerm`` + upwind ``ConvectionTerm`` with the
   face fluxes of step n + ``DiffusionTerm``), old reduced-pressure gradient explicit::

       rho (u* - u^n)/dt + div(rho F u*) - rho (div F) u* = div(mu grad u*) - grad p^n

   [- mu u_r / r^2 on the axisymmetric grid]. Cells whose centre is outside the liquid are
   pinned to the wall velocity; a face between a liquid-centre cell P and a wall-centre cell
   carries mu / theta, theta = phi_P / (phi_P - phi_N) the wall's fractional distance from P
   (Shortley-Weller immersed Dirichlet condition, second order for the no-slip wall);
2. face velocities u*_f = avg(u* + dt/rho grad_c p^n) - dt/rho grad_f p^n (Rhie-Chow);
3. pressure correction on the cut cells (FiPy ``DiffusionTerm`` with face coefficient
   beta dt/rho, beta = wetted face fraction)::

       sum_f beta A (u*_f - dt/rho grad_f dp) + (alpha^{n+1} - alpha^n) V / dt = 0

   i.e. every cell's liquid volume changes by exactly the flux through its wetted faces:
   moving-boundary face fluxes, no interface velocity needed for continuity;
4. u_f = u*_f - dt/rho grad_f dp, u_c = u* - dt/rho grad_c dp, p^{n+1} = p^n + dp, where
   grad_c is the beta-weighted average of the face gradients on each axis (exact for the
   linear pressure of a uniformly accelerated liquid).
"""
from __future__ import annotations

import time as _time
from dataclasses import dataclass, replace

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components

from . import assembly as _assembly  # noqa: F401  (registers the "direct" assembly)
from . import terms as _terms  # noqa: F401  (registers the "fipy" assembly)
from .geometry import Geometry
from .linear import make_solver, pressure_solver_for, single_blas_thread, warn_if_unconverged
from .model import FluidModel, FluidState
from .steppers import STEPPERS, register_stepper
from .systems import ASSEMBLIES, MomentumInputs, PressureInputs
from .time_schemes import TIME_SCHEMES

#: smallest wall distance fraction used by the immersed viscous condition
THETA_MIN = 0.05
#: pin strength for wall-centred cells, times the stiffest diagonal term (rho/dt or the
#: immersed-wall viscous coefficient mu/(theta_min h^2)). They start the solve at the wall
#: velocity, so a moderate pin holds them there to ~1/PIN_FACTOR of their coupling while
#: keeping the momentum system well scaled for Krylov solvers (a huge pin would dominate the
#: right-hand side and stop the iteration before the liquid rows converge)
PIN_FACTOR = 1e3
#: relative residual (FiPy's RHS criterion) and iteration cap of the momentum solves
MOMENTUM_TOLERANCE = 1e-10
MOMENTUM_ITERATIONS = 1000
#: iteration cap of the pressure solve (its tolerance is the model's)
PRESSURE_ITERATIONS = 2000


@dataclass(frozen=True)
class StepReport:
    """volume_mismatch: interface volume rate minus net port inflow (m^3/s) that the
    pressure equation could not honour (flow ports only; removed uniformly, should be ~0);
    divergence: largest |cell continuity residual| / cell volume (1/s) after the step;
    seconds: wall time of (geometry is the caller's) the momentum predictor (with what
    it needs: old pressure gradients, port values) and the rest (face velocities, pressure
    correction, update);
    momentum_iterations: most iterations of the component solves; pressure_iterations and
    pressure_residual: of the pressure solve (relative residual, FiPy's RHS criterion)."""

    volume_mismatch: float
    divergence: float
    seconds_momentum: float
    seconds_pressure: float
    momentum_iterations: int = 0
    pressure_iterations: int = 0
    pressure_residual: float = 0.0


class ProjectionOperators:
    """Port faces, the assembly of the two linear systems and their solvers for one model,
    built once (see :mod:`fluid.systems`)."""

    def __init__(self, model: FluidModel):
        self.model = model
        grid = model.grid
        self.flow_faces = np.zeros(grid.n_faces, dtype=bool)
        self.pressure_faces = np.zeros(grid.n_faces, dtype=bool)
        self.port_faces = []
        for port in model.ports:
            faces = grid.boundary_faces(port.side)
            self.port_faces.append(faces)
            (self.flow_faces if port.kind == "flow" else self.pressure_faces)[faces] = True
        if model.interface_condition not in STEPPERS:
            raise ValueError(f"unknown interface condition {model.interface_condition!r}; "
                             f"allowed: {sorted(STEPPERS)}")
        if model.time_scheme not in TIME_SCHEMES:
            raise ValueError(f"unknown time scheme {model.time_scheme!r}; allowed: "
                             f"{sorted(TIME_SCHEMES)}")
        if model.interface_condition != "wall" and model.time_scheme != "euler":
            raise ValueError(f"time scheme {model.time_scheme!r} is the moving wall's; the "
                             f"{model.interface_condition!r} interface's step has its own "
                             f"(use 'euler')")
        if model.assembly not in ASSEMBLIES:
            raise ValueError(f"unknown assembly {model.assembly!r}; allowed: "
                             f"{sorted(ASSEMBLIES)}")
        self.assembly = ASSEMBLIES[model.assembly](model, self.flow_faces, self.pressure_faces)
        self.normals = np.asarray(grid.mesh.faceNormals).T.copy()  # (n_faces, dim)
        self.momentum_solver = make_solver(model.momentum_solver, MOMENTUM_TOLERANCE,
                                           MOMENTUM_ITERATIONS, symmetric=False)
        name = model.pressure_solver
        if name == "auto":
            name = pressure_solver_for(grid.n_cells, grid.axisymmetric)
        self.pressure_solver_name = name
        self.pressure_solver = make_solver(name, model.pressure_tolerance, PRESSURE_ITERATIONS,
                                           symmetric=True)


# ---------------------------------------------------------------- discrete operators (numpy)

def face_gradient(model: FluidModel, cell_values: np.ndarray, boundary: np.ndarray) -> np.ndarray:
    """Normal derivative (n_faces,) along FiPy's face normals; ``boundary`` (n_faces,) holds
    Dirichlet values on exterior faces (NaN: no condition, gradient 0)."""
    g = model.grid
    p_cell, n_cell = g.face_cells
    out = np.zeros(g.n_faces)
    inner = n_cell >= 0
    out[inner] = (cell_values[n_cell[inner]] - cell_values[p_cell[inner]]) / g.face_distance[inner]
    bc = ~inner & np.isfinite(boundary)
    out[bc] = (boundary[bc] - cell_values[p_cell[bc]]) / g.face_distance[bc]
    return out


def gradient_weights(model: FluidModel, geometry: Geometry) -> np.ndarray:
    """(n_faces,) weight of each face in the cell-gradient reconstruction: wetted fraction
    times the smaller liquid fraction of the two cells, so that a face into a sliver cell
    the interface has just uncovered counts in proportion to the sliver (the reconstruction
    then varies continuously as the interface crosses grid lines)."""
    g = model.grid
    alpha = geometry.cell_fraction
    p_cell, n_cell = g.face_cells
    smaller = alpha[p_cell].copy()
    inner = n_cell >= 0
    smaller[inner] = np.minimum(smaller[inner], alpha[n_cell[inner]])
    return geometry.face_fraction * smaller


def cell_gradient(model: FluidModel, face_grad: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """(n_cells, dim) cell gradient: per axis, the weighted mean (weights ``beta``, see
    :func:`gradient_weights`) of the face normal gradients of the cell's two faces on that
    axis."""
    g = model.grid
    along = face_grad * g.face_sign * beta
    first, second, inner = _face_slots(g)
    size = g.n_cells * g.dim
    num = np.bincount(first, along, size) + np.bincount(second, along[inner], size)
    den = np.bincount(first, beta, size) + np.bincount(second, beta[inner], size)
    num, den = num.reshape(g.n_cells, g.dim), den.reshape(g.n_cells, g.dim)
    return np.divide(num, den, out=np.zeros_like(num), where=den > 0)


def _face_slots(g):
    """Per face, the slot (cell, axis) of its first cell in a C-ordered (n_cells, dim)
    array; the same for the second cell of the inner faces; the inner-face mask."""
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    return p_cell * g.dim + g.face_axis, n_cell[inner] * g.dim + g.face_axis[inner], inner


def net_outflow(model: FluidModel, face_flux: np.ndarray) -> np.ndarray:
    """(n_cells,) sum of a face flux (FiPy m^3/s per radian on the axisymmetric grid, along
    FiPy's normals) out of each cell."""
    g = model.grid
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    return np.bincount(p_cell, face_flux, g.n_cells) - \
        np.bincount(n_cell[inner], face_flux[inner], g.n_cells)


def interpolate_to_faces(model: FluidModel, cell_vec: np.ndarray,
                         fluid: np.ndarray) -> np.ndarray:
    """(n_faces,) normal component (along FiPy's normal) of cell vectors (n_cells, dim)
    averaged onto the faces over the adjacent cells whose centre is in the liquid (``fluid``;
    both cells if neither is): a wall-centre cell holds the wall velocity for the no-slip
    condition, not the liquid's, and must not be averaged in. Exterior faces take the
    adjacent cell's value."""
    g = model.grid
    p_cell, n_cell = g.face_cells
    comp = cell_vec[p_cell, g.face_axis]
    inner = n_cell >= 0
    a, b = p_cell[inner], n_cell[inner]
    wa = fluid[a].astype(float)
    wb = fluid[b].astype(float)
    neither = (wa + wb) == 0
    wa[neither] = wb[neither] = 1.0
    comp[inner] = (wa * comp[inner] + wb * cell_vec[b, g.face_axis[inner]]) / (wa + wb)
    return comp * g.face_sign


def viscous_face_coefficient(model: FluidModel, geometry: Geometry) -> np.ndarray:
    """mu / theta on faces between a liquid-centre and a wall-centre cell, mu elsewhere."""
    g = model.grid
    mu = np.full(g.n_faces, model.viscosity)
    p_cell, n_cell = g.face_cells
    inner = np.nonzero(n_cell >= 0)[0]
    phi_p = geometry.centre_level[p_cell[inner]]
    phi_n = geometry.centre_level[n_cell[inner]]
    cut = (phi_p < 0) != (phi_n < 0)
    fluid_phi = np.where(phi_p < 0, phi_p, phi_n)[cut]
    wall_phi = np.where(phi_p < 0, phi_n, phi_p)[cut]
    theta = fluid_phi / (fluid_phi - np.minimum(wall_phi, 1e6))
    mu[inner[cut]] = model.viscosity / np.maximum(theta, THETA_MIN)
    return mu


def port_values(model: FluidModel, ops: ProjectionOperators, time: float):
    """Reduced pressure (Pa) on pressure-port faces at ``time``: (n_faces,), NaN elsewhere."""
    g = model.grid
    reduced = np.full(g.n_faces, np.nan)
    points = model.grid_points(g.face_centre)
    for port, faces in zip(model.ports, ops.port_faces):
        if port.kind == "pressure":
            reduced[faces] = port.at(time) - model.body_potential(points[faces], time)
    return reduced


def _flow_port_velocity(model: FluidModel, ops: ProjectionOperators, beta: np.ndarray,
                        time: float) -> np.ndarray:
    """(n_faces,) prescribed face velocity along FiPy's (outward) normal on flow ports."""
    g = model.grid
    u = np.zeros(g.n_faces)
    for port, faces in zip(model.ports, ops.port_faces):
        if port.kind != "flow":
            continue
        open_area = (beta[faces] * g.face_area[faces]).sum() * g.volume_factor()
        if open_area <= 0:
            raise ValueError(f"the {port.side} port has no wetted face on this grid")
        u[faces] = -port.at(time) / open_area  # inflow = against the outward normal
    return u


# ---------------------------------------------------------------- the step

def initial_state(model: FluidModel, ops: ProjectionOperators, geometry: Geometry,
                  time: float = 0.0) -> FluidState:
    """Liquid at rest (tank frame) in hydrostatic equilibrium: p_red uniform, given by the
    stepper (the wall's: the first pressure port's value, 0 with flow ports only)."""
    g = model.grid
    pressure = STEPPERS[model.interface_condition].initial_pressure(model, ops, geometry, time)
    return FluidState(time=time, cell_velocity=np.zeros((g.n_cells, g.dim)),
                      face_velocity=np.zeros(g.n_faces), pressure=pressure, geometry=geometry)


def step(model: FluidModel, ops: ProjectionOperators, state: FluidState, geometry: Geometry,
         dt: float) -> tuple[FluidState, StepReport]:
    """Advance ``state`` by ``dt`` (s) to the liquid region ``geometry`` (at t + dt), by the
    stepper of the model's interface condition."""
    if not dt > 0:
        raise ValueError(f"time step must be > 0 s, got {dt}")
    with single_blas_thread():
        return STEPPERS[model.interface_condition].step(model, ops, state, geometry, dt)


def _known(model, ops, state, geometry, dt):
    """What the step knows before it solves: wall velocities (n_cells, dim) m/s, old port
    pressures, old face and cell pressure gradients, gradient weights, port inflow at
    t + dt (see :func:`step`)."""
    g = model.grid
    wall = geometry.wall_velocity[:, [0, 2]] if g.axisymmetric else geometry.wall_velocity
    p_bc_old = port_values(model, ops, state.time)
    grad_f_old = face_gradient(model, state.pressure, p_bc_old)
    weights = gradient_weights(model, geometry)
    grad_c_old = cell_gradient(model, grad_f_old, weights)
    u_flow = _flow_port_velocity(model, ops, geometry.face_fraction, state.time + dt)
    return wall, p_bc_old, grad_f_old, weights, grad_c_old, u_flow


def step_inputs(model: FluidModel, ops: ProjectionOperators, state: FluidState,
                geometry: Geometry, dt: float) -> tuple[MomentumInputs, PressureInputs]:
    """The inputs of the two linear systems that :func:`step` fills for this step (the
    pressure inputs after the momentum predictor has been solved)."""
    wall, p_bc_old, grad_f_old, _, grad_c_old, u_flow = _known(model, ops, state, geometry, dt)
    momentum = momentum_inputs(model, ops, state, geometry, wall, grad_c_old, u_flow, dt)
    u_star, _ = _momentum_predictor(ops, geometry, wall, momentum)
    u_face = _face_predictor(model, ops, state, geometry, wall, u_star, grad_c_old,
                             grad_f_old, u_flow, dt)
    dp_ports = port_values(model, ops, state.time + dt) - p_bc_old
    pressure, *_ = pressure_inputs(model, ops, state, geometry, u_face, dp_ports, dt)
    return momentum, pressure


def _port_level(model, ops, geometry, time):
    """(n_cells,) the first pressure port's value (0 with flow ports only), uniform."""
    bc = port_values(model, ops, time)
    level = 0.0
    for port, faces in zip(model.ports, ops.port_faces):
        if port.kind == "pressure":
            level = float(np.mean(bc[faces]))
            break
    return np.full(model.grid.n_cells, level)


@register_stepper("wall", _port_level)
def _step(model, ops, state, geometry, dt):
    """The step of the module doc, its time derivatives by the model's time scheme
    (:mod:`fluid.time_schemes`: the old velocities and cell fractions and the step dt_eff
    that every part below sees; the port values and the new time are the real step's)."""
    tic = _time.perf_counter()
    g = model.grid
    rho = model.density
    t1 = state.time + dt
    beta = geometry.face_fraction
    fluid = geometry.fluid_centre
    old = TIME_SCHEMES[model.time_scheme](state, dt)
    start, h = old.state, old.dt
    wall, p_bc_old, grad_f_old, weights, grad_c_old, u_flow = _known(model, ops, start,
                                                                     geometry, dt)
    p_bc_new = port_values(model, ops, t1)
    u_star, momentum_iterations = _momentum_predictor(
        ops, geometry, wall,
        momentum_inputs(model, ops, start, geometry, wall, grad_c_old, u_flow, h))
    toc_momentum = _time.perf_counter() - tic

    tic = _time.perf_counter()
    u_face = _face_predictor(model, ops, start, geometry, wall, u_star, grad_c_old,
                             grad_f_old, u_flow, h)
    dp, dvol, coupled, mismatch, info = _pressure_correction(
        model, ops, start, geometry, u_face, p_bc_new - p_bc_old, h)

    dp_bc = np.where(ops.pressure_faces, p_bc_new - p_bc_old, np.nan)
    grad_f = face_gradient(model, dp, dp_bc)
    u_face_new = u_face - h / rho * grad_f
    u_face_new[ops.flow_faces] = u_flow[ops.flow_faces]
    u_face_new[beta == 0] = 0.0
    u_cell = u_star - h / rho * cell_gradient(model, grad_f, weights)
    u_cell[~fluid] = wall[~fluid]
    residual = net_outflow(model, beta * g.face_area * u_face_new) + dvol / h
    divergence = float(np.max(np.abs(residual[coupled]) / g.cell_volume[coupled])) \
        if coupled.any() else 0.0
    pressure = _extend_pressure(model, state.pressure + dp, coupled, p_bc_new, weights)
    new = FluidState(time=t1, cell_velocity=u_cell, face_velocity=u_face_new,
                     pressure=pressure, geometry=geometry,
                     previous=replace(state, previous=None))
    toc_pressure = _time.perf_counter() - tic
    return new, StepReport(mismatch, divergence, toc_momentum, toc_pressure,
                           momentum_iterations, info.iterations, info.residual)


def momentum_inputs(model, ops, state, geometry, wall, grad_c_old, u_flow, dt):
    """What fills the momentum systems of step 1 (see :class:`fluid.systems.MomentumInputs`)."""
    g = model.grid
    rho = model.density
    fluid = geometry.fluid_centre
    flux_old = state.face_velocity * geometry.face_fraction
    stiffest = max(rho / dt, model.viscosity / (THETA_MIN * g.spacing**2))
    start = np.where(fluid[:, None], state.cell_velocity, wall)
    return MomentumInputs(
        dt=dt, face_viscosity=viscous_face_coefficient(model, geometry),
        face_mass_flux=rho * flux_old,
        cell_flux_divergence=rho * net_outflow(model, flux_old * g.face_area) / g.cell_volume,
        cell_pin=np.where(fluid, 0.0, PIN_FACTOR * stiffest), cell_pin_velocity=wall,
        cell_pressure_gradient=grad_c_old, face_inflow=u_flow[:, None] * ops.normals,
        cell_velocity_old=start)


def _momentum_predictor(ops, geometry, wall, inputs: MomentumInputs):
    """Step 1 from its inputs (:func:`momentum_inputs`): u* (n_cells, dim) m/s, wall-centred
    cells at the wall velocity; and the largest number of iterations of the component
    solves."""
    fluid = geometry.fluid_centre
    start = inputs.cell_velocity_old
    u_star = np.empty_like(start)
    iterations = 0
    for a, (matrix, rhs) in enumerate(ops.assembly.momentum(inputs)):
        u_star[:, a], info = ops.momentum_solver.solve(matrix, rhs, start[:, a])
        warn_if_unconverged(info, f"momentum component {a}")
        iterations = max(iterations, info.iterations)
    u_star[~fluid] = wall[~fluid]
    return u_star, iterations


def wall_ring(model: FluidModel, geometry: Geometry) -> np.ndarray:
    """(n_faces,) bool: the wetted inner faces between two wall-centred cells (the ring of cut
    cells along an immersed wall), which have no momentum equation of their own."""
    p_cell, n_cell = model.grid.face_cells
    fluid = geometry.fluid_centre
    return (n_cell >= 0) & (geometry.face_fraction > 0) & ~fluid[p_cell] & \
        ~fluid[np.maximum(n_cell, 0)]


def ring_drag_rate(model: FluidModel, ring_fraction: np.ndarray) -> np.ndarray:
    """(k,) 1/s: nu / l^2, the rate at which the wall's shear holds back a ring face of wetted
    fraction ``ring_fraction`` (k,) across a layer l = max(beta / 2, THETA_MIN) h."""
    layer = np.maximum(0.5 * ring_fraction, THETA_MIN) * model.grid.spacing
    return model.viscosity / (model.density * layer**2)


def _memory_faces(model: FluidModel, state: FluidState, geometry: Geometry) -> np.ndarray:
    """(n_faces,) bool: the faces besides the wall's ring that keep their own history in the
    moving-wall step: with ``face_memory = "every-face"`` every inner face wetted at the
    step's start and end (none with ``"ring"``, and none for the free surface's step, which
    keeps its own, :mod:`fluid.free_surface`).

    Why: Rhie-Chow's face velocity, re-interpolated from the cells each step, differs from
    the face's own by dt/rho times the difference of the interpolated cell gradient and the
    face gradient of the pressure, and that difference is dissipated: an inviscid slosh mode
    whose pressure bends sharply at the cut cells (the diaphragm's) is damped at a zeta that
    falls only with the step (docs/notes/second-order-window.md). A face that keeps its
    history instead evolves as a staggered grid's, u_f^{n+1} = u_f^n - dt/rho grad_f p^{n+1}
    without viscosity and convection (Choi 1999; the free surface's step does the same)."""
    if model.face_memory == "ring" or model.interface_condition != "wall":
        return np.zeros(model.grid.n_faces, dtype=bool)
    n_cell = model.grid.face_cells[1]
    return (n_cell >= 0) & (geometry.face_fraction > 0) & (state.geometry.face_fraction > 0)


def _face_predictor(model, ops, state, geometry, wall, u_star, grad_c_old, grad_f_old, u_flow,
                    dt):
    """Step 2: Rhie-Chow face velocities u*_f (n_faces,) m/s along FiPy's normals."""
    g = model.grid
    rho = model.density
    beta = geometry.face_fraction
    fluid = geometry.fluid_centre
    u_tilde = u_star + np.where(fluid[:, None], dt / rho * grad_c_old, 0.0)
    u_face = interpolate_to_faces(model, u_tilde, fluid) - dt / rho * grad_f_old
    # A wetted face between two wall-centred cells (the ring of cut cells along an immersed
    # wall) has no momentum equation of its own: it keeps its own old velocity (inertia,
    # Choi 1999's memory term) and the wall holds its liquid back by the shear of a layer
    # beta h / 2 thick (implicit). Without the memory the ring restarts from the wall velocity
    # every step and the liquid column behaves as if an O(h) heavier.
    p_cell, n_cell = g.face_cells
    ring = wall_ring(model, geometry) & (state.geometry.face_fraction > 0)
    keep = _memory_faces(model, state, geometry) | ring
    old_cells = np.where(fluid[:, None], state.cell_velocity, wall)
    u_face[keep] += (state.face_velocity - interpolate_to_faces(model, old_cells, fluid))[keep]
    if model.viscosity > 0 and ring.any():
        u_wall = interpolate_to_faces(model, wall, fluid)[ring]
        u_face[ring] = u_wall + (u_face[ring] - u_wall) / \
            (1.0 + dt * ring_drag_rate(model, beta[ring]))
    exterior = n_cell < 0
    u_face[exterior & ~ops.pressure_faces] = 0.0
    u_face[ops.flow_faces] = u_flow[ops.flow_faces]
    return u_face


def pressure_inputs(model, ops, state, geometry, u_face, dp_ports, dt):
    """What fills the pressure system of step 3 (:class:`fluid.systems.PressureInputs`); also
    the cells' liquid-volume changes dvol (FiPy m^3), the mask of cells in the pressure
    system and the volume mismatch (m^3/s)."""
    g = model.grid
    rho = model.density
    area_open = geometry.face_fraction * g.face_area
    dvol = (geometry.cell_fraction - state.geometry.cell_fraction) * g.cell_volume
    coupled = (geometry.cell_fraction > 0) | (_open_area(model, area_open) > 0)
    dvol = _merge_dead_cells(model, dvol, coupled, geometry.cell_fraction)
    source = net_outflow(model, area_open * u_face) + dvol / dt  # FiPy m^3/s per cell
    pin_scale = dt / rho * 2 * g.dim / g.spacing**2
    pressure_pin = np.where(coupled, 0.0, pin_scale)
    region = _liquid_regions(model, geometry, coupled)
    if not ops.pressure_faces.any():
        gauge = _gauge_cell(model, ops, geometry)
        pressure_pin[gauge] = pin_scale
        anchored = region[[gauge]]
    else:
        wet_port = ops.pressure_faces & (geometry.face_fraction > 0)
        anchored = np.unique(region[g.face_cells[0][wet_port]])
    mismatch = _balance_regions(model, geometry, region, anchored, source, pressure_pin,
                                pin_scale, flow_only=not ops.pressure_faces.any())
    inputs = PressureInputs(face_coefficient=geometry.face_fraction * dt / rho,
                            cell_pin=pressure_pin, cell_source=source / g.cell_volume,
                            face_boundary=dp_ports)
    return inputs, dvol, coupled, mismatch


def _pressure_correction(model, ops, state, geometry, u_face, dp_ports, dt):
    """Step 3: the correction dp (n_cells,) Pa; also dvol, coupled and the mismatch (see
    :func:`pressure_inputs`) and the solve's :class:`fluid.linear.SolveInfo`."""
    inputs, dvol, coupled, mismatch = pressure_inputs(model, ops, state, geometry, u_face,
                                                      dp_ports, dt)
    matrix, rhs = ops.assembly.pressure(inputs)
    # FiPy's sign convention makes the matrix negative definite: solve with -A, -b
    dp, info = ops.pressure_solver.solve(-matrix, -rhs, np.zeros(model.grid.n_cells))
    warn_if_unconverged(info, "pressure correction")
    return dp, dvol, coupled, mismatch, info


#: layers of cells outside the liquid that get an extrapolated pressure after each step
GHOST_LAYERS = 2


def _extend_pressure(model: FluidModel, pressure: np.ndarray, coupled: np.ndarray,
                     boundary: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Give the cells next to the liquid (``GHOST_LAYERS`` deep) the pressure extrapolated
    linearly from their liquid neighbours, so that a cell the interface uncovers next step
    starts from a consistent value (a stale value would enter the old-pressure gradient of
    the incremental scheme and make the fluid's response jump as the interface crosses a
    grid line)."""
    g = model.grid
    grad = cell_gradient(model, face_gradient(model, pressure, boundary), weights)
    valid = coupled.copy()
    out = pressure.copy()
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    a, b = p_cell[inner], n_cell[inner]
    n = g.n_cells
    for _ in range(GHOST_LAYERS):
        total = np.zeros(n)
        count = np.zeros(n)
        for src, dst in ((a, b), (b, a)):
            use = valid[src] & ~valid[dst]
            s_, d_ = src[use], dst[use]
            value = out[s_] + np.einsum("ij,ij->i", grad[s_],
                                        g.cell_centre[d_] - g.cell_centre[s_])
            total += np.bincount(d_, value, n)
            count += np.bincount(d_, minlength=n)
        new = count > 0
        if not new.any():
            break
        out[new] = total[new] / count[new]
        # the new layer extrapolates with its neighbours' gradient
        grad_new = np.zeros((n, g.dim))
        cnt = np.zeros(n)
        for src, dst in ((a, b), (b, a)):
            use = valid[src] & new[dst]
            for axis in range(g.dim):
                grad_new[:, axis] += np.bincount(dst[use], grad[src[use], axis], n)
            cnt += np.bincount(dst[use], minlength=n)
        grad[new] = grad_new[new] / cnt[new, None]
        valid |= new
    return out


def _merge_dead_cells(model: FluidModel, dvol: np.ndarray, coupled: np.ndarray,
                      alpha: np.ndarray) -> np.ndarray:
    """Move the volume change of cells that left the liquid this step (no wetted face left)
    to their wettest coupled neighbour, so that no liquid volume is lost from the balance."""
    dead = np.nonzero(~coupled & (dvol != 0))[0]
    if len(dead) == 0:
        return dvol
    g = model.grid
    dvol = dvol.copy()
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    pairs = np.concatenate([np.stack([p_cell[inner], n_cell[inner]]),
                            np.stack([n_cell[inner], p_cell[inner]])], axis=1)
    order = np.argsort(pairs[0], kind="stable")
    src, dst = pairs[0][order], pairs[1][order]
    start = np.searchsorted(src, dead)
    stop = np.searchsorted(src, dead, side="right")
    for cell, a, b in zip(dead, start, stop):
        nbrs = dst[a:b]
        nbrs = nbrs[coupled[nbrs]]
        if len(nbrs):
            dvol[nbrs[np.argmax(alpha[nbrs])]] += dvol[cell]
        dvol[cell] = 0.0
    return dvol


def _open_area(model: FluidModel, area_open: np.ndarray) -> np.ndarray:
    """(n_cells,) total wetted face area of each cell."""
    g = model.grid
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    return np.bincount(p_cell, weights=area_open, minlength=g.n_cells) + \
        np.bincount(n_cell[inner], weights=area_open[inner], minlength=g.n_cells)


def _liquid_regions(model: FluidModel, geometry: Geometry, coupled: np.ndarray) -> np.ndarray:
    """(n_cells,) label of the connected liquid region of each coupled cell (cells joined by
    wetted inner faces), -1 for the others. A folded membrane can trap liquid in pockets
    that no wetted face joins to the rest."""
    g = model.grid
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    wet = np.zeros(g.n_faces, dtype=bool)
    wet[inner] = ((geometry.face_fraction[inner] > 0) & coupled[p_cell[inner]]
                  & coupled[n_cell[inner]])
    adjacency = sparse.coo_matrix((np.ones(int(wet.sum())), (p_cell[wet], n_cell[wet])),
                                  shape=(g.n_cells, g.n_cells))
    _, labels = connected_components(adjacency, directed=False)
    return np.where(coupled, labels, -1)


def _balance_regions(model: FluidModel, geometry: Geometry, region: np.ndarray,
                     anchored: np.ndarray, source: np.ndarray, pressure_pin: np.ndarray,
                     pin_scale: float, flow_only: bool) -> float:
    """Make the pressure system solvable region by region (in place on ``source`` and
    ``pressure_pin``): a region without a pressure port (with flow ports only: every region)
    cannot change its liquid volume, so its net source is removed in proportion to the cell
    fractions; a region that is neither the gauge's nor a pressure port's gets one pinned
    cell (its wettest). Returns the removed volume rate (m^3/s), the volume mismatch."""
    g = model.grid
    coupled = region >= 0
    labels = region[coupled]
    n = int(labels.max()) + 1 if labels.size else 0
    weight = geometry.cell_fraction * g.cell_volume
    free = np.bincount(labels, minlength=n) > 0
    free[anchored[anchored >= 0]] = False
    balance = np.ones(n, dtype=bool) if flow_only else free
    totals = np.bincount(labels, weights=source[coupled], minlength=n)
    weights = np.bincount(labels, weights=weight[coupled], minlength=n)
    share = np.where(balance & (weights > 0), totals / np.where(weights > 0, weights, 1.0),
                     0.0)
    source[coupled] -= share[labels] * weight[coupled]
    cells = np.flatnonzero(coupled)
    for r in np.flatnonzero(free):
        members = cells[labels == r]
        pressure_pin[members[np.argmax(weight[members])]] = pin_scale
    return float((totals * (balance & (weights > 0))).sum() * g.volume_factor())


def _gauge_cell(model: FluidModel, ops: ProjectionOperators, geometry: Geometry) -> int:
    """Cell whose reduced pressure stays 0 with flow ports only: next to the first port."""
    g = model.grid
    for faces in ops.port_faces:
        cells = g.face_cells[0][faces & (geometry.face_fraction > 0)]
        if len(cells):
            return int(cells[np.argmax(geometry.cell_fraction[cells])])
    return int(np.argmax(geometry.cell_fraction))
