"""The loop's energy per cycle (solver.io.fretting_outputs.loop_energy) on Mindlin and
Deresiewicz's loop for a sphere, sampled as a run samples it (Q linear in the load parameter
between turning points, 20 points a cycle), against its closed form (Johnson 1985, section 7.4)."""

import numpy as np
import pytest

from ibfem.solver.io.fretting_outputs import loop_energy


def _cycle(x: float, points: int):
    """Q / (mu N) and delta / C over one cycle from +Q* down to -Q* and back, where
    delta_1(Q) = C (1 - (1 - Q / (mu N))^(2/3)) is the first loading's compliance (mu N = C = 1)."""
    first = lambda q: 1.0 - (1.0 - q) ** (2.0 / 3.0)
    top = first(x)
    half = points // 2
    down = np.linspace(x, -x, half + 1)
    up = np.linspace(-x, x, half + 1)[1:]
    d_down = top - 2.0 * first((x - down) / 2.0)
    d_up = -top + 2.0 * first((up + x) / 2.0)
    return np.concatenate([down, up]), np.concatenate([d_down, d_up])


def _closed_form(x: float) -> float:
    """W / (C mu N) = (24 / 5) (1 - (1 - x)^(5/3) - (5 x / 6) (1 + (1 - x)^(2/3)))."""
    return 4.8 * (1.0 - (1.0 - x) ** (5.0 / 3.0) - 5.0 * x / 6.0 * (1.0 + (1.0 - x) ** (2.0 / 3.0)))


@pytest.mark.parametrize("x", [0.3, 0.6, 0.9])
def test_twenty_points_a_cycle_read_the_closed_form(x):
    q, d = _cycle(x, 20)
    # from +Q* down and back: anticlockwise in (delta, Q), the integral of Q d delta is the area
    assert loop_energy(q, d, 0, len(q) - 1) == pytest.approx(_closed_form(x), rel=2e-3)


def test_trapezoids_would_cut_the_branches():
    # what the rule replaces: trapezoids over the same 20 points read the loop about 1.6 % low
    q, d = _cycle(0.6, 20)
    trapezoids = float(np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(d)))
    assert trapezoids < 0.99 * _closed_form(0.6)


def test_a_branch_without_a_turn_is_the_integral_of_a_linear_path():
    # Q linear in delta along one branch: the integral is exact (the trapezoid's value)
    d = np.linspace(0.0, 2.0, 9)
    q = 3.0 * d + 1.0
    assert loop_energy(q, d, 0, 8) == pytest.approx(1.5 * 4.0 + 2.0, rel=1e-12)
