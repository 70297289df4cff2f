"""Convergence of the coupled fill: fluid grid, membrane grid, window and coupling tolerance,
one at a time, with the observed order, and the speed-against-accuracy chart.

    python benchmarks/coupled_convergence.py [--end-time 0.048] [--families ...]

The study is :mod:`fsi.analysis.coupled_study` (the case, the families, the observed order and the
anchor are defined there; ``notebooks/speed_vs_accuracy.ipynb`` reads the same).  Writes
``benchmarks/output/coupled_convergence.json``, ``coupled_convergence.png`` and
``coupled_speed_accuracy.png``; prints one JSON object.  Default run: about 9 min on 2 cores
(4.5 of them the tension-field family, 3 the one-fold-state family); ``--families "membrane grid, tension field, N = 20-32"``
takes the tension field one grid further (about 17 min); ``--families "membrane grid, flat
diaphragm" "membrane grid, flat diaphragm, N = 20-38"`` runs the flat diaphragm on N = 14 to
38 (85 s).
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fsi.analysis.coupled_study import DEFAULT_FAMILIES, FAMILIES, THESIS_FSI_SECONDS, family, \
    plot_families, plot_speed_accuracy  # noqa: E402

OUTPUT = Path(__file__).resolve().parent / "output"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--end-time", type=float, default=0.048)
    parser.add_argument("--families", nargs="+", default=list(DEFAULT_FAMILIES),
                        choices=list(FAMILIES))
    args = parser.parse_args(argv)
    logging.getLogger().setLevel(logging.ERROR)
    result = dict(end_time=args.end_time, families={})
    for name in args.families:
        result["families"][name] = family(name, args.end_time)
        print(f"{name}: {result['families'][name]['observed_order']}", file=sys.stderr)
    OUTPUT.mkdir(exist_ok=True)
    (OUTPUT / "coupled_convergence.json").write_text(json.dumps(result, indent=1))
    for draw, name in ((plot_families, "coupled_convergence.png"),
                       (plot_speed_accuracy, "coupled_speed_accuracy.png")):
        fig = draw(result)
        fig.savefig(OUTPUT / name, dpi=110, bbox_inches="tight")
        plt.close(fig)
    result["thesis_fsi_seconds"] = THESIS_FSI_SECONDS
    result["slowest_run_over_thesis"] = max(r["seconds"] for f in result["families"].values()
                                            for r in f["runs"]) / THESIS_FSI_SECONDS
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
