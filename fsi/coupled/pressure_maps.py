"""How the liquid's pressure reaches the membrane's nodes (registry, ``fluid.pressure_map``).

The membrane takes a pressure p_i per node and applies it on the node's area vector,
F_i = p_i a_i with a_i = dV/dx_i = sum over its triangles of A n / 3 (:mod:`structure.load`).
The liquid has one pressure per cut cell. A map turns the cells' pressure into the (n,) Pa
the membrane reads, without the uniform level's part that the caller adds. Each is a
function ``map(solver, surface, level, cell_weight=None) -> (n,) Pa`` of the fluid solver
(:class:`fluid.solver.FluidSolver`, its interface the membrane's closed surface) and the
:class:`fsi.coupled.adapters.MembraneSurface`, fitting from the cells of ``cell_weight``
(:data:`fluid.sampling.CELL_WEIGHTS`; None: the liquid fraction where it is at least
:data:`fluid.sampling.MIN_FRACTION`):

* ``node-fit``: the value at each node of a weighted least-squares plane through the liquid
  cells around it (:func:`fluid.sampling.sample_cells`): exact for a linear pressure,
  collocated at the nodes (the default);
* ``surface-mean``: that fit at the quadrature points of the membrane's triangles, averaged
  to each node with its hat function, p_i = int N_i p dA / int N_i dA (a consistent
  mapping in preCICE's words, evaluated as a Galerkin mean: p_i a_i is then int N_i p n dA
  wherever the sheet is flat around the node);
* ``cell-mean``: the same mean of each quadrature point's own cell's pressure (piecewise
  constant over the cut cells, plus the body potential rho b . x evaluated at the point):
  the pressure whose work on the sheet is what the cut cells' volume change does in the
  liquid's continuity equation, the conservative side of the pair. A point whose cell holds
  less liquid than :data:`fluid.sampling.MIN_FRACTION` of it (with ``cell_weight``: whose
  cell has no weight) takes the fit instead: such a cell's pressure is extrapolated from its
  neighbours or barely constrained (with every cell that holds any liquid taken, the 1 ms
  BDF2 run of the half-full diaphragm diverged at t = 0.29 s).

Quadrature: each triangle cut into QUADRATURE_LEVELS^2 similar triangles, one point at
each centroid, weight A / QUADRATURE_LEVELS^2.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from fluid.sampling import MIN_FRACTION

#: each membrane triangle is cut into this many squared similar triangles for the quadrature
QUADRATURE_LEVELS = 3

PRESSURE_MAPS: dict[str, Callable] = {}
"""``fluid.pressure_map`` name -> map(solver, surface, level, cell_weight=None) -> node
pressure (n,) Pa."""


def register_pressure_map(name: str):
    """Decorator: register a pressure map under ``name``."""
    def register(func):
        PRESSURE_MAPS[name] = func
        return func
    return register


def subdivision_barycentres(levels: int) -> np.ndarray:
    """Barycentric coordinates (levels^2, 3) of the centroids of the levels^2 similar
    triangles that cut a triangle, each of area A / levels^2."""
    out = []
    for i in range(levels):
        for j in range(levels - i):
            out.append(((3 * i + 1) / (3 * levels), (3 * j + 1) / (3 * levels)))
            if i + j < levels - 1:
                out.append(((3 * i + 2) / (3 * levels), (3 * j + 2) / (3 * levels)))
    b = np.array(out)
    return np.column_stack([1.0 - b.sum(axis=1), b])


def membrane_quadrature(points: np.ndarray, triangles: np.ndarray, levels: int):
    """Quadrature of the triangles (m, 3) over ``points`` (n, 3) m: the points (m q, 3) m
    and each one's weight on each vertex of its triangle, N_v(x_q) A / q, as (m, q, 3) m^2."""
    bary = subdivision_barycentres(levels)
    corners = points[triangles]                                      # (m, 3, 3)
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                         corners[:, 2] - corners[:, 0]), axis=1)
    quad = np.einsum("qv,mvk->mqk", bary, corners).reshape(-1, 3)
    weight = (area[:, None, None] / len(bary)) * bary[None]
    return quad, weight


def _node_mean(n: int, triangles: np.ndarray, weight: np.ndarray, quad_pressure: np.ndarray,
               fallback: Callable[[], np.ndarray]) -> np.ndarray:
    """int N_i p dA / int N_i dA per node (n,); ``fallback()`` (n,) where a node has no area
    (evaluated only then: it is a second fit of the whole interface)."""
    p = quad_pressure.reshape(weight.shape[:2])
    num, den = np.zeros(n), np.zeros(n)
    for v in range(3):
        np.add.at(num, triangles[:, v], np.sum(weight[:, :, v] * p, axis=1))
        np.add.at(den, triangles[:, v], np.sum(weight[:, :, v], axis=1))
    has = den > 0
    out = np.empty(n) if has.all() else np.array(fallback(), dtype=float)
    out[has] = num[has] / den[has]
    return out


def _membrane_triangles(surface) -> np.ndarray:
    """The surface's triangles on membrane nodes only (the can closing it left out)."""
    faces = surface.faces
    return faces[np.all(faces < surface.n_points, axis=1)]


@register_pressure_map("node-fit")
def node_fit(solver, surface, level: float, cell_weight=None) -> np.ndarray:
    return solver.interface_pressure(level, cell_weight)[:surface.n_points]


@register_pressure_map("surface-mean")
def surface_mean(solver, surface, level: float, cell_weight=None) -> np.ndarray:
    n, triangles = surface.n_points, _membrane_triangles(surface)
    quad, weight = membrane_quadrature(solver.interface.points, triangles, QUADRATURE_LEVELS)
    return _node_mean(n, triangles, weight, solver.pressure_at(quad, level, cell_weight),
                      lambda: node_fit(solver, surface, level, cell_weight))


@register_pressure_map("cell-mean")
def cell_mean(solver, surface, level: float, cell_weight=None) -> np.ndarray:
    n, triangles = surface.n_points, _membrane_triangles(surface)
    quad, weight = membrane_quadrature(solver.interface.points, triangles, QUADRATURE_LEVELS)
    model, state = solver.model, solver.state
    cell = model.grid.cell_of(quad)
    wet = (cell >= 0)
    wet[wet] = (state.geometry.cell_fraction[cell[wet]] >= MIN_FRACTION if cell_weight is None
                else cell_weight[cell[wet]] > 0)
    p = np.empty(len(quad))
    p[wet] = (state.pressure[cell[wet]] + model.body_potential(quad[wet], state.time)
              + level)
    if not wet.all():  # a point in a cell with little or no liquid: the fit there
        p[~wet] = solver.pressure_at(quad[~wet], level, cell_weight)
    return _node_mean(n, triangles, weight, p,
                      lambda: node_fit(solver, surface, level, cell_weight))
