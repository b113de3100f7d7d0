"""The zones of Mindlin and Deresiewicz that the 3D fretting validation can impose for a
diagnostic (solver.reports.validate_fretting_sphere.ClosedFormZones), against the closed forms:
the stick circle c / a = (1 - |Q| / (mu N))^(1/3) on first loading and
(1 - |Q - Q_t| / (2 mu N))^(1/3) after a turning point Q_t, and a slip direction opposite to the
branch's change of the force on body 1 (R. D. Mindlin, H. Deresiewicz, J. Appl. Mech. 20 (1953)
327-344; K. L. Johnson, Contact Mechanics, 1985, section 7.3)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ibfem.solver.reference.fretting_sphere import branch_stick_ratio, stick_ratio
from ibfem.solver.reports.validate_fretting_sphere import ClosedFormZones

MU, N, A = 0.3, 1.0e6, 0.02
AXIS, NORMAL = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])


def _contact():
    frame = SimpleNamespace(axes=np.array([AXIS, [1.0, 0.0, 0.0]]), normal=NORMAL)
    return SimpleNamespace(frame=frame, friction=MU, h=1e-3,
                           normalised_radius=lambda s, a: np.hypot(s[:, 0], s[:, 1]) / a)


def _force(q: float) -> np.ndarray:
    return q * AXIS - N * NORMAL


def _radius_found(rule: ClosedFormZones, q: float) -> tuple[float, np.ndarray]:
    """The stick radius / a read from points along a ray, and the slip direction of the outermost."""
    s = np.column_stack([np.linspace(0.0, A, 20001), np.zeros(20001)])
    slip, direction = rule.zones(_contact(), s, A, _force(q))
    assert np.all(np.diff(slip.astype(int)) >= 0)  # one stick circle, the slip annulus outside it
    return float(s[np.argmax(slip), 0] / A) if slip.any() else 1.0, direction[-1]


def test_first_loading_and_branches_follow_the_closed_form():
    rule, c = ClosedFormZones(), _contact()
    # first loading to +0.6 mu N: Cattaneo-Mindlin's circle, slip against +Q (on body 1 the
    # friction traction -mu p e carries +Q: e = -axis)
    for q in (0.2, 0.4, 0.6):
        radius, e = _radius_found(rule, q * MU * N)
        assert abs(radius - stick_ratio(q * MU * N, N, MU)) < 1e-4
        np.testing.assert_allclose(e, -AXIS)
        rule.step_end(c, _force(q * MU * N))
    # unloading from the turning point +0.6 mu N: the reversed annulus c', slip the other way
    for q in (0.45, 0.0, -0.6):
        radius, e = _radius_found(rule, q * MU * N)
        assert abs(radius - branch_stick_ratio(q * MU * N, 0.6 * MU * N, N, MU)) < 1e-4
        np.testing.assert_allclose(e, AXIS)
        rule.step_end(c, _force(q * MU * N))
    # reloading from -0.6 mu N
    radius, e = _radius_found(rule, 0.1 * MU * N)
    assert abs(radius - branch_stick_ratio(0.1 * MU * N, -0.6 * MU * N, N, MU)) < 1e-4
    np.testing.assert_allclose(e, -AXIS)


def test_gross_slip_leaves_no_stick_zone():
    radius, _ = _radius_found(ClosedFormZones(), 1.2 * MU * N)
    assert radius <= 1.0 / 20000  # every point but the centre itself slips
