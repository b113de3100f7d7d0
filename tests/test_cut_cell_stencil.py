"""The leaf stencil's shared points (solver.fem.cut_cells3d._shared_points): points of one cell on
the sub-cubes' lattice are one point whoever asks, whether found by integer keys or, where those
would pass int64, by rows."""

import numpy as np

from ibfem.solver.fem import cut_cells3d as cc


def _distinct_rows(owner, local):
    keys = np.column_stack([owner, local])
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    return keys, first, inverse.reshape(-1)


def test_shared_points_are_the_distinct_rows():
    rng = np.random.default_rng(0)
    for width, owners in ((2.0, 5), (0.25, 50), (2.0 / 128, 400)):
        owner = rng.integers(0, owners, 3000)
        local = -1.0 + 0.5 * width * rng.integers(0, int(round(4.0 / width)) + 1, (3000, 3))
        keys, first_rows, inverse_rows = _distinct_rows(owner, local)
        first, inverse = cc._shared_points(owner, local, width)
        np.testing.assert_array_equal(inverse, inverse_rows)
        np.testing.assert_array_equal(keys[first], keys[first_rows])
        # a deep level with a huge cell index: the keys would pass int64, the rows decide
        deep = 2.0 / 2**22
        big = owner.astype(np.int64) + 2**40
        local_deep = -1.0 + 0.5 * deep * rng.integers(0, 8, (3000, 3))
        keys, _, inverse_rows = _distinct_rows(big, local_deep)
        first, inverse = cc._shared_points(big, local_deep, deep)
        np.testing.assert_array_equal(inverse, inverse_rows)
        np.testing.assert_array_equal(keys[first][inverse], keys)
