"""2D contacts as CAD makes them: contact curves that are chains of edges (tangent junctions,
corners, a full circle's seam), the two kinds of region ends (incomplete on a smooth surface,
complete at a corner of body 1) and half models on a symmetry line.

The references are closed forms (solver.reference.punch): the rounded flat punch of Ciavarella,
Hills and Monno (1998) and Sadowsky's sharp flat punch. The FE runs here use coarse grids
(finest cell b / 16 to b / 32) with tolerances to match; the validation grids are in
tests/test_contact2d_validation.py (slow)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.polynomial.legendre import leggauss

from ibfem.geometry.shapes import profile_from_shape
from ibfem.solver.contact.chain import CORNER_ANGLE, contact_chain
from ibfem.solver.contact.ends import (CONFORMAL_CELLS, GAP_NODES, chebyshev_ends, conformal_weight, gap_pressure,
                                      gap_slope_coefficients)
from ibfem.solver.io.scene import SceneError, scene_from_dict
from ibfem.solver.reference.punch import (flat_punch_pressure, flat_punch_stress_intensity, rounded_punch_half_width,
                                          rounded_punch_load, rounded_punch_pressure)
from ibfem.solver.solving import solve

from _contact2d_scenes import E_STAR, EDGE_RADIUS, EDGE_TURN, HALF_FLAT, _punch_edges, pin_in_bore, punch_on_block

B, R = HALF_FLAT, EDGE_RADIUS


# ------------------------------------------------------------------ chains of edges


def test_chain_joins_the_loop_and_finds_only_real_corners():
    profile = profile_from_shape({"type": "profile", "edges": _punch_edges(B, R, 0.1, sharp=False)})
    chain = contact_chain(profile, dict(profile.edges), "flat")
    k = chain.middle
    assert chain.names[k] == "flat" and len(chain.names) == 2 * 6 + 1
    # continuous through every junction, and dX/dT is the edge's derivative times its span
    for j in range(1, len(chain.names)):
        left, right = chain.evaluate(np.array([j - 1e-12, j + 1e-12]))
        assert np.hypot(*(left - right)) < 1e-9
    t = np.array([0.3])
    edge = chain.curves[k]
    span = float(edge.t_end) - float(edge.t_start)
    np.testing.assert_allclose(chain.derivative(k + t), np.asarray(edge.derivative(chain.local(k, k + t))) * span,
                               rtol=1e-14)
    # the flat -> arc -> flank junctions are tangent; the flank -> top junctions are convex corners
    corners = {chain.edge_at(T - 0.5) + ">" + chain.edge_at(T + 0.5) for T in chain.corners()}
    assert corners == {"flank_right>top", "top>flank_left"}
    assert np.all(np.abs(chain.turns[np.abs(chain.turns) <= CORNER_ANGLE]) < 1e-12)
    np.testing.assert_allclose(chain.turns[chain.turns > CORNER_ANGLE], math.radians(180.0 - EDGE_TURN), rtol=1e-12)


def test_chain_of_a_full_circle_crosses_its_seam():
    profile = profile_from_shape({"type": "profile", "edges": [
        {"name": "rim", "type": "arc", "center": [0.0, 0.0], "radius": 0.5, "start_angle": -90.0, "end_angle": 270.0}]})
    chain = contact_chain(profile, dict(profile.edges), "rim")
    assert chain.names == ("rim",) * 3 and chain.corners().size == 0
    # across the seam (T = 1, 2) the points run on around the circle
    T = np.linspace(0.9, 2.1, 13)
    x = chain.evaluate(T)
    np.testing.assert_allclose(np.hypot(*x.T), 0.5, rtol=1e-14)
    angle = np.unwrap(np.arctan2(x[:, 1], x[:, 0]))
    np.testing.assert_allclose(np.diff(angle), 0.1 * 2 * math.pi, rtol=1e-12)


# ------------------------------------------------------------------ the ends of a region


def _gauss(lo, hi, pieces=400, order=8):
    x, w = leggauss(order)
    edges = np.linspace(lo, hi, pieces + 1)
    mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
    return (mid[:, None] + half[:, None] * x).ravel(), (half[:, None] * w).ravel()


def _cos_nodes(a, n=4000):
    theta = (np.arange(n) + 0.5) * np.pi / n
    return a * np.cos(theta), a * np.sin(theta) * np.pi / n  # Gauss-Chebyshev: exact for p sqrt(a^2 - s^2) smooth


def test_end_values_of_hertz_and_sadowsky():
    a, load = 0.02, 1.0e6
    s, w = _cos_nodes(a)
    hertz = 2 * load / (math.pi * a) * np.sqrt(1 - (s / a) ** 2)
    v = chebyshev_ends(s / a, w, hertz, a)
    assert abs(v.coefficient(1)) < 1e-12 and abs(v.coefficient(-1)) < 1e-12
    v = chebyshev_ends(s / a, w, flat_punch_pressure(s, load, a), a)
    assert v.upper == pytest.approx(load / math.pi, rel=1e-12)
    assert v.stress_intensity(1, a) == pytest.approx(flat_punch_stress_intensity(load, a), rel=1e-12)


@pytest.mark.parametrize("ratio", [1.1, 1.5, 3.0])
def test_end_values_of_the_rounded_punch_need_the_gap_shape(ratio):
    # at the closed form's own width both ends are incomplete (Q = 0); the degree-2 Chebyshev sum
    # alone sees them as singular, the gap's truncation removed it does not
    a = ratio * B
    s, w = _cos_nodes(a)
    p = rounded_punch_pressure(s, a, B, R, E_STAR)
    slope = lambda x: np.sign(x) * np.maximum(np.abs(x) - B, 0.0) / R  # noqa: E731
    gap = gap_slope_coefficients(slope, 0.0, a, E_STAR)
    assert chebyshev_ends(s / a, w, p, a).coefficient(1) > 0.02
    for higher in (0.0, 1.0):  # the degree-2 and degree-4 sums (GAP_NODES quadrature of the kinked slope)
        assert abs(chebyshev_ends(s / a, w, p, a, gap, higher).coefficient(1)) < 5e-4
    # the gap's own half-plane pressure is the closed form's (a series of GAP_NODES terms: RMS)
    assert np.sqrt(np.average((gap_pressure(gap, s / a) - p) ** 2, weights=w)) < 3e-3 * p.max()


# ------------------------------------------------------------------ the closed forms


def test_rounded_punch_closed_form():
    a = 1.5 * B
    s, w = _gauss(-a, a)
    p = rounded_punch_pressure(s, a, B, R, E_STAR)
    assert w @ p == pytest.approx(rounded_punch_load(a, B, R, E_STAR), rel=1e-6)
    assert rounded_punch_half_width(rounded_punch_load(a, B, R, E_STAR), B, R, E_STAR) == pytest.approx(a, rel=1e-12)
    # its defining principal value: with t = a cos(u), PV int_0^pi du / (cos u - cos u0) = 0, so
    # PV int h'(t) dt / (sqrt(a^2 - t^2) (t - x)) = int_0^pi (h'(a cos u) - h'(x)) / (a cos u - x) du
    ub = math.acos(B / a)
    u, wu = np.concatenate([_gauss(0, ub)[0], _gauss(ub, math.pi - ub)[0], _gauss(math.pi - ub, math.pi)[0]]), \
        np.concatenate([_gauss(0, ub)[1], _gauss(ub, math.pi - ub)[1], _gauss(math.pi - ub, math.pi)[1]])
    slope = lambda t: np.sign(t) * np.maximum(np.abs(t) - B, 0.0) / R  # noqa: E731
    for x in (0.0, 0.3 * a, 0.8 * a):
        t = a * np.cos(u)
        pv = wu @ ((slope(t) - slope(x)) / (t - x))
        assert rounded_punch_pressure(np.array([x]), a, B, R, E_STAR)[0] == pytest.approx(
            E_STAR / (2 * math.pi) * math.sqrt(a * a - x * x) * pv, rel=1e-8)
    # b -> 0: Hertz's cylinder
    s = np.linspace(-0.9 * a, 0.9 * a, 7)
    np.testing.assert_allclose(rounded_punch_pressure(s, a, 0.0, R, E_STAR),
                               E_STAR / (2 * R) * np.sqrt(a * a - s * s), rtol=1e-12)


# ------------------------------------------------------------------ coarse FE runs


def _run(scene: dict):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy warnings
        sol = solve(scene_from_dict(scene).problem)
    return sol, sol.contacts[0]


def _rounded_check(c, factor, a_tol, rms_tol):
    a_ref = rounded_punch_half_width(factor * c["normal_force"], B, R, E_STAR)
    assert c["half_width"] == pytest.approx(a_ref, rel=a_tol)
    s, p = np.array(c["pressure"]["s"]), np.array(c["pressure"]["value"])
    inside = np.abs(s) < a_ref
    ref = rounded_punch_pressure(np.abs(s), a_ref, B, R, E_STAR)
    assert np.sqrt(np.mean((p - ref)[inside] ** 2)) < rms_tol * ref.max()


def test_rounded_punch_region_crosses_the_tangent_junctions():
    sol, c = _run(punch_on_block(8.1e-5, levels=6))  # a / b ~ 1.5, a / h ~ 24
    assert sol.converged
    assert 1.4 < c["half_width"] / B < 1.7  # the region reaches onto both rounded edges
    assert [e["type"] for e in c["ends"]] == ["incomplete", "incomplete"]
    _rounded_check(c, 1.0, 0.005, 0.03)


def test_half_model_on_the_symmetry_line():
    sol, c = _run(punch_on_block(8.1e-5, levels=6, half=True))
    assert sol.converged
    lo, hi = c["region"]
    assert min(abs(lo), abs(hi)) == 0.0 and max(abs(lo), abs(hi)) == pytest.approx(c["half_width"])
    assert sorted(e["type"] for e in c["ends"]) == ["incomplete", "symmetry"]
    _rounded_check(c, 2.0, 0.005, 0.03)


def test_half_model_needs_a_sliding_condition():
    with pytest.raises(SceneError, match="symmetry line"):
        scene_from_dict(punch_on_block(8.1e-5, levels=6, half=True, sliding=False))


def test_sharp_punch_is_a_complete_contact():
    sol, c = _run(punch_on_block(2e-4, levels=6, sharp=True, punch_modulus=100 * 2.0e11))
    assert sol.converged
    assert c["half_width"] == pytest.approx(B, rel=1e-12)
    load = c["normal_force"]
    for end in c["ends"]:
        assert end["type"] == "complete"
        assert end["stress_intensity"] == pytest.approx(flat_punch_stress_intensity(load, B), rel=0.06)
    s, p = np.array(c["pressure"]["s"]), np.array(c["pressure"]["value"])
    inner = np.abs(s) < 0.9 * B
    assert np.abs(p - flat_punch_pressure(s, load, B))[inner].max() < 0.06 * load / (2 * B)


def test_refinement_follows_a_region_beyond_its_radius():
    # the region (a ~ 0.015 m) does not fit in the candidate region of a 0.01 m refinement radius
    # (0.008 m): a coarse pass finds it, the refinement is widened about it and the scene solved
    sol, c = _run(punch_on_block(8.1e-5, levels=4, radius=0.01))
    assert sol.converged
    grown = sol.iterations["refinement"]
    assert grown["coarse_passes"][-1]["region"] is not None
    assert 0.8 * 0.01 * grown["radius_factor"] > c["half_width"]  # the fine pass's candidate region holds it
    _rounded_check(c, 1.0, 0.005, 0.05)


def test_growing_refinement_refuses_other_causes():
    from ibfem.solver.contact.band import CandidateRegionExceeded
    from ibfem.solver.contact.grow import MAX_COARSE_PASSES, solve_growing

    problem = scene_from_dict(punch_on_block(8.1e-5, levels=4, radius=0.01)).problem
    calls = []

    def run(cause):
        def attempt(p):
            calls.append(min(r.radius for r in p.body("punch").refinements if r.around_contact))
            raise CandidateRegionExceeded(("punch", "block"), cause, f"bounded by the {cause}")
        return attempt

    # a region bounded by a body's far side: the bodies are too small, no coarse pass
    with pytest.raises(CandidateRegionExceeded, match="far side"):
        solve_growing(problem, run("far side of body 'block'"))
    assert len(calls) == 1
    # a region that runs off every widened refinement is refused with the widening said
    calls.clear()
    with pytest.raises(CandidateRegionExceeded, match="still after widening the contact refinement 16 times"):
        solve_growing(problem, run("refinement radius"))
    assert len(calls) == 1 + MAX_COARSE_PASSES and calls[-1] == pytest.approx(16 * calls[0])


# ------------------------------------------------------------------ the pin in a bore


def test_pin_in_bore_reference():
    from ibfem.solver.reference.pin import _dimensionless_load

    # small angles: Hertz's cylinder in a bore, P = pi E* dR alpha^2 / 4 (R* = R (R + dR) / dR)
    assert _dimensionless_load(0.01) == pytest.approx(math.pi * 0.01**2 / 4, rel=1e-4)
    # conformity stiffens the contact: at 0.55 rad Hertz's angle for Persson's load is 9 % larger
    # (its convergence, monotony and inverse: tests/test_contact2d_validation.py, slow)
    hertz = math.sqrt(4 * _dimensionless_load(0.55) / math.pi)
    assert hertz / 0.55 == pytest.approx(1.0907, abs=5e-4)


def test_pin_in_bore_pressure_and_its_end_values():
    from ibfem.solver.reference.pin import pin_in_bore_load, pin_in_bore_pressure

    radius, clearance = 0.5, 5e-4
    # a small angle: Hertz's cylinder in a bore, p = (E* / (2 R*)) sqrt(a^2 - s^2), R* = R (R + dR) / dR
    angle = 0.02
    theta = np.linspace(-0.95, 0.95, 9) * angle
    hertz = E_STAR * clearance / (2 * radius * (radius + clearance)) * radius * np.sqrt(angle**2 - theta**2)
    np.testing.assert_allclose(pin_in_bore_pressure(theta, angle, radius, clearance, E_STAR), hertz, rtol=2e-3)
    # at 1.3 rad: its resultant is the load, P = int p cos(theta) R dtheta
    angle = 1.3
    theta, dtheta = _cos_nodes(angle)
    p = pin_in_bore_pressure(theta, angle, radius, clearance, E_STAR)
    assert (dtheta * p) @ np.cos(theta) * radius == pytest.approx(pin_in_bore_load(angle, clearance, E_STAR), rel=1e-6)
    # at its own angle the ends are incomplete (Q = 0). In the chord coordinate the gap is quadratic
    # (h = dR s^2 / (2 R^2)) but the conformal pressure is not the half-plane's: the degree-2
    # Chebyshev sum sees tension at the ends (-2.3e-2), the degree-4 sum (a conformal contact's, on a
    # region of enough cells) is within 5e-4
    s, w = 2 * radius * np.sin(theta / 2), radius * np.cos(theta / 2) * dtheta  # chord, ds
    a = 2 * radius * math.sin(angle / 2)
    v2, v4 = (chebyshev_ends(s / a, w, p, a, higher=h) for h in (0.0, 1.0))
    assert v2.coefficient(1) < -0.02 and abs(v4.coefficient(1)) < 5e-4
    # half way between CONFORMAL_CELLS: half of the degree-4 terms
    mid = chebyshev_ends(s / a, w, p, a, higher=conformal_weight(a, a / (0.5 * sum(CONFORMAL_CELLS))))
    assert mid.upper == pytest.approx(0.5 * (v2.upper + v4.upper), rel=1e-12)


# ------------------------------------------------------------------ one complete and one incomplete end


def test_one_sided_reference_is_the_tilted_flat_punch():
    # a flat punch tilted by eps toward its upper corner: p = (E* eps / 2) sqrt((1 + x) / (1 - x)),
    # P = pi E* eps a / 2 (Johnson, Contact Mechanics, 1985, sec. 2.8), and K = E* eps sqrt(pi a)
    from ibfem.solver.reference.one_sided import one_sided_load, one_sided_pressure, one_sided_stress_intensity

    eps, a = 1e-3, 0.01
    slope = lambda s: np.full_like(s, -eps)  # noqa: E731
    s = np.linspace(-0.99, 0.99, 9) * a
    closed = E_STAR * eps / 2 * np.sqrt((a + s) / (a - s))
    np.testing.assert_allclose(one_sided_pressure(s, slope, -a, a, E_STAR), closed, rtol=1e-10)
    assert one_sided_load(slope, -a, a, E_STAR) == pytest.approx(math.pi * E_STAR * eps * a / 2, rel=1e-12)
    assert one_sided_stress_intensity(slope, -a, a, E_STAR) == pytest.approx(E_STAR * eps * math.sqrt(math.pi * a),
                                                                            rel=1e-12)
    # mirrored: the lower end complete
    np.testing.assert_allclose(one_sided_pressure(-s, lambda t: -slope(t), -a, a, E_STAR, complete=-1), closed,
                               rtol=1e-10)


def _one_sharp_reference(load, e_star):
    from ibfem.solver.reference.one_sided import one_sided_region, one_sided_stress_intensity

    # the punch's flat ends at its sharp corner (x = b) and on its rounded edge (x = -b); the
    # chord s of the region runs along -x, so the corner is at s = -b and the gap grows for s > b
    def slope(s):
        t = np.maximum(np.asarray(s, dtype=float) - B, 0.0)
        return t / np.sqrt(R * R - t * t)

    lo, hi = one_sided_region(load, slope, -B, e_star, complete=-1, longest=0.1)
    return lo, hi, one_sided_stress_intensity(slope, lo, hi, e_star, complete=-1), slope


def test_punch_with_one_sharp_edge_pins_the_region_at_its_corner():
    # one sharp and one rounded edge, the punch 100 times stiffer than the block: the region runs
    # from the sharp corner (complete end) onto the rounded edge (incomplete end); its length and
    # the corner's stress intensity against the half-plane reference (solver.reference.one_sided)
    from _contact2d_scenes import NU

    sol, c = _run(punch_on_block(2e-4, levels=6, one_sharp=True, punch_modulus=100 * 2.0e11))
    e_star = 1.0 / ((1 - NU**2) / 2.0e11 + (1 - NU**2) / (100 * 2.0e11))
    lo, hi, k, slope = _one_sharp_reference(c["normal_force"], e_star)
    assert [e["type"] for e in c["ends"]] == ["complete", "incomplete"]
    assert c["ends"][0]["s"] == pytest.approx(-B, rel=1e-9)
    assert (c["region"][1] - c["region"][0]) / (hi - lo) == pytest.approx(1.0, abs=0.005)
    assert c["ends"][0]["stress_intensity"] == pytest.approx(k, rel=0.03)
    assert not c["checks"]["penetration"] and c["checks"]["centroid_offset"] == 0.0
    # the recovered pressure (the gap's half-plane shape and singular modes) away from the corner
    from ibfem.solver.reference.one_sided import one_sided_pressure

    s, p = np.array(c["pressure"]["s"]), np.array(c["pressure"]["value"])
    inner = (s > lo + 0.1 * (hi - lo)) & (s < hi)
    ref = one_sided_pressure(s, slope, lo, hi, e_star, complete=-1)
    assert np.sqrt(np.mean((p - ref)[inner] ** 2)) < 0.02 * c["normal_force"] / (hi - lo)



def test_free_end_value_is_exact_and_blind_to_the_corner():
    # a region with a corner at x = +1: Q = (a P / pi)(1 + x) / 2 + the bounded pressure of a
    # curved gap (b_2, b_3 != 0); the free end's value Q(-1) from the corner-free moment is exact,
    # and an error of the singular value within 3 % of the region next to the corner (what the
    # discrete pressure does there) moves it far less than it moves the degree-2 sum
    from ibfem.solver.contact.ends import free_end_value

    a, load = 0.01, 1.0e6
    s, w = _cos_nodes(a)
    x = s / a
    b = np.zeros(GAP_NODES)
    b[1:4] = [2.0e8, 5.0e7, -3.0e7]
    p = load / (math.pi * a) * (1 + x) / np.sqrt(1 - x * x) / 2 + gap_pressure(b, x)
    assert free_end_value(x, w, p, a, -1, b) == pytest.approx(0.0, abs=1e-9 * load / math.pi)
    assert chebyshev_ends(x, w, p, a, b).lower == pytest.approx(0.0, abs=1e-9 * load / math.pi)
    wrong = p * np.where(x > 0.97, 1.3, 1.0)
    moved_free = abs(free_end_value(x, w, wrong, a, -1, b)) / (load / math.pi)
    moved_sum = abs(chebyshev_ends(x, w, wrong, a, b).lower) / (load / math.pi)
    assert moved_free < 0.1 * moved_sum


@pytest.mark.parametrize("point, levels", [("corner", 6), ("far", 6), ("none", 6), ("far", 7)])
def test_tilted_punch_touching_at_its_corner(point, levels):
    # a sharp flat punch tilted by 2 mrad touches at its right corner: the contact point given at
    # the corner, beside the other corner or found as the closest points; the region runs from the
    # corner (complete end) along the flat to where the pressure vanishes, and Johnson's tilted
    # punch (Contact Mechanics, 1985, sec. 2.8: P = pi E* eps a / 2 for a region of length 2 a,
    # K = E* eps sqrt(pi a) at the corner) is met to first order in the cell (finest 6.3e-4 m
    # here: -2.0 % and +7.0 %; 3.1e-4 m: -0.8 % and +3.5 %; the slow validation halves the cell
    # twice). The point beside the other corner on 3.1e-4 m cells ended not converged when the
    # final check read a sample at the corner itself, outside the region by round-off, as
    # penetration (nothing of body 1 lies beyond a pinned corner)
    from _contact2d_scenes import NU, tilted_punch

    eps = 0.002
    sol, c = _run(tilted_punch(6e-5, eps, levels=levels, point=point))
    e_star = 1.0 / ((1 - NU**2) / 2.0e11 + (1 - NU**2) / (1000 * 2.0e11))
    a = 2.0 * c["normal_force"] / (math.pi * e_star * eps)
    assert sol.converged
    assert sorted(e["type"] for e in c["ends"]) == ["complete", "incomplete"]
    corner, = [e for e in c["ends"] if e["type"] == "complete"]
    assert (c["region"][1] - c["region"][0]) / (2 * a) == pytest.approx(1.0, abs=0.03)
    assert corner["stress_intensity"] / (e_star * eps * math.sqrt(math.pi * a)) == pytest.approx(1.0, abs=0.1)


def test_contact_point_at_a_corner_moves_into_the_facing_edge():
    # the tilted punch's corner: the resolved point lies on the punch's flat (not its side), two
    # finest cells from the corner, and on the block's top within the tilt's rise
    from ibfem.solver.model.resolve import CORNER_OFFSET_CELLS

    from _contact2d_scenes import tilted_punch

    scene = scene_from_dict(tilted_punch(6e-5, 0.002, levels=6, point="corner"))
    punch = scene.problem.body("punch").profile
    p = np.asarray(scene.problem.contacts[0].point, dtype=float)
    proj = punch.project(p[None, :])
    assert punch.edge_names[int(proj.edge_index[0])] == "flat"
    assert abs(float(punch.signed_distance(p[None, :])[0])) < 1e-12
    corner = np.array([HALF_FLAT, 0.0])
    assert np.hypot(*(p - corner)) == pytest.approx(CORNER_OFFSET_CELLS * 0.04 / 2**6, rel=1e-6)
    assert np.allclose(scene.problem.contacts[0].moved_from, corner, atol=1e-15)  # the summary's given_point
