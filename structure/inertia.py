"""The inertia of a symmetric sparse matrix, and on a constraint's tangent space.

SuperLU in symmetric mode (a diagonal pivot order, equal row and column permutations) gives
K = P^T L U P with the signs of U's diagonal those of K's eigenvalues (Sylvester's law of
inertia), so one factorisation counts K's negative eigenvalues. On the tangent space of one
constraint {v . dy = 0} the count is neg(K) - 1 where v . K^-1 v < 0 and neg(K) otherwise
(Haynsworth's inertia additivity on the bordered matrix [[K, v], [v^T, 0]]). Used for the
stability of equilibria under a held volume, and to put an eigensolver's shift below the
spectrum.
"""
from __future__ import annotations

from typing import Optional

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

__all__ = ["factor_symmetric", "negative_eigenvalues", "constrained_negative"]


def factor_symmetric(matrix: sp.spmatrix):
    """(SuperLU of the symmetric ``matrix`` in symmetric mode, the number of its negative
    eigenvalues from the signs of its pivots) (module doc); (None, None) where it is singular,
    and the count None where pivoting was needed (it would not be the inertia)."""
    try:
        lu = splu(sp.csc_matrix(matrix), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options=dict(SymmetricMode=True))
    except RuntimeError:
        return None, None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return lu, None
    pivots = lu.U.diagonal()
    if not np.all(np.isfinite(pivots)) or np.any(pivots == 0):
        return None, None
    return lu, int(np.count_nonzero(pivots < 0))


def negative_eigenvalues(matrix: sp.spmatrix) -> Optional[int]:
    """The number of negative eigenvalues of the symmetric ``matrix`` (:func:`factor_symmetric`),
    or None."""
    return factor_symmetric(matrix)[1]


def constrained_negative(k: sp.spmatrix, v: np.ndarray) -> int:
    """The negative eigenvalues of ``k`` on the tangent space {v . dy = 0} (module doc); -1
    where K is singular or its inertia cannot be read."""
    neg = negative_eigenvalues(k)
    if neg is None:
        return -1
    try:
        kv = splu(sp.csc_matrix(k)).solve(v)
    except RuntimeError:
        return -1
    return neg - 1 if v @ kv < 0 else neg
