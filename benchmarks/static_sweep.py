"""Time the thesis static sweep and the thesis mode against the thesis's 6 h 50 min.

    python benchmarks/static_sweep.py [--smoke]

Runs (compilation excluded: a small warm-up run compiles and caches the numba kernels first)
1. the volume-controlled sweep of the bundled ``thesis-static`` scene, filling leg only
   (11 fills, 26 x 26 grid);
2. the thesis mode, the bundled ``thesis-ramp`` scene (50,000 steps at dt = 1e-4 s);
and prints one JSON object: seconds of each, the speed-up over 24,600 s (Levine 2014, Table 4.1
runtime), the goals (sweep <= 10 s, thesis mode <= 60 s) and, for the sweep, the largest
volume error and strain, so that speed is never reported without accuracy, and the profile of each (a second run
under cProfile: the functions with the most own time). A full run's JSON
also goes to ``docs/data/static_sweep.json``. ``--smoke``: both on a 10 x 10 grid, the sweep
to three fills, the thesis mode for 0.05 s (:data:`SMOKE_KEYS`).
"""
from __future__ import annotations

import argparse
import logging
import time

import numpy as np

from _report import SMOKE_HELP, emit, profile
from fsi.setup.build import build
from fsi.constants import THESIS_RUNTIME_SECONDS
from fsi.procedures import PROCEDURES
from fsi.scene import load_scene, parse_scene

GOALS = {"sweep_seconds": 10.0, "thesis_mode_seconds": 60.0}
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("sweep_seconds", "sweep_speedup", "sweep_max_relative_volume_error",
              "thesis_mode_seconds", "thesis_mode_speedup", "goals_met", "sweep_profile",
              "thesis_mode_profile", "anchor_seconds", "goals_seconds", "sweep_max_strain_error",
              "sweep_max_single_spring_strain", "thesis_mode_final_fill")
#: --smoke: the keys changed in the two scenes
SMOKE_KEYS = {"thesis-static": {"membrane": {"grid_size": 10},
                                "sweep": {"fills": [0.0, 0.5, 1.0]}},
              "thesis-ramp": {"membrane": {"grid_size": 10}, "thesis": {"end_time": 0.05}}}


def _quiet(fraction, message):
    pass


def _timed(setup):
    t0 = time.perf_counter()
    result = PROCEDURES[setup.scene["scene"]["procedure"]](setup, _quiet)
    return time.perf_counter() - t0, result


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    smoke = SMOKE_KEYS if args.smoke else {"thesis-static": {}, "thesis-ramp": {}}
    # warm-up: compile every kernel on a small grid (its convergence warnings are not the point)
    logging.getLogger("fsi").setLevel(logging.ERROR)
    for proc in ("volume-sweep", "thesis-ramp"):
        warm = parse_scene(f"[scene]\nprocedure = '{proc}'\n[structure]\nmodel = 'thesis'\n"
                           "[membrane]\ngrid_size = 6\n"
                           "[sweep]\nfills = [0.0, 0.5]\ndrain = false\n"
                           "scale = 'full-inversion'\n"
                           "[thesis]\nend_time = 0.01\nframe_interval = 10\n")
        _timed(build(warm))
    logging.getLogger("fsi").setLevel(logging.WARNING)

    static = load_scene("thesis-static").with_keys({"sweep": {"drain": False}})
    static = static.with_keys(smoke["thesis-static"])
    sweep_s, sweep = _timed(build(static))
    frames = sweep.groups["frames"]
    target = np.asarray(frames["target_fill"])
    volume_error = np.abs(frames["liquid_volume"] - (
        sweep.attrs["empty_volume"] + target * (sweep.attrs["full_volume"]
                                                - sweep.attrs["empty_volume"])))
    rel = volume_error / np.maximum(frames["liquid_volume"], 1e-300)

    ramp_scene = load_scene("thesis-ramp").with_keys(smoke["thesis-ramp"])
    ramp_s, ramp = _timed(build(ramp_scene))
    # the profiles: a second run of each under cProfile (its overhead kept out of the timings)
    _, sweep_profile = profile(_timed, build(static))
    _, ramp_profile = profile(_timed, build(ramp_scene))
    out = {
        "sweep_seconds": round(sweep_s, 3),
        "sweep_speedup": round(THESIS_RUNTIME_SECONDS / sweep_s, 1),
        "sweep_fills": len(target),
        "sweep_all_converged": bool(np.all(frames["converged"])),
        "sweep_max_relative_volume_error": float(np.max(rel[target > 0])) if np.any(target > 0)
        else 0.0,
        "sweep_max_strain_error": float(np.max(frames["strain_error"])),
        "sweep_max_single_spring_strain": float(np.max(frames["strain_max"])),
        "thesis_mode_seconds": round(ramp_s, 3),
        "thesis_mode_speedup": round(THESIS_RUNTIME_SECONDS / ramp_s, 1),
        "thesis_mode_final_fill": float(ramp.groups["history"]["inversion_fraction"][-1]),
        "anchor_seconds": THESIS_RUNTIME_SECONDS,
        "goals_seconds": GOALS,
        "sweep_profile": sweep_profile,
        "thesis_mode_profile": ramp_profile,
        "goals_met": {k: bool(out_s <= GOALS[k]) for k, out_s in
                      (("sweep_seconds", sweep_s), ("thesis_mode_seconds", ramp_s))},
    }
    emit("static_sweep", out, args.smoke)
    return out


if __name__ == "__main__":
    main()
