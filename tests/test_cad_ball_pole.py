"""A CAD ball whose sphere's pole (the singular point of its parametrisation) is the contact point:
what the 3D contact reads from the ball there against the closed form of a sphere of radius R on
a flat block (contact frame: the block's normal, relative curvatures 1/R each, circular; the
region's points on the ball: z = -sqrt(R^2 - |s|^2); the sectors: the whole circle), and in the
slow set the whole scene against Hertz and against the same ball turned so the pole lies on the
side. The ball is written here by OpenCascade (one SPHERE face, its seam and two degenerate pole
edges, as CAD systems write a ball), its axis along -z."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples" / "cad"))

import make_ball  # noqa: E402
from ibfem.geometry.solids import solid_from_dict  # noqa: E402
from ibfem.geometry.solids.part_solid import PartSolid  # noqa: E402
from ibfem.importers.step import load_part  # noqa: E402

R = 0.001  # the ball's radius (m), 1 mm in the file
E, NU = 2.0e11, 0.3


@pytest.fixture(scope="module")
def pole_down(tmp_path_factory):
    """The ball written with its sphere's axis along -z: one pole at (0, 0, -R), the contact."""
    return PartSolid(load_part(str(make_ball.write(tmp_path_factory.mktemp("pole") / "ball.step"))))


def _block():
    return solid_from_dict({"type": "box", "min": [-0.0015, -0.0015, -0.0025], "max": [0.0015, 0.0015, -R]})


def test_the_ball_has_its_pole_at_the_contact(pole_down):
    """The part as a user's: one SPHERE face whose degenerate edge (a pole) is the lowest point."""
    (face,) = pole_down.faces.values()
    poles = [e for e in pole_down.edges if np.ptp(np.asarray(e.polyline, float).reshape(-1, 3), axis=0).max() < 1e-12]
    assert any(np.allclose(np.asarray(e.polyline, float).reshape(-1, 3)[0], [0, 0, -R], atol=1e-12) for e in poles)


def test_signed_distance_about_the_pole_is_the_spheres(pole_down):
    rng = np.random.default_rng(3)
    for spread in (1e-7, 1e-5, 3e-4):
        p = rng.uniform(-spread, spread, (4000, 3)) + [0.0, 0.0, -R]
        np.testing.assert_allclose(pole_down.signed_distance(p), R - np.linalg.norm(p, axis=1), rtol=0, atol=1e-15)


def test_contact_frame_at_the_pole_is_the_spheres_on_a_flat(pole_down):
    """Normal +z (the block's), relative curvatures 1/R each (the flat adds none), circular."""
    from ibfem.solver.contact.ellipse_geometry import contact_frame_3d

    scale = 0.00025 / 16  # the finest cell of a 0.25 mm grid refined 4 levels
    frame = contact_frame_3d(pole_down, _block(), np.array([0.0, 0.0, -R]), scale)
    np.testing.assert_allclose(frame.normal, [0, 0, 1], atol=1e-9)
    np.testing.assert_allclose(frame.curvatures, [1.0 / R, 1.0 / R], rtol=1e-4)
    np.testing.assert_allclose(frame.point, [0, 0, -R], atol=1e-12)
    assert not frame.conforming


def test_region_points_on_the_ball_about_the_pole(pole_down):
    """The points of the region laid on the ball along the normal, through the pole itself and on
    rays of every direction out to twice Hertz's radius, on the sphere to 1e-13 m; the sectors
    where the ball has surface: the whole circle."""
    from ibfem.solver.contact.ellipse_geometry import contact_frame_3d, sectors, surface_point

    scale = 0.00025 / 16
    frame = contact_frame_3d(pole_down, _block(), np.array([0.0, 0.0, -R]), scale)
    theta = np.linspace(0.0, 2.0 * math.pi, 37)
    radius = np.concatenate([[0.0], np.geomspace(1e-9, 2e-4, 12)])
    rho, th = np.meshgrid(radius, theta, indexing="ij")
    s = np.column_stack([(rho * np.cos(th)).ravel(), (rho * np.sin(th)).ravel()])
    x1, ok = surface_point(pole_down, frame, s, 20.0 * scale)
    assert ok.all()
    y = frame.point + s[:, :1] * frame.axes[0] + s[:, 1:] * frame.axes[1]
    np.testing.assert_allclose(x1[:, :2], y[:, :2], atol=1e-15)
    np.testing.assert_allclose(x1[:, 2], -np.sqrt(R**2 - (s**2).sum(axis=1)), rtol=0, atol=1e-13)
    ranges = sectors(pole_down, frame, 2e-4, 20.0 * scale)
    assert len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 2.0 * math.pi * (1 - 1e-9)


def _scene(tmp_path: Path, shape: str, size: float, face: str) -> Path:
    text = (ROOT / "examples" / "cad" / "ball_on_block_reference_point.toml").read_text()
    text = text.replace('shape = { type = "step", path = "ball.step", body = "ball", '
                        'rotate = { axis = [1, 0, 0], angle_deg = 90 } }', shape)
    text = text.replace("element_size = 0.00024", f"element_size = {size}")
    text = text.replace('face = { type = "sphere" }', face)
    assert shape in text and face in text and f"element_size = {size}" in text  # the example's lines were found
    path = tmp_path / f"scene_{abs(hash((shape, size)))}.toml"
    path.write_text(text)
    return path


@pytest.mark.slow
@pytest.mark.parametrize("size", [0.00024, 0.00025])
def test_ball_with_its_pole_at_the_contact_against_hertz_and_the_analytic_ball(tmp_path, size):
    """The pole-down ball pressed 0.01 mm into the block through a reference point on its upper
    half (examples/cad/ball_on_block_reference_point.toml without its turn): converged, a within
    2 % of Hertz for its force (Johnson, Contact Mechanics, eq. 4.22), and within 0.5 % of the
    analytic ball's a on the same grid (measured: -1.09 % and -0.95 % from Hertz, the analytic
    ball -0.80 % and -1.00 %)."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.reference.theory import hertz_sphere_radius
    from ibfem.solver.solving import solve

    make_ball.write(tmp_path / "ball.step")
    cad = _scene(tmp_path, 'shape = { type = "step", path = "ball.step", body = "ball" }', size, 'face = { type = "sphere" }')
    ana = _scene(tmp_path, 'shape = { type = "sphere", center = [0, 0, 0], radius = 0.001 }', size, 'face = "surface"')
    a = {}
    for name, path in (("cad", cad), ("analytic", ana)):
        sol = solve(load_scene(path).problem)
        assert sol.converged, name
        c = sol.contacts[0]
        a[name] = c["semi_axes"][0]
        a_hertz = hertz_sphere_radius(c["normal_force"], R, E / (2 * (1 - NU**2)))
        for semi_axis in c["semi_axes"]:
            assert abs(semi_axis / a_hertz - 1.0) < 0.02, (name, semi_axis, a_hertz)
    assert abs(a["cad"] / a["analytic"] - 1.0) < 0.005
