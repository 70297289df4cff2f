"""What the two static procedures (``volume-sweep``, ``thesis-ramp``) share: the ``[sweep]``
and ``[relaxation]`` tables, the frame record of a static equilibrium, the 100 % reference
that every static result carries, and the summary ``fsi run`` prints."""
from __future__ import annotations

from typing import Optional

import numpy as np

from structure.statics import strain_error
from structure.volume import FillScale, tank_volume

from fsi.setup.fill import FILL_SCALES, FullInversion
from fsi.lifecycle import membrane_frame
from fsi.registry import Key, Table, one_of, positive
from fsi.text import format_table


def _fills(v):
    return isinstance(v, list) and len(v) >= 1 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and 0.0 <= c <= 1.0 for c in v)


SWEEP = Table({
    "fills": Key(list, [round(0.1 * k, 10) for k in range(1, 8)], _fills,
                 "non-empty list of numbers in [0, 1]",
                 "fills on the sweep.scale, in order (tank: from the rest shape's, 0.003, to "
                 "the fully inverted membrane's, 0.79, at N = 26 clamped)"),
    "scale": Key(str, "tank", *one_of(FILL_SCALES),
                 "scale of sweep.fills: tank (V / (4/3 pi R^3)) or full-inversion (the "
                 "thesis's App. J: 0 rest shape, 1 the fully inverted equilibrium) "
                 "(volume-sweep; thesis-ramp picks frames on App. J's last-frame scale)"),
    "drain": Key(bool, True, lambda v: True, "true or false",
                 "after filling, sweep back down the same fills (volume-sweep)"),
    "full_height": Key(float, 1.05, lambda v: 0 < v <= 100, "0 < value <= 100 (x radius)",
                       "equivalent height / radius of the load whose fully inverted "
                       "equilibrium is 100 % fill (App. J: the ramp's final +1.05)"),
})
"""[sweep]: the fills of a static result and the load of its 100 % reference."""

RELAXATION = Table({
    "dt": Key(float, None, positive, "> 0 s, below the explicit stability limit",
              "pseudo time step (s); default: the solver's"),
    "damping": Key(float, None, lambda v: 0 <= v < 1, "0 <= value < 1",
                   "velocity fraction removed per pseudo-step; default: the solver's"),
    "tolerance": Key(float, None, lambda v: 0 < v < 1, "0 < value < 1",
                     "converged when max node move per step / node size < tolerance"),
    "max_steps": Key(int, None, lambda v: v >= 1, ">= 1", "pseudo-steps per fill at most"),
})
"""[relaxation]: the thesis model's static relaxation (:mod:`structure.statics`)."""


def static_frame(setup, node_position, pressure_level, target_fill, seconds, steps, converged,
                 inversion: Optional[FillScale] = None) -> dict:
    """A static equilibrium's frame: :func:`fsi.lifecycle.membrane_frame` (with the
    ``inversion`` fraction where App. J is reproduced), the requested fill ``target_fill`` (on
    the run's ``fill_scale``; NaN for a frame not requested), wall seconds, solver steps,
    convergence and the thesis strain measures."""
    mean, worst = strain_error(setup.model, node_position)
    return dict(membrane_frame(setup, node_position, pressure_level, inversion),
                target_fill=float(target_fill), wall_seconds=seconds,
                relaxation_steps=steps, converged=bool(converged), strain_error=mean,
                strain_max=worst)


def full_inversion_parts(setup, full: FullInversion) -> tuple[dict, dict]:
    """(groups, attrs) carrying the fill scale and the 100 % reference shape."""
    info = full.info
    groups = dict(full_inversion=dict(node_position=full.state.node_position[None],
                                      liquid_volume=np.array([info.liquid_volume]),
                                      strain_error=np.array([info.strain_error]),
                                      strain_max=np.array([info.strain_max]),
                                      converged=np.array([info.converged])))
    attrs = dict(empty_volume=full.scale.empty_volume, full_volume=full.scale.full_volume,
                 full_tank_fraction=full.scale.full_volume / tank_volume(setup.model.radius),
                 mirrored_volume=full.mirrored_volume, full_pressure_level=info.pressure_level,
                 full_height=setup.liquid.equivalent_height(info.pressure_level))
    return groups, attrs


SWEEP_COLUMNS = (
    ("tank_fraction", "tank fraction", "-", ".4f"),
    ("inversion_fraction", "inversion fraction", "-", ".4f"),
    ("liquid_volume", "liquid volume", "m^3", ".6e"),
    ("pressure_level", "level p_ref", "Pa", ".1f"),
    ("strain_error", "mean strain", "-", ".5f"),
    ("strain_max", "max strain", "-", ".5f"),
    ("relaxation_steps", "steps", "-", "d"),
    ("wall_seconds", "wall", "s", ".2f"),
)
"""The columns of the static table: dataset, header, unit, format (``inversion_fraction``
only where the run reproduces App. J)."""

SWEEP_NOTES = (
    "tank fraction: V / (4/3 pi R^3), the liquid's share of the tank",
    "inversion fraction: the thesis's App. J scale, 0 at the rest shape, 1 at the full "
    "inversion",
    "liquid volume: below the sheet",
    "level p_ref: the liquid's pressure at the tank centre over the gas's, the volume's "
    "multiplier (negative: below the gas's; the sheet's tension carries the difference)",
    "mean strain, max strain: the in-plane springs' |L - L0| / L0, mean (the thesis's "
    "error) and largest",
    "steps: the solver's pseudo-steps (the thesis ramp: the step index)",
    "wall: the frame's solve time",
)
"""What the static table's columns mean, printed under it."""


def _notes_by_column() -> dict:
    """Column header -> the note of :data:`SWEEP_NOTES` that explains it."""
    return {head: note for note in SWEEP_NOTES for head in note.split(":")[0].split(", ")}


def columns_markdown() -> str:
    """The static table's columns (:data:`SWEEP_COLUMNS`) and what they mean
    (:data:`SWEEP_NOTES`), for the outputs page."""
    notes = _notes_by_column()
    rows = ["| column | unit | dataset | meaning |", "|---|---|---|---|"]
    for key, head, unit, _ in SWEEP_COLUMNS:
        meaning = notes[head].split(":", 1)[1].strip()
        rows.append(f"| {head} | {unit} | `{key}` | {meaning.replace('|', chr(92) + '|')} |")
    return "\n".join(rows)


def report_sweep(result) -> None:
    """The fill table ``fsi run`` prints after a static procedure (:data:`SWEEP_COLUMNS`),
    and what its columns mean (:data:`SWEEP_NOTES`)."""
    a = result.attrs
    print(f"full inversion (inversion fraction 1): tank fraction "
          f"{a['full_tank_fraction']:.4f}, "
          f"{a['full_volume'] / a['mirrored_volume']:.4f} of the mirrored rest shape, under an "
          f"equivalent liquid height of {a['full_height']:.4f} m (sweep.full_height x R)")
    for name in ("frames", "drain"):
        if name not in result.groups:
            continue
        g = result.groups[name]
        columns = [c for c in SWEEP_COLUMNS if c[0] in g]
        rows = [[_cell(g[key][k], fmt) for key, _, _, fmt in columns]
                for k in range(len(g["tank_fraction"]))]
        print(f"[{'filling' if name == 'frames' else 'draining'}]")
        print(format_table([(head, unit) for _, head, unit, _ in columns], rows,
                           [fmt for *_, fmt in columns]))
    _print_limit_points(result.groups.get("limit_points"))
    notes = _notes_by_column()
    shown = [notes[head] for key, head, *_ in SWEEP_COLUMNS
             if any(key in result.groups.get(n, {}) for n in ("frames", "drain"))]
    for note in dict.fromkeys(shown):
        print(f"  {note}")


def _print_limit_points(points) -> None:
    """One line per snap a sweep crossed (group ``limit_points``), None: none recorded."""
    for k in range(len(points["tank_fraction"]) if points else 0):
        event = points["event"][k]
        event = event.decode() if isinstance(event, bytes) else str(event)
        print(f"  {event} at tank fraction {float(points['tank_fraction'][k]):.4f}: level "
              f"{float(points['pressure_level_before'][k]):.1f} -> "
              f"{float(points['pressure_level'][k]):.1f} Pa")


def _cell(value, fmt: str):
    """A table cell: the number (an integer for an integer format), or None where it is
    missing."""
    value = float(value)
    if not np.isfinite(value):
        return None
    return int(value) if fmt == "d" else float(np.round(value, 12)) + 0.0  # no -0.0000


