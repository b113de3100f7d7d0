"""The condensed contact system (solver.fem.linalg.SmallSystem) against a dense solve of
(S + Kc) x = r: the active-set path (an LU of I + G_AA Kc_AA with G = S^-1) and the full path,
for a symmetric Kc and a non-symmetric one (a friction block)."""

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.fem.linalg import SmallSystem


def _system(m, active, symmetric, seed):
    rng = np.random.default_rng(seed)
    q = rng.standard_normal((m, m))
    schur = q @ q.T + m * np.eye(m)  # SPD
    kc = np.zeros((m, m))
    a = np.sort(rng.choice(m, active, replace=False))
    block = rng.standard_normal((active, active))
    block = 1e3 * (block @ block.T) if symmetric else 1e3 * (block @ block.T) + 50.0 * block
    kc[np.ix_(a, a)] = block
    return schur, kc, rng.standard_normal(m)


@pytest.mark.parametrize("symmetric", [True, False])
@pytest.mark.parametrize("active", [12, 50])  # 12 of 60: the active-set path; 50 of 60: the full one
def test_small_system_solves_the_condensed_system(symmetric, active):
    m = 60
    schur, kc, r = _system(m, active, symmetric, seed=active + symmetric)
    small = SmallSystem(schur, sp.csr_matrix(kc), symmetric, np.linalg.inv(schur))
    assert (small.active is not None) == (active <= SmallSystem.ACTIVE_FRACTION * m)
    x = small.solve(r)
    exact = np.linalg.solve(schur + kc, r)
    assert np.max(np.abs(x - exact)) <= 1e-10 * np.max(np.abs(exact))
