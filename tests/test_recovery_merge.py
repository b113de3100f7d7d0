"""The mirror images' merge with the grid's nodes (solver.fem.recovery._merge_nodes) against the
distances themselves: the nearest node within the tolerance of each point, -1 where none is."""

import numpy as np
import pytest

from ibfem.solver.fem.recovery import _merge_nodes


def _brute_force(nodes, points, tol):
    dist = np.linalg.norm(points[:, None, :] - nodes[None, :, :], axis=2)
    nearest = dist.argmin(axis=1)
    return np.where(dist[np.arange(len(points)), nearest] <= tol, nearest, -1)


@pytest.mark.parametrize("dim", [2, 3])
def test_the_nearest_node_within_the_tolerance_or_none(dim):
    rng = np.random.default_rng(7)
    h = 0.1
    lattice = np.stack(np.meshgrid(*[np.arange(12) * h] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    nodes = np.vstack([lattice, lattice[:40] + 0.3 * 1e-4])  # some nodes sharing a bin with another
    tol = 1e-4
    near = lattice[rng.integers(0, len(lattice), 300)] + rng.uniform(-0.9, 0.9, (300, dim)) * tol / np.sqrt(dim)
    far = rng.uniform(0.0, 1.1, (300, dim))  # almost all farther than tol from every node
    points = np.vstack([near, far])
    got = _merge_nodes(nodes, points, tol)
    want = _brute_force(nodes, points, tol)
    assert np.array_equal(got, want) and (got[:300] >= 0).all() and (got[300:] == -1).mean() > 0.99


def test_points_far_from_every_node_and_empty_inputs():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert _merge_nodes(nodes, np.array([[5.0, 5.0]]), 1e-3).tolist() == [-1]
    assert _merge_nodes(nodes, np.zeros((0, 2)), 1e-3).shape == (0,)
    assert _merge_nodes(np.zeros((0, 2)), np.array([[0.0, 0.0]]), 1e-3).tolist() == [-1]
