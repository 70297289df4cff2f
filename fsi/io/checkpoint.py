"""Checkpoints of a time-dependent run: everything needed to continue it, pickled
(cloudpickle: the participants hold closures) and written atomically.

A coupled fill with ``dynamics.checkpoint_interval`` = n > 0 writes, every n windows (and
with ``dynamics.checkpoint_seconds`` = T > 0 whenever T seconds of wall time have passed
since the last),
``checkpoint.pkl`` into the run's staging folder (:mod:`fsi.io.run_folder`): both participants
(membrane state and history, the liquid's fields and solver), the coupling loop (the
acceleration's memory, past windows' fields, time, window size), the window controller and
the records so far. ``fsi run SCENE --out DIR --resume`` finds the newest staging folder of
DIR with a checkpoint and continues from it; the finished run's arrays equal an uninterrupted
run's bit for bit (the wall-clock seconds excepted). The file is removed when the run is
complete.  The thesis ramp does the same with ``thesis.checkpoint_interval`` (steps) and
``thesis.checkpoint_seconds``: its state, the next step and the records; a slosh run with
``slosh.checkpoint_interval`` (windows) and ``slosh.checkpoint_seconds``: its surface model's
windows (:class:`fsi.procedures.slosh.SurfaceWindows`: the liquid, the height surface or the
membrane and the coupling loop) and the records. Every checkpoint holds the wall seconds run
so far, which a resumed run's clock counts on from.
"""
from __future__ import annotations

import os
import time
from pathlib import Path

CHECKPOINT_FILE = "checkpoint.pkl"


CHECKPOINT_KEYS = ("checkpoint_interval", "checkpoint_seconds")
"""Scene keys that ask a procedure for checkpoints, in whichever table it owns them."""


def wanted(scene) -> bool:
    """Whether the scene asks for checkpoints (a CHECKPOINT_KEYS key > 0 in any table)."""
    return any(table.get(key, 0) > 0 for table in scene.values.values()
               for key in CHECKPOINT_KEYS)


class CheckpointDue:
    """``due(k)``: whether a checkpoint is written after window ``k``: every ``interval``
    windows (0: not by count) or when ``seconds`` of wall time have passed since the last
    one (0: not by time)."""

    def __init__(self, interval: int, seconds: float):
        self.interval, self.seconds = int(interval), float(seconds)
        self.last = time.monotonic()

    def __call__(self, k: int) -> bool:
        now = time.monotonic()
        if (self.interval > 0 and k % self.interval == 0) or \
                (self.seconds > 0 and now - self.last >= self.seconds):
            self.last = now
            return True
        return False


def write(path: Path, payload: dict) -> None:
    """Pickle ``payload`` to ``path`` atomically (a temporary file renamed over it)."""
    import cloudpickle

    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        cloudpickle.dump(payload, f)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def read(path: Path) -> dict:
    """The payload a checkpoint at ``path`` holds."""
    import pickle

    with open(path, "rb") as f:
        return pickle.load(f)
