"""Junctions of a 2D profile's loops: where one edge ends and the next begins, the turn of the
tangent there (from the exact edges; positive to the left, where the material lies: a convex
corner) and the two edges. Shared by the contact point's resolution (a point at a corner of body
1 moves into its flatter edge) and the contact curve's chain (a body's contact region ends at its
corners)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["CORNER_ANGLE", "Junction", "nearest_junction", "tangent_turn", "unit_tangent"]

#: a junction whose tangents turn by more than this angle (rad) is a corner: a contact region
#: of the body ends there (G1 junctions of CAD edges agree to round-off; a chamfer or a
#: punch's edge turns by tenths of a radian or more)
CORNER_ANGLE = 1e-2


def tangent_turn(a_end: np.ndarray, b_start: np.ndarray) -> float:
    """Signed angle (rad) from unit tangent ``a_end`` to unit tangent ``b_start``, positive to the left."""
    cross = a_end[0] * b_start[1] - a_end[1] * b_start[0]
    return float(np.arctan2(cross, a_end @ b_start))


def unit_tangent(curve: Any, t: float) -> np.ndarray:
    """The unit tangent (2,) of ``curve`` at its parameter ``t``."""
    d = np.asarray(curve.derivative(np.array([float(t)])), dtype=float).reshape(2)
    return d / np.linalg.norm(d)


@dataclass(frozen=True)
class Junction:
    """The end of edge ``before`` and the start of edge ``after`` (loop order, the material on
    the left), at ``point``, ``distance`` from the query point; ``turn`` the tangent's turn there
    and ``tangents`` the two unit tangents (of ``before`` at its end, of ``after`` at its start)."""

    point: np.ndarray
    distance: float
    turn: float
    before: Any
    after: Any
    tangents: tuple[np.ndarray, np.ndarray]


def nearest_junction(profile: Any, point: np.ndarray) -> Junction | None:
    """The junction of ``profile``'s loops nearest ``point`` (None for a profile without one)."""
    point = np.asarray(point, dtype=float).reshape(2)
    best = None
    for loop in profile.loops:
        for a, b in zip(loop, loop[1:] + loop[:1]):
            x = np.asarray(a.evaluate(np.array([float(a.t_end)])), dtype=float).reshape(2)
            d = float(np.hypot(*(x - point)))
            if best is None or d < best[0]:
                best = (d, x, a, b)
    if best is None:
        return None
    d, x, a, b = best
    ta, tb = unit_tangent(a, a.t_end), unit_tangent(b, b.t_start)
    return Junction(point=x, distance=d, turn=tangent_turn(ta, tb), before=a, after=b, tangents=(ta, tb))
