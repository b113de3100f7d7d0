"""The 3D friction history's region quadrature follows the cells it lies in
(solver.contact.friction_history3d.GRADED_QUADRATURE): a grid refined further only in part of
the contact (a ball of finer cells at its edge) adds points only there, while the rule keeps
integrating the region exactly; on cells of one size it is the finest cell's uniform rule."""

from __future__ import annotations

import numpy as np
import pytest

A = 0.0449  # the fretting example's contact radius (m)


def _contact(extra_ball: bool):
    from ibfem.solver.contact.driver import ContactDriver
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.reports.validate_fretting_sphere import EXAMPLE, scene_data

    data = scene_data(1e-4, 0.5, 20, refinement_levels=4)  # the example's grid one level coarser (a / h = 2.9)
    if extra_ball:  # one level finer in a ball at the contact's edge
        for body in data["bodies"]:
            body["refinement"] = [body["refinement"], {"levels": 5, "radius": 0.015, "around": [0.04, 0.0, 0.0]}]
    driver = ContactDriver(scene_from_dict(data, label=str(EXAMPLE), base_dir=EXAMPLE.parent).problem)
    driver._discretise()
    driver._assemble()
    return driver.contacts[0]


def _moments(pts, powers=(0, 2, 4)):
    r = np.hypot(pts.s[:, 0], pts.s[:, 1])
    return np.array([np.sum(pts.weights * r ** k) for k in powers])


@pytest.mark.parametrize("extra_ball", [False, True])
def test_graded_quadrature_against_the_uniform_rule(extra_ball):
    from ibfem.solver.contact.ellipse import EllipseContact
    from ibfem.solver.contact.friction_history3d import HistoryEllipseContact

    c = _contact(extra_ball)
    assert isinstance(c, HistoryEllipseContact)
    graded, uniform = c.region_quadrature(A), EllipseContact.region_quadrature(c, A)
    # both integrate the half disc's area and its radial moments (exact for each rule's pieces)
    np.testing.assert_allclose(_moments(graded), _moments(uniform), rtol=1e-8)
    np.testing.assert_allclose(np.sum(graded.weights), 0.5 * np.pi * A * A, rtol=2e-3)  # the ball's surface
    if not extra_ball:  # cells of one size: the same points and weights (in another order)
        (sg, wg), (su, wu) = ((np.round(p.s / A, 9), p.weights) for p in (graded, uniform))
        og, ou = np.lexsort(sg.T), np.lexsort(su.T)
        np.testing.assert_allclose(sg[og], su[ou], rtol=0.0, atol=1e-8)
        np.testing.assert_allclose(wg[og], wu[ou], rtol=1e-9, atol=1e-9 * wu.max())  # slivers to round-off
        return
    # the finer ball's cells keep the finest cell's density; the coarser cells get a quarter of it
    assert len(graded.weights) < 0.5 * len(uniform.weights)
    in_ball = [np.hypot(p.s[:, 0] - 0.04, p.s[:, 1]) < 0.008 for p in (graded, uniform)]
    assert in_ball[0].sum() >= 0.9 * in_ball[1].sum()
