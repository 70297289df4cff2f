"""The surface models of a slosh run (:mod:`.slosh`), a registry: each is a
:class:`SurfaceWindows`, the window loop of one model of the diaphragm (:mod:`.slosh_limp`,
:mod:`.slosh_diaphragm`), registered with :func:`register_surface`; and what they share with
the procedure: the liquid's :class:`Start` and the :class:`Contents`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fluid.container import SphericalTank

from ..lateral_compliance import Compliance
from ..lifecycle import Run

#: slosh.surface -> the :class:`SurfaceWindows` of that surface model
#: (:mod:`.slosh_limp`, :mod:`.slosh_diaphragm`)
SURFACES: dict[str, type] = {}


@dataclass
class Contents:
    """What the tank holds at the start: liquid volume (m^3), mass of the contents (kg,
    liquid and membrane), their centre of mass (3,) m and their static lateral compliance
    (:class:`fsi.lateral_compliance.Compliance`, s^2)."""

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
    (:mod:`fsi.checkpoint`)."""

    def __init__(self, window: float, n_windows: int):
        self.window, self.n_windows = window, n_windows
        self.k, self.stopped = 0, False

    @property
    def done(self) -> bool:
        return self.stopped or self.k >= self.n_windows

    def advance(self, run: Run) -> bool:
        """One window; False, doing nothing, once all are done or the run stopped."""
        if self.done:
            return False
        self.step(run)
        return True

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
