"""The parser on the shipped part studios: geometry, topology and orientation checked
against invariants of a closed solid and the design values of each studio, and the two
wire formats giving the same Part."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.importers.onshape import load_part
from test_onshape_support import FIXTURES, STUDIOS, body_volume, cached_part, generator, missing_primitives


def _skip_if_missing(studio):
    missing = missing_primitives(studio)
    if missing:
        pytest.skip(f"primitives not registered yet: {missing}")


def winding_number(points, tris):
    """Generalised winding number of points w.r.t. a triangle soup (van Oosterom and
    Strackee's solid angle, vectorised): ~1 inside a closed outward-wound surface, ~0 outside."""
    a = tris[None, :, 0, :] - points[:, None, :]
    b = tris[None, :, 1, :] - points[:, None, :]
    c = tris[None, :, 2, :] - points[:, None, :]
    la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
    num = np.einsum("pti,pti->pt", a, np.cross(b, c))
    den = la * lb * lc + np.einsum("pti,pti->pt", a, b) * lc + np.einsum("pti,pti->pt", b, c) * la \
        + np.einsum("pti,pti->pt", c, a) * lb
    return np.sum(2 * np.arctan2(num, den), axis=1) / (4 * math.pi)


# design values of the studios (fixtures/onshape/README.md), volumes of the exact solids
def _expected_volumes():
    pi, t15 = math.pi, math.tan(math.radians(15))
    half_cyl = pi * 0.05**2 / 2 * 0.02
    block = 0.2 * 0.1 * 0.02
    a, b, h, rc, r, rho = 0.04, 0.03, 0.02, 0.006, 0.01, 0.003
    spandrel = rho**2 * (1 - pi / 4)
    spandrel_x = r + rho * (10 - 3 * pi) / (12 - 3 * pi)  # centroid of the fillet's removed corner
    fa, fb, fh, fd = 0.03, 0.02, 0.01, 0.004
    r0, k, H = 0.008, 0.003, 0.02
    return {
        "half_cylinder_on_block": {"Half cylinder": half_cyl, "Block": block},
        "half_ellipse_on_block": {"Half ellipse": pi * 0.05 * 0.025 / 2 * 0.02, "Block": block},
        "cylinder_on_v_groove": {"Half cylinder": half_cyl, "V-groove block": (0.02 - 0.06 * 0.06 * t15) * 0.02},
        "cylinder_in_concave_seat": {"Half cylinder": half_cyl,
                                     "Concave seat": (0.2 * 0.12 - (0.01 * math.acos(0.8) - 0.08 * 0.06)) * 0.02},
        "elliptical_extrusion": {"Elliptical prism": pi * 0.03 * 0.015 * 0.02},
        "cone_sphere": {"Cone with sphere cap": pi * 0.03 * (0.01**2 + 0.01 * 0.02 + 0.02**2) / 3 + 2 / 3 * pi * 0.02**3,
                        "Ball": 4 / 3 * pi * 0.012**3},
        "block_hole_fillet": {"Block with hole": (4 * a * b - (4 - pi) * rc**2) * h - pi * r**2 * h
                              - 2 * pi * spandrel * spandrel_x},
        "freeform": {"Free-form block": 4 * fa * fb * fh + fd * (4 * fa / 3) * (4 * fb / 3),
                     "Knob": pi * (r0**2 * H + 4 * r0 * k * H / pi + k**2 * H / 2)},
    }


EXPECTED = _expected_volumes()


def test_every_studio_is_documented_and_there_are_enough():
    readme = (FIXTURES / "README.md").read_text()
    assert len(STUDIOS) >= 8
    for s in STUDIOS:
        assert f"`{s}`" in readme


def test_both_wire_formats_are_shipped():
    fmts = {cached_part(s).metadata["wire_format"]["tessellatedfaces.json"] for s in STUDIOS}
    assert fmts == {"A", "B"}


@pytest.mark.parametrize("studio", sorted(EXPECTED))
def test_body_volumes_match_the_design(studio):
    """Divergence theorem over the welded, outward-wound face meshes against the exact
    volume (the tessellation's chordal error is below 1 %)."""
    part = cached_part(studio)
    names = {b.name: b.id for b in part.bodies.values()}
    assert set(names) == set(EXPECTED[studio])
    for name, volume in EXPECTED[studio].items():
        assert body_volume(part, names[name]) == pytest.approx(volume, rel=1e-2)


@pytest.mark.parametrize("studio", STUDIOS)
def test_every_face_points_out_of_its_body(studio):
    part = cached_part(studio)
    for body in part.bodies.values():
        soup = np.vstack([np.asarray(part.faces[f].mesh.vertices)[np.asarray(part.faces[f].mesh.faces)]
                          for f in body.face_ids])
        size = float(np.ptp(soup.reshape(-1, 3), axis=0).max())
        probes, expected = [], []
        for fid in body.face_ids:
            m = part.faces[fid].mesh
            P = np.asarray(m.vertices)[np.asarray(m.faces)]
            cent = P.mean(axis=1)
            k = int(np.argmin(np.linalg.norm(cent - np.asarray(m.vertices).mean(axis=0), axis=1)))
            n = np.cross(P[k, 1] - P[k, 0], P[k, 2] - P[k, 0])
            n /= np.linalg.norm(n)
            eps = 2e-3 * size
            probes += [cent[k] + eps * n, cent[k] - eps * n]
            expected += [0.0, 1.0]
            face = part.faces[fid]
            if face.surface is not None:  # orientation agrees with the winding
                sn = face.surface.project(cent[k:k + 1]).normals[0] * face.orientation
                assert np.dot(sn, n) > 0.99, fid
        w = winding_number(np.array(probes), soup)
        assert np.allclose(w, expected, atol=0.05), (studio, body.id, w)


@pytest.mark.parametrize("studio", STUDIOS)
def test_topology_of_closed_solids(studio):
    part = cached_part(studio)
    for body in part.bodies.values():
        uses: dict[str, int] = {}
        for fid in body.face_ids:
            face = part.faces[fid]
            assert sum(1 for lp in face.loops if lp.is_outer) <= 1
            for loop in face.loops:
                chain = []
                for co in loop.coedges:
                    assert co.edge_id in body.edge_ids
                    uses[co.edge_id] = uses.get(co.edge_id, 0) + 1
                    e = part.edges[co.edge_id]
                    chain.append((e.start, e.end) if co.same_sense else (e.end, e.start))
                # each coedge ends where the next begins
                for (s0, e0), (s1, e1) in zip(chain, chain[1:] + chain[:1]):
                    assert np.linalg.norm(e0 - s1) < 1e-12
        # a closed manifold solid uses every edge exactly twice
        assert set(uses) == set(body.edge_ids)
        assert all(n == 2 for n in uses.values()), uses


@pytest.mark.parametrize("studio", STUDIOS)
def test_loops_run_with_the_face_on_their_left(studio):
    """Planar faces: the outer loop is counter-clockwise about the outward normal, holes
    clockwise (coedge senses + polylines + orientation together)."""
    part = cached_part(studio)
    for face in part.faces.values():
        if face.surface_type != "PLANE" or not face.loops:
            continue
        n = face.surface.project(np.asarray(face.mesh.vertices[:1])).normals[0] * face.orientation
        for loop in face.loops:
            pts = []
            for co in loop.coedges:
                pl = part.edges[co.edge_id].polyline
                pts.append(pl if co.same_sense else pl[::-1])
            P = np.vstack(pts)
            area = 0.5 * np.dot(np.sum(np.cross(P, np.roll(P, -1, axis=0)), axis=0), n)
            assert (area > 0) == loop.is_outer, (face.id, area)


@pytest.mark.parametrize("studio", STUDIOS)
def test_edges_lie_on_their_curves_and_faces(studio):
    _skip_if_missing(studio)
    part = cached_part(studio)
    for edge in part.edges.values():
        assert len(edge.polyline) >= 2
        pts = np.vstack([edge.polyline, edge.start, edge.end])
        if edge.curve is not None:
            assert np.max(np.abs(edge.curve.project(pts).distances)) < 1e-12, edge.id
            assert np.max(np.linalg.norm(edge.curve.project(pts).points - pts, axis=1)) < 1e-12
        else:
            assert edge.curve_type == "ICURVE"
    for face in part.faces.values():
        if face.surface is None:
            continue
        for loop in face.loops:
            for co in loop.coedges:
                d = face.surface.project(part.edges[co.edge_id].polyline).distances
                assert np.max(np.abs(d)) < 1e-12, (face.id, co.edge_id)


def test_tessellation_only_faces_and_edges_are_kept_and_reported():
    part = cached_part("freeform")
    only = {f.surface_type for f in part.tessellation_only_faces()}
    assert only == {"BSURFACE", "SPUN"}
    assert all(f.mesh is not None and len(f.mesh.faces) > 0 for f in part.tessellation_only_faces())
    assert part.edges_by_type()["ICURVE"] == 2
    text = "\n".join(part.warnings)
    for kind in ("BSURFACE", "SPUN", "ICURVE"):
        assert kind in text


def test_meshes_are_welded_and_indexed():
    part = cached_part("half_cylinder_on_block")
    for face in part.faces.values():
        m = face.mesh
        V = np.asarray(m.vertices)
        assert len(np.unique(V, axis=0)) == len(V)  # no duplicate vertices
        # a welded strip shares vertices: far fewer vertices than facet corners
        assert len(V) < 3 * len(m.faces)
        # each face is one connected piece of surface
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        F = np.asarray(m.faces)
        i = np.concatenate([F[:, 0], F[:, 1], F[:, 2]])
        j = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
        graph = coo_matrix((np.ones(len(i)), (i, j)), shape=(len(V), len(V)))
        assert connected_components(graph, directed=False)[0] == 1


def _same_part(p, q):
    assert p.bodies.keys() == q.bodies.keys()
    assert p.faces.keys() == q.faces.keys() and p.edges.keys() == q.edges.keys()
    for fid, f in p.faces.items():
        g = q.faces[fid]
        assert (f.surface_type, f.orientation, f.body_id, f.loops) == (g.surface_type, g.orientation, g.body_id, g.loops)
        assert (f.surface is None) == (g.surface is None)
        if f.surface is not None:
            a, b = f.surface.to_dict(), g.surface.to_dict()
            assert a.keys() == b.keys()
            for k in a:
                assert np.allclose(np.asarray(a[k], dtype=float) if not isinstance(a[k], (str, dict)) else 0,
                                   np.asarray(b[k], dtype=float) if not isinstance(b[k], (str, dict)) else 0,
                                   rtol=0, atol=1e-15), (fid, k)
        assert np.array_equal(f.mesh.vertices, g.mesh.vertices)
        assert np.array_equal(f.mesh.faces, g.mesh.faces)
        assert np.array_equal(f.vertex_normals, g.vertex_normals)
    for eid, e in p.edges.items():
        d = q.edges[eid]
        assert (e.curve_type, e.length) == (d.curve_type, d.length)
        assert np.array_equal(e.polyline, d.polyline) and np.array_equal(e.start, d.start)


@pytest.mark.parametrize("studio,fmt,indexed", [
    ("half_cylinder_on_block", "B", False),  # shipped as A, inline vertices
    ("cylinder_on_v_groove", "A", False),  # shipped as B with an index table
    ("cone_sphere", "A", True),  # shipped as B, inline
])
def test_both_wire_formats_give_the_same_part(tmp_path, studio, fmt, indexed):
    _skip_if_missing(studio)
    generator().write_studio(studio, tmp_path / "other", fmt=fmt, indexed=indexed)
    other = load_part(tmp_path / "other")
    shipped = cached_part(studio)
    assert other.metadata["wire_format"]["bodydetails.json"] == fmt
    assert shipped.metadata["wire_format"]["bodydetails.json"] != fmt
    _same_part(shipped, other)


def test_the_shipped_fixtures_are_what_the_generator_writes(tmp_path):
    """The fixtures are reproducible from fixtures/onshape/make_fixtures.py."""
    generator().write_studio("cylinder_on_v_groove", tmp_path / "s")
    for name in ("tessellatedfaces.json", "tessellatededges.json", "bodydetails.json"):
        assert (tmp_path / "s" / name).read_bytes() == (FIXTURES / "cylinder_on_v_groove" / name).read_bytes()


def test_metadata_carries_the_source_and_microversion():
    part = cached_part("half_cylinder_on_block")
    src = part.metadata["source"]
    assert src["microversion"] == part.metadata["microversion"]
    assert src["url"].startswith("https://") and "/documents/" in src["url"]
