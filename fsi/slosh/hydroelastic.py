"""The slosh modes of the liquid under the diaphragm: the membrane's tangent stiffness about
its loaded state and the liquid's added mass, one eigenvalue problem.

About the membrane's static equilibrium at a tank fraction (the statics' XPBD start, settled
under the Newton model's energies, :func:`structure.newton.window.settled`), small motion u
of its free nodes obeys

    K u + (M + M_a) u'' = 0,   g . u = 0,

* K (3n x 3n, N/m): the Newton model's tangent at the equilibrium (elasticity, bending,
  prestress, the hydrostatic load's stiffness; :func:`structure.newton.system.linearise`);
* M: the lumped node masses; g: the enclosed volume's gradient (the liquid is
  incompressible and the tank closed: the volume held is the constraint);
* M_a = rho B^T L^+ B: the liquid's added mass. B (cells x 3n, m^2) is each liquid cell's
  volume change per node displacement, the membrane's area vectors shared by points on
  each triangle at most half a cell apart, each point's share given to the cell holding it
  (its columns sum to g exactly); L the liquid step's pressure operator with the membrane as a wall (the cut
  faces' conductances beta A / d, Neumann at every wall); L^+ its inverse on the liquid's
  volume-preserving motions. The kinetic energy of the potential flow that the membrane's
  motion drives is 1/2 u'^T M_a u'.

The eigenvalues omega^2 come from ARPACK in symmetric shift-invert mode about 0 (K's
symmetric part; the follower load leaves round-off), the inverse that of K bordered by g and
M + M_a applied as an operator: one SuperLU factorisation each of the bordered K and of L
bordered by the constant. A loaded membrane can hold
directions of negative stiffness (compressed where it would wrinkle): they come out with
omega^2 < 0, are counted (``unstable``) and left out of the modes.

The spring-mass equivalent of a mode phi under a lateral tank acceleration a along x: the
contents feel the body force -a, the membrane's nodes as M r_x and the liquid as the
pressure -rho a x, which loads the membrane by B^T; with f = M r_x + rho B^T x_c, mode j's
slosh mass is m_j = (phi_j . f)^2 / (phi_j . (M + M_a) phi_j) (NASA SP-106's modal mass).
"""
from __future__ import annotations

import time as _time
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from fluid.linear import single_blas_thread
from fluid.projection import ProjectionOperators, _liquid_regions, _open_area
from fluid.systems import PressureInputs
from structure.newton.system import linearise
from structure.newton.window import newton_model

from fsi.slosh.modal import lateral_pairs

POINT_SPACING = 0.5
"""The volume map's points on a membrane triangle lie at most this many fluid cells apart
(its sub-triangles' edges; measured: a three-point rule on the flat diaphragm's N = 14
triangles, about two cells wide on 32^3 cells, put its first mode 3.9 % under the time
domain's, where 16^3 and 24^3 agree within 3 %)."""
MIN_FACE_FRACTION = 1e-6
"""A cut face open less than this fraction of its area is closed in the liquid's operator (a
cell joined to the rest only through such faces makes it singular beyond the constant)."""
PAIR_RTOL = 0.03
"""A diaphragm's two modes closer than this in omega^2 are one lateral pair, split by the
membrane's and the fluid's grids (measured: 1.2 % on the flat diaphragm, N = 14 on 24^3
cells; a folded hemisphere's split pair is 70 % apart, and stays two modes)."""
LATERAL_MASS = 1e-3
"""A mode whose lateral slosh mass is below this fraction of the contents' is not lateral."""


@dataclass(frozen=True)
class DiaphragmModes:
    """The diaphragm's slosh modes at one tank fraction, by ascending frequency: ``omega2``
    (n,) rad^2/s^2, ``slosh_mass`` (n,) kg (the x share), ``lateral_mass`` (n,) kg (along
    its own direction), ``direction_deg`` (n,) deg, ``lateral`` (n,) bool; ``unstable``: the
    directions of negative stiffness found among the lowest (left out); the contents'
    ``mass`` (kg, liquid and membrane), the equilibrium's ``level`` (Pa) and whether it
    ``converged``, ``dofs`` the free degrees of freedom, ``seconds``; ``seed`` the
    imperfection its static start was seeded with (:attr:`structure.load.Equilibrium.seed`)."""

    omega2: np.ndarray
    slosh_mass: np.ndarray
    lateral_mass: np.ndarray
    direction_deg: np.ndarray
    lateral: np.ndarray
    unstable: int
    mass: float
    level: float
    converged: bool
    dofs: int
    seconds: float
    seed: tuple = ()


def coupled_modes(xpbd, state, equilibrium, load, model, geometry, count: int) \
        -> DiaphragmModes:
    """The first ``count`` modes of the membrane ``xpbd`` (:class:`structure.xpbd.XpbdModel`)
    at its static ``state`` (:class:`structure.load.Equilibrium` ``equilibrium`` under
    ``load``) over the liquid of ``model`` in ``geometry`` (the cut cells with the membrane
    as the interface): see the module doc."""
    tic = _time.perf_counter()
    with single_blas_thread():
        out = _modes(xpbd, state, equilibrium, load, model, geometry, count)
    return DiaphragmModes(*out, mass=model.density * geometry.liquid_volume
                          + float(np.sum(xpbd.base.node_mass)),
                          level=float(equilibrium.pressure_level),
                          converged=bool(equilibrium.converged),
                          dofs=3 * int(np.count_nonzero(newton_model(xpbd).free)),
                          seconds=_time.perf_counter() - tic)


def _modes(xpbd, state, equilibrium, load, model, geometry, count):
    newton = newton_model(xpbd)
    x = state.node_position
    lin = linearise(newton, x, equilibrium.pressure_level, load)
    free = np.flatnonzero(newton.free)
    dof = (3 * free[:, None] + np.arange(3)).ravel()
    stiffness = sp.csr_matrix(lin.matrix)[dof][:, dof]
    gradient = lin.volume_gradient[free].ravel()
    mass = np.repeat(newton.base.node_mass[free], 3)
    cells, laplacian = _liquid_operator(model, geometry)
    volume_map = _volume_map(model.grid, xpbd.triangles, x, free, cells, gradient)
    rho = model.density
    liquid = sla.splu(_bordered(laplacian, np.ones(len(cells)) / np.sqrt(len(cells))))
    solid = sla.splu(_bordered(stiffness, gradient))
    n, m = len(cells), len(dof)

    def inertia(v):
        v = np.ravel(v)
        pressure = liquid.solve(np.concatenate([volume_map @ v, [0.0]]))[:n]
        return mass * v + rho * (volume_map.T @ pressure)

    # K is symmetric but for the follower load's round-off (measured 8e-6 of its largest
    # entry): its symmetric part, so that ARPACK's symmetric shift-invert mode applies
    mass_operator = sla.LinearOperator((m, m), matvec=inertia, dtype=float)
    inverse = sla.LinearOperator(
        (m, m), matvec=lambda v: solid.solve(np.concatenate([np.ravel(v), [0.0]]))[:m],
        dtype=float)
    symmetric = 0.5 * (stiffness + stiffness.T)
    wanted = min(count + 4, m - 2)
    while True:
        omega2, vectors = sla.eigsh(symmetric, k=wanted, M=mass_operator, sigma=0.0,
                                    OPinv=inverse, which="LM")
        stable = omega2 > 0
        if stable.sum() >= count or wanted >= m - 2:
            break
        wanted = min(2 * wanted, m - 2)
    order = np.argsort(omega2[stable])[:count]
    unstable_values = omega2[~stable]
    omega2, vectors = omega2[stable][order], vectors[:, stable][:, order]
    unstable = len(unstable_values)
    centre = model.grid_points(model.grid.cell_centre[cells])
    node = np.zeros((m, 2))
    node[0::3, 0] = 1.0
    node[1::3, 1] = 1.0
    forcing = mass[:, None] * node + rho * (volume_map.T @ centre[:, :2])  # (m, 2)
    norms = np.array([v @ inertia(v) for v in vectors.T])
    vectors = vectors / np.sqrt(norms)
    participation = vectors.T @ forcing                                       # (n, 2)
    omega2, vectors, participation, _ = lateral_pairs(omega2, vectors, participation,
                                                      rtol=PAIR_RTOL)
    lateral_mass = np.sum(participation**2, axis=1)
    slosh_mass = participation[:, 0] ** 2
    direction = np.degrees(np.arctan2(participation[:, 1], participation[:, 0]))
    direction = np.where(direction <= -90, direction + 180,
                         np.where(direction > 90, direction - 180, direction))
    return omega2, slosh_mass, lateral_mass, direction, \
        lateral_mass > LATERAL_MASS * lateral_mass.max(), unstable


def _bordered(matrix, vector) -> sp.csc_matrix:
    """[[A, v], [v^T, 0]]: A on the space orthogonal to v (its inverse's first block is A's
    on that space)."""
    column = sp.csr_matrix(vector[:, None])
    return sp.bmat([[matrix, column], [column.T, None]], format="csc")


def _liquid_operator(model, geometry):
    """The liquid's cells (the connected region holding the most liquid) and the pressure
    operator on them with every wall Neumann: (cells (k,), L (k, k) m, the step's
    conductances beta A / d)."""
    g = model.grid
    ops = ProjectionOperators(model)
    beta = np.where(geometry.face_fraction > MIN_FACE_FRACTION, geometry.face_fraction, 0.0)
    geometry = replace(geometry, face_fraction=beta)
    area_open = geometry.face_fraction * g.face_area
    coupled = (geometry.cell_fraction > 0) | (_open_area(model, area_open) > 0)
    region = _liquid_regions(model, geometry, coupled)
    held = np.flatnonzero(coupled)
    volume = geometry.cell_fraction[held] * g.cell_volume[held]
    largest = np.argmax(np.bincount(region[held], volume))
    cells = held[region[held] == largest]
    inputs = PressureInputs(face_coefficient=geometry.face_fraction.copy(),
                            cell_pin=np.where(coupled, 0.0, 1.0),
                            cell_source=np.zeros(g.n_cells),
                            face_boundary=np.full(g.n_faces, np.nan))
    matrix, _ = ops.assembly.pressure(inputs)
    return cells, (-matrix).tocsr()[cells][:, cells]


def _volume_map(grid, triangles, x, free, cells, gradient) -> sp.csr_matrix:
    """B (cells, 3 free nodes): each cell's liquid volume change per node displacement (m^2),
    oriented so that its columns sum to the enclosed volume's ``gradient``: each triangle's
    area vector shared among its nodes by the centroids of its s^2 sub-triangles (s the
    subdivisions that bring them under half a cell, :func:`subtriangle_points`), each
    point's share to the cell holding it."""
    points = x[triangles]
    area = 0.5 * np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    edge = np.max(np.linalg.norm(points - np.roll(points, 1, axis=1), axis=2))
    weights = subtriangle_points(int(np.ceil(edge / (POINT_SPACING * grid.spacing))))
    row_of = np.full(grid.n_cells, -1)
    row_of[cells] = np.arange(len(cells))
    column_of = np.full(len(x), -1)
    column_of[free] = np.arange(len(free))
    rows, cols, values = [], [], []
    share = 1.0 / len(weights)
    for weight in weights:
        cell = grid.cell_of(np.einsum("j,tjk->tk", weight, points))
        row = np.where(cell >= 0, row_of[np.maximum(cell, 0)], -1)
        for j in range(3):
            column = column_of[triangles[:, j]]
            use = (row >= 0) & (column >= 0)
            for axis in range(3):
                rows.append(row[use])
                cols.append(3 * column[use] + axis)
                values.append(area[use, axis] * weight[j] * share)
    volume_map = sp.csr_matrix((np.concatenate(values), (np.concatenate(rows),
                                                          np.concatenate(cols))),
                               shape=(len(cells), 3 * len(free)))
    total = np.asarray(volume_map.sum(axis=0)).ravel()
    return volume_map * float(np.sign(total @ gradient))


def subtriangle_points(s: int) -> np.ndarray:
    """(s^2, 3) barycentric coordinates of the centroids of the s^2 equal sub-triangles of a
    triangle cut s times along each edge: a rule of equal weights 1 / s^2 that integrates a
    linear function exactly (each node's share of the area is 1/3)."""
    s = max(int(s), 1)
    out = []
    for i in range(s):
        for j in range(s - i):
            out.append([(i + 1 / 3), (j + 1 / 3), s - i - j - 2 / 3])          # upright
            if i + j < s - 1:
                out.append([(i + 2 / 3), (j + 2 / 3), s - i - j - 4 / 3])      # inverted
    return np.array(out) / s
