"""The linear solvers behind solver.fem.linalg.linear_solve: the iterative one (CG preconditioned
by smoothed-aggregation AMG with the rigid-body modes) gives the direct solution and Lame's
displacement; a solve that cannot reach its tolerance says so with its residual history."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.solving import solve

pytest.importorskip("pyamg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "single_body"
E, NU, P, A, B = 2.0e11, 0.3, 1.0e8, 1.0, 2.0


def lame_scene(method: str, h: float = 0.04):
    data = tomllib.loads((EXAMPLES / "lame_quarter_annulus_turned.toml").read_text())
    data["bodies"][0]["element_size"] = h
    data["output"] = {"vtk": False}
    data["solver"] = {"linear_solver": method}
    return scene_from_dict(data, label="lame.toml")


def lame_radial(r):
    """Plane-strain Lame radial displacement of a thick cylinder under internal pressure."""
    return P * A**2 / (E * (B**2 - A**2)) * (1 + NU) * ((1 - 2 * NU) * r + B**2 / r)


def test_iterative_solve_matches_direct_and_lame():
    points = np.array([[1.2, 0.3], [0.5, 1.6], [1.0, 1.0]])
    points = points @ np.array([[np.cos(np.pi / 6), np.sin(np.pi / 6)], [-np.sin(np.pi / 6), np.cos(np.pi / 6)]])
    direct = solve(lame_scene("direct").problem)
    iterative = solve(lame_scene("iterative").problem)
    assert direct.converged and iterative.converged
    ud, ui = direct.displacement(points), iterative.displacement(points)
    np.testing.assert_allclose(ui, ud, rtol=1e-7, atol=1e-9 * np.abs(ud).max())
    r = np.linalg.norm(points, axis=1)
    np.testing.assert_allclose(np.linalg.norm(ui, axis=1), lame_radial(r), rtol=2e-3)


def test_iterative_solver_that_cannot_converge_reports_its_history():
    from ibfem.solver.fem import linalg
    from ibfem.solver.fem.assembly import assemble
    from ibfem.solver.fem.bodies import discretise

    problem = lame_scene("iterative").problem
    bodies = discretise(problem, problem.options)
    system = assemble(problem, bodies, problem.options)
    with pytest.raises(linalg.LinearSolveError, match="did not reach the relative residual 1e-14 in 2 iterations"):
        linalg.amg_cg_solve(system.stiffness, system.load, bodies, tolerance=1e-14, max_iterations=2)


def test_unknown_linear_solver_is_a_scene_error():
    from ibfem.solver.io.scene import SceneError

    with pytest.raises(SceneError, match=r"solver\.linear_solver = \"cholmod\": must be one of"):
        lame_scene("cholmod")


def test_direct_solve_by_the_multifrontal_cholesky_matches_lame(monkeypatch):
    """A direct solve on the nested-dissection path (its threshold lowered to this grid's size)
    by the multifrontal L D L^T (forced) and by SuperLU (forced): both Lame's displacement to the
    discretisation error, and the same discrete solution to round-off."""
    pytest.importorskip("numba")
    from ibfem.solver.fem import linalg

    monkeypatch.setattr(linalg, "NESTED_DISSECTION_DOFS", 5000)
    points = np.array([[1.2, 0.3], [0.5, 1.6]])
    points = points @ np.array([[np.cos(np.pi / 6), np.sin(np.pi / 6)], [-np.sin(np.pi / 6), np.cos(np.pi / 6)]])
    runs = {}
    for factor in ("cholesky", "superlu"):
        monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", factor)
        scene = lame_scene("direct", h=0.02)
        sol = solve(scene.problem)
        assert sol.converged
        assert sol.body_info["ring"]["dofs"] >= linalg.NESTED_DISSECTION_DOFS
        runs[factor] = sol.displacement(points)
    exact = lame_radial(np.linalg.norm(points, axis=1))
    for u in runs.values():
        np.testing.assert_allclose(np.linalg.norm(u, axis=1), exact, rtol=5e-3)
    np.testing.assert_allclose(runs["cholesky"], runs["superlu"], rtol=1e-9, atol=1e-18)
