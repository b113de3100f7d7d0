"""The stick/slip boundary's root search of the 2D friction history
(HistoryBandContact._boundary_step) on edge coefficients given in closed form: it converges to the
root of a monotone beta from either side and into either stick side within the refinement's
budget, and, where beta falls over a stretch and has no root nearby, it keeps stepping one way
(the sign of beta) instead of jumping back and forth."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from ibfem.solver.contact.friction_history import BOUNDARY_TOLERANCE, MAX_REFINEMENTS, HistoryBandContact

H = 1.0  # finest cell


def _contact():
    return SimpleNamespace(h=H, edge_slope=0.0, slopes=[])


def _search(beta, b0: float, into_stick: float):
    """Positions tried by the refinement for beta(b) from b0 (at most MAX_REFINEMENTS tries)."""
    c, tries, b = _contact(), [], b0
    for _ in range(MAX_REFINEMENTS):
        tries.append((b, beta(b)))
        step = HistoryBandContact._boundary_step(c, tries, into_stick)
        b += step
        if abs(step) <= BOUNDARY_TOLERANCE * H:
            return b, len(tries)
    return b, len(tries)


@pytest.mark.parametrize("into_stick", [1.0, -1.0])
@pytest.mark.parametrize("b0", [-1.3, 0.2, 1.4])
def test_monotone_root(into_stick, b0):
    # beta grows with the move into the stick side; nonlinear (the edge fit is not linear in b)
    root = 0.37
    beta = lambda b: math.tanh(2.0 * into_stick * (b - root)) + 0.3 * (into_stick * (b - root)) ** 3  # noqa: E731
    b, n = _search(beta, b0, into_stick)
    assert n < MAX_REFINEMENTS
    assert b == pytest.approx(root, abs=2.0 * BOUNDARY_TOLERANCE * H)


def test_no_root_keeps_one_direction():
    # beta < 0 everywhere, least negative at b = 0 (a falling stretch beyond): the stick zone is too
    # large wherever the boundary is, so each step shrinks it (moves into the stick side, +b)
    beta = lambda b: -0.01 - 0.02 * b * b  # noqa: E731
    c, tries, b = _contact(), [], -0.5
    c.edge_slope = 0.05
    moves = []
    for _ in range(6):
        tries.append((b, beta(b)))
        step = HistoryBandContact._boundary_step(c, tries, 1.0)
        moves.append(step)
        b += step
    assert all(m > 0.0 for m in moves)
