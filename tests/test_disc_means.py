"""The binned disc means against the exact weighted disc means of a brute force over all pairs."""
import numpy as np
import pytest

from ibfem.solver.contact.disc_means import BINS_PER_RADIUS, DiscBins


def _exact(s, w, v, members, rows, radius, keep=None):
    d = np.linalg.norm(s[rows][:, None, :] - s[None, :, :], axis=2)
    take = (d <= radius) & members[None, :]
    if keep is not None:
        take &= keep
    ww = np.where(take, w[None, :], 0.0)
    return ww @ v / ww.sum(axis=1)[:, None]


@pytest.fixture
def points():
    rng = np.random.default_rng(7)
    s = rng.uniform(0.0, 1.0, (3000, 2)) * [1.0, 0.5]
    return s, rng.uniform(0.5, 1.5, len(s))


def test_plain_means_within_the_rims_half_bin(points):
    s, w = points
    radius = 0.08
    v = np.column_stack([s[:, 0], s[:, 1], np.ones(len(s))])
    members = s[:, 0] + 0.4 * s[:, 1] < 0.55  # one zone: the means take its points only
    rows = np.flatnonzero(members)
    got = DiscBins.build(s, w, radius).means(v, members, rows)
    want = _exact(s, w, v, members, rows, radius)
    np.testing.assert_allclose(got[:, 2], 1.0, rtol=1e-12)  # a constant is its own mean
    err = np.linalg.norm(got[:, :2] - want[:, :2], axis=1) / radius
    # the taken bins hold every point within r - diag and none beyond r + diag (diag = sqrt 2 r / BINS_PER_RADIUS):
    # the centroids of the two sets differ by a small fraction of r
    assert err.max() < 0.08 and np.sqrt(np.mean(err**2)) < 0.02  # measured 0.053 and 0.012
    # a disc of a zone's points only: no mean leaves the zone's side of its boundary by more than the bins' diagonal
    assert np.all(got[:, 0] + 0.4 * got[:, 1] < 0.55 + np.sqrt(2.0) * radius / BINS_PER_RADIUS)


def test_windows_limited_by_a_distance(points):
    s, w = points
    radius = 0.08
    d = np.abs(s[:, 0] - 0.5)  # the distance to a line
    v = s[:, :1].copy()
    members = s[:, 0] < 0.5
    rows = np.flatnonzero(members & (d < radius))

    def limit(c):
        return np.where(c >= radius, np.inf, 2.0 * c)
    got = DiscBins.build(s, w, radius).means(v, members, rows, ((d, d[rows], limit),))
    keep = d[None, :] <= limit(d[rows])[:, None]
    want = _exact(s, w, v, members, rows, radius, keep)
    # symmetric windows about each row along x: the means stay near the rows' own x (within the bins)
    err = np.abs(got[:, 0] - want[:, 0]) / radius
    assert np.sqrt(np.mean(err**2)) < 0.015 and err.max() < 0.06  # measured 0.008 and 0.033


def test_bad_input_named():
    with pytest.raises(ValueError, match="radius"):
        DiscBins.build(np.zeros((3, 2)), np.ones(3), 0.0)
    with pytest.raises(ValueError, match="plane coordinates"):
        DiscBins.build(np.zeros((3, 3)), np.ones(3), 1.0)


def _binned_by_definition(s, w, v, members, rows, radius, side, keep=None):
    """The means as defined from the bins, bin by bin: a row takes the member sums of each bin whose
    members' weighted centre lies within the radius of it, and of its own bin."""
    cell = np.floor((s - s.min(axis=0)) / side).astype(np.int64)
    keys, which = np.unique(cell, axis=0, return_inverse=True)
    which = which.ravel()
    wm = np.where(members, w, 0.0)
    wb = np.bincount(which, weights=wm, minlength=len(keys))
    centre = np.column_stack([np.bincount(which, weights=wm * s[:, j], minlength=len(keys)) for j in range(2)])
    centre /= np.where(wb > 0.0, wb, 1.0)[:, None]
    vb = np.column_stack([np.bincount(which, weights=wm * v[:, j], minlength=len(keys)) for j in range(v.shape[1])])
    take = np.linalg.norm(centre[None, :, :] - s[rows][:, None, :], axis=2) <= radius
    take[np.arange(len(rows)), which[rows]] = True
    if keep is not None:
        take &= keep
    return (take * 1.0) @ vb / ((take * 1.0) @ wb)[:, None]


def test_the_means_are_the_bins_definition(points):
    """The inner bins summed as runs along the grid's rows, the rim bins tested one by one: both give the
    bins' means as defined, to round-off, with and without a condition on the bins."""
    s, w = points
    s = np.concatenate([s, s * 0.5 + 0.2])  # enough points that the bins have the side r / BINS_PER_RADIUS
    w = np.concatenate([w, w])
    radius = 0.08
    bins = DiscBins.build(s, w, radius)
    assert bins.side == pytest.approx(radius / BINS_PER_RADIUS)
    v = np.column_stack([np.sin(9.0 * s[:, 0]) * s[:, 1], s[:, 0] - 0.4])
    members = s[:, 0] + 0.4 * s[:, 1] < 0.55
    rows = np.flatnonzero(members)
    got = bins.means(v, members, rows)
    want = _binned_by_definition(s, w, v, members, rows, radius, bins.side)
    assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()

    d = np.abs(s[:, 0] - 0.3)
    near = np.flatnonzero(members & (d < radius))
    got = bins.means(v, members, near, ((d, d[near], lambda c: 2.0 * c),))
    cell = np.floor((s - s.min(axis=0)) / bins.side).astype(np.int64)
    keys, which = np.unique(cell, axis=0, return_inverse=True)
    which = which.ravel()
    wm = np.where(members, w, 0.0)
    mean_d = np.bincount(which, weights=wm * d, minlength=len(keys)) / np.maximum(
        np.bincount(which, weights=wm, minlength=len(keys)), 1e-300)
    keep = (mean_d[None, :] <= 2.0 * d[near][:, None]) | (np.arange(len(keys))[None, :] == which[near][:, None])
    want = _binned_by_definition(s, w, v, members, near, radius, bins.side, keep)
    assert np.abs(got - want).max() <= 1e-12 * np.abs(want).max()
