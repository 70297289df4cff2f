"""The valve fill with inertia (``valve-fill``: 1e-3 m^3/s opened in 20 ms, tank fraction
0.1 -> 0.9, 20 ms windows, IQN-ILS with mixing 0.1) against the static model at every 0.1 of
tank fraction, beside the valve drain and the thesis's slow fill when their results are given.

    python benchmarks/valve_fill.py [--fill DIR] [--drain DIR] [--thesis-fill DIR]
                                    [--opening DIR] [--smoke]

``--fill``: the result folder of ``fsi run valve-fill`` (run here when not given: about
15 min). ``--drain``: that of ``fsi run valve-drain`` (the same valve at -1e-3 m^3/s,
0.9 -> 0.1), compared the same way when given. ``--thesis-fill``: that of
``fsi run thesis-fill`` (2e-5 m^3/s, quasi-static windows), compared the same way when
given; ``--opening``: that of a run that opens the
valve to 1e-2 m^3/s from half full and fills to 0.9 (README, 'With mixing: the valve fill to
completion'), compared at the tank fractions it passes (0.5 ... 0.9). The static references
and measures are those of ``benchmarks/thesis_fill_drain.py``: the volume sweep of the same
membrane model and grid, and the static equilibrium sought from each frame's shape (the same
fold state); Eqn 6.1 (%), pressure level dynamic - static (Pa), liquid centre of mass
distance (mm), and the volume bookkeeping.

Writes ``benchmarks/output/valve_fill.json`` and ``valve_fill.png``; prints one JSON object (a
full run also writes it to ``docs/data/valve_fill.json``). ``--smoke``: ``valve-fill`` run for
its first two windows unless ``--fill`` is given, compared at tank fractions 0.1 and 0.9 (as
``thesis_fill_drain.py --smoke``; its files under ``benchmarks/output/smoke/``).
"""
from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

from _report import SMOKE_HELP, output_dir
from fsi.io.output import read_result
from fsi.scene import load_scene
from thesis_fill_drain import (FILLS, SMOKE_FILLS, leg, plot, run_scene, smoke_scene,
                               static_sweep, write)

LEGS = (("valve-fill", "o-"), ("valve-drain", "v:"), ("thesis-fill", "s--"),
        ("opening", "^-."))
TITLE = ("valve-fill and valve-drain (+-1e-3 m^3/s, inertia), thesis-fill (2e-5 m^3/s) and the "
         "opening from half full (1e-2 m^3/s) against the static model, N = 14, 16^3")
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("valve-fill", "static_sweep_seconds")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fill", type=Path)
    parser.add_argument("--drain", type=Path)
    parser.add_argument("--thesis-fill", type=Path)
    parser.add_argument("--opening", type=Path)
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    logging.getLogger().setLevel(logging.ERROR)
    output = output_dir(args.smoke)
    output.mkdir(parents=True, exist_ok=True)
    fills = SMOKE_FILLS if args.smoke else FILLS
    scene = smoke_scene("valve-fill", output) if args.smoke else "valve-fill"
    fill = read_result(args.fill or run_scene(scene, output / "valve-fill", exit_codes=(0, 3),
                                              overwrite=args.smoke))
    t0 = time.perf_counter()
    static = static_sweep(load_scene("valve-fill"), fills)
    out = {"valve-fill": leg(fill, static.groups["frames"], fills),
           "static_sweep_seconds": time.perf_counter() - t0}
    if args.drain is not None:
        out["valve-drain"] = leg(read_result(args.drain), static.groups["frames"], fills)
    if args.thesis_fill is not None:
        out["thesis-fill"] = leg(read_result(args.thesis_fill), static.groups["frames"], fills)
    if args.opening is not None:
        out["opening"] = leg(read_result(args.opening), static.groups["frames"], fills)
        passed = [i for i, row in enumerate(out["opening"]["sweep"]) if row["paired"]]
        for ref in ("sweep", "same_fold"):
            out["opening"][ref] = [out["opening"][ref][i] for i in passed]
    write("valve_fill", out, plot(out, LEGS, TITLE), args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
