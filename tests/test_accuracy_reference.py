"""The converged references of the finite bodies (slow): the rounded flat punch and the pin in a
bore, whose closed forms describe other bodies (half-planes, an infinite plate), against the
solutions of the same scenes by another code (NGSolve P3 on fitted curved meshes, penalty contact
on the same pairs: ibfem.solver.reference.converged.HALF_WIDTHS). Checked here:

- the reference reproduces: NGSolve on the coarsest mesh of its ladder lies within that mesh's
  distance from the limit;
- ibfem converges to it: the Richardson limit of the contact's half width from the scene's grid and
  the grids 2 and 4 times as coarse lies within 0.01 % of the other code's value (two codes, two
  discretisations, one answer);
- the error estimate of the scene's grid is within a factor 2 of its error against the reference;
- the sphere on a flat (examples/solid/sphere_on_flat.toml): the converged solution of its finite
  bodies (converged.SPHERE_ON_FLAT, NGSolve on fitted curved meshes) is Hertz's radius for its own
  force within the finite bodies' effect, and ibfem's coarsest graded rung lies within a factor 2 of
  its error estimate from it."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import pytest

from ibfem.solver.io.scene import load_scene
from ibfem.solver.reference.converged import HALF_WIDTHS
from ibfem.solver.solving import coarser, estimate_errors, solve

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "contact2d"

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("name", ["rounded_punch", "pin_in_bore"])
def test_ibfem_converges_to_the_other_codes_width_and_estimates_its_error(name):
    scene = load_scene(EXAMPLES / f"{name}.toml")
    solution = solve(scene.problem)
    widths = [float(solution.contacts[0]["half_width"])]
    widths += [float(solve(coarser(scene.problem, f)).contacts[0]["half_width"]) for f in (2.0, 4.0)]
    d_fine, d_coarse = widths[0] - widths[1], widths[1] - widths[2]
    assert d_fine * d_coarse > 0 and abs(d_coarse) > abs(d_fine), widths   # converging steadily
    order = math.log2(d_coarse / d_fine)
    limit = widths[0] + d_fine / (2.0 ** order - 1.0)
    reference = HALF_WIDTHS[name]["half_width"]
    assert abs(limit / reference - 1.0) < 1e-4, (limit, reference)
    estimate_errors(scene.problem, solution)
    true = abs(widths[0] / reference - 1.0)
    estimated = solution.contacts[0]["estimated_error"]["half_width"]
    assert 0.5 * true <= estimated <= 2.0 * true, (estimated, true)


@pytest.mark.skipif(importlib.util.find_spec("ngsolve") is None, reason="needs ngsolve (the peers extra)")
def test_the_rounded_punch_reference_reproduces():
    # the coarsest mesh of the reference's ladder (h_c 4e-4 m) read 0.0148000 m, 2.7e-6 m above the
    # stored limit; the two finer meshes 0.0147980 and 0.0147975 m
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from accuracy_reference_2d import solve as solve_ngsolve

    row = solve_ngsolve("full", 0.0148, 4e-4, 0.05, 3, 1e3)
    ref = HALF_WIDTHS["rounded_punch"]
    assert abs(row["a_fit"] - ref["half_width"]) < 4e-6
    assert abs(row["N"] / ref["N"] - 1.0) < 1e-4


# --------------------------------------------------------------------------- the sphere on a flat

def test_the_sphere_reference_is_hertz_for_its_force_within_the_finite_bodies_effect():
    # Hertz's radius for the reference's own force (Johnson eq. 4.22, the whole contact 4 N): the
    # finite bodies (a block 22 a deep with its bottom fixed, a ball held on its flat top) and the
    # sphere's exact gap put the converged a within 0.5 % of it (the exact gap: -0.027 %), while
    # the force for the prescribed 2 mm lies 3.5 % above Hertz's for that approach: a depends on
    # the bodies' far field only through N, as Hertz's theory says.
    from ibfem.solver.reference import theory
    from ibfem.solver.reference.converged import SPHERE_ON_FLAT

    e_star = 2.0e11 / (2.0 * (1.0 - 0.3 ** 2))
    a_hertz = theory.hertz_sphere_radius(4.0 * SPHERE_ON_FLAT["N"], 1.0, e_star)
    assert abs(SPHERE_ON_FLAT["a"] / a_hertz - 1.0) < 5e-3, (SPHERE_ON_FLAT["a"], a_hertz)
    # the stored a is the exact gap's half-space radius for that force, as its note says
    assert SPHERE_ON_FLAT["a"] == pytest.approx(theory.exact_sphere_radius(4.0 * SPHERE_ON_FLAT["N"], 1.0, e_star), rel=1e-6)
    n_hertz = 4.0 * e_star * math.sqrt(1.0) * 0.002 ** 1.5 / 3.0 / 4.0   # quarter of Hertz's N for the approach
    assert 1.0 < SPHERE_ON_FLAT["N"] / n_hertz < 1.06, (SPHERE_ON_FLAT["N"], n_hertz)


def test_ibfem_graded_coarse_rung_against_the_sphere_reference_within_its_estimate():
    # The coarsest rung of the 3D ladder (docs/accuracy.md): the grid graded about the contact,
    # cells growing in proportion to the distance (zones 6 ... 2 levels within 0.07 ... 1.2 m),
    # h0 0.5 m (16k dofs). Measured: a -0.58 % and N +0.83 % from the reference, estimated at
    # 1.05 % and 1.26 % (the two-grid 0.73 % plus the far field's energy share 0.53 %).
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from accuracy_ladder import GRADED_ZONES, sphere_zones_scene

    from ibfem.solver.reference.converged import SPHERE_ON_FLAT

    scene = load_scene(sphere_zones_scene(0.5, GRADED_ZONES))
    solution = solve(scene.problem)
    assert solution.converged
    estimate_errors(scene.problem, solution)
    contact = solution.contacts[0]
    estimated = contact["estimated_error"]
    for true, est in ((contact["semi_axes"][0] / SPHERE_ON_FLAT["a"] - 1.0, estimated["semi_axes"][0]),
                      (contact["normal_force"] / SPHERE_ON_FLAT["N"] - 1.0, estimated["normal_force"])):
        assert 0.5 * abs(true) <= est <= 2.0 * abs(true), (true, est)


def test_ibfem_shipped_sphere_grid_normal_force_within_its_estimate():
    # The shipped sphere_on_flat grid (cells of 0.25 m beyond 0.07 m of the contact): N is about
    # 1 % above the converged reference, most of it from the far field, which the two-grid
    # difference alone (0.14 %) did not see; the far field's energy share does
    from ibfem.solver.reference.converged import SPHERE_ON_FLAT

    scene = load_scene(ROOT / "examples" / "solid" / "sphere_on_flat.toml")
    solution = solve(scene.problem)
    assert solution.converged
    estimate_errors(scene.problem, solution)
    contact = solution.contacts[0]
    true = contact["normal_force"] / SPHERE_ON_FLAT["N"] - 1.0
    assert 0.5 * abs(true) <= contact["estimated_error"]["normal_force"] <= 2.0 * abs(true)
    assert 0.0 < contact["far_field_force_error"] < contact["estimated_error"]["normal_force"]
