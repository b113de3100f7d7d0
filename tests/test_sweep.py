"""Sweep (a curve extruded along a direction): projection against analytic surfaces
(plane, circular and elliptic cylinders) and dense sampling of the profile."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from ibfem import geometry
from ibfem.geometry import primitive_from_dict
from ibfem.geometry.sweep import Sweep

RNG = np.random.default_rng(7)
W = np.sqrt(0.5)

QUARTER = {
    "type": "bspline_curve",
    "degree": 2,
    "knots": [0, 0, 0, 1, 1, 1],
    "control_points": [[2, 0, 0.5], [2, 2, 0.5], [0, 2, 0.5]],
    "weights": [1, W, 1],
}


def registered(kind):
    try:
        primitive_from_dict({"type": kind})
    except ValueError as exc:
        return "is not one of" not in str(exc)
    return True


def dense_section_distance(sweep, p, n=100_001):
    """Brute force: distance in the plane normal to d between p and densely sampled profile points."""
    d = sweep.direction
    prof = sweep.profile
    if prof.type == "bspline_curve":
        a, b = prof.domain
        pts = prof.derivatives(np.linspace(a, b, n), 0)[0]
    else:
        pts = sweep._profile_points(np.linspace(-np.pi, np.pi, n))
    flat = lambda x: x - np.outer(x @ d, d)  # noqa: E731
    return cKDTree(flat(pts)).query(flat(p))[0]


def check_generic(sweep, p):
    pr = sweep.project(p)
    # on the surface at the returned parameters, normal unit and perpendicular to d
    assert np.allclose(sweep.evaluate(pr.parameters), pr.points, atol=1e-12)
    assert np.allclose(np.linalg.norm(pr.normals, axis=1), 1.0)
    assert np.abs(pr.normals @ sweep.direction).max() < 1e-13
    r = p - pr.points
    assert np.abs(r @ sweep.direction).max() < 1e-12  # nothing left along the extrusion
    # signed Euclidean distances: |r| with the sign of r . normal
    assert np.allclose(np.abs(pr.distances), np.linalg.norm(r, axis=1), rtol=0, atol=1e-14)
    assert np.all(pr.distances * np.einsum("ij,ij->i", r, pr.normals) >= 0)
    assert np.all(np.linalg.norm(r, axis=1) <= dense_section_distance(sweep, p) + 1e-12)
    return pr


def test_nurbs_quarter_circle_along_its_normal_is_an_exact_cylinder():
    s = primitive_from_dict({"type": "sweep", "profile": QUARTER, "direction": [0, 0, 3]})
    ang = RNG.uniform(0.01, np.pi / 2 - 0.01, 2000)
    rho = RNG.uniform(0.1, 4.0, 2000)
    z = RNG.uniform(-5, 5, 2000)
    p = np.c_[rho * np.cos(ang), rho * np.sin(ang), z]
    pr = check_generic(s, p)
    # S_t x S_h points away from the axis for this counter-clockwise profile and d = +z
    assert np.allclose(pr.distances, rho - 2.0, rtol=1e-12, atol=1e-12)
    assert np.allclose(pr.points[:, 2], z, atol=1e-14)
    assert np.allclose(pr.parameters[:, 1], z - 0.5, atol=1e-13)  # h measured from the profile


def test_bspline_profile_oblique_direction_and_ends():
    s = Sweep(profile=QUARTER, direction=[0.4, -0.3, 1.0])
    p = RNG.uniform([-1.0, -1.0, -3.0], [3.0, 3.0, 3.0], (1500, 3))
    pr = check_generic(s, p)
    assert np.any(pr.parameters[:, 0] == 0.0) and np.any(pr.parameters[:, 0] == 1.0)
    # interior: first-order optimality along the profile
    inner = (pr.parameters[:, 0] > 1e-9) & (pr.parameters[:, 0] < 1 - 1e-9)
    St = s.profile.derivatives(pr.parameters[inner, 0], 1)[1]
    tangential = np.einsum("ij,ij->i", p[inner] - pr.points[inner], St) / np.linalg.norm(St, axis=1)
    assert np.abs(tangential).max() < 2e-12 * s._section.scale  # Newton stops at 1e-12 of the size


def test_line_profile_is_a_plane():
    if not registered("line"):
        pytest.skip("line primitive not available")
    line = {"type": "line", "origin": [1, 2, 3], "direction": [1, 1, 0]}
    s = primitive_from_dict({"type": "sweep", "profile": line, "direction": [0, 0.5, 1]})
    u = np.array([1, 1, 0]) / np.sqrt(2)
    d = np.array([0, 0.5, 1]) / np.linalg.norm([0, 0.5, 1])
    n = np.cross(u, d)
    n /= np.linalg.norm(n)
    p = RNG.uniform(-5, 5, (1000, 3))
    pr = check_generic(s, p)
    assert np.allclose(pr.normals, n, atol=1e-14)
    assert np.allclose(pr.distances, (p - [1, 2, 3]) @ n, atol=1e-12)


@pytest.mark.parametrize("normal_sign", [1.0, -1.0])
def test_circle_profile_along_its_axis_is_a_cylinder(normal_sign):
    if not registered("circle"):
        pytest.skip("circle primitive not available")
    s = Sweep(
        profile={"type": "circle", "origin": [1, -1, 2], "normal": [0, 0, normal_sign], "radius": 1.5},
        direction=[0, 0, 1],
    )
    p = RNG.uniform(-4, 4, (2000, 3))
    pr = check_generic(s, p)
    rho = np.linalg.norm(p[:, :2] - [1, -1], axis=1)
    assert np.allclose(pr.distances, rho - 1.5, rtol=1e-12, atol=1e-12)  # away from the axis


@pytest.mark.parametrize("kind", ["circle", "ellipse"])
def test_tilted_conic_profile_is_an_elliptic_cylinder(kind):
    if not registered(kind):
        pytest.skip(f"{kind} primitive not available")
    prof = (
        {"type": "circle", "origin": [0.5, 0, 1], "normal": [0, 0.6, 0.8], "radius": 2.0}
        if kind == "circle"
        else {
            "type": "ellipse",
            "origin": [0.5, 0, 1],
            "normal": [0.2, 0.6, 0.8],
            "major_axis": [1, 0, 0],
            "major_radius": 3.0,
            "minor_radius": 1.0,
        }
    )
    s = Sweep(profile=prof, direction=[0.1, 0.0, 1.0])
    p = RNG.uniform(-5, 5, (2000, 3))
    pr = check_generic(s, p)
    # first-order optimality: the residual is orthogonal to S_t = C'(theta)
    c, A, B, _, _ = s._conic
    t = pr.parameters[:, 0]
    St = -np.sin(t)[:, None] * A + np.cos(t)[:, None] * B
    assert np.abs(np.einsum("ij,ij->i", p - pr.points, St)).max() < 1e-11 * np.linalg.norm(A)
    # away from the axis: the normal points from the axis line towards the surface point
    axis_foot = s._conic[3] + np.outer(pr.points @ s.direction, s.direction)
    assert np.all(np.einsum("ij,ij->i", pr.points - axis_foot, pr.normals) > 0)


def test_offset_and_project_back():
    s = Sweep(profile=QUARTER, direction=[0.2, 0.1, 1.0])
    th = np.c_[RNG.uniform(0.05, 0.95, 1000), RNG.uniform(-2, 2, 1000)]
    S = s.evaluate(th)
    first = s.project(S)
    delta = RNG.uniform(-0.5, 0.5, 1000)
    pr = s.project(S + delta[:, None] * first.normals)
    assert np.allclose(pr.points, S, atol=1e-12)
    assert np.allclose(pr.parameters, th, atol=1e-10)
    assert np.allclose(pr.distances, delta, atol=1e-12)
    assert np.allclose(pr.normals, first.normals, atol=1e-12)


def test_round_trip():
    profiles = [QUARTER] + [
        prof
        for kind, prof in (
            ("line", {"type": "line", "origin": [0, 0, 0], "direction": [1, 0, 0]}),
            ("circle", {"type": "circle", "origin": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0}),
        )
        if registered(kind)
    ]
    p = RNG.uniform(-2, 2, (20, 3))
    for prof in profiles:
        s = primitive_from_dict({"type": "sweep", "profile": prof, "direction": [0, 1, 2]})
        d = s.to_dict()
        again = geometry.primitive_from_dict(d)
        assert isinstance(again, Sweep) and again.to_dict() == d
        assert np.array_equal(again.project(p).distances, s.project(p).distances)


@pytest.mark.parametrize(
    "definition, field",
    [
        ({"type": "sweep", "direction": [0, 0, 1]}, "profile"),
        ({"type": "sweep", "profile": QUARTER}, "direction"),
        ({"type": "sweep", "profile": QUARTER, "direction": [0, 0, 0]}, "direction"),
        ({"type": "sweep", "profile": {**QUARTER, "degree": 0}, "direction": [0, 0, 1]}, "profile"),
        ({"type": "sweep", "profile": [1, 2, 3], "direction": [0, 0, 1]}, "profile"),
        (
            {
                "type": "sweep",
                "profile": {"type": "bspline_curve", "degree": 1, "knots": [0, 0, 1, 1], "control_points": [[0, 0, 0], [0, 0, 1]]},
                "direction": [0, 0, 1],
            },
            "profile",
        ),
    ],
)
def test_invalid_definitions(definition, field):
    with pytest.raises(ValueError, match=field):
        primitive_from_dict(definition)


def test_degenerate_analytic_profiles_rejected():
    if registered("plane"):
        with pytest.raises(ValueError, match="profile"):
            Sweep(profile={"type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1]}, direction=[0, 0, 1])
    if registered("line"):
        with pytest.raises(ValueError, match="profile"):
            Sweep(profile={"type": "line", "origin": [0, 0, 0], "direction": [0, 0, 2]}, direction=[0, 0, 1])
    if registered("circle"):
        with pytest.raises(ValueError, match="profile"):
            Sweep(profile={"type": "circle", "origin": [0, 0, 0], "normal": [1, 0, 0], "radius": 1}, direction=[0, 0, 1])
