"""Linear solvers by name (registry) for the systems the liquid step assembles.

Every solver takes a SciPy CSR matrix, a right-hand side and a start vector and stops on
FiPy's ``RHS`` criterion, ||b - A x|| <= tolerance ||b|| (FiPy's SciPy suite passes the same
relative tolerance to the same SciPy Krylov functions). ``pcg-jacobi`` runs SciPy's ``cg``
iteration compiled (:class:`JacobiCG`: SciPy's Python loop costs about 50 us per iteration
whatever the size), and the solvers that build their preconditioner for each solve leave
out the rows that hold only their diagonal (:func:`decoupled_rows`: the pinned cells
outside the liquid). Only SciPy and PyAMG install on this machine from the package registry
(PETSc, Trilinos and pyamgx do not).

A preconditioner built from one step's matrix stays valid for the next steps' matrices, which
differ only where the moving interface changed the coefficients: the ``pcg-amg`` and
``pcg-lu`` solvers keep their smoothed-aggregation hierarchy or sparse LU factors and rebuild
them only when the iteration count has grown ``REBUILD_GROWTH`` times past the count just after
a rebuild (or the solve fails to converge, which then repeats with fresh ones). The answer
meets the same tolerance either way; only the work changes.

BLAS threads: numpy and SciPy each load an OpenBLAS with a thread per core, and on two cores
the two pools fight over vector reductions (10-30x slower Krylov solves after a sparse LU ran in
the same process). :func:`single_blas_thread` limits both pools to one thread; the liquid step
runs inside it.
"""
from __future__ import annotations

import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from numba import njit

#: a kept preconditioner is rebuilt once a solve needs this many times the iterations it
#: needed right after the last rebuild (and at least ``REBUILD_MIN_ITERATIONS`` more)
REBUILD_GROWTH = 2.0
REBUILD_MIN_ITERATIONS = 4


class LinearSolveWarning(UserWarning):
    """A linear solve ended above its tolerance."""


@dataclass(frozen=True)
class SolveInfo:
    """iterations: Krylov iterations (refinement sweeps for LU); residual: ||b - A x|| / ||b||
    at the end (0 for b = 0); tolerance: the relative tolerance asked for; rebuilt: the
    preconditioner was (re)built for this solve."""

    iterations: int
    residual: float
    tolerance: float
    rebuilt: bool = False


_controller = None


@contextmanager
def single_blas_thread():
    """Run the block with one OpenBLAS/OpenMP thread in every loaded pool (see module doc)."""
    global _controller
    if _controller is None:
        from threadpoolctl import ThreadpoolController
        _controller = ThreadpoolController()
    with _controller.limit(limits=1):
        yield


def _relative_residual(matrix, x, rhs) -> float:
    norm = float(np.linalg.norm(rhs))
    return float(np.linalg.norm(rhs - matrix @ x)) / norm if norm > 0 else 0.0


def _diagonal_solve(matrix, rhs, tolerance: float):
    """x = b / diag(A) and its :class:`SolveInfo` (0 iterations) when every off-diagonal
    entry of ``matrix`` is zero (the explicit zeros of a kept pattern included: an inviscid
    momentum predictor without convection is its transient term and its pins), else None."""
    m = matrix.tocsr()
    # canonical (no duplicate entries): every stored non-zero is on the diagonal exactly when
    # the two counts agree and no diagonal entry is zero
    if not (m.has_canonical_format and np.count_nonzero(m.data) == m.shape[0]):
        return None
    diagonal = m.diagonal()
    if not np.all(diagonal != 0):
        return None
    x = rhs / diagonal
    return x, SolveInfo(0, _relative_residual(matrix, x, rhs), tolerance)


# ---------------------------------------------------------------- preconditioners


def _inverse_diagonal(matrix) -> np.ndarray:
    """1 / diag(A) (n,), 1 where the diagonal is zero."""
    if sp.issparse(matrix) and matrix.format == "csr":
        return _csr_inverse_diagonal(matrix.indptr, matrix.indices, matrix.data,
                                     matrix.shape[0])
    diagonal = matrix.diagonal()
    return np.where(diagonal != 0, 1.0 / np.where(diagonal != 0, diagonal, 1.0), 1.0)


@njit(cache=True, nogil=True)
def _csr_inverse_diagonal(indptr, indices, data, n):
    """1 / diag(A) (n,) of a CSR matrix (a row's stored diagonal entries summed, as
    ``diagonal()`` does), 1 where the diagonal is zero."""
    inverse = np.ones(n)
    for i in range(n):
        diagonal = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            if indices[k] == i:
                diagonal += data[k]
        if diagonal != 0.0:
            inverse[i] = 1.0 / diagonal
    return inverse


def _jacobi(matrix):
    # applied as a product with the inverse diagonal: the same numbers as the diagonal
    # matrix's product (one term per row), without building that matrix at every solve
    inverse = _inverse_diagonal(matrix)
    return sla.LinearOperator(matrix.shape, matvec=lambda x: inverse * np.ravel(x),
                              dtype=inverse.dtype)


def _ilu(matrix):
    factors = sla.spilu(matrix.tocsc())
    return sla.LinearOperator(matrix.shape, factors.solve)


def _amg(matrix):
    import pyamg
    return pyamg.smoothed_aggregation_solver(matrix.tocsr()).aspreconditioner(cycle="V")


def _lu(matrix):
    factors = sla.splu(matrix.tocsc())
    return sla.LinearOperator(matrix.shape, factors.solve)


#: preconditioner name -> (build from a matrix, worth keeping across steps)
PRECONDITIONERS: dict[str, tuple[Callable, bool]] = {
    "none": (lambda matrix: None, False),
    "jacobi": (_jacobi, False),
    "ilu": (_ilu, False),
    "amg": (_amg, True),
    "lu": (_lu, True),
}


#: the share of decoupled rows (diagonal only) from which a Krylov solve leaves them out
DECOUPLED_SHARE = 0.1


def decoupled_rows(matrix) -> np.ndarray | None:
    """bool (n,): the rows of the CSR ``matrix`` whose every stored off-diagonal entry is
    zero and whose diagonal is not; None when they are fewer than ``DECOUPLED_SHARE`` of
    the rows (too few to be worth leaving out) or the matrix is not CSR."""
    if not sp.isspmatrix_csr(matrix) and not isinstance(matrix, sp.csr_array):
        return None
    n = matrix.shape[0]
    known = _decoupled(matrix.indptr, matrix.indices, matrix.data, n)
    return known if known.sum() >= DECOUPLED_SHARE * n else None


@njit(cache=True, nogil=True)
def _decoupled(indptr, indices, data, n):
    """bool (n,): the CSR rows with no non-zero stored off-diagonal entry and a non-zero
    diagonal (its stored entries summed, as ``diagonal()`` does)."""
    known = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        coupled = False
        diagonal = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            if indices[k] == i:
                diagonal += data[k]
            elif data[k] != 0.0:
                coupled = True
        known[i] = not coupled and diagonal != 0.0
    return known


class KrylovSolver:
    """A SciPy Krylov method with a preconditioner (kept across solves where that pays)."""

    def __init__(self, method: Callable, preconditioner: str, tolerance: float,
                 iterations: int):
        self.method = method
        self.build, self.keep = PRECONDITIONERS[preconditioner]
        self.tolerance = tolerance
        self.iterations = iterations
        self._kept = None
        self._kept_shape = None
        self._iterations_at_build = 0
        self._stale = True

    def _preconditioner(self, matrix):
        if not self.keep:
            return self.build(matrix), True
        if self._stale or self._kept_shape != matrix.shape:
            self._kept = self.build(matrix)
            self._kept_shape = matrix.shape
            self._stale = False
            return self._kept, True
        return self._kept, False

    def _run(self, matrix, rhs, x0, preconditioner, atol=None):
        """The Krylov method on ``matrix``; it stops at ||b - A x|| <= tolerance ||b||, or
        at ``atol`` (absolute) where given."""
        count = [0]

        def callback(_):
            count[0] += 1

        extra = {"callback_type": "pr_norm"} if self.method is sla.gmres else {}
        rtol, atol = (self.tolerance, 0.0) if atol is None else (0.0, atol)
        x, info = self.method(matrix, rhs, x0=x0, rtol=rtol, atol=atol,
                              maxiter=self.iterations, M=preconditioner, callback=callback,
                              **extra)
        return x, info, count[0]

    def _solve_coupled_rows(self, matrix, rhs, x0, known):
        """The solve with the rows ``known`` (bool (n,): no off-diagonal entry, a non-zero
        diagonal) divided out first and the Krylov method run on the other rows alone, to
        the whole system's criterion; None where the method did not converge (the caller
        then solves the whole system)."""
        live = ~known
        x = np.empty(len(rhs))
        x[known] = rhs[known] / matrix.diagonal()[known]
        rows = matrix[live]
        rest = rhs[live] - rows[:, known] @ x[known]
        sub = rows[:, live]
        target = self.tolerance * float(np.linalg.norm(rhs))
        x[live], info, count = self._run(sub, rest, np.asarray(x0)[live],
                                         self.build(sub), atol=target)
        if info != 0:
            return None
        return x, SolveInfo(count, _relative_residual(matrix, x, rhs), self.tolerance, True)

    def solve(self, matrix, rhs, x0) -> tuple[np.ndarray, SolveInfo]:
        """x with ||b - A x|| <= tolerance ||b||, started from ``x0`` (a diagonal matrix:
        divided, no iteration). Where a preconditioner is built for each solve anyway and
        at least ``DECOUPLED_SHARE`` of the rows hold only their diagonal (the cells outside
        the liquid, pinned), those rows are divided out and the method runs on the others
        (:func:`decoupled_rows`): the same criterion on fewer unknowns."""
        diagonal = _diagonal_solve(matrix, rhs, self.tolerance)
        if diagonal is not None:
            return diagonal
        if not self.keep and np.any(rhs):
            known = decoupled_rows(matrix)
            if known is not None:
                reduced = self._solve_coupled_rows(matrix, rhs, x0, known)
                if reduced is not None:
                    return reduced
        preconditioner, rebuilt = self._preconditioner(matrix)
        x, info, count = self._run(matrix, rhs, x0, preconditioner)
        if info != 0 and self.keep and not rebuilt:
            self._stale = True
            preconditioner, rebuilt = self._preconditioner(matrix)
            x, info, count = self._run(matrix, rhs, x0, preconditioner)
        if self.keep:
            if rebuilt:
                self._iterations_at_build = count
            elif count > max(REBUILD_GROWTH * self._iterations_at_build,
                             self._iterations_at_build + REBUILD_MIN_ITERATIONS):
                self._stale = True
        residual = _relative_residual(matrix, x, rhs)
        if info != 0 and residual > self.tolerance:
            # breakdown or no convergence: the direct solve is the fallback
            x, more = DirectSolver(self.tolerance).solve(matrix, rhs, x)
            residual, count = more.residual, count + more.iterations
        return x, SolveInfo(count, residual, self.tolerance, rebuilt)


@njit(cache=True, nogil=True)
def _jacobi_cg(indptr, indices, data, b, x, inverse, target, maxiter):
    """Conjugate gradients preconditioned by ``inverse`` (the inverse diagonal) on the CSR
    matrix (indptr, indices, data), in place on x, until the recurred residual's norm is at
    most ``target``: (iterations, converged)."""
    n = b.shape[0]
    r = np.empty(n)
    z = np.empty(n)
    p = np.empty(n)
    q = np.empty(n)
    rr = 0.0
    for i in range(n):
        s = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            s += data[k] * x[indices[k]]
        r[i] = b[i] - s
        rr += r[i] * r[i]
    if np.sqrt(rr) <= target:
        return 0, True
    rho = 0.0
    for i in range(n):
        z[i] = inverse[i] * r[i]
        p[i] = z[i]
        rho += r[i] * z[i]
    for iteration in range(1, maxiter + 1):
        pq = 0.0
        for i in range(n):
            s = 0.0
            for k in range(indptr[i], indptr[i + 1]):
                s += data[k] * p[indices[k]]
            q[i] = s
            pq += p[i] * s
        if pq == 0.0:
            return iteration, False
        alpha = rho / pq
        rr = 0.0
        for i in range(n):
            x[i] += alpha * p[i]
            r[i] -= alpha * q[i]
            rr += r[i] * r[i]
        if np.sqrt(rr) <= target:
            return iteration, True
        rho_new = 0.0
        for i in range(n):
            z[i] = inverse[i] * r[i]
            rho_new += r[i] * z[i]
        if rho == 0.0:
            return iteration, False
        beta = rho_new / rho
        rho = rho_new
        for i in range(n):
            p[i] = z[i] + beta * p[i]
    return maxiter, False


class JacobiCG(KrylovSolver):
    """Conjugate gradients preconditioned by the diagonal, compiled (:func:`_jacobi_cg`):
    SciPy's ``cg`` with a Jacobi preconditioner does the same iteration but spends about
    50 us per iteration in Python whatever the size, which on a 16^3 tank's pressure
    system (100 iterations on 500-2,000 liquid cells) is most of the solve."""

    def __init__(self, tolerance: float, iterations: int):
        super().__init__(sla.cg, "none", tolerance, iterations)

    def _run(self, matrix, rhs, x0, preconditioner, atol=None):
        m = _csr_canonical(matrix)
        rhs = np.ascontiguousarray(rhs, dtype=float)
        target = self.tolerance * float(np.linalg.norm(rhs)) if atol is None else atol
        inverse = _inverse_diagonal(m)
        x = np.array(x0, dtype=float)
        count, converged = _jacobi_cg(m.indptr, m.indices, m.data, rhs, x, inverse, target,
                                      self.iterations)
        return x, 0 if converged else 1, count


@njit(cache=True, nogil=True)
def _csr_product(indptr, indices, data, x, out):
    """out = A x for the CSR matrix (indptr, indices, data)."""
    for i in range(out.shape[0]):
        s = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            s += data[k] * x[indices[k]]
        out[i] = s


@njit(cache=True, nogil=True)
def _jacobi_bicgstab(indptr, indices, data, b, x, inverse, target, maxiter):
    """BiCGSTAB right-preconditioned by ``inverse`` (the inverse diagonal) on the CSR matrix
    (indptr, indices, data), in place on x, step for step as SciPy's ``bicgstab`` (its
    breakdown tests included) until the residual's norm is below ``target``: (iterations,
    status), status 0 converged, -10 / -11 a breakdown, 1 not converged in ``maxiter``;
    iterations counts the full ones, as SciPy's callback does."""
    n = b.shape[0]
    r = np.empty(n)
    rtilde = np.empty(n)
    p = np.zeros(n)
    v = np.zeros(n)
    s = np.empty(n)
    phat = np.empty(n)
    shat = np.empty(n)
    t = np.empty(n)
    _csr_product(indptr, indices, data, x, r)
    for i in range(n):
        r[i] = b[i] - r[i]
        rtilde[i] = r[i]
    tiny = np.finfo(np.float64).eps ** 2
    rho_prev, omega, alpha = 1.0, 1.0, 1.0
    for iteration in range(maxiter):
        if np.sqrt(np.dot(r, r)) < target:
            return iteration, 0
        rho = np.dot(rtilde, r)
        if abs(rho) < tiny:
            return iteration, -10
        if iteration > 0:
            if abs(omega) < tiny:
                return iteration, -11
            beta = (rho / rho_prev) * (alpha / omega)
            for i in range(n):
                p[i] = (p[i] - omega * v[i]) * beta + r[i]
        else:
            for i in range(n):
                p[i] = r[i]
        for i in range(n):
            phat[i] = inverse[i] * p[i]
        _csr_product(indptr, indices, data, phat, v)
        rv = np.dot(rtilde, v)
        if rv == 0.0:
            return iteration, -11
        alpha = rho / rv
        for i in range(n):
            r[i] -= alpha * v[i]
            s[i] = r[i]
        if np.sqrt(np.dot(s, s)) < target:
            for i in range(n):
                x[i] += alpha * phat[i]
            return iteration, 0
        for i in range(n):
            shat[i] = inverse[i] * s[i]
        _csr_product(indptr, indices, data, shat, t)
        omega = np.dot(t, s) / np.dot(t, t)
        for i in range(n):
            x[i] += alpha * phat[i]
            x[i] += omega * shat[i]
            r[i] -= omega * t[i]
        rho_prev = rho
    return maxiter, 1


def _csr_canonical(matrix):
    """``matrix`` as CSR with summed duplicates (on a copy: the caller's stays as given)."""
    if sp.issparse(matrix) and matrix.format == "csr" and matrix.has_canonical_format:
        return matrix
    m = sp.csr_matrix(matrix)
    if not m.has_canonical_format:
        m = m.copy()
        m.sum_duplicates()
    return m


class JacobiBiCGSTAB(KrylovSolver):
    """BiCGSTAB preconditioned by the diagonal, compiled (:func:`_jacobi_bicgstab`): SciPy's
    ``bicgstab`` with a Jacobi preconditioner does the same steps but spends about 1 ms of
    Python per solve whatever the size, where a liquid step's momentum solve (three per step,
    one or two iterations each on the diagonally dominant system) needs tens of
    microseconds. The same criterion and the same operations in the same order (the dot
    products by BLAS, as NumPy's): here its answers equal SciPy's bit for bit."""

    def __init__(self, tolerance: float, iterations: int):
        super().__init__(sla.bicgstab, "none", tolerance, iterations)

    def _run(self, matrix, rhs, x0, preconditioner, atol=None):
        m = _csr_canonical(matrix)
        rhs = np.ascontiguousarray(rhs, dtype=float)
        norm = float(np.linalg.norm(rhs))
        if norm == 0.0:  # as SciPy: b = 0 gives x = 0
            return np.zeros_like(rhs), 0, 0
        target = self.tolerance * norm if atol is None else max(atol, 0.0)
        x = np.array(x0, dtype=float)
        count, status = _jacobi_bicgstab(m.indptr, m.indices, m.data, rhs, x,
                                         _inverse_diagonal(m), target, self.iterations)
        return x, status, count


class DirectSolver:
    """Sparse LU (SuperLU) of the matrix scaled by its largest diagonal entry, with iterative
    refinement until the tolerance holds (at most ``REFINEMENTS`` sweeps), as FiPy's
    ``LinearLUSolver`` does."""

    REFINEMENTS = 10

    def __init__(self, tolerance: float):
        self.tolerance = tolerance

    def solve(self, matrix, rhs, x0) -> tuple[np.ndarray, SolveInfo]:
        diagonal = _diagonal_solve(matrix, rhs, self.tolerance)
        if diagonal is not None:
            return diagonal
        scale = 1.0 / np.max(np.abs(matrix.diagonal()))
        a = (matrix * scale).tocsc()
        b = rhs * scale
        factors = sla.splu(a)
        x = np.array(x0, dtype=float)
        target = self.tolerance * np.linalg.norm(b)
        sweeps = 0
        for sweeps in range(1, self.REFINEMENTS + 1):
            residual = a @ x - b
            if np.linalg.norm(residual) <= target:
                break
            x -= factors.solve(residual)
        return x, SolveInfo(sweeps, _relative_residual(matrix, x, rhs), self.tolerance, True)


def _krylov(method, preconditioner):
    return lambda tolerance, iterations: KrylovSolver(method, preconditioner, tolerance,
                                                      iterations)


#: name -> factory(tolerance, iterations) of a solver with ``solve(matrix, rhs, x0)``
LINEAR_SOLVERS: dict[str, Callable] = {
    "lu": lambda tolerance, iterations: DirectSolver(tolerance),
    "pcg": _krylov(sla.cg, "none"),
    "pcg-jacobi": lambda tolerance, iterations: JacobiCG(tolerance, iterations),
    "pcg-amg": _krylov(sla.cg, "amg"),
    "pcg-lu": _krylov(sla.cg, "lu"),
    "bicgstab-jacobi": lambda tolerance, iterations: JacobiBiCGSTAB(tolerance, iterations),
    "bicgstab-ilu": _krylov(sla.bicgstab, "ilu"),
    "gmres-ilu": _krylov(sla.gmres, "ilu"),
    "gmres-amg": _krylov(sla.gmres, "amg"),
}

#: solvers valid for the symmetric pressure equation only (CG needs a symmetric operator)
SYMMETRIC_ONLY = {"pcg", "pcg-jacobi", "pcg-amg", "pcg-lu"}


def make_solver(name: str, tolerance: float = 1e-10, iterations: int = 2000, *, symmetric: bool):
    """Solver ``name`` from :data:`LINEAR_SOLVERS`; ``symmetric``: the system is."""
    if name not in LINEAR_SOLVERS:
        raise ValueError(f"unknown linear solver {name!r}; allowed: {sorted(LINEAR_SOLVERS)}")
    if name in SYMMETRIC_ONLY and not symmetric:
        raise ValueError(f"linear solver {name!r} needs a symmetric system; for momentum use "
                         f"one of {sorted(set(LINEAR_SOLVERS) - SYMMETRIC_ONLY)}")
    return LINEAR_SOLVERS[name](tolerance, iterations)


def warn_if_unconverged(info: SolveInfo, what: str) -> None:
    """A :class:`LinearSolveWarning` naming ``what`` when the residual exceeds the tolerance."""
    if info.residual > info.tolerance:
        warnings.warn(f"{what}: relative residual {info.residual:.2e} above the tolerance "
                      f"{info.tolerance:.0e} after {info.iterations} iterations",
                      LinearSolveWarning, stacklevel=3)


def pressure_solver_for(n_cells: int, axisymmetric: bool) -> str:
    """The pressure solver that was fastest on this machine (``benchmarks/fluid_step.py``,
    filling tank; ``benchmarks/coupled_fill.py``): on axisymmetric grids CG preconditioned by
    a kept sparse LU (little fill-in in 2-D, 1-9 iterations with factors from earlier steps);
    on 3-D grids up to ~40k cells Jacobi-preconditioned CG (LU fill-in grows in 3-D; ~100-200
    cheap iterations); beyond, CG with a kept smoothed-aggregation hierarchy (its iteration
    count stays near 15 as the grid grows)."""
    if axisymmetric:
        return "pcg-lu"
    return "pcg-jacobi" if n_cells <= 40_000 else "pcg-amg"
