"""Bounded (trimmed) 2D curves, the edges of a :class:`geometry.profile.Profile` (their
conventions: :mod:`geometry.bounded_curve`).

This module gathers them: the interface (``geometry.bounded_curve``), segments
(``geometry.segments``), circular and elliptic arcs (``geometry.arcs``), B-spline pieces
(``geometry.bspline_arc``), the edge dicts (``geometry.edge_dicts``) and the shared numerics
(``geometry._curve_numerics``).
"""

from __future__ import annotations

from ._base import MAX_COORDINATE  # noqa: F401  (was importable from here)
from .arcs import Arc, EllipticArc
from .bounded_curve import BoundedCurve, BoundedProjection
from .bspline_arc import BSplineArc
from .edge_dicts import bounded_curve_from_dict
from .segments import Segment

__all__ = [
    "BoundedProjection",
    "BoundedCurve",
    "Segment",
    "Arc",
    "EllipticArc",
    "BSplineArc",
    "bounded_curve_from_dict",
]
