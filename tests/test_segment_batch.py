"""SegmentBatch: several segments' signed distances in one pass agree with each segment's own
projection (its closest point and side), and a profile of straight edges keeps the exact
distance of a square."""

import numpy as np

from ibfem.geometry.profile import Profile
from ibfem.geometry.segments import Segment, SegmentBatch


def test_rows_match_each_segments_projection():
    rng = np.random.default_rng(7)
    segments = [Segment((0.0, 0.0), (1.0, 0.5)), Segment((2.0, -1.0), (-1.0, 3.0)), Segment((0.3, 0.3), (0.3, -4.0))]
    P = rng.uniform(-5.0, 5.0, (200, 2))
    sd, t = SegmentBatch(segments).nearest_signed(P)
    assert sd.shape == t.shape == (3, 200)
    for row, seg in enumerate(segments):
        pr = seg.project(P)
        np.testing.assert_allclose(sd[row], pr.distances, rtol=0, atol=1e-12)
        np.testing.assert_allclose(t[row], pr.parameters, rtol=0, atol=1e-12)


def test_square_profile_distance_is_exact():
    corners = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]
    square = Profile([[Segment(corners[k], corners[(k + 1) % 4]) for k in range(4)]])
    rng = np.random.default_rng(3)
    P = rng.uniform(-1.0, 3.0, (500, 2))
    inside = np.minimum(np.minimum(P[:, 0], 2.0 - P[:, 0]), np.minimum(P[:, 1], 2.0 - P[:, 1]))
    gap = np.hypot(np.maximum(np.maximum(-P[:, 0], P[:, 0] - 2.0), 0.0), np.maximum(np.maximum(-P[:, 1], P[:, 1] - 2.0), 0.0))
    expected = np.where(inside >= 0.0, inside, -gap)
    np.testing.assert_allclose(square.signed_distance(P), expected, rtol=0, atol=1e-12)
