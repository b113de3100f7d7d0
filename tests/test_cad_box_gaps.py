"""The distances of points to boxes a CAD body's search asks (geometry.solids.mesh_jit.box_gaps):
the compiled pass and the numpy path give the same numbers bit for bit, the distance to the
box's nearest point (0 inside, the distance to a face, an edge or a corner outside)."""

from __future__ import annotations

import numpy as np

from ibfem.geometry.solids import mesh_jit


def _boxes(rng, m):
    lo = rng.uniform(-1.0, 1.0, (m, 3))
    return lo, lo + rng.uniform(0.0, 0.5, (m, 3))


def test_box_gaps_are_the_distances_to_the_boxes():
    lo, hi = np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 2.0, 3.0]])
    p = np.array([[0.5, 1.0, 1.5], [2.0, 1.0, 1.5], [2.0, 3.0, 1.5], [-3.0, -2.0, 4.0]])
    expected = [0.0, 1.0, np.sqrt(2.0), np.sqrt(9.0 + 4.0 + 1.0)]
    np.testing.assert_allclose(mesh_jit.box_gaps(p, lo, hi)[0], expected, rtol=1e-15)


def test_compiled_and_numpy_box_gaps_agree_bit_for_bit(monkeypatch):
    rng = np.random.default_rng(7)
    lo, hi = _boxes(rng, 37)
    p = rng.uniform(-2.0, 2.0, (5000, 3))
    p[:37] = 0.5 * (lo + hi)  # each box's centre: inside it
    compiled = mesh_jit.box_gaps(p, lo, hi)
    monkeypatch.setattr(mesh_jit, "mesh_kernels", lambda: None)
    plain = mesh_jit.box_gaps(p, lo, hi)
    reference = np.linalg.norm(p[None] - np.clip(p[None], lo[:, None], hi[:, None]), axis=2)
    assert compiled.shape == plain.shape == (37, 5000)
    assert np.array_equal(plain, reference)
    assert np.array_equal(compiled, reference)
    assert (compiled == 0.0).any()
