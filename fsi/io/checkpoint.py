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

Unpickling runs code, so a checkpoint from elsewhere (a results folder copied from another
machine or user) could run anything. Each checkpoint therefore starts with an HMAC-SHA256 of
its pickle under a per-user key (:data:`KEY_FILE` in ``$XDG_CONFIG_HOME/slosh-fsi/``, else
``~/.config/slosh-fsi/``, 32 random bytes made on the first write, readable by the user
only), and :func:`read` refuses, before unpickling, a file whose HMAC does not match:
:class:`CheckpointRefused`, one line naming the file. A checkpoint written by another user,
on another machine or before this check (no HMAC) is refused; its run starts again.
"""
from __future__ import annotations

import hashlib
import hmac
import os
import secrets
import time
from pathlib import Path

CHECKPOINT_FILE = "checkpoint.pkl"
KEY_FILE = "checkpoint.key"
MAGIC = b"slosh-fsi checkpoint, HMAC-SHA256 of the pickle after this line:\n"


class CheckpointRefused(ValueError):
    """A checkpoint this user's runs did not write (its HMAC does not match)."""


def key_path() -> Path:
    """The per-user key's file (module doc)."""
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "slosh-fsi" / KEY_FILE


def user_key(create: bool) -> bytes | None:
    """The per-user key; made (mode 0600) when absent and ``create``, else None."""
    path = key_path()
    if path.is_file():
        return path.read_bytes()
    if not create:
        return None
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f"{KEY_FILE}.{os.getpid()}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(secrets.token_bytes(32))
    try:
        os.link(tmp, path)  # the first writer's key wins; never replace a key in use
    except FileExistsError:
        pass
    finally:
        os.unlink(tmp)
    return path.read_bytes()


def _mac(key: bytes, data: bytes) -> bytes:
    return hmac.new(key, data, hashlib.sha256).hexdigest().encode("ascii")


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
    """Pickle ``payload`` to ``path`` atomically (a temporary file renamed over it), with
    its HMAC under the user's key in front (module doc)."""
    import cloudpickle

    data = cloudpickle.dumps(payload)
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        f.write(MAGIC + _mac(user_key(create=True), data) + b"\n" + data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def read(path: Path) -> dict:
    """The payload a checkpoint at ``path`` holds; :class:`CheckpointRefused` when its HMAC
    is missing or does not match this user's key (nothing is unpickled then)."""
    import pickle

    blob = Path(path).read_bytes()
    key = user_key(create=False)
    head, _, rest = blob.partition(b"\n")
    mac, _, data = rest.partition(b"\n")
    if not blob.startswith(MAGIC) or key is None or \
            not hmac.compare_digest(mac, _mac(key, data)):
        raise CheckpointRefused(
            f"'{path}' was not written by this user's runs (its HMAC does not match the key "
            f"in '{key_path()}'): not unpickled, since unpickling runs code; start the run "
            f"again without --resume")
    return pickle.loads(data)
