"""Where the axisymmetric diaphragm starts to fold: the stability table of a fill or drain leg by
circumferential wave number (:mod:`~structure.axisymmetric.harmonics`), and the onset of
folding, the first tank fraction at which some harmonic loses stability, located between the
leg's last stable and first unstable state by regula falsi (Illinois) on the lowest
eigenvalue of the harmonics unstable at the unstable end and their neighbours (the
states between found on the leg's branch by
:func:`~structure.axisymmetric.fill_drain.next_state` from the bracket's stable end, else from
its unstable one, else by Newton from the two interpolated). Its wave number is the predicted number of lobes; its
mode is the fold's shape.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial
from typing import Optional, Sequence

import numpy as np

from ..parallel import process_map
from .fill_drain import Leg, next_state, volume_load
from .harmonics import HarmonicStability, stability
from .loads import AxisymmetricLoad
from .model import ShellOfRevolution
from .solve import AxisymmetricEquilibrium, NewtonSettings, equilibrium

WAVE_NUMBERS = tuple(range(1, 31))
"""The circumferential wave numbers of the stability table."""
RESOLVED = 1e-3
"""An onset's bracket (tank fraction) no wider than this is resolved."""


@dataclass(frozen=True)
class Onset:
    """The onset of folding: ``tank_fraction``; ``lobes``, the wave number that loses
    stability there; ``level`` (Pa), the liquid's pressure level; ``state`` (4 n,), the
    axisymmetric equilibrium; ``mode`` (6 n,), the critical harmonic's shape (nodal U, U', V,
    V', W, W', unit mass); ``bracket`` the last stable and first unstable fractions (the
    onset is the latter); ``resolved`` whether the bracket was narrowed to :data:`RESOLVED`
    (else the states between could not be found, and the onset is only known to lie in it)."""

    tank_fraction: float
    lobes: int
    level: float
    state: np.ndarray
    mode: np.ndarray
    bracket: tuple

    @property
    def resolved(self) -> bool:
        return abs(self.bracket[1] - self.bracket[0]) <= RESOLVED


def harmonic_table(shell: ShellOfRevolution, load: AxisymmetricLoad,
                   result: AxisymmetricEquilibrium,
                   wave_numbers: Sequence[int] = WAVE_NUMBERS) -> HarmonicStability:
    """The stability of the equilibrium ``result`` under ``load`` to each of ``wave_numbers``."""
    return stability(shell, result.state, load.liquid_density * load.gravity,
                     result.pressure - result.pressure_level, wave_numbers)


def _between(shell, load, lo: AxisymmetricEquilibrium, hi: AxisymmetricEquilibrium,
             w: float, fraction: float, newton: NewtonSettings):
    """The held-volume equilibrium at ``fraction`` from the states ``lo`` and ``hi``
    interpolated at ``w`` (a bracket too wide for the tangent's step), or None."""
    start = lo.state + w * (hi.state - lo.state)
    mu = (1 - w) * (lo.pressure - lo.pressure_level) + w * (hi.pressure - hi.pressure_level)
    result = equilibrium(shell, volume_load(load, shell.radius, fraction), start, mu,
                         replace(newton, max_iterations=200))
    return result if result.converged else None


def stability_table(shell: ShellOfRevolution, load: AxisymmetricLoad, path: Leg,
                    wave_numbers: Sequence[int] = WAVE_NUMBERS, workers: Optional[int] = 1
                    ) -> list[Optional[HarmonicStability]]:
    """The stability of each state of the leg ``path`` (None where it has none), over
    ``workers`` processes (:func:`structure.parallel.process_map`; None: every core)."""
    return stability_tables(shell, load, [None if s is None else s.equilibrium
                                          for s in path.states], wave_numbers, workers)


def stability_tables(shell: ShellOfRevolution, load: AxisymmetricLoad,
                     results: Sequence[Optional[AxisymmetricEquilibrium]],
                     wave_numbers: Sequence[int] = WAVE_NUMBERS, workers: Optional[int] = 1
                     ) -> list[Optional[HarmonicStability]]:
    """:func:`harmonic_table` of each of the equilibria ``results`` (None where None), over
    ``workers`` processes (:func:`structure.parallel.process_map`; None: every core)."""
    given = [k for k, r in enumerate(results) if r is not None]
    tables = process_map(partial(harmonic_table, shell, load, wave_numbers=tuple(wave_numbers)),
                         [results[k] for k in given], workers)
    out: list[Optional[HarmonicStability]] = [None] * len(results)
    for k, table in zip(given, tables):
        out[k] = table
    return out


def onset_of_folding(shell: ShellOfRevolution, load: AxisymmetricLoad, path: Leg,
                     tables: Sequence[Optional[HarmonicStability]],
                     wave_numbers: Sequence[int] = WAVE_NUMBERS, tolerance: float = 1e-5,
                     newton: NewtonSettings = NewtonSettings()) -> Optional[Onset]:
    """The onset of folding on the leg ``path`` with its stability ``tables`` (module doc),
    to ``tolerance`` in the tank fraction; None where every state is stable."""
    states = path.states
    for k in range(1, len(states)):
        if tables[k] is None or tables[k - 1] is None or tables[k].stable \
                or not tables[k - 1].stable or states[k].piece != states[k - 1].piece:
            continue
        lo, hi = states[k - 1].equilibrium, states[k].equilibrium
        f_lo, f_hi = states[k - 1].tank_fraction, states[k].tank_fraction
        unstable = tables[k].wave_numbers[tables[k].negative != 0]
        near = sorted({int(n) + d for n in unstable for d in (-1, 0, 1)}
                      & set(int(n) for n in wave_numbers))
        v_lo = tables[k - 1].eigenvalue[np.isin(tables[k - 1].wave_numbers, near)].min()
        v_hi = tables[k].eigenvalue[np.isin(tables[k].wave_numbers, near)].min()
        best = (hi, tables[k], f_hi)
        side = 0
        for _ in range(60):
            if abs(f_hi - f_lo) < tolerance:
                break
            w = min(max(v_lo / (v_lo - v_hi), 0.05), 0.95)   # Illinois regula falsi
            f = f_lo + w * (f_hi - f_lo)
            result = next_state(shell, load, lo, f, newton) \
                or next_state(shell, load, hi, f, newton) \
                or _between(shell, load, lo, hi, w, f, newton)
            if result is None:
                break
            table = harmonic_table(shell, load, result, near)
            if table.stable:
                lo, f_lo, v_lo = result, f, table.eigenvalue.min()
                v_hi, side = (0.5 * v_hi if side == -1 else v_hi), -1
            else:
                hi, f_hi, v_hi, best = result, f, table.eigenvalue.min(), (result, table, f)
                v_lo, side = (0.5 * v_lo if side == 1 else v_lo), 1
        result, table, f = best
        critical = int(np.argmin(table.eigenvalue))
        return Onset(float(f), int(table.wave_numbers[critical]), float(result.pressure_level),
                     result.state, table.modes[critical], (float(f_lo), float(f_hi)))
    return None
