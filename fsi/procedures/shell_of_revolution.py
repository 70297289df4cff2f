"""``shell-of-revolution``: the diaphragm as a shell of revolution (:mod:`structure.axisymmetric`):
its fill and drain along the axisymmetric branch, the snaps between them, its stability to
each circumferential wave number n at every fill and the onset of folding with its number of
lobes.

The meridian of the scene's hemisphere (``membrane.thickness``, ``density``,
``youngs_modulus``, ``poisson_ratio``, ``support``; rubber, nu >= 0.49, takes the
incompressible neo-Hookean law of E, else ``structure.shell_law``) on ``axisymmetric.elements``
cubic Hermite elements, inside the tank's wall (a barrier whose band is
``axisymmetric.wall_band`` a), its own weight and the liquid below it. Fill from rest through
the tank fractions ``axisymmetric.fills`` and drain back
(:func:`structure.axisymmetric.study.fill_and_drain`); the stability table by n = 1 ...
``axisymmetric.wave_numbers``. The stability tables and the slosh modes are spread over the
machine's cores (:func:`structure.parallel.process_map`).

Writes, per leg (groups ``axisymmetric_fill`` and ``axisymmetric_drain``, one record per tank
fraction): the level, whether the state is stable to every harmonic, the lowest eigenvalue of
each harmonic, the critical wave number, and the meridian at ``axisymmetric.samples`` points
(radius, height, stretches, membrane stresses, moments); the snaps and the onsets of folding
as rows of ``axisymmetric_events``; at each of ``axisymmetric.slosh_fills`` the fill's n = 1
slosh mode on the liquid's potential flow (``axisymmetric_slosh``:
:func:`fsi.slosh.axisymmetric.fill_slosh`): lambda1 = omega^2 a / g, the slosh mass fraction,
the pendulum's hinge height above the tank's centre, the lowest stable mode, the unstable
n = 1 directions, whether the branch is stable to every harmonic, and the free surface's
lambda1 and slosh mass at the same fill (a slosh fill the fill jumped over in a snap has no
state, and is said so in the log). A leg that does not reach its end is a failed run (exit 3).
"""
from __future__ import annotations

import logging

import numpy as np

from structure.axisymmetric.fields import meridian_fields
from structure.axisymmetric.study import fill_and_drain

from fsi.lifecycle import Progress, Run, RunResult
from fsi.registry import Procedure, register_procedure
from fsi.setup.shell_of_revolution import AXISYMMETRIC, build
from fsi.slosh.axisymmetric import fill_slosh_table
from fsi.text import format_table

LOG = logging.getLogger(__name__)


def _record(shell, state, table, samples: np.ndarray) -> dict:
    fields = meridian_fields(shell, state.equilibrium.state, samples)
    critical = int(np.argmin(table.eigenvalue))
    return dict(tank_fraction=state.tank_fraction,
                pressure_level=state.equilibrium.pressure_level,
                stable=bool(table.stable), axisymmetric_stable=state.negative == 0,
                harmonic_eigenvalue=table.eigenvalue,
                critical_wave_number=int(table.wave_numbers[critical]),
                meridian_radius=fields["radius"], meridian_height=fields["height"],
                meridian_stretch=fields["stretch"], meridian_stress=fields["stress"],
                meridian_moment=fields["moment"])


def _slosh_record(row: dict, table) -> dict:
    return dict(tank_fraction=row["tank_fraction"], lambda1=row["lambda1_full"],
                slosh_mass_fraction=row["slosh_mass_fraction"], hinge_height=row["hinge"],
                wet_gap_order=np.nan if row["wet_gap_order"] is None else row["wet_gap_order"],
                lambda1_lowest=row["lambda1_lowest"],
                lowest_slosh_mass_fraction=row["lowest_slosh_mass_fraction"],
                unstable_directions=row["unstable_n1"], stable=bool(table.stable),
                lambda1_free=row["lambda1_free"],
                free_slosh_mass_fraction=row["free_slosh_mass_fraction"])


def run_shell_of_revolution(setup, progress: Progress) -> RunResult:
    """Fill, drain and the stability tables (module doc)."""
    table = setup.scene["axisymmetric"]
    shell, load = build(setup.scene)
    fills = np.asarray(table["fills"], dtype=float)
    end = fills[-1]
    run = Run(progress, 4 if table["slosh_fills"] else 3)

    def report(part, f):
        done = f / end if part == "fill" else 1 + (end - f) / end
        run.progress(done, f"{part}: tank fraction {f:.3f}")

    study = fill_and_drain(shell, load, fills, range(1, table["wave_numbers"] + 1), report,
                           workers=None)
    run.progress(3, "stability by wave number")
    samples = np.linspace(0.0, shell.meridian.shape.length, table["samples"])
    for name, states, tables in (("axisymmetric_fill", study.fill.states, study.fill_tables),
                                 ("axisymmetric_drain", study.drain_states,
                                  study.drain_tables)):
        for state, stab in zip(states, tables):
            if state is not None:
                run.record(name, _record(shell, state, stab, samples))
    picked = [(f, study.fill_index(f)) for f in table["slosh_fills"]]
    for f, j in picked:
        if j is None:
            LOG.warning("no slosh mode at tank fraction %.4f: the fill jumped over it in a "
                        "snap", f)
    picked = [(f, j) for f, j in picked if j is not None]
    if picked:
        run.progress(3, f"slosh at {len(picked)} fills")
    rows = fill_slosh_table(shell, [study.fill.states[j].equilibrium for _, j in picked],
                            [f for f, _ in picked], load.liquid_density, load.gravity,
                            workers=None)
    for (f, j), row in zip(picked, rows):
        run.record("axisymmetric_slosh", _slosh_record(row, study.fill_tables[j]))
    for snap in list(study.fill.snaps) + list(study.drain.snaps):
        run.record("axisymmetric_events", dict(
            event=np.bytes_(f"{snap.direction} snaps"), tank_fraction=snap.tank_fraction,
            pressure_level=snap.level_before, lobes=0))
    for leg_name, onset in (("fill", study.fill_onset), ("drain", study.drain_onset)):
        if onset is not None:
            where = "" if onset.resolved else \
                f" between {onset.bracket[0]:.4f} and {onset.bracket[1]:.4f}"
            run.record("axisymmetric_events", dict(
                event=np.bytes_(f"{leg_name}: folding starts{where}"),
                tank_fraction=onset.tank_fraction, pressure_level=onset.level,
                lobes=onset.lobes))
    if not study.complete:
        run.stop(study.fill.reason or study.drain.reason)
    onset = study.fill_onset
    return run.result(
        wave_number=np.arange(1, table["wave_numbers"] + 1),
        meridian_arc_length=samples, elements=table["elements"], radius=shell.radius,
        onset_tank_fraction=np.nan if onset is None else onset.tank_fraction,
        onset_lobes=0 if onset is None else onset.lobes,
        **{f"seconds_{k}": v for k, v in study.seconds.items()})


COLUMNS = [("tank fraction", "-"), ("level fill", "Pa"), ("level drain", "Pa"),
           ("critical n", "-"), ("its omega^2", "1/s^2"), ("fill stable", ""),
           ("drain stable", "")]
"""The report's columns: per tank fraction the pressure level p_ref of each leg, the
circumferential wave number with the lowest eigenvalue on the fill and that eigenvalue
(omega^2 of the sheet's in-vacuo vibration in that harmonic; negative: unstable), and
whether each leg's state is stable to every harmonic."""
FORMATS = [".3f", ".2f", ".2f", "d", ".3g", "", ""]


def rows(result: RunResult) -> list[tuple]:
    """The report's rows (:data:`COLUMNS`), one per tank fraction of the fill."""
    fill = result.groups["axisymmetric_fill"]
    drain = result.groups.get("axisymmetric_drain", {})
    by_fraction = {round(float(f), 9): k for k, f in enumerate(drain.get("tank_fraction", []))}
    out = []
    for k, f in enumerate(fill["tank_fraction"]):
        j = by_fraction.get(round(float(f), 9))
        eig = np.asarray(fill["harmonic_eigenvalue"][k])
        out.append((float(f), float(fill["pressure_level"][k]),
                    None if j is None else float(drain["pressure_level"][j]),
                    int(fill["critical_wave_number"][k]), float(eig.min()),
                    "yes" if fill["stable"][k] else "no",
                    None if j is None else ("yes" if drain["stable"][j] else "no")))
    return out


def headline(result: RunResult) -> None:
    """The snaps and the onset of folding, one line each."""
    events = result.groups.get("axisymmetric_events", {})
    for k, event in enumerate(events.get("event", [])):
        text = event.decode() if isinstance(event, bytes) else str(event)
        lobes = int(events["lobes"][k])
        print(f"{text} at tank fraction {float(events['tank_fraction'][k]):.5f}"
              + (f", {lobes} lobes" if lobes else "")
              + f" (level {float(events['pressure_level'][k]):.1f} Pa)")


SLOSH_COLUMNS = [("tank fraction", "-"), ("lambda1", "-"), ("slosh mass", "-"),
                 ("hinge", "m"), ("unstable n=1", "-"), ("branch stable", ""),
                 ("lambda1 free", "-"), ("slosh mass free", "-")]
"""The slosh table's columns: per slosh fill lambda1 = omega^2 a / g of the diaphragm's
slosh mode, its slosh mass over the liquid's, its pendulum hinge above the tank's centre,
the unstable n = 1 directions, whether the branch is stable to every harmonic, and the free
surface's lambda1 and slosh mass at the same fill."""
SLOSH_FORMATS = [".3f", ".4f", ".4f", ".4f", "d", "", ".4f", ".4f"]


def slosh_rows(result: RunResult) -> list[tuple]:
    """The slosh table's rows (:data:`SLOSH_COLUMNS`), one per slosh fill."""
    g = result.groups.get("axisymmetric_slosh", {})
    return [(float(f), float(g["lambda1"][k]), float(g["slosh_mass_fraction"][k]),
             float(g["hinge_height"][k]), int(g["unstable_directions"][k]),
             "yes" if g["stable"][k] else "no", float(g["lambda1_free"][k]),
             float(g["free_slosh_mass_fraction"][k]))
            for k, f in enumerate(g.get("tank_fraction", []))]


def report(result: RunResult) -> None:
    """The fill and drain table, the events, then the slosh table."""
    print(format_table(COLUMNS, rows(result), FORMATS))
    headline(result)
    slosh = slosh_rows(result)
    if slosh:
        print("\nn = 1 slosh on the fill's branch (lambda1 = omega^2 a / g):")
        print(format_table(SLOSH_COLUMNS, slosh, SLOSH_FORMATS))


PROCEDURE = register_procedure(Procedure(
    name="shell-of-revolution",
    summary="the diaphragm as a shell of revolution: fill and drain on the axisymmetric "
            "branch, its snaps, its stability to each circumferential wave number and the "
            "onset of folding with its lobes (converged in the meridian grid, seconds)",
    run=run_shell_of_revolution,
    tables={"axisymmetric": AXISYMMETRIC},
    report=report,
    headline=headline,
))
