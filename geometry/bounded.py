"""Bounded (trimmed) 2D curves: the edges of a :class:`geometry.profile.Profile`.

Every curve is an immutable, oriented piece of curve in the plane with a native parameter
``t`` that increases along the curve from ``t_start`` to ``t_end``:

- :class:`Segment`: ``t`` is the arc length, ``t`` in [0, length];
- :class:`Arc` and :class:`EllipticArc`: ``t`` is the angle swept from the start point,
  ``t`` in [0, |end_angle - start_angle|] (so a clockwise arc still has increasing ``t``);
- :class:`BSplineArc`: ``t`` is the spline parameter on [knots[p], knots[-p-1]].

The normal is the tangent turned by -90 degrees (the right-hand side): the outward normal
when the curve belongs to a counter-clockwise outer loop.

Projection is onto the *trimmed* curve, end points included. ``distances`` in the returned
:class:`BoundedProjection` are signed Euclidean distances ``sign((p - c) . n) * |p - c|``;
they equal ``(p - c) . n`` wherever the closest point ``c`` is interior to the curve.

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
