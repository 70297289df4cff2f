"""Cubic Hermite shape functions on one element of the meridian, and the Gauss rule.

On an element [S_a, S_b] of length h = S_b - S_a with local coordinate xi = (S - S_a) / h in
[0, 1], a field f with nodal values and S-derivatives (f_a, f'_a, f_b, f'_b) is

    f(S) = H0(xi) f_a + h H1(xi) f'_a + H2(xi) f_b + h H3(xi) f'_b,
    H0 = 1 - 3 xi^2 + 2 xi^3,  H1 = xi - 2 xi^2 + xi^3,  H2 = 3 xi^2 - 2 xi^3,  H3 = xi^3 - xi^2,

C1 across elements (value and slope shared at the nodes), so the bending energy, which holds
second derivatives, is conforming. d/dS = (1/h) d/dxi.
"""
from __future__ import annotations

import numpy as np


def hermite_basis(xi: np.ndarray, length: np.ndarray) -> np.ndarray:
    """(..., 3, 4): the four shape functions (f_a, f'_a, f_b, f'_b order) and their first and
    second S-derivatives (rows: value 1, d/dS 1/m, d2/dS2 1/m^2, each times the unit of the
    nodal value they multiply) at local coordinates ``xi`` (...) on elements of
    ``length`` (...) m (broadcast together)."""
    xi, h = np.broadcast_arrays(np.asarray(xi, dtype=float), np.asarray(length, dtype=float))
    x2, x3 = xi * xi, xi * xi * xi
    value = np.stack([1 - 3 * x2 + 2 * x3, h * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3,
                      h * (x3 - x2)], axis=-1)
    slope = np.stack([(-6 * xi + 6 * x2) / h, 1 - 4 * xi + 3 * x2, (6 * xi - 6 * x2) / h,
                      3 * x2 - 2 * xi], axis=-1)
    curvature = np.stack([(-6 + 12 * xi) / h**2, (-4 + 6 * xi) / h, (6 - 12 * xi) / h**2,
                          (6 * xi - 2) / h], axis=-1)
    return np.stack([value, slope, curvature], axis=-2)


def gauss_rule(points: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre abscissae (points,) and weights (points,) on [0, 1] (exact for
    polynomials of degree 2 points - 1)."""
    if points < 1:
        raise ValueError(f"a Gauss rule needs at least one point, got {points}")
    x, w = np.polynomial.legendre.leggauss(points)
    return 0.5 * (x + 1.0), 0.5 * w
