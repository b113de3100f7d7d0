"""The trial's small system factored in single precision and solved to double precision by
iterative refinement (solver.fem.linalg.SmallSystem): on a condensed system of known solution
(the right-hand side made from it) the solution is reached to double precision's accuracy, and
where the matrix is too ill-conditioned for single precision the system is still solved (in
double precision)."""

import numpy as np
import scipy.sparse as sp

from ibfem.solver.fem.linalg import SmallSystem


def _system(m: int, active: int, spread: float, seed: int = 0):
    """G = S^-1 symmetric positive definite with eigenvalues over ``spread`` decades, Kc a
    symmetric positive semi-definite banded stiffness on the first ``active`` dofs."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((m, m)))
    g = (q * np.logspace(0, -spread, m)) @ q.T
    band = sp.diags([np.full(active - 1, -1.0), np.full(active, 2.0), np.full(active - 1, -1.0)], [-1, 0, 1])
    kc = sp.block_diag([1e3 * band, sp.csr_matrix((m - active, m - active))]).tocsr()
    return np.linalg.inv(g), kc, g


def test_single_precision_factor_refined_to_double():
    schur, kc, g = _system(1500, 1040, 2.0)
    small = SmallSystem(schur, kc, True, g_inverse=g)
    assert small.lu32 is not None  # the active set (1,040 dofs) is factored in single precision
    x = np.random.default_rng(1).standard_normal(1500)
    r = schur @ x + kc @ x
    np.testing.assert_allclose(small.solve(r), x, rtol=0, atol=1e-10 * np.abs(x).max())
    assert small.lu32 is not None  # the refinement converged: no double factor was needed


def test_ill_conditioned_system_falls_back_to_double():
    schur, kc, g = _system(1200, 1100, 11.0, seed=2)
    small = SmallSystem(schur, kc, True, g_inverse=g)
    x = np.random.default_rng(3).standard_normal(1200)
    r = schur @ x + kc @ x
    y = small.solve(r)
    assert small.lu32 is None and small.lu is not None  # refinement stalled: factored in double
    # the residual of the condensed system is at double precision's level
    assert np.abs(schur @ y + kc @ y - r).max() <= 1e-6 * np.abs(r).max()


def test_block_diagonal_product_in_single_precision_slabs():
    """G block-diagonal (two bodies), the active set across both: M = I + G_AA Kc_AA written in
    single precision, M not kept, and the solution still reached to
    double precision (the residual of the refinement formed from G and Kc_AA)."""
    from ibfem.solver.fem.block_diagonal import BlockDiagonal

    sizes, active = (800, 900), 1100  # at most ACTIVE_FRACTION of the dofs
    blocks = [_system(n, n // 2, 2.0, seed=n)[2] for n in sizes]
    positions = [np.arange(sizes[0]), np.arange(sizes[0], sum(sizes))]
    g = BlockDiagonal(blocks, positions)
    dense_g = g.toarray()
    band = sp.diags([np.full(active - 1, -1.0), np.full(active, 2.0), np.full(active - 1, -1.0)], [-1, 0, 1])
    m = sum(sizes)
    start = (m - active) // 2  # the active dofs straddle the two blocks
    kc = sp.block_diag([sp.csr_matrix((start, start)), 1e3 * band,
                        sp.csr_matrix((m - start - active, m - start - active))]).tocsr()
    schur = np.linalg.inv(dense_g)
    small = SmallSystem(schur, kc, True, g_inverse=g)
    assert small.lu32 is not None and small.lu32[0].dtype == np.float32
    assert not hasattr(small, "matrix")  # only the single-precision factor is kept
    # M itself, written slab by slab, against the dense product
    exact = np.eye(active) + dense_g[start:start + active, start:start + active] @ (1e3 * band.toarray())
    built = small._active_matrix(1, np.float32)
    assert np.abs(built - exact).max() <= 1e-6 * np.abs(exact).max()
    x = np.random.default_rng(4).standard_normal(m)
    r = schur @ x + kc @ x
    np.testing.assert_allclose(small.solve(r), x, rtol=0, atol=1e-9 * np.abs(x).max())
    assert small.lu32 is not None
