"""The diagnostic ties of the 3D friction history's stuck points (solver.contact.friction_history_ties):
the mean tie of a group ties its stuck points by their area-weighted mean tangential jump (a jump
constant over a group is its own mean, a jump along the normal has no tangential mean, the tie's
traction is -k (mean jump) plus the mean flux), the groups tied so are those the slip zone cuts
(or all), the groups follow the cells, and the stuck points by the slip zone can be given their
own layer."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.contact import friction_history_ties as ties


def _points(seed: int = 0):
    """Six points in three groups, random weights and stiffness, normals tilted off z."""
    rng = np.random.default_rng(seed)
    q = 6
    normal = np.column_stack([0.1 * rng.standard_normal(q), 0.1 * rng.standard_normal(q), np.ones(q)])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return np.array([0, 0, 1, 1, 2, 2]), rng.uniform(0.5, 2.0, q), normal, rng.uniform(1.0, 3.0, q)


def test_the_mean_tie_reads_the_tangential_mean_of_each_group():
    group, weights, normal, layer_t = _points()
    tied = np.array([True, True, True, False, True, True])
    mean, area, stiffness, g, idx = ties.mean_operator(group, tied, weights, normal, layer_t)
    np.testing.assert_array_equal(idx, [0, 1, 2, 4, 5])
    np.testing.assert_array_equal(g, [0, 0, 1, 2, 2])
    np.testing.assert_allclose(area, [weights[0] + weights[1], weights[2], weights[4] + weights[5]])
    np.testing.assert_allclose(stiffness, [np.average(layer_t[i], weights=weights[i]) for i in ([0, 1], [2], [4, 5])])
    np.testing.assert_allclose(mean @ (3.0 * normal).ravel(), 0.0, atol=1e-14)  # no tangential mean
    flat = np.tile([0.0, 0.0, 1.0], (6, 1))  # one normal: a tangential jump constant over a group is its mean
    mean = ties.mean_operator(group, tied, weights, flat, layer_t)[0]
    w = np.array([[1.0, -2.0, 5.0]] * 3 + [[7.0, 7.0, 7.0]] + [[0.5, 0.25, -1.0]] * 2)
    np.testing.assert_allclose((mean @ w.ravel()).reshape(-1, 3), [[1.0, -2.0, 0.0], [1.0, -2.0, 0.0], [0.5, 0.25, 0.0]])
    np.testing.assert_allclose(ties.mean_traction(mean, stiffness, w, 0.0 * w), -stiffness[:, None] * [[1.0, -2.0, 0.0],
                               [1.0, -2.0, 0.0], [0.5, 0.25, 0.0]])


def test_the_mean_terms_are_the_energy_of_the_mean_jump(monkeypatch):
    """Without the consistency term the stiffness is the Hessian of sum A k |M (J x + d)|^2 / 2 and
    the load its gradient at x = 0, negated."""
    monkeypatch.setattr(ties, "CUT_CELL_CONSISTENCY", 0.0)
    group, weights, _, layer_t = _points(1)
    normal = np.tile([0.0, 0.0, 1.0], (6, 1))
    tied = np.ones(6, dtype=bool)
    mean, area, stiffness, _, _ = ties.mean_operator(group, tied, weights, normal, layer_t)
    rng = np.random.default_rng(2)
    jump = sp.csr_matrix(rng.standard_normal((18, 5)))
    offset = rng.standard_normal((6, 3))
    k, f = ties.mean_terms(mean, area, stiffness, jump, sp.csr_matrix((18, 5)), offset)
    x = rng.standard_normal(5)

    def energy(v):
        m = (mean @ (jump @ v + offset.ravel())).reshape(-1, 3)
        return 0.5 * float(np.sum(area * stiffness * np.sum(m * m, axis=1)))

    assert energy(x) == pytest.approx(energy(0 * x) - f @ x + 0.5 * x @ (k @ x), rel=1e-12)


@pytest.mark.parametrize("rule, expected", [("points", [0, 0, 0, 0, 0, 0]), ("mean", [0, 0, 1, 0, 0, 0]),
                                            ("all", [1, 1, 1, 0, 1, 1])])
def test_the_groups_tied_by_their_mean(monkeypatch, rule, expected):
    monkeypatch.setattr(ties, "CUT_CELL_TIE", rule)
    slip = np.array([False, False, False, True, False, False])  # the second group is cut
    np.testing.assert_array_equal(ties.grouped(_points()[0], slip), np.array(expected, dtype=bool))


@pytest.mark.parametrize("rule, expected", [("cell1", [0, 0, 1, 1]), ("pairs", [0, 1, 2, 2]),
                                            ("patch2", [0, 0, 0, 1]), ("nodes", [0, 1, 1, 2])])
def test_the_groups(monkeypatch, rule, expected):
    monkeypatch.setattr(ties, "TIE_GROUPS", rule)
    s = np.array([[0.1, 0.2], [0.7, 0.3], [1.2, 0.1], [2.6, 0.4]])  # cells of 1 from the centre
    cells1, cells2 = np.array([5, 5, 6, 6]), np.array([1, 2, 3, 3])
    np.testing.assert_array_equal(ties.tie_groups(s, 1.0, cells1, cells2), expected)


def test_the_layer_of_the_stuck_points_by_the_slip_zone(monkeypatch):
    s = np.column_stack([np.arange(6.0), np.zeros(6)])
    slip = np.array([False, False, False, True, False, False])
    np.testing.assert_allclose(ties.tangential_bands(s, slip, 1.5, 2.0), 2.0)
    monkeypatch.setattr(ties, "NEAR_BAND", 0.5)
    monkeypatch.setattr(ties, "NEAR_CELLS", 1.0)  # the points 1 from the slipping one
    np.testing.assert_allclose(ties.tangential_bands(s, slip, 1.5, 2.0), [2.0, 2.0, 1.0, 2.0, 1.0, 2.0])


def test_the_recovered_flux_is_the_stuck_points_disc_mean():
    """A stuck point's row is the area-weighted mean over the stuck points within the radius (checked
    against the means computed point by point), per component; a slipping point keeps its own."""
    rng = np.random.default_rng(3)
    s = rng.uniform(0.0, 4.0, (60, 2))
    weights = rng.uniform(0.5, 2.0, 60)
    stuck = np.linalg.norm(s - 2.0, axis=1) < 1.5
    values = rng.standard_normal((60, 3))
    out = (ties.recovery_operator(s, weights, stuck, 0.8) @ values.ravel()).reshape(-1, 3)
    for i in range(60):
        if stuck[i]:
            near = stuck & (np.linalg.norm(s - s[i], axis=1) <= 0.8)
            np.testing.assert_allclose(out[i], np.average(values[near], axis=0, weights=weights[near]), rtol=1e-12)
        else:
            np.testing.assert_allclose(out[i], values[i], rtol=1e-14)
