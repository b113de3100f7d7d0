"""SuperLU's L U of a symmetric matrix kept as L D L^T (solver.fem.linalg.SymmetricFactor: only L
and D after the factorisation) solves as the matrix itself does (residuals at round-off, against
a dense solve), for one right-hand side and several; and the condensed factorisation's choice
between it and the multifrontal Cholesky by the entries of K0 and their density."""

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.fem import linalg


def _spd(n: int, seed: int) -> sp.csc_matrix:
    """A sparse symmetric positive definite matrix (a shifted graph Laplacian, random weights)."""
    rng = np.random.default_rng(seed)
    a = sp.random(n, n, density=8.0 / n, random_state=rng, format="csr")
    a = a + a.T
    return (sp.diags(np.asarray(abs(a).sum(axis=1)).ravel() + 1.0) - a).tocsc()


@pytest.mark.parametrize("public", [False, True])
@pytest.mark.parametrize("columns", [None, 3])
def test_l_d_lt_from_superlu_solves_the_matrix(columns, public, monkeypatch):
    if public:  # SuperLU's triangular solve not at hand: scipy's spsolve_triangular
        monkeypatch.setattr(linalg, "_superlu_triangular_solve", lambda: None)
    k = _spd(300, 2)
    order = np.random.default_rng(5).permutation(300)
    factor, schur, inverse = linalg._superlu_condensed(k, order, 20)
    assert isinstance(factor.lu, linalg.SymmetricFactor)
    f = np.random.default_rng(7).standard_normal(300 if columns is None else (300, columns))
    u = factor.solve(f)
    dense = np.linalg.solve(k.toarray(), f)
    np.testing.assert_allclose(u, dense, rtol=0, atol=1e-12 * np.abs(dense).max())
    # the condensed blocks: S of the last 20 dofs of the order, G = S^-1
    last, rest = order[-20:], order[:-20]
    kd = k.toarray()
    coupling = kd[np.ix_(rest, last)]
    s = kd[np.ix_(last, last)] - coupling.T @ np.linalg.solve(kd[np.ix_(rest, rest)], coupling)
    np.testing.assert_allclose(schur, s, rtol=0, atol=1e-12 * np.abs(s).max())
    np.testing.assert_allclose(inverse @ s, np.eye(20), rtol=0, atol=1e-10)


def test_the_cholesky_starts_later_for_dense_rows(monkeypatch):
    from ibfem.solver.fem import multifrontal

    monkeypatch.setattr(multifrontal, "available", lambda: True)
    monkeypatch.delenv("IBFEM_CONDENSED_FACTOR", raising=False)
    n = linalg.CHOLESKY_NONZEROS
    sparse_rows, dense_rows = n // 20, n // (2 * linalg.DENSE_ROWS)  # 20 and 80 entries a row
    assert linalg._condensed_choice(n, sparse_rows) == "auto"
    assert linalg._condensed_choice(n, dense_rows) == "superlu"
    assert linalg._condensed_choice(int(linalg.DENSE_ROWS_FACTOR * n), dense_rows) == "auto"
    assert linalg._condensed_choice(n) == "auto"  # rows unknown (the plain solve): as before
