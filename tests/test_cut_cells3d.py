"""Cut-cell moments of solver/fem/cut_cells3d.py: leaves whose lines run along different axes
integrated in one pass against the closed-form moments of a ball and the volume of a turned box,
and a bound on the calls of the signed distance (the rules batch every leaf of every level)."""

import numpy as np
import pytest

import ibfem.solver.fem.cut_cells3d as cc
from ibfem.solver.fem.hexahedra import full_cube_moments
from ibfem.solver.fem.octree import build_octree

CENTRE = np.array([0.05, -0.03, 0.02])
RADIUS = 1.0


def _ball(p):
    return RADIUS - np.linalg.norm(p - CENTRE, axis=1)


def _world_moments(phi, bounds, h, depth):
    """Volume V, first moments S_a and second moments I_ab about CENTRE of the region phi > 0,
    summed from the cut-cell moments of a grid of h (monomial 9 a + 3 b + c is xi^a eta^b zeta^c
    in each cell's local coordinates, x = centre + half xi)."""
    tree = build_octree(bounds, h, (), lambda lo, s: phi(lo + 0.5 * s[:, None]) > -0.87 * s, (0.013, 0.007, 0.011))
    status = cc.classify_cells(tree.lower, tree.size, phi)
    mom = np.zeros((len(tree.size), 27))
    mom[status == cc.INSIDE] = full_cube_moments()
    cut = status == cc.CUT
    mom[cut] = cc.inside_moments(tree.lower[cut], tree.size[cut], phi, depth)
    half = 0.5 * tree.size
    c = tree.center - CENTRE
    unit = np.eye(3, dtype=int)
    m = lambda e: mom[:, 9 * e[0] + 3 * e[1] + e[2]]  # noqa: E731
    volume = (half**3 * m((0, 0, 0))).sum()
    first = np.array([(half**3 * (c[:, a] * m((0, 0, 0)) + half * m(unit[a]))).sum() for a in range(3)])
    second = np.zeros((3, 3))
    for a in range(3):
        for b in range(3):
            term = c[:, a] * c[:, b] * m((0, 0, 0)) + half * (c[:, a] * m(unit[b]) + c[:, b] * m(unit[a]))
            second[a, b] = (half**3 * (term + half**2 * m(unit[a] + unit[b]))).sum()
    return volume, first, second


def test_ball_moments_with_mixed_line_axes_in_one_pass(monkeypatch):
    # every smooth leaf of every level goes through one call of the reduced rule, whose rows
    # run their lines along all three axes; the sums are the ball's closed-form moments
    calls = []
    rule = cc._reduced_rule

    def recording(signed_distance, cell_lower, scale, lo, width, axes):
        calls.append(axes.copy())
        return rule(signed_distance, cell_lower, scale, lo, width, axes)

    monkeypatch.setattr(cc, "_reduced_rule", recording)
    volume, first, second = _world_moments(_ball, ([-1.5] * 3, [1.5] * 3), 0.25, depth=1)
    assert len(calls) == 1
    axes = calls[0]
    assert set(axes[:, 0]) == {0, 1, 2} and len({tuple(a) for a in axes}) == 6  # all (k, j, i)
    assert volume == pytest.approx(4 / 3 * np.pi * RADIUS**3, rel=1e-10)
    np.testing.assert_allclose(first, 0.0, atol=1e-10 * RADIUS**4)
    np.testing.assert_allclose(second, 4 * np.pi / 15 * RADIUS**5 * np.eye(3), rtol=0, atol=1e-10 * RADIUS**5)


def test_turned_box_volume_through_the_kinked_rule():
    # a box turned by 25 degrees about (1, 2, 3): its edges and vertices take the plain rule
    # (lines along all three axes in one pass); its volume and centroid to about 1e-5
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    angle = np.radians(25.0)
    rot = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    size = np.array([1.0, 0.8, 0.6])

    def box(p):
        d = np.maximum(-((p - CENTRE) @ rot), (p - CENTRE) @ rot - size)
        return -(np.linalg.norm(np.maximum(d, 0.0), axis=1) + np.minimum(d.max(axis=1), 0.0))

    volume, first, _ = _world_moments(box, ([-1.0] * 3, [1.5] * 3), 0.3, depth=1)
    assert volume == pytest.approx(size.prod(), rel=2e-5)
    np.testing.assert_allclose(first / volume, rot @ (0.5 * size), atol=2e-5)


def test_calls_of_the_signed_distance_are_bounded():
    # 50 cut cells at depth 3: two calls per level, then one batched pass of each rule (their
    # root searches share calls across all lines); the per-axis passes made hundreds
    calls = [0]

    def counting(p):
        calls[0] += 1
        return _ball(p)

    lower = np.array([CENTRE + RADIUS * np.array([np.cos(t) * np.cos(s), np.sin(t) * np.cos(s), np.sin(s)]) - 0.1
                      for t, s in zip(np.linspace(0, 2 * np.pi, 50, endpoint=False), np.linspace(-1.2, 1.2, 50))])
    size = np.full(50, 0.2)
    assert (cc.classify_cells(lower, size, _ball) == cc.CUT).all()
    cc.inside_moments(lower, size, counting, depth=3)
    assert calls[0] <= 2 * (3 + cc.EDGE_DEPTH + 1) + 4 * (cc.ROOT_STEPS + 1)
    assert calls[0] <= 60
