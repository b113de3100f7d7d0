"""An arc's angle-to-parameter map takes the remainder modulo 2 pi by a fast path on arctan2's
range: the same bits as np.mod everywhere (signed zeros, the ends of the range, values outside
it), and an arc's distances unchanged by it."""

import math

import numpy as np

from ibfem.geometry.arcs import _mod_two_pi
from ibfem.geometry.bounded import Arc


def test_remainder_has_the_bits_of_np_mod():
    rng = np.random.default_rng(4)
    edge = [-0.0, 0.0, -2 * math.pi, -math.pi, math.pi, np.nextafter(2 * math.pi, 0.0),
            np.nextafter(-2 * math.pi, 0.0), 1e-300, -1e-300, -5e-324, 2 * math.pi, 7.0, -7.0]
    for a in (rng.uniform(-2 * math.pi, 2 * math.pi, 10000), np.array(edge), rng.uniform(-30, 30, 1000),
              np.array([np.nan, 1.0])):
        got, ref = _mod_two_pi(a), np.mod(a, 2 * math.pi)
        assert np.array_equal(np.isnan(got), np.isnan(ref))
        finite = ~np.isnan(ref)
        assert np.array_equal(got[finite].view(np.int64), ref[finite].view(np.int64))


def test_arc_distance_against_the_closed_form():
    arc = Arc([0.3, -0.2], 0.7, math.radians(-40.0), math.radians(200.0))  # counter-clockwise through 0
    rng = np.random.default_rng(5)
    p = rng.uniform(-1.5, 1.5, (5000, 2))
    d, t = arc._nearest_signed(p)
    rel = p - [0.3, -0.2]
    span = np.mod(np.degrees(np.arctan2(rel[:, 1], rel[:, 0])) + 40.0, 360.0)
    on = span <= 239.9  # the foot is inside the arc's span
    np.testing.assert_allclose(np.abs(d[on]), np.abs(np.linalg.norm(rel[on], axis=1) - 0.7), rtol=0, atol=1e-15)
    np.testing.assert_allclose(t[on], np.radians(span[on]), rtol=0, atol=1e-13)
