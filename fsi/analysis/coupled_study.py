"""Convergence of the coupled fill one key at a time, and its speed against accuracy.

The case: the bundled ``diaphragm-fill`` (Table 4.1 diaphragm, start at tank fraction 0.5,
0.5 L/s ramped over 0.1 s, membrane with its inertia) to ``end_time``.  Each family
(:data:`FAMILIES`) varies one key, the others at the scene's values (N = 14, 16^3 cells,
2 ms windows, pressure tolerance 1e-4):

* fluid grid 16^3, 24^3, 32^3 cells;
* membrane grid N = 14, 20, 26, under the full law (each grid's own start, and every grid's
  start carried from N = 14's, ``dynamics.start_grid``: one fold state,
  docs/notes/one-fold-state.md) and under the tension field (``membrane.wrinkling``:
  compression relaxed, docs/notes/tension-field.md), and
  the tension field one grid further, N = 20, 26, 32 (about 17 min, so not in
  :data:`DEFAULT_FAMILIES`);
* membrane grid N = 14, 20, 26 of a flat diaphragm (``membrane.shape = "disc"``, started at
  tank fraction 0.52, the sheet taut: no folds), and one grid further, N = 20, 26, 38 (not
  in :data:`DEFAULT_FAMILIES`): the same coupled stack where the membrane has a converged
  answer to approach (docs/notes/flat-diaphragm.md); and the same two with the rim held by
  its ring on r = R only (``membrane.support = "simply-supported"``), not by a second ring
  one grid edge inside it whose width changes with N (docs/notes/lateral-compliance.md, 'The
  flat diaphragm's second fixed ring');
* window 16, 8, 4 ms with ``dynamics.substep_fraction`` 0.266: 24, 12 and 6 XPBD substeps of
  the same 0.667 ms (at the scene's 0.3 an 8 ms window would take 11 of 0.727 ms).  The
  substep must stay: plain XPBD substeps (one sweep each) make the membrane's stiffness
  depend on it, and the static start picks its fold state with it (at 0.5 ms, a 1 ms
  window's, the start's level is 646 Pa against 526 Pa at 0.667 ms);
* coupling tolerance (relative pressure change per iteration) 1e-3, 1e-4, 1e-5.

Per run at the end time: the pressure level (Pa; and its mean over the windows of the run's
second half, ``level_mean``, the measure for a level that rings window to window, as the
tension-field sheet's at N = 26 does), the liquid's centre of mass (m) and the
shape, by Eqn 6.1 (%) against the finest member of its family (other grids compared on the
finest's nodes by interpolation, as Eqn 6.1 does), and wall seconds.  Per family: the
observed order p solving (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) for the three
sizes h (window; tolerance; grid spacing 1 / (N - 1) or 1 / cells), and for the shape, whose
errors are against the finest, e1 / e2 = (h1^p - h3^p) / (h2^p - h3^p).

Speed against accuracy (:func:`plot_speed_accuracy`): every run's wall seconds against its
shape error, beside the anchor, the thesis's Fluent-Transient Structural model: 4+ weeks,
never finished (:data:`THESIS_FSI_SECONDS`).
"""
from __future__ import annotations

import time

import numpy as np

from structure.volume import liquid_first_moment, liquid_volume

from fsi.setup.build import build
from fsi.analysis.compare import eqn_6_1_error
from fsi.analysis.extrapolation import observed_order
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene

THESIS_FSI_SECONDS = 4 * 7 * 24 * 3600.0
"""The thesis's coupled Fluent-Transient Structural run: 4+ weeks, not finished (s)."""
TENSION_FIELD_FURTHER = "membrane grid, tension field, N = 20-32"
"""The tension-field membrane grid one grid further: about 17 min, not in a plain study."""
ONE_FOLD_STATE = "membrane grid, one fold state"
"""The membrane grid with every grid's start carried from N = 14's (``dynamics.start_grid``)."""
FLAT = "membrane grid, flat diaphragm"
"""The membrane grid on a flat diaphragm across the equator, taut (no folds)."""
FLAT_FURTHER = "membrane grid, flat diaphragm, N = 20-38"
"""The flat diaphragm one grid further (about 1.5 min, not in a plain study)."""
FLAT_KEYS = {"membrane": {"shape": "disc"}, "dynamics": {"start_fill": 0.52}}
"""The flat diaphragm's keys: the disc, started bulged by 0.02 of the tank (taut)."""
FLAT_RIM = "membrane grid, flat diaphragm, rim ring only"
"""The flat diaphragm held by its rim ring on r = R only (``simply-supported``: the bending
holds the rim's slope), not by a second ring one grid edge inside it."""
FLAT_RIM_FURTHER = "membrane grid, flat diaphragm, rim ring only, N = 20-38"
"""The rim-ring flat diaphragm one grid further (about 35 s, not in a plain study)."""
FLAT_RIM_KEYS = {**FLAT_KEYS, "membrane": {**FLAT_KEYS["membrane"], "support": "simply-supported"}}
"""The flat diaphragm's keys with the rim held by one ring."""
FAMILIES = {
    "fluid cells": ("fluid", "cells", [16, 24, 32], {}),
    "membrane grid": ("membrane", "grid_size", [14, 20, 26], {}),
    ONE_FOLD_STATE: ("membrane", "grid_size", [14, 20, 26], {"dynamics": {"start_grid": 14}}),
    "membrane grid, tension field": ("membrane", "grid_size", [14, 20, 26],
                                     {"membrane": {"wrinkling": "tension-field"}}),
    TENSION_FIELD_FURTHER: ("membrane", "grid_size", [20, 26, 32],
                            {"membrane": {"wrinkling": "tension-field"}}),
    FLAT: ("membrane", "grid_size", [14, 20, 26], FLAT_KEYS),
    FLAT_FURTHER: ("membrane", "grid_size", [20, 26, 38], FLAT_KEYS),
    FLAT_RIM: ("membrane", "grid_size", [14, 20, 26], FLAT_RIM_KEYS),
    FLAT_RIM_FURTHER: ("membrane", "grid_size", [20, 26, 38], FLAT_RIM_KEYS),
    "window (s)": ("dynamics", "window", [0.016, 0.008, 0.004],
                   {"dynamics": {"substep_fraction": 0.266}}),
    "coupling tolerance": ("coupling", "pressure_tolerance", [1e-3, 1e-4, 1e-5], {}),
}
"""Family -> (scene table, key, values coarse to fine, other keys held: {table: {key: value}})."""
DEFAULT_FAMILIES = tuple(name for name in FAMILIES
                         if name not in (TENSION_FIELD_FURTHER, FLAT_FURTHER, FLAT_RIM_FURTHER))
"""The families a plain study runs (about 9 min on 2 cores)."""


def run(table: str, key: str, value, end_time: float, held: dict) -> dict:
    """One member: ``diaphragm-fill`` with ``table.key = value`` (and ``held``) to ``end_time``
    (s): its failure ('' when none), whether its static start converged, level (Pa) at the
    end and ``level_mean`` over the windows ending in the run's second half (Pa), liquid
    centre of mass (3,) m, end node positions (n, 3) m and faces, mean coupling iterations
    and wall seconds."""
    changes = {t: dict(keys) for t, keys in held.items()}
    changes.setdefault(table, {})[key] = value
    changes["dynamics"] = {**changes.get("dynamics", {}), "end_time": end_time,
                           "frame_interval": 100_000}
    setup = build(load_scene("diaphragm-fill").with_keys(changes))
    t0 = time.perf_counter()
    result = PROCEDURES["coupled-fill"](setup, lambda f, m: None)
    x = result.groups["frames"]["node_position"][-1]
    volume = liquid_volume(setup.model, x)
    windows = result.groups["windows"]
    late = np.asarray(windows["time"]) > end_time / 2
    return dict(value=value, failure=result.attrs["failure"],
                start_converged=bool(result.attrs["start_converged"]),
                level=float(windows["pressure_level"][-1]),
                level_mean=float(np.mean(np.asarray(windows["pressure_level"])[late])),
                centre=(liquid_first_moment(setup.model, x) / volume).tolist(),
                node_position=x, faces=setup.model.face_nodes, radius=setup.model.radius,
                mean_iterations=float(result.attrs["mean_coupling_iterations"]),
                seconds=time.perf_counter() - t0)


def family(name: str, end_time: float) -> dict:
    """The three members of family ``name`` to ``end_time`` (s): values, sizes h, runs (each
    with ``eqn_6_1_vs_finest`` in % and ``centre_vs_finest_mm``) and the observed orders of
    the level, the centre's z and the shape (None where the differences do not shrink)."""
    table, key, values, held = FAMILIES[name]
    runs = [run(table, key, v, end_time, held) for v in values]
    finest = runs[-1]
    for r in runs:
        r["eqn_6_1_vs_finest"] = eqn_6_1_error(finest["node_position"], finest["faces"],
                                               r["node_position"], finest["radius"])
        r["centre_vs_finest_mm"] = 1e3 * float(np.linalg.norm(np.subtract(r["centre"],
                                                                          finest["centre"])))
    h = ([1.0 / (v - 1) for v in values] if key == "grid_size" else
         [1.0 / v for v in values] if key == "cells" else list(values))
    out = dict(values=values, sizes=h,
               runs=[{k: v for k, v in r.items() if k not in ("node_position", "faces")}
                     for r in runs])

    def differences(f):
        return abs(f[0] - f[1]), abs(f[1] - f[2])
    e1, e2 = runs[0]["eqn_6_1_vs_finest"], runs[1]["eqn_6_1_vs_finest"]
    out["observed_order"] = {
        "level": observed_order(*differences([r["level"] for r in runs]), h),
        "level_mean": observed_order(*differences([r["level_mean"] for r in runs]), h),
        "centre_z": observed_order(*differences([r["centre"][2] for r in runs]), h),
        # the shape's errors are against the finest: e1 / e2 = (h1^p - h3^p) / (h2^p - h3^p)
        "shape": observed_order(e1 - e2, e2, h) if e1 > e2 > 0 else None}
    return out


def plot_families(result: dict):
    """Level and shape error against each family's key: a matplotlib Figure."""
    import matplotlib.pyplot as plt

    count = len(result["families"])
    fig, axes = plt.subplots(1, count, figsize=(4.3 * count, 3.8), squeeze=False)
    axes = axes[0]
    for ax, (name, fam) in zip(axes, result["families"].items()):
        v = fam["values"]
        ax.plot(v, [r["level"] for r in fam["runs"]], "o-", label="level (Pa)")
        ax2 = ax.twinx()
        ax2.plot(v, [r["eqn_6_1_vs_finest"] for r in fam["runs"]], "s--", color="tab:red",
                 label="Eqn 6.1 vs finest (%)")
        ax.set_xscale("log")
        ax.set_xlabel(name)
        ax.set_ylabel("pressure level (Pa)")
        ax2.set_ylabel("Eqn 6.1 against the finest (%)", color="tab:red")
        order = fam["observed_order"]
        ax.set_title(f"order: level {order['level'] or float('nan'):.2f}, "
                     f"shape {order['shape'] or float('nan'):.2f}", fontsize=9)
    fig.suptitle(f"diaphragm-fill at t = {result['end_time']} s")
    return fig


def plot_speed_accuracy(result: dict):
    """Wall seconds against shape error per run, one marker per family, the thesis anchor:
    a matplotlib Figure."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, fam in result["families"].items():
        runs = fam["runs"][:-1]  # the finest is each family's reference
        ax.loglog([r["seconds"] for r in runs], [r["eqn_6_1_vs_finest"] for r in runs], "o-",
                  label=name)
        for r in runs:
            ax.annotate(f"{r['value']:g}", (r["seconds"], r["eqn_6_1_vs_finest"]), fontsize=7)
    ax.axvline(THESIS_FSI_SECONDS, color="k", ls="--")
    ax.text(THESIS_FSI_SECONDS, ax.get_ylim()[0], " thesis FSI:\n 4+ weeks,\n unfinished",
            fontsize=8, va="bottom")
    ax.set_xlabel(f"wall seconds for t = {result['end_time']} s of the fill")
    ax.set_ylabel("shape error, Eqn 6.1 against the family's finest (%)")
    ax.set_title("diaphragm-fill: speed against accuracy, one key at a time")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return fig


def study(end_time: float, families=None) -> dict:
    """Every family in ``families`` (default :data:`DEFAULT_FAMILIES`) to ``end_time`` (s):
    {end_time, families}."""
    return dict(end_time=end_time, families={name: family(name, end_time)
                                             for name in (families or DEFAULT_FAMILIES)})
