"""The error estimate's arithmetic (solver.model.accuracy): Richardson's estimate is exact on a
sequence converging at the assumed order, and the summary's blocks are read as documented; the
accuracy target's ladder (slow) meets its target against Hertz's theory."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.io.result_line import accuracy_line, contact_line
from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.model.accuracy import (COMPLETE_END_ORDER_RANGE, ORDERS, SIZE_ORDER_RANGE, contact_quantities, largest_error, observed_order,
                                        orders_for, relative_errors, three_grid_error)
from ibfem.solver.reference import theory
from ibfem.solver.reports.validate import effective_properties
from ibfem.solver.solving import solve_to_accuracy

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("key", sorted(ORDERS))
def test_richardson_exact_at_the_assumed_order(key):
    # q_h = q + C h^p with p the assumed order: the estimate is the true error of q_h
    p, q, c, h = ORDERS[key], 3.7, 0.8, 0.01
    fine, coarse = q + c * h ** p, q + c * (2 * h) ** p
    if key in ("semi_axes", "stick_semi_axes"):
        est = relative_errors({key: [fine, fine]}, {key: [coarse, coarse]})[key]
        assert est == pytest.approx([abs(fine - q) / fine] * 2, rel=1e-9)
    else:
        assert relative_errors({key: fine}, {key: coarse})[key] == pytest.approx(abs(fine - q) / fine, rel=1e-9)


@pytest.mark.parametrize("dim", [2, 3])
def test_peak_pressure_carries_the_region_size_error(dim):
    # Hertz's relation at a fixed force, p0 = 2 N / (pi a) in 2D and 3 N / (2 pi a b) in 3D, with the
    # region's size converging at order 3/2: the peak pressure's true error is the size's (2D) or
    # twice it (3D), which p0's own two-grid difference at order 2 underestimates by (2^1.5 - 1) / 3
    force, size, c = 1.0e8, 0.04, 0.5

    def block(h):
        a = size * (1.0 + c * h ** 1.5)
        p0 = 2.0 * force / (math.pi * a) if dim == 2 else 3.0 * force / (2.0 * math.pi * a * a)
        return ({"half_width": a} if dim == 2 else {"semi_axes": [a, a]}) | {"max_pressure": p0}

    exact = 2.0 * force / (math.pi * size) if dim == 2 else 3.0 * force / (2.0 * math.pi * size * size)
    fine = block(0.01)
    est = relative_errors(fine, block(0.02))["max_pressure"]
    assert est == pytest.approx(abs(fine["max_pressure"] / exact - 1.0), rel=0.02)


def test_quantities_of_a_block():
    block = {"type": "frictionless", "half_width": 0.03, "stick_half_width": 0.0, "normal_force": 1e8,
             "pressure": {"s": [-0.01, 0.0, 0.01], "value": [1.0e9, 2.0e9, 1.5e9]}, "max_von_mises": 1.1e9}
    q = contact_quantities(block)
    assert q == {"half_width": 0.03, "normal_force": 1e8, "max_pressure": 2.0e9, "max_von_mises": 1.1e9}
    block3d = {"type": "frictional", "semi_axes": [0.04, 0.05], "stick_semi_axes": [0.02, 0.025], "normal_force": 1e6,
               "pressure": {"axis0": {"s": [0.0], "value": [3e9]}, "axis1": {"s": [0.0], "value": [3.1e9]}}}
    q = contact_quantities(block3d)
    assert q["semi_axes"] == [0.04, 0.05] and q["stick_semi_axes"] == [0.02, 0.025] and q["max_pressure"] == 3.1e9


def test_complete_end_sizes_take_the_safe_or_the_observed_order():
    # a region ending at a corner of body 1: with two grids its sizes take the safe order 1/2 of a
    # square-root singular field (q_h = q + C h^(1/2): the estimate is exact), with three the
    # observed one; the singular peak pressure has no limit: no estimate
    block = {"half_width": 0.005, "ends": [{"type": "complete"}, {"type": "incomplete"}]}
    orders = orders_for(block)
    assert orders["half_width"] == 0.5 and orders["max_pressure"] is None and orders["normal_force"] == 2.0
    assert orders_for({"ends": [{"type": "incomplete"}] * 2}) == ORDERS
    # a 3D region's peak pressure is a fit over the region: it converges with its edge (3/2)
    assert orders_for({"semi_axes": [0.04, 0.05]}) == {**ORDERS, "max_pressure": 1.5}
    q, c, h = 0.005, 0.3, 0.01
    fine, coarse = {"half_width": q + c * h ** 0.5, "max_pressure": 2e9}, {"half_width": q + c * (2 * h) ** 0.5, "max_pressure": 1.5e9}
    errors = relative_errors(fine, coarse, orders)
    assert errors["half_width"] == pytest.approx(c * h ** 0.5 / fine["half_width"], rel=1e-9)
    assert errors["max_pressure"] is None
    # three grids converging at order 0.8: the observed order, and with it the exact estimate
    grids = [q + c * (k * h) ** 0.8 for k in (1, 2, 4)]
    p = observed_order(*grids)
    assert p == pytest.approx(0.8, rel=1e-9)
    errors = relative_errors({"half_width": grids[0]}, {"half_width": grids[1]}, orders_for(block, p))
    assert errors["half_width"] == pytest.approx(c * h ** 0.8 / grids[0], rel=1e-9)
    # differences of opposite signs (not yet converging steadily) give no observed order
    assert observed_order(1.0, 1.1, 1.05) is None
    # an observed order outside the trusted range is clamped to it
    assert observed_order(*[q + c * (k * h) ** 3 for k in (1, 2, 4)]) == 1.0
    # the three-grid estimate of such a size: faster than order 1, the coarser pair's difference
    # carried down at order 1, (2^1.2 - 1) c h^1.2 / 2 (the tilted punch's case)
    g = [q + c * (k * h) ** 1.2 for k in (1, 2, 4)]
    errors = relative_errors({"half_width": g[0]}, {"half_width": g[1]}, orders, coarsest={"half_width": g[2]},
                             order_range=COMPLETE_END_ORDER_RANGE)
    assert errors["half_width"] == pytest.approx((g[2] - g[1]) / (2.0 * g[0]), rel=1e-9)


def test_three_grids_give_the_sizes_their_observed_order():
    # q_h = q + C h^p on three grids, each twice as fine as the one before: for p inside the trusted
    # range the estimate is the exact error of the finest; outside it the clamped order
    q, c, h = 0.0148, 0.02, 0.001
    for p in (1.2, 1.5, 2.0):
        grids = [q + c * (k * h) ** p for k in (1, 2, 4)]
        assert three_grid_error(*grids, 1.5) == pytest.approx(c * h ** p / grids[0], rel=1e-9)
    # faster than the range (order 3): the coarser pair's difference carried down at order 2,
    # (64 - 8) c h^3 / ((2^2 - 1) 2^2), never the clamped (8 - 1) c h^3 / (2^2 - 1), 4/7 of it
    grids = [q - c * (k * h) ** 3 for k in (1, 2, 4)]
    assert three_grid_error(*grids, 1.5) == pytest.approx(56.0 * c * h ** 3 / (12.0 * grids[0]), rel=1e-9)
    # slower than the range (order 0.7): its slowest order, 1
    grids = [q + c * (k * h) ** 0.7 for k in (1, 2, 4)]
    assert three_grid_error(*grids, 1.5) == pytest.approx((grids[1] - grids[0]) / grids[0], rel=1e-9)
    assert SIZE_ORDER_RANGE == (1.0, 2.0)
    # element by element for lists (3D semi-axes), only for the sizes
    g = [q + c * (k * h) ** 1.2 for k in (1, 2, 4)]
    fine = {"semi_axes": [g[0]] * 2, "normal_force": 1.0}
    coarse = {"semi_axes": [g[1]] * 2, "normal_force": 1.03}
    coarsest = {"semi_axes": [g[2]] * 2, "normal_force": 0.5}
    errors = relative_errors(fine, coarse, coarsest=coarsest)
    assert errors["semi_axes"] == [pytest.approx(c * h ** 1.2 / fine["semi_axes"][0], rel=1e-9)] * 2
    assert errors["normal_force"] == pytest.approx(0.01)


def test_three_grids_see_through_a_coincidence():
    # a size scattered by the grid's position: the two finest grids happen to agree, the coarser
    # pair's difference carried down to the finest grid (order 3/2) bounds the estimate from below
    q, h = 0.0148, 0.001
    fine, coarse, coarsest = q + 1e-7, q + 1e-7 + 1e-9, q + 6e-6
    est = three_grid_error(fine, coarse, coarsest, 1.5)
    assert est == pytest.approx((coarsest - coarse) / ((2 ** 2 - 1) * 2 ** 2 * fine), rel=1e-12)   # at order 2
    assert est > 50 * abs(fine - coarse) / ((2 ** 1.5 - 1) * fine)
    # differences of opposite signs: the same bound, never below the two-grid estimate
    est = three_grid_error(q + 2e-6, q, q + 1e-6, 1.5)
    assert est == pytest.approx(2e-6 / ((2 ** 1.5 - 1) * (q + 2e-6)), rel=1e-12)
    assert math.isnan(three_grid_error(q, q, math.nan, 1.5))


def test_missing_coarse_quantity_and_largest():
    errors = relative_errors({"normal_force": 1.0, "stick_half_width": 0.5}, {"normal_force": 1.03})
    assert errors["stick_half_width"] is None and errors["normal_force"] == pytest.approx(0.01)
    assert largest_error(errors) == ("normal_force", pytest.approx(0.01))
    assert largest_error({"half_width": math.nan}) == (None, 0.0)


def test_result_line_prints_the_estimate():
    line = contact_line({"type": "frictionless", "half_width": 0.03, "normal_force": 1e8,
                         "estimated_error": {"half_width": 0.0042, "normal_force": 0.0003}})
    assert "estimated error half_width 0.42 %, normal_force 0.03 %" in line


def test_accuracy_line_lists_the_ladder():
    line = accuracy_line({"target": 0.005, "reached": True, "rungs": [
        {"dofs": 4444, "largest_error": 0.0841, "quantity": "max_von_mises"},
        {"dofs": 16576, "largest_error": 0.0041, "quantity": "half_width"}]})
    assert line == ("accuracy 0.5 % reached in 2 rung(s): 4444 dofs, 8.4 % (max_von_mises); "
                    "16576 dofs, 0.41 % (half_width)")


@pytest.mark.slow
def test_accuracy_target_is_met_against_hertz():
    # a cylinder on a block from a grid too coarse for 2 %: the ladder refines until the estimate
    # is below the target, and the true error of a against Hertz for the computed force is too
    data = tomllib.loads((ROOT / "examples" / "mesh_convergence.toml").read_text())
    for body in data["bodies"]:
        body["element_size"] = 0.1
        for ref in body["refinement"]:
            ref["levels"] = min(ref["levels"], 3)
    data["solver"].update(accuracy=0.02, load_steps=1)
    data["output"] = {"vtk": False, "plots": False}
    scene = scene_from_dict(data, label="accuracy", base_dir=ROOT / "examples")
    solution, ladder = solve_to_accuracy(scene.problem)
    errors = [r["largest_error"] for r in ladder["rungs"]]
    assert ladder["reached"] and len(errors) >= 2 and errors[-1] <= 0.02 < errors[0]
    assert all(b < a for a, b in zip(errors, errors[1:]))
    c = solution.contacts[0]
    r_eff, e_eff = effective_properties(scene.problem, c)
    a_hertz = theory.hertz_half_width(c["normal_force"], r_eff, e_eff)
    assert abs(c["half_width"] / a_hertz - 1.0) < 0.02


def _resolved_mesh_convergence():
    from ibfem.solver.model.resolve import resolve_problem
    data = tomllib.loads((ROOT / "examples" / "mesh_convergence.toml").read_text())
    scene = scene_from_dict(data, label="accuracy", base_dir=ROOT / "examples")
    return resolve_problem(scene.problem)


def test_rung_around_the_contact_covers_the_region_one_level_deeper():
    # the new zone of each body in contact: one level below its deepest, centred on the contact
    # point, reaching 1.5 times the region's farthest end plus four of its new cells
    from types import SimpleNamespace

    from ibfem.solver.solving import REGION_MARGIN, REGION_MARGIN_CELLS, _next_rung, refined_around_contacts
    problem = _resolved_mesh_convergence()
    block = {"point": [0.0, 0.0], "half_width": 0.03, "region": [-0.031, 0.0305]}
    refined = refined_around_contacts(problem, SimpleNamespace(contacts=[block]))
    for before, after in zip(problem.bodies, refined.bodies):
        assert after.refinements[:-1] == before.refinements and after.element_size == before.element_size
        zone = after.refinements[-1]
        deepest = max(r.levels for r in before.refinements)
        assert zone.levels == deepest + 1 and np.allclose(zone.center, [0.0, 0.0])
        h_new = before.element_size / 2.0 ** zone.levels
        assert zone.radius == pytest.approx(REGION_MARGIN * 0.031 + REGION_MARGIN_CELLS * h_new, rel=1e-12)
        # the region's cells are then half the size they were
        from ibfem.solver.model.resolve import finest_size_at
        assert finest_size_at(after, np.array([0.031, 0.0])) == pytest.approx(0.5 * finest_size_at(before, np.array([0.031, 0.0])))
    # it is a contact zone: a pass that finds the region on a grid COARSER_LEVELS shallower about
    # the contact takes it shallower too (its cells there 2^COARSER_LEVELS times the rung's)
    from ibfem.solver.contact.sizing import COARSER_LEVELS, coarse_pass_problem
    shallow = coarse_pass_problem(refined, [0])
    for body, rung in zip(shallow.bodies, refined.bodies):
        assert rung.refinements[-1].around_contact
        assert finest_size_at(body, np.zeros(2)) == pytest.approx(2.0 ** COARSER_LEVELS * finest_size_at(rung, np.zeros(2)))
    # a normal force error is the far field's too: that rung grades the far field about the
    # contact, and once it is graded halves every cell
    finer, how, _ = _next_rung(problem, SimpleNamespace(contacts=[block]), "normal_force")
    assert how == "far field"
    finer, how, ratio = _next_rung(finer, SimpleNamespace(contacts=[block]), "normal_force")
    assert how == "everywhere" and ratio == 2.0
    assert all(f.element_size == 0.5 * b.element_size for f, b in zip(finer.bodies, problem.bodies))
    # a contact without a region to refine around: every cell halved as well
    assert refined_around_contacts(problem, SimpleNamespace(contacts=[{"point": None}])) is None
    assert _next_rung(problem, SimpleNamespace(contacts=[{"point": None}]), "half_width")[1] == "everywhere"


def test_rung_ratio_scales_each_estimate_by_h_to_its_order():
    # an estimate E at order p falls like h^p: the cells r = (E / (share target))^(1/p) times
    # smaller bring it to that share of the target; the largest need over the quantities decides
    from ibfem.solver.model.accuracy import RATIO_RANGE, TARGET_SHARE, refinement_ratio
    target = 0.002
    errors = {"semi_axes": [0.0038, 0.0030], "max_von_mises": 0.0053, "normal_force": 0.001, "max_pressure": None}
    r = refinement_ratio(errors, ORDERS, target)
    assert r == pytest.approx((0.0053 / (TARGET_SHARE * target)) ** 0.5, rel=1e-12)
    assert 0.0053 * r ** -2 == pytest.approx(TARGET_SHARE * target)  # the worst lands on the share
    assert 0.0038 * r ** -1.5 < TARGET_SHARE * target  # the others below it
    # the sizes' slower order can need more than a larger error at order 2
    assert refinement_ratio({"half_width": 0.004, "max_pressure": 0.0045}, ORDERS, target) == pytest.approx(
        (0.004 / (TARGET_SHARE * target)) ** (1 / 1.5), rel=1e-12)
    # bounded: never below RATIO_RANGE[0] (Richardson's r^p - 1 would magnify the scatter), never
    # above one level; a quantity without an order (a corner's singular peak) does not count
    assert refinement_ratio({"normal_force": 0.00161}, ORDERS, target) == RATIO_RANGE[0]
    assert refinement_ratio({"normal_force": 0.05}, ORDERS, target) == RATIO_RANGE[1]
    assert refinement_ratio({"max_pressure": 0.05}, {"max_pressure": None}, target) == RATIO_RANGE[0]


@pytest.mark.parametrize("ratios", [(1.6, 2.0), (2.0, 1.6), (1.3, 1.8)])
def test_richardson_with_any_ratio_of_the_cells(ratios):
    # q_h = q + C h^p on grids whose cells differ by r1 and then r2: the two-grid estimate with
    # r1 and the three-grid estimate's observed order are exact
    q, c, h = 0.0452, 0.03, 0.004
    r1, r2 = ratios
    for p in (1.2, 1.5, 1.9):
        grids = [q + c * (k * h) ** p for k in (1.0, r1, r1 * r2)]
        exact = c * h ** p / grids[0]
        assert three_grid_error(*grids, 1.5, ratios=ratios) == pytest.approx(exact, rel=1e-9)
        est = relative_errors({"half_width": grids[0]}, {"half_width": grids[1]}, {"half_width": p}, ratios=ratios)
        assert est["half_width"] == pytest.approx(exact, rel=1e-9)
    # faster than the range (order 3): the coarser pair's difference carried down at order 2
    grids = [q - c * (k * h) ** 3 for k in (1.0, r1, r1 * r2)]
    carried = (grids[1] - grids[2]) / ((r2 ** 2 - 1.0) * r1 ** 2)
    assert three_grid_error(*grids, 1.5, ratios=ratios) == pytest.approx(abs(carried / grids[0]), rel=1e-9)


def test_rung_around_the_contact_keeps_the_far_field_estimate():
    from types import SimpleNamespace

    from ibfem.solver.solving import _carry_far_field
    previous = SimpleNamespace(contacts=[{"estimated_error": {"half_width": 0.005, "normal_force": 0.002}}])
    local = SimpleNamespace(contacts=[{"estimated_error": {"half_width": 0.0015, "normal_force": 1e-5}}])
    _carry_far_field(local, previous)
    assert local.contacts[0]["estimated_error"] == {"half_width": 0.0015, "normal_force": 0.002}
    # in 3D the rung's own estimate of N holds its far field's share (the energy error of its
    # unrefined cells): the previous rung's is not carried over it
    solid = SimpleNamespace(contacts=[{"estimated_error": {"semi_axes": [0.001, 0.001], "normal_force": 0.0017},
                                       "far_field_force_error": 0.0015}])
    _carry_far_field(solid, SimpleNamespace(contacts=[{"estimated_error": {"normal_force": 0.0042}}]))
    assert solid.contacts[0]["estimated_error"]["normal_force"] == 0.0017
    # a rung that graded only the far field keeps the contact's cells: the other quantities'
    # estimates are carried, the normal force's is its own
    previous = SimpleNamespace(contacts=[{"estimated_error": {"semi_axes": [0.004, None], "max_pressure": 0.003,
                                                              "normal_force": 0.01}}])
    graded = SimpleNamespace(contacts=[{"estimated_error": {"semi_axes": [1e-5, 2e-5], "max_pressure": 1e-5,
                                                            "normal_force": 0.003}}])
    _carry_far_field(graded, previous, far=False)
    assert graded.contacts[0]["estimated_error"] == {"semi_axes": [0.004, 2e-5], "max_pressure": 0.003,
                                                     "normal_force": 0.003}


def test_accuracy_target_tightens_the_stick_tolerance_below_it():
    # the stick zone's iteration error (in c/a) must stay below the discretisation error asked for
    from ibfem.solver.solving import STICK_TOLERANCE_SHARE, _tightened
    problem = _resolved_mesh_convergence()
    tight = _tightened(problem, 0.002)
    assert all(c.options.stick_tolerance == pytest.approx(STICK_TOLERANCE_SHARE * 0.002) for c in tight.contacts)
    loose = _tightened(problem, 0.5)  # never looser than the scene's own
    assert all(t.options.stick_tolerance == c.options.stick_tolerance for t, c in zip(loose.contacts, problem.contacts))


def test_graded_far_field_cells_grow_in_proportion_to_the_distance():
    # beyond the deepest zone every doubling of the distance from the contact point is one level
    # coarser, out to the body's far corner: the cell size over the distance stays within a factor
    # 2 of its value at the deepest zone's edge, and the cells inside that zone are kept
    from types import SimpleNamespace

    from ibfem.solver.model.resolve import finest_size_at
    from ibfem.solver.solving import graded_around_contacts
    problem = _resolved_mesh_convergence()
    block = {"point": [0.0, 0.0], "half_width": 0.03, "region": [-0.031, 0.0305]}
    graded = graded_around_contacts(problem, SimpleNamespace(contacts=[block]))
    for before, after in zip(problem.bodies, graded.bodies):
        deepest = max(r.levels for r in before.refinements)
        r0 = max(r.radius for r in before.refinements if r.levels == deepest)
        lo, hi = (np.asarray(v, dtype=float) for v in after.profile.bounds)
        reach = float(np.linalg.norm(np.maximum(np.abs(lo), np.abs(hi))))
        ratio0 = finest_size_at(before, np.array([0.5 * r0, 0.0])) / r0
        for distance in np.geomspace(1.05 * r0, 0.99 * min(reach, r0 * 2.0 ** (deepest - 1)), 12):
            point = np.array([distance * 0.6, -distance * 0.8])
            assert finest_size_at(after, point) / distance <= 2.0 * ratio0 + 1e-12
        assert finest_size_at(after, np.array([0.5 * r0, 0.0])) == pytest.approx(ratio0 * r0)
    # a graded grid is not graded again
    assert graded_around_contacts(graded, SimpleNamespace(contacts=[block])) is None


@pytest.mark.slow
def test_partial_slip_sphere_estimates_within_a_factor_two_of_theory():
    # the partial-slip sphere on a flat (a / h 5.8; its grid twice as coarse, a / h 2.9, fails the
    # Hertz-like test of the peak's inner reading): every estimate within a factor 2 of the true
    # error, never below half, against Hertz's radius and peak pressure and Mindlin's stick radius
    # c = a (1 - Q / (mu N))^(1/3) for the computed forces (Johnson, Contact Mechanics, 1985, 4.2, 7.2)
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import estimate_errors, solve

    scene = load_scene(ROOT / "examples" / "solid" / "sphere_on_flat_partial_slip.toml")
    solution = solve(scene.problem)
    estimate_errors(scene.problem, solution)
    c = solution.contacts[0]
    mats = [scene.problem.body(n).material for n in c["bodies"]]
    e_star = 1.0 / sum((1 - m.poissons_ratio ** 2) / m.youngs_modulus for m in mats)
    n_full, q_full = (f / c["model_share"] for f in (c["normal_force"], float(np.hypot(*c["tangential_force"]))))
    a = theory.hertz_sphere_radius(n_full, 1.0 / c["relative_curvatures"][0], e_star)
    stick = theory.mindlin_sphere_stick_ratio(q_full, n_full, c["friction"]) * a
    true = {"semi_axes": abs(c["semi_axes"][0] / a - 1.0), "stick_semi_axes": abs(c["stick_semi_axes"][0] / stick - 1.0),
            "max_pressure": abs(c["max_pressure"] / theory.hertz_sphere_peak_pressure(n_full, a) - 1.0)}
    estimated = c["estimated_error"]
    for key, error in true.items():
        value = estimated[key][0] if isinstance(estimated[key], list) else estimated[key]
        assert 0.5 <= value / error <= 2.0, (key, value, error)


def test_observed_orders_of_the_sizes_with_any_ratio():
    # three grids of q + C h^p with cells differing by (r1, r2): the order is recovered; clamped to
    # the range; a list's slowest element; none where the differences change sign
    from ibfem.solver.model.accuracy import observed_order, size_orders
    q, c, h = 0.0452, 0.03, 0.004
    for ratios in [(2.0, 2.0), (1.7, 2.0), (1.4, 1.6)]:
        grids = [q + c * (k * h) ** 1.7 for k in (1.0, ratios[0], ratios[0] * ratios[1])]
        assert observed_order(*grids, (1.0, 2.0), ratios) == pytest.approx(1.7, abs=1e-9)
        fast = [q + c * (k * h) ** 2.6 for k in (1.0, ratios[0], ratios[0] * ratios[1])]
        assert observed_order(*fast, (1.0, 2.0), ratios) == 2.0
        slow = [q + c * (k * h) ** 0.6 for k in (1.0, ratios[0], ratios[0] * ratios[1])]
        assert observed_order(*slow, (1.0, 2.0), ratios) == 1.0
        three = [{"semi_axes": [g, s], "normal_force": 1.0} for g, s in zip(grids, slow)]
        assert size_orders(*three, ratios=ratios) == {"semi_axes": 1.0}
    assert observed_order(q + 1e-6, q, q + 1e-6, (1.0, 2.0), (1.7, 2.0)) is None
    assert size_orders({"half_width": q + 1e-6}, {"half_width": q}, {"half_width": q + 1e-6}) == {}


@pytest.mark.parametrize("dim", [2, 3])
def test_largest_von_mises_reads_hertz_s_peak(dim):
    # a field that is Hertz's below the contact (the sphere's on its axis in 3D, the cylinder's in
    # plane strain in 2D, both p0 = 1, a = 1): the sampled largest stress is its peak, not the
    # largest of the coarse samples (in 3D 0.10 % below it)
    from types import SimpleNamespace

    from ibfem.solver.solving import max_von_mises
    nu = 0.3
    if dim == 3:
        z = np.linspace(0.0, 3.0, 30001)
        sr, sz = theory.hertz_sphere_axis_stress(z, 1.0, 1.0, nu)
        peak = float(np.max(np.abs(sr - sz)))

        def von_mises(pts):
            r, s = theory.hertz_sphere_axis_stress(np.abs(pts[:, 2]), 1.0, 1.0, nu)
            return np.abs(r - s)
        block = {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], "semi_axes": [1.0, 1.0],
                 "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]}
    else:
        peak = theory.axis_peak(nu, "von_mises")[0]

        def von_mises(pts):  # McEwen's field below the surface (the same in the other body)
            return theory.von_mises_plane_strain(*theory.mcewen_stress(pts[:, 0], np.abs(pts[:, 1]), 1.0, 1.0), nu)
        block = {"point": [0.0, 0.0], "normal": [0.0, 1.0], "half_width": 1.0}
    solution = SimpleNamespace(body_at=lambda pts: np.zeros(len(pts), dtype=int), von_mises=von_mises)
    assert max_von_mises(solution, block, dim) == pytest.approx(peak, rel=1e-4)


def test_next_rung_takes_the_cheaper_of_the_ratio_everywhere_and_the_contact_level():
    # the 3D sphere on a flat, its estimates those of its graded second rung on the 0.2 % ladder:
    # the von Mises stress asks for cells sqrt(0.53 / 0.18) times smaller; halving the contact's
    # cells would quadruple the dense contact block, and scaling every cell by that ratio is
    # estimated smaller: every cell scaled. In 2D the zone one level deeper is the smaller.
    from types import SimpleNamespace

    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.model.accuracy import TARGET_SHARE
    from ibfem.solver.model.resolve import resolve_problem
    from ibfem.solver.solving import _next_rung, graded_around_contacts
    block = {"point": [0.0, 0.0, 0.0], "semi_axes": [0.0451, 0.0451],
             "estimated_error": {"semi_axes": [0.0038, 0.0038], "normal_force": 0.0042, "max_von_mises": 0.0053}}
    scene = resolve_problem(load_scene(ROOT / "examples" / "solid" / "sphere_on_flat.toml").problem)
    problem = graded_around_contacts(scene, SimpleNamespace(contacts=[block]))
    finer, how, ratio = _next_rung(problem, SimpleNamespace(contacts=[block]), "max_von_mises", 0.002)
    assert how == "everywhere" and ratio == pytest.approx((0.0053 / (TARGET_SHARE * 0.002)) ** 0.5, rel=1e-12)
    assert all(f.element_size == pytest.approx(b.element_size / ratio) and f.refinements == b.refinements
               for f, b in zip(finer.bodies, problem.bodies))
    flat = _resolved_mesh_convergence()
    block2d = {"point": [0.0, 0.0], "half_width": 0.03, "estimated_error": {"half_width": 0.0043}}
    finer, how, ratio = _next_rung(flat, SimpleNamespace(contacts=[block2d]), "half_width", 0.002)
    assert how == "contact" and ratio == 2.0
    # no estimate to scale (a coarse partner without the contact): one level, as before
    from ibfem.solver.solving import rung_ratio
    assert rung_ratio(SimpleNamespace(contacts=[{"estimated_error": None}]), 0.002) == 2.0
