"""The whole axisymmetric fill and drain of a diaphragm: both legs through the requested tank
fractions (:mod:`~structure.axisymmetric.fill_drain`), the stability table of each by
circumferential wave number and the onset of folding on each
(:mod:`~structure.axisymmetric.folding`),
with the time each part took.

The drain starts at the fill's end on the branch the fill reached after its last snap; that
branch is stable at every fraction the fill visited on it, so the drain retraces it (its
states there are the fill's) down to the fill's last landing, and is followed on from there
by :func:`~structure.axisymmetric.fill_drain.leg`, through its own snaps. Where the drain
holds the fill's state its stability table is the fill's, not computed again.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Callable, Optional, Sequence

import numpy as np

from .fill_drain import Leg, LegState, leg, volume_load
from .folding import WAVE_NUMBERS, Onset, harmonic_table, onset_of_folding, stability_table
from .loads import AxisymmetricLoad
from .model import ShellOfRevolution
from .solve import equilibrium

SAME_STATE = 1e-9
"""Two states whose nodal values differ by less than this fraction of a are the same."""


@dataclass(frozen=True)
class FillDrainStudy:
    """fractions (k,), the tank fractions of both legs; fill and drain, the
    :class:`~structure.axisymmetric.fill_drain.Leg` (the drain's states in the fill's order of
    ``fractions``: ``drain_states``); fill_tables and drain_tables, the stability of each
    state (:class:`~structure.axisymmetric.harmonics.HarmonicStability` or None); fill_onset
    and drain_onset (:class:`~structure.axisymmetric.folding.Onset` or None); seconds, the
    time of each part (s)."""

    fractions: np.ndarray
    fill: Leg
    drain: Leg
    fill_tables: list
    drain_tables: list
    fill_onset: Optional[Onset]
    drain_onset: Optional[Onset]
    seconds: dict

    @property
    def drain_states(self) -> list:
        return list(self.drain.states[::-1])

    @property
    def complete(self) -> bool:
        return self.fill.complete and self.drain.complete


def _same(a, b, radius: float) -> bool:
    return a is not None and b is not None and \
        np.abs(a.equilibrium.state - b.equilibrium.state).max() < SAME_STATE * radius


def _drain(shell, load, fractions: np.ndarray, fill: Leg, progress) -> Leg:
    """The drain leg: the fill's states down to its last landing, then followed on (module
    doc)."""
    landing = fill.snaps[-1].landing_fraction if fill.snaps else fractions[0]
    start = int(np.searchsorted(fractions, landing))        # the first fraction past it
    shared = [replace(state, piece=0) for state in fill.states[start:][::-1]]
    if start == 0:
        return Leg("drain", tuple(shared), (), True)
    below = leg(shell, load, fill.states[start].equilibrium, fractions[start::-1],
                progress=progress)
    return Leg("drain", tuple(shared[:-1]) + below.states, below.snaps, below.complete,
               below.reason)


def fill_and_drain(shell: ShellOfRevolution, load: AxisymmetricLoad, fractions: Sequence[float],
                   wave_numbers: Sequence[int] = WAVE_NUMBERS,
                   progress: Optional[Callable[[str, float], None]] = None) -> FillDrainStudy:
    """Fill ``shell`` under ``load`` (its liquid, gravity and pressure) from its equilibrium
    at the first of ``fractions`` (increasing, from 0) through them, drain it back, and
    tabulate the stability of both legs (module doc). ``progress(part, fraction)`` is called
    as each leg advances."""
    fractions = np.asarray(fractions, dtype=float)
    if np.any(np.diff(fractions) <= 0) or fractions[0] < 0 or fractions[-1] >= 1:
        raise ValueError("tank fractions must increase within [0, 1)")
    seconds = {}
    began = time.perf_counter()
    first = equilibrium(shell, volume_load(load, shell.radius, fractions[0]))
    if not first.converged:
        raise RuntimeError(f"no equilibrium at tank fraction {fractions[0]}")

    def report(part):
        return None if progress is None else (lambda f: progress(part, f))

    fill = leg(shell, load, first, fractions, progress=report("fill"))
    seconds["fill"] = time.perf_counter() - began
    began = time.perf_counter()
    if fill.complete:
        drain = _drain(shell, load, fractions, fill, report("drain"))
    else:
        drain = Leg("drain", (), (), False, "the fill did not reach its end")
    seconds["drain"] = time.perf_counter() - began
    began = time.perf_counter()
    fill_tables = stability_table(shell, load, fill, wave_numbers)
    drain_tables = []
    for k, state in enumerate(drain.states):
        twin = len(fractions) - 1 - k
        if twin < len(fill.states) and _same(state, fill.states[twin], shell.radius):
            drain_tables.append(fill_tables[twin])
        else:
            drain_tables.append(None if state is None else harmonic_table(
                shell, load, state.equilibrium, wave_numbers))
    seconds["stability"] = time.perf_counter() - began
    began = time.perf_counter()
    fill_onset = onset_of_folding(shell, load, fill, fill_tables, wave_numbers)
    drain_onset = onset_of_folding(shell, load, drain, drain_tables, wave_numbers) \
        if drain.states else None
    seconds["onset"] = time.perf_counter() - began
    return FillDrainStudy(fractions, fill, drain, fill_tables, drain_tables[::-1], fill_onset,
                          drain_onset, seconds)


def fill_onset(shell: ShellOfRevolution, load: AxisymmetricLoad, fractions: Sequence[float],
               wave_numbers: Sequence[int] = WAVE_NUMBERS) -> Optional[Onset]:
    """The onset of folding of ``shell`` filled from its equilibrium at the first of
    ``fractions`` through them, the fill stopped at its first unstable state (each state's
    stability tabulated as it is reached); None where every state is stable or the fill
    fails."""
    fractions = np.asarray(fractions, dtype=float)
    here = equilibrium(shell, volume_load(load, shell.radius, fractions[0]))
    if not here.converged:
        return None
    states = [LegState(float(fractions[0]), here, 0, 0)]
    tables = [harmonic_table(shell, load, here, wave_numbers)]
    snaps = 0
    for a, b in zip(fractions, fractions[1:]):
        step = leg(shell, load, here, [a, b])
        if not step.complete:
            return None
        snaps += len(step.snaps)
        state = replace(step.states[-1], piece=snaps)
        states.append(state)
        tables.append(harmonic_table(shell, load, state.equilibrium, wave_numbers))
        if not tables[-1].stable:
            path = Leg("fill", tuple(states), (), True)
            return onset_of_folding(shell, load, path, tables, wave_numbers)
        here = state.equilibrium
    return None
