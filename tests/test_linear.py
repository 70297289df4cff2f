"""The liquid step's linear solvers: FiPy's RHS criterion met by every registered solver, and
kept preconditioners that still meet it on changed matrices and are rebuilt when they stop
paying."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from fluid.linear import LINEAR_SOLVERS, SYMMETRIC_ONLY, make_solver

TOLERANCE = 1e-10


def poisson(n: int, pin: float = 1e-3, scale: np.ndarray | None = None):
    """SPD 7-point Laplacian on an n^3 lattice with a small diagonal pin; ``scale`` (n^3,)
    multiplies the face coefficients cell by cell (a changed interface)."""
    one = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    eye = sp.identity(n)
    a = sp.kron(sp.kron(one, eye), eye) + sp.kron(sp.kron(eye, one), eye) \
        + sp.kron(sp.kron(eye, eye), one)
    if scale is not None:
        s = sp.diags(np.sqrt(scale))
        a = s @ a @ s
    return (a + pin * sp.identity(n**3)).tocsr()


def convection_diffusion(n: int):
    """Nonsymmetric, diagonally dominant (upwind) 1-D operator on n^3 unknowns, like the
    momentum predictor's."""
    m = n**3
    return sp.diags([-1.5 * np.ones(m - 1), 4.0 * np.ones(m), -0.5 * np.ones(m - 1)],
                    [-1, 0, 1]).tocsr()


def _residual(a, x, b):
    return np.linalg.norm(b - a @ x) / np.linalg.norm(b)


@pytest.mark.parametrize("name", sorted(LINEAR_SOLVERS))
def test_every_solver_meets_the_relative_residual(name):
    rng = np.random.default_rng(1)
    symmetric = name in SYMMETRIC_ONLY
    a = poisson(8) if symmetric or name == "lu" else convection_diffusion(8)
    b = rng.normal(size=a.shape[0])
    solver = make_solver(name, TOLERANCE, 2000, symmetric=symmetric or name == "lu")
    x, info = solver.solve(a, b, np.zeros_like(b))
    assert _residual(a, x, b) <= TOLERANCE
    assert info.residual == pytest.approx(_residual(a, x, b), rel=1e-6)


@pytest.mark.parametrize("name", ["pcg-lu", "pcg-amg"])
def test_a_kept_preconditioner_serves_changed_matrices_and_is_rebuilt_when_stale(name):
    rng = np.random.default_rng(2)
    n = 10
    solver = make_solver(name, TOLERANCE, 2000, symmetric=True)
    b = rng.normal(size=n**3)
    first, info = solver.solve(poisson(n), b, np.zeros_like(b))
    assert info.rebuilt and _residual(poisson(n), first, b) <= TOLERANCE
    # a small change (a few cells' coefficients): the kept factors still converge, no rebuild
    scale = np.ones(n**3)
    scale[:20] = 1.3
    changed = poisson(n, scale=scale)
    x, info = solver.solve(changed, b, np.zeros_like(b))
    assert not info.rebuilt and _residual(changed, x, b) <= TOLERANCE
    # a large change: still the tolerance; the preconditioner is rebuilt on the next solves
    far = poisson(n, scale=rng.uniform(0.01, 100.0, n**3))
    rebuilt = []
    for _ in range(3):
        x, info = solver.solve(far, b, np.zeros_like(b))
        assert _residual(far, x, b) <= TOLERANCE
        rebuilt.append(info.rebuilt)
    assert any(rebuilt)


def test_bad_solver_names_are_refused():
    with pytest.raises(ValueError, match="unknown linear solver 'magic'"):
        make_solver("magic", symmetric=True)
    with pytest.raises(ValueError, match="needs a symmetric system"):
        make_solver("pcg-jacobi", symmetric=False)


@pytest.mark.parametrize("name", ["bicgstab-jacobi", "lu", "pcg-jacobi"])
def test_a_diagonal_system_is_divided_not_iterated(name):
    """A kept CSR pattern whose off-diagonal entries are explicit zeros (an inviscid momentum
    predictor without convection) is solved by division: 0 iterations, exact; one non-zero
    off-diagonal entry sends it to the solver."""
    n = 50
    rng = np.random.default_rng(1)
    diagonal = rng.uniform(1.0, 3.0, n)
    rows = np.concatenate([np.arange(n), np.arange(1, n), np.arange(n - 1)])
    cols = np.concatenate([np.arange(n), np.arange(n - 1), np.arange(1, n)])
    values = np.concatenate([diagonal, np.zeros(2 * (n - 1))])
    order = np.lexsort((cols, rows))
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))])
    pattern = sp.csr_matrix((values[order], cols[order], indptr), shape=(n, n))
    assert pattern.nnz == 3 * n - 2  # the zeros are stored
    rhs = rng.normal(size=n)
    solver = make_solver(name, 1e-10, symmetric=True)
    x, info = solver.solve(pattern, rhs, np.zeros(n))
    assert info.iterations == 0 and np.array_equal(x, rhs / diagonal)
    coupled = pattern.copy()
    coupled.data[coupled.indices != np.repeat(np.arange(n), np.diff(coupled.indptr))] = -0.1
    x, info = solver.solve(coupled, rhs, np.zeros(n))
    assert info.iterations > 0 and info.residual <= 1e-10


def _pinned(a, dry: np.ndarray, pin: float = 7.0):
    """``a`` (CSR) with the couplings of ``dry`` (bool) rows and columns set to zero but kept
    stored (as the pressure system keeps the pattern of closed faces) and their diagonal
    ``pin``; also the stored positions (row live, column dry) of the cut couplings."""
    a = a.tocsr().copy()
    row = np.repeat(np.arange(a.shape[0]), np.diff(a.indptr))
    cut = (row != a.indices) & (dry[row] | dry[a.indices])
    a.data[cut] = 0.0
    a.data[(row == a.indices) & dry[row]] = pin
    return a, np.flatnonzero(cut & ~dry[row] & dry[a.indices])


def test_decoupled_rows_are_found_by_their_stored_entries():
    from fluid.linear import decoupled_rows

    a = poisson(4)
    dry = np.zeros(64, dtype=bool)
    dry[:20] = True
    pinned, _ = _pinned(a, dry)
    assert np.count_nonzero(pinned.data == 0.0) > 0  # the cut couplings stay stored, as zeros
    np.testing.assert_array_equal(decoupled_rows(pinned), dry)
    assert decoupled_rows(a) is None  # no row decoupled
    few = np.zeros(64, dtype=bool)
    few[:3] = True  # under DECOUPLED_SHARE of the rows: not worth leaving out
    assert decoupled_rows(_pinned(a, few)[0]) is None


@pytest.mark.parametrize("name", ["pcg-jacobi", "pcg", "bicgstab-jacobi", "gmres-ilu"])
def test_decoupled_rows_left_out_meet_the_whole_systems_criterion(name):
    n = 8
    dry = np.random.default_rng(3).random(n**3) < 0.6  # most cells out of the liquid
    symmetric = name in SYMMETRIC_ONLY
    a, cut = _pinned(poisson(n) if symmetric else convection_diffusion(n), dry)
    if not symmetric:
        # a decoupled row's value feeds the others (no symmetry): moved to their right side
        a.data[cut[:5]] = -0.7
    b = np.random.default_rng(4).random(n**3)
    x, info = make_solver(name, TOLERANCE, symmetric=symmetric).solve(a, b, np.zeros(n**3))
    assert info.residual <= TOLERANCE and _residual(a, x, b) <= TOLERANCE
    np.testing.assert_allclose(x, sp.linalg.spsolve(a.tocsc(), b), rtol=1e-7, atol=1e-12)
    np.testing.assert_array_equal(x[dry], b[dry] / 7.0)  # divided, not iterated


def test_the_compiled_jacobi_cg_takes_scipys_iterations():
    # the same iteration as SciPy's cg with the inverse diagonal as preconditioner: the same
    # number of iterations to the criterion and the same answer to round-off
    import scipy.sparse.linalg as sla

    from fluid.linear import JacobiCG

    scale = np.random.default_rng(5).uniform(0.1, 10.0, 12**3)
    a = poisson(12, scale=scale)
    b = np.random.default_rng(6).random(12**3)
    inverse = 1.0 / a.diagonal()
    count = [0]
    reference, info = sla.cg(a, b, rtol=TOLERANCE, atol=0.0,
                             M=sla.LinearOperator(a.shape, matvec=lambda v: inverse * v),
                             callback=lambda _: count.__setitem__(0, count[0] + 1))
    assert info == 0
    x, ours = JacobiCG(TOLERANCE, 2000).solve(a, b, np.zeros(12**3))
    assert abs(ours.iterations - count[0]) <= 1 and count[0] > 50
    np.testing.assert_allclose(x, reference, rtol=1e-8)
    assert ours.residual <= TOLERANCE


def test_the_compiled_jacobi_bicgstab_takes_scipys_iterations():
    # the same steps as SciPy's bicgstab with the inverse diagonal as preconditioner: the
    # same number of iterations to the criterion and the same answer to round-off, from a
    # zero and from a non-zero start; b = 0 gives x = 0 as SciPy's does
    import scipy.sparse.linalg as sla

    from fluid.linear import JacobiBiCGSTAB

    n = 12
    rng = np.random.default_rng(7)
    upwind = sp.kron(sp.kron(sp.diags([-np.ones(n - 1), np.ones(n)], [-1, 0]),
                             sp.identity(n)), sp.identity(n))
    a = (poisson(n, scale=rng.uniform(0.1, 10.0, n**3)) + 2.0 * upwind).tocsr()
    b = rng.random(n**3)
    inverse = 1.0 / a.diagonal()
    for start in (np.zeros(n**3), rng.normal(size=n**3)):
        count = [0]
        reference, info = sla.bicgstab(
            a, b, x0=start.copy(), rtol=TOLERANCE, atol=0.0,
            M=sla.LinearOperator(a.shape, matvec=lambda v: inverse * v),
            callback=lambda _: count.__setitem__(0, count[0] + 1))
        assert info == 0
        x, ours = JacobiBiCGSTAB(TOLERANCE, 2000).solve(a, b, start)
        assert abs(ours.iterations - count[0]) <= 1 and count[0] > 20
        np.testing.assert_allclose(x, reference, rtol=1e-8)
        assert ours.residual <= TOLERANCE
    x, _ = JacobiBiCGSTAB(TOLERANCE, 2000).solve(a, np.zeros(n**3), np.ones(n**3))
    assert not x.any()


def test_the_inverse_diagonal_sums_duplicate_entries_as_scipy_does():
    # a CSR matrix not in canonical form: row 0 stores its diagonal twice, row 1 has a zero
    # diagonal (its inverse is taken as 1), row 2 stores an explicit zero off the diagonal
    from fluid.linear import _inverse_diagonal, decoupled_rows

    indptr = np.array([0, 3, 4, 6])
    indices = np.array([0, 0, 2, 1, 2, 0])
    data = np.array([2.0, 0.5, -1.0, 0.0, 4.0, 0.0])
    m = sp.csr_matrix((data, indices, indptr), shape=(3, 3))
    assert not m.has_canonical_format
    diagonal = m.diagonal()
    np.testing.assert_array_equal(diagonal, [2.5, 0.0, 4.0])
    np.testing.assert_array_equal(_inverse_diagonal(m), [1 / 2.5, 1.0, 0.25])
    np.testing.assert_array_equal(decoupled_rows(m), [False, False, True])
