"""The slosh modes of the liquid under a fixed mean surface: one eigenvalue problem, no time
history.

Linear slosh theory on the grid of :mod:`fluid.linear_surface`. Without viscosity and
convection, the faces of that step evolve as a staggered grid's: for small motion about a
mean surface at rest,

    rho d2 xi_f / dt2 = -grad_f p           (every face of the liquid, displacement xi_f)
    sum_f beta_f A_f xi_f = 0               (every liquid cell: incompressible)
    p_s = rho s_s eta_s                     (every surface face s, eta_s = xi_s . n_s)

with p the reduced pressure's change, s_s = -b . n_s the body acceleration's pull into the
liquid across the face (g on a level surface's upward faces, 0 on a face whose normal is
horizontal: p = 0 stays fixed there) and grad_f the step's face gradient (the ghost-fluid
distance theta h at a surface face). Eliminating the cells' pressures leaves, on the faces
with s_s > 0, the symmetric eigenproblem

    S p = omega^2 diag(A_s / s_s) p,   S = K_ss - K_sc L^-1 K_cs,

with L the pressure operator of the step on the liquid's cells (the container's cut faces,
the surface faces' ghost-fluid conductances K_ss = diag(beta A / (theta h)) on its diagonal)
and K_cs those conductances between each surface face and its cell. S is the discrete
Dirichlet-to-Neumann map of the liquid, positive semi-definite; its null vector (uniform
p: the liquid's volume changing) is the zero mode that incompressibility excludes. This is
the liquid's added-mass operator condensed on the surface (NASTRAN's virtual fluid mass,
Morand & Ohayon's (u, p) form with the liquid eliminated), and the time step of
:mod:`fluid.linear_surface` is its Stormer-Verlet integrator: its frequencies are this
problem's to O((omega dt)^2).

The free surface's modes come from the whole sparse system of the cells' and the surface's
pressures (S its Schur complement on the surface, the mass diag(A_s / s_s) on the surface
faces only) by ARPACK in shift-invert mode, one SuperLU factorisation (:func:`_sparse_modes`).
With a membrane on the surface its stiffness couples the faces and the mass
rho A K^-1 A is dense: S is then condensed whole, one SuperLU solve per surface face (about
450 on 24^3 cells at half fill), and solved by LAPACK (:func:`_dense_modes`). The two agree
to round-off on the free surface (measured 1e-14 in omega^2 over nine fills and five grids),
the sparse one two to four times faster on 32^3 cells.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as la
import scipy.sparse.linalg as sla
from scipy import sparse

from .free_surface import Surface, _pressure_inputs, surface_of
from .geometry import Geometry
from .linear import single_blas_thread
from .linear_surface import outward_normals, surface_areas
from .model import FluidModel
from .projection import THETA_MIN, ProjectionOperators, _liquid_regions

#: a mode whose omega^2 is below this fraction of the largest is the zero (volume) mode
ZERO_MODE_RTOL = 1e-9
#: a surface face with less than this fraction of the largest face's area or conductance
#: carries no flux (condensed out as a wall)
MASSLESS_AREA = 1e-9
#: a surface face through which less than this fraction of its own conductance reaches the
#: rest of the liquid (the diagonal of the Dirichlet-to-Neumann map over it) is a wall
DECOUPLED = 1e-6
#: the shift-invert's shift, below zero by this fraction of omega^2 of a cell-size wave
SHIFT = 1e-3


@dataclass(frozen=True)
class SurfaceModes:
    """The slosh modes of the liquid under a mean surface, by ascending frequency.

    ``omega2`` (n,) rad^2/s^2; ``surface`` the :class:`fluid.free_surface.Surface`;
    ``faces`` (k,) the indices (into ``surface.faces``) of the surface faces that carry a
    restoring pressure (s > 0); ``area`` (k,) m^2 their wetted areas; ``pull`` (k,) m/s^2,
    s = -b . n on each; ``elevation`` (k, n) m: each mode's surface elevation eta along the
    outward normal, normalised to sum_s rho A_s eta_s^2 = 1 kg (so eta is in m per
    sqrt(kg)); ``cell_pressure`` (n_cells, n) Pa: each mode's reduced-pressure amplitude
    in the liquid's cells (0 elsewhere); ``face_displacement`` (n_faces, n) m: each mode's
    displacement along FiPy's face normals, grad_f p / (rho omega^2); ``stiffness``
    (n,) m/s^2: each mode's eta^T K eta, its elastic and gravitational energy twice over
    (g for every mode of a free surface under gravity g); ``tension`` (N/m) the membrane's
    on the surface (0: free)."""

    omega2: np.ndarray
    surface: Surface
    faces: np.ndarray
    area: np.ndarray
    pull: np.ndarray
    elevation: np.ndarray
    cell_pressure: np.ndarray
    face_displacement: np.ndarray
    stiffness: np.ndarray
    tension: float = 0.0

    @property
    def frequency_hz(self) -> np.ndarray:
        """(n,) Hz."""
        return np.sqrt(self.omega2) / (2.0 * np.pi)


def surface_modes(model: FluidModel, geometry: Geometry, count: int,
                  time: float = 0.0, tension: float = 0.0) -> SurfaceModes:
    """The first ``count`` slosh modes of ``model``'s liquid under the mean surface of
    ``geometry`` (a geometry computed with the interface at rest), body acceleration at
    ``time`` (s); see the module doc. ``tension`` (N/m): a massless membrane under this
    uniform tension lies on the surface, pinned where it meets the wall (0: the free
    surface; see :func:`membrane_stiffness`). ValueError when the surface has a face where
    the body acceleration pulls the liquid out (liquid above gas) or fewer faces than
    ``count``."""
    if count < 1:
        raise ValueError(f"count: at least 1 mode, got {count}")
    if not tension >= 0:
        raise ValueError(f"tension: at least 0 N/m, got {tension}")
    with single_blas_thread():
        return _surface_modes(model, geometry, count, time, tension)


def membrane_stiffness(model: FluidModel, surface: Surface, faces: np.ndarray) -> sparse.csr_matrix:
    """(k, k) m^0: the finite-volume form of int |grad eta|^2 dA over the surface faces
    ``faces`` (indices into ``surface.faces``, faces normal to the vertical on one level),
    finite differences between the faces' centres: between two faces of neighbouring
    columns their difference squared (edge over distance, h / h); where a column's
    neighbour is not a face whose centre is inside the container, eta = 0 on the wall
    where the container's level set crosses between the two centres (its distance theta h
    from the face's, at least ``THETA_MIN`` h), eta^2 / theta (Shortley-Weller's distance);
    a face whose centre is outside lies on the wall, eta = 0 (held by 1 / THETA_MIN). A membrane of uniform tension
    T stores T/2 eta^T G eta (J) in it."""
    g = model.grid
    f = surface.faces[faces]
    if np.any(g.face_axis[f] != g.vertical_axis):
        raise ValueError("a membrane lies on a level surface: faces normal to the vertical")
    ij = g.cell_index[surface.cell[faces]][:, :2]
    centre = model.grid_points(g.face_centre[f])
    level = model.container.level_set
    inside = np.array([float(level(tuple(c))) < 0 for c in centre])
    key = ij[:, 0] * g.shape[1] + ij[:, 1]
    lookup = {int(k): a for a, k in enumerate(key) if inside[a]}
    rows, cols, values = [], [], []
    # a face whose centre is outside the container lies on the wall: eta = 0 there
    outside = np.flatnonzero(~inside)
    rows += outside.tolist()
    cols += outside.tolist()
    values += [1.0 / THETA_MIN] * len(outside)
    h = g.spacing
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        other = [lookup.get(int(k)) for k in (ij[:, 0] + di) * g.shape[1] + ij[:, 1] + dj]
        for a in np.flatnonzero(inside):
            b = other[a]
            if b is not None:
                if b > a:  # each pair once
                    rows += [a, b, a, b]
                    cols += [a, b, b, a]
                    values += [1.0, 1.0, -1.0, -1.0]
                continue
            phi0 = float(level(tuple(centre[a])))
            phi1 = float(level(tuple(centre[a] + h * np.array([di, dj, 0.0]))))
            theta = phi0 / (phi0 - phi1) if phi1 > 0 else 1.0
            rows.append(a)
            cols.append(a)
            values.append(1.0 / max(theta, THETA_MIN))
    return sparse.csr_matrix((values, (rows, cols)), shape=(len(faces), len(faces)))


def _surface_modes(model, geometry, count, time, tension):
    g = model.grid
    rho = model.density
    surface = surface_of(model, geometry)
    normals = outward_normals(model, surface)
    pull = -(normals @ model.body_acceleration_at(time))
    scale = float(np.max(np.abs(pull))) if len(pull) else 0.0
    if np.any(pull < -1e-12 * scale):
        raise ValueError("the mean surface has faces with liquid above gas: no slosh modes "
                         "about an unstable surface")
    restoring = np.flatnonzero(pull > 1e-12 * scale)
    wet = _main_region(model, surface)
    restoring = restoring[np.isin(surface.cell[restoring], wet)]
    if len(restoring) <= count:
        raise ValueError(f"count: {count} modes asked of a surface with {len(restoring)} "
                         f"restoring faces (refine the fluid grid)")
    ops = ProjectionOperators(model)
    zero_faces = np.zeros(g.n_faces)
    # dt = rho: the step's coefficients beta dt / rho become the conductances beta A / d
    inputs, _ = _pressure_inputs(model, ops, surface, zero_faces, zero_faces,
                                 np.zeros(len(surface.faces)), rho)
    matrix, _ = ops.assembly.pressure(inputs)
    laplacian = (-matrix).tocsr()[wet][:, wet].tocsc()
    conductance = surface.conductance(model)[restoring]
    row = np.searchsorted(wet, surface.cell[restoring])
    area = surface_areas(model, surface)[restoring]
    stiffness = pull[restoring]
    solve = _dense_modes if tension > 0 else _sparse_modes
    values, elevation, surface_pressure, cell_values, modal_stiffness, held = solve(
        model, surface, restoring, laplacian, row, conductance, area, stiffness, count,
        tension)
    area, stiffness = area[held], stiffness[held]
    cell_pressure = np.zeros((g.n_cells, len(values)))
    cell_pressure[wet] = cell_values
    displacement = _face_displacement(model, surface, restoring, cell_pressure,
                                      surface_pressure, values)
    return SurfaceModes(values, surface, restoring[held], area, stiffness, elevation,
                        cell_pressure, displacement, modal_stiffness, tension)


def _dense_modes(model, surface, restoring, laplacian, row, conductance, area, stiffness,
                 count, tension):
    """The modes by the Dirichlet-to-Neumann map S condensed whole (one SuperLU solve per
    surface face) and LAPACK on S p = omega^2 rho A K^-1 A p, K the gravity's and the
    membrane's stiffness (dense when a membrane couples the faces). Returns (omega^2 (n,),
    elevation (k', n), surface pressures (k, n), the wet cells' pressures, each mode's
    eta^T K eta (n,), held (k,) bool: the faces that carry flux)."""
    rho = model.density
    k = len(restoring)
    coupling = np.zeros((laplacian.shape[0], k))
    coupling[row, np.arange(k)] = conductance
    response = sla.splu(laplacian).solve(coupling)          # (n_wet, k): L^-1 K_cs
    dtn = np.diag(conductance) - coupling.T @ response
    dtn = 0.5 * (dtn + dtn.T)
    # a face the wall all but closes (its fraction round-off), or whose cell reaches the
    # rest of the liquid only through such faces (a pocket with its own volume mode),
    # carries no flux: a wall (its pressure condensed out)
    held = _carries_flux(area, conductance)
    held &= np.diag(dtn) > DECOUPLED * conductance
    expand = np.eye(k)[:, held]  # surface pressures from the held faces'
    if not held.all():
        h, f = np.flatnonzero(held), np.flatnonzero(~held)
        # (pseudo-inverse: a massless face whose cell joins nothing else has a zero row)
        expand[f] = -np.linalg.pinv(dtn[np.ix_(f, f)], hermitian=True) @ dtn[np.ix_(f, h)]
        dtn = expand.T @ dtn @ expand
        dtn = 0.5 * (dtn + dtn.T)
    area, stiffness = area[held], stiffness[held]
    # the surface's stiffness K (N/m per face): gravity, and the membrane's tension; the
    # pressure p on the faces balances it, A p = K eta, so that S p = omega^2 rho A K^-1 A p
    gravity = rho * stiffness * area
    if tension > 0:
        elastic = tension * membrane_stiffness(model, surface, restoring[held])
        compliance = np.linalg.inv(np.diag(gravity) + elastic.toarray())
    else:
        compliance = np.diag(1.0 / gravity)
    mass = rho * area[:, None] * compliance * area[None, :]
    mass = 0.5 * (mass + mass.T)
    top = min(2 * count + 1, len(area) - 1)
    values, vectors = la.eigh(dtn, mass, subset_by_index=[0, min(count, top)])
    keep = values > ZERO_MODE_RTOL * max(float(values[-1]), 0.0)
    if keep.sum() < count:
        values, vectors = la.eigh(dtn, mass, subset_by_index=[0, top])
        keep = values > ZERO_MODE_RTOL * float(values[-1])
    values, vectors = values[keep][:count], vectors[:, keep][:, :count]
    # eta = K^-1 A p, scaled (with p) to sum rho A eta^2 = 1 kg
    elevation = compliance @ (area[:, None] * vectors)
    scale = 1.0 / np.sqrt(np.sum(rho * area[:, None] * elevation**2, axis=0))
    elevation = elevation * scale
    surface_pressure = expand @ (vectors * scale)
    # A p = K eta: eta^T K eta = eta^T A p
    modal_stiffness = np.sum(elevation * area[:, None] * vectors * scale, axis=0)
    return values, elevation, surface_pressure, response @ surface_pressure, \
        modal_stiffness, held


def _carries_flux(area: np.ndarray, conductance: np.ndarray) -> np.ndarray:
    """(k,) bool: a surface face whose wetted area and conductance are not round-off."""
    return (area > MASSLESS_AREA * float(np.max(area))) & \
        (conductance > MASSLESS_AREA * float(np.max(conductance)))


def _sparse_modes(model, surface, restoring, laplacian, row, conductance, area, stiffness,
                  count, tension):
    """The free surface's modes (no membrane: its stiffness diagonal) from the whole
    symmetric system of the cells' and the surface faces' pressures,

        [ L     -K_cs ] [p_c]             [0      0    ] [p_c]
        [-K_sc   K_ss ] [p_s] = omega^2   [0  diag(A/s)] [p_s],

    whose Schur complement on p_s is S, by ARPACK in shift-invert mode just below zero (one
    SuperLU factorisation; the mass is only semi-definite, which shift-invert allows). The
    zero mode (the volume's) is dropped. Returns what :func:`_dense_modes` does."""
    rho = model.density
    held = _carries_flux(area, conductance)
    faces = np.flatnonzero(held)
    n, k = laplacian.shape[0], len(faces)
    coupling = sparse.csc_matrix((-conductance[faces], (row[faces], np.arange(k))),
                                 shape=(n, k))
    system = sparse.bmat([[laplacian, coupling],
                          [coupling.T, sparse.diags(conductance[faces])]], format="csc")
    weight = area[faces] / stiffness[faces]
    mass = sparse.diags(np.concatenate([np.zeros(n), weight]), format="csc")
    scale = float(np.max(stiffness)) / model.grid.spacing  # omega^2 of a cell-size wave
    wanted = count + 2
    while True:
        values, vectors = sla.eigsh(system, k=min(wanted, k - 1), M=mass,
                                    sigma=-SHIFT * scale, which="LM")
        order = np.argsort(values)
        values, vectors = values[order], vectors[:, order]
        keep = values > ZERO_MODE_RTOL * scale
        if keep.sum() >= count or wanted >= k - 1:
            break
        wanted = min(2 * wanted, k - 1)
    values, vectors = values[keep][:count], vectors[:, keep][:, :count]
    cells, surface_values = vectors[:n], vectors[n:]
    elevation = surface_values / (rho * stiffness[faces, None])
    norm = 1.0 / np.sqrt(np.sum(rho * area[faces, None] * elevation**2, axis=0))
    surface_pressure = np.zeros((len(restoring), len(values)))
    surface_pressure[faces] = surface_values * norm
    elevation = elevation * norm
    modal_stiffness = np.sum(rho * stiffness[faces, None] * area[faces, None] * elevation**2,
                             axis=0)
    return values, elevation, surface_pressure, cells * norm, modal_stiffness, held


def _main_region(model: FluidModel, surface: Surface) -> np.ndarray:
    """The wet cells (sorted indices) of the connected liquid region holding the most liquid.
    A cut cell at the wall can hold a sliver of liquid joined to nothing but its own surface
    face: a pocket of its own volume, whose slosh is the zero mode of its volume (measured:
    8 such modes on 28^3 cells at tank fraction 0.3)."""
    beta = surface.view.face_fraction.copy()
    beta[surface.faces] = 0.0
    region = _liquid_regions(model, replace(surface.view, face_fraction=beta), surface.wet)
    cells = np.flatnonzero(region >= 0)
    volume = surface.view.cell_fraction[cells] * model.grid.cell_volume[cells]
    largest = np.argmax(np.bincount(region[cells], volume))
    return cells[region[cells] == largest]


def _face_displacement(model, surface, restoring, cell_pressure, surface_pressure, omega2):
    """(n_faces, n) m: grad_f p / (rho omega^2) on the liquid's faces along FiPy's normals
    (the surface faces with their Dirichlet values, 0 on the faces without liquid)."""
    g = model.grid
    p_cell, n_cell = g.face_cells
    beta = surface.view.face_fraction.copy()
    beta[surface.faces] = 0.0
    inner = (n_cell >= 0) & (beta > 0)
    inner[inner] &= surface.wet[p_cell[inner]] & surface.wet[n_cell[np.flatnonzero(inner)]]
    out = np.zeros((g.n_faces, len(omega2)))
    f = np.flatnonzero(inner)
    out[f] = (cell_pressure[n_cell[f]] - cell_pressure[p_cell[f]]) / g.face_distance[f, None]
    values = np.zeros((len(surface.faces), len(omega2)))
    values[restoring] = surface_pressure
    towards = (values - cell_pressure[surface.cell]) / \
        (surface.theta * g.face_distance[surface.faces])[:, None]
    out[surface.faces] = np.where(surface.first[:, None], towards, -towards)
    return out / (model.density * omega2[None, :])
