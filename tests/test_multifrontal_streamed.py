"""A condensed multifrontal factor written to disk while it is computed (solver.fem.multifrontal.
CholeskyFactor(on_disk=True): the numeric phase runs over chunks of supernodes, each chunk's
blocks written out before the next is computed, the root block kept): the same Schur complement
and solves as dense truth, a disk that fails mid-way keeps the factor in memory, and a bad pivot
in a later chunk is named."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from test_multifrontal import dense_schur, elasticity_like, random_order

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)


def system(seed: int):
    k = elasticity_like((7, 6, 5), seed=seed)
    n = k.shape[0]
    rng = np.random.default_rng(seed)
    dofs = np.sort(rng.choice(n, n // 8, replace=False))
    return k, dofs, random_order(n, dofs, rng)


def check_against_truth(k, dofs, factor, schur):
    kd = k.toarray()
    n = k.shape[0]
    truth = dense_schur(kd, np.setdiff1d(np.arange(n), dofs), dofs)
    np.testing.assert_allclose(schur.toarray(), truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    f = np.random.default_rng(1).standard_normal((n, 2))
    u = factor.solve(f)
    assert np.abs(kd @ u - f).max() <= 1e-12 * np.abs(kd).max() * np.abs(u).max()


def test_streamed_factor_matches_dense_truth_and_holds_only_the_root(monkeypatch):
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 4096)
    k, dofs, order = system(3)
    factor, schur, _ = mf.condensed_cholesky(k, order, len(dofs), on_disk=True)
    assert factor._disk is not None and len(factor._chunks) >= 3
    assert factor.factor.size == len(dofs) ** 2
    check_against_truth(k, dofs, factor, schur)
    # the file holds exactly the blocks below the root, as the in-memory factor has them
    whole, _, _ = mf.condensed_cholesky(k, order, len(dofs), on_disk=False)
    factor._disk.seek(0)
    below = np.fromfile(factor._disk, dtype=np.float64)
    np.testing.assert_array_equal(below, whole.factor[:factor._base])


class FailingFile:
    """A temporary file whose second write fails (a disk that fills up)."""

    def __init__(self):
        import tempfile

        self.inner, self.writes = tempfile.TemporaryFile(), 0

    def write(self, data):
        self.writes += 1
        if self.writes >= 2:
            self.inner.write(bytes(data)[:16])  # a partial write, then the error
            raise OSError(28, "No space left on device")
        return self.inner.write(data)

    def __getattr__(self, name):
        return getattr(self.inner, name)


def test_a_disk_that_fills_up_keeps_the_factor_in_memory(monkeypatch):
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 4096)
    monkeypatch.setattr(mf, "_temporary_file", FailingFile)
    k, dofs, order = system(4)
    factor, schur, _ = mf.condensed_cholesky(k, order, len(dofs), on_disk=True)
    assert factor._disk is None and factor.factor.size * 8 == factor.factor_bytes
    check_against_truth(k, dofs, factor, schur)


def test_a_bad_pivot_in_a_later_chunk_is_named(monkeypatch):
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 4096)
    k, dofs, order = system(5)
    bad = int(order[len(order) // 2])  # eliminated in the middle, after several chunks
    k = k.tolil()
    k[bad, :] = 0.0
    k[:, bad] = 0.0
    k = sp.csr_matrix(k)
    with pytest.raises(mf.NotPositiveDefinite, match=rf"dof {bad} \(of {k.shape[0]}\) is zero") as err:
        mf.condensed_cholesky(k, order, len(dofs), on_disk=True)
    assert err.value.dof == bad
