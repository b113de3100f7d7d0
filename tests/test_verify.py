"""Projection verification (thesis 4.2.7): every fixture passes the
acceptance tolerances, and the check detects known, analytically sized errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from ibfem.geometry import Face, Part, primitive_from_dict
from ibfem.geometry.verify import angle_between, verify_projection
from test_onshape_support import STUDIOS, cached_part, missing_primitives

POSITION_TOL, NORMAL_TOL = 1e-12, 1e-9


@pytest.mark.parametrize("studio", STUDIOS)
def test_every_fixture_meets_the_acceptance_tolerances(studio):
    missing = missing_primitives(studio)
    if missing:
        pytest.skip(f"primitives not registered yet: {missing}")
    part = cached_part(studio)
    for offset in (1e-4, -1e-4):  # outward, and into the solid
        report = verify_projection(part, offset)
        json.dumps(report)  # serialisable (the verify report is JSON)
        assert set(report) >= {"faces", "max_error"}
        assert len(report["faces"]) == len(part.faces)
        for row in report["faces"]:
            assert set(row) >= {"id", "type", "vertices", "max_error", "max_normal_error"}
            face = part.faces[row["id"]]
            assert row["vertices"] == len(face.mesh.vertices) > 0
            if face.surface is None:
                assert row["exact"] is False and row["max_error"] is None
            else:
                assert row["max_error"] <= POSITION_TOL, row
                assert row["max_normal_error"] <= NORMAL_TOL, row
                # the tessellation itself lies on the surface, and the CAD vertex normals agree
                assert row["max_vertex_distance"] <= POSITION_TOL
                assert row["max_vertex_normal_deviation"] <= NORMAL_TOL
        assert report["max_error"] <= POSITION_TOL


def test_tessellation_only_faces_are_reported():
    report = verify_projection(cached_part("freeform"))
    rows = {r["type"]: r for r in report["faces"] if not r["exact"]}
    assert set(rows) == {"BSURFACE", "SPUN"}
    assert all(r["max_error"] is None and r["vertices"] > 0 and "tessellation-only" in r["note"] for r in rows.values())
    assert report["tessellation_only_faces"] == 2
    assert report["by_type"]["BSURFACE"]["max_error"] is None


def _sphere_part(mesh_radius, surface_radius, orientation=1):
    import trimesh

    mesh = trimesh.creation.icosphere(subdivisions=3, radius=mesh_radius)
    sphere = primitive_from_dict({"type": "sphere", "origin": [0.0, 0.0, 0.0], "radius": surface_radius})
    part = Part()
    part.faces["F"] = Face(id="F", surface_type="SPHERE", surface=sphere, orientation=orientation, mesh=mesh)
    return part


def test_an_independent_mesh_on_its_surface_passes():
    """trimesh's icosphere (not our fixtures) has its vertices on the sphere."""
    report = verify_projection(_sphere_part(0.02, 0.02))
    assert report["max_error"] < 1e-16 and report["max_normal_error"] < 1e-13


def test_a_tessellation_off_its_surface_is_measured_exactly():
    # vertices on radius r, surface of radius r (1 + eps): every projected point lies eps r
    # from its vertex, whatever the offset direction
    r, eps = 0.02, 1e-6
    for offset in (1e-4, -1e-4):
        report = verify_projection(_sphere_part(r, r * (1 + eps)), offset)
        assert report["max_error"] == pytest.approx(r * eps, rel=1e-6)
        assert report["faces"][0]["max_vertex_distance"] == pytest.approx(r * eps, rel=1e-6)


class _TiltedPlane:
    """A plane z = 0 whose projection reports normals tilted by a known angle away from the
    query point's x side (a deliberately wrong primitive)."""

    def __init__(self, tilt):
        self.tilt = tilt
        self.plane = primitive_from_dict({"type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1]})

    def project(self, points):
        pr = self.plane.project(points)
        n = np.tile([0.0, 0.0, 1.0], (len(pr.points), 1))
        moved = np.abs(np.asarray(points)[:, 2]) > 0  # only off-surface queries are wrong
        n[moved] = [math.sin(self.tilt), 0.0, math.cos(self.tilt)]
        return type(pr)(points=pr.points, normals=n, distances=pr.distances)


def test_a_wrong_normal_is_measured_exactly():
    import trimesh

    mesh = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 2]], process=False)
    part = Part()
    part.faces["P"] = Face(id="P", surface_type="PLANE", surface=_TiltedPlane(1e-3), orientation=1, mesh=mesh)
    report = verify_projection(part)
    assert report["faces"][0]["max_normal_error"] == pytest.approx(1e-3, rel=1e-9)
    assert report["max_error"] == 0.0


def test_orientation_is_applied_to_the_offset():
    # orientation -1 means outward = minus the sphere normal: offsetting 'outward' then goes
    # towards the centre; with an offset beyond the radius the projection lands on the far
    # side, so the error is the diameter -- proof the orientation is used
    r = 0.01
    report = verify_projection(_sphere_part(r, r, orientation=-1), offset=1.5 * r)
    assert report["max_error"] == pytest.approx(2 * r, rel=1e-12)
    report = verify_projection(_sphere_part(r, r, orientation=1), offset=1.5 * r)
    assert report["max_error"] < 1e-16


def test_angle_between_is_accurate_for_tiny_angles():
    a = np.array([[1.0, 0.0, 0.0]])
    b = np.array([[math.cos(1e-12), math.sin(1e-12), 0.0]])
    assert angle_between(a, b)[0] == pytest.approx(1e-12, rel=1e-6)


@pytest.mark.parametrize("offset", [0.0, float("nan")])
def test_bad_offset_is_rejected(offset):
    with pytest.raises(ValueError, match="offset"):
        verify_projection(Part(), offset)
