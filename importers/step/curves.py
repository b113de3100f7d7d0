"""OpenCascade curves (of edges, and the profiles of extrusion surfaces) -> ``geometry`` curve
dicts, exactly: lines, circles, ellipses, B-splines (NURBS with weights;
Bezier curves as single-span B-splines). Periodic B-splines are written as their clamped,
non-periodic equivalent (same curve, OpenCascade's ``SetNotPeriodic``); an edge that uses part
of a B-spline gets the B-spline cut to its range (``Segment``, exact), so every B-spline edge
runs from its start point to its end point.

Hyperbolas, parabolas, offset and other curves have no ``geometry`` primitive: their edges are
kept with their polyline only and reported.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["xyz", "curve_dict", "bspline_curve_dict", "edge_curve", "edge_polyline", "CURVE_KINDS"]

#: OpenCascade curve type (GeomAbs_CurveType name) -> the Part's curve type label (Onshape's words)
CURVE_KINDS = {"GeomAbs_Line": "LINE", "GeomAbs_Circle": "CIRCLE", "GeomAbs_Ellipse": "ELLIPSE",
               "GeomAbs_BSplineCurve": "BCURVE", "GeomAbs_BezierCurve": "BCURVE",
               "GeomAbs_Hyperbola": "HYPERBOLA", "GeomAbs_Parabola": "PARABOLA",
               "GeomAbs_OffsetCurve": "OFFSET", "GeomAbs_OtherCurve": "OTHER"}


def xyz(p) -> list[float]:
    """[x, y, z] of a gp_Pnt / gp_Dir / gp_Vec."""
    return [p.X(), p.Y(), p.Z()]


def _expanded_knots(curve) -> list[float]:
    """The flat knot vector (each knot repeated by its multiplicity)."""
    out: list[float] = []
    for i in range(1, curve.NbKnots() + 1):
        out += [curve.Knot(i)] * curve.Multiplicity(i)
    return out


def bspline_curve_dict(curve, first: float | None = None, last: float | None = None) -> dict[str, Any]:
    """A Geom_BSplineCurve (a copy is changed, never the argument) as a ``bspline_curve``
    dict; cut to [first, last] when that lies inside its domain."""

    c = curve.Copy()  # OCP returns the derived type
    if c.IsPeriodic():
        c.SetNotPeriodic()
    if first is not None and last is not None:
        lo, hi = c.FirstParameter(), c.LastParameter()
        span = hi - lo
        if (first > lo + 1e-12 * span or last < hi - 1e-12 * span) and last > first:
            c.Segment(max(first, lo), min(last, hi))
    d: dict[str, Any] = {"type": "bspline_curve", "degree": int(c.Degree()), "knots": _expanded_knots(c),
                         "control_points": [xyz(c.Pole(i)) for i in range(1, c.NbPoles() + 1)]}
    if c.IsRational():
        d["weights"] = [c.Weight(i) for i in range(1, c.NbPoles() + 1)]
    return d


def _bezier_dict(curve) -> dict[str, Any]:
    n = curve.NbPoles()
    k = n - 1
    d: dict[str, Any] = {"type": "bspline_curve", "degree": k, "knots": [0.0] * (k + 1) + [1.0] * (k + 1),
                         "control_points": [xyz(curve.Pole(i)) for i in range(1, n + 1)]}
    if curve.IsRational():
        d["weights"] = [curve.Weight(i) for i in range(1, n + 1)]
    return d


def curve_dict(adaptor, first: float | None = None, last: float | None = None) -> tuple[dict | None, str]:
    """(geometry dict or None, type label) of an Adaptor3d_Curve (BRepAdaptor_Curve of an
    edge, with its location applied, or the basis curve of an extrusion)."""
    name = adaptor.GetType().name
    kind = CURVE_KINDS.get(name, "OTHER")
    if kind == "LINE":
        g = adaptor.Line()
        return {"type": "line", "origin": xyz(g.Location()), "direction": xyz(g.Direction())}, kind
    if kind == "CIRCLE":
        g = adaptor.Circle()
        return {"type": "circle", "origin": xyz(g.Location()), "normal": xyz(g.Axis().Direction()),
                "radius": g.Radius()}, kind
    if kind == "ELLIPSE":
        g = adaptor.Ellipse()
        return {"type": "ellipse", "origin": xyz(g.Location()), "normal": xyz(g.Axis().Direction()),
                "major_axis": xyz(g.XAxis().Direction()), "major_radius": g.MajorRadius(),
                "minor_radius": g.MinorRadius()}, kind
    if name == "GeomAbs_BSplineCurve":
        return bspline_curve_dict(adaptor.BSpline(), first, last), kind
    if name == "GeomAbs_BezierCurve":
        return _bezier_dict(adaptor.Bezier()), kind
    return None, kind


def edge_curve(edge) -> dict[str, Any]:
    """The exact curve of an edge: {"dict", "kind", "start", "end", "length", "adaptor"};
    "dict" is None for curve types geometry has no primitive of (and degenerated edges)."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GCPnts import GCPnts_AbscissaPoint

    if BRep_Tool.Degenerated_s(edge):
        from OCP.TopExp import TopExp

        p = np.asarray(xyz(BRep_Tool.Pnt_s(TopExp.FirstVertex_s(edge))))
        return {"dict": None, "kind": "DEGENERATE", "start": p, "end": p, "length": 0.0, "adaptor": None}
    adaptor = BRepAdaptor_Curve(edge)
    first, last = adaptor.FirstParameter(), adaptor.LastParameter()
    d, kind = curve_dict(adaptor, first, last)
    return {"dict": d, "kind": kind, "start": np.asarray(xyz(adaptor.Value(first))),
            "end": np.asarray(xyz(adaptor.Value(last))), "length": float(GCPnts_AbscissaPoint.Length_s(adaptor)),
            "adaptor": adaptor}


def edge_polyline(adaptor, deflection: float, start: np.ndarray) -> np.ndarray:
    """Points (m, 3) along the edge's curve within ``deflection`` (m) of it, from its start."""
    if adaptor is None:
        return start.reshape(1, 3)
    from OCP.GCPnts import GCPnts_QuasiUniformDeflection

    sampler = GCPnts_QuasiUniformDeflection(adaptor, deflection)
    if not sampler.IsDone() or sampler.NbPoints() < 2:
        t = np.linspace(adaptor.FirstParameter(), adaptor.LastParameter(), 33)
        return np.array([xyz(adaptor.Value(float(s))) for s in t])
    return np.array([xyz(sampler.Value(i)) for i in range(1, sampler.NbPoints() + 1)])
