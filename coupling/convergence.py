"""Convergence measures per data field (as preCICE's relative/absolute measures).

For a field with input ``x`` and output ``x_tilde`` of one coupling iteration:

* ``absolute``: |x_tilde - x|_2 <= limit;
* ``relative``: |x_tilde - x|_2 <= limit * |x_tilde|_2.

A window has converged when every measure holds, or when any measure marked ``sufficient``
holds (preCICE's ``suffices``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MEASURE_KINDS = ("absolute", "relative")


@dataclass(frozen=True)
class ConvergenceMeasure:
    """field : data field name; kind : ``absolute`` or ``relative``; limit : tolerance (field
    units for absolute, - for relative); sufficient : this measure alone ends the window."""

    field: str
    kind: str = "relative"
    limit: float = 1e-5
    sufficient: bool = False

    def __post_init__(self):
        if self.kind not in MEASURE_KINDS:
            raise ValueError(f"convergence measure kind must be one of {MEASURE_KINDS}, "
                             f"got {self.kind!r}")
        if not self.limit > 0:
            raise ValueError(f"convergence limit for field '{self.field}' must be > 0, "
                             f"got {self.limit!r}")

    def residual(self, x: np.ndarray, x_tilde: np.ndarray) -> float:
        """The measured norm: absolute |x_tilde - x|, or relative |x_tilde - x| / |x_tilde|."""
        with np.errstate(over="ignore", invalid="ignore"):  # a diverging iteration overflows
            diff = float(np.linalg.norm(x_tilde - x))
            scale = float(np.linalg.norm(x_tilde))
        if self.kind == "absolute":
            return diff
        return diff / scale if scale > 0.0 else (0.0 if diff == 0.0 else np.inf)

    def holds(self, residual: float) -> bool:
        return residual <= self.limit


def window_converged(measures, residuals: dict[str, float]) -> bool:
    """True when all measures hold, or any sufficient one does."""
    held = [m.holds(residuals[m.field]) for m in measures]
    if any(h and m.sufficient for h, m in zip(held, measures)):
        return True
    return all(held)


def residual_score(measures, residuals: dict[str, float]) -> float:
    """The largest residual over its measure's limit (-): at most 1 when every measure
    holds."""
    return max(residuals[m.field] / m.limit for m in measures)


class StallRule:
    """Whether a try of a window has stalled: called with each iteration (1-based) and its
    :func:`residual_score`, True once the best score has not fallen to ``reduction`` of
    itself within ``iterations`` iterations."""

    def __init__(self, iterations: int, reduction: float):
        self.iterations, self.reduction = iterations, reduction
        self.best, self.since = np.inf, 0

    def __call__(self, iteration: int, score: float) -> bool:
        if score < self.reduction * self.best:
            self.best, self.since = score, iteration
        return iteration - self.since >= self.iterations
