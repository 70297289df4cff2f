"""Command line: ``fsi run``, ``fsi sweep``, ``fsi compare``, ``fsi advise``, ``fsi show``,
``fsi scenes``.

    fsi run <bundled scene | scene.toml> --out DIR [--no-plots]
    fsi sweep <bundled sweep | sweep.toml> --out DIR [--workers N | --scheduler ADDRESS]
    fsi compare A B [--fill F] [--obj-scale S]
    fsi advise <bundled scene | scene.toml> [--accuracy PERCENT]
    fsi show DIR
    fsi scenes [NAME] [--reference]
    fsi sweeps [NAME]
    fsi --version
"""
from __future__ import annotations

import argparse
import logging
import sys

import numpy as np

from fsi.run_job import (EXIT_NOT_CONVERGED, ProgressBar, UsageError, guarded,  # noqa: F401
                         not_converged, run as cmd_run)

log = logging.getLogger("fsi")


class SweepBar:
    """A sweep's progress on stderr: cases done of those to run, ETA (tqdm), failures, and a
    line per case as it finishes."""

    def __init__(self, label: str):
        self.label, self.bar, self.failed = label, None, 0

    def start(self, total: int, skipped: int) -> None:
        from tqdm import tqdm

        if skipped:
            print(f"{self.label}: {skipped} cases finished before, skipped", file=sys.stderr)
        self.bar = tqdm(total=total, desc=self.label, unit="case", file=sys.stderr)

    def done(self, case, record: dict) -> None:
        self.failed += record["status"] in (1, 2) or record["status"] < 0
        self.bar.write(f"  {case.name}: exit {record['status']}, {record['seconds']:.1f} s"
                       + (f" ({record['reason']})" if record["reason"] else ""),
                       file=sys.stderr)
        self.bar.set_postfix_str(f"{self.failed} failed", refresh=False)
        self.bar.update(1)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def cmd_sweep(args) -> int:
    from fsi.sweep import data as sweep_data
    from fsi.sweep.file import load_sweep
    from fsi.sweep.run import run_sweep

    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers {args.workers}: allowed an integer >= 1")
    import distributed  # noqa: F401  (its logging set up on import; quieted after)

    if not args.verbose:
        logging.getLogger("distributed").setLevel(logging.WARNING)
    sweep = load_sweep(args.sweep)  # every case built and checked before anything runs
    print(f"sweep {sweep.name}: {len(sweep.cases)} cases over "
          + " x ".join(f"{a.name} ({a.size})" for a in sweep.axes), file=sys.stderr)
    bar = SweepBar(sweep.name)
    try:
        outcome = run_sweep(sweep, args.out, scheduler=args.scheduler, workers=args.workers,
                            resume=args.resume, overwrite=args.overwrite, plots=args.plots,
                            progress=bar)
    finally:
        bar.close()
    dataset = sweep_data.collect(sweep, args.out)
    path = sweep_data.write(dataset, args.out)
    plots = sweep_data.plot(dataset, sweep.plot, args.out)
    print(f"wrote {path} ({len(sweep.cases)} cases, {len(outcome.records)} run, "
          f"{len(outcome.skipped)} skipped, {outcome.seconds:.1f} s) and {len(plots)} plots")
    if outcome.failed:
        print(f"fsi: error: {len(outcome.failed)} of {len(sweep.cases)} cases failed: "
              + "; ".join(f"{n}: {outcome.every_record[n]['reason']}"
                          for n in outcome.failed),
              file=sys.stderr)
        return 1
    if outcome.unconverged:
        print(f"fsi: warning: {len(outcome.unconverged)} cases did not converge in "
              f"everything: {', '.join(outcome.unconverged)}", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return 0


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


OBJ_SIZE_RATIO = 2.0
"""A compared surface's largest distance from the tank axis must lie within this factor of
the tank radius, or its units are taken to be wrong (-)."""


def check_obj_size(points: np.ndarray, radius: float, path) -> None:
    """Refuse a surface (m) whose reach from the axis is off the tank radius (m) by more than
    OBJ_SIZE_RATIO: its units are not metres (--obj-scale)."""
    reach = float(np.max(np.hypot(points[:, 0], points[:, 1]))) if len(points) else 0.0
    if not radius / OBJ_SIZE_RATIO <= reach <= radius * OBJ_SIZE_RATIO:
        raise UsageError(f"'{path}' reaches {reach:.4g} (after --obj-scale) from the axis, "
                         f"the tank radius is {radius:.4g} m: give --obj-scale to convert "
                         f"its units to m (e.g. 0.001 for mm)")


def read_run(path) -> dict:
    """A result for ``fsi compare``/``show``; :class:`UsageError` naming the file when it is
    not one."""
    from fsi.io.output import read_result

    try:
        res = read_result(path)
    except FileNotFoundError:
        raise
    except ValueError as err:  # HDF5, not a result: the message names the file
        raise UsageError(str(err)) from None
    except OSError as err:
        raise UsageError(f"'{path}' is not a slosh-fsi result ({err})") from None
    if not ("frames" in res and "node_position" in res["frames"]) and "radius" not in \
            res["attrs"]:
        raise UsageError(f"'{path}' is not a slosh-fsi result (no frames and no radius)")
    return res


def read_obj(path):
    """Vertices (m, unscaled) and faces of a .obj surface; :class:`UsageError` naming the
    file when it cannot be read as one."""
    import meshio

    from fsi.analysis.compare import read_obj_surface

    try:
        points, faces = read_obj_surface(path)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0 or faces.size == 0 \
                or faces.min() < 0 or faces.max() >= len(points) \
                or not np.all(np.isfinite(points)):
            raise ValueError("vertices need 3 finite coordinates, and every face 3 or 4 "
                             "vertices that exist")
    except FileNotFoundError:
        raise
    except (meshio.ReadError, OSError, ValueError, IndexError, KeyError,
            UnicodeDecodeError) as err:
        raise UsageError(f"'{path}' is not a readable Wavefront .obj surface ({err})") \
            from None
    return points, faces


def cmd_compare(args) -> int:
    from fsi.analysis.compare import eqn_6_1_error

    a = read_run(args.a)
    if "frames" not in a or "node_position" not in a["frames"]:
        raise UsageError(f"'{args.a}' has no membrane frames to compare")
    radius = float(a["attrs"]["radius"])
    frames = a["frames"]
    pick = _pick_frames(a, args.fill, args.scale, str(args.a))
    if str(args.b).lower().endswith(".obj"):
        if not args.obj_scale > 0:
            raise UsageError(f"--obj-scale {args.obj_scale}: a scale from .obj units to m is "
                             f"> 0")
        points, faces = read_obj(args.b)
        points = points * args.obj_scale
        check_obj_size(points, radius, args.b)
        print("tank A   Eqn 6.1 error (%)  vs " + str(args.b))
        for k in pick:
            e = eqn_6_1_error(points, faces, frames["node_position"][k], radius)
            print(f"{frames['tank_fraction'][k]:6.3f}  {e:10.4f}")
        return 0
    b = read_run(args.b)
    if "frames" not in b or "node_position" not in b["frames"]:
        raise UsageError(f"'{args.b}' has no membrane frames to compare")
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
    from fsi.scene import bundled_scenes, bundled_text, load_scene, reference_markdown

    if args.name:
        print(bundled_text(args.name), end="")
        return 0
    if args.reference:
        print(reference_markdown())
        return 0
    for name in bundled_scenes():
        print(f"{name:16s} {load_scene(name)['scene']['description']}")
    return 0


def cmd_sweeps(args) -> int:
    import tomllib

    from fsi.sweep.file import bundled_sweep_text, bundled_sweeps

    if args.name:
        print(bundled_sweep_text(args.name), end="")
        return 0
    for name in bundled_sweeps():
        head = tomllib.loads(bundled_sweep_text(name)).get("sweep", {})
        print(f"{name:16s} {head.get('description', '')} (scene {head.get('scene')})")
    return 0


def cmd_advise(args) -> int:
    from fsi.analysis.regime import advise_scene, load_table
    from fsi.scene import load_scene

    if not args.accuracy > 0:
        raise UsageError(f"--accuracy {args.accuracy}: an accuracy is > 0 (% Eqn 6.1)")
    scene = load_scene(args.scene)
    model, reasons = advise_scene(scene, args.accuracy, load_table())
    print(f"{scene['scene']['name']}: {model} model")
    for line in reasons:
        print(f"  {line}")
    return 0


def cmd_show(args) -> int:
    from fsi.analysis.diaphragm import summary_lines
    from fsi.lifecycle import RunResult
    from fsi.procedures import PROCEDURES

    res = read_run(args.run)
    a = res["attrs"]
    groups = {k: v for k, v in res.items() if k not in ("attrs", "membrane")}
    print(f"{args.run}: scene {a.get('scene_name', '?')}, procedure {a.get('procedure', '?')}, "
          f"written by slosh-fsi {a.get('software_version', 'before 0.1.0')}")
    for name, g in groups.items():
        n = len(next(iter(g.values()))) if g else 0
        span = (f", t = {g['time'][0]:.4g} ... {g['time'][-1]:.4g} s" if "time" in g and n
                else "")
        fills = (f", tank fraction {g['tank_fraction'][0]:.3f} ... "
                 f"{g['tank_fraction'][-1]:.3f}" if "tank_fraction" in g and n else "")
        print(f"  {name}: {n} records{span}{fills}")
    result = RunResult(groups=groups, attrs=a)
    procedure = PROCEDURES.get(str(a.get("procedure", "")))
    if procedure is not None:
        procedure.headline(result)
    for line in summary_lines(res):
        print(line)
    unconverged = not_converged(result)
    print(f"  converged: {'all' if not unconverged else 'not ' + unconverged}")
    print(f"  failure: {a.get('failure') or 'none'}; wall {float(a.get('run_seconds', np.nan)):.1f} s")
    return 0


def _run_parsers(sub) -> None:
    """The ``run`` and ``sweep`` subcommands."""
    p = sub.add_parser("run", help="run a scene and write results and plots")
    p.add_argument("scene", help="bundled scene name or path to a .toml scene file")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing results folder whole")
    p.add_argument("--resume", action="store_true",
                   help="continue a stopped run from its last checkpoint "
                        "(dynamics.checkpoint_interval)")
    p.set_defaults(func=cmd_run)
    p = sub.add_parser("sweep", help="run many cases of a scene on Dask, one dataset")
    p.add_argument("sweep", help="bundled sweep name or path to a sweep .toml file")
    p.add_argument("--out", required=True, help="output folder of the sweep")
    p.add_argument("--workers", type=int,
                   help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--scheduler", help="address of an existing Dask scheduler to use "
                                       "(its workers must see --out)")
    p.add_argument("--resume", action="store_true",
                   help="continue a sweep in --out: finished cases are skipped")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing sweep folder whole")
    p.add_argument("--plots", action="store_true", help="also write each case's plots")
    p.set_defaults(func=cmd_sweep)


def _result_parsers(sub) -> None:
    """The ``compare``, ``advise``, ``scenes``, ``sweeps`` and ``show`` subcommands."""
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
    p = sub.add_parser("scenes", help="list bundled scenes, or print one to copy")
    p.add_argument("name", nargs="?", help="print this bundled scene's TOML")
    p.add_argument("--reference", action="store_true", help="print the scene key reference")
    p.set_defaults(func=cmd_scenes)
    p = sub.add_parser("sweeps", help="list bundled sweeps, or print one to copy")
    p.add_argument("name", nargs="?", help="print this bundled sweep's TOML")
    p.set_defaults(func=cmd_sweeps)
    p = sub.add_parser("show", help="summarise a result: scene, procedure, records, the "
                                    "diaphragm's peak stress, events and cycles, "
                                    "convergence, failure, version")
    p.add_argument("run", help="result folder or result.h5")
    p.set_defaults(func=cmd_show)


def main(argv=None) -> int:
    from fsi.io.output import software_version

    parser = argparse.ArgumentParser(prog="fsi", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version",
                        version=f"slosh-fsi {software_version()}")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="show the libraries' INFO messages too (FiPy's)")
    sub = parser.add_subparsers(dest="command", required=True)
    _run_parsers(sub)
    _result_parsers(sub)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("fsi").setLevel(logging.INFO)
    return guarded(args.func, args)


if __name__ == "__main__":
    sys.exit(main())
