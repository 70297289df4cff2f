"""Newton steps on a finite-difference Jacobian of the coupling map: the rescue of a window
whose quasi-Newton iterations stalled (``on_max_iterations = "newton"``).

The window's fixed point x = H(x) is the root of R(x) = H(x) - x. At the window's best
iterate x_b the Jacobian of H is taken column by column,

    J[:, j] = (H(x_b + delta e_j) - H(x_b)) / delta,     delta = step * rms(x_b),

one solve of both participants per entry of x (the accelerated vector, scaled as the
acceleration's), and the steps that follow use B0 = (J - I)^-1, the inverse Jacobian of R,
corrected by the secants of the steps taken since (the multisecant update of IQN-ILS with
B0 as its initial inverse Jacobian; Delaisse, Demeester, Haelterman & Degroote 2023 call
this the generalized Broyden form):

    x+ = x + (W_x - B0 V) a - B0 r,    a = argmin |V a + r|,

with r = H(x) - x, V the differences of r and W_x those of x between steps. With no secant
it is the chord step x+ = x - B0 r.

Where this helps: a fold snapping inside a window makes H smooth but steep (on the valve
fill, singular values of J up to about 900, cond(J - I) about 4e3), and the secants of
100 iterations of IQN-ILS do not span it; the Jacobian at the best iterate does, and three
steps from a residual of 1.8e-2 reached 3e-5 (docs/notes/newton-steps.md).
Where H jumps (a cut cell changing class within the window) no Jacobian helps.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

JACOBIAN_STEP = 1e-4
"""Finite-difference step of the Jacobian, as a fraction of the rms of the vector (-)."""


def finite_difference_jacobian(evaluate: Callable[[np.ndarray], np.ndarray], x: np.ndarray,
                               y: np.ndarray, step: float = JACOBIAN_STEP) -> np.ndarray:
    """J (n, n) of ``evaluate`` (R^n -> R^n) at ``x`` (n,) whose value is ``y`` (n,), by
    forward differences of ``step`` times the rms of ``x`` (an absolute ``step`` where x is
    zero). Raises FloatingPointError if a column is not finite."""
    x = np.asarray(x, dtype=float)
    scale = float(np.sqrt(np.mean(x ** 2)))
    delta = step * (scale if scale > 0.0 else 1.0)
    jacobian = np.empty((y.size, x.size))
    for j in range(x.size):
        shifted = x.copy()
        shifted[j] += delta
        column = (np.asarray(evaluate(shifted), dtype=float) - y) / delta
        if not np.all(np.isfinite(column)):
            raise FloatingPointError(f"column {j} of the finite-difference Jacobian is not "
                                     "finite")
        jacobian[:, j] = column
    return jacobian


class SecantNewton:
    """Steps x+ from (x, H(x)) with the initial inverse Jacobian B0 = (J - I)^-1 of R and the
    secants of the steps taken with it (module doc)."""

    def __init__(self, jacobian: np.ndarray):
        n = jacobian.shape[0]
        self.inverse = np.linalg.inv(jacobian - np.eye(n))
        self._v: list[np.ndarray] = []  # differences of r, newest first
        self._w: list[np.ndarray] = []  # differences of x
        self._previous = None

    def update(self, x: np.ndarray, x_tilde: np.ndarray) -> np.ndarray:
        r = x_tilde - x
        if self._previous is not None:
            self._v.insert(0, r - self._previous[1])
            self._w.insert(0, x - self._previous[0])
        self._previous = (x.copy(), r.copy())
        if not self._v:
            return x - self.inverse @ r
        V, W = np.stack(self._v, axis=1), np.stack(self._w, axis=1)
        q, rr = np.linalg.qr(V)
        a = np.linalg.lstsq(rr, -(q.T @ r), rcond=None)[0]
        return x + W @ a - self.inverse @ (r + V @ a)
