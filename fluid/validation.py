"""Validation cases of the immersed-boundary fluid, each with its closed-form oracle.

Used by the test suite, ``benchmarks/fluid_step.py`` and ``benchmarks/fluid_checks.py``.
Every case places its walls off the grid lines on purpose (immersed, not grid-aligned). Gravity
g (m/s^2) is an input of every case that has one.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from .container import UprightCylinder
from .grid import axisymmetric_grid
from .interface import Interface
from .model import FluidModel, Port
from .solver import FluidSolver
from .tank import sphere_model, tank_grid

#: fraction of a cell by which validation walls sit off the grid lines
OFF_GRID = 0.37


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
    an upright cylinder (immersed wall, radius off the grid lines) full of liquid under gravity
    ``gravity`` g (m/s^2, downwards), open to ``top_pressure`` at the top. Oracle:
    p(piston) - p(top) = rho (g + a) h, h the liquid depth (the extra rho a h is the added-mass
    pressure)."""

    gravity: float
    radius: float = 0.1
    depth: float = 0.3
    acceleration: float = 2.0
    density: float = 1000.0
    viscosity: float = 1.0e-3
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


def spherical_cap_volume(radius: float, z: float) -> float:
    """Volume (m^3) of the sphere below the plane at height z (centre at 0)."""
    d = radius + z
    return np.pi * d * d * (3 * radius - d) / 3.0


def sphere_cross_section(radius: float, z: float) -> float:
    """Area (m^2) of the sphere's horizontal section at height z."""
    return np.pi * (radius**2 - z**2)


# ------------------------------------------------------------------ the checks, measured

def hydrostatic_check(radius: float, axisymmetric: bool, cells: int, gravity: float,
                      steps: int = 100, density: float = 1000.0, level: float = 0.05) -> dict:
    """Membrane (a bowl) at rest in the immersed sphere under gravity g = ``gravity`` (m/s^2)
    and a pressure port holding the equivalent height ``level`` (m): largest relative error of
    p = rho g (h - z) at the membrane points and largest speed (m/s) after ``steps`` steps of
    1 ms."""
    grid = tank_grid(radius, cells, axisymmetric)
    port = Port("bottom", "pressure", density * gravity * (level - grid.lower[-1]))
    model = sphere_model(radius, grid, [port], density=density,
                         body_acceleration=(0.0, 0.0, -gravity))
    itf = bowl_meridian(radius, 0.3 * radius) if axisymmetric else \
        bowl_surface(radius, 0.3 * radius, 16)
    solver = FluidSolver(model, itf)
    for _ in range(steps):
        solver.advance(1e-3, itf)
    inside = np.hypot(itf.points[:, 0], itf.points[:, 1]) < radius
    p = solver.pressure_at(itf.points[inside])
    exact = density * gravity * (level - itf.points[inside, 2])
    return {"grid": list(grid.shape), "steps": steps,
            "max_relative_error": float(np.max(np.abs(p - exact) / np.abs(exact))),
            "max_speed_m_s": solver.velocity_magnitude_max()}


def piston_check(cells: int, gravity: float, steps: int = 50, dt: float = 1e-3) -> dict:
    """:class:`PistonCase` under gravity g = ``gravity`` (m/s^2) after ``steps`` steps of
    ``dt`` (s): largest relative error of rho (g + a) h over 8 points of the piston, and of
    its added-mass part rho a h."""
    case = PistonCase(gravity=gravity, cells_across=cells)
    model = case.model()
    solver = FluidSolver(model, case.piston(0.0))
    for k in range(1, steps + 1):
        solver.advance(dt, case.piston(k * dt))
    z = solver.interface.points[0, 2]
    pts = np.stack([np.linspace(0, 0.9 * case.radius, 8), np.zeros(8), np.full(8, z)], axis=1)
    err = float(np.max(np.abs(solver.pressure_at(pts) / case.oracle(model, steps * dt) - 1)))
    added = case.acceleration / (case.gravity + case.acceleration)
    return {"cells_across": cells, "max_relative_error": err,
            "max_error_of_added_mass_part": err / added}


def volume_check(radius: float, gravity: float, cells: int = 32, steps: int = 200,
                 flow: float = 1.0e-3, dt: float = 5e-3, start_height: float = -0.05) -> dict:
    """Port inflow ``flow`` (m^3/s) into the sphere under gravity g = ``gravity`` (m/s^2) with
    the membrane a plane rising at Q / A(z) (A the sphere's section): the liquid volume's
    departure from V0 + Q t relative to Q t, the largest |volume mismatch| / Q, and the
    largest continuity residual relative to Q / V0, over ``steps`` steps."""
    grid = tank_grid(radius, cells, True)
    model = sphere_model(radius, grid, [Port("bottom", "flow", flow)],
                         body_acceleration=(0.0, 0.0, -gravity))
    v_start = spherical_cap_volume(radius, start_height)

    def plane(t):
        z = brentq(lambda zz: spherical_cap_volume(radius, zz) - v_start - flow * t,
                   -radius, radius)
        return flat_interface(z, 1.1 * radius, flow / sphere_cross_section(radius, z), True,
                              False)

    solver = FluidSolver(model, plane(0.0))
    v0 = solver.liquid_volume
    mismatch = divergence = 0.0
    for k in range(1, steps + 1):
        report = solver.advance(dt, plane(k * dt))
        mismatch = max(mismatch, abs(report.volume_mismatch))
        divergence = max(divergence, report.divergence)
    return {"steps": steps,
            "relative_volume_error": float((solver.liquid_volume - v0) / (flow * steps * dt) - 1),
            "max_volume_mismatch_over_Q": mismatch / flow,
            "max_divergence_over_Q_per_V": divergence / (flow / v0)}


def poiseuille_error(cells: int, dt: float = 0.01) -> float:
    """:class:`PoiseuilleCase` after six viscous times: largest error of the profile at
    mid-length over its maximum."""
    case = PoiseuilleCase(cells_across=cells)
    model = case.model()
    solver = FluidSolver(model)
    for _ in range(int(6 * case.viscous_time / dt)):
        solver.advance(dt)
    g = model.grid
    mid = g.centre_axes[1][g.shape[1] // 2]
    sel = (np.abs(g.cell_centre[:, 1] - mid) < 0.25 * g.spacing) & \
        solver.state.geometry.fluid_centre
    exact = case.profile(model, g.cell_centre[sel, 0])
    return float(np.max(np.abs(solver.state.cell_velocity[sel, 1] - exact)) / exact.max())
