"""Body 1's contact face about the contact point, read at set-up (solver.contact.face_shape): a
torus's ring direction is flat (its relative curvature 0, the line of its contact a circle of
the ring's radius), a flat face with a hole or a notch is not star-shaped about a point that
does not see it whole (the rays that leave the face and enter it again, against the circle's and
the polygon's own geometry), and the scenes that take such faces are refused before any solve
with what is wrong and what to do."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.contact.ellipse_geometry import contact_frame_3d
from ibfem.solver.contact.face_shape import face_rays, line_bend, on_face, resumed_rays
from ibfem.solver.contact.star_region import _whole_face

SCENES = Path(__file__).resolve().parent / "scenes"
RING, TUBE = 0.5, 0.1  # the torus's ring and tube radii
BLOCK = {"type": "box", "min": [-0.8, -0.8, -0.3], "max": [0.8, 0.8, 0.0]}


def _half_torus():
    """The lower half of a torus (tube radius 0.1 about a circle of radius 0.5 at z = 0.1) closed by
    a flat top: its bottom circle of radius 0.5 touches z = 0."""
    return solid_from_dict({"type": "revolution", "axis_origin": [0, 0, TUBE], "axis": [0, 0, 1], "profile": {
        "type": "profile", "edges": [
            {"type": "line", "start": [RING - TUBE, 0], "end": [RING + TUBE, 0], "name": "flat"},
            {"type": "arc", "center": [RING, 0], "radius": TUBE, "start_angle": 0, "end_angle": -180,
             "name": "tube"}]}})


@pytest.mark.parametrize("angle", [0.0, 37.0])
def test_a_torus_ring_direction_is_flat(angle):
    """At a point of the bottom circle the torus curves 1/0.1 across the ring and not at all along
    it (the circle lies in the plane z = 0, its curvature vector in the tangent plane): the
    relative curvatures on a flat are 0 and 10 1/m, the smaller along the ring."""
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    frame = contact_frame_3d(_half_torus(), solid_from_dict(BLOCK), np.array([RING * c, RING * s, 0.0]), 0.00625)
    k0, k1 = frame.curvatures
    assert abs(k0) <= 1e-6 * k1
    assert k1 == pytest.approx(1.0 / TUBE, rel=1e-5)
    assert abs(frame.axes[0] @ np.array([-s, c, 0.0])) == pytest.approx(1.0, abs=1e-9)


def test_line_bend_of_a_torus_and_of_a_roller():
    """The valley of the gap along the line: on the torus the bottom circle, whose curvature in
    the tangent plane is 1/0.5 (read within 1e-5 over 24 mm on either side of the point); on a
    straight roller (a full cylinder of radius 0.5 and length 0.2 on the block) straight to
    round-off."""
    h = 0.00625
    block = solid_from_dict(BLOCK)
    torus = _half_torus()
    kappa, span = line_bend(torus, block, contact_frame_3d(torus, block, np.array([RING, 0, 0]), h), 0.012, 0.024, h)
    assert kappa == pytest.approx(1.0 / RING, rel=1e-5) and span == pytest.approx(0.024)
    roller = solid_from_dict({"type": "cylinder", "center": [0.1, -0.05, 0.5], "axis": [1, 1, 0], "radius": 0.5,
                              "length": 0.2})
    frame = contact_frame_3d(roller, block, np.array([0.1, -0.05, 0.0]), h)
    kappa, span = line_bend(roller, block, frame, 0.05, 0.09, h)
    assert 0.5 * abs(kappa) * span**2 <= 1e-6 * h and span == pytest.approx(0.09)


def _flat_frame(body, point):
    return contact_frame_3d(body, solid_from_dict(BLOCK), np.asarray(point, dtype=float), 0.01)


def _hole_chords(point, psi, inner, outer):
    """(enter, leave) distances along the rays psi from ``point`` through the annulus's hole (the
    circle of radius ``inner`` about the origin; nan for rays that miss it) and the distance at
    which each ray leaves the outer circle."""
    d = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    b = d @ point[:2]
    disc = b**2 - (point[:2] @ point[:2] - inner**2)
    root = np.sqrt(np.where(disc > 0, disc, np.nan))
    return -b - root, -b + root, -b + np.sqrt(b**2 - (point[:2] @ point[:2] - outer**2))


def _washer():
    """A washer on z = 0: the revolution of the rectangle r 0.3 to 0.5, z 0 to 0.1."""
    return solid_from_dict({"type": "revolution", "axis_origin": [0, 0, 0], "axis": [0, 0, 1], "profile": {
        "type": "profile", "edges": [
            {"type": "line", "start": [0.3, 0], "end": [0.5, 0], "name": "bottom"},
            {"type": "line", "start": [0.5, 0], "end": [0.5, 0.1], "name": "outer"},
            {"type": "line", "start": [0.5, 0.1], "end": [0.3, 0.1], "name": "top"},
            {"type": "line", "start": [0.3, 0.1], "end": [0.3, 0], "name": "inner"}]}})


def test_a_washer_face_is_not_star_shaped_about_a_point_of_it():
    """A washer (annulus r 0.3 to 0.5) seen from a point at r = 0.4: every ray that crosses the hole
    (for at least two samples) and comes back onto the face within the candidate region is
    found, with where the face ends and starts again to a sample; the rays that miss the hole
    (or come back beyond the region) are not."""
    washer = _washer()
    point, extent = np.array([0.4, 0.0, 0.0]), 0.5
    frame = _flat_frame(washer, point)
    psi, t, ok, _ = face_rays(washer, frame, 0.25, extent, 360)
    resumed, leaves, returns = resumed_rays(t, ok, np.ones(len(psi), dtype=bool))
    in_plane = np.cos(psi)[:, None] * frame.axes[0][:2] + np.sin(psi)[:, None] * frame.axes[1][:2]
    enter, leave, out = _hole_chords(point, np.arctan2(in_plane[:, 1], in_plane[:, 0]), 0.3, 0.5)
    dt = t[1] - t[0]
    ahead = enter > 0.0  # the hole in front of the point (nan: the ray misses it)
    clear = ahead & (leave - enter > 2 * dt) & (leave < np.minimum(extent, out) - 2 * dt)
    assert clear.sum() >= 20
    assert resumed[clear].all()
    assert not resumed[~ahead | (leave > extent + dt)].any()
    np.testing.assert_array_less(np.abs(leaves[clear] - enter[clear]), dt + 1e-12)
    np.testing.assert_array_less(np.abs(returns[clear] - leave[clear]), dt + 1e-12)


def _l_punch():
    """An L-shaped punch 0.1 high on z = 0: the square [0, 0.4]^2 less [0.2, 0.4]^2."""
    edges = [[0, 0], [0.4, 0], [0.4, 0.2], [0.2, 0.2], [0.2, 0.4], [0, 0.4]]
    return solid_from_dict({"type": "extrusion", "z0": 0.0, "height": 0.1, "profile": {"type": "profile", "edges": [
        {"type": "line", "start": edges[k], "end": edges[(k + 1) % 6], "name": f"side{k}"} for k in range(6)]}})


@pytest.mark.parametrize("point, star", [([0.35, 0.05, 0.0], False), ([0.18, 0.18, 0.0], True)])
def test_an_l_shaped_face_from_a_leg_and_from_its_corner(point, star):
    """From the end of a leg the other leg lies behind the notch (rays leave the face at the notch
    and enter it again); from a point by the inner corner every point of the L is in sight."""
    punch = _l_punch()
    frame = _flat_frame(punch, point)
    psi, t, ok, _ = face_rays(punch, frame, 0.05, 0.6, 360)
    resumed = resumed_rays(t, ok, np.ones(len(psi), dtype=bool))[0]
    assert resumed.any() != star


def _run(scene: Path, out: Path):
    return subprocess.run([sys.executable, "-m", "ibfem", "run", str(scene), "--out", str(out), "--quiet",
                           "--no-estimate"], capture_output=True, text=True)


def test_a_washer_on_a_block_is_refused_at_set_up(tmp_path):
    r = _run(SCENES / "washer_on_block.toml", tmp_path)
    assert r.returncode != 0
    assert "contact washer/block" in r.stderr and "not star-shaped about the contact point" in r.stderr
    assert "sector" in r.stderr and "sliding" in r.stderr  # what to do
    # the face reaches 0.9 m from the point (plus a sample's spacing): the refinement radius that holds it
    assert "up to 0.917 m from the point" in r.stderr and "refinement of radius 1.15 m or more" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "summary.json").exists()


def test_a_half_torus_on_a_block_is_refused_at_set_up(tmp_path):
    r = _run(SCENES / "torus_on_block.toml", tmp_path)
    assert r.returncode != 0
    assert "contact ring/block" in r.stderr and "curves in the tangent plane (radius 0.5 m" in r.stderr
    assert "closed line" in r.stderr and "plane_strain" in r.stderr
    assert "conforming" not in r.stderr and "Traceback" not in r.stderr


def test_a_blind_hole_is_off_the_face():
    """A round punch (radius 0.5) with a blind hole (radius 0.1, 0.05 deep) in its face, seen from
    r = 0.3: the hole's floor is body 1's surface within the reach, so every ray has surface all
    the way, but the floor lies 0.05 above the face: the rays across the hole leave the face and
    come back (as many as cross the hole's circle in front of the point for two samples), the
    others do not; without the hole all rays stay on the face."""
    def punch(hole: bool):
        edges = ([[0, 0.05], [0.1, 0.05], [0.1, 0]] if hole else [[0, 0]]) + [[0.5, 0], [0.5, 0.3], [0, 0.3]]
        return solid_from_dict({"type": "revolution", "axis_origin": [0, 0, 0], "axis": [0, 0, 1], "profile": {
            "type": "profile", "edges": [{"type": "line", "start": edges[k], "end": edges[(k + 1) % len(edges)],
                                          "name": f"e{k}"} for k in range(len(edges))]}})
    point, extent, h = np.array([0.3, 0.0, 0.0]), 0.5, 0.01
    counts = []
    for hole in (True, False):
        body = punch(hole)
        frame = _flat_frame(body, point)
        psi, t, ok, height = face_rays(body, frame, 0.25, extent, 360)
        assert ok[:, :8].all()  # surface on every ray near the point, the hole's floor included
        counts.append(resumed_rays(t, on_face(ok, height, h), np.ones(len(psi), dtype=bool))[0])
        if hole:  # the frame's axes are not the same for both punches (a flat contact's axes are free)
            in_plane = np.cos(psi)[:, None] * frame.axes[0][:2] + np.sin(psi)[:, None] * frame.axes[1][:2]
            enter, leave, out = _hole_chords(point, np.arctan2(in_plane[:, 1], in_plane[:, 0]), 0.1, 0.5)
    dt = t[1] - t[0]
    assert counts[0][(enter > 0) & (leave - enter > 2 * dt)].all()
    assert not counts[0][~(enter > 0)].any() and not counts[1].any()


@pytest.mark.parametrize("extent, held", [(0.95, True), (0.5, False)])
def test_a_washer_face_is_taken_whole_only_where_the_candidate_region_holds_it(extent, held):
    """From r = 0.4 the washer's face reaches 0.9 m away: a candidate region of 0.95 m holds it
    whole, and its samples (the face to be held by the region) are exactly the samples within the
    annulus; one of 0.5 m does not, and the contact is refused saying so."""
    washer = _washer()
    frame = _flat_frame(washer, [0.4, 0.0, 0.0])
    psi, t, ok, height = face_rays(washer, frame, 0.25, extent, 360)
    inside = np.ones(len(psi), dtype=bool)
    c = SimpleNamespace(name="contact washer/block", frame=frame, extent=extent, solids=(washer, None), reach=0.25,
                        h=0.01, ranges=[(0.0, 2.0 * math.pi)], options=SimpleNamespace(extent_fraction=0.8))
    if not held:
        with pytest.raises(ValueError, match="refinement of radius 1.1[0-9] m or more"):
            _whole_face(c, psi, t, ok, on_face(ok, height, 0.01), inside)
        return
    s = _whole_face(c, psi, t, ok, on_face(ok, height, 0.01), inside)
    r = np.hypot(*(frame.point[:2] + s @ frame.axes[:, :2]).T)
    assert len(s) > 1000 and ((r > 0.3 - 1e-9) & (r < 0.5 + 1e-9)).all()
    direction = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    every = (t[None, :, None] * direction[:, None, :]).reshape(-1, 2)
    rr = np.hypot(*(frame.point[:2] + every @ frame.axes[:, :2]).T)
    strictly = int(((rr > 0.3 + 1e-6) & (rr < 0.5 - 1e-6)).sum())  # samples on the circles may go either way
    on_circles = int(((np.abs(rr - 0.3) <= 1e-6) | (np.abs(rr - 0.5) <= 1e-6)).sum())
    assert strictly <= len(s) <= strictly + on_circles


def test_a_recess_is_not_taken_whole():
    """The punch with a blind hole seen from r = 0.3, its whole face within the candidate region:
    the hole's floor would lie in the region's quadrature, so the contact is refused."""
    edges = [[0, 0.05], [0.1, 0.05], [0.1, 0], [0.5, 0], [0.5, 0.3], [0, 0.3]]
    body = solid_from_dict({"type": "revolution", "axis_origin": [0, 0, 0], "axis": [0, 0, 1], "profile": {
        "type": "profile", "edges": [{"type": "line", "start": edges[k], "end": edges[(k + 1) % 6], "name": f"e{k}"}
                                     for k in range(6)]}})
    frame = _flat_frame(body, [0.3, 0.0, 0.0])
    psi, t, ok, height = face_rays(body, frame, 0.25, 0.9, 360)
    c = SimpleNamespace(name="contact punch/block", frame=frame, extent=0.9, options=None)
    with pytest.raises(ValueError, match="a recess in the face"):
        _whole_face(c, psi, t, ok, on_face(ok, height, 0.01), np.ones(len(psi), dtype=bool))


def _summary(scene: Path, out: Path) -> dict:
    r = _run(scene, out)
    assert r.returncode == 0, r.stderr
    import json

    return json.loads((out / "summary.json").read_text())


def _radial_pressure(contact: dict, lo: float, hi: float, angles=None) -> float:
    """The pressure map's mean (area-weighted) over the squares whose centres lie at radii lo to hi
    from the washer's axis (and between the ``angles`` in degrees about it)."""
    m = contact["pressure_map"]
    xy = np.asarray(contact["point"][:2]) + np.asarray(m["s"]) @ np.asarray(contact["axes"])[:, :2]
    r, theta = np.hypot(*xy.T), np.degrees(np.arctan2(xy[:, 1], xy[:, 0])) % 360.0
    sel = (r >= lo) & (r < hi)
    if angles is not None:
        sel &= (theta > angles[0]) & (theta < angles[1])
    return float(np.average(np.asarray(m["value"])[sel], weights=np.asarray(m["area"])[sel]))


@pytest.mark.slow
def test_a_whole_washer_against_its_sector(tmp_path):
    """The washer on a cylindrical block, its face taken whole in complete contact
    (benchmarks/scenes/washer_whole.toml), against the same problem's 60 degree sector with
    sliding cut faces on the same grids' cells (benchmarks/scenes/washer_sector.toml: a region
    star-shaped about its point, on the ordinary flat contact's path): by symmetry the whole
    washer carries six times the sector's force (measured +0.21 %). Also equilibrium (the
    contact's force against both reactions), the region's area against the annulus's
    (+0.27 % measured), every sample of the face in the region, and the pressure axisymmetric:
    in four rings of 5 cm the means over eight 45 degree sectors about the axis within 7 % of
    each other (measured 2.1 to 6.4 %, the cubic grid's 90 degree pattern)."""
    whole = _summary(Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "washer_whole.toml",
                     tmp_path / "whole")
    sector = _summary(Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "washer_sector.toml",
                      tmp_path / "sector")
    c, s = whole["contacts"][0], sector["contacts"][0]
    assert whole["converged"] and sector["converged"] and c["complete_contact"]
    assert c["checks"]["face_samples_outside_region"] == 0
    assert c["normal_force"] == pytest.approx(-whole["reactions"]["washer/top"][2], rel=1e-9)
    assert c["normal_force"] == pytest.approx(whole["reactions"]["block/bottom"][2], rel=1e-9)
    assert c["normal_force"] == pytest.approx(6.0 * s["normal_force"], rel=0.01)
    assert c["area"] == pytest.approx(math.pi * (0.5**2 - 0.3**2), rel=0.01)
    for lo in (0.3, 0.35, 0.4, 0.45):
        means = [_radial_pressure(c, lo, lo + 0.05, (a, a + 45.0)) for a in range(0, 360, 45)]
        assert max(means) - min(means) <= 0.07 * np.mean(means)


@pytest.mark.slow
def test_an_l_shaped_punch_taken_whole(tmp_path):
    """The L-shaped punch pressed flat, its point at the end of a leg (benchmarks/scenes/
    l_punch.toml): its face taken whole in complete contact, the contact's force the reactions',
    the region's area the L's 0.12 m^2 (+0.36 % measured), and the pressure map symmetric about
    the L's diagonal x = y, which the contact point is not on: each square's mean against its
    mirror image's within 3 % of the mean pressure (measured: 2.3 % at most, 0.95 % RMS)."""
    s = _summary(Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "l_punch.toml", tmp_path)
    c = s["contacts"][0]
    assert s["converged"] and c["complete_contact"] and c["checks"]["face_samples_outside_region"] == 0
    assert c["normal_force"] == pytest.approx(-s["reactions"]["punch/top"][2], rel=1e-9)
    assert c["area"] == pytest.approx(0.12, rel=0.01)
    m = c["pressure_map"]
    xy = np.asarray(c["point"][:2]) + np.asarray(m["s"]) @ np.asarray(c["axes"])[:, :2]
    value = np.asarray(m["value"])
    mirror = np.argmin(np.linalg.norm(xy[:, None, :] - xy[None, :, ::-1], axis=2), axis=0)
    assert np.allclose(xy[mirror], xy[:, ::-1], atol=0.01)  # every square has its mirror image
    assert np.abs(value - value[mirror]).max() <= 0.03 * value.mean()


def test_a_curved_line_between_free_ends_and_a_straight_one():
    """A quarter of the half torus (revolved through 90 degrees), its point in the middle of the
    arc: the line has free ends (the cut faces, 0.38 m away along the tangent) and bends from its
    chord by far more than a quarter of a cell: refused, with the ring's radius. A straight full
    roller on the same block passes the same check."""
    from ibfem.solver.contact.star_region import _require_straight_line

    quarter = solid_from_dict({"type": "revolution", "axis_origin": [0, 0, TUBE], "axis": [0, 0, 1], "angle_deg": 90,
                               "profile": {"type": "profile", "edges": [
                                   {"type": "line", "start": [RING - TUBE, 0], "end": [RING + TUBE, 0], "name": "flat"},
                                   {"type": "arc", "center": [RING, 0], "radius": TUBE, "start_angle": 0,
                                    "end_angle": -180, "name": "tube"}]}})
    block = solid_from_dict(BLOCK)
    h, c45 = 0.00625, math.sqrt(0.5)
    frame = contact_frame_3d(quarter, block, np.array([RING * c45, RING * c45, 0.0]), h)
    c = SimpleNamespace(name="contact ring/block", solids=(quarter, block), frame=frame, reach=0.05, extent=0.45, h=h)
    with pytest.raises(ValueError, match=r"curves in the tangent plane \(radius 0.5 m.*from its chord between"):
        _require_straight_line(c, RING * math.tan(math.pi / 4.0) * 0.75)
    roller = solid_from_dict({"type": "cylinder", "center": [0, 0, 0.5], "axis": [1, 0, 0], "radius": 0.5,
                              "length": 0.3})
    frame = contact_frame_3d(roller, block, np.zeros(3), h)
    _require_straight_line(SimpleNamespace(name="contact roller/block", solids=(roller, block), frame=frame,
                                           reach=0.05, extent=0.45, h=h), 0.15)
