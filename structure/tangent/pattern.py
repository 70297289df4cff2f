"""The block-sparse pattern of a tangent matrix, built once per grid, and the assembly of
element blocks into it.

A term's elements each couple k nodes (``element_nodes`` (m, k) int64, -1 for none); its
Hessian arrives as blocks (m, k, k, 3, 3), block (p, q) of element e the 3 x 3 coupling of
node ``element_nodes[e, p]`` with node ``element_nodes[e, q]``. The pattern is the union of
every term's node pairs in block compressed-row form (SciPy's BSR, blocks of 3 x 3); each
element keeps the slot of each of its pairs in the data array, so that an assembly is one
scatter-add (numba) and no sort or duplicate sum per Newton iteration.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numba import njit

JIT = dict(cache=True, nogil=True)


@njit(**JIT)
def _scatter(data, slots, blocks):
    """data[slots[e, p, q]] += blocks[e, p, q] for every slot >= 0."""
    m, k = slots.shape[0], slots.shape[1]
    for e in range(m):
        for p in range(k):
            for q in range(k):
                s = slots[e, p, q]
                if s < 0:
                    continue
                for r in range(3):
                    for c in range(3):
                        data[s, r, c] += blocks[e, p, q, r, c]


@dataclass(frozen=True)
class BlockPattern:
    """The union of node pairs of some element families over ``n_nodes`` nodes.

    indptr (n + 1,), indices (nnzb,): the block rows' column nodes, sorted; slots: per family
    (m, k, k) int64, the data index of each element pair (-1 where a node is absent).
    """

    n_nodes: int
    indptr: np.ndarray
    indices: np.ndarray
    slots: tuple

    @classmethod
    def build(cls, n_nodes: int, families) -> "BlockPattern":
        """The pattern of ``families``, a sequence of ``element_nodes`` arrays (m, k) int64
        (-1: no node); every node's diagonal block is in it."""
        rows, cols = [np.arange(n_nodes)], [np.arange(n_nodes)]
        for nodes in families:
            nodes = np.asarray(nodes, dtype=np.int64)
            p = np.broadcast_to(nodes[:, :, None], nodes.shape + (nodes.shape[1],))
            q = np.broadcast_to(nodes[:, None, :], p.shape)
            keep = (p >= 0) & (q >= 0)
            rows.append(p[keep])
            cols.append(q[keep])
        row, col = np.concatenate(rows), np.concatenate(cols)
        key = np.unique(row * n_nodes + col)
        row, col = key // n_nodes, key % n_nodes
        indptr = np.zeros(n_nodes + 1, dtype=np.int64)
        np.add.at(indptr, row + 1, 1)
        indptr = np.cumsum(indptr)
        slots = []
        for nodes in families:
            nodes = np.asarray(nodes, dtype=np.int64)
            p = np.broadcast_to(nodes[:, :, None], nodes.shape + (nodes.shape[1],))
            q = np.broadcast_to(nodes[:, None, :], p.shape)
            keep = (p >= 0) & (q >= 0)
            slot = np.full(p.shape, -1, dtype=np.int64)
            slot[keep] = np.searchsorted(key, p[keep] * n_nodes + q[keep])
            slots.append(slot)
        return cls(n_nodes, indptr, col.astype(np.int64), tuple(slots))

    @property
    def n_blocks(self) -> int:
        """Number of 3 x 3 blocks stored."""
        return len(self.indices)

    def zeros(self) -> np.ndarray:
        """A zero data array (nnzb, 3, 3)."""
        return np.zeros((self.n_blocks, 3, 3))

    def matrix(self, data: np.ndarray) -> sp.bsr_matrix:
        """The (3n, 3n) block-sparse matrix of ``data`` (nnzb, 3, 3) (not copied)."""
        n = 3 * self.n_nodes
        return sp.bsr_matrix((data, self.indices, self.indptr), shape=(n, n))


def assemble(pattern: BlockPattern, blocks, data: np.ndarray | None = None) -> np.ndarray:
    """Add each family's element blocks (m, k, k, 3, 3), in the order of the families the
    pattern was built from (None: a family left out), into ``data`` (a new zero array when
    None); returns it."""
    if data is None:
        data = pattern.zeros()
    if len(blocks) != len(pattern.slots):
        raise ValueError(f"{len(blocks)} families of blocks for a pattern of "
                         f"{len(pattern.slots)}")
    for slots, family in zip(pattern.slots, blocks):
        if family is None:
            continue
        family = np.ascontiguousarray(family, dtype=float)
        if family.shape[:3] != slots.shape or family.shape[3:] != (3, 3):
            raise ValueError(f"element blocks of shape {family.shape} for slots "
                             f"{slots.shape}")
        _scatter(data, slots, family)
    return data


@dataclass(frozen=True)
class Tangent:
    """Terms summed with weights, over one pattern built once: each term has
    ``element_nodes`` and ``evaluate(x, hessian) -> (value, gradient (n, 3), blocks)``."""

    terms: tuple
    pattern: BlockPattern

    @classmethod
    def build(cls, n_nodes: int, terms) -> "Tangent":
        terms = tuple(terms)
        return cls(terms, BlockPattern.build(n_nodes, [t.element_nodes for t in terms]))

    def evaluate(self, x: np.ndarray, weights=None, hessian: bool = True):
        """(sum of w_i value_i, gradient (n, 3), matrix (3n, 3n) BSR or None) at ``x``
        (n, 3); ``weights`` one per term (ones when None)."""
        weights = np.ones(len(self.terms)) if weights is None else np.asarray(weights, float)
        if len(weights) != len(self.terms):
            raise ValueError(f"{len(weights)} weights for {len(self.terms)} terms")
        value, grad, families = 0.0, np.zeros((self.pattern.n_nodes, 3)), []
        for w, term in zip(weights, self.terms):
            if w == 0.0:
                families.append(None)
                continue
            v, g, b = term.evaluate(x, hessian)
            value += w * v
            grad += w * g
            families.append(w * np.asarray(b) if hessian else None)
        if not hessian:
            return value, grad, None
        return value, grad, self.pattern.matrix(assemble(self.pattern, families))
