"""Sparse direct solves of the tangent: SciPy's SuperLU (an LU, so indefinite and
non-symmetric tangents are solved as well), the factors kept so that one factorisation serves
several right-hand sides (the bordered solves of :mod:`structure.newton.statics`) and, in a modified Newton
iteration, several iterations.

The column ordering is SuperLU's minimum degree on A^T + A (``MMD_AT_PLUS_A``): the tangent's
pattern is symmetric, and on the flat diaphragm's tangent it factorised 1.7x (N = 26), 1.5x
(N = 38) and 2.3x (N = 54, 8,748 unknowns) faster than the default COLAMD. CHOLMOD through
``cholespy`` (a Cholesky, so positive definite tangents only) took 0.020, 0.047 and 0.20 s
against SuperLU's 0.011, 0.065 and 0.15 s on the same three matrices, and cannot take the
indefinite tangents of folds and snaps: it is not used.

SuperLU runs in symmetric mode (``SymmetricMode``: the diagonal preferred as pivot, so the
row order follows the column order and the fill stays that of the symmetric pattern), with a
diagonal pivot threshold of 0.1 (:data:`DIAGONAL_PIVOT_THRESHOLD`). On the 3-D hemisphere's
bordered tangent at a carried axisymmetric state (tank fractions 0.025 and 0.05) it
factorised in 0.031 s against partial pivoting's 0.052-0.060 s at N = 38 (fill 1.0 M against
1.5-1.8 M) and in 0.34-0.37 s against 0.61-0.71 s at N = 76 (7.7 M against 11-12 M), with the
same residual (1e-11 to 2e-10 of the right-hand side); without a threshold (0) the residual
rose to 4e-9 on one of them."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu


DIAGONAL_PIVOT_THRESHOLD = 0.1
"""SuperLU's symmetric mode: a diagonal pivot is kept unless it is below this fraction of its
column's largest entry (partial pivoting takes the largest, 1)."""


class SingularTangent(RuntimeError):
    """The tangent could not be factorised (exactly singular), or its solve is not finite."""


class Factorisation:
    """``solve(b)`` for a (3n, 3n) sparse matrix: SuperLU, minimum degree on A^T + A, in
    symmetric mode (module doc)."""

    def __init__(self, matrix):
        csc = sp.csc_matrix(matrix)
        try:
            self._lu = splu(csc, permc_spec="MMD_AT_PLUS_A",
                            diag_pivot_thresh=DIAGONAL_PIVOT_THRESHOLD,
                            options=dict(SymmetricMode=True))
        except RuntimeError as error:  # "Factor is exactly singular"
            raise SingularTangent(str(error)) from error
        self.shape = csc.shape

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """The solution, the shape of ``rhs`` ((3n,) or (n, 3), or (3n, k))."""
        b = np.asarray(rhs, dtype=float)
        flat = b.reshape(self.shape[0], -1)
        out = self._lu.solve(np.ascontiguousarray(flat))
        if not np.all(np.isfinite(out)):
            raise SingularTangent("the tangent's solve is not finite")
        return out.reshape(b.shape)

    @property
    def determinant_sign(self) -> float:
        """The sign of the matrix's determinant (+1 or -1): changes where an eigenvalue
        crosses zero along a path, at a limit or bifurcation point."""
        diag = np.concatenate([self._lu.U.diagonal(), self._lu.L.diagonal()])
        sign = np.prod(np.sign(diag))
        # permutations' parities
        for perm in (self._lu.perm_r, self._lu.perm_c):
            sign *= _permutation_parity(perm)
        return float(sign)


def _permutation_parity(perm: np.ndarray) -> float:
    """+1 for an even permutation, -1 for an odd one (cycle decomposition)."""
    perm = np.asarray(perm)
    seen = np.zeros(len(perm), dtype=bool)
    parity = 1.0
    for start in range(len(perm)):
        if seen[start]:
            continue
        length, j = 0, start
        while not seen[j]:
            seen[j] = True
            j = perm[j]
            length += 1
        if length % 2 == 0:
            parity = -parity
    return parity
