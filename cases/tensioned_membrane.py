"""A tensioned membrane on the liquid of an upright cylinder, membrane and liquid coupled in
the time domain through :mod:`coupling`: the first closed form of the coupled stack's
dynamics.

A flat sheet of uniform tension T and areal density mu, pinned at the wall of an upright
cylinder (radius a) and lying on its liquid (depth h), is pushed sideways with the tank (a
sin^2 lateral pulse of the body acceleration) and left to swing. Its first antisymmetric
mode is Bauer's hydroelastic one, the Rayleigh-Ritz series of
:mod:`fsi.analysis.membrane_series` (with the sheet's own mass, m = mu / (rho a)).

The participants:

- the sheet: :mod:`structure.tensioned` on the nodes of the liquid grid's columns inside the
  wall, Newmark's trapezoidal rule, the liquid's volume held by a uniform pressure
  (:class:`SheetParticipant`; writes the interface points and velocities, reads the
  pressure);
- the liquid: :class:`fluid.solver.FluidSolver` on the cut-cell cylinder under the sheet as a
  moving wall (the ``wall`` step, its time scheme ``TIME_SCHEME``, no convective term: the
  linear liquid of the series), the sheet closed into a height surface
  (:class:`fsi.slosh.limp.HeightSurface`, the nodes outside the wall at the level), its
  pressure fitted at the sheet's nodes (:class:`fsi.coupled.adapters.FluidParticipant`).

They are coupled implicit-serial (sheet first), IQN-ILS on the pressure, windows of
``WINDOWS_PER_PERIOD`` per period of the series' mode. lambda = omega^2 a / g comes from the
free decay of the sheet's first moment sum A_i x_i w_i after the pulse
(:func:`fsi.slosh.analysis.fit_free_decay`).
"""
from __future__ import annotations

import time as _time
from dataclasses import dataclass

import numpy as np

from coupling import AccelerationSettings, ConvergenceMeasure, CouplingSettings, run
from fluid.container import UprightCylinder
from fluid.grid import cartesian_grid
from fluid.model import FluidModel
from fluid.solver import FluidSolver
from fsi.analysis.membrane_series import pinned_membrane_limit
from fsi.constants import STANDARD_GRAVITY, WATER_DENSITY
from fsi.coupled.adapters import POINTS, PRESSURE, VELOCITIES, FluidParticipant
from fsi.slosh.analysis import fit_free_decay
from fsi.slosh.limp import HeightSurface
from structure.tensioned import (MembraneMotion, TensionedMembrane, at_rest, newmark_step,
                                 tensioned_membrane)

RADIUS = 0.15
"""a (m): the cylinder's radius."""
AREAL_DENSITY = 1.2
"""mu (kg/m^2): a rubber sheet 1.2 mm thick at 1000 kg/m^3, a hundredth of the liquid's
added mass per area in the first mode."""
TIME_SCHEME = "bdf2"
"""The liquid's moving-wall step (:data:`fluid.time_schemes.TIME_SCHEMES`): second order,
its numerical damping O((omega dt)^3)."""
WINDOWS_PER_PERIOD = 100
PERIODS = 4.0
"""Simulated periods of the series' mode after the pulse."""
PULSE_PERIODS = 0.25
"""The lateral pulse's duration in periods of the series' mode."""
PULSE_ACCELERATION = 0.05
"""The pulse's peak lateral acceleration over g: a swing of a small fraction of a cell."""
PRESSURE_LIMIT = 1e-4
"""The coupling's convergence limit: the pressure's change over one iteration, relative to
rho g a (a 1e-4 of the pressure a wave of the tank's radius carries)."""
MAX_ITERATIONS = 60


@dataclass
class SheetParticipant:
    """The tensioned sheet seen by the coupling: writes the sheet's node positions (at the
    ``level``, m, plus the displacement) and velocities, reads the liquid's pressure there,
    less ``rest_pressure`` (n,) Pa (the liquid's at rest under the flat sheet)."""

    model: TensionedMembrane
    state: MembraneMotion
    level: float
    rest_pressure: np.ndarray
    name: str = "membrane"
    write_fields: tuple = (POINTS, VELOCITIES)

    def fields(self) -> dict:
        n = self.model.n_nodes
        points = np.column_stack([self.model.plan, self.level + self.state.displacement])
        velocities = np.zeros((n, 3))
        velocities[:, 2] = self.state.velocity
        return {POINTS: points.ravel(), VELOCITIES: velocities.ravel()}

    def initial_data(self) -> dict:
        return self.fields()

    def solve_window(self, time: float, dt: float, data_in) -> dict:
        pressure = np.asarray(data_in[PRESSURE]) - self.rest_pressure
        self.state = newmark_step(self.model, self.state, pressure, dt)
        return self.fields()

    def store_checkpoint(self):
        return self.state

    def restore_checkpoint(self, checkpoint) -> None:
        self.state = checkpoint


class SheetSurface:
    """The sheet's nodes closed into the liquid's interface: a height surface over the
    liquid grid's columns, the nodes outside the wall held at the level; ``pressure``, the
    liquid's fitted pressure at the sheet's nodes (:class:`FluidParticipant`'s map)."""

    def __init__(self, heights: HeightSurface, inside: np.ndarray, level: float):
        self.heights = heights
        self.inside = inside  # (n_surface_nodes,) bool: the sheet's nodes
        self.level = level
        self.n_points = int(inside.sum())
        self.points = None

    def __call__(self, points: np.ndarray, velocities: np.ndarray):
        z = np.full(self.heights.n_nodes, self.level)
        z[self.inside] = points[:, 2]
        v = np.zeros((self.heights.n_nodes, 3))
        v[self.inside] = velocities
        self.points = points
        return self.heights.interface(z.reshape(self.heights.shape), v)

    @staticmethod
    def pressure(solver, surface: "SheetSurface", level: float, cell_weight=None):
        return solver.pressure_at(surface.points, level, cell_weight)


@dataclass(frozen=True)
class Outcome:
    """One coupled run: ``lambda1`` = omega^2 a / g and ``zeta`` of the sheet's free decay,
    the ``series`` value it is checked against, the mean and largest coupling
    ``iterations`` per window, the windows that did not converge, wall ``seconds``."""

    gamma: float
    depth_ratio: float
    cells: int
    lambda1: float
    zeta: float
    series: float
    mean_iterations: float
    max_iterations: int
    unconverged: int
    seconds: float

    @property
    def error(self) -> float:
        return self.lambda1 / self.series - 1.0


def cylinder_grid(radius: float, depth: float, cells: int):
    """The 3-D grid of ``cells`` per axis over an upright cylinder of ``radius`` (m) filled
    ``depth`` (m) deep, its level z = 0 a plane of faces: 1.5 cells beyond the wall on each
    side, two below the bottom, three above the level."""
    h = 2 * radius / (cells - 3)
    half = 0.5 * cells * h
    below = int(np.ceil(depth / h)) + 2
    return cartesian_grid((-half, -half, -below * h), (half, half, 3 * h), cells)


def couple(gamma: float, depth_ratio: float, cells: int, periods: float = PERIODS,
           windows_per_period: int = WINDOWS_PER_PERIOD) -> Outcome:
    """The coupled run at Gamma = T / (rho g a^2) = ``gamma``, depth h = ``depth_ratio`` a,
    on ``cells`` cells across the cylinder's box (module doc)."""
    tic = _time.perf_counter()
    a, rho, g = RADIUS, WATER_DENSITY, STANDARD_GRAVITY
    depth = depth_ratio * a
    tension = gamma * rho * g * a**2
    series = pinned_membrane_limit(gamma, depth_ratio, AREAL_DENSITY / (rho * a))
    period = 2 * np.pi / np.sqrt(series * g / a)
    dt = period / windows_per_period
    pulse = PULSE_PERIODS * period
    peak = PULSE_ACCELERATION * g

    def body(t):
        lateral = peak * np.sin(np.pi * t / pulse) ** 2 if t < pulse else 0.0
        return np.array([-lateral, 0.0, -g])

    grid = cylinder_grid(a, depth, cells)
    model = FluidModel(grid=grid, container=UprightCylinder(a, -depth, 1.0), density=rho,
                       viscosity=0.0, body_acceleration=body, convection=False,
                       time_scheme=TIME_SCHEME)
    heights = HeightSurface(grid, bottom=-4 * depth)
    lattice = heights.plan.reshape(heights.shape + (2,))
    sheet = tensioned_membrane(lattice[:, 0, 0], lattice[0, :, 1], a, tension, AREAL_DENSITY)
    inside = np.hypot(heights.plan[:, 0], heights.plan[:, 1]) < a
    if not np.allclose(heights.plan[inside], sheet.plan):
        raise RuntimeError("the sheet's nodes are not the height surface's inside the wall")
    surface = SheetSurface(heights, inside, 0.0)
    flat = np.column_stack([sheet.plan, np.zeros(sheet.n_nodes)])
    solver = FluidSolver(model, surface(flat, np.zeros_like(flat)))
    fluid = FluidParticipant(solver, surface=surface, pressure_map=SheetSurface.pressure)
    rest = SheetSurface.pressure(solver, surface, 0.0)
    membrane = SheetParticipant(sheet, at_rest(sheet), 0.0, rest)
    settings = CouplingSettings(
        scheme="implicit-serial", acceleration="iqn-ils",
        acceleration_settings=AccelerationSettings(),
        measures=[ConvergenceMeasure(PRESSURE, "absolute",
                                     PRESSURE_LIMIT * rho * g * a * np.sqrt(sheet.n_nodes))],
        max_iterations=MAX_ITERATIONS, on_max_iterations="accept", extrapolation_order=1)
    n_windows = int(round((periods + PULSE_PERIODS) * windows_per_period))
    times, moment = [], []

    def on_window(window, data):
        times.append(window.time + dt)
        moment.append(float(sheet.area @ (sheet.plan[:, 0] * membrane.state.displacement)))

    log = run(membrane, fluid, settings, dt, n_windows, on_window=on_window)
    fit = fit_free_decay(np.array(times), np.array(moment), start=pulse + 0.25 * period)
    iterations = [w.iterations for w in log.windows]
    return Outcome(gamma, depth_ratio, cells, float(fit.omega**2 * a / g), float(fit.zeta),
                   series, float(np.mean(iterations)), int(max(iterations)),
                   sum(not w.converged for w in log.windows), _time.perf_counter() - tic)
