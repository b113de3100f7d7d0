"""ibfem.solver.fem.dense.symmetric_from_lower (in place, by row blocks) and linalg's upper variant
against numpy's triangle arithmetic, for blocks that do and do not divide the size, on C- and
Fortran-ordered arrays (LAPACK's results are Fortran-ordered)."""

import numpy as np
import pytest

from ibfem.solver.fem.dense import symmetric_from_lower
from ibfem.solver.fem.linalg import _symmetric_from_upper


@pytest.mark.parametrize("m, block", [(1, 512), (20, 7), (21, 7), (64, 64), (300, 512)])
@pytest.mark.parametrize("order", ["C", "F"])
def test_triangles_mirrored_in_place(m, block, order):
    rng = np.random.default_rng(m)
    a = np.asarray(rng.normal(size=(m, m)), order=order)
    want_lower = np.tril(a) + np.tril(a, -1).T
    want_upper = np.triu(a) + np.triu(a, 1).T
    low, up = a.copy(order=order), a.copy(order=order)
    out = symmetric_from_lower(low, block)
    assert out is low and np.array_equal(low, want_lower)
    sym = _symmetric_from_upper(up)
    assert np.shares_memory(sym, up) and np.array_equal(sym, want_upper)
