"""FiPy linear solvers by name (registry), so that scenes, tests and benchmarks can choose.

Only FiPy's SciPy suite installs on this machine from the package registry (PETSc, Trilinos and
pyamgx do not); within it the Krylov solvers take SciPy's Jacobi/ILU or PyAMG's
smoothed-aggregation preconditioner.
"""
from __future__ import annotations

from typing import Callable

import numpy as np
import scipy.sparse as sp
from fipy.solvers import scipy as suite
from fipy.solvers.scipy.preconditioners import ILUPreconditioner
from fipy.solvers.scipy.preconditioners.scipyPreconditioner import ScipyPreconditioner

SUITE = "scipy"


class JacobiPreconditioner(ScipyPreconditioner):
    """Diagonal scaling as a sparse diagonal matrix (FiPy's own Jacobi preconditioner applies
    the diagonal through a sparse direct solve at every Krylov iteration)."""

    def _applyToMatrix(self, matrix):
        diagonal = matrix.diagonal()
        return sp.diags(np.where(diagonal != 0, 1.0 / np.where(diagonal != 0, diagonal, 1), 1.0)
                        ).tocsr(), None


def _amg():
    from fipy.solvers.pyAMG.preconditioners import SmoothedAggregationPreconditioner
    return SmoothedAggregationPreconditioner()


def _krylov(cls, precon: Callable | None):
    def make(tolerance: float, iterations: int):
        return cls(tolerance=tolerance, criterion="RHS", iterations=iterations,
                   precon=precon() if precon else None)
    return make


#: name -> factory(tolerance, iterations) of a FiPy solver
LINEAR_SOLVERS: dict[str, Callable] = {
    "lu": lambda tolerance, iterations: suite.LinearLUSolver(tolerance=tolerance),
    "pcg": _krylov(suite.LinearPCGSolver, None),
    "pcg-jacobi": _krylov(suite.LinearPCGSolver, JacobiPreconditioner),
    "pcg-amg": _krylov(suite.LinearPCGSolver, _amg),
    "bicgstab-jacobi": _krylov(suite.LinearBicgstabSolver, JacobiPreconditioner),
    "bicgstab-ilu": _krylov(suite.LinearBicgstabSolver, ILUPreconditioner),
    "gmres-ilu": _krylov(suite.LinearGMRESSolver, ILUPreconditioner),
    "gmres-amg": _krylov(suite.LinearGMRESSolver, _amg),
}

#: solvers valid for the symmetric pressure equation (PCG needs a symmetric operator)
SYMMETRIC_ONLY = {"pcg", "pcg-jacobi", "pcg-amg"}


def make_solver(name: str, tolerance: float = 1e-10, iterations: int = 2000, *, symmetric: bool):
    """FiPy solver ``name`` from :data:`LINEAR_SOLVERS`; ``symmetric``: the system is."""
    if name not in LINEAR_SOLVERS:
        raise ValueError(f"unknown linear solver {name!r}; allowed: {sorted(LINEAR_SOLVERS)}")
    if name in SYMMETRIC_ONLY and not symmetric:
        raise ValueError(f"linear solver {name!r} needs a symmetric system; for momentum use "
                         f"one of {sorted(set(LINEAR_SOLVERS) - SYMMETRIC_ONLY)}")
    return LINEAR_SOLVERS[name](tolerance, iterations)


def pressure_solver_for(n_cells: int, axisymmetric: bool) -> str:
    """The pressure solver that was fastest on this machine (``benchmarks/fluid_step.py``):
    sparse LU on axisymmetric grids (8k unknowns in 2-D: little fill-in, no iterations);
    Jacobi-preconditioned CG on 3-D grids up to ~40k cells (LU fill-in grows, the Jacobi
    iteration count is still small); smoothed-aggregation AMG beyond (its iteration count stays
    flat as the grid grows, which pays for its setup at every step)."""
    if axisymmetric:
        return "lu"
    return "pcg-jacobi" if n_cells <= 40_000 else "pcg-amg"
