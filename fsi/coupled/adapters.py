"""Adapters that make our solvers coupling participants (see :mod:`coupling.participant`).

Interface fields (flat float64): ``interface_points`` (3 n, m) and ``interface_velocities``
(3 n, m/s), the interface at the end of the window, written by the structure side;
``interface_pressure`` (n, Pa, liquid side) written by the fluid side.

The enclosed liquid (incompressibility dilemma, Kuettler, Foerster & Wall 2006): the fluid
sends its pressure without a uniform level; the membrane holds the liquid volume that the
ports have delivered and its multiplier is the level (``MembraneParticipant.level``).
"""
from __future__ import annotations

import logging
from dataclasses import replace
from typing import Callable

import numpy as np

from fluid.interface import Interface, is_closed
from fluid.sampling import CELL_WEIGHTS
from fluid.solver import FluidSolver
from structure.load import Load, StepInfo
from structure.model import MembraneState
from structure.newton.window import alpha_window
from structure.xpbd import WINDOW_SCHEMES, XpbdDivergence, XpbdModel, XpbdSettings, \
    quasi_static_step

from fsi.coupled.pressure_maps import node_fit

CENTRE_CELLS = ("iteration", "window")
"""``fluid.centre_cells``: which cells carry the liquid's velocity in a coupling window's
iterations: those whose centre is in the liquid at each iteration, or those of the window's
start, held (:func:`fluid.geometry.hold_liquid_centres`)."""
POINTS = "interface_points"
VELOCITIES = "interface_velocities"
PRESSURE = "interface_pressure"

log = logging.getLogger(__name__)


def _membrane_velocity(start: MembraneState, end: MembraneState, dt: float) -> np.ndarray:
    return end.node_velocity


def _window_mean_velocity(start: MembraneState, end: MembraneState, dt: float) -> np.ndarray:
    return (end.node_position - start.node_position) / dt


INTERFACE_VELOCITIES = {"membrane": _membrane_velocity, "window-mean": _window_mean_velocity}
"""The node velocities (n, 3) m/s the membrane sends with its window's end positions, by
name, ``f(start, end, dt)``: ``membrane``, its own velocity at the window's end (the last
substep's); ``window-mean``, (x_end - x_start)/dt, the velocity of a backward Euler liquid
step whose cut cells move from the window's start to its end."""


class FluidParticipant:
    """A :class:`fluid.solver.FluidSolver` seen by the coupling.

    ``level``: uniform pressure (Pa) added to the fluid's pressure, or a function of time
    returning it (the pressure level of an enclosed liquid with flow ports only, see
    :mod:`fluid.model`). ``surface``: how the partner's points and velocities become the
    fluid's interface (:class:`MembraneSurface`; default: the solver's interface moved to
    them); pressure is returned at the partner's points only, by ``pressure_map``
    (``map(solver, surface, level, cell_weight) -> (n,) Pa``,
    :data:`fsi.coupled.pressure_maps.PRESSURE_MAPS`; default: the fit at each node), from the cells
    that ``pressure_cells`` picks (a name in :data:`fluid.sampling.CELL_WEIGHTS`: chosen at
    every iteration, or at the window's start, when :meth:`store_checkpoint` records the
    liquid fraction); ``centre_cells`` (:data:`CENTRE_CELLS`): which cells carry the liquid's
    velocity in the window's iterations."""

    name = "fluid"
    write_fields = (PRESSURE,)

    def __init__(self, solver: FluidSolver, level: float | Callable[[float], float] = 0.0,
                 surface: "MembraneSurface | None" = None,
                 pressure_map: Callable | None = None, pressure_cells: str = "iteration",
                 centre_cells: str = "iteration"):
        if solver.interface is None:
            raise ValueError("a coupled fluid needs an interface")
        if pressure_cells not in CELL_WEIGHTS:
            raise ValueError(f"unknown pressure cells {pressure_cells!r}; allowed: "
                             f"{sorted(CELL_WEIGHTS)}")
        if centre_cells not in CENTRE_CELLS:
            raise ValueError(f"unknown centre cells {centre_cells!r}; allowed: "
                             f"{list(CENTRE_CELLS)}")
        self.centre_cells = centre_cells
        self.start_centre = None  # (n_cells,) liquid-centre cells at the window's start
        self.solver = solver
        self.level = level
        self.surface = surface
        self.pressure_map = pressure_map if pressure_map is not None else node_fit
        self.cell_weight = CELL_WEIGHTS[pressure_cells]
        self.start_fraction = None  # (n_cells,) liquid fraction at the window's start

    def _level(self, time: float) -> float:
        return float(self.level(time)) if callable(self.level) else float(self.level)

    def _pressure(self, time: float) -> np.ndarray:
        weight = self.cell_weight(self.solver.state.geometry.cell_fraction,
                                  self.start_fraction)
        if self.surface is None:
            return self.solver.interface_pressure(self._level(time), weight)
        return self.pressure_map(self.solver, self.surface, self._level(time), weight)

    def initial_data(self) -> dict:
        return {PRESSURE: self._pressure(self.solver.state.time)}

    def solve_window(self, time: float, dt: float, data_in) -> dict:
        points = np.asarray(data_in[POINTS]).reshape(-1, 3)
        velocities = np.asarray(data_in[VELOCITIES]).reshape(-1, 3)
        if self.surface is not None:
            interface = self.surface(points, velocities)
        else:
            interface = self.solver.interface.with_state(points, velocities)
        held = getattr(self, "start_centre", None)  # absent from an older code's checkpoint
        if held is None:
            self.solver.advance(dt, interface)
        else:
            self.solver.advance(dt, interface, held)
        return {PRESSURE: self._pressure(time + dt)}

    def store_checkpoint(self):
        self.start_fraction = self.solver.state.geometry.cell_fraction
        if getattr(self, "centre_cells", "iteration") == "window":
            self.start_centre = self.solver.state.geometry.fluid_centre
        return self.solver.store_checkpoint()

    def restore_checkpoint(self, checkpoint) -> None:
        self.solver.restore_checkpoint(checkpoint)


class MembraneSurface:
    """The membrane closed into the surface of the liquid, as the fluid sees it.

    The membrane's triangles (normals to the gas side, out of the liquid) and a fixed can
    through its rim ring: a flat annulus at the rim's height out to CAP_REACH R, a cylinder
    down to -CAP_REACH R and a bottom, all outside the tank and beyond any tank grid. The
    surface is closed, so the fluid takes the liquid side from its winding number, robust
    where folds touch or cross (:mod:`fluid.interface`); the liquid side contains the port
    stub below the tank. Called with the membrane's node positions and velocities (n, 3), it
    returns the :class:`fluid.interface.Interface` (membrane nodes first, can nodes at rest).
    ``volume``: where given, a function of the node positions (n, 3) m returning the liquid
    volume (m^3) the surface holds on the fluid's grid, carried by each interface (the cut
    cells are matched to it, :mod:`fluid.geometry`); a volume that is not > 0 raises
    :class:`structure.xpbd.XpbdDivergence` (the membrane has left the tank).
    """

    CAP_REACH = 4.0

    def __init__(self, model: XpbdModel,
                 volume: Callable[[np.ndarray], float] | None = None):
        base = model.base
        radius = base.radius
        rest = base.node_rest_position
        r = np.hypot(rest[:, 0], rest[:, 1])
        tol = 1e-9 * radius
        rim = np.flatnonzero((np.abs(rest[:, 2]) < tol) & (np.abs(r - radius) < tol))
        if len(rim) < 3:
            raise ValueError("the membrane has no rim ring on the equator (z = 0, r = R) to "
                             "close the liquid surface with")
        rim = rim[np.argsort(np.arctan2(rest[rim, 1], rest[rim, 0]))]
        n, m = len(rest), len(rim)
        angle = np.arctan2(rest[rim, 1], rest[rim, 0])
        reach = self.CAP_REACH * radius
        ring = np.stack([reach * np.cos(angle), reach * np.sin(angle), np.zeros(m)], axis=1)
        points = np.concatenate([ring, ring - [0.0, 0.0, reach], [[0.0, 0.0, -reach]]])
        rings = [rim, n + np.arange(m), n + m + np.arange(m)]
        pole = n + 2 * m
        k = np.arange(m)
        cap = [np.stack([a[k], b[k], b[(k + 1) % m]], 1) for a, b in zip(rings[:-1], rings[1:])]
        cap += [np.stack([a[k], b[(k + 1) % m], a[(k + 1) % m]], 1)
                for a, b in zip(rings[:-1], rings[1:])]
        cap.append(np.stack([rings[-1][k], np.full(m, pole), rings[-1][(k + 1) % m]], 1))
        cap = np.concatenate(cap)
        faces = np.concatenate([model.triangles, cap])
        if not is_closed(faces):
            faces = np.concatenate([model.triangles, cap[:, ::-1]])
        if not is_closed(faces):
            raise ValueError("the membrane's boundary is not its rim ring: cannot close the "
                             "liquid surface")
        self.n_points = n
        self.faces = faces
        self.cap_points = points
        self.volume = volume

    def __call__(self, node_position: np.ndarray, node_velocity: np.ndarray) -> Interface:
        points = np.concatenate([node_position, self.cap_points])
        velocities = np.concatenate([node_velocity, np.zeros_like(self.cap_points)])
        volume = None if self.volume is None else float(self.volume(node_position))
        if volume is not None and not (np.isfinite(volume) and volume > 0):
            raise XpbdDivergence(f"the membrane holds {volume:.4g} m^3 of liquid: it has left "
                                 f"the tank (diverged)")
        return Interface(points, self.faces, velocities, volume)

    def of(self, state: MembraneState) -> Interface:
        """The surface of a membrane state."""
        return self(state.node_position, state.node_velocity)


MEMBRANE_WINDOWS = {**WINDOW_SCHEMES, "generalised-alpha": alpha_window}
"""The membrane's window schemes, name -> ``f(model, state, load, dt, settings, history)`` ->
(state, StepInfo): XPBD's (:data:`structure.xpbd.WINDOW_SCHEMES`) and the implicit
generalised-alpha step on the tangent stiffness (:func:`structure.newton.window.alpha_window`,
whose settings are :class:`structure.newton.dynamics.AlphaSettings`)."""


class MembraneParticipant:
    """An XPBD membrane (:func:`structure.xpbd.step`) seen by the coupling.

    Reads ``interface_pressure`` (n,) Pa at its nodes (liquid side, without the uniform
    level); writes ``interface_points`` and ``interface_velocities`` (3 n,). ``volume(t)`` is
    the liquid volume (m^3) the ports have delivered by time t (s); each window moves the
    liquid volume from its value at the window's start to ``volume(t + dt)``, and the uniform
    pressure level (Pa) that holds it is :attr:`level` afterwards. ``body_acceleration``:
    (3,) m/s^2 or a function of time returning it (tank frame). ``scheme``: the window's
    time scheme, a name in :data:`structure.xpbd.WINDOW_SCHEMES` ('substeps', 'bdf2', which
    reads the state one window back: kept here and in the checkpoints, or 'quasi-static').
    ``velocity``: the node velocities sent, a name in :data:`INTERFACE_VELOCITIES`.
    ``liquid_density`` (kg/m^3): the liquid's pressure received at the points last sent is
    moved with each node along the hydrostatic gradient, p(x) = p + rho b . (x - x_sent), a
    field the membrane's solver evaluates where the node is (the quasi-static scheme does so
    every substep: the hydrostatic stiffness then lives in the membrane's solve, not in the
    coupling iteration); None: the received values as they are.

    Under 'quasi-static' each window's end is the membrane's equilibrium found by damped
    relaxation (:func:`structure.xpbd.quasi_static_step` with ``relaxed``: the static
    sweep's solve, so that a slow fill and the static model are one model; warm-started
    substeps, exact but slow to converge near a fold and liable to blow up there, made the
    thesis fill several times slower).  A window whose equilibrium is not reached in
    QUASI_STATIC_MAX_SUBSTEPS substeps, or one redone after its coupling failed
    (:meth:`with_inertia`), is done with the membrane's inertia instead ('substeps'), every
    iteration of it; its start time is in :attr:`dynamic_windows`. ``minimiser``: a
    :class:`structure.minimise.window.QuasiStaticMinimiser` that finds each quasi-static
    window's end by the minimisation statics instead (``coupling.quasi_static_solver``).
    """

    QUASI_STATIC_MAX_SUBSTEPS = 50_000
    SETTLED_SPEED = 1e-3  # m/s: after an inertial window, quasi-static again below this

    name = "structure"
    write_fields = (POINTS, VELOCITIES)
    # what a participant checkpointed before ``velocity`` existed sent: resumed, it goes on so
    velocity = staticmethod(_membrane_velocity)

    def __init__(self, model: XpbdModel, state: MembraneState, settings: XpbdSettings,
                 volume: Callable[[float], float], body_acceleration, level: float = 0.0,
                 scheme: str = "substeps", liquid_density: float | None = None,
                 velocity: str = "membrane", minimiser=None):
        if scheme not in MEMBRANE_WINDOWS:
            raise ValueError(f"unknown membrane window scheme {scheme!r}; allowed: "
                             f"{sorted(MEMBRANE_WINDOWS)}")
        if velocity not in INTERFACE_VELOCITIES:
            raise ValueError(f"unknown interface velocity {velocity!r}; allowed: "
                             f"{sorted(INTERFACE_VELOCITIES)}")
        self.model = model
        self.state = state.copy()
        self.settings = settings
        self.volume = volume
        self.body_acceleration = body_acceleration
        self.level = float(level)
        self.scheme = scheme
        self.liquid_density = liquid_density
        self.velocity = INTERFACE_VELOCITIES[velocity]
        if minimiser is not None and (scheme != "quasi-static" or liquid_density is None):
            raise ValueError("a minimiser solves quasi-static windows, with the liquid's "
                             "density")
        self.minimiser = minimiser
        self.history: tuple[MembraneState, float] | None = None
        self.sent = self.state.node_position.copy()
        self.dynamic_windows: list[float] = []
        self._guess = (np.nan, np.nan, None)  # (window start s, size s, its last end state)
        self._inertial_end = np.nan  # end time (s) of the last window done with inertia

    def _body(self, time: float) -> np.ndarray:
        b = self.body_acceleration
        return np.asarray(b(time) if callable(b) else b, dtype=float)

    def _fields(self, node_velocity: np.ndarray) -> dict:
        self.sent = self.state.node_position.copy()
        return {POINTS: self.state.node_position.ravel().copy(),
                VELOCITIES: np.array(node_velocity, dtype=float).ravel()}

    def initial_data(self) -> dict:
        return self._fields(self.state.node_velocity)

    def _pressure(self, received: np.ndarray, body: np.ndarray):
        """The node pressure (n,) Pa, or with ``liquid_density`` the field x -> (n,) Pa."""
        if self.liquid_density is None:
            return received
        rho, sent = self.liquid_density, self.sent.copy()
        return lambda x: received + rho * (x - sent) @ body

    def solve_window(self, time: float, dt: float, data_in) -> dict:
        body = self._body(time + dt)
        received = np.asarray(data_in[PRESSURE], dtype=float)
        start = self.state
        self.state, info = self._step(start, received, body, time, dt)
        self.history = (start, dt)
        self.level = info.pressure_level
        return self._fields(self.velocity(start, self.state, dt))

    def with_inertia(self, time: float) -> None:
        """The window starting at ``time`` (s) is done with the membrane's inertia."""
        if time not in self.dynamic_windows:
            self.dynamic_windows.append(time)

    def _inertial(self, start: MembraneState, time: float) -> bool:
        """Whether the window from ``time`` keeps the membrane's inertia: not quasi-static,
        marked so, or following an inertial window while the membrane still moves faster
        than SETTLED_SPEED."""
        if self.scheme != "quasi-static" or time in self.dynamic_windows:
            return True
        previous = time == self._inertial_end
        speed = float(np.linalg.norm(start.node_velocity, axis=1).max())
        if previous and speed > self.SETTLED_SPEED:
            self.with_inertia(time)
            return True
        return False

    def _step(self, start: MembraneState, received: np.ndarray, body: np.ndarray,
              time: float, dt: float):
        """The window by :attr:`scheme`, or with inertia where a quasi-static one fails
        (the received pressure as it is: the hydrostatic field is the quasi-static's)."""
        target = float(self.volume(time + dt))
        if self._inertial(start, time):
            self._inertial_end = time + dt
            scheme = self.scheme if self.scheme != "quasi-static" else "substeps"
            # the level held at the last window's end: the guess (XPBD's steps find their own)
            return MEMBRANE_WINDOWS[scheme](self.model, start,
                                          Load(received, body, volume_target=target,
                                               pressure_level=self.level), dt,
                                          self.settings, self.history)
        try:
            if self.minimiser is not None:
                return self._minimised(start, received, body, target, time, dt)
            load = Load(self._pressure(received, body), body, volume_target=target,
                        pressure_level=self.level)
            return self._quasi_static(start, load, time, dt)
        except XpbdDivergence as err:
            log.info("window from t = %g s: %s; done with the membrane's inertia", time, err)
            self.with_inertia(time)
            return self._step(start, received, body, time, dt)

    def _quasi_static(self, start: MembraneState, load: Load, time: float, dt: float):
        """The window's end in equilibrium by damped relaxation (the static sweep's solve),
        from the last iteration's end when this window was solved before (the same
        equilibrium, from nearer)."""
        guess = self._guess[2] if self._guess[:2] == (time, dt) else None
        out = quasi_static_step(
            self.model, start, load, dt,
            replace(self.settings, max_steps=self.QUASI_STATIC_MAX_SUBSTEPS), self.history,
            relaxed=True, guess=guess)
        self._guess = (time, dt, out[0])
        return out

    def _minimised(self, start: MembraneState, received: np.ndarray, body: np.ndarray,
                   target: float, time: float, dt: float):
        """The window's end in equilibrium by the minimisation statics
        (:mod:`structure.minimise.window`), from the last iteration's end when this window was
        solved before; :class:`structure.xpbd.XpbdDivergence` where its path stops short."""
        guess = self._guess[2] if self._guess[:2] == (time, dt) else None
        x0 = start.node_position
        state, info, _ = self.minimiser.solve(
            x0, received, self.sent, body, self.liquid_density, target, self.level,
            None if guess is None else guess.node_position)
        if not info.converged:
            raise XpbdDivergence(f"minimisation window: no equilibrium at {target:.6g} m^3 "
                                 f"(force ratio {info.force_ratio:.2e})")
        out = MembraneState(state.node_position, (state.node_position - x0) / dt)
        self._guess = (time, dt, out)
        return out, StepInfo(info.steps, info.pressure_level)

    def store_checkpoint(self):
        return self.state.copy(), self.level, self.history

    def restore_checkpoint(self, checkpoint) -> None:
        state, self.level, self.history = checkpoint
        self.state = state.copy()
