"""Grid studies: the observed order of a sequence of solutions and Richardson's extrapolation
to zero cell size (Roache 1998, Verification and Validation in Computational Science and
Engineering, ch. 5), for cell sizes that need not halve."""
from __future__ import annotations

from scipy.optimize import brentq


def observed_order(d12: float, d23: float, h) -> float | None:
    """p with d12 / d23 = (h1^p - h2^p) / (h2^p - h3^p), h coarse to fine (None when the
    differences do not shrink, or p is outside 0.1..10)."""
    h1, h2, h3 = h
    if not (d12 > 0 and d23 > 0 and d12 > d23):
        return None
    g = lambda p: (h1**p - h2**p) / (h2**p - h3**p) - d12 / d23  # noqa: E731
    if g(0.1) * g(10.0) > 0:
        return None
    return float(brentq(g, 0.1, 10.0))


def richardson(f_coarse: float, f_fine: float, h_coarse: float, h_fine: float,
               order: float) -> float:
    """The value at zero cell size from two grids' values f (any unit) on cells of size h,
    with an error C h^order: f_fine + (f_fine - f_coarse) / ((h_coarse / h_fine)^order - 1)."""
    if not (h_coarse > h_fine > 0 and order > 0):
        raise ValueError(f"richardson needs h_coarse > h_fine > 0 and order > 0, got "
                         f"{h_coarse}, {h_fine}, {order}")
    return f_fine + (f_fine - f_coarse) / ((h_coarse / h_fine) ** order - 1.0)
