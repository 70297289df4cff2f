"""The fluid's verification numbers, printed as one JSON object (about 2 minutes).

    python benchmarks/fluid_checks.py

Each entry is measured against a closed-form oracle (see tests/test_fluid.py for the same
cases as pass/fail tests): hydrostatics with a membrane in the immersed sphere (axisymmetric
and 3-D), the added-mass pressure under an accelerating piston, liquid-volume bookkeeping
with port inflow, Hagen-Poiseuille flow through an immersed pipe wall and its grid
convergence.
"""
from __future__ import annotations

import json
import sys
import time

import numpy as np

from fluid.validation import hydrostatic_check, piston_check, poiseuille_error, volume_check
from fsi.constants import STANDARD_GRAVITY, TANK_RADIUS, WATER_DENSITY

R, RHO, G = TANK_RADIUS, WATER_DENSITY, STANDARD_GRAVITY


def main() -> dict:
    tic = time.perf_counter()
    out = {}
    for name, job in [("hydrostatics_axisymmetric",
                       lambda: hydrostatic_check(R, True, 32, density=RHO, gravity=G)),
                      ("hydrostatics_3d",
                       lambda: hydrostatic_check(R, False, 16, density=RHO, gravity=G)),
                      ("piston", lambda: [piston_check(n, gravity=G) for n in (16, 32, 64)]),
                      ("volume_bookkeeping", lambda: volume_check(R, gravity=G))]:
        print(f"{name} ...", file=sys.stderr, flush=True)
        out[name] = job()
    errors = [poiseuille_error(n) for n in (8, 16, 32)]
    out["poiseuille"] = {"cells_across": [8, 16, 32], "max_relative_error": errors,
                         "observed_order": [float(np.log2(a / b))
                                            for a, b in zip(errors[:-1], errors[1:])]}
    out["seconds"] = time.perf_counter() - tic
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
