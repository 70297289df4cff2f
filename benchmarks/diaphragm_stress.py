"""What the valve opening, the forced slosh and the thesis's fill do to the diaphragm: the
stress envelope, the topology's events, the stress cycles, and the dynamic amplification
against the static model at the same volume.

    python benchmarks/diaphragm_stress.py [--cases valve-open ...] [--smoke]

Each case is a bundled scene run as a user runs it (``fsi run NAME``: results, the
diaphragm's fields and plots) into ``benchmarks/output/diaphragm_stress/NAME``. From its
``result.h5``: the free sheet's peak surface stress and log strain with their place (polar, azimuthal
angle on the rest shape) and time, the folds at most, the events by kind, the three largest
rainflow ranges of the most loaded triangles. The dynamic amplification, the sheet's peak
stress over the static model's at the same liquid volume: for the coupled fills, every frame
against the static equilibrium holding its volume from its own shape
(:func:`fsi.analysis.static_vs_dynamic.against_static`), the largest ratio over the frames;
for the forced slosh, whose volume is its static start's, the result's
``dynamic_amplification``. Writes ``diaphragm_stress.png`` (the sheet's largest stress in
time, with the static model's where it is computed) and prints one JSON object, ``cases``
keyed by scene (a full run also writes it to ``docs/data/diaphragm_stress.json``). About
8 min on 2 cores. ``--smoke``: each scene cut to its first
windows (:data:`SMOKE_KEYS`), run without its plots.
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import tomli_w  # noqa: E402

from _report import ROOT, SMOKE_HELP, emit, output_dir  # noqa: E402
from fsi.analysis.static_vs_dynamic import against_static  # noqa: E402
from fsi.io.output import read_result  # noqa: E402
from fsi.scene import load_scene  # noqa: E402
from fsi.setup.build import build  # noqa: E402
from structure.grid import triangles_from_quads  # noqa: E402
from structure.topology import free_triangles  # noqa: E402

CASES = ("valve-open", "slosh-forced-diaphragm", "thesis-fill")
"""The bundled scenes it runs."""
SMOKE_KEYS = {"valve-open": {"dynamics": {"end_time": 0.003, "frame_interval": 1}},
              "slosh-forced-diaphragm": {"slosh": {"end_time": 0.004, "frame_interval": 1,
                                                   "analysis_start": 0.0},
                                         "membrane": {"grid_size": 10}, "fluid": {"cells": 12}},
              "thesis-fill": {"dynamics": {"end_time": 0.4}}}
"""--smoke: the keys that cut each scene to its first windows (the slosh on a coarser grid:
its static start dominates)."""
DOC_FIELDS = ("cases",)


def run_case(name: str, out: Path, smoke: bool) -> tuple[dict, dict, object]:
    """Run scene ``name`` into ``out`` as ``fsi run`` does (``smoke``: cut, no plots); (facts,
    result, scene)."""
    raw = tomllib.loads(load_scene(name).text)
    for table, keys in (SMOKE_KEYS[name] if smoke else {}).items():
        raw.setdefault(table, {}).update(keys)
    scene = load_scene(name).with_keys(SMOKE_KEYS[name]) if smoke else load_scene(name)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{name}.toml"
        path.write_text(tomli_w.dumps(raw))
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "fsi.cli", "run", str(path), "--out",
                               str(out), "--overwrite"] + (["--no-plots"] if smoke else []),
                              capture_output=True, text=True, cwd=ROOT)
        wall = time.perf_counter() - start
    if done.returncode not in (0, 3):
        raise SystemExit(f"{name}: exit {done.returncode}\n{done.stderr[-3000:]}")
    return dict(wall_seconds=round(wall, 1), exit_code=done.returncode), read_result(out), scene


def sheet_of(res: dict) -> np.ndarray:
    """(m,) bool: the free sheet's triangles of a result."""
    return free_triangles(res["membrane"]["fixed"],
                          triangles_from_quads(res["membrane"]["face_nodes"]))


def summary(res: dict) -> dict:
    """The case's figures from its result (module doc)."""
    a, frames, events = res["attrs"], res["frames"], res["events"]
    start = float(np.max(frames["surface_stress"][0][sheet_of(res)]))
    kinds, counts = np.unique([e.decode() for e in events["event"]], return_counts=True)
    out = {k: float(a[k]) for k in ("peak_stress", "peak_stress_time", "peak_stress_polar_deg",
                                     "peak_stress_azimuth_deg", "peak_strain",
                                     "peak_strain_time")}
    out.update(stress_law=str(a["stress_law"]), frames=int(len(frames["time"])),
               folds_max=int(np.max(frames["fold_count"])),
               wall_contact_max=float(np.max(frames["wall_contact_area"])),
               events={str(k): int(c) for k, c in zip(kinds, counts)},
               start_stress=start,
               peak_stress_mpa=float(a["peak_stress"]) / 1e6,
               start_stress_mpa=start / 1e6,
               event_count=int(len(events["event"])))
    cycles = res.get("cycles", {})
    order = np.argsort(cycles.get("stress_range", np.zeros(0)))[::-1][:3]
    out["largest_range_mpa"] = float(cycles["stress_range"][order[0]]) / 1e6 if len(order) \
        else 0.0
    out["largest_ranges"] = [dict(stress_range=float(cycles["stress_range"][k]),
                                  count=float(cycles["count"][k]),
                                  triangle=int(cycles["triangle"][k])) for k in order]
    if "dynamic_amplification" in a:
        out["amplification"] = float(a["dynamic_amplification"])
    return out


def amplification(scene, res: dict) -> tuple[float, list[dict]]:
    """The coupled fill's largest stress ratio over its frames, and the rows."""
    rows = against_static(build(scene), res["frames"])
    return max(r["stress_ratio"] for r in rows), rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    output = output_dir(args.smoke) / "diaphragm_stress"
    cases, series = {}, {}
    for name in args.cases:
        facts, res, scene = run_case(name, output / name, args.smoke)
        cases[name] = dict(facts, **summary(res))
        frames = res["frames"]
        series[name] = dict(time=frames["time"],
                            stress=np.max(frames["surface_stress"][:, sheet_of(res)], axis=1))
        if "amplification" not in cases[name]:
            cases[name]["amplification"], rows = amplification(scene, res)
            series[name]["static"] = [r["peak_stress_static"] for r in rows]
        if args.smoke:
            shutil.rmtree(output / name, ignore_errors=True)
        c = cases[name]
        print(f"{name}: peak {c['peak_stress'] / 1e6:.4g} MPa at t = {c['peak_stress_time']:.4g}"
              f" s, polar {c['peak_stress_polar_deg']:.1f} deg; x {c['amplification']:.4g} of "
              f"the static model's; {c['folds_max']} folds at most, events {c['events']}; "
              f"{c['wall_seconds']} s", file=sys.stderr, flush=True)
    fig, axes = plt.subplots(1, len(series), figsize=(4.6 * len(series), 3.6), squeeze=False)
    for ax, (name, s) in zip(axes[0], series.items()):
        ax.plot(s["time"], s["stress"] / 1e6, "k-", lw=1.2, label="coupled")
        if "static" in s:
            ax.plot(s["time"], np.asarray(s["static"]) / 1e6, "C0o", ms=3,
                    label="static, same volume")
        else:
            ax.axhline(s["stress"][0] / 1e6, color="C0", ls="--", label="static start")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("largest surface stress on the sheet (MPa)")
        ax.set_title(f"{name}: x {cases[name]['amplification']:.3g}", fontsize=10)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(output / "diaphragm_stress.png", dpi=110)
    plt.close(fig)
    emit("diaphragm_stress", {"cases": cases}, args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
