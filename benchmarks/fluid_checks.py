"""The fluid's verification numbers, printed as one JSON object (about 2 minutes).

    python benchmarks/fluid_checks.py [--smoke]

Each entry is measured against a closed-form oracle (see tests/test_fluid.py for the same
cases as pass/fail tests): hydrostatics with a membrane in the immersed sphere (axisymmetric
and 3-D), the added-mass pressure under an accelerating piston, liquid-volume bookkeeping
with port inflow, Hagen-Poiseuille flow through an immersed pipe wall and its grid
convergence. A full run's JSON also goes to ``docs/data/fluid_checks.json``; ``--smoke`` runs
each check on its coarsest grid for a few steps (:data:`SMOKE`).
"""
from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from _report import SMOKE_HELP, emit
from fluid.validation import hydrostatic_check, piston_check, poiseuille_error, volume_check
from fsi.constants import STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY

R, RHO, G = TANK_RADIUS, WATER_DENSITY, STANDARD_GRAVITY
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("hydrostatics_axisymmetric", "hydrostatics_3d", "piston", "volume_bookkeeping",
              "poiseuille", "seconds")
#: each check's grids (cells) and steps: full run (the checks' own steps where None)
FULL = dict(axisymmetric=32, cells_3d=16, piston=(16, 32, 64), volume=32, poiseuille=(8, 16, 32),
            steps=None, poiseuille_dt=0.01)
#: --smoke: the coarsest grids, a few steps, a coarser Poiseuille time step
SMOKE = dict(axisymmetric=16, cells_3d=16, piston=(8, 16), volume=16, poiseuille=(4, 8),
             steps=3, poiseuille_dt=0.1)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    c = SMOKE if args.smoke else FULL
    steps = {} if c["steps"] is None else {"steps": c["steps"]}
    tic = time.perf_counter()
    out = {}
    for name, job in [("hydrostatics_axisymmetric",
                       lambda: hydrostatic_check(R, True, c["axisymmetric"], density=RHO,
                                                 gravity=G, **steps)),
                      ("hydrostatics_3d",
                       lambda: hydrostatic_check(R, False, c["cells_3d"], density=RHO,
                                                 gravity=G, **steps)),
                      ("piston", lambda: [piston_check(n, gravity=G, **steps)
                                          for n in c["piston"]]),
                      ("volume_bookkeeping", lambda: volume_check(R, gravity=G,
                                                                  cells=c["volume"], **steps))]:
        print(f"{name} ...", file=sys.stderr, flush=True)
        out[name] = job()
    errors = [poiseuille_error(n, dt=c["poiseuille_dt"]) for n in c["poiseuille"]]
    out["poiseuille"] = {"cells_across": list(c["poiseuille"]), "max_relative_error": errors,
                         "observed_order": [float(np.log2(a / b))
                                            for a, b in zip(errors[:-1], errors[1:])]}
    out["seconds"] = time.perf_counter() - tic
    emit("fluid_checks", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
