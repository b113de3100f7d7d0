"""PartSolid's signed distance (geometry.solids.part_solid) on the cone-with-sphere-cap body of
fixtures/onshape/cone_sphere against the closed form of that solid of revolution.

Independent truth: the body is the frustum r <= r0 + z tan(alpha), 0 <= z <= H (r0 = 10 mm, R =
20 mm, H = 30 mm, fixtures/onshape/make_fixtures.py) capped by the hemisphere |x - (0, 0, H)| <= R,
z >= H. A solid of revolution is nearest to a point in the point's own meridian half-plane, so its
signed distance is the 2D distance in (r, z) to the profile's three curves (bottom segment, cone
line, quarter arc), positive inside. PartSolid finds it from the CAD faces' exact surfaces, the
trimmed-face test (the exact trimming edges near a face's boundary), the exact edges and the winding number, with
the trimmed test asked only of the face whose untrimmed foot is nearest: points near every face,
edge and vertex (the rim circles, the bottom's edge, the pole, the axis) exercise each branch."""

from pathlib import Path

import math

import numpy as np
import pytest

from ibfem.solver.io.scene import load_scene

FIXTURE = Path(__file__).resolve().parent.parent / "fixtures" / "onshape" / "cone_sphere"
R0, R, H = 0.01, 0.02, 0.03


def _segment_distance(q, a, b):
    e = b - a
    t = np.clip(((q - a) @ e) / (e @ e), 0.0, 1.0)
    return np.linalg.norm(q - a - t[:, None] * e, axis=1)


def exact_signed_distance(p, origin, axis):
    """In the body's own frame: ``origin`` the bottom's centre, ``axis`` towards the cap."""
    z = (p - origin) @ axis
    r = np.linalg.norm(p - origin - z[:, None] * axis, axis=1)
    q = np.stack([r, z], axis=1)
    bottom = _segment_distance(q, np.array([0.0, 0.0]), np.array([R0, 0.0]))
    cone = _segment_distance(q, np.array([R0, 0.0]), np.array([R, H]))
    phi = np.arctan2(z - H, r)  # the arc spans angles 0 .. 90 degrees about (0, H)
    on_arc = (phi >= 0.0) & (phi <= math.pi / 2)
    arc = np.where(on_arc, np.abs(np.hypot(r, z - H) - R),
                   np.minimum(np.hypot(r - R, z - H), np.hypot(r, z - H - R)))
    d = np.minimum(np.minimum(bottom, cone), arc)
    inside = np.where(z <= H, (z >= 0.0) & (r <= R0 + z * (R - R0) / H), np.hypot(r, z - H) <= R)
    return np.where(inside, d, -d)


@pytest.fixture(scope="module")
def solid():
    scene = {"model": "solid", "name": "cone",
             "materials": [{"name": "steel", "youngs_modulus": 2e11, "poissons_ratio": 0.3}],
             "bodies": [{"name": "cone", "material": "steel", "element_size": 0.01,
                         "shape": {"type": "onshape", "path": str(FIXTURE), "body": "Cone with sphere cap"}}],
             "boundary_conditions": [{"type": "fixed", "body": "cone", "face": "JIU"}]}
    return load_scene(scene, label="cone.json").problem.bodies[0].profile


def test_signed_distance_matches_the_solid_of_revolution(solid):
    # the studio stands the body on its bottom at (0, 0, 0.02) with the axis along -y: the CAD
    # data's cone (origin and axis) says where; the local points below are placed in that frame
    cone = solid.faces["JIS"].surface
    origin, axis = np.asarray(cone.origin, float), np.asarray(cone.axis, float)
    e1 = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    frame = np.stack([e1, np.cross(axis, e1), axis])  # rows: local x, y, z
    rng = np.random.default_rng(7)
    box = rng.uniform([-0.03, -0.03, -0.01], [0.03, 0.03, 0.06], size=(4000, 3))
    # near the features: the rims (z = 0, r = r0; z = H, r = R), the pole and the bottom's centre
    t = rng.uniform(0, 2 * math.pi, 3000)
    rims = np.concatenate([np.stack([R0 * np.cos(t[:1000]), R0 * np.sin(t[:1000]), 0 * t[:1000]], 1),
                           np.stack([R * np.cos(t[1000:2000]), R * np.sin(t[1000:2000]), H + 0 * t[1000:2000]], 1),
                           np.tile([[0.0, 0.0, H + R]], (500, 1)), np.tile([[0.0, 0.0, 0.0]], (500, 1))])
    near = rims + rng.normal(scale=1e-3, size=rims.shape)
    p = origin + np.concatenate([box, near]) @ frame
    got = np.asarray(solid.signed_distance(p), float)
    want = exact_signed_distance(p, origin, axis)
    # the trimmed-face test judges feet near a face's trimming curves by the exact edges (not the
    # tessellation's band), so the distance is the solid of revolution's to round-off
    err = np.abs(got - want)
    assert err.max() <= 1e-12, (err.max(), solid.tolerance)
