"""A large front's assembly and storage shared by rows between threads (solver.fem.multifrontal:
each thread zeroes its rows of the front, adds the matrix's columns and the children's update
matrices there, then copies its pivot rows into the factor and its rows of the update matrix onto
the stack), with the factor streamed to disk and its largest supernodes written from the front
buffer: the factor solves K u = f as scipy's sparse LU does, its Schur complement is the dense
formula's, and the file and the root block are to the bit those of the same factorisation with
every front assembled and stored by the one-thread kernels (every entry gets the same operations
in the same order)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from test_multifrontal import dense_schur
from test_parallel_factor_fronts import bodies

from ibfem.solver.fem import linalg

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)


def _serial_assemble(kern, args, s, work, pool):
    return kern.assemble_front(*args, s, np.empty(0), 0, work, np.zeros((0, 0)))


def _serial_store(kern, factor, s, t, segment, base, work, pool):
    kern.store_front(factor.sn_start, factor.row_ptr, factor.sn_parent, factor.factor_ptr, s, t, segment, base, work)


def test_rows_on_threads_give_the_one_thread_kernels_front_to_the_bit(monkeypatch):
    monkeypatch.setattr(mf, "THREADED_FRONT_ROWS", 64)
    monkeypatch.setattr(mf, "DISK_CHUNK_BYTES", 1 << 16)  # several ranges; the largest blocks written from the front
    k, dofs, n1 = bodies()
    body = k[:n1][:, :n1]
    contact = dofs[dofs < n1]
    order = linalg.metis_order(body, 3)
    order = np.concatenate([order[~np.isin(order, contact)], contact])
    calls = []
    rowwise = mf._threaded_assemble
    monkeypatch.setattr(mf, "_threaded_assemble", lambda *a: calls.append(a[2]) or rowwise(*a))
    two = mf.condensed_cholesky(body, order, len(contact), on_disk=True, threads=2)[0]
    assert calls  # fronts were assembled by rows on the threads
    assert any(two._in_front(s0, s1) for s0, s1 in two._chunks)  # some blocks written from the front buffer
    # the same threaded factorisation with each front assembled and stored by the one-thread kernels
    monkeypatch.setattr(mf, "_threaded_assemble", _serial_assemble)
    monkeypatch.setattr(mf, "_threaded_store", _serial_store)
    one = mf.condensed_cholesky(body, order, len(contact), on_disk=True, threads=2)[0]
    files = []
    for factor in (one, two):
        factor._disk.seek(0)
        files.append(np.fromfile(factor._disk, dtype=np.float64))
    np.testing.assert_array_equal(files[1], files[0])
    np.testing.assert_array_equal(two.factor, one.factor)  # the root block
    kd = body.toarray()
    truth = dense_schur(kd, np.setdiff1d(np.arange(n1), contact), contact)
    s = two.schur_operator() @ np.eye(len(contact))
    np.testing.assert_allclose(s, truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    f = np.random.default_rng(14).standard_normal(n1)
    exact = spla.spsolve(body.tocsc(), f)
    assert np.abs(two.solve(f) - exact).max() <= 1e-10 * np.abs(exact).max()


@pytest.mark.parametrize("lo, hi, parts", [(0, 1000, 2), (0, 7, 3), (5, 5, 2), (0, 3000, 4)])
def test_triangle_bounds_share_the_entries_evenly(lo, hi, parts):
    bounds = mf._triangle_bounds(lo, hi, parts)
    assert bounds[0] == lo and bounds[-1] == hi and all(a <= b for a, b in zip(bounds, bounds[1:]))
    if hi - lo >= 100:
        work = [sum(hi - j for j in range(a, b)) for a, b in zip(bounds, bounds[1:])]
        assert max(work) <= 1.05 * min(work)
