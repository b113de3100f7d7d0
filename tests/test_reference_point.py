"""A rigid reference point coupled to a face: the traction that distributes a force and moment
carries them exactly, the rigid fit recovers a rigid motion; solved on a block, a kinematic cap
gives the uniform-strain solution (Poisson's ratio 0: the cap does not restrain the section), a
distributed force the uniform stress F / A, and the reaction force and moment at the point
balance those of the supports (equilibrium, moments included)."""

from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.fem.reference_point import distributing_traction, resultant, rigid_fit, rigid_motion
from ibfem.solver.io.reference_point_output import reference_point_blocks
from ibfem.solver.io.scene import SceneError, scene_from_dict
from ibfem.solver.solving import solve

E = 2.0e11
SIZE = np.array([0.010, 0.012, 0.020])
TOP = (0.005, 0.006, 0.020)  # the top face's centre


def _points(dim: int, n: int = 40):
    rng = np.random.default_rng(3)
    return rng.uniform(-1.0, 1.0, (n, dim)), rng.uniform(0.1, 1.0, n)


@pytest.mark.parametrize("dim", [2, 3])
def test_distributed_traction_carries_the_force_and_the_moment_about_the_point(dim):
    x, w = _points(dim)
    point = np.full(dim, 0.7)
    force = np.arange(1.0, dim + 1.0)
    moment = np.array([-2.0]) if dim == 2 else np.array([0.5, -2.0, 1.5])
    t = distributing_traction(x, w, point, force, moment)
    f, m = resultant(x, w, t, point)
    np.testing.assert_allclose(f, force, rtol=1e-12)
    np.testing.assert_allclose(m, moment, atol=1e-12 * np.abs(moment).max())


def test_points_on_a_line_carry_no_moment_about_it():
    x = np.column_stack([np.linspace(0, 1, 5), np.zeros(5), np.zeros(5)])
    with pytest.raises(ValueError, match="one line"):
        distributing_traction(x, np.ones(5), np.zeros(3), np.zeros(3), np.array([1.0, 0.0, 0.0]))


@pytest.mark.parametrize("dim", [2, 3])
def test_rigid_fit_recovers_a_rigid_motion(dim):
    x, w = _points(dim)
    point = np.full(dim, -0.3)
    shift = np.arange(1.0, dim + 1.0) * 1e-3
    turn = np.array([2e-4]) if dim == 2 else np.array([2e-4, -1e-4, 3e-4])
    u = rigid_motion(x, point, shift, turn)
    fit_shift, fit_turn = rigid_fit(x, w, u, point)
    np.testing.assert_allclose(fit_shift, shift, atol=1e-15)
    np.testing.assert_allclose(fit_turn, turn, atol=1e-15)


def _scene(top: dict, nu: float, supports: dict) -> dict:
    return {
        "model": "solid",
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": nu}],
        "bodies": [{"name": "block", "material": "steel", "element_size": 0.0049,
                    "shape": {"type": "box", "min": [0, 0, 0], "max": SIZE.tolist()}}],
        "boundary_conditions": [{"type": kind, "body": "block", "face": f} for f, kind in supports.items()] + [top],
    }


SYMMETRY = {"x_min": "sliding", "y_min": "sliding", "z_min": "sliding"}


def _solve(top: dict, nu: float = 0.3, supports: dict = SYMMETRY):
    return solve(scene_from_dict(_scene(dict(type="reference_point", body="block", **top), nu, supports)).problem)


def _inside(n: int = 60) -> np.ndarray:
    return np.random.default_rng(5).uniform(0.05, 0.95, (n, 3)) * SIZE


def test_kinematic_cap_pushed_down_gives_the_uniform_strain_solution():
    d = 2e-6
    sol = _solve({"face": "z_max", "point": list(TOP), "displacement": [0, 0, -d]}, nu=0.0)
    sigma = -E * d / SIZE[2]
    stress = sol.stress(_inside(), recovered=False)
    np.testing.assert_allclose(stress, np.broadcast_to([0, 0, sigma, 0, 0, 0], stress.shape), atol=1e-7 * abs(sigma))
    force, moment = resultant(*sol.boundary_tractions["block/z_max"], np.array(TOP))
    np.testing.assert_allclose(force, [0, 0, sigma * SIZE[0] * SIZE[1]], atol=1e-7 * abs(sigma) * SIZE[0] * SIZE[1])
    assert np.abs(moment).max() < 1e-7 * abs(force[2]) * SIZE[0]


def test_force_distributed_from_a_point_above_the_face_gives_the_uniform_stress():
    force = -1000.0
    sol = _solve({"face": "z_max", "coupling": "distributing", "point": [0.005, 0.006, 0.05], "force": [0, 0, force]})
    sigma = force / (SIZE[0] * SIZE[1])
    stress = sol.stress(_inside(), recovered=False)
    np.testing.assert_allclose(stress, np.broadcast_to([0, 0, sigma, 0, 0, 0], stress.shape), atol=1e-7 * abs(sigma))
    np.testing.assert_allclose(sol.reactions["block/z_min"], [0, 0, -force], rtol=1e-9)


def test_distributing_point_moves_with_the_face_and_the_results_say_so():
    force, nu = -1000.0, 0.3
    point = [0.005, 0.006, 0.05]
    scene = _scene(dict(type="reference_point", body="block", face="z_max", coupling="distributing", point=point,
                        force=[0, 0, force]), nu, SYMMETRY)
    problem = scene_from_dict(scene).problem
    block = reference_point_blocks(problem, solve(problem))[0]
    sigma = force / (SIZE[0] * SIZE[1])
    # uniaxial stress: the top face moves down by sigma L / E and sideways by -nu sigma x / E,
    # whose rigid fit about the point is that translation at the face's centre (no rotation)
    expected = [-nu * sigma / E * 0.005, -nu * sigma / E * 0.006, sigma * SIZE[2] / E]
    np.testing.assert_allclose(block["displacement"], expected, atol=1e-7 * abs(expected[2]))
    assert np.abs(block["rotation"]).max() < 1e-7 * abs(expected[2]) / SIZE[0]
    assert block["force"] == [0, 0, force] and block["coupling"] == "distributing"


def _balance(sol, point) -> tuple[np.ndarray, np.ndarray]:
    """Sum of every essential condition's force and moment about ``point`` (2D or 3D)."""
    parts = [resultant(points, weights, traction, point) for points, weights, traction in sol.boundary_tractions.values()]
    return sum(f for f, _ in parts), sum(m for _, m in parts)


def test_kinematic_point_off_the_face_turned_and_moved_balances_the_support():
    point = np.array([0.002, 0.009, 0.026])
    sol = _solve({"face": "z_max", "point": point.tolist(), "displacement": [1e-6, -2e-6, -3e-6],
                  "rotation": [2e-4, -1e-4, 3e-4]}, supports={"z_min": "fixed"})
    f_point, m_point = resultant(*sol.boundary_tractions["block/z_max"], point)
    total_f, total_m = _balance(sol, point)
    assert np.linalg.norm(total_f) < 1e-9 * np.linalg.norm(f_point)
    assert np.linalg.norm(total_m) < 1e-9 * np.linalg.norm(m_point)


def test_force_and_moment_distributed_on_part_of_a_face_balance_the_support():
    point = np.array([0.003, 0.004, 0.030])
    force, moment = np.array([100.0, -50.0, -800.0]), np.array([2.0, -3.0, 1.0])
    region = {"center": [0.003, 0.004, 0.020], "radius": 0.004}
    sol = _solve({"face": "z_max", "coupling": "distributing", "point": point.tolist(), "region": region,
                  "force": force.tolist(), "moment": moment.tolist()}, supports={"z_min": "fixed"})
    f_support, m_support = _balance(sol, point)
    np.testing.assert_allclose(f_support, -force, atol=1e-9 * np.abs(force).max())
    np.testing.assert_allclose(m_support, -moment, atol=1e-9 * np.abs(force).max() * SIZE.max())


def test_kinematic_region_couples_only_the_points_inside_it():
    region = {"min": [0.0, 0.0, 0.019], "max": [0.005, 0.012, 0.021]}
    sol = _solve({"face": "z_max", "point": list(TOP), "region": region, "displacement": [0, 0, -1e-6]},
                 supports={"z_min": "fixed"})
    points, weights, traction = sol.boundary_tractions["block/z_max"]
    outside = points[:, 0] > 0.005
    assert outside.any() and (~outside).any()
    assert np.all(traction[outside] == 0.0)
    assert weights[outside].sum() == 0.0
    total_f, total_m = _balance(sol, np.array(TOP))
    f_point = sol.reactions["block/z_max"]
    assert np.linalg.norm(total_f) < 1e-9 * np.linalg.norm(f_point)


@pytest.mark.parametrize("top, message", [
    ({"face": "z_max", "point": [0, 0, 0], "force": [0, 0, 1]}, 'force and moment need coupling = "distributing"'),
    ({"face": "z_max", "point": [0, 0, 0], "coupling": "distributing", "displacement": [0, 0, 1]},
     'displacement and rotation need coupling = "kinematic"'),
    ({"face": "z_max", "point": [0, 0, 0], "coupling": "distributing"}, "needs a force or a moment"),
    ({"face": "z_max", "point": [0, 0, 0], "displacement": [0, 0, 1], "region": {"min": [0, 0, 0], "center": [0, 0, 0]}},
     "either min and max"),
    ({"face": "z_max", "point": [0, 0, 0], "displacement": [0, 0, 1], "region": {"min": [1, 0, 0], "max": [0, 1, 1]}},
     "below max"),
])
def test_scene_errors_name_the_condition(top, message):
    with pytest.raises(SceneError, match=r"boundary_conditions\[3\]") as err:
        scene_from_dict(_scene(dict(type="reference_point", body="block", **top), 0.3, SYMMETRY), "s.toml", Path("."))
    assert message in str(err.value)


def test_a_region_that_holds_no_point_of_the_face_is_an_error():
    region = {"center": [1.0, 1.0, 1.0], "radius": 0.001}
    with pytest.raises(ValueError, match="no quadrature point of the face lies inside the region"):
        _solve({"face": "z_max", "point": list(TOP), "region": region, "displacement": [0, 0, -1e-6]})


# --- 2D (plane strain): the same conditions on an edge -------------------------------------------

WIDTH, HEIGHT = 0.010, 0.020


def _solve_2d(top: dict, nu: float, supports: dict):
    scene = {
        "model": "plane_strain", "thickness": 1.0,
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": nu}],
        "bodies": [{"name": "plate", "material": "steel", "element_size": 0.0024,
                    "shape": {"type": "rectangle", "min": [0, 0], "max": [WIDTH, HEIGHT]}}],
        "boundary_conditions": [{"type": kind, "body": "plate", "edge": e} for e, kind in supports.items()]
        + [dict(type="reference_point", body="plate", edge="top", **top)],
    }
    return solve(scene_from_dict(scene).problem)


def test_2d_kinematic_cap_gives_the_uniform_strain_solution():
    d = 2e-6
    sol = _solve_2d({"point": [0.005, 0.02], "displacement": [0, -d]}, 0.0, {"bottom": "sliding", "left": "sliding"})
    sigma = -E * d / HEIGHT
    x = np.random.default_rng(2).uniform(0.05, 0.95, (40, 2)) * [WIDTH, HEIGHT]
    stress = sol.stress(x, recovered=False)
    np.testing.assert_allclose(stress, np.broadcast_to([0, sigma, 0], stress.shape), atol=1e-7 * abs(sigma))
    np.testing.assert_allclose(sol.reactions["plate/top"], [0, sigma * WIDTH], rtol=1e-7, atol=1e-7 * abs(sigma) * WIDTH)


def test_2d_turned_cap_and_distributed_moment_balance_the_support():
    point = np.array([0.003, 0.025])
    sol = _solve_2d({"point": point.tolist(), "displacement": [1e-6, -2e-6], "rotation": 3e-4}, 0.3, {"bottom": "fixed"})
    f_point, m_point = resultant(*sol.boundary_tractions["plate/top"], point)
    total_f, total_m = _balance(sol, point)
    assert np.linalg.norm(total_f) < 1e-9 * np.linalg.norm(f_point)
    assert abs(total_m[0]) < 1e-9 * abs(m_point[0])
    force, moment = np.array([50.0, -400.0]), np.array([1.5])
    sol = _solve_2d({"point": point.tolist(), "coupling": "distributing", "force": force.tolist(), "moment": 1.5,
                     "region": {"min": [0.0, 0.019], "max": [0.006, 0.021]}}, 0.3, {"bottom": "fixed"})
    f_support, m_support = _balance(sol, point)
    np.testing.assert_allclose(f_support, -force, atol=1e-9 * np.abs(force).max())
    np.testing.assert_allclose(m_support, -moment, atol=1e-9 * np.abs(force).max() * HEIGHT)


def test_a_kinematic_point_holds_a_body_and_a_distributing_one_does_not():
    sol = _solve_2d({"point": [0.005, 0.03], "displacement": [0, -1e-6], "rotation": 1e-4}, 0.3, {})
    assert sol.converged
    with pytest.raises(SceneError, match="rigid"):
        _solve_2d({"point": [0.005, 0.03], "coupling": "distributing", "force": [0, -1.0]}, 0.3, {})
