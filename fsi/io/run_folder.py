"""The results folder of ``fsi run``: checked before anything is computed, filled in a
staging folder beside it, and put in place whole.

* ``--out DIR`` must not be a file, its parent must be writable, and an existing folder that
  holds anything is refused unless ``--overwrite`` (which replaces it whole: no stale plots
  of an earlier run stay beside new ones);
* the result and its plots are written into ``.partial-<name>-*`` beside DIR; only when both
  are complete is it renamed to DIR (the earlier DIR, with ``--overwrite``, moved aside
  first and removed after).  A run that dies leaves DIR as it was and a ``.partial-``
  folder that says what it is;
* a run stopped by a signal writes what it did to DIR and keeps its last checkpoint there
  (``DIR/checkpoint.pkl``), so that ``--resume`` continues it as it would a killed run's
  staging folder; the resumed run is staged anew and replaces DIR whole.
"""
from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

STAGING_PREFIX = ".partial-"
"""Name prefix of a run folder being written (an incomplete run when one is left)."""


class OutputError(Exception):
    """``--out`` cannot take a run: one line on stderr, exit status 2."""


class RunFolder:
    """``out``: the results folder asked for; ``overwrite``: replace an existing one."""

    def __init__(self, out, overwrite: bool = False, resume: bool = False):
        self.out = Path(out)
        self.overwrite = overwrite
        self.staging: Path | None = None
        self.source: Path | None = None  # the checkpoint resumed from
        if resume:
            self.source = self.checkpoint()
            found = self.source.parent
            # a killed run's staging folder is carried on; DIR itself (a run stopped by a
            # signal) is replaced whole by a new staging folder at the end
            self.staging = found if found.name.startswith(STAGING_PREFIX) else None
        else:
            self.check()
        self.resumed = self.staging is not None

    def checkpoint(self) -> Path:
        """The newest checkpoint in a staging folder of ``out`` or in ``out`` itself
        (:class:`OutputError` when there is none)."""
        from fsi.io.checkpoint import CHECKPOINT_FILE

        parent = self.out.resolve().parent
        found = sorted(list(parent.glob(f"{STAGING_PREFIX}{self.out.name}-*/{CHECKPOINT_FILE}"))
                       + list(self.out.resolve().glob(CHECKPOINT_FILE)),
                       key=lambda p: p.stat().st_mtime)
        if not found:
            raise OutputError(f"--resume: no checkpoint of '{self.out}' in '{parent}' (a run "
                              f"writes them with dynamics.checkpoint_interval > 0)")
        return found[-1]

    def check(self) -> None:
        """Raise :class:`OutputError` when ``out`` cannot take a run (module doc)."""
        out = self.out
        if out.exists() and not out.is_dir():
            raise OutputError(f"--out '{out}' is a file; give a folder")
        if out.is_dir() and any(out.iterdir()) and not self.overwrite:
            raise OutputError(f"--out '{out}' already holds files; give a new folder or "
                              f"--overwrite to replace it whole")
        parent = out.resolve().parent
        try:
            parent.mkdir(parents=True, exist_ok=True)
            probe = tempfile.NamedTemporaryFile(dir=parent, prefix=STAGING_PREFIX)
            probe.close()
        except OSError as err:
            raise OutputError(f"--out '{out}': cannot write in '{parent}' ({err.strerror})")

    def stage(self) -> Path:
        """The staging folder beside ``out`` (made on first call)."""
        if self.staging is None:
            self.staging = Path(tempfile.mkdtemp(prefix=f"{STAGING_PREFIX}{self.out.name}-",
                                                 dir=self.out.resolve().parent))
        return self.staging

    def discard(self) -> None:
        """Remove a staging folder this run made (not a resumed run's, which holds its
        checkpoint): nothing was written."""
        if self.staging is not None and not self.resumed:
            shutil.rmtree(self.staging, ignore_errors=True)
            self.staging = None

    def commit(self, keep_checkpoint: bool = False) -> Path:
        """Put the staged run in place of ``out`` (an earlier one removed); returns ``out``.
        Its checkpoint is removed unless ``keep_checkpoint`` (a run stopped by a signal:
        where it wrote none since it was resumed from DIR's, that one is kept)."""
        from fsi.io.checkpoint import CHECKPOINT_FILE

        staged = self.stage() / CHECKPOINT_FILE
        if not keep_checkpoint:
            staged.unlink(missing_ok=True)
        elif not staged.is_file() and self.source is not None and self.source.is_file():
            shutil.copy2(self.source, staged)
        old = None
        if self.out.exists():
            old = Path(tempfile.mkdtemp(prefix=".replaced-", dir=self.out.resolve().parent))
            os.replace(self.out, old / "run")
        os.replace(self.stage(), self.out)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        self.staging = None
        return self.out
