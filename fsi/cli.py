"""Command line: ``fsi run``, ``fsi compare``, ``fsi advise``, ``fsi scenes``.

    fsi run <bundled scene | scene.toml> --out DIR [--no-plots]
    fsi compare A B [--fill F] [--obj-scale S]
    fsi advise <bundled scene | scene.toml> [--accuracy PERCENT]
    fsi scenes [--reference]
"""
from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

import numpy as np

log = logging.getLogger("fsi")


class ProgressBar:
    """Progress with ETA on stderr (tqdm), driven by fraction done. The ETA is the rate since
    the first work reported, so a long setup (a static start) does not inflate it."""

    def __init__(self, label: str):
        from tqdm import tqdm

        self.bar = tqdm(total=1000, desc=label, unit="‰", file=sys.stderr,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}{postfix}",
                        mininterval=0.5)
        self.last = -1e9
        self.first = None  # (time, fraction) of the first report with work done

    def eta(self, now: float, fraction: float) -> str:
        """'ETA h:mm:ss' from the rate since the first report with work done, or '' before
        there is a rate."""
        from tqdm import tqdm

        if self.first is None:
            if fraction > 0:
                self.first = (now, fraction)
            return ""
        t0, f0 = self.first
        if fraction <= f0:
            return ""
        return "ETA " + tqdm.format_interval((now - t0) / (fraction - f0) * (1 - fraction))

    def __call__(self, fraction: float, message: str) -> None:
        now = time.monotonic()
        eta = self.eta(now, fraction)
        if fraction < 1.0 and now - self.last < 0.5:
            return
        self.last = now
        self.bar.n = int(1000 * fraction)
        self.bar.set_postfix_str(f"{eta}, {message}" if eta else message, refresh=False)
        self.bar.refresh()

    def close(self):
        self.bar.close()


def cmd_run(args) -> int:
    from .build import build
    from .output import write_result
    from .plots import make_plots
    from .scene import load_scene

    scene = load_scene(args.scene)
    setup = build(scene)  # validates the time step before anything is written
    procedure = setup.procedure
    bar = ProgressBar(scene.name)
    t0 = time.perf_counter()
    try:
        result = procedure(setup, bar)
    finally:
        bar.close()
    result.attrs["run_seconds"] = time.perf_counter() - t0
    path = write_result(Path(args.out), scene, setup.model, result)
    log.info("wrote %s (%.1f s)", path, result.attrs["run_seconds"])
    procedure.report(result)
    if not args.no_plots:
        plots = make_plots(args.out)
        log.info("wrote %d plots in %s", len(plots), Path(args.out) / "plots")
    if result.attrs.get("failure"):
        print(f"fsi: error: the run stopped early: {result.attrs['failure']}", file=sys.stderr)
        return 1
    if result.attrs.get("analysis_failure"):
        print(f"fsi: error: the run's analysis failed: {result.attrs['analysis_failure']}",
              file=sys.stderr)
        return 1
    return 0


class UsageError(Exception):
    """A command-line value out of range: one line on stderr, exit status 2."""


PAIRING_TOLERANCE = 0.01
"""Tank fractions of two compared frames further apart than this are flagged (-)."""


def _pick_frames(res: dict, fill, scale: str, label: str) -> list[int]:
    """Indices of the frames of ``res`` to compare: all, or the one nearest ``fill`` on
    ``scale`` (tank: V / (4/3 pi R^3); full-inversion: the thesis's, static results only)."""
    frames = res["frames"]
    if fill is None:
        return list(range(len(frames["tank_fraction"])))
    if not 0.0 <= fill <= 1.0:
        raise UsageError(f"--fill {fill}: a fill is in [0, 1]")
    if scale == "tank":
        values = frames["tank_fraction"]
    elif "mirrored_volume" in res["attrs"]:  # a static result: it carries its full inversion
        a = res["attrs"]
        values = (frames["liquid_volume"] - a["empty_volume"]) / (a["full_volume"]
                                                                  - a["empty_volume"])
    else:
        raise UsageError(f"--scale full-inversion: {label} has no full inversion (only static "
                         f"results do); compare by tank fraction")
    return [int(np.argmin(np.abs(values - fill)))]


def cmd_compare(args) -> int:
    from .compare import eqn_6_1_error, read_obj_surface
    from .output import read_result

    a = read_result(args.a)
    radius = float(a["attrs"]["radius"])
    frames = a["frames"]
    pick = _pick_frames(a, args.fill, args.scale, str(args.a))
    if str(args.b).lower().endswith(".obj"):
        points, faces = read_obj_surface(args.b)
        points = points * args.obj_scale
        print("tank A   Eqn 6.1 error (%)  vs " + str(args.b))
        for k in pick:
            e = eqn_6_1_error(points, faces, frames["node_position"][k], radius)
            print(f"{frames['tank_fraction'][k]:6.3f}  {e:10.4f}")
        return 0
    b = read_result(args.b)
    faces = b["membrane"]["face_nodes"]
    b_tank = b["frames"]["tank_fraction"]
    print("tank A  tank B   Eqn 6.1 error (%)   (B's frame nearest in tank fraction "
          "V / (4/3 pi R^3))")
    flagged = False
    for k in pick:
        j = int(np.argmin(np.abs(b_tank - frames["tank_fraction"][k])))
        e = eqn_6_1_error(b["frames"]["node_position"][j], faces, frames["node_position"][k],
                          radius)
        far = abs(b_tank[j] - frames["tank_fraction"][k]) > PAIRING_TOLERANCE
        flagged |= far
        print(f"{frames['tank_fraction'][k]:6.3f}  {b_tank[j]:6.3f}  {e:10.4f}"
              + ("  *" if far else ""))
    if flagged:
        print(f"* B has no frame within {PAIRING_TOLERANCE} of A's tank fraction: the shapes "
              f"hold different volumes")
    return 0


def cmd_scenes(args) -> int:
    from .scene import bundled_scenes, load_scene, reference_markdown

    if args.reference:
        print(reference_markdown())
        return 0
    for name in bundled_scenes():
        print(f"{name:16s} {load_scene(name)['scene']['description']}")
    return 0


def cmd_advise(args) -> int:
    from .regime import advise_scene, load_table
    from .scene import load_scene

    if not args.accuracy > 0:
        raise UsageError(f"--accuracy {args.accuracy}: an accuracy is > 0 (% Eqn 6.1)")
    scene = load_scene(args.scene)
    model, reasons = advise_scene(scene, args.accuracy, load_table())
    print(f"{scene['scene']['name']}: {model} model")
    for line in reasons:
        print(f"  {line}")
    return 0


def main(argv=None) -> int:
    from .scene import SceneError

    parser = argparse.ArgumentParser(prog="fsi", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run a scene and write results and plots")
    p.add_argument("scene", help="bundled scene name or path to a .toml scene file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.set_defaults(func=cmd_run)
    p = sub.add_parser("compare", help="Eqn 6.1 error per fill between two results, "
                                       "or a result and a Wavefront .obj surface")
    p.add_argument("a", help="result folder or result.h5 (compared)")
    p.add_argument("b", help="result folder / result.h5, or .obj surface (reference)")
    p.add_argument("--fill", type=float,
                   help="compare only A's frame nearest this fill, in [0, 1], on --scale")
    p.add_argument("--scale", choices=("tank", "full-inversion"), default="tank",
                   help="scale of --fill: tank fraction V / (4/3 pi R^3) (default) or the "
                        "thesis's full-inversion scale (static results)")
    p.add_argument("--obj-scale", type=float, default=1.0,
                   help="factor from .obj units to m (default 1)")
    p.set_defaults(func=cmd_compare)
    p = sub.add_parser("advise", help="which model a scene needs for a stated accuracy, and "
                                      "why (the numbers it used)")
    p.add_argument("scene", help="bundled scene name or path to a .toml scene file")
    p.add_argument("--accuracy", type=float, default=1.0,
                   help="largest acceptable shape difference from the coupled model, "
                        "% Eqn 6.1 (default 1)")
    p.set_defaults(func=cmd_advise)
    p = sub.add_parser("scenes", help="list bundled scenes")
    p.add_argument("--reference", action="store_true", help="print the scene key reference")
    p.set_defaults(func=cmd_scenes)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except (SceneError, UsageError, FileNotFoundError) as exc:
        print(f"fsi: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
