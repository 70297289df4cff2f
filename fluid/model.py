"""Fluid model (what does not change during a run) and fluid state (what does).

Pressure convention. The liquid has uniform density, so a uniform body acceleration b(t)
(gravity minus the tank's acceleration, tank frame) is the gradient of rho b . x and only
shifts the pressure: the solver advances the *reduced* pressure p_red = p - rho b . x and the
total gauge pressure is

    p(x, t) = p_red(x, t) + rho b(t) . x + level                                   (Pa)

with ``level`` a uniform pressure. With a pressure port, p_red is fixed by the port. With
flow ports only, the pressure level of an enclosed liquid is undetermined (the
incompressibility dilemma): p_red is gauged to 0 in the cell next to the first port and the
caller supplies ``level`` (the Lagrange multiplier of the structure's volume constraint).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .geometry import Geometry
from .grid import TankGrid
from .sampling import FIT_KERNELS

PORT_KINDS = ("flow", "pressure")


def _as_function(value) -> Callable[[float], float]:
    return value if callable(value) else (lambda t, v=float(value): v)


@dataclass(frozen=True)
class Port:
    """An opening of the liquid through one side of the grid ('bottom' or 'top').

    kind 'flow': ``value`` is the volume flow into the liquid (m^3/s), a number or a function
    of time (s), spread uniformly over the port's open faces; kind 'pressure': ``value`` is
    the total gauge pressure there (Pa), and the velocity leaves with zero normal gradient."""

    side: str
    kind: str
    value: object = 0.0

    def __post_init__(self):
        if self.kind not in PORT_KINDS:
            raise ValueError(f"port kind must be one of {PORT_KINDS}, got {self.kind!r}")
        if self.side not in ("bottom", "top"):
            raise ValueError(f"port side must be 'bottom' or 'top', got {self.side!r}")

    def at(self, time: float) -> float:
        """Port value at ``time`` (s): m^3/s (flow) or Pa (pressure)."""
        return float(_as_function(self.value)(time))


FACE_MEMORIES = ("ring", "every-face")
"""The moving-wall step's faces that keep their history (:attr:`FluidModel.face_memory`)."""


@dataclass(frozen=True)
class FluidModel:
    """Incompressible laminar liquid on an immersed-boundary grid.

    grid: the fixed grid; container: level set of the tank (see :mod:`fluid.container`);
    density kg/m^3; viscosity: dynamic, Pa s (0: inviscid);
    body_acceleration: (3,) m/s^2 or a function of time (s) returning it (gravity minus the
    tank's acceleration, e.g. (0, 0, -g) at rest; on an axisymmetric grid only its z
    component may be non-zero); ports: openings;
    convection: keep the nonlinear term (off for Stokes / linear acoustics-free checks);
    momentum_solver, pressure_solver: names in :data:`fluid.linear.LINEAR_SOLVERS`
    (``auto`` for the pressure: the fastest measured for the grid, see
    :func:`fluid.linear.pressure_solver_for`);
    pressure_tolerance: relative residual of the pressure solve;
    interface_condition: 'wall' (the interface is a moving wall: its motion is given, the
    liquid's pressure on it is the answer), 'free' (a free surface at the gas pressure: the
    liquid's velocity at it is the answer, :mod:`fluid.free_surface`) or 'free-linear' (the
    same linearised: the mean surface fixed, its elevation a state,
    :mod:`fluid.linear_surface`);
    assembly: who builds the linear systems, a name in :data:`fluid.systems.ASSEMBLIES`
    ('direct': laid out once, refilled each step; 'fipy': FiPy's terms, rebuilt each step;
    the two give the same matrices, see :mod:`fluid.assembly`);
    time_scheme: the moving-wall step's time derivative, a name in
    :data:`fluid.time_schemes.TIME_SCHEMES` ('euler': backward Euler; 'bdf2': second-order
    backward differences; the free surface's step has its own, :mod:`fluid.free_surface`);
    face_memory: which faces of the moving-wall step keep their own velocity's history
    (Choi 1999's memory term), a name in :data:`FACE_MEMORIES`: 'ring' (the wetted faces
    between two wall-centred cells only; every other face re-interpolated from the cells each
    step, Rhie-Chow) or 'every-face' (every inner face wetted before and after the step; see
    :mod:`fluid.projection`). The free surface's step keeps every face's history whatever
    this says;
    pressure_fit: the weights of the pressure's fit at points (:meth:`FluidSolver.pressure_at
    <fluid.solver.FluidSolver.pressure_at>`), a name in :data:`fluid.sampling.FIT_KERNELS`:
    'block' (alpha / (d^2 + h^2) over the block of cells around the point) or 'tapered' (the
    same times a factor that vanishes at the block's edge: continuous in the point's position).
    """

    grid: TankGrid
    container: object
    density: float
    viscosity: float
    body_acceleration: object
    ports: tuple = ()
    convection: bool = True
    momentum_solver: str = "bicgstab-jacobi"
    pressure_solver: str = "auto"
    pressure_tolerance: float = 1e-10
    assembly: str = "direct"
    interface_condition: str = "wall"
    time_scheme: str = "euler"
    face_memory: str = "ring"
    pressure_fit: str = "block"

    def __post_init__(self):
        if self.pressure_fit not in FIT_KERNELS:
            raise ValueError(f"pressure_fit must be one of {sorted(FIT_KERNELS)}, got "
                             f"{self.pressure_fit!r}")
        if self.face_memory not in FACE_MEMORIES:
            raise ValueError(f"face_memory must be one of {FACE_MEMORIES}, got "
                             f"{self.face_memory!r}")
        if not self.density > 0:
            raise ValueError(f"density must be > 0 kg/m^3, got {self.density}")
        if not self.viscosity >= 0:
            raise ValueError(f"viscosity must be >= 0 Pa s, got {self.viscosity}")
        object.__setattr__(self, "ports", tuple(self.ports))
        b = self.body_acceleration_at(0.0)
        if self.grid.axisymmetric and (b[0] != 0 or b[1] != 0):
            raise ValueError("an axisymmetric grid allows body_acceleration along z only, got "
                             f"{b.tolist()} m/s^2 at t = 0")

    def body_acceleration_at(self, time: float) -> np.ndarray:
        """b(t) (3,) m/s^2."""
        b = self.body_acceleration(time) if callable(self.body_acceleration) \
            else self.body_acceleration
        b = np.asarray(b, dtype=float)
        if b.shape != (3,) or not np.all(np.isfinite(b)):
            raise ValueError(f"body_acceleration must be 3 finite numbers (m/s^2), got {b!r}")
        return b

    def body_potential(self, points: np.ndarray, time: float) -> np.ndarray:
        """rho b(t) . x (Pa) at points (n, 3) m, the hydrostatic part of the pressure."""
        return self.density * (np.asarray(points, dtype=float) @ self.body_acceleration_at(time))

    def grid_points(self, coords: np.ndarray) -> np.ndarray:
        """Grid coordinates (n, dim) -> 3-D points (n, 3) (r, z) -> (r, 0, z)."""
        coords = np.asarray(coords, dtype=float)
        if self.grid.axisymmetric:
            return np.stack([coords[:, 0], np.zeros(len(coords)), coords[:, 1]], axis=1)
        return coords


@dataclass(frozen=True)
class FluidState:
    """time s; cell_velocity (n_cells, dim) m/s (r, z or x, y, z components);
    face_velocity (n_faces,) m/s along FiPy's face normal; pressure (n_cells,) reduced
    pressure p_red (Pa, see module doc); geometry: the liquid region at ``time``;
    previous: the state one step earlier (its own ``previous`` dropped), which multistep
    time schemes read (:mod:`fluid.time_schemes`); None at the start; surface_height (k,) m:
    a linearised free surface's displacement along its outward normal at each of its faces
    (:mod:`fluid.linear_surface`), None for every other step."""

    time: float
    cell_velocity: np.ndarray
    face_velocity: np.ndarray
    pressure: np.ndarray
    geometry: Geometry
    previous: "FluidState | None" = None
    surface_height: np.ndarray | None = None
