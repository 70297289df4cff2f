"""Element Hessians projected to positive semi-definite (projected Newton: Teran et al. 2005,
"Robust quasistatic finite elements and flesh simulation"): each element's block matrix
(3k x 3k) has its negative eigenvalues set to zero, so that the assembled matrix of the
projected terms is positive semi-definite while each element keeps its stable curvature.
The step it gives is a descent direction of the energy wherever the exact tangent's is not,
and far less damped than a uniform shift of the whole matrix."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..newton.system import Linearisation, NewtonModel, tangent_matrix


def project_blocks(blocks: np.ndarray) -> np.ndarray:
    """Element blocks (m, k, k, 3, 3) with each element's (3k, 3k) matrix projected to positive
    semi-definite (a new array)."""
    m, k = blocks.shape[0], blocks.shape[1]
    dense = blocks.transpose(0, 1, 3, 2, 4).reshape(m, 3 * k, 3 * k)
    dense = 0.5 * (dense + dense.transpose(0, 2, 1))
    values, vectors = np.linalg.eigh(dense)
    negative = (values < 0).any(axis=1)
    if negative.any():
        v, w = vectors[negative], np.maximum(values[negative], 0.0)
        dense[negative] = (v * w[:, None, :]) @ v.transpose(0, 2, 1)
    return dense.reshape(m, k, 3, k, 3).transpose(0, 1, 3, 2, 4)


def projected_tangent(model: NewtonModel, lin: Linearisation, x: np.ndarray,
                      projected: tuple) -> object:
    """The tangent at ``x`` (n, 3) m with the element blocks of the terms ``projected``
    (indices into ``model.terms``) made positive semi-definite (3n, 3n) BSR N/m: a term's own
    ``convex_blocks(x)`` where it has them (the bending's Gauss-Newton blocks, no eigenvalue
    problem), else its blocks projected (:func:`project_blocks`)."""
    if lin.blocks is None:
        raise ValueError("the linearisation carries no element blocks (hessian=False)")
    families = list(lin.blocks)
    for i in projected:
        term = model.terms[i]
        if hasattr(term, "convex_blocks"):
            families[i] = term.convex_blocks(x)
        elif families[i] is not None:
            families[i] = project_blocks(families[i])
    matrix = tangent_matrix(model, families)
    return matrix if lin.extra is None else sp.csr_matrix(matrix) + lin.extra
