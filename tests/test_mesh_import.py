"""STL/OBJ import into a tessellation-only Part, checked against the analytic volume and
area of the meshed solids."""

from __future__ import annotations

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

from ibfem.geometry.verify import verify_projection  # noqa: E402
from ibfem.importers.mesh import load_mesh_part  # noqa: E402
from test_onshape_support import body_volume  # noqa: E402


def _write(tmp_path, mesh, name):
    path = tmp_path / name
    mesh.export(str(path))
    return path


@pytest.mark.parametrize("name", ["box.stl", "box.obj"])
def test_box_round_trip(tmp_path, name):
    extents = (0.2, 0.1, 0.05)
    part = load_mesh_part(_write(tmp_path, trimesh.creation.box(extents=extents), name))
    assert len(part.bodies) == 1 and len(part.faces) == 1
    face = next(iter(part.faces.values()))
    assert face.surface is None and face.surface_type == "MESH" and not face.is_exact
    body = next(iter(part.bodies.values()))
    # binary STL stores float32 coordinates: 1e-7 relative
    assert body_volume(part, body.id) == pytest.approx(np.prod(extents), rel=1e-6)
    assert face.mesh.area == pytest.approx(2 * (0.02 + 0.01 + 0.005), rel=1e-6)
    assert face.mesh.is_watertight and not part.faces_by_type().keys() - {"MESH"}


def test_units_scale_and_verify_reports_tessellation_only(tmp_path):
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=10.0)  # "millimetres"
    part = load_mesh_part(_write(tmp_path, sphere, "ball.stl"), units_scale=1e-3)
    face = next(iter(part.faces.values()))
    radii = np.linalg.norm(face.mesh.vertices, axis=1)
    assert np.allclose(radii, 0.01, rtol=1e-6)
    report = verify_projection(part)
    assert report["tessellation_only_faces"] == 1 and report["faces"][0]["max_error"] is None
    assert report["faces"][0]["vertices"] == len(sphere.vertices)


def test_info_command_on_a_mesh(tmp_path, capsys):
    from ibfem.solver.cli import main

    path = _write(tmp_path, trimesh.creation.box(extents=(1, 1, 1)), "cube.stl")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "MESH" in out and "tessellation-only" in out and "12" in out  # 12 triangles


def test_bad_mesh_files(tmp_path):
    with pytest.raises(ValueError, match="no such mesh file"):
        load_mesh_part(tmp_path / "missing.stl")
    bad = tmp_path / "bad.stl"
    bad.write_text("solid nothing\nendsolid nothing\n")
    with pytest.raises(ValueError, match="bad.stl"):
        load_mesh_part(bad)
    with pytest.raises(ValueError, match="units_scale"):
        load_mesh_part(_write(tmp_path, trimesh.creation.box(), "b.stl"), units_scale=-1)
