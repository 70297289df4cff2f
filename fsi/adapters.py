"""Adapters that make our solvers coupling participants (see :mod:`coupling.participant`).

Interface fields (flat float64): ``interface_points`` (3 n, m) and ``interface_velocities``
(3 n, m/s), the interface at the end of the window, written by the structure side;
``interface_pressure`` (n, Pa, liquid side) written by the fluid side.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from fluid.solver import FluidSolver

POINTS = "interface_points"
VELOCITIES = "interface_velocities"
PRESSURE = "interface_pressure"


class FluidParticipant:
    """A :class:`fluid.solver.FluidSolver` seen by the coupling.

    ``level``: uniform pressure (Pa) added to the fluid's pressure, or a function of time
    returning it (the pressure level of an enclosed liquid with flow ports only, see
    :mod:`fluid.model`)."""

    name = "fluid"
    write_fields = (PRESSURE,)

    def __init__(self, solver: FluidSolver, level: float | Callable[[float], float] = 0.0):
        if solver.interface is None:
            raise ValueError("a coupled fluid needs an interface")
        self.solver = solver
        self.level = level

    def _level(self, time: float) -> float:
        return float(self.level(time)) if callable(self.level) else float(self.level)

    def initial_data(self) -> dict:
        return {PRESSURE: self.solver.interface_pressure(self._level(self.solver.state.time))}

    def solve_window(self, time: float, dt: float, data_in) -> dict:
        shape = self.solver.interface.points.shape
        interface = self.solver.interface.with_state(
            np.asarray(data_in[POINTS]).reshape(shape),
            np.asarray(data_in[VELOCITIES]).reshape(shape))
        self.solver.advance(dt, interface)
        return {PRESSURE: self.solver.interface_pressure(self._level(time + dt))}

    def store_checkpoint(self):
        return self.solver.store_checkpoint()

    def restore_checkpoint(self, checkpoint) -> None:
        self.solver.restore_checkpoint(checkpoint)
