"""Tangent stiffness: the energy, gradient and Hessian of every term of the membrane's
potential, element by element, assembled into one sparse matrix whose pattern is built once
per grid.

Each term (:mod:`.membrane`, :mod:`.bending`, :mod:`.load`, :mod:`.inertia`) is a frozen
dataclass with ``element_nodes`` (m, k) int64 (-1: no node, e.g. a clamped edge's fixed
ghost) and ``evaluate(x) -> (energy J, gradient (n, 3) N, blocks (m, k, k, 3, 3) N/m)``;
:class:`.pattern.BlockPattern` adds the blocks into a 3 x 3 block-sparse matrix
(energy -> residual -> tangent, as in FEniCS and CalculiX).
"""
from .pattern import BlockPattern, Tangent, assemble

__all__ = ["BlockPattern", "Tangent", "assemble"]
