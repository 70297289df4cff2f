"""Coupling schemes (registry): explicit, implicit serial, implicit parallel.

Two participants, ``first`` and ``second`` (see :mod:`coupling.participant`). Per window:

* ``explicit`` (staggered): first solves with the second's last data, then second with the
  first's new data; one pass, no checkpoints.
* ``implicit-serial`` (Gauss-Seidel): the fixed point x = H(x) with x the second's fields:
  first solves with x, second with the first's output, giving x_tilde = H(x); the acceleration
  proposes the next x; checkpoints are restored before each repeat.
* ``implicit-parallel`` (Jacobi): both solve with the other's previous iterate; the fixed point is
  over both participants' fields together.

Convergence is measured per field on the change over one iteration (:mod:`coupling.convergence`),
every iteration counted, the one in which convergence is detected included; that iteration's
input and output go to the acceleration's ``converged`` (quasi-Newton secants for reuse);
the accelerated vector is each accelerated field scaled by its norm at the window's first
iteration (so fields of different units weigh alike in the quasi-Newton least squares).
On reaching ``max_iterations`` without convergence the scheme raises :class:`CouplingError`
(``on_max_iterations = "error"``), accepts the last iterate and logs it (``"accept"``; while
every measured residual is at most ``accept_residual``, else it raises as ``"error"`` does),
accepts the window's best iterate in the same way (``"accept-best"``: the iteration whose
largest residual over its measure's limit was smallest, its two solves repeated from the
window's start with that iteration's input, one iteration more), redoes it from its start as two windows of half its size, each from the fields the one before it
converged to (``"split"``: a half that does not converge is halved again, at most
``split_depth`` times, and at the last level its best iterate is accepted as with
``"accept-best"``, or with ``split_unconverged = "window"`` the whole window is redone
from its start and its best iterate kept; the window is converged if every part is, and its
log counts every try's iterations; with ``stall_iterations`` > 0 a try to be split stops
before ``max_iterations`` once its best residual, the largest over its measure's limit, has
not fallen to ``stall_reduction`` of itself within ``stall_iterations`` iterations: a split
window's parts start from the window's start whatever its first try did, so only the
iterations spent change), or redoes the window once from its start by the explicit scheme
(``"explicit"``: the first participant with the window's predicted data, the second with the
first's output; both restored from their checkpoints, the acceleration's reused secants
dropped) and logs it. Except for a split window whose parts all converged, the window's log
says ``converged = False``; ``explicit`` marks the redone one.
Where "explicit" is meant: a fixed point that does not exist near the window's start, as when
a quasi-static membrane's equilibrium path jumps (a fold snapping), which no smaller window
mends (docs/notes/slow-fills.md).

Every scheme starts a window from a prediction of every field made from the converged values
of past windows x^n, x^{n-1}, x^{n-2} (``extrapolation_order``, after preCICE's
``extrapolation-order``): 0 keeps x^n (default); 1 takes 2 x^n - x^{n-1} (linear); 2 takes
2.5 x^n - 2 x^{n-1} + 0.5 x^{n-2} (preCICE's second order). While fewer past windows exist
the order is lowered.
"""
from __future__ import annotations

import logging
import time as _time
from dataclasses import dataclass, field, replace
from typing import Callable, Optional

import numpy as np

from .acceleration import ACCELERATIONS, AccelerationSettings
from .convergence import ConvergenceMeasure, StallRule, residual_score, window_converged
from .participant import Participant

log = logging.getLogger(__name__)

SCHEMES: dict[str, Callable] = {}
IMPLICIT_SCHEMES: set[str] = set()
"""Names in SCHEMES that iterate each window until the convergence measures hold."""
ON_MAX_ITERATIONS = ("error", "accept", "accept-best", "explicit", "split")
SPLIT_UNCONVERGED = ("parts", "window")
"""What a split window some of whose smallest parts did not converge keeps: those parts'
best iterates, or the whole window redone from its start with its best iterate kept."""
EXTRAPOLATION_WEIGHTS = {0: (1.0,), 1: (2.0, -1.0), 2: (2.5, -2.0, 0.5)}
"""Weights of x^n, x^{n-1}, x^{n-2} in the prediction of a window's starting values."""


def register_scheme(name: str, implicit: bool = True):
    """Decorator: register a window-iteration function under ``name``; ``implicit``: it
    iterates each window until the convergence measures hold (so it needs at least one)."""
    def deco(func):
        SCHEMES[name] = func
        if implicit:
            IMPLICIT_SCHEMES.add(name)
        else:
            IMPLICIT_SCHEMES.discard(name)
        return func
    return deco


class CouplingError(RuntimeError):
    """A window did not converge within ``max_iterations`` and the settings say stop, or its
    data became non-finite (the window diverged, whatever the settings say); ``window`` is its
    :class:`WindowLog` (residual history included)."""

    def __init__(self, message: str, window: "WindowLog"):
        super().__init__(message)
        self.window = window


@dataclass
class CouplingSettings:
    """Every knob of a coupled run (the scene's [coupling] table maps onto these).

    scheme : one of SCHEMES; acceleration : one of ACCELERATIONS (ignored by ``explicit``);
    acceleration_settings : :class:`AccelerationSettings`; measures : list of
    :class:`ConvergenceMeasure`, at least one for a scheme in IMPLICIT_SCHEMES;
    max_iterations : per window; on_max_iterations : one of ON_MAX_ITERATIONS (module doc);
    split_depth : with ``split``, how many times a window may be halved (its
    smallest parts 2**-split_depth of it); stall_iterations, stall_reduction : with
    ``split``, a try that will be split stops once its best residual has not fallen to
    stall_reduction of itself in stall_iterations iterations (0: it runs max_iterations);
    split_unconverged : with ``split``, one of SPLIT_UNCONVERGED;
    accelerated_fields : fields in the fixed-point vector (default: the second's fields for
    serial, all fields for parallel); extrapolation_order : 0, 1 or 2, prediction of each
    window's starting values from past windows; accept_residual : with ``accept``, the largest
    residual (each measure's, in its own units) a window that did not converge is accepted at
    (default inf: any).
    """

    scheme: str = "implicit-serial"
    acceleration: str = "iqn-ils"
    acceleration_settings: AccelerationSettings = field(default_factory=AccelerationSettings)
    measures: list = field(default_factory=list)
    max_iterations: int = 50
    on_max_iterations: str = "error"
    accelerated_fields: Optional[tuple] = None
    extrapolation_order: int = 0
    accept_residual: float = float("inf")
    split_depth: int = 3
    stall_iterations: int = 0
    stall_reduction: float = 0.5
    split_unconverged: str = "parts"

    def __post_init__(self):
        if self.scheme not in SCHEMES:
            raise ValueError(f"coupling scheme must be one of {sorted(SCHEMES)}, "
                             f"got {self.scheme!r}")
        if self.acceleration not in ACCELERATIONS:
            raise ValueError(f"acceleration must be one of {sorted(ACCELERATIONS)}, "
                             f"got {self.acceleration!r}")
        if self.on_max_iterations not in ON_MAX_ITERATIONS:
            raise ValueError(f"on_max_iterations must be one of {ON_MAX_ITERATIONS}, "
                             f"got {self.on_max_iterations!r}")
        if not self.accept_residual > 0:
            raise ValueError(f"accept_residual must be > 0, got {self.accept_residual!r}")
        if not 1 <= self.split_depth <= 20:
            raise ValueError(f"split_depth must be in 1..20, got {self.split_depth!r}")
        if not 0 <= self.stall_iterations <= 10_000:
            raise ValueError(f"stall_iterations must be in 0..10000, got "
                             f"{self.stall_iterations!r}")
        if self.stall_iterations and self.on_max_iterations != "split":
            raise ValueError("stall_iterations > 0 needs on_max_iterations = 'split' (a try "
                             "stopped early is split), got on_max_iterations = "
                             f"{self.on_max_iterations!r}")
        if self.split_unconverged not in SPLIT_UNCONVERGED:
            raise ValueError(f"split_unconverged must be one of {SPLIT_UNCONVERGED}, got "
                             f"{self.split_unconverged!r}")
        if not 0.0 < self.stall_reduction < 1.0:
            raise ValueError(f"stall_reduction must be in (0, 1), got {self.stall_reduction!r}")
        if self.max_iterations < 1:
            raise ValueError(f"max_iterations must be >= 1, got {self.max_iterations!r}")
        if self.extrapolation_order not in EXTRAPOLATION_WEIGHTS:
            raise ValueError(f"extrapolation_order must be one of {sorted(EXTRAPOLATION_WEIGHTS)}, "
                             f"got {self.extrapolation_order!r}")
        if self.scheme in IMPLICIT_SCHEMES and not self.measures:
            raise ValueError(f"implicit coupling scheme {self.scheme!r} needs at least one "
                             "ConvergenceMeasure in measures (with none, every window would "
                             "stop after one iteration as if converged)")


@dataclass
class WindowLog:
    """One window: index, start time (s), size (s), iterations, residuals per iteration
    ({field: norm}), relaxation per iteration (NaN for quasi-Newton steps), converged flag,
    seconds spent in each participant's ``solve_window``, ``explicit``: redone by the
    explicit scheme after ``iterations - 1`` iterations did not converge;
    ``parts``: the windows it was done in (more than 1: split, ``on_max_iterations =
    "split"``; its iterations, residuals and relaxations are then its first try's followed
    by every part's), ``part_residuals``, each part's last residuals, and ``split_undone``:
    split, some of its smallest parts unconverged, and redone whole with its best iterate
    kept (``split_unconverged = "window"``; ``parts`` is then 1)."""

    index: int
    time: float
    size: float = float("nan")
    iterations: int = 0
    residuals: list = field(default_factory=list)
    relaxation: list = field(default_factory=list)
    converged: bool = False
    seconds: dict = field(default_factory=dict)
    explicit: bool = False
    part_residuals: list = field(default_factory=list)
    split_undone: bool = False

    @property
    def parts(self) -> int:
        return len(self.part_residuals) or 1

    @property
    def last_residuals(self) -> dict:
        """{field: norm} the window ended with: its last iteration's, or for a split window
        the largest over its parts' last ones."""
        if self.part_residuals:
            return {name: max(r[name] for r in self.part_residuals)
                    for name in self.part_residuals[0]}
        return self.residuals[-1] if self.residuals else {}


@dataclass
class CouplingLog:
    """All windows of a run."""

    windows: list = field(default_factory=list)

    @property
    def mean_iterations(self) -> float:
        return float(np.mean([w.iterations for w in self.windows])) if self.windows else 0.0


class _Timed:
    """Calls a participant's solve_window and adds its wall time to the window log."""

    def __init__(self, participant: Participant, window: WindowLog):
        self.p, self.w = participant, window
        self.w.seconds.setdefault(participant.name, 0.0)

    def __call__(self, t, dt, data):
        t0 = _time.perf_counter()
        out = self.p.solve_window(t, dt, data)
        self.w.seconds[self.p.name] += _time.perf_counter() - t0
        return {k: np.asarray(v, dtype=np.float64) for k, v in out.items()}


def run(first: Participant, second: Participant, settings: CouplingSettings, dt: float,
        n_windows: int, t0: float = 0.0, on_window: Optional[Callable] = None,
        next_window: Optional[Callable] = None) -> CouplingLog:
    """Couple ``first`` and ``second`` over ``n_windows`` windows of ``dt`` (s) from ``t0``.

    ``on_window(window_log, data)`` is called after each window with the converged fields of
    both participants. ``next_window(window_log, data)``, when given, is called just before
    it and returns the next window's size (s), or None to stop (windows of varying size;
    ``n_windows`` is then the most); if it also has ``retry(window_log)``, a window that
    raises :class:`CouplingError` is redone from its start (both participants restored, the
    acceleration's memory of past windows dropped) at the size that returns, until it
    returns None. Returns the :class:`CouplingLog`. The same, a window at a time:
    :func:`start` and :func:`advance`.
    """
    loop = start(first, second, settings, dt, n_windows, t0)
    while advance(loop, first, second, on_window, next_window):
        pass
    return loop.log


@dataclass
class Loop:
    """A coupled run between two windows: all that :func:`advance` carries from one window
    to the next (the acceleration's memory, the converged fields of past windows for the
    prediction, time, window size and count, the log). Pickled with both participants it is
    a checkpoint: the run continues from it as if never stopped."""

    settings: CouplingSettings
    acceleration: object
    history: list
    t0: float
    t: float
    dt: Optional[float]
    k: int
    n_windows: int
    log: CouplingLog
    done: bool = False


def start(first: Participant, second: Participant, settings: CouplingSettings, dt: float,
          n_windows: int, t0: float = 0.0) -> Loop:
    """The :class:`Loop` before the first window (arguments as :func:`run`'s)."""
    _check_window(dt)
    data = {**{k: np.asarray(v, dtype=np.float64) for k, v in first.initial_data().items()},
            **{k: np.asarray(v, dtype=np.float64) for k, v in second.initial_data().items()}}
    return Loop(settings, ACCELERATIONS[settings.acceleration](settings.acceleration_settings),
                [data], t0, t0, dt, 0, n_windows, CouplingLog())


def advance(loop: Loop, first: Participant, second: Participant,
            on_window: Optional[Callable] = None, next_window: Optional[Callable] = None) -> bool:
    """One window of ``loop`` (callbacks as :func:`run`'s); False, doing nothing, once the
    run is over."""
    if loop.done or loop.k >= loop.n_windows:
        return False
    s, k = loop.settings, loop.k
    window, data, dt = _window(first, second, s, loop.acceleration, SCHEMES[s.scheme],
                               _extrapolate(loop.history, s.extrapolation_order), k,
                               loop.t0 + k * loop.dt if next_window is None else loop.t,
                               loop.dt, getattr(next_window, "retry", None))
    loop.history = [data] + loop.history[:s.extrapolation_order]
    loop.log.windows.append(window)
    loop.k += 1
    log.debug("window %d: %d iterations, converged %s", k, window.iterations,
              window.converged)
    if next_window is not None:  # before on_window, which may report what it found
        loop.t = window.time + dt
        loop.dt = next_window(window, data)
    if on_window is not None:
        on_window(window, data)
    if next_window is not None:
        if loop.dt is None:
            loop.done = True
        else:
            _check_window(loop.dt)
    return True


def _window(first, second, settings, acceleration, iterate, predicted, k, t, dt, retry):
    """One window from ``predicted`` fields, redone smaller on a CouplingError while
    ``retry(window_log)`` gives a size: (window log, converged fields, the size it took)."""
    checkpoints = (first.store_checkpoint(), second.store_checkpoint())
    while True:
        window = WindowLog(index=k, time=t, size=dt)
        try:
            out = iterate(first, second, settings, acceleration, dict(predicted), t, dt, window)
            if not window.converged and settings.on_max_iterations == "split":
                log.warning("window %d (t = %g s) not converged after %d iterations: redone "
                            "in halves", k, t, window.iterations)
                _restart(first, second, checkpoints, acceleration)
                out = _split(first, second, settings, acceleration, iterate, predicted, t, dt,
                             window, settings.split_depth)
                window.converged = all(window_converged(settings.measures, r)
                                       for r in window.part_residuals)
                if not window.converged and settings.split_unconverged == "window":
                    out = _whole_best(first, second, settings, acceleration, iterate,
                                      predicted, checkpoints, window)
            return window, out, dt
        except CouplingError:
            smaller = retry(window) if retry is not None else None
            if smaller is None:
                if retry is not None:
                    log.warning("window %d (t = %g s) not converged at %g s: not redone", k,
                                t, dt)
                raise
            log.warning("window %d (t = %g s) not converged at %g s: redone at %g s", k, t, dt,
                        smaller)
            _restart(first, second, checkpoints, acceleration)
            _check_window(smaller)
            dt = smaller


def _best_kept(settings: CouplingSettings) -> CouplingSettings:
    """``settings`` for a try that is not split again: its best iterate kept
    (``"accept-best"``), never stopped early."""
    return replace(settings, on_max_iterations="accept-best", stall_iterations=0)


def _restart(first, second, checkpoints, acceleration) -> None:
    """Both participants back to ``checkpoints`` and the acceleration's past dropped: a
    window begun again from its start."""
    first.restore_checkpoint(checkpoints[0])
    second.restore_checkpoint(checkpoints[1])
    acceleration.forget()


def _split(first, second, settings, acceleration, iterate, data, t, dt, window, depth):
    """The window [t, t + dt] (both participants at its start) done as two windows of dt/2,
    the first from ``data``, the second from the first's converged fields; a half that does
    not converge is redone from its start in halves while ``depth`` allows, and at the last
    level its best iterate is accepted (as ``"accept-best"`` does). Every part's iterations,
    residuals, relaxations and seconds are added to ``window``. Returns the fields at
    t + dt."""
    half = 0.5 * dt
    last_level = _best_kept(settings)
    for i in range(2):
        t_part = t + i * half
        part = WindowLog(index=window.index, time=t_part, size=half)
        checkpoints = (first.store_checkpoint(), second.store_checkpoint())
        out = iterate(first, second, settings if depth > 1 else last_level, acceleration,
                      dict(data), t_part, half, part)
        _add(window, part)
        if part.converged or depth == 1:
            window.part_residuals.append(part.residuals[-1])
        else:
            _restart(first, second, checkpoints, acceleration)
            out = _split(first, second, settings, acceleration, iterate, data, t_part, half,
                         window, depth - 1)
        data = out
    return data


def _whole_best(first, second, settings, acceleration, iterate, data, checkpoints, window):
    """A split window some of whose smallest parts did not converge, redone from its start
    (``checkpoints``) as one window whose best iterate is kept (``"accept-best"``, every
    iteration); its parts are dropped from ``window`` but for their iterations. Returns
    the fields at the window's end."""
    log.warning("window %d (t = %g s): parts not converged; redone whole, its best iterate "
                "kept", window.index, window.time)
    _restart(first, second, checkpoints, acceleration)
    whole = WindowLog(index=window.index, time=window.time, size=window.size)
    out = iterate(first, second, _best_kept(settings),
                  acceleration, dict(data), window.time, window.size, whole)
    _add(window, whole)
    window.part_residuals = []
    window.split_undone = True
    window.converged = whole.converged
    return out


def _add(window: WindowLog, part: WindowLog) -> None:
    """``part``'s iterations, residuals, relaxations and seconds added to ``window``'s."""
    window.iterations += part.iterations
    window.residuals.extend(part.residuals)
    window.relaxation.extend(part.relaxation)
    window.explicit |= part.explicit
    for name, seconds in part.seconds.items():
        window.seconds[name] = window.seconds.get(name, 0.0) + seconds


def _check_window(dt: float) -> None:
    if not dt > 0 or not np.isfinite(dt):
        raise ValueError(f"time-window size dt must be finite and > 0 s, got {dt!r}")


def _extrapolate(history: list, order: int) -> dict:
    """Prediction of every field from ``history`` (newest first) at the highest order <= ``order``
    that the history allows."""
    weights = EXTRAPOLATION_WEIGHTS[min(order, len(history) - 1)]
    if len(weights) == 1:
        return history[0]
    return {n: sum(w * h[n] for w, h in zip(weights, history)) for n in history[0]}


@register_scheme("explicit", implicit=False)
def _explicit(first, second, settings, acceleration, data, t, dt, window):
    solve1, solve2 = _Timed(first, window), _Timed(second, window)
    out1 = solve1(t, dt, _pick(data, second.write_fields))
    out2 = solve2(t, dt, out1)
    window.iterations, window.converged = 1, True
    return {**data, **out1, **out2}


def _redo_explicit(first, second, data, t, dt, window):
    """The window by the explicit scheme from the predicted ``data``, counted as one more
    iteration of ``window`` (left unconverged, marked ``explicit``)."""
    redo = WindowLog(index=window.index, time=t, size=dt)
    out = _explicit(first, second, None, None, dict(data), t, dt, redo)
    _add(window, redo)
    window.explicit = True
    return out


class _Packer:
    """Concatenate named fields into one scaled vector and back."""

    def __init__(self, names, sample: dict):
        self.names = tuple(names)
        self.sizes = [sample[n].size for n in self.names]
        self.scale = np.array([max(float(np.linalg.norm(sample[n])), 1e-300) for n in self.names])

    def pack(self, fields: dict) -> np.ndarray:
        return np.concatenate([fields[n] / s for n, s in zip(self.names, self.scale)])

    def unpack(self, vec: np.ndarray) -> dict:
        out, i = {}, 0
        for n, size, s in zip(self.names, self.sizes, self.scale):
            out[n] = vec[i:i + size] * s
            i += size
        return out


def _check_finite(fields: dict, source: str, window, t: float, iteration: int) -> None:
    """Raise :class:`CouplingError` when any of ``fields`` (the measured or the accelerated
    ones: a participant may write a field it has no value for as NaN) holds a non-finite
    value: no later iteration or window can use it."""
    bad = [name for name, value in fields.items() if not np.all(np.isfinite(value))]
    if bad:
        raise CouplingError(f"window {window.index} (t = {t:g} s) not converged: at iteration "
                            f"{iteration} {source} non-finite {', '.join(sorted(bad))} (the "
                            "window diverged)", window)


class _BestIterate:
    """The iteration of a window whose largest residual over its measure's limit is the
    smallest so far (``iteration``) and a copy of its input fields (``input``)."""

    def __init__(self, measures):
        self.measures = measures
        self.score = np.inf
        self.iteration = 0
        self.input: dict = {}

    def offer(self, iteration: int, x: dict, residuals: dict) -> None:
        score = residual_score(self.measures, residuals)
        if score < self.score:
            self.score, self.iteration = score, iteration
            self.input = {name: np.array(value, copy=True) for name, value in x.items()}


def _pick(data: dict, names) -> dict:
    return {n: data[n] for n in names}


def _implicit(first, second, settings, acceleration, data, t, dt, window, parallel: bool):
    solve1, solve2 = _Timed(first, window), _Timed(second, window)
    checkpoints = (first.store_checkpoint(), second.store_checkpoint())
    names = settings.accelerated_fields or (
        tuple(first.write_fields) + tuple(second.write_fields) if parallel
        else tuple(second.write_fields))
    x = dict(data)  # current input of every field
    acceleration.start_window()
    packer = None
    best = _BestIterate(settings.measures) \
        if settings.on_max_iterations == "accept-best" else None

    stalled = StallRule(settings.stall_iterations, settings.stall_reduction) \
        if settings.stall_iterations else None

    def iteration(x: dict, it: int):
        """Both solves from the window's start with input ``x``, logged as iteration ``it``
        (the participants then hold its solves): (x_tilde, residuals)."""
        if window.iterations > 0:
            first.restore_checkpoint(checkpoints[0])
            second.restore_checkpoint(checkpoints[1])
        out1 = solve1(t, dt, _pick(x, second.write_fields))
        out2 = solve2(t, dt, _pick(x if parallel else out1, first.write_fields))
        x_tilde = {**x, **out1, **out2}
        _check_finite({m.field: x_tilde[m.field] for m in settings.measures},
                      "a participant returned", window, t, it)
        residuals = {m.field: m.residual(x[m.field], x_tilde[m.field]) for m in settings.measures}
        window.residuals.append(residuals)
        window.iterations = it
        if best is not None:
            best.offer(it, x, residuals)
        return x_tilde, residuals

    for it in range(1, settings.max_iterations + 1):
        x_tilde, residuals = iteration(x, it)
        if window_converged(settings.measures, residuals):
            window.converged = True
            if packer is not None:
                acceleration.converged(packer.pack(x), packer.pack(x_tilde))
            window.relaxation.append(float("nan"))
            break
        if stalled is not None and stalled(it, residual_score(settings.measures, residuals)):
            break  # split by the caller (_window)
        if packer is None:
            packer = _Packer(names, x_tilde)
        new = packer.unpack(acceleration.update(packer.pack(x), packer.pack(x_tilde)))
        _check_finite(new, "the acceleration gave", window, t, it)
        window.relaxation.append(acceleration.last_relaxation)
        x = {**x_tilde, **new}
    if not window.converged and settings.on_max_iterations == "split":
        return x_tilde  # redone in halves by the caller (_window)
    if not window.converged:
        msg = (f"window {window.index} (t = {t:g} s) not converged after {window.iterations} "
               f"iterations; last residuals {window.residuals[-1]}")
        if settings.on_max_iterations == "error":
            raise CouplingError(msg, window)
        if best is not None and window.iterations != best.iteration:
            x_tilde, residuals = iteration(best.input, window.iterations + 1)
            msg = (f"{msg}; the best, iteration {best.iteration}, repeated: residuals "
                   f"{residuals}")
        if (settings.on_max_iterations in ("accept", "accept-best")
                and max(window.residuals[-1].values()) > settings.accept_residual):
            raise CouplingError(f"{msg}, above accept_residual = {settings.accept_residual:g}",
                                window)
        if settings.on_max_iterations == "explicit":
            log.warning("%s; redone explicitly", msg)
            _restart(first, second, checkpoints, acceleration)
            return _redo_explicit(first, second, data, t, dt, window)
        log.warning("%s; accepted", msg)
        acceleration.stalled()
    acceleration.end_window()
    return x_tilde


@register_scheme("implicit-serial")
def _implicit_serial(*args):
    return _implicit(*args, parallel=False)


@register_scheme("implicit-parallel")
def _implicit_parallel(*args):
    return _implicit(*args, parallel=True)
