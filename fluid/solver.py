"""The fluid as a coupled caller sees it: advance a window, read interface pressure,
checkpoint, timings. Nothing here needs the caller to know FiPy or the cut-cell internals.

    solver = FluidSolver(model, interface)           # liquid at rest at t = 0
    solver.store_checkpoint()
    report = solver.advance(dt, interface_at_t_plus_dt)
    p = solver.interface_pressure(points, level)      # Pa, liquid side
    solver.restore_checkpoint()                       # implicit coupling: iterate the window

The interface passed to :meth:`advance` is its position and velocity at the *end* of the
window. With flow ports only, the liquid volume change it implies must equal the net port
inflow (the structure's volume constraint guarantees it); any rest is reported as
``volume_mismatch`` (m^3/s) and removed uniformly, and the pressure ``level`` (Pa, uniform)
is the caller's (see :mod:`fluid.model`).
"""
from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np

from .geometry import Geometry, compute_geometry, hold_liquid_centres
from .interface import Interface
from .model import FluidModel, FluidState
from . import free_surface as _free_surface  # noqa: F401  (registers the 'free' stepper)
from . import linear_surface as _linear_surface  # noqa: F401  (registers 'free-linear')
from .projection import ProjectionOperators, StepReport, initial_state, step
from .sampling import sample_cells


@dataclass
class Timings:
    """Accumulated wall time (s) per phase and the number of advances."""

    geometry: float = 0.0
    momentum: float = 0.0
    pressure: float = 0.0
    calls: int = 0
    last_call: float = 0.0

    def per_call(self) -> dict:
        n = max(self.calls, 1)
        return {"geometry": self.geometry / n, "momentum": self.momentum / n,
                "pressure": self.pressure / n}


@dataclass
class FluidSolver:
    """Stateful driver of the stateless projection stepper for one model."""

    model: FluidModel
    interface: Interface | None = None
    time: float = 0.0
    timings: Timings = field(default_factory=Timings)

    def __post_init__(self):
        self._ops = ProjectionOperators(self.model)
        geometry = self.geometry_for(self.interface)
        self.state: FluidState = initial_state(self.model, self._ops, geometry, self.time)
        self._checkpoint: FluidState | None = None
        self.last_report: StepReport | None = None

    def geometry_for(self, interface: Interface | None) -> Geometry:
        """Cut-cell geometry of the liquid bounded by ``interface`` (None: the full tank)."""
        return compute_geometry(self.model.grid, self.model.container, interface)

    @property
    def liquid_volume(self) -> float:
        """Liquid volume (m^3) on the grid now."""
        return self.state.geometry.liquid_volume

    def advance(self, dt: float, interface: Interface | None = None,
                liquid_centre: np.ndarray | None = None) -> StepReport:
        """Advance by ``dt`` (s) with the interface at the end of the step (None, or the
        interface already there: the same geometry, not computed again); ``liquid_centre``
        (n_cells,) bool, where given: the cells that carry the liquid's velocity whatever
        side of the interface their centre lies on (:func:`fluid.geometry.hold_liquid_centres`).
        """
        tic = _time.perf_counter()
        if interface is None or interface is self.interface:
            geometry = self.state.geometry
        else:
            geometry = self.geometry_for(interface)
        if liquid_centre is not None:
            geometry = hold_liquid_centres(geometry, liquid_centre, self.model.grid.spacing)
        toc = _time.perf_counter() - tic
        self.state, report = step(self.model, self._ops, self.state, geometry, dt)
        if interface is not None:
            self.interface = interface
        self.timings.geometry += toc
        self.timings.momentum += report.seconds_momentum
        self.timings.pressure += report.seconds_pressure
        self.timings.calls += 1
        self.timings.last_call = _time.perf_counter() - tic
        self.last_report = report
        return report

    def pressure_at(self, points: np.ndarray, level: float = 0.0,
                    cell_weight: np.ndarray | None = None) -> np.ndarray:
        """Total gauge pressure (n,) Pa at ``points`` (n, 3) m, from the liquid cells next to
        them: reduced pressure + rho b . x + ``level``; ``cell_weight`` (n_cells,): the cells
        fitted and their weights (:data:`fluid.sampling.CELL_WEIGHTS`; default: the liquid
        fraction where it is at least :data:`fluid.sampling.MIN_FRACTION`); the fit's kernel
        is the model's ``pressure_fit``."""
        points = np.asarray(points, dtype=float)
        reduced = sample_cells(self.model.grid, self.state.pressure,
                               self.state.geometry.cell_fraction, points,
                               cell_weight=cell_weight, kernel=self.model.pressure_fit)
        return reduced + self.model.body_potential(points, self.state.time) + level

    def velocity_at(self, points: np.ndarray) -> np.ndarray:
        """Liquid velocity (n, 3) m/s at ``points`` (n, 3) m, from the cells whose centre is
        in the liquid (a linear fit over the block around each point, so points just
        outside the liquid, e.g. on a free surface, get the linear extension); zero where no
        such cell is near."""
        points = np.asarray(points, dtype=float)
        g = self.model.grid
        weight = self.state.geometry.fluid_centre.astype(float)
        parts = [sample_cells(g, self.state.cell_velocity[:, a], weight, points, 0.5)
                 for a in range(g.dim)]
        out = np.zeros((len(points), 3))
        if g.axisymmetric:
            r = np.hypot(points[:, 0], points[:, 1])
            safe = np.where(r > 0, r, 1.0)
            out[:, 0] = parts[0] * np.where(r > 0, points[:, 0] / safe, 1.0)
            out[:, 1] = parts[0] * np.where(r > 0, points[:, 1] / safe, 0.0)
            out[:, 2] = parts[1]
        else:
            out[:] = np.stack(parts, axis=1)
        return np.nan_to_num(out)

    def interface_pressure(self, level: float = 0.0,
                           cell_weight: np.ndarray | None = None) -> np.ndarray:
        """Pressure (n,) Pa at the current interface points (liquid side), fitted from the
        cells of ``cell_weight`` (as :meth:`pressure_at`)."""
        if self.interface is None:
            raise ValueError("this fluid has no interface")
        return self.pressure_at(self.interface.points, level, cell_weight)

    def store_checkpoint(self):
        """Remember the current state and return it (states are immutable: a reference)."""
        self._checkpoint = (self.state, self.interface)
        return self._checkpoint

    def restore_checkpoint(self, checkpoint=None) -> None:
        """Return to ``checkpoint`` (default: the last stored one)."""
        checkpoint = checkpoint if checkpoint is not None else self._checkpoint
        if checkpoint is None:
            raise RuntimeError("restore_checkpoint before store_checkpoint")
        self.state, self.interface = checkpoint

    def velocity_magnitude_max(self) -> float:
        """Largest cell speed (m/s) among cells whose centre is in the liquid."""
        fluid = self.state.geometry.fluid_centre
        if not fluid.any():
            return 0.0
        return float(np.max(np.linalg.norm(self.state.cell_velocity[fluid], axis=1)))
