"""Accelerations of the coupling fixed point x = H(x): a registry of stateful objects.

Each iteration of a window the scheme hands the acceleration the input ``x`` it used and the
output ``x_tilde = H(x)``; the acceleration returns the next input. All work on one flat
vector (the accelerated fields concatenated, each scaled by the scheme).

* ``constant``: x+ = x + omega (x_tilde - x).
* ``aitken``: dynamic relaxation (Irons & Tuck 1969; Kuettler & Wall 2008):
  omega_k = -omega_{k-1} r_{k-1}.(r_k - r_{k-1}) / |r_k - r_{k-1}|^2, r = x_tilde - x; the first
  iteration of every window uses ``initial_relaxation``.
* ``iqn-ils``: interface quasi-Newton with inverse Jacobian from a least-squares model
  (Degroote, Bathe & Vierendeels 2009): with V = [dr_i], W = [dx_tilde_i] (differences between
  consecutive iterations, newest first, plus ``reuse`` past windows), solve min |V a + r| by QR
  and set x+ = x_tilde + W a. The secant of the iteration in which the window converged is
  added too (``converged``, as preCICE's ``iterationsConverged``), so reused windows keep their
  newest, most local secant. Columns whose QR diagonal falls below ``filter_limit`` times their
  norm are dropped (QR2 filter, Haelterman et al. 2016). The first iteration of the first window
  (or when no column is left) is a constant relaxation with ``initial_relaxation``.
  ``mixing`` beta < 1 relaxes the part of the residual the secants do not span:
  x+ = x + (W - V) a + beta (r + V a), the multisecant update with the initial inverse
  Jacobian -beta I (Anderson mixing with damping beta; beta = 1 is the update above, in which
  that part takes a full Gauss-Seidel step). Where the liquid's added mass makes the full step
  grow a direction tenfold or more, beta near the first relaxation keeps the unexplored
  directions from blowing up between secants.
* ``iqn-imvj``: multi-vector quasi-Newton (Lindner, Mehl, Neumann & Uekermann 2015): the same
  secants, but the inverse Jacobian J (maps residual changes to output changes) is the least
  change from the previous window's J_prev that meets them,
  J = J_prev + (W - J_prev V)(V^T V)^-1 V^T, and x+ = x_tilde - J r; J is kept for the next
  window instead of its columns. Dense n x n: for interfaces of moderate size. With
  J_prev = 0 it is IQN-ILS without reuse. ``mixing`` beta < 1 starts from
  J_prev = (1 - beta) I (the inverse Jacobian -beta I of the residual), so that its first
  window is IQN-ILS with mixing beta and no reuse, and a later window's directions that no
  secant has reached keep beta's relaxation; what the secants taught replaces it where they
  reached. ``jacobian_windows`` K > 0 rebuilds J at each window's end from (1 - beta) I and
  the last K windows' secants, so what a window taught is forgotten K windows later (preCICE's
  IMVJ restarts bound the same memory). A window accepted unconverged restarts J.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

ACCELERATIONS: dict[str, Callable[..., "Acceleration"]] = {}


def register_acceleration(name: str):
    """Class decorator: register an acceleration under ``name``."""
    def deco(cls):
        ACCELERATIONS[name] = cls
        cls.name = name
        return cls
    return deco


@dataclass
class AccelerationSettings:
    """Knobs of every acceleration (each uses the ones it needs).

    relaxation : constant omega (``constant``); initial_relaxation : first omega of a window
    (``aitken``) or of the first iteration (``iqn-ils``); reuse : past windows kept
    (``iqn-ils``); filter_limit : QR2 filter threshold (``iqn-ils``, ``iqn-imvj``);
    max_columns : cap on secant columns (``iqn-ils``, ``iqn-imvj``); mixing : relaxation of
    the residual outside the secants' span (``iqn-ils``, ``iqn-imvj``; 1 as published);
    jacobian_windows : ``iqn-imvj`` rebuilds its inverse Jacobian at each window's end from
    the secants of this many past windows, oldest first (0: every window since the start or
    the last restart, as published).
    """

    relaxation: float = 0.5
    initial_relaxation: float = 0.1
    reuse: int = 0
    filter_limit: float = 1e-8
    max_columns: int = 100
    mixing: float = 1.0
    jacobian_windows: int = 0

    def __post_init__(self):
        if not 0.0 < self.mixing <= 1.0:
            raise ValueError(f"mixing must be in (0, 1], got {self.mixing!r}")
        if self.jacobian_windows < 0:
            raise ValueError(f"jacobian_windows must be >= 0, got {self.jacobian_windows!r}")


class Acceleration:
    """Base: no memory. ``last_relaxation`` is logged (NaN for quasi-Newton steps)."""

    name = "base"

    def __init__(self, settings: AccelerationSettings):
        self.s = settings
        self.last_relaxation = float("nan")

    def start_window(self) -> None:
        """Called before the first iteration of a window."""

    def forget(self) -> None:
        """Drop what past windows taught (called before a failed window is redone: the
        operator that failed it need not be theirs)."""

    def converged(self, x: np.ndarray, x_tilde: np.ndarray) -> None:
        """Called, before :meth:`end_window`, with the input and output of the iteration in
        which the window converged (no update follows); not called when it converges in its
        first iteration."""

    def end_window(self) -> None:
        """Called when a window has converged (or been accepted)."""

    def stalled(self) -> None:
        """Called, before :meth:`end_window`, when a window that did not converge is
        accepted (``on_max_iterations`` accept or accept-best); keeps everything by default."""

    def update(self, x: np.ndarray, x_tilde: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def _relax(self, x, x_tilde, omega):
        self.last_relaxation = float(omega)
        return x + omega * (x_tilde - x)


@register_acceleration("constant")
class ConstantRelaxation(Acceleration):
    def update(self, x, x_tilde):
        return self._relax(x, x_tilde, self.s.relaxation)


@register_acceleration("aitken")
class Aitken(Acceleration):
    def __init__(self, settings):
        super().__init__(settings)
        self.previous_residual = None
        self.omega = settings.initial_relaxation

    def start_window(self):
        self.previous_residual = None

    def update(self, x, x_tilde):
        r = x_tilde - x
        if self.previous_residual is None:
            self.omega = self.s.initial_relaxation
        else:
            dr = r - self.previous_residual
            denom = float(dr @ dr)
            if denom > 0.0:
                self.omega = -self.omega * float(self.previous_residual @ dr) / denom
        self.previous_residual = r.copy()
        return self._relax(x, x_tilde, self.omega)


@register_acceleration("iqn-ils")
class IQNILS(Acceleration):
    def __init__(self, settings):
        super().__init__(settings)
        self.window_v: list[np.ndarray] = []  # this window's columns, newest first
        self.window_w: list[np.ndarray] = []
        self.past: list[tuple[list, list]] = []  # (V cols, W cols) of past windows, newest first
        self.previous = None  # (r, x_tilde) of the previous iteration
        self.columns_used = 0
        self.columns_filtered = 0

    def start_window(self):
        self.window_v, self.window_w = [], []
        self.previous = None

    def forget(self):
        self.past = []

    def end_window(self):
        if self.s.reuse > 0 and self.window_v:
            self.past.insert(0, (self.window_v, self.window_w))
            del self.past[self.s.reuse:]

    def converged(self, x, x_tilde):
        self._record_secant(x, x_tilde)  # kept for reuse (preCICE does the same)

    def _record_secant(self, x, x_tilde) -> np.ndarray:
        """Add this iteration's differences to the window's columns; returns r = x_tilde - x."""
        r = x_tilde - x
        if self.previous is not None:
            r_old, xt_old = self.previous
            self.window_v.insert(0, r - r_old)
            self.window_w.insert(0, x_tilde - xt_old)
        self.previous = (r.copy(), x_tilde.copy())
        return r

    def update(self, x, x_tilde):
        r = self._record_secant(x, x_tilde)
        v_cols = list(self.window_v)
        w_cols = list(self.window_w)
        for pv, pw in self.past:
            v_cols += pv
            w_cols += pw
        v_cols, w_cols = v_cols[: self.s.max_columns], w_cols[: self.s.max_columns]
        if not v_cols:
            self.columns_used = 0
            return self._relax(x, x_tilde, self.s.initial_relaxation)
        V = np.stack(v_cols, axis=1)
        W = np.stack(w_cols, axis=1)
        keep = _qr2_filter(V, self.s.filter_limit)
        self.columns_filtered = V.shape[1] - keep.size
        V, W = V[:, keep], W[:, keep]
        self.columns_used = V.shape[1]
        if V.shape[1] == 0:
            return self._relax(x, x_tilde, self.s.initial_relaxation)
        q, rr = np.linalg.qr(V)
        alpha = np.linalg.solve(rr, -(q.T @ r))
        self.last_relaxation = float("nan")
        if self.s.mixing == 1.0:
            return x_tilde + W @ alpha
        return x + (W - V) @ alpha + self.s.mixing * (r + V @ alpha)


def _qr2_filter(V: np.ndarray, limit: float) -> np.ndarray:
    """Indices of the columns of V kept by a QR2 filter: Gram-Schmidt in order (newest first),
    dropping a column whose orthogonal remainder is below ``limit`` times its norm
    (classical Gram-Schmidt against the kept basis, applied twice: CGS2)."""
    basis = np.empty((V.shape[0], V.shape[1]))
    kept = 0
    keep = []
    for j in range(V.shape[1]):
        v = V[:, j].copy()
        norm = np.linalg.norm(v)
        if norm == 0.0:
            continue
        b = basis[:, :kept]
        for _ in range(2):  # re-orthogonalise once for stability
            v -= b @ (b.T @ v)
        rest = np.linalg.norm(v)
        if rest < limit * norm:
            continue
        basis[:, kept] = v / rest
        kept += 1
        keep.append(j)
    return np.asarray(keep, dtype=int)


@register_acceleration("iqn-imvj")
class IQNIMVJ(IQNILS):
    def __init__(self, settings):
        super().__init__(settings)
        self.jacobian = None  # (n, n) inverse Jacobian of the previous window
        self.windows: list[tuple[list, list]] = []  # (V, W) of past windows, oldest first

    def forget(self):
        super().forget()
        self.jacobian = None
        self.windows = []

    def stalled(self):
        """A window accepted unconverged: its secants come from an iteration that did not
        settle, and the operator it met need not be the next window's, so J restarts."""
        self.forget()
        self.window_v, self.window_w = [], []

    def end_window(self):
        if not self.window_v:
            return
        if self.s.jacobian_windows == 0:
            self.jacobian = self._current_jacobian(self.window_v, self.window_w)
            return
        self.windows.append((self.window_v, self.window_w))
        del self.windows[:-self.s.jacobian_windows]
        self.jacobian = None
        for v_cols, w_cols in self.windows:
            self.jacobian = self._current_jacobian(v_cols, w_cols)

    def _first_jacobian(self, n: int) -> np.ndarray:
        """J before any secant: 0 as published, (1 - mixing) I with mixing (-mixing I for the
        residual)."""
        return (1.0 - self.s.mixing) * np.eye(n)

    def _current_jacobian(self, v_cols, w_cols):
        V = np.stack(v_cols, axis=1)
        W = np.stack(w_cols, axis=1)
        keep = _qr2_filter(V, self.s.filter_limit)
        V, W = V[:, keep], W[:, keep]
        base = self.jacobian if self.jacobian is not None else self._first_jacobian(V.shape[0])
        if V.shape[1] == 0:
            return base
        q, rr = np.linalg.qr(V)
        # (W - J_prev V)(V^T V)^-1 V^T = (W - J_prev V) R^-1 Q^T
        return base + np.linalg.solve(rr.T, (W - base @ V).T).T @ q.T

    def update(self, x, x_tilde):
        r = self._record_secant(x, x_tilde)
        self.columns_used = len(self.window_v)
        if not self.window_v and self.jacobian is None:
            return self._relax(x, x_tilde, self.s.initial_relaxation)
        cols = self.window_v[: self.s.max_columns]
        jac = self._current_jacobian(cols, self.window_w[: self.s.max_columns]) if cols \
            else self.jacobian
        self.last_relaxation = float("nan")
        return x_tilde - jac @ r
