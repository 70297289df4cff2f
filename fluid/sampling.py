"""Pressure at arbitrary points from the cell field, on the liquid side only (numba).

Each point gets the value at the point of a weighted least-squares linear fit over the liquid
cells (fraction >= ``min_fraction``) in the block of cells around it, weights
alpha / (d^2 + h^2). The fit is exact for a linear pressure (hydrostatic or uniformly
accelerated liquid) wherever the block has dim + 1 independent liquid cells; otherwise the
weighted mean is used.

The block is the 2 reach cells per axis whose centres bracket the point, so it moves by a cell
when the point crosses a plane of cell centres, and a cell at the block's edge enters or
leaves the fit with its full weight: the fitted value jumps (by about h^2 times the
pressure's curvature). Under the ``tapered`` kernel (:data:`FIT_KERNELS`, the scene key
``fluid.pressure_fit``) each weight is multiplied by prod_a (1 - (d_a / (reach h))^2)^2, which
is zero for every cell a block could gain or lose, so the fitted value is continuous in the
point's position (moving least squares with a compactly supported weight, Lancaster &
Salkauskas 1981); ``block`` keeps the plain weights.

Which cells a coupled interface's pressure is fitted from (:data:`CELL_WEIGHTS`, the scene
key ``fluid.pressure_cells``): a cell weight w (n_cells,) from the liquid fraction now and at
the coupling window's start,

* ``iteration``: w = alpha where alpha >= MIN_FRACTION, else 0, chosen anew at every call;
* ``window``: the cells with alpha >= MIN_FRACTION at the window's start, each weighted by its
  fraction now and faded linearly to 0 as that falls from MIN_FRACTION to MIN_FRACTION / 2
  (a cell drying within the window; a cell's pressure is barely constrained below that).
  Within a window's coupling iterations the map from the interface to the pressure is then
  continuous: under ``iteration`` a cell whose fraction sits at the threshold enters and
  leaves the fit from one iteration to the next, the nodes around it jump by kilopascals,
  and the iteration stalls on the jump (docs/notes/pressure-cells.md).
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from numba import njit

from .grid import TankGrid

JIT = dict(cache=True, nogil=True)
#: half-width of the block of cells searched around a point
SAMPLE_REACH_CELLS = 2
#: cells with a smaller liquid fraction are not used
MIN_FRACTION = 0.25
#: a point with no such cell within the block is sampled from a block twice as wide, up to this
MAX_REACH_CELLS = 8
#: ``fluid.pressure_fit`` name -> whether the fit's weights taper to zero at the block's edge
FIT_KERNELS = {"block": False, "tapered": True}


@njit(**JIT)
def _fit(points, lower, h, values, weights, reach, taper):
    n, dim = points.shape
    shape = values.shape
    out = np.empty(n)
    ata = np.empty((dim + 1, dim + 1))
    atb = np.empty(dim + 1)
    row = np.empty(dim + 1)
    idx = np.empty(3, dtype=np.int64)
    lo = np.empty(3, dtype=np.int64)
    hi = np.empty(3, dtype=np.int64)
    for p in range(n):
        ata[:] = 0.0
        atb[:] = 0.0
        wsum = 0.0
        vsum = 0.0
        count = 0
        for a in range(3):
            if a < dim:
                c = int(np.floor((points[p, a] - lower[a]) / h - 0.5))
                lo[a] = max(0, c - reach + 1)
                hi[a] = min(shape[a] - 1, c + reach)
            else:
                lo[a] = 0
                hi[a] = 0
        for i in range(lo[0], hi[0] + 1):
            idx[0] = i
            for j in range(lo[1], hi[1] + 1):
                idx[1] = j
                for k in range(lo[2], hi[2] + 1):
                    idx[2] = k
                    if dim == 2:
                        w0 = weights[i, j, 0]
                        v = values[i, j, 0]
                    else:
                        w0 = weights[i, j, k]
                        v = values[i, j, k]
                    if w0 <= 0.0:
                        continue
                    d2 = 0.0
                    row[0] = 1.0
                    fade = 1.0
                    for a in range(dim):
                        dx = lower[a] + (idx[a] + 0.5) * h - points[p, a]
                        row[a + 1] = dx / h
                        d2 += dx * dx
                        if taper:
                            q = dx / (reach * h)
                            fade *= max(0.0, 1.0 - q * q) ** 2
                    if fade <= 0.0:
                        continue
                    w = w0 * fade / (d2 / (h * h) + 1.0)
                    for r in range(dim + 1):
                        atb[r] += w * row[r] * v
                        for c in range(dim + 1):
                            ata[r, c] += w * row[r] * row[c]
                    wsum += w
                    vsum += w * v
                    count += 1
        if count == 0:
            out[p] = np.nan
            continue
        mean = vsum / wsum
        if count > dim:
            # the normal equations' symmetric matrix by its eigenpairs: one LAPACK call for
            # the solve and the condition number (lstsq and cond took two SVDs, 2.8x the time)
            eig, vec = np.linalg.eigh(ata)
            # reject a fit that extrapolates wildly (degenerate stencil: cond >= 1e8)
            if eig[0] > eig[-1] * 1e-8:
                value = 0.0
                for r in range(dim + 1):
                    proj = 0.0
                    for c in range(dim + 1):
                        proj += vec[c, r] * atb[c]
                    value += vec[0, r] * proj / eig[r]
                if np.isfinite(value):
                    out[p] = value
                    continue
        out[p] = mean
    return out


CELL_WEIGHTS: dict[str, Callable] = {}
"""``fluid.pressure_cells`` name -> weight(cell_fraction, start_fraction) -> (n_cells,) -:
the cells a pressure is fitted from and their weights (module doc); ``start_fraction`` is
the liquid fraction (n_cells,) at the coupling window's start, None outside a window."""


def register_cell_weight(name: str):
    """Decorator: register a cell weight under ``name``."""
    def register(func):
        CELL_WEIGHTS[name] = func
        return func
    return register


@register_cell_weight("iteration")
def threshold_weight(cell_fraction: np.ndarray, start_fraction: np.ndarray | None = None,
                     min_fraction: float = MIN_FRACTION) -> np.ndarray:
    """alpha where alpha >= ``min_fraction``, else 0 (n_cells,)."""
    return np.where(cell_fraction >= min_fraction, cell_fraction, 0)


@register_cell_weight("window")
def window_weight(cell_fraction: np.ndarray, start_fraction: np.ndarray | None) -> np.ndarray:
    """The cells with alpha >= MIN_FRACTION at the window's start, weighted by alpha now
    times min(1, (alpha - MIN_FRACTION / 2) / (MIN_FRACTION / 2)) (0 below MIN_FRACTION / 2);
    :func:`threshold_weight` outside a window (no ``start_fraction``)."""
    if start_fraction is None:
        return threshold_weight(cell_fraction)
    floor = 0.5 * MIN_FRACTION
    fade = np.clip((cell_fraction - floor) / floor, 0.0, 1.0)
    return np.where(start_fraction >= MIN_FRACTION, cell_fraction * fade, 0.0)


def sample_cells(grid: TankGrid, cell_values: np.ndarray, cell_fraction: np.ndarray,
                 points: np.ndarray, min_fraction: float = MIN_FRACTION,
                 cell_weight: np.ndarray | None = None, kernel: str = "block") -> np.ndarray:
    """Values (n,) at ``points`` (n, 3) m of a cell field (n_cells,), from liquid cells only.

    On an axisymmetric grid a point (x, y, z) is sampled at (hypot(x, y), z). A point with no
    liquid cell within ``SAMPLE_REACH_CELLS`` is sampled from a block twice as wide, then
    again, up to ``MAX_REACH_CELLS``; NaN where none lies within that. ``cell_weight``
    (n_cells,) -, where given, is each cell's weight in place of
    ``threshold_weight(cell_fraction, min_fraction=min_fraction)`` (0: not used); ``kernel``:
    a name in :data:`FIT_KERNELS`."""
    if kernel not in FIT_KERNELS:
        raise ValueError(f"pressure fit kernel must be one of {sorted(FIT_KERNELS)}, got "
                         f"{kernel!r}")
    taper = FIT_KERNELS[kernel]
    points = np.asarray(points, dtype=float)
    if grid.axisymmetric:
        coords = np.stack([np.hypot(points[:, 0], points[:, 1]), points[:, 2]], axis=1)
    else:
        coords = points
    lattice_values = np.empty(int(np.prod(grid.shape)))
    lattice_values[grid.cell_lattice] = cell_values
    lattice_weights = np.empty_like(lattice_values)
    lattice_weights[grid.cell_lattice] = (
        threshold_weight(cell_fraction, min_fraction=min_fraction) if cell_weight is None
        else cell_weight)
    shape = tuple(grid.shape) + ((1,) if grid.dim == 2 else ())
    coords = np.ascontiguousarray(coords)
    lower = np.asarray(grid.lower, dtype=float)
    values, weights = lattice_values.reshape(shape), lattice_weights.reshape(shape)
    out = _fit(coords, lower, grid.spacing, values, weights, SAMPLE_REACH_CELLS, taper)
    reach = SAMPLE_REACH_CELLS
    missing = np.isnan(out)
    while missing.any() and reach < MAX_REACH_CELLS:
        # a point in a thin liquid gap (under a fold, against the wall) on a fine grid
        reach *= 2
        out[missing] = _fit(np.ascontiguousarray(coords[missing]), lower, grid.spacing, values,
                            weights, reach, taper)
        missing = np.isnan(out)
    return out
