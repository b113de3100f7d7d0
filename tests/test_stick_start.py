"""Where a frictional 3D contact's load step starts its stick ratio: the last two settled ratios
extrapolated linearly (solver.contact.ellipse.predicted_stick_ratio). Only the start moves: the
step's ratio is still the root of Mindlin's condition, so the checks are on the start itself."""

import pytest

from ibfem.solver.contact.ellipse import predicted_stick_ratio


def test_a_linear_drift_is_continued_exactly():
    # ratios settled at equal load increments drifting linearly: the next is the line's next point
    settled = [0.85 + 0.003 * k for k in range(4)]
    assert predicted_stick_ratio(settled, settled[-1]) == pytest.approx(0.85 + 0.003 * 4, abs=1e-15)


def test_fewer_than_two_steps_keep_the_current_ratio():
    assert predicted_stick_ratio([], 1.0) == 1.0
    assert predicted_stick_ratio([0.86], 0.86) == 0.86


def test_the_start_stays_a_ratio():
    # c / a lies in [0, 1]: a drift towards full stick or gross slip is cut there
    assert predicted_stick_ratio([0.9, 0.99], 0.99) == 1.0
    assert predicted_stick_ratio([0.2, 0.05], 0.05) == 0.0


def test_gross_slip_in_either_step_keeps_the_current_ratio():
    # a step that slipped grossly (ratio 0) says nothing about the drift
    assert predicted_stick_ratio([0.0, 0.4], 0.4) == 0.4
    assert predicted_stick_ratio([0.4, 0.0], 0.0) == 0.0
