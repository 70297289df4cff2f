"""The run lifecycle every procedure shares (as pyro2's simulations share one)::

    run = Run(progress, total, frame_interval)   # the clock starts
    run.frame_due(k)                             # frame cadence: every interval, and the last
    run.record(group, record)                    # a frame: {dataset: scalar or array}
    run.progress(done, message)                  # fraction done = done / total, with a message
    run.stop(reason)                             # a run that ends early says why
    result = run.result(**attrs)                 # frames stacked per group, timing, stop reason

A procedure returns a :class:`RunResult`: named groups of frames (arrays with a leading frame
axis) that :mod:`fsi.io.output` writes as HDF5 groups, and run facts (attrs). Procedures never
write files or plot. Every result carries ``failure`` (empty, or why the run stopped early)
and every frame of the membrane the fields of :func:`membrane_frame`.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

from structure.volume import FillScale, liquid_volume, tank_volume

log = logging.getLogger(__name__)

Progress = Callable[[float, str], None]
"""progress(fraction_done in [0, 1], message)."""


@dataclass
class RunResult:
    """groups: {group name: {dataset name: array with leading frame axis}}; attrs: run facts."""

    groups: dict = field(default_factory=dict)
    attrs: dict = field(default_factory=dict)


def stack(records: list[dict]) -> dict:
    """Frame records (dicts with the same keys) -> {key: array with a leading frame axis}."""
    return {k: np.asarray([r[k] for r in records]) for k in records[0]}


def membrane_frame(setup, node_position: np.ndarray, pressure_level: float,
                   inversion: Optional[FillScale] = None) -> dict:
    """The fields every membrane frame carries: node_position (n, 3) m, tank_fraction
    V / (4/3 pi R^3), liquid_volume (m^3), pressure_level (Pa, uniform level at the tank
    centre) and equivalent_height (m, p_ref / (rho |b|)); where the thesis's App. J procedure
    is reproduced, on its full-``inversion`` scale, inversion_fraction too
    (:mod:`fsi.setup.fill`)."""
    volume = liquid_volume(setup.model, node_position)
    tank = tank_volume(setup.model.radius)
    out = dict(node_position=node_position.copy(), tank_fraction=volume / tank,
               liquid_volume=volume, pressure_level=float(pressure_level),
               equivalent_height=setup.liquid.equivalent_height(pressure_level))
    if inversion is not None:
        out["inversion_fraction"] = float(inversion.fill(volume))
    return out


class StopRequest:
    """A signal asking the running procedure to stop at the end of its current unit of work
    (window, step or fill): ``signal`` is its number, None while none came."""

    def __init__(self):
        self.signal: Optional[int] = None


STOP = StopRequest()
"""Set by ``fsi run``'s SIGINT/SIGTERM handler, read by :meth:`Run.progress`."""


class Interrupted(Exception):
    """Raised by :meth:`Run.progress` after a stop was requested: ``run`` is the
    :class:`Run` with the work done, ``signal`` the signal's number."""

    def __init__(self, run: "Run", signal: int):
        super().__init__(f"interrupted by signal {signal}")
        self.run, self.signal = run, signal


class Run:
    """One run of a procedure: ``total`` units of work (fills, steps or windows), frames
    every ``frame_interval`` units (and at the last), wall time from construction."""

    current: Optional["Run"] = None
    """The run most recently started (what a procedure stopped by a solver's error did)."""

    def __init__(self, progress: Progress, total: int, frame_interval: Optional[int] = None):
        Run.current = self
        self._progress = progress
        self.total = max(int(total), 1)
        self.frame_interval = frame_interval
        self.started = time.perf_counter()
        self.groups: dict[str, list[dict]] = {}
        self.failure = ""

    def elapsed(self) -> float:
        """Wall seconds since the run started."""
        return time.perf_counter() - self.started

    def resumed(self, checkpoint: dict) -> None:
        """The run continues from ``checkpoint`` (:mod:`fsi.io.checkpoint`): its records, and
        its clock counts the ``elapsed`` seconds of the run before it."""
        self.groups = checkpoint["groups"]
        self.started -= checkpoint.get("elapsed", 0.0)

    def frame_due(self, done: int) -> bool:
        """Whether a frame is recorded after ``done`` units of work."""
        return done % self.frame_interval == 0 or done == self.total

    def record(self, group: str, record: dict) -> None:
        self.groups.setdefault(group, []).append(record)

    def progress(self, done: float, message: str) -> None:
        """Report ``done`` units of work; raises :class:`Interrupted` when a stop was
        requested (:data:`STOP`): called after each unit is recorded, so the run stops
        between units."""
        self._progress(done / self.total, message)
        if STOP.signal is not None:
            raise Interrupted(self, STOP.signal)

    def stop(self, reason: str) -> None:
        """The run ends early: ``reason`` is logged and written as the result's ``failure``."""
        self.failure = reason
        log.error("the run stopped early: %s; writing what was done", reason)

    def result(self, groups: Optional[dict] = None, **attrs) -> RunResult:
        """:class:`RunResult` of ``groups`` (already stacked) and the recorded frames
        stacked per group, with ``attrs`` and ``failure``."""
        out = RunResult(groups=dict(groups or {}), attrs=dict(attrs))
        out.groups.update({name: stack(records) for name, records in self.groups.items()
                           if records})
        out.attrs["failure"] = self.failure
        return out
