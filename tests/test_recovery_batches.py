"""Several stress fields recovered side by side (the load steps' of a run with paths): the
recovery is linear in the centroid stresses and its fits depend only on the grid, so fields
given side by side, mirror planes included, must come back exactly as each recovered alone."""

from types import SimpleNamespace

import numpy as np

from ibfem.solver.fem.recovery import reflect_stress
from ibfem.solver.model.problem import Sliding
from ibfem.solver.solution import IBFEMSolution
from test_recovery_3d import _box, _field


def test_fields_side_by_side_are_recovered_each_as_alone():
    body = _box(refine=True)
    cent = body.cell_centroids()
    problem = SimpleNamespace(boundary_conditions=[Sliding("box", "x_min"), Sliding("box", "y_min")])
    sol = IBFEMSolution(problem=problem, bodies=[body], u=np.zeros(0), converged=True, body_info={}, reactions={},
                        iterations={}, timings={})
    first = _field(cent)
    second = np.random.default_rng(3).normal(size=first.shape)  # no symmetry: the mirrors act all the same
    sol.__dict__["_centroid_stress"] = {"box": first}
    alone = [sol.nodal_stress("box"), sol.nodal_stress("box", second)]
    assert np.isfinite(alone[0]).sum() > 1000  # the nodes outside the box have none (NaN)
    together = sol.nodal_stress("box", np.hstack([first, 2.0 * first + second, second]))
    assert np.allclose(together[:, :6], alone[0], rtol=1e-12, atol=1e-12, equal_nan=True)
    assert np.allclose(together[:, 6:12], 2.0 * alone[0] + alone[1], rtol=1e-10, atol=1e-10, equal_nan=True)
    assert np.allclose(together[:, 12:], alone[1], rtol=1e-12, atol=1e-12, equal_nan=True)
    assert np.array_equal(sol.nodal_stress("box"), alone[0], equal_nan=True)  # the solution's own, still cached


def test_reflection_of_fields_side_by_side():
    rng = np.random.default_rng(5)
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    a, b = rng.normal(size=(4, 6)), rng.normal(size=(4, 6))
    assert np.allclose(reflect_stress(np.hstack([a, b]), n), np.hstack([reflect_stress(a, n), reflect_stress(b, n)]))
    c, d = rng.normal(size=(4, 3)), rng.normal(size=(4, 3))
    assert np.allclose(reflect_stress(np.hstack([c, d]), [0.0, 1.0]),
                       np.hstack([reflect_stress(c, [0.0, 1.0]), reflect_stress(d, [0.0, 1.0])]))
