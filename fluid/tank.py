"""The spherical tank as the fluid sees it: container with port stub, grid over the tank, cell
spacing.

The tank is a sphere of radius R (m) centred at the origin with a port stub running down from
its bottom pole to the grid's bottom boundary, where the port condition acts. Cells are square
(cubic) of spacing h (m).
"""
from __future__ import annotations

import numpy as np

from .container import SphericalTank
from .grid import TankGrid, axisymmetric_grid, cartesian_grid
from .model import FluidModel


def tank_spacing(radius: float, cells: int, axisymmetric: bool) -> float:
    """Cell spacing h (m) of :func:`tank_grid` over a tank of ``radius`` (m) with ``cells``
    cells, without building the grid: R / (cells - 2) axisymmetric, 2 R / (cells - 3) 3-D.

    The grid lays out its cells with this h; its ``spacing`` attribute, the grid's width
    (cells h) divided by the cell count, can differ from it in the last bit."""
    if axisymmetric:
        return radius / (cells - 2)
    return 2 * radius / (cells - 3)


def tank_grid(radius: float, cells: int, axisymmetric: bool,
              stub_length: float | None = None, face_at: float | None = None) -> TankGrid:
    """Grid over a spherical tank of ``radius`` (m) with square cells and a port stub of
    ``stub_length`` (m; default two cells) below the bottom pole, the grid's bottom boundary
    (where the port condition acts) at its end.

    Axisymmetric: ``cells`` across the radius (r in [0, R + 2h]) and twice as many along z
    (64 -> the 64 x 128 benchmark grid). 3-D: ``cells`` along x and y (32 -> 32^3 with the
    default stub), the sphere spanning all but three of them, and along z as many as cover
    stub, sphere and one cell above it.

    ``face_at`` (m, 3-D only): the grid moves down by less than a cell (and gains a layer
    where the top needs it) so that a plane of its horizontal faces lies at this height. A
    level surface there is a plane of faces: its area is the faces' area and no cell holds
    part of it (:func:`fluid.modes.surface_modes` converges smoothly then; with the level
    anywhere between two centre planes lambda1 scatters by +-2 % on 24^3 cells)."""
    h = tank_spacing(radius, cells, axisymmetric)
    stub = 2 * h if stub_length is None else stub_length
    if face_at is not None:
        if axisymmetric:
            raise ValueError("face_at: a 3-D grid only")
        if not -radius < face_at < radius:
            raise ValueError(f"face_at: a height inside the tank, |z| < {radius} m, got "
                             f"{face_at}")
        below = int(np.ceil((face_at + radius + stub) / h - 1e-9))
        bottom = face_at - below * h
        half = 0.5 * cells * h
        layers = int(np.ceil((radius + h - bottom) / h - 1e-9))
        return cartesian_grid((-half, -half, bottom), (half, half, bottom + layers * h), cells)
    if axisymmetric:
        return axisymmetric_grid(cells * h, -radius - stub, -radius - 2 * h + 2 * cells * h,
                                 cells)
    half = 0.5 * cells * h
    return cartesian_grid((-half, -half, -radius - stub), (half, half, radius + h), cells)


def port_stub_volume(model: FluidModel) -> float:
    """Volume (m^3) of the port stub below the sphere on ``model``'s grid, from the sphere down
    to the grid's bottom boundary (:meth:`fluid.container.SphericalTank.stub_volume`)."""
    return model.container.stub_volume(model.grid.vertex_axes[-1][0])


def sphere_model(radius: float, grid: TankGrid, ports, body_acceleration,
                 density: float = 1000.0, viscosity: float = 1.0e-3,
                 port_radius_cells: float = 3.3, **options) -> FluidModel:
    """Liquid of ``density`` (kg/m^3) and ``viscosity`` (Pa s) in a spherical tank of
    ``radius`` (m) on ``grid``, with a bottom port stub of ``port_radius_cells`` cells in
    radius, openings ``ports`` and ``body_acceleration`` (3,) m/s^2 or a function of time (s)
    returning it (gravity minus the tank's acceleration, e.g. (0, 0, -g) at rest); ``options``
    go to :class:`fluid.model.FluidModel`."""
    tank = SphericalTank(radius, port_radius_cells * grid.spacing)
    return FluidModel(grid=grid, container=tank, density=density, viscosity=viscosity,
                      ports=tuple(ports), body_acceleration=body_acceleration, **options)
