"""Adapters that make our solvers coupling participants (see :mod:`coupling.participant`).

Interface fields (flat float64): ``interface_points`` (3 n, m) and ``interface_velocities``
(3 n, m/s), the interface at the end of the window, written by the structure side;
``interface_pressure`` (n, Pa, liquid side) written by the fluid side.

The enclosed liquid (incompressibility dilemma, Kuettler, Foerster & Wall 2006): the fluid
sends its pressure without a uniform level; the membrane holds the liquid volume that the
ports have delivered and its multiplier is the level (``MembraneParticipant.level``).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from fluid.interface import Interface
from fluid.solver import FluidSolver
from structure.model import MembraneState
from structure.volume import liquid_volume
from structure.xpbd import XpbdModel, XpbdSettings, advance

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


def membrane_interface(model: XpbdModel, state: MembraneState) -> Interface:
    """The membrane as the fluid sees it: its nodes, its triangles (normals to the gas side,
    i.e. out of the liquid) and its node velocities."""
    return Interface(state.node_position, model.triangles, state.node_velocity)


class MembraneParticipant:
    """An XPBD membrane (:func:`structure.xpbd.advance`) seen by the coupling.

    Reads ``interface_pressure`` (n,) Pa at its nodes (liquid side, without the uniform
    level); writes ``interface_points`` and ``interface_velocities`` (3 n,). ``volume(t)`` is
    the liquid volume (m^3) the ports have delivered by time t (s); each window moves the
    liquid volume from its value at the window's start to ``volume(t + dt)``, and the uniform
    pressure level (Pa) that holds it is :attr:`level` afterwards. ``body_acceleration``:
    (3,) m/s^2 or a function of time returning it (tank frame).
    """

    name = "structure"
    write_fields = (POINTS, VELOCITIES)

    def __init__(self, model: XpbdModel, state: MembraneState, settings: XpbdSettings,
                 volume: Callable[[float], float], body_acceleration, level: float = 0.0):
        self.model = model
        self.state = state.copy()
        self.settings = settings
        self.volume = volume
        self.body_acceleration = body_acceleration
        self.level = float(level)

    def _body(self, time: float) -> np.ndarray:
        b = self.body_acceleration
        return np.asarray(b(time) if callable(b) else b, dtype=float)

    def _fields(self) -> dict:
        return {POINTS: self.state.node_position.ravel().copy(),
                VELOCITIES: self.state.node_velocity.ravel().copy()}

    def initial_data(self) -> dict:
        return self._fields()

    def solve_window(self, time: float, dt: float, data_in) -> dict:
        pressure = np.asarray(data_in[PRESSURE], dtype=float)
        start = liquid_volume(self.model.base, self.state.node_position)
        self.state, self.level, _ = advance(self.model, self.state, dt, pressure,
                                            self._body(time + dt), self.settings,
                                            (start, float(self.volume(time + dt))))
        return self._fields()

    def store_checkpoint(self):
        return self.state.copy(), self.level

    def restore_checkpoint(self, checkpoint) -> None:
        state, self.level = checkpoint
        self.state = state.copy()
