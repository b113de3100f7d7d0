"""The condensed factorisation of two bodies that K0 does not couple (solver.fem.block_diagonal):
each body factored on its own, S and G block diagonal. Checked against dense truth on a
block-diagonal K0 of two elasticity-like grid matrices of different sizes: the Schur complement
of the contact dofs (dense formula), G S = I, K0 solves, and the condensed contact system with a
contact block that couples the two bodies (a dense solve of (S + Kc) x = r)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.fem import linalg
from ibfem.solver.fem.block_diagonal import BlockDiagonal, uncoupled_groups


def elasticity_like(shape: tuple[int, int, int], seed: int) -> sp.csr_matrix:
    """SPD: the 3D grid Laplacian coupled across a node's 3 dofs, randomly scaled per dof."""
    lap = [sp.diags([-np.ones(k - 1), 2 * np.ones(k), -np.ones(k - 1)], [-1, 0, 1]) for k in shape]
    eye = [sp.eye(k) for k in shape]
    grid = (sp.kron(sp.kron(lap[0], eye[1]), eye[2]) + sp.kron(sp.kron(eye[0], lap[1]), eye[2])
            + sp.kron(sp.kron(eye[0], eye[1]), lap[2]))
    k = sp.kron(grid, np.eye(3) + 0.4 * (np.ones((3, 3)) - np.eye(3))) + 1e-3 * sp.eye(3 * grid.shape[0])
    scale = sp.diags(np.random.default_rng(seed).uniform(0.5, 2.0, k.shape[0]))
    return (scale @ k @ scale).tocsr()


def dense_schur(k: np.ndarray, interior: np.ndarray, contact: np.ndarray) -> np.ndarray:
    kii = k[np.ix_(interior, interior)]
    return k[np.ix_(contact, contact)] - k[np.ix_(contact, interior)] @ np.linalg.solve(kii, k[np.ix_(interior, contact)])


def two_bodies():
    k = sp.block_diag([elasticity_like((6, 5, 4), seed=1), elasticity_like((5, 5, 5), seed=2)], format="csr")
    n1 = 6 * 5 * 4 * 3
    rng = np.random.default_rng(3)
    dofs = np.sort(np.concatenate([rng.choice(n1, 40, replace=False), n1 + rng.choice(k.shape[0] - n1, 30, replace=False)]))
    return k, dofs, n1


@pytest.mark.parametrize("backend", ["superlu", "cholesky"])
def test_each_body_factored_alone_gives_the_schur_complement_and_its_inverse(monkeypatch, backend):
    if backend == "cholesky":
        mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
        if not mf.available():
            pytest.skip("the compiled kernels (numba) are not available")
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", backend)
    k, dofs, n1 = two_bodies()
    groups = uncoupled_groups(k, dofs)
    assert groups is not None and np.array_equal(groups, np.arange(k.shape[0]) >= n1)
    factor, schur, g = linalg.condensed_factor(k, dofs, linalg.metis_order(k, 3))
    assert isinstance(schur, BlockDiagonal) and isinstance(g, BlockDiagonal)
    kd = k.toarray()
    truth = dense_schur(kd, np.setdiff1d(np.arange(k.shape[0]), dofs), dofs)
    s = np.asarray(schur)
    np.testing.assert_allclose(s, truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    eye = np.eye(len(dofs))
    np.testing.assert_allclose(schur @ eye, truth, rtol=0, atol=1e-10 * np.abs(truth).max())  # the products
    np.testing.assert_allclose(g @ truth, eye, rtol=0, atol=1e-9)
    f = np.random.default_rng(4).standard_normal(k.shape[0])
    u = factor.solve(f)
    assert np.abs(kd @ u - f).max() <= 1e-11 * np.abs(f).max()
    # the condensed contact system with a contact block coupling both bodies' dofs
    rng = np.random.default_rng(5)
    active = np.sort(np.concatenate([rng.choice(40, 8, replace=False), 40 + rng.choice(30, 6, replace=False)]))
    block = rng.standard_normal((len(active), len(active)))
    kc = np.zeros((len(dofs), len(dofs)))
    kc[np.ix_(active, active)] = 1e3 * np.abs(truth).max() * (block @ block.T) / len(active)
    r = rng.standard_normal(len(dofs))
    exact = np.linalg.solve(truth + kc, r)
    for system in (linalg.SmallSystem(schur, sp.csr_matrix(kc), True, g), linalg.SmallSystem(schur, sp.csr_matrix(kc), True)):
        np.testing.assert_allclose(system.solve(r), exact, rtol=0, atol=1e-9 * np.abs(exact).max())


def test_a_coupled_matrix_is_factored_as_a_whole():
    k, dofs, n1 = two_bodies()
    coupled = (k + sp.csr_matrix(([1e-3, 1e-3], ([0, n1], [n1, 0])), shape=k.shape)).tocsr()
    assert uncoupled_groups(coupled, dofs) is None
    # dofs in one body only: one group (the other body joins it)
    assert uncoupled_groups(k, dofs[dofs < n1]) is None


def test_the_trailing_inverse_gives_every_entry_of_g(monkeypatch):
    """Large blocks keep only the trailing part of G = S^-1 (the dofs nearest the contact
    point, ordered last): its entries, those outside it, the products G x and the condensed
    system must equal the dense inverse's."""
    mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
    if not mf.available():
        pytest.skip("the compiled kernels (numba) are not available")
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    monkeypatch.setattr(linalg, "TRAILING_INVERSE_DOFS", 20)
    k, dofs, n1 = two_bodies()
    nearness = np.random.default_rng(6).standard_normal(len(dofs))
    factor, schur, g = linalg.condensed_factor(k, dofs, linalg.metis_order(k, 3), nearness)
    assert all(isinstance(b, mf.RootInverse) for b in g.blocks)
    kd = k.toarray()
    truth = np.linalg.inv(dense_schur(kd, np.setdiff1d(np.arange(k.shape[0]), dofs), dofs))
    scale = np.abs(truth).max()
    np.testing.assert_allclose(np.asarray(g), truth, rtol=0, atol=1e-10 * scale)
    x = np.random.default_rng(7).standard_normal((len(dofs), 2))
    np.testing.assert_allclose(g @ x[:, 0], truth @ x[:, 0], rtol=0, atol=1e-10 * np.abs(truth @ x[:, 0]).max())
    np.testing.assert_allclose(g @ x, truth @ x, rtol=0, atol=1e-10 * np.abs(truth @ x).max())
    near = np.argsort(nearness)[-12:]  # in the trailing blocks
    far = np.argsort(nearness)[:5]
    for rows, cols in ((near, near), (far, near), (np.concatenate([far, near]), far)):
        np.testing.assert_allclose(g.take(rows, cols), truth[np.ix_(rows, cols)], rtol=0, atol=1e-10 * scale)
    kc = np.zeros((len(dofs), len(dofs)))
    block = np.random.default_rng(8).standard_normal((12, 12))
    kc[np.ix_(near, near)] = 1e3 / scale * (block @ block.T)
    r = np.random.default_rng(9).standard_normal(len(dofs))
    exact = np.linalg.solve(np.linalg.inv(truth) + kc, r)
    system = linalg.SmallSystem(schur, sp.csr_matrix(kc), True, g)
    assert system.active is not None
    np.testing.assert_allclose(system.solve(r), exact, rtol=0, atol=1e-9 * np.abs(exact).max())
