"""The Table 4.1 diaphragm as a shell of revolution (:mod:`structure.axisymmetric`): its fill and
drain converged in the meridian grid, where it starts to fold and with how many lobes.

    python benchmarks/diaphragm_axisymmetric.py [--smoke]

The diaphragm: the thesis's hemisphere of the tank's radius (E = 8.6 MPa, t = 1.778 mm,
incompressible neo-Hookean, clamped at the equator, its own weight), water below it, inside
the tank's wall (a barrier with a band of 1e-4 a). The stability tables, the onsets and the
slosh rows run over the machine's cores (:func:`structure.parallel.process_map`). Prints one
JSON object (a full run also
writes it to ``docs/data/diaphragm_axisymmetric.json``) and draws
``benchmarks/output/diaphragm_axisymmetric.png``:

* ``grid_study``: the fill leg through tank fractions 0 ... 0.5 on each of :data:`GRIDS`
  (elements on the meridian): the level at tank fraction 0.5 and at 0.25 (Pa), the fill's and
  the drain's snap fractions and the onset of folding on each; Richardson's value and the
  observed order from the three finest grids (ratio 2);
* the whole run on :data:`RUN_GRID` elements: ``fills``, one row per tank fraction of
  :data:`FRACTIONS` (levels of both legs, the critical wave number and its lowest eigenvalue,
  whether each leg's state is stable to every harmonic n = 1 ... 30); ``snaps``; ``onset``
  {``tank_fraction``, ``lobes``} on the fill and ``drain_onset`` on the drain;
  ``stability_map``, the lowest eigenvalue (1/s^2) of every harmonic at every fraction of
  each leg; ``seconds`` of the whole run and ``seconds_parts`` of its parts;
  ``seconds_slosh``, the full law's slosh table with the free surface's, and
  ``seconds_goal``, the two together (the run with its n = 1 modes);
  ``seconds_tension_field``, the tension field's fills and slosh;
* ``slosh_table``, one row per tank fraction of :data:`SLOSH_FRACTIONS` on the fill's branch
  (:func:`fsi.slosh.axisymmetric.converged_slosh`): ``lambda1_full`` = omega^2 a / g of the
  slosh mode (the largest slosh mass), ``slosh_mass_fraction`` (over the liquid's mass) and
  ``hinge`` (the pendulum's hinge, m above the tank's centre), extrapolated to a wet part
  that reaches the wall, with ``wet_gap_order`` (the observed order in the gap);
  ``lambda1_lowest`` and its slosh mass, the lowest stable mode; ``unstable_n1``, the
  directions of negative stiffness in n = 1; ``branch_stable`` (every harmonic);
  ``lambda1_free``, the free surface's (the limp limit); ``lambda1_tension_field``, the
  tension field's with the residual stiffness e = 1e-2 (its fill leg from rest, no snaps),
  and ``tension_field``, its level, lambda1, slosh mass and unstable n = 1 directions at each
  e of :data:`TENSION_RESIDUALS`, with ``tension_field_settled``: whether lambda1 at the two
  smallest e agree within 1 % (the pure relaxed sheet's Newton does not converge: its slack
  zones are held by bending alone; :mod:`structure.axisymmetric.laws`);
* ``limp_check``, one row per tank fraction: the limp limit's ``lambda1`` and slosh mass
  against the isoparametric P2 reference (``docs/data/sphere_slosh_reference.json``).

The tank fraction 1.0 is out of reach: the clamped rim holds the sheet's tangent, so the
inverted sheet turns back on itself there; the last fraction is 0.99.
``--smoke``: :data:`SMOKE_GRIDS` to tank fraction 0.05 and the run on :data:`SMOKE_RUN_GRID`
elements over :data:`SMOKE_FRACTIONS`, the slosh table at :data:`SMOKE_SLOSH_FRACTIONS`.
"""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from _report import DOCS_DATA, SMOKE_HELP, emit, output_dir
from fsi.constants import (MEMBRANE_DENSITY, MEMBRANE_THICKNESS, MEMBRANE_YOUNGS_MODULUS,
                           STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY)
from fsi.slosh.axisymmetric import converged_slosh, fill_slosh_table
from structure.axisymmetric import (AxisymmetricLoad, barrier_wall, law_of, leg,
                                    shell_of_revolution)
from structure.axisymmetric.folding import onset_of_folding, stability_table
from structure.axisymmetric.solve import equilibrium
from structure.axisymmetric.study import fill_and_drain
from structure.model import Material

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("grid_study", "onset", "drain_onset", "snaps", "fills", "seconds",
              "stability_map", "elements", "slosh_table", "limp_check", "seconds_slosh",
              "seconds_parts", "seconds_tension_field", "seconds_goal")
#: meridian grids (elements) of the grid study, and of --smoke
GRIDS = (64, 96, 128, 192, 256, 384)
SMOKE_GRIDS = (16, 32, 64)
#: the grids of Richardson's extrapolation (each twice the last), and of --smoke
RICHARDSON = (96, 192, 384)
SMOKE_RICHARDSON = (16, 32, 64)
#: the grid of the whole run, and of --smoke
RUN_GRID = 256
SMOKE_RUN_GRID = 48
#: the tank fractions of both legs, and of --smoke
FRACTIONS = tuple(np.round(np.concatenate([np.linspace(0.0, 0.975, 40), [0.99]]), 4))
SMOKE_FRACTIONS = (0.0, 0.025, 0.05, 0.95, 0.975)
#: the tank fractions of the slosh table, and of --smoke
SLOSH_FRACTIONS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)
SMOKE_SLOSH_FRACTIONS = (0.05, 0.95)
#: the tension field's residual stiffnesses e (the first is the table's column), and of --smoke
TENSION_RESIDUALS = (1e-2, 1e-3, 1e-4)
SMOKE_TENSION_RESIDUALS = (1e-2,)
#: the wall's band (fraction of a) and the element ratio at the rim
WALL_BAND = 1e-4
RIM_RATIO = 0.3


def diaphragm(elements: int):
    """The Table 4.1 diaphragm on ``elements`` meridian elements and its water load."""
    material = Material(MEMBRANE_THICKNESS, MEMBRANE_DENSITY, MEMBRANE_YOUNGS_MODULUS, 0.5)
    scale = WATER_DENSITY * STANDARD_GRAVITY * TANK_RADIUS
    shell = shell_of_revolution("hemisphere", TANK_RADIUS, material,
                                law_of(material, "neo-hookean"), elements, rim_ratio=RIM_RATIO,
                                wall=barrier_wall(TANK_RADIUS, scale, WALL_BAND))
    load = AxisymmetricLoad(liquid_density=WATER_DENSITY, gravity=STANDARD_GRAVITY,
                            volume_target=0.0)
    return shell, load


def _grid_row(elements: int, end: float) -> dict:
    shell, load = diaphragm(elements)
    began = time.perf_counter()
    fractions = np.linspace(0.0, end, int(round(end / 0.025)) + 1)
    fill = leg(shell, load, equilibrium(shell, load), fractions)
    onset = onset_of_folding(shell, load, fill, stability_table(shell, load, fill))
    drain = leg(shell, load, fill.states[2].equilibrium, fractions[2::-1])
    levels = {round(f, 4): s.equilibrium.pressure_level for f, s in zip(fractions, fill.states)
              if s is not None}
    return dict(elements=elements, level_at_half=levels.get(0.5),
                level_at_quarter=levels.get(0.25), level_at_end=levels[round(end, 4)],
                snap_fill=fill.snaps[0].tank_fraction if fill.snaps else None,
                snap_drain=drain.snaps[0].tank_fraction if drain.snaps else None,
                onset=None if onset is None else onset.tank_fraction,
                lobes=None if onset is None else onset.lobes,
                seconds=round(time.perf_counter() - began, 2))


def richardson(values, ratio: float = 2.0) -> dict:
    """Richardson's extrapolation of three values on grids refined by ``ratio``: the observed
    order p = log(d1 / d2) / log(ratio) and f3 + (f3 - f2) / (ratio^p - 1)."""
    f1, f2, f3 = values
    d1, d2 = f2 - f1, f3 - f2
    if d1 == 0 or d2 == 0 or d1 * d2 < 0:
        return dict(observed_order=None, value=f3, note="not monotone in the grid")
    order = float(np.log(d1 / d2) / np.log(ratio))
    return dict(observed_order=order, value=float(f3 + d2 / (ratio**order - 1)))


def _figure(study, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    f = study.fractions
    fill = [np.nan if s is None else s.equilibrium.pressure_level for s in study.fill.states]
    drain = [np.nan if s is None else s.equilibrium.pressure_level for s in study.drain_states]
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    a.plot(f, fill, "o-", ms=3, label="fill")
    a.plot(f, drain, "s--", ms=3, mfc="none", label="drain")
    for snap in list(study.fill.snaps) + list(study.drain.snaps):
        a.plot([snap.tank_fraction] * 2, [snap.level_before, snap.level_after], "k:", lw=1)
    if study.fill_onset is not None:
        a.axvline(study.fill_onset.tank_fraction, color="C3", lw=1,
                  label=f"onset of folding ({study.fill_onset.lobes} lobes)")
    a.set_xlabel("tank fraction V / (4/3 pi R^3)")
    a.set_ylabel("pressure level p_ref (Pa)")
    a.set_title("fill and drain (axisymmetric branch)")
    a.legend(fontsize=8)
    waves = study.fill_tables[0].wave_numbers
    grid = np.array([[np.nan] * len(waves) if t is None else np.sign(t.eigenvalue)
                     for t in study.fill_tables]).T
    b.pcolormesh(f, waves, grid, cmap="RdBu", vmin=-1.5, vmax=1.5, shading="nearest")
    b.set_xlabel("tank fraction")
    b.set_ylabel("circumferential wave number n")
    b.set_title("fill: stable (blue) / unstable (red) by n")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _first(values):
    return float(values[0]) if values else None


def _settled(values, tolerance: float = 1e-2):
    """Whether the last two of ``values`` agree within ``tolerance`` (None with fewer)."""
    if len(values) < 2:
        return None
    return bool(abs(values[-1] - values[-2]) <= tolerance * abs(values[-2]))


def _reference() -> dict:
    """The free surface's lambda1 and slosh mass by tank fraction, P2 to 8 digits."""
    return json.loads((DOCS_DATA / "sphere_slosh_reference.json").read_text())["fills"]


def tension_field_rows(shell, load, fractions, residuals) -> dict:
    """{fraction: {residual, level, lambda1, slosh_mass_fraction, hinge, unstable_n1} lists}:
    the tension field's fill leg from rest through the tank fractions 0, 0.025, ... up to the
    last of ``fractions`` for each residual stiffness e of ``residuals``, its n = 1 slosh at
    each of ``fractions``."""
    material = replace(shell.material, wrinkling="tension-field")
    end = max(fractions)
    steps = np.union1d(np.round(np.arange(0.0, end + 1e-9, 0.025), 4), np.round(fractions, 4))
    out = {float(f): dict(residual=[], level=[], lambda1=[], slosh_mass_fraction=[], hinge=[],
                          unstable_n1=[]) for f in fractions}
    for e in residuals:
        relaxed = replace(shell, material=material, residual_stiffness=e)
        fill = leg(relaxed, load, equilibrium(relaxed, load), steps)
        for f, state in zip(steps, fill.states):
            if float(f) not in out or state is None:
                continue
            q = state.equilibrium
            slosh = converged_slosh(relaxed, q.state, load.liquid_density, load.gravity,
                                    q.pressure - q.pressure_level,
                                    f * 4.0 / 3.0 * np.pi * shell.radius**3)
            row = out[float(f)]
            for key, value in (("residual", e), ("level", q.pressure_level),
                               ("lambda1", slosh.lambda1),
                               ("slosh_mass_fraction", slosh.slosh_mass_fraction),
                               ("hinge", slosh.hinge), ("unstable_n1", slosh.unstable)):
                row[key].append(value)
    return out


def slosh_rows(shell, load, study, fractions, relaxed) -> tuple[list, list]:
    """(slosh_table, limp_check) at ``fractions`` on the fill's branch (module doc), with the
    tension field's rows ``relaxed`` (:func:`tension_field_rows`)."""
    reference = _reference()
    table, limp = [], []
    picked = [(f, k) for f, k in ((f, study.fill_index(f)) for f in fractions)
              if k is not None]
    rows = fill_slosh_table(shell, [study.fill.states[k].equilibrium for _, k in picked],
                            [f for f, _ in picked], load.liquid_density, load.gravity,
                            workers=None)
    for (f, k), row in zip(picked, rows):
        stab = study.fill_tables[k]
        row.update(branch_stable=None if stab is None else stab.stable,
                   lambda1_tension_field=_first(relaxed[float(f)]["lambda1"]),
                   tension_field=relaxed[float(f)],
                   tension_field_settled=_settled(relaxed[float(f)]["lambda1"]))
        table.append(row)
        known = reference.get(str(round(float(f), 4)))
        limp.append(dict(
            tank_fraction=float(f), lambda1=row["lambda1_free"],
            slosh_mass_fraction=row["free_slosh_mass_fraction"],
            reference=None if known is None else known["lambda1"],
            error=None if known is None else row["lambda1_free"] / known["lambda1"] - 1,
            mass_error=None if known is None
            else row["free_slosh_mass_fraction"] / known["slosh_mass_fraction"] - 1))
    return table, limp


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    grids = SMOKE_GRIDS if args.smoke else GRIDS
    end = 0.05 if args.smoke else 0.5
    rows = [_grid_row(n, end) for n in grids]
    triple = SMOKE_RICHARDSON if args.smoke else RICHARDSON
    chosen = [next(r for r in rows if r["elements"] == n) for n in triple]
    study_grid = dict(rows=rows, end_fraction=end, richardson_grids=list(triple),
                      richardson_level_at_end=richardson([r["level_at_end"] for r in chosen]),
                      richardson_onset=richardson([r["onset"] for r in chosen])
                      if all(r["onset"] for r in chosen) else None)
    shell, load = diaphragm(SMOKE_RUN_GRID if args.smoke else RUN_GRID)
    began = time.perf_counter()
    study = fill_and_drain(shell, load, SMOKE_FRACTIONS if args.smoke else FRACTIONS,
                           workers=None)
    seconds = time.perf_counter() - began
    fills = []
    for f, a, b, ta, tb in zip(study.fractions, study.fill.states, study.drain_states,
                               study.fill_tables, study.drain_tables):
        critical = None if ta is None else int(np.argmin(ta.eigenvalue))
        fills.append(dict(
            tank_fraction=float(f),
            level_fill=None if a is None else a.equilibrium.pressure_level,
            level_drain=None if b is None else b.equilibrium.pressure_level,
            critical_wave_number=None if ta is None else int(ta.wave_numbers[critical]),
            lowest_eigenvalue=None if ta is None else float(ta.eigenvalue[critical]),
            fill_stable=None if ta is None else ta.stable,
            drain_stable=None if tb is None else tb.stable))
    slosh_fractions = SMOKE_SLOSH_FRACTIONS if args.smoke else SLOSH_FRACTIONS
    began = time.perf_counter()
    relaxed = tension_field_rows(shell, load, slosh_fractions,
                                 SMOKE_TENSION_RESIDUALS if args.smoke else TENSION_RESIDUALS)
    seconds_tension_field = time.perf_counter() - began
    began = time.perf_counter()
    slosh_table, limp_check = slosh_rows(shell, load, study, slosh_fractions, relaxed)
    seconds_slosh = time.perf_counter() - began
    snaps = [dict(direction=s.direction, tank_fraction=s.tank_fraction,
                  level_before=s.level_before, level_after=s.level_after)
             for s in list(study.fill.snaps) + list(study.drain.snaps)]

    def onset(o):
        return None if o is None else dict(tank_fraction=o.tank_fraction, lobes=o.lobes,
                                           level=o.level, bracket=list(o.bracket),
                                           resolved=o.resolved)

    out = dict(elements=shell.meridian.nodes - 1, complete=study.complete,
               seconds=round(seconds, 2),
               seconds_parts={k: round(v, 2) for k, v in study.seconds.items()},
               onset=onset(study.fill_onset), drain_onset=onset(study.drain_onset),
               snaps=snaps, fills=fills, grid_study=study_grid,
               slosh_table=slosh_table, limp_check=limp_check,
               seconds_slosh=round(seconds_slosh, 2),
               seconds_tension_field=round(seconds_tension_field, 2),
               seconds_goal=round(seconds + seconds_slosh, 2),
               stability_map=dict(
                   wave_numbers=[int(n) for n in study.fill_tables[0].wave_numbers],
                   fill=[None if t is None else [float(v) for v in t.eigenvalue]
                         for t in study.fill_tables],
                   drain=[None if t is None else [float(v) for v in t.eigenvalue]
                          for t in study.drain_tables]))
    path = output_dir(args.smoke) / "diaphragm_axisymmetric.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    _figure(study, path)
    out["figure"] = str(path.relative_to(path.parents[2]))
    emit("diaphragm_axisymmetric", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
