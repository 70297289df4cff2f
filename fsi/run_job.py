"""``fsi run``: one scene run into a results folder (:mod:`fsi.io.run_folder`), with progress,
signals, checkpoints and an exit status that says how it went; what ``fsi sweep`` runs for
each case too (:func:`fsi.sweep.run.run_case`).

Exit status: 0 all converged; 1 the run stopped early (written) or could not start (nothing
written); 2 bad input; 3 (:data:`EXIT_NOT_CONVERGED`) finished and written, something did not
converge; 128 + n stopped by signal n (SIGINT 130, SIGTERM 143).
"""
from __future__ import annotations

import contextlib
import dataclasses
import logging
import signal
import sys
import time

import numpy as np

log = logging.getLogger("fsi")


def guarded(command, args) -> int:
    """``command(args)``; bad input (a scene, a value, an output folder, a missing file) is
    one line on stderr and exit status 2."""
    from fsi.registry import SceneError
    from fsi.io.run_folder import OutputError

    try:
        return command(args)
    except (SceneError, UsageError, OutputError, FileNotFoundError) as exc:
        print(f"fsi: error: {exc}", file=sys.stderr)
        return 2


class UsageError(Exception):
    """A command-line value out of range: one line on stderr, exit status 2."""



BAR_FORMAT = "{desc}: {percentage:3.0f}%|{bar}| {elapsed}{postfix}"
"""What the progress says: 'label:  25%|██▌       | 00:04, ETA 00:12, message'."""
LINE_SECONDS = 30.0
"""Off a terminal (a file, a pipe, a CI log), where a bar cannot be redrawn in place, the
progress is a line of its own at most this often, and at the start and the end (s)."""
BAR_SECONDS = 0.5
"""On a terminal the bar is redrawn at most this often (s)."""


def on_terminal(stream) -> bool:
    """Whether ``stream`` is a terminal, where a bar can be redrawn in place."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or closed
        return False


class ProgressBar:
    """Progress with ETA on stderr, driven by fraction done. On a terminal a tqdm bar redrawn
    in place (:func:`progress_shown` writes the log records above it); anywhere else the same
    text as whole lines, every :data:`LINE_SECONDS`, so that no other line shares one with
    it. The ETA is the rate since the first work reported, so a long setup (a static start)
    does not inflate it."""

    def __init__(self, label: str, stream=None):
        self.stream = sys.stderr if stream is None else stream
        self.label, self.live = label, on_terminal(self.stream)
        self.started = self.last = time.monotonic()
        self.first = None  # (time, fraction) of the first report with work done
        self.finished = False
        self.bar = self._tqdm() if self.live else None
        if not self.live:
            self.write_line(0.0, "", self.started)

    def _tqdm(self):
        from tqdm import tqdm

        return tqdm(total=1000, desc=self.label, unit="‰", file=self.stream,
                    bar_format=BAR_FORMAT, mininterval=BAR_SECONDS)

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
        interval = BAR_SECONDS if self.live else LINE_SECONDS
        if (fraction < 1.0 and now - self.last < interval) or self.finished:
            return
        self.last, self.finished = now, fraction >= 1.0 and not self.live
        postfix = f"{eta}, {message}" if eta else message
        if self.live:
            self.bar.n = int(1000 * fraction)
            self.bar.set_postfix_str(postfix, refresh=False)
            self.bar.refresh()
        else:
            self.write_line(fraction, postfix, now)

    def write_line(self, fraction: float, postfix: str, now: float) -> None:
        """The progress as a line of its own (off a terminal)."""
        from tqdm import tqdm

        print(tqdm.format_meter(int(1000 * fraction), 1000, now - self.started,
                                prefix=self.label, bar_format=BAR_FORMAT, postfix=postfix,
                                unit="‰"), file=self.stream, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


@contextlib.contextmanager
def progress_shown(label: str):
    """A :class:`ProgressBar` of ``label`` while inside, closed on leaving. On a terminal,
    where the bar is redrawn in place, the log records and warnings meanwhile are
    written above it (:func:`logs_above_bar`), each on a line of its own; off a terminal the
    bar's lines are whole lines already."""
    bar = ProgressBar(label)
    try:
        with logs_above_bar() if bar.live else contextlib.nullcontext():
            yield bar
    finally:
        bar.close()


@contextlib.contextmanager
def logs_above_bar():
    """While inside: every logger writing to stdout or stderr (:func:`console_loggers`)
    writes through tqdm, which clears the bar, writes the line and redraws the bar below it;
    Python's warnings go to the log (logger 'py.warnings') rather than straight to stderr."""
    import warnings

    from tqdm.contrib.logging import logging_redirect_tqdm

    def to_log(message, category, filename, lineno, file=None, line=None):
        logging.getLogger("py.warnings").warning(
            "%s", warnings.formatwarning(message, category, filename, lineno, "").rstrip())

    shown, warnings.showwarning = warnings.showwarning, to_log
    try:
        with logging_redirect_tqdm(loggers=console_loggers()):
            yield
    finally:
        warnings.showwarning = shown


def console_loggers() -> list[logging.Logger]:
    """The root logger, and every other logger with a handler of its own writing to stdout
    or stderr (one that does not only pass its records on to the root's)."""
    def console(handler) -> bool:
        return isinstance(handler, logging.StreamHandler) and \
            handler.stream in (sys.stdout, sys.stderr)

    others = [logger for logger in logging.root.manager.loggerDict.values()
              if isinstance(logger, logging.Logger) and any(map(console, logger.handlers))]
    return [logging.root, *others]


def prepare(args):
    """(folder, scene, setup) of ``fsi run``: the results folder checked and the scene built
    and validated before anything is computed; with ``--resume`` the checkpoint read, and the
    checkpoint file set when the scene asks for checkpoints."""
    from fsi.setup.build import build
    from fsi.io.checkpoint import (CHECKPOINT_FILE, CheckpointRefused, read as read_checkpoint,
                                   wanted as wants_checkpoints)
    from fsi.io.run_folder import RunFolder
    from fsi.scene import load_scene

    folder = RunFolder(args.out, args.overwrite, args.resume)  # before anything is computed
    scene = load_scene(args.scene)
    setup = build(scene)  # validates the time step before anything is written
    if args.resume:
        try:
            setup = dataclasses.replace(setup, resume=read_checkpoint(folder.checkpoint()))
        except CheckpointRefused as err:
            raise UsageError(str(err)) from None
        if setup.resume.get("scene") != scene.text:
            raise UsageError(f"--resume: the checkpoint in '{folder.stage()}' is of another "
                             f"scene text than '{args.scene}'")
    if wants_checkpoints(scene):
        setup = dataclasses.replace(setup, checkpoint=folder.stage() / CHECKPOINT_FILE)
    return folder, scene, setup


def annotate_result(setup, result) -> None:
    """:func:`fsi.analysis.diaphragm.annotate`; a failure of it is the run's
    ``stress_analysis_failure`` (the frames are still written, the exit status is 1)."""
    from fsi.analysis.diaphragm import annotate

    try:
        annotate(setup, result)
    except Exception as err:  # the run's work is kept whatever the analysis does
        log.exception("the diaphragm's stress analysis failed")
        result.attrs["stress_analysis_failure"] = f"{type(err).__name__}: {err}"


def run(args) -> int:
    """``fsi run`` with the parsed ``args`` (scene, out, no_plots, overwrite, resume);
    returns the exit status (module doc)."""
    from fsi.io.checkpoint import CHECKPOINT_FILE
    from fsi.io.output import write_result
    from fsi.io.plots import make_plots
    from fsi.registry import StartFailure

    folder, scene, setup = prepare(args)
    procedure = setup.procedure
    t0 = time.perf_counter()
    try:
        with stop_on_signals(), progress_shown(scene.name) as bar:  # logs on lines of their own
            result = procedure(setup, bar)
    except StartFailure as err:
        folder.discard()
        print(f"fsi: error: the run could not start: {err}; nothing was written",
              file=sys.stderr)
        return 1
    result.attrs["run_seconds"] = time.perf_counter() - t0
    annotate_result(setup, result)
    write_result(folder.stage(), scene, setup.model, result)
    if "interrupted" in result.attrs:
        out = folder.commit(keep_checkpoint=True)
        name = signal.Signals(result.attrs["interrupted"]).name
        again = ("; continue it from its last checkpoint with --resume"
                 if (out / CHECKPOINT_FILE).is_file() else "")
        print(f"fsi: interrupted by {name}: the work done is in '{out}' (no plots){again}",
              file=sys.stderr)
        return 128 + int(result.attrs["interrupted"])
    if "solver_failure" in result.attrs:
        out = folder.commit()
        print(f"fsi: error: the run stopped: {result.attrs['failure']}; the work done is in "
              f"'{out}' (no plots)", file=sys.stderr)
        return 1
    procedure.report(result)
    plots = [] if args.no_plots else make_plots(folder.stage())
    out = folder.commit()
    log.info("wrote %s (%.1f s) and %d plots", out, result.attrs["run_seconds"], len(plots))
    if result.attrs.get("failure"):
        print(f"fsi: error: the run stopped early: {result.attrs['failure']}", file=sys.stderr)
        return 1
    for key, what in (("analysis_failure", "the run's analysis"),
                      ("stress_analysis_failure", "the diaphragm's stress analysis")):
        if result.attrs.get(key):
            print(f"fsi: error: {what} failed: {result.attrs[key]}", file=sys.stderr)
            return 1
    unconverged = not_converged(result)
    if unconverged:
        print(f"fsi: warning: the run finished, but not everything converged: {unconverged} "
              f"(results in '{out}')", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return 0


EXIT_NOT_CONVERGED = 3
"""``fsi run``'s exit status when the run finished and was written but some fill, frame or
window did not converge (0: all converged; 1: stopped early; 2: bad input)."""


FRAME_CHECKS = {"converged": "", "stress_valid": " (stress fields not finite)"}
"""Per-frame true-or-false datasets a group may hold -> what a false one is called."""


def not_converged(result) -> str:
    """'' when every ``converged`` (and ``stress_valid``) entry of every group and every true-or-false
    ``*_converged`` attribute of ``result`` holds (a count such as ``windows_not_converged``
    is not one); else what did not, e.g. '1 of 999 windows, start'."""
    parts = [f"{int(np.sum(~np.asarray(g[key], dtype=bool)))} of {len(g[key])} {name}{what}"
             for name, g in result.groups.items() for key, what in FRAME_CHECKS.items()
             if key in g and not np.all(g[key])]
    parts += [key[:-len("_converged")] for key, value in result.attrs.items()
              if key.endswith("_converged") and isinstance(value, (bool, np.bool_))
              and not value]
    return ", ".join(parts)


@contextlib.contextmanager
def stop_on_signals():
    """While inside: SIGINT and SIGTERM ask the run to stop at the end of its current unit of
    work (:data:`fsi.lifecycle.STOP`); a second one stops at once. Off the main thread (a
    sweep's case on a Dask worker) signals are the worker's own: nothing is changed."""
    import threading

    from fsi.lifecycle import STOP

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def ask(signum, frame):
        if STOP.signal is not None:
            raise KeyboardInterrupt
        STOP.signal = signum

    previous = {s: signal.signal(s, ask) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        STOP.signal = None
