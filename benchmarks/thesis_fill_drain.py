"""The thesis's fill and drain, coupled, against the static model at every 0.1 of tank
fraction.

    python benchmarks/thesis_fill_drain.py [--fill DIR] [--drain DIR] [--smoke]

``--fill`` / ``--drain``: result folders of ``fsi run thesis-fill`` / ``thesis-drain`` (run
here when not given, one after the other: about 5 and 10 min). The static reference is the
volume sweep of the same membrane model and grid (XPBD, N = 14, one fixed ring, tank
fractions 0.1 ... 0.9 and back down), and, at each run's own frames, the static equilibrium
sought from the frame's shape (the same fold state). At each tank fraction 0.1 ... 0.9:
Eqn 6.1 (%), pressure level dynamic - static (Pa), liquid centre of mass distance (mm), for
both references; the runs' wall time, windows, explicit (fold-snap) windows and the volume
bookkeeping (membrane and fluid cut cells against the port's integrated flow).

Writes ``benchmarks/output/thesis_fill_drain.json`` and ``thesis_fill_drain.png``; prints
one JSON object (a full run also writes it to ``docs/data/thesis_fill_drain.json``).
``--smoke``: both scenes run for their first :data:`SMOKE_WINDOWS` windows (scene files written
under ``benchmarks/output/smoke/``, with its results and figure), compared at
:data:`SMOKE_FILLS` only.
"""
from __future__ import annotations

import argparse
import json
import logging
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import tomli_w  # noqa: E402

from _report import SMOKE_HELP, emit, output_dir  # noqa: E402
from fsi.setup.build import build  # noqa: E402
from fsi.io.output import read_result  # noqa: E402
from fsi.procedures import PROCEDURES  # noqa: E402
from fsi.scene import load_scene, parse_scene  # noqa: E402
from fsi.analysis.static_vs_dynamic import against_static, compare  # noqa: E402

OUTPUT = output_dir(False)
FILLS = [round(0.1 * k, 1) for k in range(1, 10)]
STUB = "port stub"
#: the JSON's top-level keys the documentation reads
DOC_FIELDS = ("fill", "drain", "static_sweep_seconds")
#: --smoke: the windows each scene runs, and the tank fractions compared (the runs' starts)
SMOKE_WINDOWS = 2
SMOKE_FILLS = [0.1, 0.9]


def smoke_scene(name: str, folder: Path, windows: int = SMOKE_WINDOWS) -> Path:
    """Bundled scene ``name`` cut to its first ``windows`` windows, written as
    ``folder/name.toml`` (the file ``fsi run`` takes)."""
    values = tomllib.loads(load_scene(name).text)
    dynamics = values["dynamics"]
    dynamics["end_time"] = windows * dynamics["window"]
    dynamics["frame_interval"] = 1
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.toml"
    path.write_text(tomli_w.dumps(values))
    return path


def run_scene(name: str, folder: Path, exit_codes=(0,), overwrite: bool = False) -> Path:
    """``fsi run name --out folder`` (``name``: a bundled scene or a scene file;
    ``overwrite``: replace ``folder``); raises unless it exits with one of ``exit_codes`` (3:
    it ran to its end with windows accepted unconverged)."""
    code = subprocess.run([sys.executable, "-m", "fsi.cli", "run", str(name), "--out",
                           str(folder), "--no-plots"] + (["--overwrite"] if overwrite else [])
                          ).returncode
    if code not in exit_codes:
        raise RuntimeError(f"fsi run {name} exited with {code}")
    return folder


def static_sweep(dynamic_scene, fills=FILLS):
    """The volume sweep of the coupled scene's membrane (XPBD), up and down through
    ``fills`` (by 0.1)."""
    keys = {table: dict(dynamic_scene[table]) for table in ("tank", "membrane", "liquid")}
    keys["structure"] = {"model": "xpbd"}
    keys["sweep"] = {"scale": "tank", "fills": list(fills), "drain": True}
    scene = load_scene("diaphragm-static").with_keys(keys)
    return PROCEDURES["volume-sweep"](build(scene), lambda fraction, message: None)


def bookkeeping(result: dict) -> dict:
    """Membrane and fluid (cut cells, without the port stub below the sphere) against V0 +
    the port's integral at the end, relative to the end volume; the fluid also at the start
    and its largest difference over the windows."""
    w, frames, a = result["windows"], result["frames"], result["attrs"]
    delivered = w["delivered_volume"][-1]
    stub = a["port_stub_volume"]
    fluid = w["fluid_liquid_volume"][-1] - stub
    membrane = w["liquid_volume"][-1]
    expected = a["start_volume"] + delivered
    return dict(membrane=float((membrane - expected) / expected),
                fluid=float((fluid - expected) / expected),
                fluid_start=float((frames["fluid_liquid_volume"][0] - stub - a["start_volume"])
                                  / a["start_volume"]),
                fluid_windows_max=float(np.max(np.abs(
                    w["fluid_liquid_volume"] - stub - a["start_volume"] - w["delivered_volume"])
                    / (a["start_volume"] + w["delivered_volume"]))))


def leg(result: dict, static_frames: dict, fills=FILLS) -> dict:
    """One run against the static sweep and the same-fold equilibria at ``fills``."""
    setup = build(parse_scene(result["attrs"]["scene"]))
    frames = result["frames"]
    picks = [int(np.argmin(np.abs(frames["tank_fraction"] - f))) for f in fills]
    picked = {k: v[picks] for k, v in frames.items() if hasattr(v, "shape") and len(v) == len(
        frames["tank_fraction"])}
    w, a = result["windows"], result["attrs"]
    return dict(sweep=compare(frames, static_frames, setup.model, fills),
                same_fold=against_static(setup, picked),
                run_seconds=float(a["run_seconds"]), windows=int(a["windows_done"]),
                windows_explicit=int(np.sum(w["explicit"])),
                windows_with_inertia=int(a["windows_with_inertia"]),
                windows_over_tolerance=(int(a["windows_over_tolerance"])
                                        if "windows_over_tolerance" in a else None),
                windows_unconverged=int(a["windows_unconverged"]),
                mean_coupling_iterations=float(a["mean_coupling_iterations"]),
                failure=a["failure"], volume=bookkeeping(result))


LEGS = (("fill", "o-"), ("drain", "s--"))
TITLE = "thesis-fill and thesis-drain (2e-5 m^3/s, N = 14, 16^3) against the static model"


def plot(out: dict, legs=LEGS, title: str = TITLE):
    """Eqn 6.1 and the level difference by tank fraction for each (name, line style) in
    ``legs`` present in ``out``, against both static references."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for name, style in legs:
        if name not in out:
            continue
        for ref, colour in (("sweep", "tab:red"), ("same_fold", "tab:blue")):
            rows = out[name][ref]
            f = [r["fill"] for r in rows]
            axes[0].semilogy(f, [max(r["eqn_6_1"], 1e-6) for r in rows], style, color=colour,
                             label=f"{name}, against the {ref.replace('_', ' ')}")
            axes[1].plot(f, [r["level_difference"] for r in rows], style, color=colour,
                         label=f"{name}, {ref.replace('_', ' ')}")
    axes[0].set_ylabel("Eqn 6.1 dynamic against static (%)")
    axes[1].set_ylabel("pressure level, dynamic - static (Pa)")
    for ax in axes:
        ax.set_xlabel("tank fraction V / (4/3 pi R^3)")
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    fig.suptitle(title)
    return fig


def write(name: str, out: dict, fig, smoke: bool = False) -> None:
    """``name.json`` and ``name.png`` (``fig``, closed) under :func:`_report.output_dir`, and
    ``out`` emitted (:func:`_report.emit`: printed as one JSON object, and unless ``smoke``
    written to ``docs/data/name.json``)."""
    output = output_dir(smoke)
    output.mkdir(parents=True, exist_ok=True)
    (output / f"{name}.json").write_text(json.dumps(out, indent=1))
    fig.savefig(output / f"{name}.png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    emit(name, out, smoke)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fill", type=Path)
    parser.add_argument("--drain", type=Path)
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    args = parser.parse_args(argv)
    logging.getLogger().setLevel(logging.ERROR)
    output = output_dir(args.smoke)
    output.mkdir(parents=True, exist_ok=True)
    fills = SMOKE_FILLS if args.smoke else FILLS
    runs = {}
    for name, given in (("thesis-fill", args.fill), ("thesis-drain", args.drain)):
        if given is None and args.smoke:
            given = run_scene(smoke_scene(name, output), output / name, overwrite=True)
        runs[name] = read_result(given or run_scene(name, output / name))
    t0 = time.perf_counter()
    static = static_sweep(load_scene("thesis-fill"), fills)
    static_seconds = time.perf_counter() - t0
    out = dict(fill=leg(runs["thesis-fill"], static.groups["frames"], fills),
               drain=leg(runs["thesis-drain"], static.groups["drain"], fills),
               static_sweep_seconds=static_seconds)
    write("thesis_fill_drain", out, plot(out), args.smoke)
    return 0


if __name__ == "__main__":
    sys.exit(main())
