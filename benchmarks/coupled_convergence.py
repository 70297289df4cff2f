"""Convergence of the coupled fill: fluid grid, membrane grid, window and coupling tolerance,
one at a time, with the observed order, and the speed-against-accuracy chart.

    python benchmarks/coupled_convergence.py [--end-time 0.048] [--families ...] [--smoke]

The study is :mod:`fsi.analysis.coupled_study` (the case, the families, the observed order and the
anchor are defined there; ``notebooks/speed_vs_accuracy.ipynb`` reads the same).  Writes
``benchmarks/output/coupled_convergence.json``, ``coupled_convergence.png`` and
``coupled_speed_accuracy.png``; prints one JSON object.  Default run: about 9 min on 2 cores
(4.5 of them the tension-field family, 3 the one-fold-state family); ``--families "membrane grid, tension field, N = 20-32"``
takes the tension field one grid further (about 17 min); ``--families "membrane grid, flat
diaphragm" "membrane grid, flat diaphragm, N = 20-38"`` runs the flat diaphragm on N = 14 to
38 (85 s).  ``--smoke``: the coupling-tolerance family to 4 ms (its files under
``benchmarks/output/smoke/``); a full run's JSON also goes to ``docs/data/``.
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
from fsi.analysis.coupled_study import DEFAULT_FAMILIES, FAMILIES, THESIS_FSI_SECONDS, family, \
    plot_families, plot_speed_accuracy  # noqa: E402

#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("end_time", "families", "thesis_fsi_seconds", "slowest_run_over_thesis")
#: --smoke: one family (three coupled fills of the bundled scene), two windows each
SMOKE_FAMILIES = ["coupling tolerance"]
SMOKE_END_TIME = 0.004


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end-time", type=float, default=0.048)
    parser.add_argument("--families", nargs="+", default=list(DEFAULT_FAMILIES),
                        choices=list(FAMILIES))
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    if args.smoke:
        args.end_time, args.families = SMOKE_END_TIME, SMOKE_FAMILIES
    output = output_dir(args.smoke)
    logging.getLogger().setLevel(logging.ERROR)
    result = dict(end_time=args.end_time, families={})
    for name in args.families:
        result["families"][name] = family(name, args.end_time)
        print(f"{name}: {result['families'][name]['observed_order']}", file=sys.stderr)
    output.mkdir(parents=True, exist_ok=True)
    (output / "coupled_convergence.json").write_text(json.dumps(result, indent=1))
    for draw, name in ((plot_families, "coupled_convergence.png"),
                       (plot_speed_accuracy, "coupled_speed_accuracy.png")):
        fig = draw(result)
        fig.savefig(output / name, dpi=110, bbox_inches="tight")
        plt.close(fig)
    result["thesis_fsi_seconds"] = THESIS_FSI_SECONDS
    result["slowest_run_over_thesis"] = max(r["seconds"] for f in result["families"].values()
                                            for r in f["runs"]) / THESIS_FSI_SECONDS
    emit("coupled_convergence", result, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
