"""Validation cases of the immersed-boundary fluid, each with its closed-form oracle.

Used by the test suite, ``benchmarks/fluid_step.py`` and ``benchmarks/fluid_checks.py``.
Every case places its walls off the grid lines on purpose (immersed, not grid-aligned).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .container import SphericalTank, UprightCylinder
from .grid import TankGrid, axisymmetric_grid, cartesian_grid
from .interface import Interface
from .model import FluidModel, Port

#: fraction of a cell by which validation walls sit off the grid lines
OFF_GRID = 0.37


def tank_grid(radius: float, cells: int, axisymmetric: bool) -> TankGrid:
    """Grid over a spherical tank of ``radius`` (m) with square cells and two cells of port
    stub below the bottom pole.

    Axisymmetric: ``cells`` across the radius (r in [0, R + 2h]) and twice as many along z
    (64 -> the 64 x 128 benchmark grid). 3-D: ``cells`` along each axis (32 -> 32^3), the
    sphere spanning all but three of them."""
    if axisymmetric:
        h = radius / (cells - 2)
        return axisymmetric_grid(cells * h, -radius - 2 * h, -radius - 2 * h + 2 * cells * h,
                                 cells)
    h = 2 * radius / (cells - 3)
    half = 0.5 * cells * h
    z0 = -radius - 2 * h
    return cartesian_grid((-half, -half, z0), (half, half, z0 + cells * h), cells)


def bowl_meridian(radius: float, sag: float, n: int = 41, velocity=(0.0, 0.0)) -> Interface:
    """Axisymmetric membrane z = -sag (1 - r^2/R^2) from the tank wall (slightly beyond it) to
    the axis, liquid below (normal up). ``velocity``: uniform (v_r, v_z) m/s."""
    r = np.linspace(1.02 * radius, 0.0, n)
    z = -sag * (1.0 - np.minimum(r, radius) ** 2 / radius**2)
    points = np.stack([r, np.zeros(n), z], axis=1)
    vel = np.tile([velocity[0], 0.0, velocity[1]], (n, 1))
    return Interface(points, np.stack([np.arange(n - 1), np.arange(1, n)], axis=1), vel)


def bowl_surface(radius: float, sag: float, n: int = 24) -> Interface:
    """Triangulated membrane z = -sag (1 - (x^2 + y^2)/R^2) on a square lattice covering the
    tank, liquid below (normals up)."""
    s = np.linspace(-1.05 * radius, 1.05 * radius, n + 1)
    x, y = np.meshgrid(s, s, indexing="ij")
    rr = np.minimum(x**2 + y**2, radius**2)
    z = -sag * (1.0 - rr / radius**2)
    points = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return Interface(points, faces, np.zeros_like(points))


def flat_interface(z: float, r_max: float, velocity: float, axisymmetric: bool,
                   liquid_above: bool) -> Interface:
    """Horizontal plane at height z (m) moving at ``velocity`` (m/s, along z), spanning
    r <= r_max; the liquid above or below."""
    if axisymmetric:
        r = np.array([0.0, r_max]) if liquid_above else np.array([r_max, 0.0])
        points = np.stack([r, np.zeros(2), np.full(2, z)], axis=1)
        faces = np.array([[0, 1]])
    else:
        s = np.array([-r_max, r_max])
        points = np.array([[s[0], s[0], z], [s[1], s[0], z], [s[1], s[1], z], [s[0], s[1], z]])
        faces = np.array([[0, 2, 1], [0, 3, 2]]) if liquid_above else np.array([[0, 1, 2], [0, 2, 3]])
    vel = np.zeros_like(points)
    vel[:, 2] = velocity
    return Interface(points, faces, vel)


@dataclass(frozen=True)
class PistonCase:
    """Rigid piston accelerating at ``acceleration`` (m/s^2) upwards from rest at the bottom of
    an upright cylinder (immersed wall, radius off the grid lines) full of liquid, open to
    ``top_pressure`` at the top. Oracle: p(piston) - p(top) = rho (g + a) h, h the liquid
    depth (the extra rho a h is the added-mass pressure)."""

    radius: float = 0.1
    depth: float = 0.3
    acceleration: float = 2.0
    density: float = 1000.0
    viscosity: float = 1.0e-3
    gravity: float = 9.81
    cells_across: int = 32
    start_height: float = 0.01

    def model(self) -> FluidModel:
        h = self.radius / (self.cells_across - 2 + OFF_GRID)
        grid = axisymmetric_grid(self.cells_across * h, 0.0, self.start_height + self.depth,
                                 self.cells_across)
        top = grid.lower[1] + grid.shape[1] * grid.spacing
        return FluidModel(grid=grid, container=UprightCylinder(self.radius, -1.0, top + 1.0),
                          density=self.density, viscosity=self.viscosity,
                          ports=(Port("top", "pressure", 0.0),),
                          body_acceleration=(0.0, 0.0, -self.gravity))

    def piston(self, time: float) -> Interface:
        z = self.start_height + 0.5 * self.acceleration * time**2
        return flat_interface(z, 1.5 * self.radius, self.acceleration * time, True, True)

    def oracle(self, model: FluidModel, time: float) -> float:
        """p(piston) (Pa) at ``time``."""
        top = model.grid.lower[1] + model.grid.shape[1] * model.grid.spacing
        z = self.start_height + 0.5 * self.acceleration * time**2
        return self.density * (self.gravity + self.acceleration) * (top - z)


@dataclass(frozen=True)
class PoiseuilleCase:
    """Steady flow in a pipe of ``radius`` (m, immersed wall off the grid lines) driven by a
    pressure drop between the bottom and top ports. Oracle (Hagen-Poiseuille):
    u_z(r) = G (R^2 - r^2) / (4 mu), G = dp / L."""

    radius: float = 0.01
    length: float = 0.04
    viscosity: float = 1.0
    density: float = 1000.0
    pressure_drop: float = 100.0
    cells_across: int = 16

    def model(self) -> FluidModel:
        h = self.radius / (self.cells_across + OFF_GRID)
        grid = axisymmetric_grid(h * (self.cells_across + 3), 0.0, self.length,
                                 self.cells_across + 3)
        return FluidModel(grid=grid, container=UprightCylinder(self.radius, -1.0, 1.0),
                          density=self.density, viscosity=self.viscosity,
                          ports=(Port("bottom", "pressure", self.pressure_drop),
                                 Port("top", "pressure", 0.0)),
                          body_acceleration=(0.0, 0.0, 0.0), convection=False)

    def profile(self, model: FluidModel, r: np.ndarray) -> np.ndarray:
        length = model.grid.shape[1] * model.grid.spacing
        gradient = self.pressure_drop / length
        return gradient * (self.radius**2 - r**2) / (4 * self.viscosity)

    @property
    def viscous_time(self) -> float:
        """R^2 / nu (s)."""
        return self.radius**2 * self.density / self.viscosity


def sphere_model(radius: float, grid: TankGrid, ports, density: float = 1000.0,
                 viscosity: float = 1.0e-3, body_acceleration=(0.0, 0.0, -9.81),
                 port_radius_cells: float = 3.3, **options) -> FluidModel:
    """Spherical tank on ``grid`` with a bottom port stub of ``port_radius_cells`` cells."""
    tank = SphericalTank(radius, port_radius_cells * grid.spacing)
    return FluidModel(grid=grid, container=tank, density=density, viscosity=viscosity,
                      ports=tuple(ports), body_acceleration=body_acceleration, **options)


def spherical_cap_volume(radius: float, z: float) -> float:
    """Volume (m^3) of the sphere below the plane at height z (centre at 0)."""
    d = radius + z
    return np.pi * d * d * (3 * radius - d) / 3.0


def sphere_cross_section(radius: float, z: float) -> float:
    """Area (m^2) of the sphere's horizontal section at height z."""
    return np.pi * (radius**2 - z**2)
