"""A STEP part in contact scenes (examples/cad): the part written by OpenCascade inside the test,
read back, graded into the solver's cells and pressed onto a block; the contact patch against
Hertz (Johnson, Contact Mechanics, 1985, eq. 4.22: a = (3 N R / (4 E*))^(1/3) for a sphere on a
flat), and the faces' graded quadrature against the exact areas."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples" / "cad"))

import make_quarter_ball  # noqa: E402
from ibfem.geometry.solids.part_solid import PartSolid, mesh_kernels  # noqa: E402
from ibfem.importers.step import load_part  # noqa: E402

E, NU = 2.0e11, 0.3
SCENE = ROOT / "examples" / "cad" / "quarter_ball_on_block.toml"


@pytest.fixture(scope="module")
def unit_ball(tmp_path_factory):
    """The quarter of a half ball of radius 1 m (written in millimetres), its pole at the origin."""
    path = make_quarter_ball.write(tmp_path_factory.mktemp("cad") / "ball.step", radius=1000.0)
    return PartSolid(load_part(str(path)))


def test_graded_panels_keep_the_exact_area_with_few_points(unit_ball):
    sphere = next(f for f in unit_ball.faces.values() if type(f.surface).__name__ == "Sphere")
    finest = 0.005
    # panels of 5 mm at the pole growing to half the distance from it: as a refined grid asks
    def panel_size(points, normals):
        return np.maximum(finest, 0.5 * np.linalg.norm(points, axis=1))

    x, w, n = sphere.quadrature(finest, panel_size=panel_size)
    # the quarter of a hemisphere: 2 pi R^2 / 4; the chords of the trimming arcs project onto the arcs
    assert w.sum() == pytest.approx(math.pi / 2, rel=1e-8)
    np.testing.assert_allclose(np.linalg.norm(x - [0, 0, 1], axis=1), 1.0, atol=1e-12)  # on the sphere
    np.testing.assert_allclose((n * (x - [0, 0, 1])).sum(axis=1), 1.0, atol=1e-12)  # outward normals
    assert len(w) < 20_000  # the uniform split to 5 mm: about 4 million points
    near = np.linalg.norm(x, axis=1) < 0.02
    assert near.sum() > 0.5 * (math.pi / 4 * 0.02**2) / (0.5 * finest**2) * 6 / 2  # fine panels at the pole


def test_compiled_and_numpy_tessellation_queries_agree(unit_ball, monkeypatch):
    if mesh_kernels() is None:
        pytest.skip("numba not installed")
    rng = np.random.default_rng(3)
    p = rng.uniform(-0.2, 1.2, (3000, 3))
    compiled = unit_ball.signed_distance(p)
    monkeypatch.setenv("IBFEM_NO_JIT", "1")
    plain = unit_ball.signed_distance(p)
    np.testing.assert_allclose(compiled, plain, rtol=0, atol=1e-14)
    # the sign (positive inside): the quarter half ball exactly where the closed form says so
    inside = (np.linalg.norm(p - [0, 0, 1], axis=1) < 1) & (p[:, 2] < 1) & (p[:, 0] > 0) & (p[:, 1] > 0)
    clear = np.abs(compiled) > 1e-3
    assert np.array_equal((compiled > 0)[clear], inside[clear])


@pytest.mark.slow
def test_step_quarter_ball_on_a_block_against_hertz(tmp_path):
    """The example scene with its part written here: a and b within 1 % of Hertz for the computed
    force, the reactions in equilibrium with the contact force."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.reference.theory import hertz_sphere_radius
    from ibfem.solver.solving import solve

    make_quarter_ball.write(tmp_path / "quarter_ball.step")
    (tmp_path / "scene.toml").write_text(SCENE.read_text())
    sol = solve(load_scene(tmp_path / "scene.toml").problem)
    c = sol.contacts[0]
    n = c["normal_force"]
    a_hertz = hertz_sphere_radius(4 * n, 0.025, E / (2 * (1 - NU**2)))  # the quarter carries N / 4
    for semi_axis in c["semi_axes"]:
        assert abs(semi_axis / a_hertz - 1.0) < 0.01
    np.testing.assert_allclose(sol.reactions["block/z_min"][2], n, rtol=1e-6)


@pytest.mark.slow
def test_step_half_cylinder_section_on_a_block_against_hertz(tmp_path):
    """2D: the plane section of a half cylinder (R = 50 mm) and a block written to STEP here, the
    half-width within 1 % of Hertz's line contact for the computed force per unit length
    (Johnson eq. 4.43: b = sqrt(4 N R / (pi E*))); measured -0.24 %."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.reference.theory import hertz_half_width
    from ibfem.solver.solving import solve

    sys.path.insert(0, str(ROOT / "examples" / "step"))
    import make_half_cylinder_on_block

    make_half_cylinder_on_block.write(tmp_path / "part.step")
    text = (ROOT / "examples" / "step" / "half_cylinder_on_block.toml").read_text()
    (tmp_path / "scene.toml").write_text(text.replace("../../fixtures/step/half_cylinder_on_block.step", "part.step"))
    sol = solve(load_scene(tmp_path / "scene.toml").problem)
    c = sol.contacts[0]
    b = hertz_half_width(c["normal_force"], 0.05, E / (2 * (1 - NU**2)))
    assert abs(c["half_width"] / b - 1.0) < 0.01


@pytest.mark.slow
def test_step_ball_held_by_a_reference_point_on_a_block_against_hertz(tmp_path):
    """A whole ball of one SPHERE face written here (as CAD systems write a ball), loaded through
    a kinematic reference point at its centre coupled to the upper half of its face: converged,
    a and b within 2 % of Hertz for the computed force (measured -0.97 %), and the point's force
    equal to the contact force and to the block's reaction (equilibrium)."""
    from ibfem.solver.fem.reference_point import resultant
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.reference.theory import hertz_sphere_radius
    from ibfem.solver.solving import solve

    import make_ball

    make_ball.write(tmp_path / "ball.step")
    scene = ROOT / "examples" / "cad" / "ball_on_block_reference_point.toml"
    (tmp_path / "scene.toml").write_text(scene.read_text())
    sol = solve(load_scene(tmp_path / "scene.toml").problem)
    assert sol.converged
    c = sol.contacts[0]
    n = c["normal_force"]
    a_hertz = hertz_sphere_radius(n, 0.001, E / (2 * (1 - NU**2)))
    for semi_axis in c["semi_axes"]:
        assert abs(semi_axis / a_hertz - 1.0) < 0.02
    force, moment = resultant(*sol.boundary_tractions["ball/F1"], np.zeros(3))
    np.testing.assert_allclose(force, [0, 0, -n], atol=1e-6 * n)
    np.testing.assert_allclose(sol.reactions["block/z_min"], [0, 0, n], atol=1e-6 * n)
    assert np.abs(moment).max() < 1e-4 * n * 0.001


def test_signed_distance_outside_the_quarter_near_the_pole(unit_ball):
    """Points off the quarter ball near its pole (where a contact search probes), whose nearest
    feature is the pole or a trimming arc: outside (negative), at the closed-form distances within
    the solid's tolerance (an edge's foot counts as on it within the tessellation's chord bound)."""
    rng = np.random.default_rng(5)
    h = rng.uniform(0.001, 0.05, (200, 3))
    below = -h  # x, y, z < 0: the pole (the origin) is the nearest point
    tol = unit_ball.tolerance
    d = unit_ball.signed_distance(below)
    assert (d < 0).all()
    np.testing.assert_allclose(d, -np.linalg.norm(below, axis=1), rtol=0, atol=tol)
    # x < 0 beside the arc x = 0 of the sphere face, y > 0 and below the sphere: the distance to the
    # circle y^2 + (z - 1)^2 = 1 in the plane x = 0
    side = np.c_[-h[:, 0], h[:, 1], h[:, 1] ** 2 - h[:, 2]]
    r = np.hypot(side[:, 1], side[:, 2] - 1.0)
    expect = np.hypot(side[:, 0], r - 1.0)
    d = unit_ball.signed_distance(side)
    assert (d < 0).all()
    np.testing.assert_allclose(d, -expect, rtol=0, atol=tol)
