"""The command line, ``fsi``: :func:`main` parses the arguments and runs a subcommand
(``run``, ``sweep``, ``compare``, ``advise``, ``show``, ``scenes``, ``sweeps``); its help is
:data:`DESCRIPTION`, the exit statuses (:data:`RUN_EXIT`, :data:`SWEEP_EXIT`) and each
subcommand's description."""
from __future__ import annotations

import argparse
import logging
import os
import sys

import numpy as np

from fsi.run_job import (EXIT_NOT_CONVERGED, ProgressBar, UsageError, guarded,  # noqa: F401
                         not_converged, on_terminal, run as cmd_run)
from fsi.text import format_table

log = logging.getLogger("fsi")


class SweepBar:
    """A sweep's progress on stderr: a line per case as it finishes, and cases done of those
    to run, ETA and failures: on a terminal a tqdm bar below the lines, elsewhere (a file, a
    pipe) in each line, so that no line is shared with a bar."""

    def __init__(self, label: str):
        self.label, self.bar, self.failed, self.count, self.total = label, None, 0, 0, 0

    def start(self, total: int, skipped: int) -> None:
        from tqdm import tqdm

        if skipped:
            print(f"{self.label}: {skipped} cases finished before, skipped", file=sys.stderr)
        self.total = total
        if on_terminal(sys.stderr):
            self.bar = tqdm(total=total, desc=self.label, unit="case", file=sys.stderr)

    def done(self, case, record: dict) -> None:
        self.failed += record["status"] in (1, 2) or record["status"] < 0
        self.count += 1
        line = (f"  {case.name}: exit {record['status']}, {record['seconds']:.1f} s"
                + (f" ({record['reason']})" if record["reason"] else ""))
        if self.bar is None:
            print(f"{line} [{self.count} of {self.total} done, {self.failed} failed]",
                  file=sys.stderr, flush=True)
            return
        self.bar.write(line, file=sys.stderr)
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
    a = read_run(args.a)
    if "frames" not in a or "node_position" not in a["frames"]:
        raise UsageError(f"'{args.a}' has no membrane frames to compare")
    pick = _pick_frames(a, args.fill, args.scale, str(args.a))
    if str(args.b).lower().endswith(".obj"):
        return compare_with_surface(a, pick, args)
    return compare_with_result(a, pick, args)


def compare_with_surface(a: dict, pick: list[int], args) -> int:
    """``fsi compare A B.obj``: a table of A's tank fraction and the Eqn 6.1 error of its
    frame against the surface, scaled to m by --obj-scale."""
    from fsi.analysis.compare import eqn_6_1_error

    if not args.obj_scale > 0:
        raise UsageError(f"--obj-scale {args.obj_scale}: a scale from .obj units to m is > 0")
    radius, frames = float(a["attrs"]["radius"]), a["frames"]
    points, faces = read_obj(args.b)
    points = points * args.obj_scale
    check_obj_size(points, radius, args.b)
    print(f"compare: A '{args.a}', B the surface '{args.b}' (x {args.obj_scale:g} to m)",
          file=sys.stderr)
    rows = [(frames["tank_fraction"][k],
             eqn_6_1_error(points, faces, frames["node_position"][k], radius)) for k in pick]
    print(format_table([("tank A", "-"), ("Eqn 6.1 error", "%")], rows, [".3f", ".4f"]))
    return 0


def compare_with_result(a: dict, pick: list[int], args) -> int:
    """``fsi compare A B``: a table of each picked frame of A, B's frame nearest it in tank
    fraction and the Eqn 6.1 error between them; a pair further apart than
    PAIRING_TOLERANCE is marked '*' and explained below the table."""
    from fsi.analysis.compare import eqn_6_1_error

    b = read_run(args.b)
    if "frames" not in b or "node_position" not in b["frames"]:
        raise UsageError(f"'{args.b}' has no membrane frames to compare")
    radius, frames = float(a["attrs"]["radius"]), a["frames"]
    faces, b_tank = b["membrane"]["face_nodes"], b["frames"]["tank_fraction"]
    print("compare: B's frame nearest A's in tank fraction V / (4/3 pi R^3)", file=sys.stderr)
    rows = []
    for k in pick:
        j = int(np.argmin(np.abs(b_tank - frames["tank_fraction"][k])))
        e = eqn_6_1_error(b["frames"]["node_position"][j], faces, frames["node_position"][k],
                          radius)
        far = abs(b_tank[j] - frames["tank_fraction"][k]) > PAIRING_TOLERANCE
        rows.append((frames["tank_fraction"][k], b_tank[j], e, "*" if far else None))
    flagged = any(row[-1] for row in rows)
    columns = [("tank A", "-"), ("tank B", "-"), ("Eqn 6.1 error", "%"), ("", "")]
    if not flagged:  # no mark column
        columns, rows = columns[:-1], [row[:-1] for row in rows]
    print(format_table(columns, rows, [".3f", ".3f", ".4f", ""][:len(columns)]))
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
    print_listing([(name, load_scene(name)["scene"]["description"])
                   for name in bundled_scenes()])
    return 0


def print_listing(rows: list[tuple[str, str]]) -> None:
    """Names and descriptions in two columns, the names padded to the longest, each
    description wrapped to the terminal's width with a hanging indent."""
    import shutil

    print(format_table(None, rows, ["", ""], width=shutil.get_terminal_size().columns))


def cmd_sweeps(args) -> int:
    import tomllib

    from fsi.sweep.file import bundled_sweep_text, bundled_sweeps

    if args.name:
        print(bundled_sweep_text(args.name), end="")
        return 0
    heads = {name: tomllib.loads(bundled_sweep_text(name)).get("sweep", {})
             for name in bundled_sweeps()}
    print_listing([(name, f"{head.get('description', '')} (scene {head.get('scene')})")
                   for name, head in heads.items()])
    return 0


def cmd_advise(args) -> int:
    from fsi.analysis import onset
    from fsi.analysis.regime import advise_scene, load_table, work_note
    from fsi.scene import load_scene

    if not args.accuracy > 0:
        raise UsageError(f"--accuracy {args.accuracy}: an accuracy is > 0 (% Eqn 6.1)")
    scene = load_scene(args.scene)
    note = work_note(scene)
    if note:  # said before the wait
        print(f"{scene.name}: {note}...", file=sys.stderr, flush=True)
    model, reasons = advise_scene(scene, args.accuracy, load_table())
    if onset.applies(scene):
        print(f"{scene.name}: computing where its diaphragm starts to fold (the shell of "
              f"revolution, {onset.ELEMENTS} meridian elements, about "
              f"{onset.SECONDS:.0f} s)...", file=sys.stderr, flush=True)
        reasons = reasons + onset.onset_lines(scene)
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


DESCRIPTION = """\
Fluid-structure interaction of a propellant tank's slosh diaphragm: run a scene, or a sweep of \
scenes, into a results folder, then compare and summarise the results.

  fsi run SCENE --out DIR     run a bundled scene, or a scene file, into DIR
  fsi sweep SWEEP --out DIR   run the cases of a sweep on Dask into one dataset
  fsi compare A B             the Eqn 6.1 shape error per fill of two results
  fsi advise SCENE            which model a scene needs, and the numbers why
  fsi show DIR                summarise a result
  fsi scenes [NAME]           list the bundled scenes, or print one to copy
  fsi sweeps [NAME]           list the bundled sweeps, or print one to copy

'fsi COMMAND --help' describes a command and its options."""
"""What ``fsi --help`` says above the options."""

RUN_EXIT = """\
exit status of fsi run:
  0        done, everything converged
  1        stopped early (the work done is written), or could not start
  2        bad input: one line on stderr, nothing computed
  3        finished and written, but something did not converge
  130/143  interrupted by SIGINT/SIGTERM (the work done is written)"""
"""What ``fsi --help`` and ``fsi run --help`` say below the options."""

SWEEP_EXIT = """\
exit status of fsi sweep:
  0        every case done, everything converged
  1        a case failed (the others are written)
  2        bad input: one line on stderr, nothing computed
  3        every case written, but something did not converge in some"""

OTHER_EXIT = "The other commands exit 0 when done and 2 on bad input."


class HelpFormatter(argparse.HelpFormatter):
    """argparse's help formatter, but a paragraph of a description or an epilog with an
    indented line (a list: the commands, the exit statuses) is kept as written; the other
    paragraphs are filled to the terminal's width as usual."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        fill = super()._fill_text
        return "\n\n".join(paragraph if is_list(paragraph) else fill(paragraph, width, indent)
                           for paragraph in text.split("\n\n"))


def is_list(paragraph: str) -> bool:
    """Whether a paragraph of help text has an indented line (a list, kept as written)."""
    return any(line.startswith(" ") for line in paragraph.splitlines())


def _command(sub, name: str, description: str, epilog: str = None):
    """A subcommand's parser: its description (whole sentences) and epilog."""
    return sub.add_parser(name, description=description, epilog=epilog,
                          formatter_class=HelpFormatter)


def _run_parser(sub) -> None:
    p = _command(sub, "run", "Run a scene, bundled or a .toml file, into the results folder "
                 "DIR: result.h5, the frames for ParaView and the plots. The scene and DIR "
                 "are checked before anything is computed or written.", RUN_EXIT)
    p.add_argument("scene", help="bundled scene name or path to a .toml scene file")
    p.add_argument("--out", metavar="DIR", required=True, help="output folder")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing results folder whole")
    p.add_argument("--resume", action="store_true",
                   help="continue a stopped run from its last checkpoint "
                        "(dynamics.checkpoint_interval)")
    p.set_defaults(func=cmd_run)


def _sweep_parser(sub) -> None:
    p = _command(sub, "sweep", "Run every case of a sweep, bundled or a .toml file, on a Dask "
                 "cluster, and gather their results into one dataset, DIR/sweep.nc.",
                 SWEEP_EXIT)
    p.add_argument("sweep", help="bundled sweep name or path to a sweep .toml file")
    p.add_argument("--out", metavar="DIR", required=True, help="output folder of the sweep")
    p.add_argument("--workers", metavar="N", type=int,
                   help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of an existing Dask scheduler to use (its workers must see "
                        "--out)")
    p.add_argument("--resume", action="store_true",
                   help="continue a sweep in --out: finished cases are skipped")
    p.add_argument("--overwrite", action="store_true",
                   help="replace an existing sweep folder whole")
    p.add_argument("--plots", action="store_true", help="also write each case's plots")
    p.set_defaults(func=cmd_sweep)


def _compare_parser(sub) -> None:
    p = _command(sub, "compare", "Compare membrane shapes by the thesis's Eqn 6.1 error, frame "
                 "by frame: two results (B's frame nearest each of A's in tank fraction), or "
                 "a result and a Wavefront .obj surface.")
    p.add_argument("a", help="result folder or result.h5 (compared)")
    p.add_argument("b", help="result folder / result.h5, or .obj surface (reference)")
    p.add_argument("--fill", metavar="F", type=float,
                   help="compare only A's frame nearest this fill, in [0, 1], on --scale")
    p.add_argument("--scale", choices=("tank", "full-inversion"), default="tank",
                   help="scale of --fill: tank fraction V / (4/3 pi R^3) (default) or the "
                        "thesis's full-inversion scale (static results)")
    p.add_argument("--obj-scale", metavar="S", type=float, default=1.0,
                   help="factor from .obj units to m (default 1)")
    p.set_defaults(func=cmd_compare)


def _advise_parser(sub) -> None:
    p = _command(sub, "advise", "Say which model a scene needs for a stated accuracy, and "
                 "print every number used. A fill or drain through the port is placed on "
                 "the measured regime map (its slosh period computed first, which takes "
                 "a moment); other procedures have a fixed answer.")
    p.add_argument("scene", help="bundled scene name or path to a .toml scene file")
    p.add_argument("--accuracy", metavar="PERCENT", type=float, default=1.0,
                   help="largest acceptable shape difference from the coupled model, "
                        "%% Eqn 6.1 (default 1)")
    p.set_defaults(func=cmd_advise)


def _listing_parsers(sub) -> None:
    p = _command(sub, "scenes", "List the bundled scenes, print one (its TOML, to copy and "
                 "edit), or print the reference of every scene key.")
    p.add_argument("name", nargs="?", help="print this bundled scene's TOML")
    p.add_argument("--reference", action="store_true", help="print the scene key reference")
    p.set_defaults(func=cmd_scenes)
    p = _command(sub, "sweeps", "List the bundled sweeps, or print one (its TOML, to copy and "
                 "edit).")
    p.add_argument("name", nargs="?", help="print this bundled sweep's TOML")
    p.set_defaults(func=cmd_sweeps)
    p = _command(sub, "show", "Summarise a result: its scene and procedure, records, the "
                 "diaphragm's peak stress, events and stress cycles, convergence, failure "
                 "and the version that wrote it.")
    p.add_argument("run", help="result folder or result.h5")
    p.set_defaults(func=cmd_show)


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``fsi``: its options and every subcommand's."""
    from fsi.io.output import software_version

    parser = argparse.ArgumentParser(prog="fsi", description=DESCRIPTION,
                                     epilog="\n\n".join((RUN_EXIT, SWEEP_EXIT, OTHER_EXIT)),
                                     formatter_class=HelpFormatter)
    parser.add_argument("--version", action="version",
                        version=f"slosh-fsi {software_version()}")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="show the libraries' INFO messages too (FiPy's)")
    sub = parser.add_subparsers(dest="command", required=True, title="commands",
                                metavar="COMMAND", help="one of those listed above")
    for add in (_run_parser, _sweep_parser, _compare_parser, _advise_parser,
                _listing_parsers):
        add(sub)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("fsi").setLevel(logging.INFO)
    try:
        return guarded(args.func, args)
    except BrokenPipeError:  # the reader stopped early (``fsi scenes | head``): no traceback
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


if __name__ == "__main__":
    sys.exit(main())
