"""A body's large fronts factored on several threads (solver.fem.multifrontal: the update of the
rows below each outer block of pivots split into row ranges of about equal work, one per thread):
on a multi-body matrix with the structures the grids make (27-point stencils of 3 dofs per node,
hanging-node couplings beyond the stencil, contact dofs condensed in every body), the threaded
factor solves K u = f as scipy's sparse LU does (to 1e-10 relative) and gives the one-thread
factor's Schur complement; the split really runs; a non-positive pivot inside a threaded front is
reported with its dof as on one thread."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ibfem.solver.fem import linalg

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)


def grid_body(shape: tuple[int, int, int], rng) -> sp.csr_matrix:
    """SPD with a trilinear grid's sparsity (27-point stencil, 3 dofs per node), randomly scaled
    per dof, plus hanging-node couplings: a tenth of the nodes tied to a node a few cells away
    (a positive semi-definite pair term, so the sum stays positive definite)."""
    one_d = [sp.diags([np.ones(k - 1), 4 * np.ones(k), np.ones(k - 1)], [-1, 0, 1]) for k in shape]
    stencil = sp.kron(sp.kron(one_d[0], one_d[1]), one_d[2])
    k = sp.kron(stencil, np.eye(3) + 0.4 * (np.ones((3, 3)) - np.eye(3))).tolil()
    nodes = int(np.prod(shape))
    for a in rng.choice(nodes, nodes // 10, replace=False):
        b = int((a + rng.integers(2, 40)) % nodes)
        for d in range(3):
            i, j = 3 * a + d, 3 * b + d
            if i != j:
                w = 0.3 * rng.uniform()
                k[i, i] += w
                k[j, j] += w
                k[i, j] -= w
                k[j, i] -= w
    scale = sp.diags(rng.uniform(0.5, 2.0, k.shape[0]))
    return (scale @ k.tocsr() @ scale).tocsr()


def bodies():
    """Two uncoupled bodies; each condenses the nodes of its last three grid layers (729 dofs: a
    root front of three outer blocks of pivots)."""
    rng = np.random.default_rng(11)
    shapes = ((10, 9, 9), (9, 9, 9))
    blocks = [grid_body(s, rng) for s in shapes]
    k = sp.block_diag(blocks, format="csr")
    dofs, offset = [], 0
    for s, b in zip(shapes, blocks):
        layer = s[1] * s[2]
        nodes = np.arange(int(np.prod(s)) - 3 * layer, int(np.prod(s)))
        dofs.append(offset + (3 * nodes[:, None] + np.arange(3)).ravel())
        offset += b.shape[0]
    return k, np.concatenate(dofs), blocks[0].shape[0]


@pytest.fixture()
def threaded_fronts(monkeypatch):
    """Every front of 64 rows or more threaded; records the number of row ranges of each split."""
    monkeypatch.setattr(mf, "THREADED_FRONT_ROWS", 64)
    splits = []
    row_bounds = mf._row_bounds

    def recorded(*args):
        bounds = row_bounds(*args)
        splits.append(len(bounds) - 1)
        return bounds

    monkeypatch.setattr(mf, "_row_bounds", recorded)
    return splits


def test_the_threaded_factor_of_several_bodies_solves_as_scipy(monkeypatch, threaded_fronts):
    k, dofs, _ = bodies()
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    nearness = -np.arange(len(dofs), dtype=float)
    order = linalg.metis_order(k, 3)
    results = {}
    for threads in ("1", "2"):
        monkeypatch.setenv("IBFEM_THREADS", threads)
        results[threads] = linalg.condensed_factor(k, dofs, order, nearness)
    assert threaded_fronts  # fronts went through the threaded factorisation
    f = np.random.default_rng(12).standard_normal((k.shape[0], 2))
    exact = spla.spsolve(k.tocsc(), f)
    factor, schur, g = results["2"]
    u = factor.solve(f)
    assert np.abs(u - exact).max() <= 1e-10 * np.abs(exact).max()
    eye = np.eye(len(dofs))
    s, s1 = schur @ eye, results["1"][1] @ eye
    np.testing.assert_allclose(s, s1, rtol=0, atol=1e-13 * np.abs(s1).max())
    np.testing.assert_allclose(g @ s, eye, rtol=0, atol=1e-9)  # G is S's inverse


def test_a_threaded_factor_streamed_to_disk_solves_as_scipy(monkeypatch, threaded_fronts):
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 1 << 16)  # several ranges, some fronts split inside them
    k, dofs, n1 = bodies()
    body = k[:n1][:, :n1]
    contact = dofs[dofs < n1]
    order = linalg.metis_order(body, 3)
    order = np.concatenate([order[~np.isin(order, contact)], contact])
    factor, _, _ = mf.condensed_cholesky(body, order, len(contact), on_disk=True, threads=2)
    assert factor._disk is not None and len(factor._chunks) >= 2 and threaded_fronts
    f = np.random.default_rng(13).standard_normal(n1)
    exact = spla.spsolve(body.tocsc(), f)
    assert np.abs(factor.solve(f) - exact).max() <= 1e-10 * np.abs(exact).max()


def test_a_bad_pivot_in_a_threaded_front_names_its_dof_as_on_one_thread(threaded_fronts):
    k, dofs, n1 = bodies()
    body = k[:n1][:, :n1].tolil()
    contact = dofs[dofs < n1]
    bad = int(contact[len(contact) // 2])
    body[bad, bad] = -body[bad, bad]  # not positive definite
    order = linalg.metis_order(body.tocsr(), 3)
    order = np.concatenate([order[~np.isin(order, contact)], contact])
    raised = []
    for threads in (1, 2):
        with pytest.raises(mf.NotPositiveDefinite) as err:
            mf.CholeskyFactor(body.tocsr(), order, len(contact), definite=True, threads=threads)
        raised.append(err.value.dof)
    assert raised[0] == raised[1]


@pytest.mark.parametrize("b1, f, parts, lead", [(256, 9657, 2, 256), (0, 3000, 2, 0), (512, 2600, 3, 256),
                                                (256, 900, 2, 256), (768, 4000, 2, 100)])
def test_the_row_ranges_share_the_update_in_equal_work_on_the_block_grid(b1, f, parts, lead):
    """Row j of the update costs f - j; the first range's thread also factors the next ``lead``
    pivots (PANEL_COST lead (f - b1) / 2): every thread's work within one block of rows of an
    equal share."""
    block = 256
    bounds = mf._row_bounds(b1, f, block, parts, lead)
    assert bounds[0] == b1 and bounds[-1] == f and np.all(np.diff(bounds) > 0)
    assert all((r - b1) % block == 0 for r in bounds[:-1])  # the serial update's BLAS blocks
    work = [((f - lo) ** 2 - (f - hi) ** 2) / 2 for lo, hi in zip(bounds[:-1], bounds[1:])]
    work[0] += mf.PANEL_COST * lead * (f - b1) / 2
    share = sum(work) / parts
    assert max(abs(w - share) for w in work) <= block * (f - b1)


@pytest.mark.parametrize("f, nc", [(1600, 1200), (1300, 1300)])
def test_a_front_factored_on_threads_equals_the_one_thread_kernel(f, nc):
    """A dense SPD front large enough for the update to be split: the threaded L D L^T of its first
    nc columns equals the one-thread kernel's to round-off, and L D L^T rebuilds the front."""
    from concurrent.futures import ThreadPoolExecutor

    kern = mf._kernels()
    rng = np.random.default_rng(14)
    a = rng.uniform(-1.0, 1.0, (f, f)) / np.sqrt(f)
    a = a + a.T + 3.0 * np.eye(f)  # symmetric, eigenvalues within 3 +- 2.4: positive definite
    one, two = np.triu(a).copy(), np.triu(a).copy()  # row j holds column j's lower triangle
    assert kern._partial_ldlt(kern.DGEMM, one, nc, f, True) == -1
    splits = []
    row_bounds = mf._row_bounds

    with ThreadPoolExecutor(1) as pool:
        pool.parts = 2
        mf._row_bounds = lambda *args: splits.append(row_bounds(*args)) or splits[-1]
        try:
            assert mf._threaded_ldlt(kern, two, nc, True, pool) == -1
        finally:
            mf._row_bounds = row_bounds
    assert any(len(b) > 2 for b in splits)  # the update was shared between the threads
    np.testing.assert_allclose(np.triu(two), np.triu(one), rtol=0, atol=1e-12 * np.abs(one).max())
    low = np.triu(two[:nc, :]).T  # columns of L below the pivots (unit diagonal), D on the diagonal
    d = np.diag(two)[:nc].copy()
    low[np.arange(nc), np.arange(nc)] = 1.0
    update = np.triu(two[nc:, nc:])
    rebuilt = low @ (d[:, None] * low.T)
    rebuilt[nc:, nc:] += update + np.triu(update, 1).T
    np.testing.assert_allclose(rebuilt, a, rtol=0, atol=1e-10 * np.abs(a).max())
