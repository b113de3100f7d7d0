"""The exact surface points of the 3D contact region (solver.contact.ellipse_geometry.surface_point)
against closed forms: the line y + t n enters a ball |x - c| <= R first at
t = n.(c - y) - sqrt((n.(c - y))^2 - |c - y|^2 + R^2) (z = c - sqrt(R^2 - r^2) for a vertical
line). The fast path (a secant from the tangent plane, certified as the first entry) must take few
distance evaluations and agree to 1e-12 reach; lines it cannot certify (a quarter model's symmetry
planes, a body re-entered below the contact surface, no surface at all) keep the scan's answers."""

import math

import numpy as np
import pytest

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.contact.ellipse_geometry import ContactFrame3D, surface_point

REACH = 0.03


class Counting:
    """A solid's signed distance, counting the points asked."""

    def __init__(self, solid):
        self.solid, self.points = solid, 0

    def signed_distance(self, x):
        x = np.asarray(x, float).reshape(-1, 3)
        self.points += len(x)
        return self.solid.signed_distance(x)


def _frame(point, normal, hint=(1.0, 0.0, 0.0)):
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    a0 = np.asarray(hint, float) - (np.asarray(hint, float) @ n) * n
    a0 /= np.linalg.norm(a0)
    return ContactFrame3D(point=np.asarray(point, float), normal=n, axes=np.array([a0, np.cross(n, a0)]),
                          curvatures=np.ones(2))


def _entry(y, n, c, radius):
    """Where the lines y + t n (n unit) first enter the ball |x - c| <= radius: t (m,)."""
    w = np.asarray(c, float) - y
    b = w @ n
    return b - np.sqrt(b**2 - np.einsum("ij,ij->i", w, w) + radius**2)


def _disc(count, radius, seed=0):
    rng = np.random.default_rng(seed)
    r, th = radius * np.sqrt(rng.uniform(0, 1, count)), rng.uniform(0, 2 * math.pi, count)
    return np.column_stack([r * np.cos(th), r * np.sin(th)])


@pytest.mark.parametrize("normal", [(0, 0, 1), (0.3, -0.2, 1.0)])
def test_a_sphere_s_points_are_the_closed_form_from_the_fast_path(normal):
    centre, radius = np.array([0.1, -0.2, 1.0]), 1.0
    ball = Counting(solid_from_dict({"type": "sphere", "center": centre.tolist(), "radius": radius}))
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    frame = _frame(centre - radius * n, n)
    s = _disc(400, 0.05)
    x1, ok = surface_point(ball, frame, s, REACH)
    y = frame.point + s @ frame.axes
    assert ok.all()
    np.testing.assert_allclose(x1, y + _entry(y, n, centre, radius)[:, None] * n, rtol=0, atol=1e-12 * REACH)
    assert ball.points < 20 * len(s)  # the scan alone asks 33 per line


def test_steep_lines_on_a_half_sphere_are_exact():
    """Lines 0.1 R to 0.7 R off the pole (the surface up to 44 degrees from the plane): the secant's
    slope sets how far apart the certifying samples may lie."""
    half = solid_from_dict({"type": "half_sphere", "center": [0, 0, 1], "radius": 1.0, "side": "below"})
    frame = _frame([0, 0, 0], [0, 0, 1])
    r = np.linspace(0.1, 0.7, 25)
    s = np.column_stack([r * math.cos(0.3), r * math.sin(0.3)])
    x1, ok = surface_point(half, frame, s, 0.5)
    assert ok.all()
    np.testing.assert_allclose(x1[:, 2], 1.0 - np.sqrt(1.0 - r**2), rtol=0, atol=1e-12 * 0.5)


def test_a_quarter_model_s_symmetry_planes_and_outside():
    """The quarter ball of examples/solid/sphere_on_flat.toml (a quarter disc turned by 90 degrees):
    points exactly on its symmetry planes and on its axis are on the dome (z = 1 - sqrt(1 - r^2));
    points a hair (1e-6 m) or more outside the quarter have no surface."""
    ball = solid_from_dict({"type": "revolution", "axis_origin": [0, 0, 1], "axis": [0, 0, 1], "angle_deg": 90,
                            "profile": {"type": "profile", "edges": [
                                {"type": "line", "start": [0, 0], "end": [1, 0], "name": "flat"},
                                {"type": "arc", "center": [0, 0], "radius": 1, "start_angle": 0, "end_angle": -90,
                                 "name": "dome"},
                                {"type": "line", "start": [0, -1], "end": [0, 0], "name": "axis"}]}})
    frame = _frame([0, 0, 0], [0, 0, 1])
    r = np.linspace(0.0, 0.05, 11)
    zero = np.zeros_like(r)
    on_planes = np.concatenate([np.column_stack([r, zero]), np.column_stack([zero, r])])
    inside = np.abs(_disc(200, 0.05, seed=1))
    outside = np.concatenate([np.column_stack([r[1:], np.full(10, -1e-6)]), -np.abs(_disc(50, 0.05, seed=2)) - 1e-4])
    s = np.concatenate([on_planes, inside, outside])
    x1, ok = surface_point(ball, frame, s, REACH)
    m = len(on_planes) + len(inside)
    assert ok[:m].all() and not ok[m:].any()
    z = 1.0 - np.sqrt(1.0 - np.einsum("ij,ij->i", s[:m], s[:m]))
    k = len(on_planes)
    np.testing.assert_allclose(x1[k:m, 2], z[k:], rtol=0, atol=1e-12 * REACH)
    # along a symmetry plane the distance is 0 (to its round-off, |phi| <= 1e-12 reach counts as 0)
    # above the dome: the point is that band's lower end, where phi = -1e-12 reach
    np.testing.assert_allclose(x1[:k, 2], z[:k], rtol=0, atol=1.5e-12 * REACH)
    np.testing.assert_array_equal(x1[:, :2], s)


class BallOverSlab:
    """A ball resting above the contact plane and a thin slab 0.4 reach to 0.35 reach below it
    (their union): going up, a line enters the slab first."""

    def __init__(self, z0, z1):
        self.z0, self.z1 = z0, z1

    def signed_distance(self, x):
        x = np.asarray(x, float).reshape(-1, 3)
        ball = 1.0 - np.linalg.norm(x - [0.0, 0.0, 1.0], axis=1)
        slab = np.minimum(x[:, 2] - self.z0, self.z1 - x[:, 2])
        return np.maximum(ball, slab)


def test_a_body_entered_below_the_contact_surface_is_entered_there():
    solid = BallOverSlab(-0.4 * REACH, -0.35 * REACH)
    s = _disc(50, 0.05, seed=3)
    x1, ok = surface_point(solid, _frame([0, 0, 0], [0, 0, 1]), s, REACH)
    assert ok.all()
    np.testing.assert_allclose(x1[:, 2], -0.4 * REACH, rtol=0, atol=1e-12 * REACH)
