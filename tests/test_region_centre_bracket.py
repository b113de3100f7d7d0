"""The 2D region's centre moved to its pressure's centroid: plain fixed-point moves while the
centroid's offset keeps its sign, false position once two centres bracket the fixed point. Checked
on closed-form centroid maps: a smooth contraction (followed exactly), an over-steep map whose
plain moves diverge in a growing two-cycle, and a step (the centroid jumps as points change zone,
which swung a pin in a bore's region between two centres for the whole step)."""

import types

import pytest

from ibfem.solver.contact.band import BandContact


def _settle(centroid, c0: float, tol: float, most: int = 60) -> tuple[float, int, list]:
    """Moves of a centre from c0 under ``centroid(c)`` as the contact makes them: (centre, moves,
    centres visited); the loop stops where a centroid lies within tol or the bracket settles."""
    contact = types.SimpleNamespace(centre=c0, centre_tries=[])
    visited = [c0]
    for k in range(most):
        target = centroid(contact.centre)
        if abs(target - contact.centre) <= tol:
            return contact.centre, k, visited
        contact.centre, settled = BandContact._next_centre(contact, target, tol)
        visited.append(contact.centre)
        if settled:
            return contact.centre, k + 1, visited
    raise AssertionError(f"not settled in {most} moves: {visited[-6:]}")


def test_a_contraction_is_followed_move_by_move():
    centre, moves, visited = _settle(lambda c: 0.5 * c + 1.0, 0.0, 1e-9)
    assert centre == pytest.approx(2.0, abs=2e-9)
    assert visited[:4] == [0.0, 1.0, 1.5, 1.75]  # each move to the centroid, as before the bracket


def test_an_over_steep_map_is_solved_once_bracketed():
    # plain moves: 0 -> 2 -> -1 -> 3.5 ... (the two-cycle grows); the fixed point is 0.8
    centre, moves, _ = _settle(lambda c: 2.0 - 1.5 * c, 0.0, 1e-9)
    assert centre == pytest.approx(0.8, abs=1e-9) and moves <= 3


def test_a_jumping_centroid_settles_at_the_jump():
    # plain moves swing 0 <-> 1 for ever; the bracket closes on the jump at 0.5
    tol = 1e-4
    centre, moves, _ = _settle(lambda c: 1.0 if c < 0.5 else 0.0, 0.0, tol)
    assert abs(centre - 0.5) <= tol and moves <= 40
