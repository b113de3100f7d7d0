"""Analytic solids' distances computed in blocks of points (geometry.solids.shapes.BLOCK_POINTS):
every point's value is the closed form's, whichever block it falls in."""

import numpy as np

from ibfem.geometry.solids import solid_from_dict


def test_distance_of_many_points_in_blocks_against_the_closed_form():
    """More points than one block of the distance (shapes.BLOCK_POINTS): inside the quarter of a
    lower half ball (convex: the distance is the nearest of its four faces), turned and moved or
    not, every point's distance is the closed form's, whichever block it falls in."""
    from ibfem.geometry.solids.shapes import BLOCK_POINTS

    profile = {"type": "profile", "edges": [
        {"type": "line", "start": [0, 0], "end": [1, 0], "name": "flat"},
        {"type": "arc", "center": [0, 0], "radius": 1, "start_angle": 0, "end_angle": -90, "name": "dome"},
        {"type": "line", "start": [0, -1], "end": [0, 0], "name": "axis"}]}
    ball = {"type": "revolution", "profile": profile, "axis_origin": [0, 0, 1], "axis": [0, 0, 1], "angle_deg": 90}
    rng = np.random.default_rng(5)
    n = 2 * BLOCK_POINTS + 123
    u = rng.normal(size=(n, 3))
    u[:, :2], u[:, 2] = np.abs(u[:, :2]), -np.abs(u[:, 2])
    p = np.array([0.0, 0.0, 1.0]) + u / np.linalg.norm(u, axis=1)[:, None] * rng.uniform(0, 1, (n, 1)) ** (1 / 3)
    exact = np.minimum.reduce([1.0 - np.linalg.norm(p - [0, 0, 1], axis=1), 1.0 - p[:, 2], p[:, 0], p[:, 1]])
    np.testing.assert_allclose(solid_from_dict(ball).signed_distance(p), exact, rtol=0, atol=1e-14)
    moved = solid_from_dict({**ball, "rotate": {"axis": [1, 2, 3], "angle_deg": 40}, "translate": [0.5, -1, 2]})
    rot = moved.rotation
    np.testing.assert_allclose(moved.signed_distance(p @ rot.T + [0.5, -1, 2]), exact, rtol=0, atol=1e-13)
