"""OpenCascade surfaces -> ``geometry`` surface dicts, exactly.

=====================  =====================  =================================================
OpenCascade            Part type label        geometry primitive
=====================  =====================  =================================================
Plane                  PLANE                  ``plane`` (origin, normal = the frame's Z)
CylindricalSurface     CYLINDER               ``cylinder``
ConicalSurface         CONE                   ``cone`` (a negative semi-angle: axis reversed)
SphericalSurface       SPHERE                 ``sphere``
ToroidalSurface        TORUS                  ``torus``
BSplineSurface         BSURFACE               ``bspline_surface`` (periodic: clamped equivalent)
BezierSurface          BSURFACE               ``bspline_surface`` (one span)
SurfaceOfExtrusion     SWEEP                  ``sweep`` of the basis curve (line, circle,
                                              ellipse, B-spline)
SurfaceOfRevolution    SPUN                   ``bspline_surface``: OpenCascade's exact rational
                                              conversion (``GeomConvert``)
OffsetSurface          OFFSET                 none: tessellation-only, reported
other                  OTHER                  none: tessellation-only, reported
=====================  =====================  =================================================

The normal of each primitive is its own; whether the solid's outward normal
is that one or its opposite is decided by the part builder (``orientation``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .curves import curve_dict, xyz

__all__ = ["surface_dict", "bspline_surface_dict", "covering", "covering_sweep", "SURFACE_KINDS"]

SURFACE_KINDS = {"GeomAbs_Plane": "PLANE", "GeomAbs_Cylinder": "CYLINDER", "GeomAbs_Cone": "CONE",
                 "GeomAbs_Sphere": "SPHERE", "GeomAbs_Torus": "TORUS", "GeomAbs_BSplineSurface": "BSURFACE",
                 "GeomAbs_BezierSurface": "BSURFACE", "GeomAbs_SurfaceOfExtrusion": "SWEEP",
                 "GeomAbs_SurfaceOfRevolution": "SPUN", "GeomAbs_OffsetSurface": "OFFSET",
                 "GeomAbs_OtherSurface": "OTHER"}


def _knots(surface, u: bool) -> list[float]:
    n = surface.NbUKnots() if u else surface.NbVKnots()
    knot = surface.UKnot if u else surface.VKnot
    mult = surface.UMultiplicity if u else surface.VMultiplicity
    out: list[float] = []
    for i in range(1, n + 1):
        out += [knot(i)] * mult(i)
    return out


def bspline_surface_dict(surface) -> dict[str, Any]:
    """A Geom_BSplineSurface (a copy is changed) as a ``bspline_surface`` dict."""

    s = surface.Copy()  # OCP returns the derived type
    if s.IsUPeriodic():
        s.SetUNotPeriodic()
    if s.IsVPeriodic():
        s.SetVNotPeriodic()
    nu, nv = s.NbUPoles(), s.NbVPoles()
    d: dict[str, Any] = {
        "type": "bspline_surface", "degree_u": int(s.UDegree()), "degree_v": int(s.VDegree()),
        "knots_u": _knots(s, True), "knots_v": _knots(s, False),
        "control_points": [[xyz(s.Pole(i, j)) for j in range(1, nv + 1)] for i in range(1, nu + 1)],
    }
    if s.IsURational() or s.IsVRational():
        d["weights"] = [[s.Weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)]
    return d


def _bezier_surface_dict(surface) -> dict[str, Any]:
    from OCP.GeomConvert import GeomConvert

    return bspline_surface_dict(GeomConvert.SurfaceToBSplineSurface_s(surface))


def _cone(g) -> dict[str, Any]:
    axis, angle = xyz(g.Axis().Direction()), g.SemiAngle()
    if angle < 0:  # radius shrinks along +Z: the same cone about -Z
        axis, angle = [-c for c in axis], -angle
    return {"type": "cone", "origin": xyz(g.Location()), "axis": axis, "radius": g.RefRadius(),
            "half_angle": angle}


def surface_dict(adaptor, v_range: tuple[float, float] | None = None) -> tuple[dict | None, str, str | None]:
    """(geometry dict or None, type label, note or None) of a GeomAdaptor_Surface of the face's
    located surface; ``v_range``: the face's range of the second parameter (it bounds a surface of
    revolution whose profile curve is unbounded, a line)."""
    name = adaptor.GetType().name
    kind = SURFACE_KINDS.get(name, "OTHER")
    if kind == "PLANE":
        g = adaptor.Plane()
        return {"type": "plane", "origin": xyz(g.Location()), "normal": xyz(g.Axis().Direction())}, kind, None
    if kind == "CYLINDER":
        g = adaptor.Cylinder()
        return {"type": "cylinder", "origin": xyz(g.Location()), "axis": xyz(g.Axis().Direction()),
                "radius": g.Radius()}, kind, None
    if kind == "CONE":
        return _cone(adaptor.Cone()), kind, None
    if kind == "SPHERE":
        g = adaptor.Sphere()
        return {"type": "sphere", "origin": xyz(g.Location()), "radius": g.Radius()}, kind, None
    if kind == "TORUS":
        g = adaptor.Torus()
        return {"type": "torus", "origin": xyz(g.Location()), "axis": xyz(g.Axis().Direction()),
                "major_radius": g.MajorRadius(), "minor_radius": g.MinorRadius()}, kind, None
    if name == "GeomAbs_BSplineSurface":
        return bspline_surface_dict(adaptor.BSpline()), kind, None
    if name == "GeomAbs_BezierSurface":
        return _bezier_surface_dict(adaptor.Bezier()), kind, "Bezier surface as a one-span B-spline"
    if kind == "SWEEP":
        profile, pkind = curve_dict(adaptor.BasisCurve())
        if profile is None:
            return None, kind, f"extrusion of a {pkind} curve: no geometry primitive"
        return {"type": "sweep", "profile": profile, "direction": xyz(adaptor.Direction())}, kind, None
    if kind == "SPUN":
        return _revolution(adaptor, v_range)
    if kind == "OFFSET":
        return None, kind, f"offset surface (distance {adaptor.OffsetValue():g} m): no geometry primitive"
    return None, kind, None


def _revolution(adaptor, v_range: tuple[float, float] | None = None) -> tuple[dict | None, str, str | None]:
    """The surface of revolution as its exact rational B-spline; a profile without bounds (a
    line) is first cut to the face's ``v_range`` widened by a quarter of its length each side."""
    from OCP.GeomConvert import GeomConvert

    surface, note = adaptor.Surface(), "surface of revolution as its exact rational B-spline"
    if v_range is not None and not all(np.isfinite(_v_bounds(adaptor))):
        from OCP.Geom import Geom_RectangularTrimmedSurface

        v0, v1 = v_range
        margin = 0.25 * max(v1 - v0, 1e-12 * max(abs(v0), abs(v1), 1.0))
        surface = Geom_RectangularTrimmedSurface(surface, v0 - margin, v1 + margin, False)
        note += " (its unbounded profile cut to the face)"
    try:
        bs = GeomConvert.SurfaceToBSplineSurface_s(surface)
    except Exception as exc:  # OpenCascade raises Standard_Failure subclasses
        return None, "SPUN", f"surface of revolution not convertible to a B-spline: {exc}"
    return bspline_surface_dict(bs), "SPUN", note


def _v_bounds(adaptor) -> tuple[float, float]:
    v0, v1 = adaptor.FirstVParameter(), adaptor.LastVParameter()
    return (v0 if abs(v0) < 1e100 else -np.inf), (v1 if abs(v1) < 1e100 else np.inf)


def covering_sweep(d: dict[str, Any], u: np.ndarray) -> tuple[dict[str, Any], str | None]:
    """The ``sweep`` dict ``d`` with its B-spline profile extended (exactly, as in :func:`covering`)
    so that its domain covers the face's curve parameters ``u``."""
    from ibfem.geometry.bspline_extend import extend_clamped

    profile = d["profile"]
    if profile.get("type") != "bspline_curve" or profile.get("periodic"):
        return d, None
    knots, degree = profile["knots"], int(profile["degree"])
    a, b = float(knots[degree]), float(knots[len(knots) - degree - 1])
    lo, hi, margin = float(np.min(u)), float(np.max(u)), 1e-3 * (b - a)
    need = (lo - margin if lo < a - 1e-12 * (b - a) else a, hi + margin if hi > b + 1e-12 * (b - a) else b)
    if need == (a, b):
        return d, None
    P = np.asarray(profile["control_points"], float)
    w = np.asarray(profile["weights"], float) if profile.get("weights") is not None else None
    H = P if w is None else np.column_stack([P * w[:, None], w])
    try:
        t, H = extend_clamped(knots, degree, H, *need)
    except ValueError as exc:
        return d, f"the face runs beyond its profile curve's parameter domain and the curve cannot be extended: {exc}"
    out = dict(profile, knots=t.tolist())
    if w is None:
        out["control_points"] = H.tolist()
    elif not H[:, -1].min() > 0:
        return d, "the face runs beyond its profile curve's domain; extending it makes a weight non-positive"
    else:
        out.update(control_points=(H[:, :-1] / H[:, -1:]).tolist(), weights=H[:, -1].tolist())
    return dict(d, profile=out), (f"profile curve extended beyond its parameter domain to cover the face: "
                                  f"[{a:.6g}, {b:.6g}] -> [{need[0]:.6g}, {need[1]:.6g}]")


def covering(d: dict[str, Any], geom, uv: list[tuple[float, float]]) -> tuple[dict[str, Any], str | None]:
    """The ``bspline_surface`` dict ``d`` of the OpenCascade surface ``geom``, extended (exactly:
    the end spans carried on, :mod:`geometry.bspline_extend`) so that its domain covers the
    parameters ``uv`` of the face (its trimming curves' box and its mesh nodes) with a margin of
    1e-3 of the domain's width. Periodic directions are not extended. Returns (dict, note)."""
    from ibfem.geometry.bspline_extend import extend_surface_dict

    uv = np.asarray(uv, float).reshape(-1, 2)
    periodic = (geom.IsUPeriodic(), geom.IsVPeriodic())
    ranges, grown = [], []
    for axis, (knots, degree) in enumerate(((d["knots_u"], d["degree_u"]), (d["knots_v"], d["degree_v"]))):
        a, b = float(knots[degree]), float(knots[len(knots) - degree - 1])
        lo, hi = float(uv[:, axis].min()), float(uv[:, axis].max())
        margin = 1e-3 * (b - a)
        need_lo = lo - margin if lo < a - 1e-12 * (b - a) and not periodic[axis] else a
        need_hi = hi + margin if hi > b + 1e-12 * (b - a) and not periodic[axis] else b
        ranges.append((need_lo, need_hi))
        if need_lo < a or need_hi > b:
            grown.append(f"{'uv'[axis]} [{a:.6g}, {b:.6g}] -> [{need_lo:.6g}, {need_hi:.6g}]")
    if not grown:
        return d, None
    try:
        out = extend_surface_dict(d, *ranges)
    except ValueError as exc:
        return d, f"the face is trimmed beyond the surface's parameter domain and the surface cannot be extended: {exc}"
    if "weights" in out and not np.min(out["weights"]) > 0:
        return d, "the face is trimmed beyond the surface's parameter domain; extending it makes a weight non-positive"
    return out, "surface extended beyond its parameter domain to cover the trimmed face: " + ", ".join(grown)
