"""The multifrontal Cholesky's dense kernels on fronts larger than their blocks (solver.fem.
_multifrontal_kernels: panels of PANEL columns inside outer blocks of OUTER pivots, BLAS updates
by BLOCK rows accumulated in the front): the partial L D L^T of one front against numpy's
Cholesky, and whole factorisations with a root of several outer blocks against the dense Schur
complement, with negative interior pivots and a failing pivot past the first outer block."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.fem.linalg import single_threaded_blas

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)
kern = mf._kernels()


@pytest.fixture(autouse=True)
def one_blas_thread():
    """The kernels' BLAS calls on one thread, as the contact drivers run them (several OpenBLAS
    threads on a busy machine make these small products many times slower)."""
    with single_threaded_blas():
        yield


def spd(n: int, seed: int) -> np.ndarray:
    a = np.random.default_rng(seed).standard_normal((n, n))
    return a @ a.T + n * np.eye(n)


@pytest.mark.parametrize("f, nc", [(450, 290), (300, 300), (kern.OUTER + 7, kern.OUTER + 1), (330, 60)])
def test_partial_ldlt_of_one_front_against_numpy(f, nc):
    """Pivot rows hold D and L^T (the columns of the dense Cholesky factor over sqrt(D)); the
    update matrix left behind is the Schur complement of the pivots."""
    s = spd(f, seed=f + nc)
    t = s.copy()  # symmetric: row j holds column j of the lower triangle
    assert kern._partial_ldlt(kern.DGEMM, t, nc, f, True) == -1
    c = np.linalg.cholesky(s)
    d = np.diag(c)[:nc] ** 2
    np.testing.assert_allclose(np.diag(t)[:nc], d, rtol=1e-12)
    lower = np.tril(c[:, :nc] / np.sqrt(d)[None, :], -1)
    np.testing.assert_allclose(np.triu(t[:nc], 1).T, lower, rtol=0, atol=1e-12)
    if nc < f:
        schur = s[nc:, nc:] - s[nc:, :nc] @ np.linalg.solve(s[:nc, :nc], s[:nc, nc:])
        np.testing.assert_allclose(np.triu(t[nc:, nc:]), np.triu(schur), rtol=0, atol=1e-11 * np.abs(schur).max())


def test_a_bad_pivot_past_the_first_outer_block_is_named():
    n = kern.OUTER + 150
    k = spd(n, seed=3)
    bad = kern.OUTER + 40
    k[bad, :], k[:, bad] = 0.0, 0.0
    k[bad, bad] = -1.0
    with pytest.raises(mf.NotPositiveDefinite, match=rf"dof {bad} \(of {n}\) is not positive"):
        mf.CholeskyFactor(sp.csr_matrix(k), np.arange(n), 0, definite=True)


def grid3d(k: int, seed: int) -> sp.csr_matrix:
    """An SPD 3-dof-per-node 7-point grid matrix on k^3 nodes, randomly scaled per dof."""
    lap = sp.diags([-np.ones(k - 1), 2 * np.ones(k), -np.ones(k - 1)], [-1, 0, 1])
    eye = sp.eye(k)
    lap3 = sp.kron(sp.kron(lap, eye), eye) + sp.kron(sp.kron(eye, lap), eye) + sp.kron(sp.kron(eye, eye), lap)
    block = np.eye(3) + 0.4 * (np.ones((3, 3)) - np.eye(3))
    m = sp.kron(lap3, block) + 1e-3 * sp.eye(3 * k**3)
    scale = sp.diags(np.random.default_rng(seed).uniform(0.5, 2.0, m.shape[0]))
    return (scale @ m @ scale).tocsr()


def test_a_root_of_several_outer_blocks_against_the_dense_schur_complement():
    """A 3D grid (1,029 dofs) with the dofs of two grid planes condensed (294, more than an
    outer block): the root front and the separators above it take the blocked BLAS path; one
    negative interior pivot (a decoupled dof) is allowed when not definite."""
    k = grid3d(7, seed=5).toarray()
    n = len(k)
    k[7, :], k[:, 7] = 0.0, 0.0
    k[7, 7] = -2.0
    nodes = np.arange(n // 3).reshape(7, 7, 7)
    dofs = (3 * nodes[:, :, 3:5].ravel()[:, None] + np.arange(3)).ravel()
    rest = np.setdiff1d(np.arange(n), dofs)
    order = np.concatenate([np.random.default_rng(6).permutation(rest), dofs])
    factor, schur, g = mf.condensed_cholesky(sp.csr_matrix(k), order, len(dofs))
    assert len(dofs) > kern.OUTER and factor.largest_front > kern.OUTER
    truth = k[np.ix_(dofs, dofs)] - k[np.ix_(dofs, rest)] @ np.linalg.solve(k[np.ix_(rest, rest)], k[np.ix_(rest, dofs)])
    np.testing.assert_allclose(schur.toarray(), truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    np.testing.assert_allclose(g @ truth, np.eye(len(dofs)), rtol=0, atol=1e-9)
    f = np.random.default_rng(7).standard_normal((n, 2))
    x = factor.solve(f)
    assert np.abs(k @ x - f).max() <= 1e-11 * np.abs(k).max() * np.abs(x).max()
