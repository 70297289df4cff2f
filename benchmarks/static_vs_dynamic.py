"""Static against dynamic: how the coupled fill departs from the static model as the port flow
and a lateral acceleration grow, the regime map, and the table ``fsi advise`` reads.

    python benchmarks/static_vs_dynamic.py [--write-table] [--cases slow pump ...] [--smoke]

Each case (:func:`fsi.analysis.static_vs_dynamic.flow_case`): the bundled ``diaphragm-fill`` (Table
4.1 diaphragm, N = 14, 16^3 cells) from its static start at tank fraction 0.5, filled by 0.02
of the tank (0.005 in the lateral cases) at the case's flow; every frame against the static
equilibrium holding the same liquid volume on the same path (Eqn 6.1, pressure level, liquid
centre of mass, the dynamic amplification of the sheet's peak stress), the largest of each
over the frames.  Cases: the four flows of
:data:`fsi.analysis.static_vs_dynamic.FLOWS` (2e-5 to 1e-2 m^3/s, the last opened in 20 ms) and the
fast flow with a lateral impulse of 1 and 3 m/s^2 over 0.1 s.

Writes ``benchmarks/output/static_vs_dynamic.json``, ``regime_map.png`` (Pi_t against Pi_p,
each case labelled with its Eqn 6.1 difference) and ``static_vs_dynamic.png`` (the three
differences against Pi_p); with ``--write-table`` also ``fsi/regime_table.json``.  Prints
one JSON object, ``cases`` keyed by case name (a full run also writes it to
``docs/data/static_vs_dynamic.json``).  About
10 min on 2 cores.  ``--smoke``: every case with :data:`SMOKE_CHANGES` (its files under
``benchmarks/output/smoke/``; never the table).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _report import SMOKE_HELP, emit, output_dir  # noqa: E402
from fsi.analysis.regime import REGIME_TABLE_FILE, plot_map  # noqa: E402
from fsi.analysis.static_vs_dynamic import FLOWS, flow_case  # noqa: E402

#: --smoke: what it changes in every case: the fill it runs (tank fraction) and the flow's
#: ramp (s), so that each ends in one or two windows
SMOKE_CHANGES = dict(fill_step=1e-5, ramp_time=0.002)
CASES = {**{name: dict(case) for name, case in FLOWS.items()},
         "fast, lateral 1 m/s^2": dict(FLOWS["fast"], lateral=1.0, fill_step=0.005),
         "fast, lateral 3 m/s^2": dict(FLOWS["fast"], lateral=3.0, fill_step=0.005)}
#: the JSON's top-level keys the documentation reads: ``cases``, one entry per case of CASES
DOC_FIELDS = ("cases",)
MEASURES = {"eqn_6_1": "Eqn 6.1 (%)", "level_difference": "|level difference| (Pa)",
            "centre_distance_mm": "centre of mass distance (mm)",
            "stress_ratio": "peak stress, dynamic / static"}


def plot_measures(runs: list):
    fig, axes = plt.subplots(1, len(MEASURES), figsize=(13, 3.8))
    for ax, (key, label) in zip(axes, MEASURES.items()):
        for r in runs:
            ax.loglog(r["pressure_ratio"], max(abs(r[key]), 1e-9), "o", label=r["name"])
        ax.set_xlabel("Pi_p = dynamic / hydrostatic pressure")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    return fig


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--write-table", action="store_true",
                        help=f"write the measured runs to {REGIME_TABLE_FILE}")
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        args.cases, args.write_table = list(CASES), False
    output = output_dir(args.smoke)
    logging.getLogger().setLevel(logging.ERROR)
    runs = {}
    for name in args.cases:
        runs[name] = flow_case(**dict(CASES[name], **(SMOKE_CHANGES if args.smoke else {})))
        r = runs[name]
        print(f"{name}: Pi_p {r['pressure_ratio']:.3g}, Pi_t {r['time_ratio']:.3g}, Eqn 6.1 "
              f"{r['eqn_6_1']:.3g} %, level {r['level_difference']:.3g} Pa, centre "
              f"{r['centre_distance_mm']:.3g} mm, stress x {r['stress_ratio']:.3g} (static "
              f"path: {r['path_eqn_6_1']:.3g} %, "
              f"{r['path_level_difference']:.3g} Pa), {r['seconds']:.0f} s, unconverged "
              f"{r['windows_unconverged']} of {r['windows']}", file=sys.stderr)
    output.mkdir(parents=True, exist_ok=True)
    (output / "static_vs_dynamic.json").write_text(json.dumps(runs, indent=1))
    for draw, file in ((plot_map, "regime_map.png"), (plot_measures, "static_vs_dynamic.png")):
        fig = draw([dict(r, name=name) for name, r in runs.items()])
        fig.savefig(output / file, dpi=110, bbox_inches="tight")
        plt.close(fig)
    if args.write_table:
        keys = ("flow", "lateral", "pressure_ratio", "time_ratio", "eqn_6_1",
                "level_difference", "centre_distance_mm", "stress_ratio", "path_eqn_6_1",
                "path_level_difference", "path_stress_ratio", "windows_unconverged")
        table = dict(source="benchmarks/static_vs_dynamic.py",
                     case="diaphragm-fill from tank fraction 0.5, N = 14, 16^3 cells",
                     runs=[dict(name=name, **{k: r[k] for k in keys})
                           for name, r in runs.items()])
        REGIME_TABLE_FILE.write_text(json.dumps(table, indent=1) + "\n")
    emit("static_vs_dynamic", {"cases": {name: {k: v for k, v in r.items() if k != "rows"}
                                         for name, r in runs.items()}}, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
