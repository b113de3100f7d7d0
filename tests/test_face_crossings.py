"""A planar region's lines (geometry.solids.faces.PlanarRegionFace): the ends of their inside
intervals are the exact crossings of the profile's boundary (here a disc and an annulus: closed
forms), found by bisection with several steps per call of the distance."""

import numpy as np

from ibfem.geometry.shapes import profile_from_shape
from ibfem.geometry.solids import faces
from ibfem.geometry.solids.faces import PlanarRegionFace


def _region(shape):
    return PlanarRegionFace("cap", profile_from_shape(shape), [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1])


def test_line_ends_are_the_disc_chords_in_few_calls(monkeypatch):
    region = _region({"type": "disk", "center": [0.3, -0.2], "radius": 0.7})
    calls = [0]
    distance = region.profile.signed_distance

    def counting(p):
        calls[0] += 1
        return distance(p)

    monkeypatch.setattr(region.profile, "signed_distance", counting)
    y = np.linspace(-0.85, 0.45, 23)[1:-1]  # strictly inside the disc's range of p1
    ends = region._intervals(y, 0.05)
    half = np.sqrt(0.7**2 - (y + 0.2) ** 2)
    for k, e in enumerate(ends):
        np.testing.assert_allclose(e, [0.3 - half[k], 0.3 + half[k]], rtol=0, atol=2e-15)
    # one sampling call, then BISECTION_LEVELS steps per call (one step per call took 55)
    assert calls[0] <= 1 + -(-faces.BISECTION_STEPS // faces.BISECTION_LEVELS)


def test_annulus_lines_have_two_intervals():
    def circle(radius, name):
        return [{"type": "arc", "center": [0, 0], "radius": radius, "start_angle": 0, "end_angle": 180,
                 "name": name + "0"},
                {"type": "arc", "center": [0, 0], "radius": radius, "start_angle": 180, "end_angle": 360,
                 "name": name + "1"}]

    region = _region({"type": "profile", "edges": circle(1.0, "outer"), "holes": [circle(0.4, "inner")]})
    y = np.array([-0.3, 0.0001, 0.25])
    for k, e in enumerate(region._intervals(y, 0.05)):
        outer, inner = np.sqrt(1.0 - y[k] ** 2), np.sqrt(0.16 - y[k] ** 2)
        np.testing.assert_allclose(e, [-outer, -inner, inner, outer], rtol=0, atol=2e-15)
