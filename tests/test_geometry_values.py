"""Field values of shapes and profile edges: numbers given as strings or
bools, and names given as lists or tables, are refused with the key named (before: silently
converted, or a TypeError 'unhashable type')."""

from __future__ import annotations

import numpy as np
import pytest

from ibfem.geometry import primitive_from_dict
from ibfem.geometry.bounded import bounded_curve_from_dict
from ibfem.geometry.shapes import profile_from_shape


@pytest.mark.parametrize("d, words", [
    ({"type": "disk", "center": ["1", "2"], "radius": 1.0}, "shape.center must be a list of 2 numbers"),
    ({"type": "disk", "center": [True, 0], "radius": 1.0}, "shape.center must be a list of 2 numbers"),
    ({"type": "disk", "center": [0, 0], "radius": "1"}, "shape.radius must be a number, got '1'"),
    ({"type": "disk", "center": [0, 0], "radius": True}, "shape.radius must be a number, got True"),
    ({"type": "disk", "center": [0, 0], "radius": 1.0, "rotate_deg": "30"}, "shape.rotate_deg must be a number"),
    ({"type": ["disk"], "center": [0, 0], "radius": 1.0}, "shape.type must be a string"),
    ({"type": "half_disk", "center": [0, 0], "radius": 1.0, "side": ["below"]}, "shape.side must be one of"),
    ({"type": "half_disk", "center": [0, 0], "radius": 1.0, "side": {}}, "shape.side must be one of"),
])
def test_shape_values_of_the_wrong_kind(d, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        profile_from_shape(d)


@pytest.mark.parametrize("d, words", [
    ({"type": ["line"], "start": [0, 0], "end": [1, 0]}, "edge.type must be one of"),
    ({"type": "line", "start": [0, "0"], "end": [1, 0]}, "edge.start must be a list of 2 numbers"),
    ({"type": "arc", "center": [0, 0], "radius": 1, "start_angle": "0", "end_angle": 90}, "edge.start_angle must be a number"),
])
def test_edge_values_of_the_wrong_kind(d, words):
    with pytest.raises(ValueError, match=words):
        bounded_curve_from_dict(d)


def test_numpy_numbers_are_numbers():
    prof = profile_from_shape({"type": "disk", "center": np.array([0.0, 1.0]), "radius": np.int64(2)})
    assert prof.area == pytest.approx(4 * np.pi, rel=1e-12)


@pytest.mark.parametrize("kind", [
    {"type": "ellipse", "normal": [0, 0, 1], "major_axis": [1, 0, 0], "major_radius": 2.0, "minor_radius": 0.5},
    {"type": "circle", "normal": [0, 0, 1], "radius": 1.0},
    {"type": "sphere", "radius": 1.0},
    {"type": "torus", "axis": [0, 0, 1], "major_radius": 2.0, "minor_radius": 0.5},
])
def test_origins_whose_squares_overflow_are_refused_and_large_ones_stay_finite(kind):
    # make fuzz: an ellipse with origin [1e308, 0, 0] gave NaN distances for every point
    with pytest.raises(ValueError, match="origin"):
        primitive_from_dict({**kind, "origin": [1e308, 0, 0]})
    prim = primitive_from_dict({**kind, "origin": [1e99, 0, 0]})
    p = np.array([[0.001, 1e12, -1e6], [-1e12, 1e-12, -1e12], [1e99 + 1e85, 0.0, 3e85]])
    d = prim.project(p).distances
    assert np.all(np.isfinite(d))
    # the far points are about 1e99 away; the last is 3.2e85 from the origin, beyond the small shape
    np.testing.assert_allclose(np.abs(d[:2]), 1e99, rtol=1e-6)
