"""The surface models of a slosh run (:mod:`fsi.procedures.slosh`), a registry: each is a
:class:`SurfaceWindows`, the window loop of one model of the diaphragm (:mod:`.slosh_limp`,
:mod:`.slosh_diaphragm`), registered with :func:`register_surface`; and what they share with
the procedure: the liquid's :class:`Start` and the :class:`Contents`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fluid.container import SphericalTank

from fsi.slosh.lateral_compliance import Compliance
from fsi.lifecycle import Run

#: slosh.surface -> the :class:`SurfaceWindows` of that surface model
#: (:mod:`.slosh_limp`, :mod:`.slosh_linear`, :mod:`.slosh_diaphragm`)
SURFACES: dict[str, type] = {}

DIVERGED_ENERGY_FACTOR = 10.0
"""A slosh run stops when the contents' kinetic energy exceeds this many times what the start
and the tank's motion can give them (:meth:`SurfaceWindows.set_energy_scale`): its windows
diverged (measured: BDF2 windows on the N = 14 diaphragm at 2 ms reached 1e11 J, and ran on
to the end time)."""


@dataclass
class Contents:
    """What the tank holds at the start: liquid volume (m^3), mass of the contents (kg,
    liquid and membrane), their centre of mass (3,) m and their static lateral compliance
    (:class:`fsi.slosh.lateral_compliance.Compliance`, s^2)."""

    volume: float
    mass: float
    centre: np.ndarray
    compliance: Compliance


def register_surface(name: str):
    """Decorator: register a surface model's :class:`SurfaceWindows` under ``name``."""
    def deco(cls):
        SURFACES[name] = cls
        return cls
    return deco


class SurfaceWindows:
    """A surface model's windows in a slosh run, between two of them: ``k`` of ``n_windows``
    done. A subclass builds the start in ``__init__(setup, start, body, run, window,
    n_windows)`` and records its ``windows`` record at t = 0 in the run, runs one window in
    :meth:`step` (recording the next) and gives the surface's data and the
    :class:`Contents` from :meth:`finish`. Pickled with the run's records it is a checkpoint
    (:mod:`fsi.io.checkpoint`)."""

    def __init__(self, window: float, n_windows: int):
        self.window, self.n_windows = window, n_windows
        self.k, self.stopped = 0, False
        self.energy_scale = None  # J, see set_energy_scale
        self.start_facts = {}  # result attributes of the surface's start

    def set_energy_scale(self, mass: float, radius: float, body, stored: float = 0.0) -> None:
        """What the start and the tank's motion can give the contents, in J: ``stored`` (the
        start's elastic energy, J) plus the work of the largest body acceleration ``body(t)``
        (3,) m/s^2 over the windows' ends on the contents' ``mass`` (kg) moved across the
        tank's diameter (``radius`` m). A bound, not an estimate: a slosh holds far less."""
        times = self.window * np.arange(self.n_windows + 1)
        peak = max(float(np.linalg.norm(body(t))) for t in times)
        self.energy_scale = mass * peak * 2.0 * radius + stored

    @classmethod
    def check(cls, scene) -> None:
        """Raise :class:`fsi.registry.SceneError` naming the key when this surface model
        cannot run ``scene``; before the run starts."""

    @property
    def done(self) -> bool:
        return self.stopped or self.k >= self.n_windows

    def advance(self, run: Run) -> bool:
        """One window; False, doing nothing, once all are done or the run stopped."""
        if self.done:
            return False
        self.step(run)
        self._check_energy(run)
        return True

    def _check_energy(self, run: Run) -> None:
        """Stop the run when the last window's kinetic energy (liquid and membrane) exceeds
        ``DIVERGED_ENERGY_FACTOR`` times :attr:`energy_scale`."""
        if self.stopped or self.energy_scale is None:
            return
        windows = run.groups["windows"]
        last = windows[-1]
        kinetic = last["liquid_kinetic_energy"] + last.get("membrane_kinetic_energy", 0.0)
        if not kinetic <= DIVERGED_ENERGY_FACTOR * self.energy_scale:
            unconverged = sum(1 for w in windows if not w.get("converged", True))
            hint = (f" ({unconverged} window(s) accepted unconverged before it: where the "
                    f"folds snap, shorter windows (slosh.window) can follow them)"
                    if unconverged else "")
            self.stop(run, f"the contents' kinetic energy {kinetic:.3g} J at t = "
                           f"{last['time']:.4f} s exceeds {DIVERGED_ENERGY_FACTOR:g} times what "
                           f"the start and the tank's motion can give them "
                           f"({self.energy_scale:.3g} J): the windows diverged{hint}")

    def stop(self, run: Run, reason: str) -> None:
        """The windows end early: ``reason`` is the run's failure."""
        self.stopped = True
        run.stop(reason)

    def step(self, run: Run) -> None:
        raise NotImplementedError

    def finish(self) -> tuple[dict, Contents]:
        raise NotImplementedError


@dataclass
class Start:
    """The liquid at rest: tank, level z0 (m), centre of mass (3,) m."""

    tank: SphericalTank
    level: float
    centre: np.ndarray
