"""The 3D touching point (solver.contact.touching3d): a contact point given off the touching point
of two curved solids moves to it, so the frame's normal is the line of centres of two balls (the
exact touching geometry), not body 2's normal at the given point."""

import numpy as np
import pytest

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.contact.ellipse_geometry import contact_frame_3d
from ibfem.solver.contact.touching3d import touching_frame_3d


def _half_ball(centre_z, below, radius=1.0, angle=360):
    end = -90 if below else 90
    return solid_from_dict({"type": "revolution", "axis_origin": [0, 0, centre_z], "axis": [0, 0, 1], "angle_deg": angle,
                            "profile": {"type": "profile", "edges": [
                                {"type": "line", "start": [0, 0], "end": [radius, 0], "name": "flat"},
                                {"type": "arc", "center": [0, 0], "radius": radius, "start_angle": 0,
                                 "end_angle": end, "name": "dome"},
                                {"type": "line", "start": [0, -radius if below else radius], "end": [0, 0],
                                 "name": "axis"}]}})


@pytest.mark.parametrize("offset", [(0.01, 0.005), (-0.03, 0.02)])
def test_off_point_moves_to_the_touching_point_of_two_balls(offset):
    # upper ball R = 1 centred (0, 0, 1 + g), lower ball R = 0.5 centred (0, 0, -0.5): they are
    # nearest on the z axis, the gap g between them; the line of centres is the z axis
    gap = 1e-4
    upper, lower = _half_ball(1.0 + gap, below=True), _half_ball(-0.5, below=False, radius=0.5)
    given = np.array([offset[0], offset[1], 0.0])
    tilted = contact_frame_3d(upper, lower, given, 0.005)
    assert np.degrees(np.arccos(min(1.0, tilted.normal @ [0, 0, 1]))) > 0.5  # the defect this fixes
    frame, moved, ranges = touching_frame_3d(upper, lower, given, 0.005, 0.05)
    assert moved and ranges == [(0.0, 2 * np.pi)]  # body 1 all around the point it moved to
    np.testing.assert_allclose(frame.normal, [0, 0, 1], atol=1e-8)
    np.testing.assert_allclose(frame.point, [0, 0, 0.5 * gap], atol=1e-8)
    np.testing.assert_allclose(frame.curvatures, [3.0, 3.0], rtol=1e-4)  # 1/R1 + 1/R2


def test_the_touching_point_itself_and_a_quarter_model_stay():
    upper, lower = _half_ball(1.0 + 1e-4, below=True), _half_ball(-1.0, below=False)
    frame, moved, _ = touching_frame_3d(upper, lower, np.zeros(3), 0.005, 0.05)
    assert not moved
    np.testing.assert_allclose(frame.normal, [0, 0, 1], atol=1e-12)
    # a quarter model: body 1 is not all around the point (its symmetry planes pass through it)
    quarter = _half_ball(1.0 + 1e-4, below=True, angle=90)
    _, moved, ranges = touching_frame_3d(quarter, _half_ball(-1.0, below=False, angle=90), np.zeros(3), 0.005, 0.05)
    assert not moved
    assert sum(t1 - t0 for t0, t1 in ranges) == pytest.approx(np.pi / 2, abs=1e-6)  # the quarter's sector
