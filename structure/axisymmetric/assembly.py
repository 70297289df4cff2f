"""Element matrices (m, 8, 8) summed into the sparse matrix of a state's entries, or straight
into that of the free coordinates y (K = T^T H T, :mod:`~structure.axisymmetric.supports`),
through a scatter built once per meridian and support: each element entry's place in the
matrix's CSR data and its weight (T's entries: each row of T has at most one), so that an
assembly is one weighted ``bincount`` into a fixed pattern.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


@dataclass(frozen=True)
class Scatter:
    """source (c,) entries of the flattened element matrices; target (c,) their places in
    the CSR data; weight (c,); indptr and indices, the fixed CSR pattern; shape."""

    source: np.ndarray
    target: np.ndarray
    weight: np.ndarray
    indptr: np.ndarray
    indices: np.ndarray
    shape: tuple

    def matrix(self, element: np.ndarray) -> sp.csr_matrix:
        """The assembled CSR matrix of element matrices ``element`` (m, 8, 8)."""
        data = np.bincount(self.target, self.weight * element.ravel()[self.source],
                           minlength=len(self.indices))
        return sp.csr_matrix((data, self.indices, self.indptr), shape=self.shape)


def scatter(element_dofs: np.ndarray, basis: sp.spmatrix) -> Scatter:
    """The scatter of element matrices on ``element_dofs`` (m, 8) into ``basis``^T H
    ``basis`` (``basis`` (N, k), each row with at most one entry; the identity for the
    matrix of all entries)."""
    basis = sp.csr_matrix(basis)
    if np.any(np.diff(basis.indptr) > 1):
        raise ValueError("a scatter needs a basis with at most one entry per row")
    column = np.full(basis.shape[0], -1)
    value = np.zeros(basis.shape[0])
    rows = np.repeat(np.arange(basis.shape[0]), np.diff(basis.indptr))
    column[rows], value[rows] = basis.indices, basis.data
    m, d = element_dofs.shape
    gi = np.broadcast_to(element_dofs[:, :, None], (m, d, d)).ravel()
    gj = np.broadcast_to(element_dofs[:, None, :], (m, d, d)).ravel()
    kept = (column[gi] >= 0) & (column[gj] >= 0)
    source = np.nonzero(kept)[0]
    a, b = column[gi[source]], column[gj[source]]
    k = basis.shape[1]
    key = a.astype(np.int64) * k + b
    pattern, target = np.unique(key, return_inverse=True)
    pa, pb = pattern // k, pattern % k
    indptr = np.concatenate([[0], np.cumsum(np.bincount(pa, minlength=k))])
    return Scatter(source, target, value[gi[source]] * value[gj[source]], indptr,
                   pb.astype(np.int32), (k, k))
