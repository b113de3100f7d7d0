"""A condensed multifrontal factor held on disk (solver.fem.multifrontal.CholeskyFactor.to_disk:
the blocks below the root in a temporary file, read back in chunks by every solve) against dense
truth: the Schur complement of the trailing dofs and its inverse, and solves of one and several
right-hand sides, on elasticity-like grid matrices read in chunks of a few supernodes."""

from __future__ import annotations

import numpy as np
import pytest

from test_multifrontal import dense_schur, elasticity_like, random_order

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)


def test_factor_on_disk_matches_dense_truth(monkeypatch):
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 4096)
    k = elasticity_like((7, 6, 5), seed=3)
    n = k.shape[0]
    rng = np.random.default_rng(7)
    dofs = np.sort(rng.choice(n, n // 8, replace=False))
    factor, schur, g = mf.condensed_cholesky(k, random_order(n, dofs, rng), len(dofs), trailing=len(dofs) // 2,
                                             on_disk=True)
    assert factor._disk is not None and len(factor._chunks) >= 2
    assert factor.factor.size == len(dofs) ** 2  # only the root block in memory
    kd = k.toarray()
    truth = dense_schur(kd, np.setdiff1d(np.arange(n), dofs), dofs)
    np.testing.assert_allclose(schur.toarray(), truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    x = rng.standard_normal(len(dofs))
    np.testing.assert_allclose(schur @ (g @ x), x, rtol=0, atol=1e-9 * np.abs(x).max())
    f = rng.standard_normal((n, 3))
    u = factor.solve(f)
    assert np.abs(kd @ u - f).max() <= 1e-12 * np.abs(kd).max() * np.abs(u).max()
    np.testing.assert_allclose(factor.solve(f[:, 2]), u[:, 2], rtol=0, atol=1e-12 * np.abs(u[:, 2]).max())


def test_small_factors_stay_in_memory():
    """Below ON_DISK_BYTES nothing is written (the shipped examples' factors are far smaller)."""
    k = elasticity_like((9, 8), seed=1)
    n = k.shape[0]
    factor, _, _ = mf.condensed_cholesky(k, np.arange(n), 12)
    assert factor._disk is None and factor.factor.size * 8 == factor.factor_bytes


def test_unwritable_directory_keeps_the_factor_in_memory(tmp_path):
    k = elasticity_like((6, 5, 4), seed=2)
    n = k.shape[0]
    factor, _, _ = mf.condensed_cholesky(k, np.arange(n), 10, on_disk=False)
    factor.to_disk(directory=str(tmp_path / "missing"))
    assert factor._disk is None
    f = np.random.default_rng(0).standard_normal(n)
    u = factor.solve(f)
    assert np.abs(k @ u - f).max() <= 1e-12 * np.abs(k).max() * np.abs(u).max()
