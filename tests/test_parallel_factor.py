"""The bodies' condensed factorisations on threads (solver.fem.linalg._condensed_blocks: the bodies
one after the other, each one's large fronts shared by the threads): the threaded factor solves
K0 u = f as scipy's sparse LU does (to 1e-10 relative) and gives the serial path's Schur
complement and inverse to round-off; a front's update split into row ranges of equal work; the
bodies' solves side by side as one by one; a factor on disk solves alike mapped or read."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ibfem.solver.fem import linalg

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)


def grid_body(shape: tuple[int, int, int], seed: int) -> sp.csr_matrix:
    """SPD, the sparsity of a trilinear grid: the 27-point stencil coupling a node's 3 dofs,
    randomly scaled per dof."""
    one_d = [sp.diags([np.ones(k - 1), 4 * np.ones(k), np.ones(k - 1)], [-1, 0, 1]) for k in shape]
    stencil = sp.kron(sp.kron(one_d[0], one_d[1]), one_d[2])  # positive definite (a tensor product)
    block = np.eye(3) + 0.4 * (np.ones((3, 3)) - np.eye(3))
    k = sp.kron(stencil, block)
    scale = sp.diags(np.random.default_rng(seed).uniform(0.5, 2.0, k.shape[0]))
    return (scale @ k @ scale).tocsr()


def two_bodies():
    """Two uncoupled bodies of different sizes and the contact dofs (whole nodes) of each."""
    k = sp.block_diag([grid_body((7, 6, 5), seed=1), grid_body((6, 6, 6), seed=2)], format="csr")
    n1 = 7 * 6 * 5 * 3
    rng = np.random.default_rng(3)
    nodes = np.concatenate([rng.choice(n1 // 3, 20, replace=False),
                            n1 // 3 + rng.choice((k.shape[0] - n1) // 3, 16, replace=False)])
    dofs = np.sort((3 * nodes[:, None] + np.arange(3)).ravel())
    return k, dofs


def factored(monkeypatch, threads: str):
    k, dofs = two_bodies()
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    monkeypatch.setenv("IBFEM_THREADS", threads)
    nearness = -np.arange(len(dofs), dtype=float)
    return k, dofs, linalg.condensed_factor(k, dofs, linalg.metis_order(k, 3), nearness)


def test_threaded_factor_solves_as_scipy_and_equals_the_serial_factor(monkeypatch):
    k, dofs, (factor, schur, g) = factored(monkeypatch, "2")
    f = np.random.default_rng(4).standard_normal((k.shape[0], 2))
    u = factor.solve(f)
    exact = spla.spsolve(k.tocsc(), f)
    assert np.abs(u - exact).max() <= 1e-10 * np.abs(exact).max()
    _, _, (factor1, schur1, g1) = factored(monkeypatch, "1")
    eye = np.eye(len(dofs))
    s, s1 = schur @ eye, schur1 @ eye
    np.testing.assert_allclose(s, s1, rtol=0, atol=1e-13 * np.abs(s1).max())
    np.testing.assert_allclose(g @ eye, g1 @ eye, rtol=0, atol=1e-13 * np.abs(g1 @ eye).max())
    np.testing.assert_allclose(u, factor1.solve(f), rtol=0, atol=1e-13 * np.abs(exact).max())
    # S is the Schur complement of the contact dofs: G S = I
    np.testing.assert_allclose(g @ s, eye, rtol=0, atol=1e-9)


def test_a_factor_on_disk_solves_alike_mapped_or_read(monkeypatch):
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 4096 * 3)  # several chunks, mapped from inside a page
    k = grid_body((7, 6, 5), seed=6)
    order = linalg.metis_order(k, 3)
    dofs = np.arange(k.shape[0] - 30, k.shape[0])
    order = np.concatenate([order[~np.isin(order, dofs)], dofs])
    factor, _, _ = mf.condensed_cholesky(k, order, len(dofs), on_disk=True)
    assert factor._disk is not None and len(factor._chunks) >= 2
    f = np.random.default_rng(7).standard_normal((k.shape[0], 2))
    exact = spla.spsolve(k.tocsc(), f)
    mapped = factor.solve(f)
    assert np.abs(mapped - exact).max() <= 1e-10 * np.abs(exact).max()

    def unmappable(*args, **kwargs):
        raise OSError("no mapping here")

    monkeypatch.setattr(mf.mmap, "mmap", unmappable)
    np.testing.assert_array_equal(factor.solve(f), mapped)


def test_the_bodies_are_solved_side_by_side_as_one_by_one(monkeypatch):
    k, dofs, (factor, _, _) = factored(monkeypatch, "2")
    f = np.random.default_rng(8).standard_normal(k.shape[0])
    both = factor.solve(f)
    monkeypatch.setenv("IBFEM_THREADS", "1")
    np.testing.assert_array_equal(factor.solve(f), both)
    exact = spla.spsolve(k.tocsc(), f)
    assert np.abs(both - exact).max() <= 1e-10 * np.abs(exact).max()


def test_the_trial_system_on_block_diagonal_g_equals_the_dense_one(monkeypatch):
    """(S + Kc) x = r through I + G_AA Kc_AA formed block by block, against G dense and the
    direct solve of S + Kc (a contact block coupling the two bodies' dofs)."""
    k, dofs, (_, schur, g) = factored(monkeypatch, "2")
    m = len(dofs)
    s = schur @ np.eye(m)
    rng = np.random.default_rng(9)
    active = np.sort(rng.choice(m, m // 3, replace=False))
    block = rng.standard_normal((len(active), len(active)))
    kc = np.zeros((m, m))
    kc[np.ix_(active, active)] = np.abs(s).max() * (block @ block.T) / len(active)
    r = rng.standard_normal(m)
    exact = np.linalg.solve(s + kc, r)
    by_blocks = linalg.SmallSystem(schur, sp.csr_matrix(kc), True, g)
    dense = linalg.SmallSystem(schur, sp.csr_matrix(kc), True, g @ np.eye(m))
    assert by_blocks.active is not None and dense.active is not None
    np.testing.assert_allclose(by_blocks.solve(r), dense.solve(r), rtol=0, atol=1e-12 * np.abs(exact).max())
    np.testing.assert_allclose(by_blocks.solve(r), exact, rtol=0, atol=1e-9 * np.abs(exact).max())


def test_the_size_estimate_counts_one_body_at_a_time_whatever_the_threads(monkeypatch):
    """--check: the bodies are factored one after the other with any number of threads (the
    threads share a body's large fronts), so the estimate does not depend on them."""
    from pathlib import Path

    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.model import estimate

    path = Path(__file__).resolve().parent.parent / "examples" / "solid" / "full" / "ball_on_block.toml"
    problem = load_scene(path).problem
    sizes = []
    for threads in ("1", "2"):
        monkeypatch.setenv("IBFEM_THREADS", threads)
        sizes.append(estimate.estimate_size(problem, loaded=0.0))
    assert sizes[0].dofs == sizes[1].dofs and sizes[0].memory == sizes[1].memory


@pytest.mark.parametrize("interleaved", [False, True])
def test_the_trial_system_on_block_diagonal_g_by_runs_or_scattered_columns(interleaved):
    """I + G_AA Kc_AA formed block by block when each block's dofs are one run of the condensed
    positions (written as a slice) or interleaved with the other's: the solve of (S + Kc) x = r
    against the dense one."""
    from ibfem.solver.fem.block_diagonal import BlockDiagonal

    rng = np.random.default_rng(15)
    m = 60
    positions = [np.arange(0, m, 2), np.arange(1, m, 2)] if interleaved else [np.arange(30), np.arange(30, m)]
    blocks = []
    for p in positions:
        a = rng.standard_normal((len(p), len(p)))
        blocks.append(a @ a.T + len(p) * np.eye(len(p)))
    s = BlockDiagonal(blocks, positions)
    g = BlockDiagonal([np.linalg.inv(b) for b in blocks], positions)
    dense = s.toarray()
    active = np.sort(rng.choice(m, m // 3, replace=False))
    c = rng.standard_normal((len(active), len(active)))
    kc = np.zeros((m, m))
    kc[np.ix_(active, active)] = c @ c.T
    r = rng.standard_normal(m)
    small = linalg.SmallSystem(s, sp.csr_matrix(kc), True, g)
    assert small.active is not None
    exact = np.linalg.solve(dense + kc, r)
    np.testing.assert_allclose(small.solve(r), exact, rtol=0, atol=1e-10 * np.abs(exact).max())
