"""The condensed contact system with G = S^-1 block diagonal (one block per body) on several
threads (solver.fem.linalg.SmallSystem: the bodies' blocks of Kc_AA^T G_AA multiplied on threads,
the LU of I + G_AA Kc_AA on several BLAS threads) against a dense solve of (S + Kc) x = r, and
the same product as on one thread; threads only where the machine has a core free."""

import numpy as np
import scipy.sparse as sp

from ibfem.solver.fem import linalg
from ibfem.solver.fem.block_diagonal import BlockDiagonal


def _two_bodies(seed: int):
    rng = np.random.default_rng(seed)
    sizes = (70, 50)
    blocks, positions, start = [], [], 0
    for n in sizes:
        q = rng.standard_normal((n, n))
        blocks.append(q @ q.T + n * np.eye(n))  # SPD
        positions.append(np.arange(start, start + n))
        start += n
    m = start
    schur = BlockDiagonal(blocks, positions)
    g = BlockDiagonal([np.linalg.inv(b) for b in blocks], positions)
    # a contact block coupling some dofs of both bodies (a third of them active), not symmetric
    active = np.sort(np.concatenate([rng.choice(70, 24, replace=False), 70 + rng.choice(50, 16, replace=False)]))
    block = rng.standard_normal((len(active), len(active)))
    kc = np.zeros((m, m))
    kc[np.ix_(active, active)] = 1e2 * (block @ block.T) + 10.0 * block
    return schur, g, kc, rng.standard_normal(m)


def test_threaded_small_system_solves_the_condensed_system(monkeypatch):
    schur, g, kc, r = _two_bodies(3)
    exact = np.linalg.solve(schur.toarray() + kc, r)
    monkeypatch.setattr(linalg.SmallSystem, "THREADED_ACTIVE", 1)
    monkeypatch.setattr(linalg, "_idle_cores", lambda: 1.0)  # a free machine: threads used
    solutions = []
    for threads in ("1", "2"):
        monkeypatch.setenv("IBFEM_THREADS", threads)
        small = linalg.SmallSystem(schur, sp.csr_matrix(kc), False, g)
        assert small.active is not None and len(small.active) == 40
        x = small.solve(r)
        assert np.max(np.abs(x - exact)) <= 1e-10 * np.max(np.abs(exact))
        solutions.append(x)
        # the product Kc_AA^T G_AA on one thread and on two: the same sums
        product = small._block_product(small.active, int(threads))
        dense = small.kc_aa.T @ g.take(small.active, small.active)
        np.testing.assert_allclose(product, dense, rtol=0, atol=1e-12 * np.abs(dense).max())
    np.testing.assert_allclose(solutions[1], solutions[0], rtol=0, atol=1e-12 * np.max(np.abs(exact)))


def test_a_busy_machine_gets_one_thread(monkeypatch):
    monkeypatch.setenv("IBFEM_THREADS", "2")
    monkeypatch.setattr(linalg, "_idle_cores", lambda: 0.1)
    assert linalg.free_threads() == 1
    monkeypatch.setattr(linalg, "_idle_cores", lambda: 0.9)
    assert linalg.free_threads() == 2
    # no idle time measured yet: the load average decides
    monkeypatch.setattr(linalg, "_idle_cores", lambda: None)
    monkeypatch.setattr(linalg.os, "getloadavg", lambda: (50.0, 50.0, 50.0))
    assert linalg.free_threads() == 1
    monkeypatch.setattr(linalg.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert linalg.free_threads() == 2
    monkeypatch.setenv("IBFEM_THREADS", "1")
    assert linalg.free_threads() == 1


def test_idle_cores_are_read_over_an_interval():
    import time

    linalg._idle_cores()
    time.sleep(0.3)
    idle = linalg._idle_cores()
    if idle is not None:  # a system with /proc/stat
        assert 0.0 <= idle <= (linalg.os.cpu_count() or 1) + 1e-9
