"""Liquid geometry on the fixed grid at one instant: cut fractions, cell classes, wall data.

The liquid is inside the container and on the liquid side of the interface (if any):
phi = max(phi_container, phi_interface) < 0, evaluated on the vertex lattice (for the exact
cut fractions of :mod:`fluid.cutcell`) and on the cell-centre lattice (for the cell classes
and the wall distance used by the viscous immersed boundary).

Where the interface says what liquid volume it holds (``Interface.liquid_volume``, e.g. a
membrane's exact enclosed volume), its level set is shifted by one constant c (m) along its
normal so that the cut cells hold exactly that: the piecewise-linear zero set of the lattice
misses a curved or folded interface's volume at second order in h (1 % of the liquid at 16^3
cells with the diaphragm along the upper wall), and that error changes with the shape, so the
discrete liquid volume would drift from what the ports delivered. The shift is the global
volume correction of level-set methods (a uniform normal displacement of the interface, as
in Chang, Hou, Merriman & Osher 1996, J. Comput. Phys. 124); it is found by the secant method
from c = 0 (the held volume is smooth and nearly linear in c, so a few cut-cell passes do),
or, where that does not converge within half a cell, by Brent's method on the half-cell
bracket, and recorded (``Geometry.interface_shift``); beyond half a cell it stops there,
logged.
"""
from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq, root_scalar

from . import cutcell
from .grid import TankGrid
from .interface import Interface, lattice_distance

log = logging.getLogger(__name__)

#: band (in cells) around the interface where the exact distance is evaluated
DISTANCE_BAND_CELLS = 2.5
#: largest shift of the interface's level set (in cells) to match its liquid volume
MAX_SHIFT_CELLS = 0.5
#: the shift is found to this many cells (the held volume to the interface's area times it)
SHIFT_TOLERANCE_CELLS = 1e-9
#: the secant search's second point (in cells) and its iterations at most before Brent's
SHIFT_SECANT_STEP_CELLS = 1e-2
SHIFT_SECANT_ITERATIONS = 8


@dataclass(frozen=True)
class Geometry:
    """Cut-cell description of the liquid region.

    cell_fraction (n_cells,): liquid volume fraction alpha; face_fraction (n_faces,): wetted
    fraction beta of each face; centre_level (n_cells,): phi at the cell centre (m, < 0 in
    the liquid); wall_velocity (n_cells, 3): velocity of the nearest wall (m/s; the interface's
    where it is the nearer boundary, zero at the tank wall); liquid_volume: sum alpha V (m^3);
    interface_level (n_cells,): the interface's own signed distance at the cell centre (m,
    < 0 on the liquid side; far from it +-1e3 h; -1e3 h everywhere without an interface);
    container_cell_fraction (n_cells,), container_face_fraction (n_faces,): the fractions of
    the container alone (a free surface is not a wall: its cells keep the container's);
    interface_shift: the constant (m) added to the interface's level set so that the cut cells
    hold its stated liquid volume (> 0: the interface moved into the liquid; 0 without one).
    """

    cell_fraction: np.ndarray
    face_fraction: np.ndarray
    centre_level: np.ndarray
    wall_velocity: np.ndarray
    liquid_volume: float
    interface_level: np.ndarray | None = None
    container_cell_fraction: np.ndarray | None = None
    container_face_fraction: np.ndarray | None = None
    interface_shift: float = 0.0

    @property
    def fluid_centre(self) -> np.ndarray:
        """(n_cells,) bool: the cell centre lies in the liquid (velocity unknowns live here)."""
        return self.centre_level < 0.0


HELD_LEVEL_CELLS = 1e-6
"""A held cell whose centre has crossed the interface keeps this distance (in cells) on its
held side (:func:`hold_liquid_centres`)."""


def hold_liquid_centres(geometry: Geometry, liquid_centre: np.ndarray, spacing: float) \
        -> Geometry:
    """``geometry`` with the cells of ``liquid_centre`` (n_cells,) bool as its liquid-centre
    cells and no others: a cell whose centre has crossed the interface keeps its side, its
    ``centre_level`` set HELD_LEVEL_CELLS h on that side (m). Which cells carry the liquid's
    velocity (and which hold the wall's) is then fixed, so the step is continuous in the
    interface's position; the fractions stay the interface's own. The cut-cell method's
    cell classes change discontinuously where a centre crosses the interface (a "fresh"
    cell), and a coupling iteration whose fixed point sits at such a crossing cannot
    converge past the jump."""
    held = HELD_LEVEL_CELLS * spacing
    level = np.where(liquid_centre, np.minimum(geometry.centre_level, -held),
                     np.maximum(geometry.centre_level, held))
    return replace(geometry, centre_level=level)


def _lattice_coords(axes):
    return np.meshgrid(*axes, indexing="ij")


@lru_cache(maxsize=8)
def _container_lattices(grid: TankGrid, container):
    """The container's level set on the vertex and centre lattices and, on a 3-D grid, its
    cut fractions alone (cells, faces per axis): fixed for a run, computed once."""
    phi_v = container.level_set(_lattice_coords(grid.vertex_axes))
    phi_c = container.level_set(_lattice_coords(grid.centre_axes))
    for array in (phi_v, phi_c):
        array.setflags(write=False)
    dry = np.full(phi_v.shape, -1.0)
    if grid.axisymmetric:
        r, z = grid.vertex_axes
        faces = cutcell.face_fractions_2d(r, z, phi_v, dry, True)
        return phi_v, phi_c, cutcell.cell_fractions_2d(r, z, phi_v, dry, True), \
            (faces[1], faces[0])
    x, y, z = grid.vertex_axes
    return phi_v, phi_c, cutcell.cell_fractions_3d(x, y, z, phi_v, dry), \
        cutcell.face_fractions_3d(x, y, z, phi_v, dry)


@lru_cache(maxsize=8)
def _container_fractions(grid: TankGrid, container):
    """The container's own cell (n_cells,) and face (n_faces,) fractions, read-only."""
    _, _, cells_alone, faces_alone = _container_lattices(grid, container)
    cells = grid.lattice_to_cells(cells_alone)
    faces = grid.lattice_to_faces(faces_alone)
    for array in (cells, faces):
        array.setflags(write=False)
    return cells, faces


def compute_geometry(grid: TankGrid, container, interface: Interface | None) -> Geometry:
    """Geometry of the liquid in ``container`` bounded by ``interface`` (None: tank full)."""
    h = grid.spacing
    phi_v, phi_c, cells_alone, faces_alone = _container_lattices(grid, container)
    wall_c = np.zeros(phi_c.shape + (3,))
    shift = 0.0
    itf_v = np.full(phi_v.shape, -1.0)
    itf_c = np.full(phi_c.shape, -1e3 * h)
    if interface is not None:
        band = DISTANCE_BAND_CELLS * h
        lower_v = [a[0] for a in grid.vertex_axes]
        lower_c = [a[0] for a in grid.centre_axes]
        # the flood fill stays inside the tank: outside it the two sides of a membrane
        # clamped on the wall connect
        d_v, _ = lattice_distance(interface, lower_v, [h] * grid.dim, phi_v.shape, band,
                                  barrier=phi_v > 0.0)
        d_c, vel_c = lattice_distance(interface, lower_c, [h] * grid.dim, phi_c.shape, band,
                                      barrier=phi_c > 0.0)
        # outside the band only the sign matters (no cut cell has a vertex there)
        itf_v = np.where(np.isfinite(d_v), d_v, np.sign(d_v) * 1e3 * h)
        d_c = np.where(np.isfinite(d_c), d_c, np.sign(d_c) * 1e3 * h)
        if interface.liquid_volume is not None:
            shift = _volume_shift(grid, phi_v, itf_v, cells_alone, interface.liquid_volume)
            itf_v = itf_v + shift
            d_c = d_c + shift
        itf_c = d_c
        interface_wins = d_c > phi_c
        wall_c = np.where(interface_wins[..., None], vel_c, 0.0)
        phi_c = np.maximum(phi_c, d_c)
    if grid.axisymmetric:
        r, z = grid.vertex_axes
        alpha = _lattice_cell_fractions(grid, phi_v, itf_v, cells_alone)
        faces = cutcell.face_fractions_2d(r, z, phi_v, itf_v, True)
        # face_fractions_2d returns (faces normal to z, faces normal to r)
        beta = grid.lattice_to_faces((faces[1], faces[0]))
    else:
        x, y, z = grid.vertex_axes
        alpha = _lattice_cell_fractions(grid, phi_v, itf_v, cells_alone)
        beta = grid.lattice_to_faces(cutcell.face_fractions_3d(x, y, z, phi_v, itf_v,
                                                               faces_alone))
    alpha_cells = grid.lattice_to_cells(alpha)
    phi_cells = grid.lattice_to_cells(phi_c)
    wall_cells = wall_c.reshape(-1, 3)[grid.cell_lattice]
    volume = float((alpha_cells * grid.cell_volume).sum() * grid.volume_factor())
    container_cells, container_faces = _container_fractions(grid, container)
    return Geometry(alpha_cells, beta, phi_cells, wall_cells, volume,
                    grid.lattice_to_cells(itf_c), container_cells, container_faces, shift)


def _lattice_cell_fractions(grid: TankGrid, phi_v, itf_v, cells_alone) -> np.ndarray:
    """The liquid fraction of each lattice cell where the container's (phi_v) and the
    interface's (itf_v) vertex level sets are both negative."""
    if grid.axisymmetric:
        r, z = grid.vertex_axes
        return cutcell.cell_fractions_2d(r, z, phi_v, itf_v, True)
    x, y, z = grid.vertex_axes
    return cutcell.cell_fractions_3d(x, y, z, phi_v, itf_v, cells_alone)


def _volume_shift(grid: TankGrid, phi_v, itf_v, cells_alone, volume: float) -> float:
    """The constant c (m, |c| <= MAX_SHIFT_CELLS h) for which the cut cells of phi_v and
    itf_v + c hold ``volume`` (m^3), c to SHIFT_TOLERANCE_CELLS h: the secant method from 0
    and SHIFT_SECANT_STEP_CELLS h (about five cut-cell passes), else Brent's method on the
    half-cell bracket (the held volume falls monotonically with c). Where half a cell does
    not reach it (an interface that is not that volume's boundary on this grid, e.g. a
    coupling iteration's trial shape through the tank wall) the shift stops there and says
    so in the log: the geometry's ``liquid_volume`` then shows the miss."""
    weight = grid.cell_volume * grid.volume_factor()

    def excess(c: float) -> float:
        alpha = _lattice_cell_fractions(grid, phi_v, itf_v + c, cells_alone)
        return float((grid.lattice_to_cells(alpha) * weight).sum()) / volume - 1.0

    reach = MAX_SHIFT_CELLS * grid.spacing
    tolerance = SHIFT_TOLERANCE_CELLS * grid.spacing
    with warnings.catch_warnings():  # a flat excess (no interface in the tank) is not converged
        warnings.simplefilter("ignore", RuntimeWarning)
        secant = root_scalar(excess, method="secant", x0=0.0,
                             x1=SHIFT_SECANT_STEP_CELLS * grid.spacing, xtol=tolerance, rtol=0.0,
                             maxiter=SHIFT_SECANT_ITERATIONS)
    if secant.converged and abs(secant.root) < reach:
        return float(secant.root)
    low, high = excess(-reach), excess(reach)
    if not low >= 0.0 >= high:
        log.warning("the cut cells cannot hold the interface's liquid volume %.6g m^3 within "
                    "%g cell of it (they hold %.6g .. %.6g of it): shifted %g cell", volume,
                    MAX_SHIFT_CELLS, 1 + high, 1 + low, MAX_SHIFT_CELLS if high > 0 else
                    -MAX_SHIFT_CELLS)
        return reach if high > 0.0 else -reach
    if low == 0.0 or high == 0.0:
        return -reach if low == 0.0 else reach
    return float(brentq(excess, -reach, reach, xtol=tolerance,
                        rtol=4 * np.finfo(float).eps))
