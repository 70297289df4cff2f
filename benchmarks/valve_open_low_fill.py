"""Where the coupled fill fails: a valve opening from a nearly empty tank.

    python benchmarks/valve_open_low_fill.py [--cases NAME ...] [--smoke]

Each case is the bundled ``valve-open`` scene (Table 4.1 diaphragm, N = 14, 16^3 cells, the
valve opened over 20 ms) started from its static equilibrium at tank fraction 0.1 instead of
0.5, with the thesis scenes' rim (one fixed ring on the equator, ``simply-supported``, so that
the diaphragm can pass 0.62), at one port flow and one kind of window, run for a short
stretch of simulated time.  At 0.1 the liquid is a lens 2.6 cells deep under the membrane and
the rest of the sheet lies on the tank wall.  The ``from 0.5`` cases start the same opening
from half full, as the bundled scene does, and run it past the scene's 0.087 s, with its own
two-ring rim (``clamped``) and with the thesis rim, to show how far the opening holds there.
The ``mixing 0.1`` cases relax IQN-ILS's step outside its secants' span by 0.1
(``coupling.mixing``), some without reused secants (``no reuse``, ``coupling.reuse = 0``),
one with the pressure fitted from each window's starting cells (``window cells``,
``fluid.pressure_cells = "window"``);
the two long ones (``LONG_CASES``: from half full to 0.9, and the ``valve-fill``'s drain from
0.9) run only when named.
Reported per case: windows done, coupling iterations per window, windows accepted unconverged
or redone explicitly, how the run ended (``failure``: '' when it reached its end time), whether
it held (reached its end with at most 2 % of its windows unconverged), the static start's
pressure level (the start is relaxed at the window's own substep, so it lands in a fold state
of its own), wall seconds, and, for a case that reached its end, the wall time a whole fill
from its start to 0.9 (a drain: to 0.1) at that flow and window would take at the same rate
(``full_fill_hours``).

Each kind of window takes the flow study's keys (:data:`fsi.analysis.static_vs_dynamic.TIME_SCHEME_KEYS`):
the inertial ones the scene's coupling (IQN-ILS, 100 iterations, a stalled window accepted),
the quasi-static ones the thesis fill's.  Writes
``benchmarks/output/valve_open_low_fill.json`` and ``valve_open_low_fill.png`` (each case by
flow and window, marked by its outcome, and how far each ``from 0.5`` case ran).  Prints one
JSON object (a full run also writes it to ``docs/data/valve_open_low_fill.json``); about 45 min.
``--smoke``: :data:`SMOKE_CASES`, each cut to two windows (its files under
``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from _report import SMOKE_HELP, emit, output_dir  # noqa: E402
from fsi.setup.build import build  # noqa: E402
from fsi.procedures import PROCEDURES  # noqa: E402
from fsi.scene import load_scene  # noqa: E402
from fsi.analysis.static_vs_dynamic import TIME_SCHEME_KEYS  # noqa: E402

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("start_fill", "end_fill", "runs")
START_FILL = 0.1
MIXING_NO_REUSE = {"coupling": dict(mixing=0.1, reuse=0)}
"""The keys of the ``mixing 0.1, no reuse`` cases (README, 'With mixing')."""
WINDOW_CELLS = dict(MIXING_NO_REUSE, fluid=dict(pressure_cells="window"))
"""Those and the pressure fitted from each window's starting cells (README, 'The pressure
cells of a window')."""
VALVE_FILL_COUPLING = dict(WINDOW_CELLS, dynamics=dict(node_damping=0.03),
                           coupling=dict(WINDOW_CELLS["coupling"],
                                         interface_velocity="window-mean",
                                         on_max_iterations="accept-best"))
"""Those, the window-mean velocity, the node damping and the best iterate of a stalled window:
the bundled valve fill's coupling (README, 'Keeping a stalled window's best iterate')."""
BOTH_KEYS = dict(VALVE_FILL_COUPLING, fluid=dict(VALVE_FILL_COUPLING["fluid"],
                                                 centre_cells="window", pressure_fit="tapered"))
"""The valve fill's coupling with the cell classes held over a window and the tapered fit."""
END_FILL = 0.9
CASES = {
    "1e-3, 1 ms": dict(flow=1e-3, window=1e-3, end_time=0.1),
    "1e-3, 2 ms": dict(flow=1e-3, window=2e-3, end_time=0.1),
    "1e-3, 10 ms": dict(flow=1e-3, window=1e-2, end_time=0.1),
    "1e-3, windows by error from 1 ms": dict(
        flow=1e-3, window=1e-3, end_time=0.1,
        changes={"dynamics": dict(window_tolerance=1e-4, min_window=1e-3, max_window=0.2)}),
    "3e-3, 1 ms": dict(flow=3e-3, window=1e-3, end_time=0.05),
    "1e-2, 1 ms": dict(flow=1e-2, window=1e-3, end_time=0.02),
    "1e-2, 1 ms, first relaxation 1e-3": dict(
        flow=1e-2, window=1e-3, end_time=0.02,
        changes={"coupling": dict(initial_relaxation=1e-3)}),
    "1e-2, 0.25 ms": dict(flow=1e-2, window=2.5e-4, end_time=0.01),
    "1e-3, quasi-static": dict(flow=1e-3, scheme="quasi-static", end_time=4.0),
    "2e-4, quasi-static": dict(flow=2e-4, scheme="quasi-static", end_time=20.0),
    "from 0.5, clamped, 1e-2, 1 ms": dict(flow=1e-2, window=1e-3, end_time=0.2,
                                          start_fill=0.5, support="clamped"),
    "from 0.5, clamped, 1e-2, 1 ms, no reuse": dict(
        flow=1e-2, window=1e-3, end_time=0.2, start_fill=0.5, support="clamped",
        changes={"coupling": dict(reuse=0)}),
    "from 0.5, simply-supported, 1e-2, 1 ms": dict(flow=1e-2, window=1e-3, end_time=0.2,
                                                   start_fill=0.5),
    "1e-2, 1 ms, mixing 0.1, no reuse": dict(
        flow=1e-2, window=1e-3, end_time=0.02, changes=MIXING_NO_REUSE),
    "1e-3, 20 ms": dict(flow=1e-3, window=2e-2, end_time=1.0),
    "1e-3, 20 ms, no reuse": dict(flow=1e-3, window=2e-2, end_time=1.0,
                                  changes={"coupling": dict(reuse=0)}),
    "1e-3, 10 ms, mixing 0.1, no reuse": dict(
        flow=1e-3, window=1e-2, end_time=1.0, changes=MIXING_NO_REUSE),
    "1e-3, 20 ms, mixing 0.1, no reuse": dict(
        flow=1e-3, window=2e-2, end_time=1.0, changes=MIXING_NO_REUSE),
    "1e-3, 50 ms, mixing 0.1, no reuse": dict(
        flow=1e-3, window=5e-2, end_time=1.0, changes=MIXING_NO_REUSE),
    "1e-2, 1 ms, mixing 0.1, no reuse, to 0.1 s": dict(
        flow=1e-2, window=1e-3, end_time=0.1, changes=MIXING_NO_REUSE),
    "1e-2, 1 ms, mixing 0.1, no reuse, window cells": dict(
        flow=1e-2, window=1e-3, end_time=0.1, changes=WINDOW_CELLS),
    "1e-2, 1 ms, mixing 0.1, no reuse, window cells, 24^3": dict(
        flow=1e-2, window=1e-3, end_time=0.1,
        changes=dict(WINDOW_CELLS, fluid=dict(pressure_cells="window", cells=24))),
    "1e-2, 1 ms, mixing 0.1, no reuse, window cells, window-mean velocity": dict(
        flow=1e-2, window=1e-3, end_time=0.1,
        changes=dict(WINDOW_CELLS, coupling=dict(WINDOW_CELLS["coupling"],
                                                 interface_velocity="window-mean"))),
    "1e-2, 1 ms, valve-fill's coupling": dict(
        flow=1e-2, window=1e-3, end_time=0.1, changes=VALVE_FILL_COUPLING),
    "1e-2, 1 ms, valve-fill's coupling, to 0.3 s": dict(
        flow=1e-2, window=1e-3, end_time=0.3, changes=VALVE_FILL_COUPLING),
    "1e-2, 1 ms, valve-fill's coupling, both keys, to 0.3 s": dict(
        flow=1e-2, window=1e-3, end_time=0.3, changes=BOTH_KEYS),
    "3e-3, 1 ms, mixing 0.1, no reuse": dict(
        flow=3e-3, window=1e-3, end_time=0.05, changes=MIXING_NO_REUSE),
    "from 0.5, clamped, 1e-2, 1 ms, mixing 0.1": dict(
        flow=1e-2, window=1e-3, end_time=0.2, start_fill=0.5, support="clamped",
        changes={"coupling": dict(mixing=0.1)}),
    "from 0.5, simply-supported, 1e-2, 1 ms, mixing 0.1, no reuse": dict(
        flow=1e-2, window=1e-3, end_time=0.2, start_fill=0.5,
        changes=MIXING_NO_REUSE),
    "from 0.5 to 0.9, simply-supported, 1e-2, 1 ms, mixing 0.1, no reuse": dict(
        flow=1e-2, window=1e-3, end_time=1.5518, start_fill=0.5,
        changes=MIXING_NO_REUSE),
    "from 0.5 to 0.9, simply-supported, 1e-2, 1 ms, mixing 0.1, no reuse, window cells": dict(
        flow=1e-2, window=1e-3, end_time=1.5518, start_fill=0.5, changes=WINDOW_CELLS),
    "drain from 0.9 to 0.1, simply-supported, -1e-3, 20 ms, mixing 0.1, no reuse": dict(
        flow=-1e-3, window=2e-2, end_time=30.86, start_fill=0.9,
        changes=MIXING_NO_REUSE),
    "drain from 0.9 to 0.1, simply-supported, -1e-3, 20 ms, mixing 0.1, no reuse, "
    "window cells": dict(flow=-1e-3, window=2e-2, end_time=30.86, start_fill=0.9,
                         changes=WINDOW_CELLS),
}
"""name -> flow (m^3/s), window (s, inertial), end_time (s), scheme, start_fill (tank
fraction, START_FILL when not given), support (the thesis rim when not given), other keys."""
LONG_CASES = ("from 0.5 to 0.9, simply-supported, 1e-2, 1 ms, mixing 0.1, no reuse",
              "from 0.5 to 0.9, simply-supported, 1e-2, 1 ms, mixing 0.1, no reuse, "
              "window cells",
              "drain from 0.9 to 0.1, simply-supported, -1e-3, 20 ms, mixing 0.1, no reuse",
              "drain from 0.9 to 0.1, simply-supported, -1e-3, 20 ms, mixing 0.1, no reuse, "
              "window cells",
              "1e-2, 1 ms, mixing 0.1, no reuse, window cells, 24^3",
              "1e-2, 1 ms, valve-fill's coupling, to 0.3 s",
              "1e-2, 1 ms, valve-fill's coupling, both keys, to 0.3 s")
"""Cases run only when named in ``--cases``: the whole fill from half full and the valve
fill's drain (each with the cells chosen anew each iteration and at each window's start),
each a quarter of an hour or more, the opening from 0.1 on the 24^3 liquid grid, and the
opening from 0.1 with the valve fill's coupling to 0.3 s (about 10 min), alone or with the
two [fluid] keys."""
SMOKE_CASES = {"1e-3, 2 ms": 0.004, "1e-3, quasi-static": 0.4,
               "from 0.5, clamped, 1e-2, 1 ms": 0.002}
"""--smoke: one case of each kind (inertial and quasi-static windows from START_FILL, an
opening from half full) -> its end time (s): two windows."""


def run_case(flow: float, end_time: float, window: float = 1e-3, scheme: str = "euler",
             start_fill: float = START_FILL, support: str = "simply-supported",
             changes: dict | None = None) -> dict:
    keys = {table: dict(values) for table, values in TIME_SCHEME_KEYS[scheme].items()}
    keys["dynamics"].update(start_fill=start_fill, end_time=end_time)
    if scheme == "euler":
        keys["dynamics"].update(window=window)
    keys["membrane"] = dict(support=support)
    keys["port"] = dict(flow=flow)
    for table, values in (changes or {}).items():
        keys.setdefault(table, {}).update(values)
    scene = load_scene("valve-open").with_keys(keys)
    setup = build(scene)
    t0 = time.perf_counter()
    result = PROCEDURES["coupled-fill"](setup, lambda fraction, message: None)
    seconds = time.perf_counter() - t0
    a = result.attrs
    w = result.groups.get("windows", {})
    reached = float(w["time"][-1]) if len(w.get("time", [])) else 0.0
    radius = scene["tank"]["radius"]
    # to 0.9, or for a drain to START_FILL
    fill_time = ((END_FILL if flow > 0 else START_FILL) - start_fill) * 4.0 / 3.0 * np.pi \
        * radius**3 / flow
    held = not a["failure"] and a["windows_unconverged"] <= 0.02 * a["windows_done"]
    return dict(flow=flow, scheme=scheme, window=window if scheme == "euler" else None,
                start_fill=start_fill, support=support,
                end_time=end_time, reached_time=reached, failure=a["failure"],
                windows=int(a["windows_done"]),
                iterations_per_window=float(a["mean_coupling_iterations"]),
                windows_unconverged=int(a["windows_unconverged"]),
                windows_explicit=int(a["windows_explicit"]),
                start_pressure_level=float(a["start_pressure_level"]),
                level_range=[float(np.min(w["pressure_level"])),
                             float(np.max(w["pressure_level"]))] if reached else None,
                seconds=seconds, held=held,
                # the two-ring rim caps the fill at 0.62 (N = 14): no whole fill to END_FILL
                full_fill_hours=None if a["failure"] or support == "clamped"
                else seconds / reached * fill_time / 3600.0)


def plot(runs: dict):
    """Left: the cases from START_FILL by flow and window, marked by outcome; right: how far
    each case from another start ran, against its end time."""
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, r in runs.items():
        if r["start_fill"] != START_FILL:
            continue
        y = r["window"] if r["window"] is not None else 0.2
        marker = "o" if r["held"] else ("s" if not r["failure"] else "x")
        ax.loglog(r["flow"], y, marker, ms=9, label=name)
    ax.set_xlabel("port flow (m^3/s)")
    ax.set_ylabel("window (s; quasi-static at its 0.2 s floor)")
    ax.set_title(f"valve opening from tank fraction {START_FILL}: o held, s stalled windows, "
                 "x diverged", fontsize=8)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=6)
    others = {name: r for name, r in runs.items() if r["start_fill"] != START_FILL}
    for k, (name, r) in enumerate(others.items()):
        bx.barh(k, r["end_time"], color="0.85")
        bx.barh(k, r["reached_time"], color="tab:green" if r["held"] else "tab:red")
        bx.text(r["end_time"], k, f" {r['windows_unconverged']} stalled", va="center",
                fontsize=7)
    bx.set_yticks(range(len(others)), list(others), fontsize=7)
    bx.set_xlabel("simulated time reached (s); grey: the case's end")
    bx.set_title("from half full (or a drain from 0.9): green held, red stalled (over 2 % of "
                 "windows) or diverged", fontsize=8)
    fig.tight_layout()
    return fig


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", choices=list(CASES),
                        default=[name for name in CASES if name not in LONG_CASES])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.ERROR)
    output = output_dir(args.smoke)
    if args.smoke:
        runs = {name: run_case(**dict(CASES[name], end_time=end))
                for name, end in SMOKE_CASES.items()}
    else:
        runs = {name: run_case(**CASES[name]) for name in args.cases}
    output.mkdir(parents=True, exist_ok=True)
    plot(runs).savefig(output / "valve_open_low_fill.png", dpi=120)
    summary = dict(start_fill=START_FILL, end_fill=END_FILL, runs=runs,
                   png=str(output / "valve_open_low_fill.png"))
    (output / "valve_open_low_fill.json").write_text(json.dumps(summary, indent=1))
    emit("valve_open_low_fill", summary, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
