"""The size estimate's count of a 3D body's cells crossing an axis plane (solver.model.estimate:
the balanced cuts of a body graded about its contact through its whole depth set the
factorisation's work space, CONTACT_PLANE_WORK_FACTOR) against the octrees then built, and the
rule's work space and factor size against the symbolic factorisation of a graded quarter sphere
on a flat."""

import importlib.util
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.fem.bodies import discretise
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model import estimate
from ibfem.solver.model.resolve import resolve_problem

ROOT = Path(__file__).resolve().parent.parent
#: nested zones about the contact, each twice the radius of the one inside it and one level coarser
GRADED = [(4, 0.07), (3, 0.14), (2, 0.28), (1, 0.56)]


def _graded_sphere_on_flat(element_size: float, zones) -> tuple:
    path = ROOT / "examples" / "solid" / "sphere_on_flat.toml"
    data = tomllib.loads(path.read_text())
    for body in data["bodies"]:
        body["element_size"] = element_size
        body["refinement"] = [{"levels": n, "around": "contact", "radius": r} for n, r in zones]
    data["output"] = {"vtk": False, "plots": False}
    return resolve_problem(load_scene(data, label=path.name, base_dir=path.parent).problem)


def test_plane_cells_against_the_built_octrees():
    """Cells crossing the axis planes through the contact point (on a symmetry face, half a
    finest cell inside), counted by the estimate's sampling and on the octrees built."""
    problem = _graded_sphere_on_flat(0.5, GRADED)
    bodies = discretise(problem, problem.options)
    point = np.asarray(problem.contacts[0].point, dtype=float)
    rng = np.random.default_rng(0)
    for model, built in zip(problem.bodies, bodies):
        lo, hi = (np.asarray(v, dtype=float) for v in model.profile.bounds)
        zones = list(zip(model.refinements, (np.asarray(c, dtype=float) for c in estimate._zone_centres(problem, model))))
        h_fine = float(model.element_size) / 2.0 ** max(int(z.levels) for z in model.refinements)
        for axis in range(3):
            x0 = float(np.clip(point[axis], lo[axis] + 0.5 * h_fine, hi[axis] - 0.5 * h_fine))
            crossing = np.abs(built.grid.center[:, axis] - x0) < 0.5 * built.grid.size
            counted = estimate._plane_cells(model.profile.signed_distance, zones, float(model.element_size), lo, hi,
                                            axis, x0, rng)
            assert counted == pytest.approx(int(crossing.sum()), rel=0.15), (model.name, axis)


@pytest.mark.slow
def test_graded_work_space_against_the_symbolic_factorisation():
    """The quarter sphere on a flat graded through both bodies (h0 0.25 m, zones of 6 to 2 levels
    within 0.07-1.2 m, 98k dofs): the larger of the bodies' update-matrix stack and largest front,
    in the order the run factors in, within 30 % of the rule's (CONTACT_PLANE_WORK_FACTOR times
    the square of the dofs of the plane halving a body's cells, the larger body's); each body's
    factor below its root within 25 % of FACTOR_FILL n^(4/3) + ROOT_REACH_FILL m_b^2 entries."""
    spec = importlib.util.spec_from_file_location("factor_profile_3d", ROOT / "benchmarks" / "factor_profile_3d.py")
    profile = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("factor_profile_3d", profile)
    spec.loader.exec_module(profile)
    problem = _graded_sphere_on_flat(0.25, [(6, 0.07), (5, 0.14), (4, 0.28), (3, 0.56), (2, 1.2)])
    rng = np.random.default_rng(0)
    rule, measured = [], []
    for g, f in profile.body_factors(problem):
        model = problem.bodies[g]
        measured.append(f.stack_bytes + f.front_bytes)
        # the factor below the root, which decides whether it is written to disk, against its rule
        below_root = estimate._factor_below_root_bytes(np.array([float(f.n)]), np.array([float(f.m)]))[0]
        assert below_root == pytest.approx(f.factor_bytes - 8.0 * f.m**2, rel=0.25), model.name
        lo, hi = (np.asarray(v, dtype=float) for v in model.profile.bounds)
        centres = estimate._zone_centres(problem, model)
        points, weights = estimate._sampled_body_cells(model, centres, lo, hi, rng)
        rule.append(8.0 * estimate.CONTACT_PLANE_WORK_FACTOR * estimate._median_plane_dofs(model, centres, points, weights, rng) ** 2)
    # the estimate counts the larger body's plane, once (the bodies are factored one at a time)
    assert max(rule) == pytest.approx(max(measured), rel=0.3)
