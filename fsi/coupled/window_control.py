"""Window sizes of a coupled run grown and shrunk by a local error estimate.

With ``dynamics.window_tolerance`` = tol > 0 (m) the coupled fill's windows follow the
membrane: after each window of size dt, its node positions x (n, 3) m are compared with their
linear extrapolation from the two windows before it,

    x_p = x_n + (dt / dt_prev) (x_n - x_{n-1}),
    e   = dt / (dt + dt_prev) * max_i |x_i - x_p,i|        (m),

the leading term of a first-order window's local error, (dt^2 / 2) |x''| (backward Euler
liquid, substepped or quasi-static membrane).  The next window is

    dt_next = dt * clip(SAFETY * sqrt(tol / e), SHRINK, GROW),

at least ``dynamics.min_window``, at most ``dynamics.max_window`` and cut to end on
``dynamics.end_time``.  A window is not
redone: one whose e exceeded tol is counted (``windows_over_tolerance``) and the next is
smaller.  Slow fills grow to ``max_window``; a valve opening or a fold snapping shrinks them.
A window whose coupling iterations do not converge (a fold snapping within it) is redone
from its start at RETRY_FACTOR of its size, up to RETRIES times and not below
``min_window`` (``windows_redone``).  Why a floor: a quasi-static window (membrane in
equilibrium, liquid with its inertia) loses its fixed point below about 0.1 s on the thesis's
diaphragm, where the liquid's answer to the membrane solve's own tolerance, rho L dx / dt^2,
outgrows the pressure; measured in docs/notes/slow-fills.md.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

SAFETY = 0.9
"""Fraction of the window the estimate allows that is taken (-)."""
GROW = 2.0
"""Largest growth of the window from one to the next (-)."""
SHRINK = 0.5
"""Largest shrinking of the window from one to the next (-)."""
END_TOLERANCE = 1e-9
"""A run ends when it is within this fraction of end_time of it (-)."""
RETRIES = 10
"""A window whose coupling does not converge is redone at most this many times (-)..."""
RETRY_FACTOR = 0.5
"""...each time at this fraction of its size (-).  Measured on the thesis's fill: halving
from 2 s with 60 iterations allowed crossed four fold snaps and stopped at the fifth
(t = 96 s); a quarter per retry with 25 iterations stopped at the first (t = 82 s)."""


def local_error(x: np.ndarray, x_n: np.ndarray, x_nm1: np.ndarray, dt: float,
                dt_prev: float) -> float:
    """e (m) of the window of ``dt`` (s) ending at positions ``x`` (n, 3) m, after windows
    ending at ``x_n`` and ``x_nm1`` (``dt_prev`` s apart)."""
    predicted = x_n + dt / dt_prev * (x_n - x_nm1)
    return float(dt / (dt + dt_prev) * np.max(np.linalg.norm(x - predicted, axis=1)))


@dataclass
class WindowController:
    """``next_window(window_log, data)`` of :func:`coupling.run`: reads the window's size and
    the converged node positions (``data[points_field]``, flat, m), returns the next size (s)
    or None at ``end_time``; ``errors`` holds e (m) per window (NaN for the first two);
    ``on_retry(window_log)`` is told of each window redone."""

    tolerance: float
    max_window: float
    end_time: float
    points_field: str
    start_positions: np.ndarray
    on_retry: Optional[Callable] = None
    min_window: float = 0.0
    errors: list = field(default_factory=list)
    redone: int = 0
    _retries: int = 0
    _past: list = field(default_factory=list)  # [(positions, window size)] newest first

    def __post_init__(self):
        self._past = [(np.asarray(self.start_positions, dtype=float).reshape(-1, 3), np.nan)]

    def __call__(self, window, data) -> Optional[float]:
        self._retries = 0
        x = np.asarray(data[self.points_field], dtype=float).reshape(-1, 3)
        dt = float(window.size)
        error = np.nan
        if len(self._past) == 2:
            (x_n, _), (x_nm1, _) = self._past
            error = local_error(x, x_n, x_nm1, dt, self._past[0][1])
        self.errors.append(error)
        self._past = [(x, dt), self._past[0]]
        factor = GROW if not error > 0 else SAFETY * np.sqrt(self.tolerance / error)
        proposed = float(np.clip(dt * np.clip(factor, SHRINK, GROW), self.min_window,
                                 self.max_window))
        remaining = self.end_time - (window.time + dt)
        if remaining <= END_TOLERANCE * self.end_time:
            return None
        # no sliver of a window at the end: share what is left equally
        return remaining / np.ceil(remaining / proposed * (1 - 1e-12))

    def retry(self, window) -> Optional[float]:
        """The size (s) to redo a window that did not converge at, or None after RETRIES."""
        if self._retries >= RETRIES or window.size * RETRY_FACTOR < self.min_window:
            return None
        self._retries += 1
        self.redone += 1
        if self.on_retry is not None:
            self.on_retry(window)
        return window.size * RETRY_FACTOR

    @property
    def over_tolerance(self) -> int:
        """Windows whose error exceeded the tolerance."""
        return int(np.sum(np.asarray(self.errors) > self.tolerance))
