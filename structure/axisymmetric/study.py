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
from functools import partial
from typing import Callable, Optional, Sequence

import numpy as np

from ..parallel import process_map
from .fill_drain import Leg, LegState, leg, volume_load
from .folding import (WAVE_NUMBERS, Onset, harmonic_table, onset_of_folding,
                      stability_tables)
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

    def fill_index(self, fraction: float) -> Optional[int]:
        """The index in ``fractions`` of the tank ``fraction`` (within 1e-9) where the fill
        has a state, else None (not a requested fraction, or jumped over in a snap)."""
        k = int(np.argmin(np.abs(self.fractions - fraction)))
        if abs(self.fractions[k] - fraction) > 1e-9 or self.fill.states[k] is None:
            return None
        return k


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


def _onset(shell, load, wave_numbers, leg_tables):
    return onset_of_folding(shell, load, leg_tables[0], leg_tables[1], wave_numbers)


def fill_and_drain(shell: ShellOfRevolution, load: AxisymmetricLoad, fractions: Sequence[float],
                   wave_numbers: Sequence[int] = WAVE_NUMBERS,
                   progress: Optional[Callable[[str, float], None]] = None,
                   workers: Optional[int] = 1) -> FillDrainStudy:
    """Fill ``shell`` under ``load`` (its liquid, gravity and pressure) from its equilibrium
    at the first of ``fractions`` (increasing, from 0) through them, drain it back, and
    tabulate the stability of both legs (module doc). ``progress(part, fraction)`` is called
    as each leg advances; the stability tables, and the two legs' onsets of folding, are
    computed over ``workers`` processes (:func:`structure.parallel.process_map`; None: every
    core)."""
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
    # the drain's states that are the fill's share its tables; the rest are computed with
    # the fill's, over the workers
    twins = []
    for k, state in enumerate(drain.states):
        twin = len(fractions) - 1 - k
        same = twin < len(fill.states) and _same(state, fill.states[twin], shell.radius)
        twins.append(twin if same else None)
    own = [None if s is None or t is not None else s.equilibrium
           for s, t in zip(drain.states, twins)]
    tables = stability_tables(shell, load, [None if s is None else s.equilibrium
                                            for s in fill.states] + own, wave_numbers,
                              workers)
    fill_tables = tables[:len(fill.states)]
    drain_tables = [fill_tables[t] if t is not None else table
                    for t, table in zip(twins, tables[len(fill.states):])]
    seconds["stability"] = time.perf_counter() - began
    began = time.perf_counter()
    legs = [(fill, fill_tables)] + ([(drain, drain_tables)] if drain.states else [])
    onsets = process_map(partial(_onset, shell, load, tuple(wave_numbers)), legs, workers)
    fill_onset, drain_onset = onsets[0], (onsets[1] if len(onsets) > 1 else None)
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
