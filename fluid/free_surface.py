"""The liquid step with a free surface: the interface is the liquid's surface at the gas pressure.

The interface of :mod:`fluid.projection` is a moving wall: the caller gives its motion and
reads back the pressure on it (Dirichlet-Neumann coupling). A surface that carries no pressure
jump (a free surface, or a limp, slack membrane lying on one) is the opposite: the liquid is
told the pressure there and the surface moves with the liquid (kinematic condition), so the
caller gives the surface's position and reads back the liquid's velocity at it. A massless
membrane coupled the first way has an infinite added-mass ratio and no partitioned iteration
converges (Causin, Gerbeau & Nobile 2005); coupled this way there is nothing to iterate.

The step is the projection step of :mod:`fluid.projection` (same predictor, same Rhie-Chow
faces, same cut cells at the tank wall) with three differences at the surface:

* the pressure unknowns are the cells the container wets whose centre lies on the liquid side
  of the surface (interface level d < 0); the surface is a Dirichlet boundary of the
  pressure, p = p_gas (gauge 0), i.e. reduced p_red = -rho b(t) . x_s, imposed on each face
  between a liquid-centre cell P and a gas-centre cell G at the crossing
  x_s = x_P + theta (x_G - x_P), theta = d_P / (d_P - d_G) (Gibou, Fedkiw, Cheng & Kang 2002:
  the ghost-fluid Dirichlet condition, second order); the distance in the gradient is at
  least ``THETA_MIN`` h, the value is taken at the true crossing (clipping the crossing
  itself would freeze the surface pressure of columns whose level is within 0.05 h above a
  centre plane, and such a surface loses its restoring force);
* faces and cells keep the container's fractions (the surface is not a wall): the liquid
  flows through the surface faces, and the caller moves the surface with the liquid; except
  that a horizontal face of the liquid's top layer is open only as deep as the liquid is
  (its wetted fraction below the surface, plus that of the face above it when that one
  touches no liquid cell): the lateral flow near the surface, where a sloshing mode's
  velocity is largest, sees the liquid's depth and not the staircase of cell centres (with
  the container's full faces the first mode's frequency errs by up to +-6 % on 16^3 cells,
  by where the level sits between two centre planes);
* no viscous stress crosses the surface (mu = 0 on its faces: stress-free to first order),
  and gas-centre cells hold the surface velocity (the caller's node velocities: the liquid's,
  extended along the normal) as the predictor's pin;
* a face's velocity keeps its own history (Choi 1999's memory term on every face, not only
  on the wall's ring): u*_f = u_f^n + [interpolated change of the cell velocities by
  everything but the pressure] - dt/rho grad_f p^n. Without viscosity and convection the
  faces then evolve as a staggered grid's, u_f^{n+1} = u_f^n - dt/rho grad_f p^{n+1}, which
  with the surface moved by the face fluxes of step n conserves the discrete energy
  (Stormer-Verlet pairing); Rhie-Chow's re-interpolation from the cells each step damps a
  sloshing mode at zeta ~ 0.01. A face the surface opens or closes as it passes a centre
  plane hands its flux to the face below it (:func:`_carry_over`).

The incremental pressure keeps the surface condition in both parts: the old gradient uses
p_s(t^n) at the new surface, the correction dp_s = p_s(t^{n+1}) - p_s(t^n) there.
"""
from __future__ import annotations

import time as _time
from dataclasses import dataclass, replace

import numpy as np

from .geometry import Geometry
from .linear import warn_if_unconverged
from .model import FluidModel, FluidState
from .projection import (THETA_MIN, GHOST_LAYERS, ProjectionOperators, StepReport,
                         _balance_regions, _extend_pressure, _face_predictor,
                         _flow_port_velocity, _liquid_regions, _momentum_predictor,
                         _open_area, cell_gradient, face_gradient, interpolate_to_faces,
                         momentum_inputs, net_outflow, port_values)
from .steppers import register_stepper
from .systems import PressureInputs


@dataclass(frozen=True)
class Surface:
    """The free surface on the grid at one instant: ``wet`` (n_cells,) pressure unknowns;
    ``faces`` (k,) the faces between a wet cell and a gas-centre cell, ``cell`` (k,) the
    wet cell of each, ``first`` (k,) bool: it is the face's first cell (FiPy's normal points
    away from it), ``theta`` (k,) the surface's fractional distance from its centre (at
    least ``THETA_MIN``), ``point`` (k, 3) m the crossing; ``view``: the geometry as the shared parts of the step
    see it (container fractions on the faces and cells of the liquid, surface cells pinned
    to the surface velocity)."""

    wet: np.ndarray
    faces: np.ndarray
    cell: np.ndarray
    first: np.ndarray
    theta: np.ndarray
    point: np.ndarray
    view: Geometry

    def reduced_pressure(self, model: FluidModel, time: float) -> np.ndarray:
        """(k,) Pa: the gas pressure (gauge 0) as reduced pressure at the crossings."""
        return -model.body_potential(self.point, time)

    def conductance(self, model: FluidModel) -> np.ndarray:
        """(k,) m: wetted area over the distance from the wet centre to the surface."""
        g = model.grid
        return self.view.face_fraction[self.faces] * g.face_area[self.faces] / \
            (self.theta * g.face_distance[self.faces])


def surface_of(model: FluidModel, geometry: Geometry) -> Surface:
    """The :class:`Surface` of a geometry computed with an interface."""
    g = model.grid
    if geometry.interface_level is None:
        raise ValueError("a free-surface step needs a geometry with the interface level")
    d = geometry.interface_level
    beta_c = geometry.container_face_fraction
    alpha_c = geometry.container_cell_fraction
    area = beta_c * g.face_area
    wet = (d < 0) & ((alpha_c > 0) | (_open_area(model, area) > 0))
    p_cell, n_cell = g.face_cells
    inner = np.flatnonzero(n_cell >= 0)
    a, b = p_cell[inner], n_cell[inner]
    cross = (beta_c[inner] > 0) & (wet[a] != wet[b]) & ((d[a] >= 0) | (d[b] >= 0))
    faces = inner[cross]
    first = wet[a[cross]]
    cell = np.where(first, a[cross], b[cross])
    gas = np.where(first, b[cross], a[cross])
    exact = np.clip(d[cell] / (d[cell] - d[gas]), 0.0, 1.0)
    theta = np.maximum(exact, THETA_MIN)
    centre = model.grid_points(g.cell_centre)
    point = centre[cell] + exact[:, None] * (centre[gas] - centre[cell])
    # the faces of the liquid (a wet cell on at least one side) at the container's fraction,
    # the horizontal ones as deep as the liquid is
    touches = wet[p_cell].copy()
    touches[inner] |= wet[n_cell[inner]]
    beta = np.where(touches, beta_c, 0.0)
    beta_liquid = geometry.face_fraction
    horizontal = touches & (g.face_axis != g.vertical_axis)
    above = g.face_above
    lumped = horizontal & (above >= 0)
    lumped[lumped] &= ~touches[above[lumped]]
    depth = beta_liquid.copy()
    depth[lumped] += beta_liquid[above[lumped]]
    beta[horizontal] = depth[horizontal]
    # a face between a wet cell and one outside the liquid's cells that is not a surface
    # face is closed: where the wall widens upwards, the lumped depth opens a face whose
    # container fraction is 0 onto a cell outside the tank, and flux through it would leave
    # the pressure system's cells (volume not conserved; a near-zero spurious slosh mode)
    across = np.zeros(g.n_faces, dtype=bool)
    across[inner] = wet[a] != wet[b]
    across[faces] = False
    beta[across] = 0.0
    view = replace(geometry, face_fraction=beta, cell_fraction=np.where(wet, alpha_c, 0.0))
    return Surface(wet, faces, cell, first, theta, point, view)


def measured_state(model: FluidModel, state: FluidState,
                   surface: Surface | None = None) -> FluidState:
    """``state`` with the geometry :mod:`fluid.measures` weighs its faces by when the level
    lies on a plane of faces (``tank_grid(..., face_at=level)``): the step's own view
    (:func:`surface_of`), each surface face normal to the vertical carrying the liquid
    between its wet centre and the surface only (theta of its centre distance; the side
    faces, whose theta jumps at the rim's slivers, keep the view's fraction).

    The liquid's vertical momentum is then rho sum_s F_s z_s over the surface faces' fluxes
    F_s and crossings z_s, the rate of rho int z dV, and its centre of mass rises by the
    surface's potential energy over its weight (within 11 % on 12^3 cells). Weighed by the
    liquid fraction, a surface face on the plane flips between carrying nothing and a whole
    cell as the surface crosses it, and the vertical force on the tank drifts from the
    contents' weight by 0.2 % on 12^3 cells. With the level between two planes the liquid
    fraction is the better weight (the surface stays in one layer; with this view the moment
    about a sphere's centre, which vanishes, grows from 4 % to 7 % of the lateral force
    times the radius on 12^3 cells). ``surface``: the state's :func:`surface_of`, where the
    caller has it."""
    if surface is None:
        surface = surface_of(model, state.geometry)
    beta = surface.view.face_fraction.copy()
    level = model.grid.face_axis[surface.faces] == model.grid.vertical_axis
    beta[surface.faces[level]] *= surface.theta[level]
    return replace(state, geometry=replace(surface.view, face_fraction=beta))


def surface_gradient(model: FluidModel, surface: Surface, cell_values: np.ndarray,
                     boundary: np.ndarray, surface_values: np.ndarray) -> np.ndarray:
    """:func:`fluid.projection.face_gradient` with the surface faces' Dirichlet values
    ``surface_values`` (k,) at the crossings."""
    out = face_gradient(model, cell_values, boundary)
    dist = surface.theta * model.grid.face_distance[surface.faces]
    towards = (surface_values - cell_values[surface.cell]) / dist
    out[surface.faces] = np.where(surface.first, towards, -towards)
    return out


def surface_weights(model: FluidModel, surface: Surface) -> np.ndarray:
    """(n_faces,) weights of the cell-gradient reconstruction: the wetted fraction times the
    smaller cell fraction of two wet cells (as :func:`fluid.projection.gradient_weights`),
    the wet cell's on a surface face, 0 elsewhere."""
    g = model.grid
    alpha = surface.view.cell_fraction
    beta = surface.view.face_fraction
    p_cell, n_cell = g.face_cells
    inner = n_cell >= 0
    smaller = np.where(surface.wet[p_cell], alpha[p_cell], 0.0)
    both = inner.copy()
    both[inner] = surface.wet[p_cell[inner]] & surface.wet[n_cell[inner]]
    smaller[inner] = np.where(both[inner], np.minimum(alpha[p_cell[inner]],
                                                      alpha[n_cell[inner]]), 0.0)
    smaller[surface.faces] = alpha[surface.cell]
    return beta * smaller


def initial_pressure(model: FluidModel, ops, geometry: Geometry, time: float = 0.0) -> np.ndarray:
    """(n_cells,) reduced pressure of the liquid at rest under a level surface: uniform, the
    area-weighted mean of the surface's value (Pa)."""
    surface = surface_of(model, geometry)
    if len(surface.faces) == 0:
        return np.zeros(model.grid.n_cells)
    weight = surface.conductance(model) * surface.theta
    return np.full(model.grid.n_cells,
                   float(np.average(surface.reduced_pressure(model, time), weights=weight)))


@register_stepper("free", initial_pressure)
def step(model: FluidModel, ops: ProjectionOperators, state: FluidState, geometry: Geometry,
         dt: float) -> tuple[FluidState, StepReport]:
    """Advance ``state`` by ``dt`` (s) to the liquid under the surface ``geometry`` (at
    t + dt); see the module doc."""
    surface = surface_of(model, geometry)
    return advance(model, ops, state, geometry, dt, surface,
                   surface.reduced_pressure(model, state.time),
                   surface.reduced_pressure(model, state.time + dt))


def advance(model: FluidModel, ops: ProjectionOperators, state: FluidState,
            geometry: Geometry, dt: float, surface: Surface, p_s_old: np.ndarray,
            p_s_new: np.ndarray, old: Surface | None = None) -> tuple[FluidState, StepReport]:
    """The free-surface step of :func:`step` with the surface's reduced pressure given at its
    crossings (``surface``'s faces): ``p_s_old`` (k,) Pa at t and ``p_s_new`` (k,) Pa at
    t + dt (:mod:`fluid.linear_surface` adds the elevation's hydrostatic pressure); ``old``:
    the :class:`Surface` of ``state.geometry`` where the caller has it."""
    tic = _time.perf_counter()
    g = model.grid
    rho = model.density
    t0, t1 = state.time, state.time + dt
    old = surface_of(model, state.geometry) if old is None else old
    view = surface.view
    fluid = view.fluid_centre
    wall = view.wall_velocity[:, [0, 2]] if g.axisymmetric else view.wall_velocity
    p_bc_old = port_values(model, ops, t0)
    grad_f_old = surface_gradient(model, surface, state.pressure, p_bc_old, p_s_old)
    weights = surface_weights(model, surface)
    grad_c_old = cell_gradient(model, grad_f_old, weights)
    u_flow = _flow_port_velocity(model, ops, view.face_fraction, t1)
    momentum = momentum_inputs(model, ops, state, view, wall, grad_c_old, u_flow, dt)
    viscosity = momentum.face_viscosity.copy()
    viscosity[surface.faces] = 0.0
    u_star, momentum_iterations = _momentum_predictor(
        ops, view, wall, replace(momentum, face_viscosity=viscosity))
    toc_momentum = _time.perf_counter() - tic

    tic = _time.perf_counter()
    old_view = replace(state.geometry, face_fraction=old.view.face_fraction,
                       cell_fraction=old.view.cell_fraction)
    u_face = _face_predictor(model, ops, replace(state, geometry=old_view), view, wall, u_star,
                             grad_c_old, grad_f_old, u_flow, dt)
    # every face keeps its own history (the ring's is already in the predictor)
    p_cell, n_cell = g.face_cells
    ring = (n_cell >= 0) & ~fluid[p_cell] & ~fluid[np.maximum(n_cell, 0)]
    memory = (view.face_fraction > 0) & (old.view.face_fraction > 0) & ~ring
    old_cells = np.where(fluid[:, None], state.cell_velocity, wall)
    u_face[memory] += (state.face_velocity
                       - interpolate_to_faces(model, old_cells, fluid))[memory]
    _carry_over(model, old.view.face_fraction, view.face_fraction, state.face_velocity, u_face)
    p_bc_new = port_values(model, ops, t1)
    dp_s = p_s_new - p_s_old
    inputs, mismatch = _pressure_inputs(model, ops, surface, u_face, p_bc_new - p_bc_old, dp_s,
                                        dt)
    matrix, rhs = ops.assembly.pressure(inputs)
    dp, info = ops.pressure_solver.solve(-matrix, -rhs, np.zeros(g.n_cells))
    warn_if_unconverged(info, "pressure correction")

    dp_bc = np.where(ops.pressure_faces, p_bc_new - p_bc_old, np.nan)
    grad_f = surface_gradient(model, surface, dp, dp_bc, dp_s)
    beta = view.face_fraction
    u_face_new = u_face - dt / rho * grad_f
    u_face_new[ops.flow_faces] = u_flow[ops.flow_faces]
    u_face_new[beta == 0] = 0.0
    _lend_to_lumped(model, beta, geometry.face_fraction, u_face_new)
    u_cell = u_star - dt / rho * cell_gradient(model, grad_f, weights)
    u_cell[~fluid] = wall[~fluid]
    residual = net_outflow(model, beta * g.face_area * u_face_new)
    wet = surface.wet
    divergence = float(np.max(np.abs(residual[wet]) / g.cell_volume[wet])) if wet.any() else 0.0
    pressure = _extend(model, surface, state.pressure + dp, p_bc_new, p_s_new, weights)
    new = FluidState(time=t1, cell_velocity=u_cell, face_velocity=u_face_new,
                     pressure=pressure, geometry=geometry)
    toc_pressure = _time.perf_counter() - tic
    return new, StepReport(mismatch, divergence, toc_momentum, toc_pressure,
                           momentum_iterations, info.iterations, info.residual)


def _carry_over(model: FluidModel, beta_old: np.ndarray, beta_new: np.ndarray,
                u_old: np.ndarray, u_face: np.ndarray) -> None:
    """Hand the flux of the faces the surface opens or closes on, in place on the predicted
    face velocities ``u_face`` (n_faces,) m/s.

    When the surface rises past a centre plane, a face of the new top layer opens: a
    horizontal one whose liquid the face below it carried (lumped, see the module doc), or
    the vertical face that is now the column's surface face. It takes the velocity of the
    face below it, so the flux through the column is unchanged. When the surface falls past
    one, a horizontal face closes and the face below takes over its liquid: the two
    velocities merge, weighted by their fractions beta (their momentum is unchanged).
    Without this the faces' flux is dropped or re-created from the cells and every layer
    change costs the sloshing liquid energy: the half-full sphere, whose level lies on a
    centre plane so every column changes layer twice a period, decays at zeta = 0.012 /
    0.0147 / 0.0108 on 12^3 / 16^3 / 24^3 cells, and at 0.0067 / 0.0088 / 0.0060 with it.
    A vertical surface face that closes is not merged: the liquid it carried is not the
    face below's (merged, zeta fell to -0.0018 on 12^3, but the momentum jumped at each
    layer change and the moment about the centre, which vanishes for a sphere, showed
    spikes of 0.15 F R)."""
    g = model.grid
    below = g.face_below
    sign = g.face_sign
    kept = (beta_old > 0) & (beta_new > 0)
    horizontal = g.face_axis != g.vertical_axis
    opened = np.flatnonzero((beta_new > 0) & (beta_old == 0))
    source = below[opened]
    take = source >= 0
    take[take] = kept[source[take]]
    f, s = opened[take], source[take]
    u_face[f] = u_face[s] * sign[s] * sign[f]
    closed = np.flatnonzero(horizontal & (beta_new == 0) & (beta_old > 0))
    target = below[closed]
    take = target >= 0
    take[take] = kept[target[take]]
    f, t = closed[take], target[take]
    share = beta_old[f] / (beta_old[f] + beta_old[t])
    jump = u_old[f] * sign[f] - u_old[t] * sign[t]
    u_face[t] += sign[t] * share * jump


def _lend_to_lumped(model: FluidModel, beta: np.ndarray, beta_liquid: np.ndarray,
                    u_face: np.ndarray) -> None:
    """Give each face whose liquid the face below it carries (a horizontal face that touches
    no liquid-centre cell, lumped into the top layer's face, see the module doc) that face's
    velocity, in place on ``u_face`` (n_faces,) m/s: the liquid there moves with it, and the
    integral measures, which weigh each face by its liquid fraction, see the momentum and
    energy the step carries."""
    g = model.grid
    above = g.face_above
    carrier = np.flatnonzero((beta > 0) & (g.face_axis != g.vertical_axis) & (above >= 0))
    lent = above[carrier]
    take = (beta[lent] == 0) & (beta_liquid[lent] > 0)
    f, a = carrier[take], lent[take]
    sign = g.face_sign
    u_face[a] = u_face[f] * sign[f] * sign[a]


def _pressure_inputs(model, ops, surface: Surface, u_face, dp_ports, dp_surface, dt):
    """The pressure system: the container's wetted faces between wet cells, the surface faces
    as Dirichlet conditions (on the diagonal and the right-hand side), no volume source (the
    container does not move). Returns the inputs and the volume mismatch (m^3/s) of regions
    the surface does not reach."""
    g = model.grid
    rho = model.density
    view = surface.view
    wet = surface.wet
    beta = view.face_fraction.copy()
    source = net_outflow(model, beta * g.face_area * u_face)
    pin_scale = dt / rho * 2 * g.dim / g.spacing**2
    pressure_pin = np.where(wet, 0.0, pin_scale)
    k = dt / rho * surface.conductance(model)
    pressure_pin += np.bincount(surface.cell, k, g.n_cells) / g.cell_volume
    source -= np.bincount(surface.cell, k * dp_surface, g.n_cells)
    beta[surface.faces] = 0.0  # their flux is the Dirichlet term above
    region = _liquid_regions(model, replace(view, face_fraction=beta), wet)
    anchored = np.unique(region[surface.cell])
    if ops.pressure_faces.any():
        wet_port = ops.pressure_faces & (view.face_fraction > 0)
        anchored = np.union1d(anchored, region[g.face_cells[0][wet_port]])
    mismatch = _balance_regions(model, view, region, anchored, source, pressure_pin, pin_scale,
                                flow_only=False)
    inputs = PressureInputs(face_coefficient=beta * dt / rho, cell_pin=pressure_pin,
                            cell_source=source / g.cell_volume, face_boundary=dp_ports)
    return inputs, mismatch


def _extend(model, surface: Surface, pressure, boundary, surface_values, weights):
    """Pressure in the gas-centre cells next to the liquid: across each surface face the
    value on the line through the wet cell's and the surface's (the ghost value of the
    Dirichlet condition, averaged over a cell's faces), then ``GHOST_LAYERS`` - 1 more layers
    extrapolated as :func:`fluid.projection._extend_pressure` does."""
    g = model.grid
    out = pressure.copy()
    gas = np.where(surface.first, g.face_cells[1][surface.faces],
                   g.face_cells[0][surface.faces])
    ghost = pressure[surface.cell] + (surface_values - pressure[surface.cell]) / surface.theta
    count = np.bincount(gas, minlength=g.n_cells)
    total = np.bincount(gas, ghost, g.n_cells)
    layer = count > 0
    out[layer] = total[layer] / count[layer]
    known = surface.wet | layer
    if GHOST_LAYERS > 1:
        out = _extend_pressure(model, out, known, boundary, weights)
    return out


def column_rates(model: FluidModel, state: FluidState) -> tuple[np.ndarray, np.ndarray]:
    """How fast the surface rises over each vertical column of cells of a 3-D grid:
    ((nx, ny) m/s, (nx, ny) bool: the column has surface faces).

    The liquid leaving through a column's surface faces (the flux of the last step's
    face velocities, which conserve volume exactly) over the column's open cross-section
    there (the wetted fraction of its horizontal surface faces, at least
    ``MIN_COLUMN_FRACTION``): the kinematic condition of a surface that is a height
    function z = eta(x, y), in the volume-conserving form of the height-function methods
    (the flux through a side surface face, into a column whose surface is lower, raises
    that column)."""
    g = model.grid
    if g.axisymmetric:
        raise ValueError("column rates need a 3-D grid")
    surface = surface_of(model, state.geometry)
    faces = surface.faces
    beta = surface.view.face_fraction[faces]
    u = state.face_velocity[faces]
    outflow = np.where(surface.first, u, -u) * beta * g.face_area[faces]
    gas = np.where(surface.first, g.face_cells[1][faces], g.face_cells[0][faces])
    vertical = g.face_axis[faces] == g.vertical_axis
    column_cell = np.where(vertical, surface.cell, gas)
    nx, ny = g.shape[0], g.shape[1]
    column = column_index(g, column_cell)
    flux = np.bincount(column, outflow, nx * ny)
    area = np.bincount(column[vertical], beta[vertical] * g.face_area[faces][vertical],
                       nx * ny)
    area = np.maximum(area, MIN_COLUMN_FRACTION * g.spacing**2)
    has = np.bincount(column, minlength=nx * ny) > 0
    rate = np.where(has, flux / area, 0.0)
    return rate.reshape(nx, ny), has.reshape(nx, ny)


def column_index(grid, cells: np.ndarray) -> np.ndarray:
    """(k,) the vertical column (i * ny + j) of each of ``cells`` (k,) on a 3-D grid."""
    ij = np.unravel_index(grid.cell_lattice[cells], grid.shape)
    return ij[0] * grid.shape[1] + ij[1]


#: smallest open cross-section of a surface column, as a fraction of a cell face
MIN_COLUMN_FRACTION = 0.05
