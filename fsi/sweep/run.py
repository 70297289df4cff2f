"""Running a sweep's cases on Dask (``dask.distributed``), one ``fsi run`` per case.

Layout of ``fsi sweep SWEEP --out DIR``::

    DIR/sweep.toml              the sweep file as run
    DIR/cases/NAME.toml         each case's scene (the base scene with its keys set)
    DIR/cases/NAME/             each case's result folder, written atomically by ``fsi run``
    DIR/cases.jsonl             one line per case run: name, exit status, reason, seconds
    DIR/sweep.nc, DIR/plots/    the combined dataset and its plots (:mod:`fsi.sweep.data`)

Cases run on a ``LocalCluster`` sized to the machine (one worker process per core, one
thread and one case at a time each, the memory available now shared between them) or, with
``--scheduler ADDRESS``, on an existing cluster whose workers have this package installed
and see DIR. A case whose worker dies is rerun by the scheduler on another (``distributed``'s
allowed-failures, 3 by default); a case that fails is recorded with its reason and the
others go on. ``--resume`` skips the cases whose result folder exists and reruns the others
(from their checkpoint when they wrote one).
"""
from __future__ import annotations

import json
import logging
import os
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path

from fsi.io.run_folder import STAGING_PREFIX, OutputError
from fsi.sweep.file import Case, Sweep

log = logging.getLogger(__name__)

CASES_DIR = "cases"
LOG_FILE = "cases.jsonl"
SWEEP_FILE = "sweep.toml"
RESULT_FILE = "result.h5"


def run_case(scene_file: str, folder: str, plots: bool = False) -> dict:
    """On a worker: ``fsi run scene_file --out folder`` (``--resume`` from a checkpoint a
    killed run of the case left; other staging folders of the case removed first), its
    report and progress not shown (the result is in the folder). Returns
    {status: exit status, reason: the last line on stderr unless 0, seconds: wall, resumed:
    whether from a checkpoint, started: the wall clock at its start (s since the epoch), pid:
    the worker's process}."""
    import argparse
    import contextlib
    import io

    from fsi.io.checkpoint import CHECKPOINT_FILE
    from fsi.run_job import guarded, run

    out = Path(folder)
    stale = sorted(out.parent.glob(f"{STAGING_PREFIX}{out.name}-*"),
                   key=lambda p: p.stat().st_mtime)
    resume = bool(stale) and (stale[-1] / CHECKPOINT_FILE).is_file()
    for path in stale[:-1] if resume else stale:
        shutil.rmtree(path, ignore_errors=True)
    args = argparse.Namespace(scene=scene_file, out=folder, no_plots=not plots,
                              overwrite=False, resume=resume)
    err = io.StringIO()
    started, t0 = time.time(), time.perf_counter()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = guarded(run, args)
    lines = [line for line in err.getvalue().splitlines() if line.startswith("fsi:")]
    return dict(status=int(status), reason=lines[-1] if status and lines else "",
                seconds=time.perf_counter() - t0, resumed=resume, started=started,
                pid=os.getpid())


@dataclass
class SweepOutcome:
    """What a sweep did: the cases skipped (finished before; ``earlier``: their records from
    DIR/cases.jsonl) and run (``records``), by case name, and the wall seconds. ``failed``
    (exit 1 or 2, or their worker died) and ``unconverged`` (exit 3) count both, so a resumed
    sweep answers for every case."""

    skipped: list = field(default_factory=list)
    records: dict = field(default_factory=dict)
    earlier: dict = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def every_record(self) -> dict:
        return {**self.earlier, **self.records}

    @property
    def failed(self) -> list:
        return [n for n, r in self.every_record.items()
                if r["status"] in (1, 2) or r["status"] < 0]

    @property
    def unconverged(self) -> list:
        return [n for n, r in self.every_record.items() if r["status"] == 3]


def check_out(sweep: Sweep, out: Path, resume: bool, overwrite: bool) -> bool:
    """Check DIR before anything is written; returns whether it is to be replaced whole. An
    existing DIR is refused unless ``resume`` (then it must hold this sweep) or
    ``overwrite``."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out '{out}' is a file; give a folder")
    held = out.is_dir() and any(out.iterdir())
    if held and resume:
        if not (out / SWEEP_FILE).is_file() or (out / SWEEP_FILE).read_text() != sweep.text:
            raise OutputError(f"--resume: '{out}' does not hold this sweep (its {SWEEP_FILE} "
                              "differs or is missing)")
    elif held and not overwrite:
        raise OutputError(f"--out '{out}' already holds files; --resume to continue that "
                          "sweep, --overwrite to replace it whole")
    return held and not resume


def lay_out(sweep: Sweep, out: Path, replace: bool) -> list[Case]:
    """Lay out DIR, checked by :func:`check_out` (replaced whole when ``replace``; module
    doc); returns the cases still to run."""
    out = Path(out)
    if replace:
        shutil.rmtree(out)
    (out / CASES_DIR).mkdir(parents=True, exist_ok=True)
    (out / SWEEP_FILE).write_text(sweep.text)
    for case in sweep.cases:
        scene = out / CASES_DIR / f"{case.name}.toml"
        if not scene.is_file() or scene.read_text() != case.scene_text:
            scene.write_text(case.scene_text)
    return [c for c in sweep.cases if not finished(out, c)]


def finished(out: Path, case: Case) -> bool:
    """Whether the case's result folder is in place (written whole by ``fsi run``)."""
    return (Path(out) / CASES_DIR / case.name / RESULT_FILE).is_file()


WORKER_SATURATION = 1.0
"""Cases a worker holds per thread (``distributed.scheduler.worker-saturation``): one, so a
case waits on the scheduler until a worker is free instead of queueing behind another on a
busy worker (at Dask's default 1.1 a worker holds two; measured on a 9-case sweep with two
workers: 6 and 3 cases, one worker idle 56 s at the end)."""


def local_cluster(workers: int | None, cases: int):
    """A ``LocalCluster``: ``workers`` processes (default: one per core, at most one per
    case), one thread each, one case at a time each (:data:`WORKER_SATURATION`), the memory
    available now shared between them; returned once every worker has joined."""
    import dask
    from dask.distributed import LocalCluster

    from fsi.setup.limits import available_memory

    n = max(1, min(workers or os.cpu_count() or 1, cases))
    memory = available_memory()
    with dask.config.set({"distributed.scheduler.worker-saturation": WORKER_SATURATION}):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               memory_limit=int(memory / n) if memory < float("inf")
                               else "auto", silence_logs=logging.ERROR, dashboard_address=":0")
    cluster.wait_for_workers(n)
    return cluster


def run_cases(sweep: Sweep, out: Path, todo: list[Case], client, plots: bool = False,
              progress=None) -> dict:
    """Submit ``todo`` to ``client`` and gather each case's record (:func:`run_case`) as it
    finishes, appended to DIR/cases.jsonl; a case whose worker died too often is recorded
    with status -1 and the reason. ``progress.done(case, record)`` after each."""
    from dask.distributed import as_completed

    out = Path(out).resolve()
    futures = {client.submit(run_case, str(out / CASES_DIR / f"{c.name}.toml"),
                             str(out / CASES_DIR / c.name), plots, pure=False,
                             key=f"{sweep.name}:{c.name}:{time.time_ns()}"): c for c in todo}
    records = {}
    for future in as_completed(futures):
        case = futures[future]
        try:
            record = future.result()
        except Exception as err:  # a worker died too often, or the case raised
            record = dict(status=-1, reason=f"{type(err).__name__}: {err}", seconds=float("nan"),
                          resumed=False)
        record = dict(case=case.name, **record)
        records[case.name] = record
        with open(out / LOG_FILE, "a") as f:
            f.write(json.dumps(record) + "\n")
        if progress is not None:
            progress.done(case, record)
    return records


def run_sweep(sweep: Sweep, out, client=None, scheduler: str | None = None,
              workers: int | None = None, resume: bool = False, overwrite: bool = False,
              plots: bool = False, progress=None) -> SweepOutcome:
    """Run the sweep's unfinished cases (module doc) on ``client``, a cluster at
    ``scheduler``, or a new :func:`local_cluster` of ``workers``; returns the
    :class:`SweepOutcome`. ``progress``: ``start(to run, skipped)`` once, ``done(case,
    record)`` per case. The combined dataset is :func:`fsi.sweep.data.collect`'s."""
    from dask.distributed import Client

    t0 = time.perf_counter()
    out = Path(out)
    replace = check_out(sweep, out, resume, overwrite)
    pending = sum(replace or not finished(out, c) for c in sweep.cases)
    own, cluster = client is None and pending > 0, None
    if own:  # connected before DIR is written: a scheduler that does not answer leaves none
        cluster = None if scheduler else local_cluster(workers, pending)
        client = connect(Client, scheduler, cluster)
        log.info("Dask dashboard: %s", client.dashboard_link)
    try:
        todo = lay_out(sweep, out, replace)
        skipped = [c.name for c in sweep.cases if c not in todo]
        earlier = case_records(out)
        outcome = SweepOutcome(skipped=skipped,
                               earlier={n: earlier[n] for n in skipped if n in earlier})
        if progress is not None:
            progress.start(len(todo), len(outcome.skipped))
        if todo:
            outcome.records = run_cases(sweep, out, todo, client, plots, progress)
    finally:
        if own:
            client.close()
        if cluster is not None:
            cluster.close()
    outcome.seconds = time.perf_counter() - t0
    return outcome


def connect(client_class, scheduler: str | None, cluster):
    """A client of ``cluster``, or of the scheduler at ``scheduler`` (10 s to answer; else
    a :class:`fsi.run_job.UsageError` naming --scheduler)."""
    if not scheduler:
        return client_class(cluster)
    from fsi.run_job import UsageError

    try:  # not the default client: one that never connected would stay the process's
        # default, and xarray's writes would then ask it for a lock (sweep_data.write)
        return client_class(scheduler, timeout="10s", set_as_default=False)
    except (OSError, ValueError, TypeError) as err:
        raise UsageError(f"--scheduler {scheduler}: no Dask scheduler answered there "
                         f"({err})") from None


def case_records(out: Path) -> dict:
    """{case name: its last record in DIR/cases.jsonl}."""
    path = Path(out) / LOG_FILE
    records = {}
    if path.is_file():
        for line in path.read_text().splitlines():
            if line.strip():
                record = json.loads(line)
                records[record["case"]] = record
    return records
