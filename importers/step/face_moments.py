"""A meshed face's moments (``geometry.solids.domain_moments``) from OpenCascade's exact surface
over the face's (u, v) domain: the mesher's triangles in (u, v) plus the strips between their
boundary chords and the edges' curves on the surface (each boundary chord is a piece of an
edge's polygon on the triangulation, whose nodes carry the edge's parameters).

Evaluated point by point with the face's located surface (``BRepAdaptor_Surface``: S, S_u,
S_v) and the edges' curves on it (``BRepAdaptor_Curve2d``, the curve of a seam edge that goes
with its orientation in the face).
"""

from __future__ import annotations

import numpy as np

from ibfem.geometry.solids.domain_moments import (FaceMoments, boundary_edges, chain_side, domain_rule,
                                                  face_moments, gap_rule, strip_parameters, strip_rule)

__all__ = ["meshed_face_moments"]

#: a chord's trimming curve is taken as straight (no strip) within this fraction of the chord
STRAIGHT = 1e-12


def _frame(g):
    """Origin, X, Y, Z of an elementary surface's position (gp_Ax3, possibly left-handed)."""
    ax = g.Position()
    return tuple(np.array(v.Coord()) for v in (ax.Location(), ax.XDirection(), ax.YDirection(), ax.Direction()))


def _around(o, x, y, z, radius, height, u, d_radius=None, d_height=None):
    """S, S_u, S_v of O + radius(.) (cos u X + sin u Y) + height(.) Z (a surface of revolution about
    Z), ``radius``, ``height`` and their v-derivatives given per point."""
    c, s = np.cos(u)[:, None], np.sin(u)[:, None]
    ring, ring_u = c * x + s * y, -s * x + c * y
    point = o + radius[:, None] * ring + height[:, None] * z
    return point, radius[:, None] * ring_u, d_radius[:, None] * ring + d_height[:, None] * z


def _closed_form(surface):
    """S, S_u, S_v of OpenCascade's elementary surfaces (their parametrisations, ElSLib), vectorised;
    None for other surfaces."""
    from OCP.GeomAbs import GeomAbs_SurfaceType as T

    kind = surface.GetType()
    if kind == T.GeomAbs_Plane:
        o, x, y, _ = _frame(surface.Plane())
        return lambda uv: (o + uv[:, :1] * x + uv[:, 1:] * y, np.broadcast_to(x, (len(uv), 3)),
                           np.broadcast_to(y, (len(uv), 3)))
    if kind == T.GeomAbs_Cylinder:
        g = surface.Cylinder()
        r = g.Radius()
        return lambda uv: _around(*_frame(g), np.full(len(uv), r), uv[:, 1], uv[:, 0], np.zeros(len(uv)),
                                  np.ones(len(uv)))
    if kind == T.GeomAbs_Cone:
        g = surface.Cone()
        r, sa, ca = g.RefRadius(), np.sin(g.SemiAngle()), np.cos(g.SemiAngle())
        return lambda uv: _around(*_frame(g), r + uv[:, 1] * sa, uv[:, 1] * ca, uv[:, 0], np.full(len(uv), sa),
                                  np.full(len(uv), ca))
    if kind == T.GeomAbs_Sphere:
        g = surface.Sphere()
        r = g.Radius()
        return lambda uv: _around(*_frame(g), r * np.cos(uv[:, 1]), r * np.sin(uv[:, 1]), uv[:, 0],
                                  -r * np.sin(uv[:, 1]), r * np.cos(uv[:, 1]))
    if kind == T.GeomAbs_Torus:
        g = surface.Torus()
        big, r = g.MajorRadius(), g.MinorRadius()
        return lambda uv: _around(*_frame(g), big + r * np.cos(uv[:, 1]), r * np.sin(uv[:, 1]), uv[:, 0],
                                  -r * np.sin(uv[:, 1]), r * np.cos(uv[:, 1]))
    return None


def _pointwise(surface):
    """S, S_u, S_v by OpenCascade's evaluation, point by point."""
    from OCP.gp import gp_Pnt, gp_Vec

    p, du, dv = gp_Pnt(), gp_Vec(), gp_Vec()

    def evaluate(uv: np.ndarray):
        out = np.empty((len(uv), 9))
        for k, (u, v) in enumerate(uv.tolist()):
            surface.D1(u, v, p, du, dv)
            out[k] = (*p.Coord(), *du.Coord(), *dv.Coord())
        return out[:, 0:3], out[:, 3:6], out[:, 6:9]

    return evaluate


def _bspline_form(surface):
    """S, S_u, S_v of a B-spline surface, vectorised inside its knots (the same poles, weights and
    knots), point by point beyond them (OpenCascade continues a periodic surface periodically);
    None for other surfaces."""
    from OCP.GeomAbs import GeomAbs_SurfaceType as T

    from ibfem.geometry import primitive_from_dict

    from .surfaces import bspline_surface_dict

    if surface.GetType() != T.GeomAbs_BSplineSurface:
        return None
    try:
        spline = primitive_from_dict(bspline_surface_dict(surface.BSpline()))
    except ValueError:  # a B-spline the geometry primitive refuses: evaluated point by point
        return None
    (ua, ub), (va, vb) = spline.domain
    pointwise = _pointwise(surface)

    def evaluate(uv):
        inside = (uv[:, 0] >= ua) & (uv[:, 0] <= ub) & (uv[:, 1] >= va) & (uv[:, 1] <= vb)
        d = spline.derivatives(uv[inside], order=1)
        out = [np.empty((len(uv), 3)) for _ in range(3)]
        for o, part in zip(out, (d[(0, 0)], d[(1, 0)], d[(0, 1)])):
            o[inside] = part
        if not inside.all():
            for o, part in zip(out, pointwise(uv[~inside])):
                o[~inside] = part
        return tuple(out)

    return evaluate


def _evaluator(surface):
    """uv (n, 2) -> S, S_u, S_v (n, 3) each of a face's located surface (``BRepAdaptor_Surface``):
    closed forms for the elementary surfaces, vectorised B-splines, OpenCascade's D1 point by point
    for the others."""
    return _closed_form(surface) or _bspline_form(surface) or _pointwise(surface)


def _cuts(surface, uv: np.ndarray) -> tuple[list[float], list[float]]:
    """The values of u and of v inside the triangulation's range where the surface is less than
    twice continuously differentiable (a B-spline's multiple knots)."""
    from OCP.collections import Array1_double
    from OCP.GeomAbs import GeomAbs_Shape

    out = []
    for axis, count, values in ((0, surface.NbUIntervals, surface.UIntervals),
                                (1, surface.NbVIntervals, surface.VIntervals)):
        n = count(GeomAbs_Shape.GeomAbs_C2)
        bounds = Array1_double(1, n + 1)
        values(bounds, GeomAbs_Shape.GeomAbs_C2)
        lo, hi = uv[:, axis].min(), uv[:, axis].max()
        out.append([t for t in (bounds.Value(i) for i in range(2, n + 1)) if lo < t < hi])
    return out[0], out[1]


def _edge_chords(face):
    """Per edge of the face (explored in the face's FORWARD orientation, where the domain lies to
    the left of each edge's curve on the surface taken in the edge's orientation): (nodes,
    parameters, side, curve on the surface) of its polygon on the face's triangulation."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve2d
    from OCP.TopAbs import TopAbs_Orientation, TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    loc = TopLoc_Location()
    tri = BRep_Tool.Triangulation_s(face, loc)
    forward = TopoDS.Face(face.Oriented(TopAbs_Orientation.TopAbs_FORWARD))
    explorer = TopExp_Explorer(forward, TopAbs_ShapeEnum.TopAbs_EDGE)
    while explorer.More():
        edge = TopoDS.Edge(explorer.Current())
        explorer.Next()
        poly = BRep_Tool.PolygonOnTriangulation_s(edge, tri, loc)
        if poly is None or not poly.HasParameters() or poly.NbNodes() < 2:
            continue
        nodes = np.array([poly.Node(i) - 1 for i in range(1, poly.NbNodes() + 1)])
        params = np.array([poly.Parameter(i) for i in range(1, poly.NbNodes() + 1)])
        side = 1 if edge.Orientation() == TopAbs_Orientation.TopAbs_FORWARD else -1
        yield nodes, params, side, BRepAdaptor_Curve2d(edge, forward)


def _form(curve) -> tuple[int, np.ndarray]:
    """A curve on the surface (``BRepAdaptor_Curve2d``) as (kind, coefficients): 0, (o, d) for a
    line o + t d; 1, (o, x, y, r) for a circle o + r (cos t x + sin t y); 2, () for another curve."""
    from OCP.GeomAbs import GeomAbs_CurveType as T

    kind = curve.GetType()
    if kind == T.GeomAbs_Line:
        line = curve.Line()
        return 0, np.array([*line.Location().Coord(), *line.Direction().Coord(), 0.0, 0.0, 0.0])
    if kind == T.GeomAbs_Circle:
        circle = curve.Circle()
        ax = circle.Position()
        return 1, np.array([*ax.Location().Coord(), *ax.XDirection().Coord(), *ax.YDirection().Coord(),
                            circle.Radius()])
    return 2, np.zeros(7)


def _curve_values(kind: np.ndarray, coef: np.ndarray, t: np.ndarray, others) -> np.ndarray:
    """(m, S, 4): C(t) and dC/dt at the parameters t (m, S) of m chords, each on a curve of
    :func:`_form`'s ``kind`` (m,) and ``coef`` (m, 7): lines and circles in closed form, the other
    curves (``others``: [(chord indices, curve)]) by OpenCascade's evaluation point by point."""
    from OCP.gp import gp_Pnt2d, gp_Vec2d

    out = np.empty(t.shape + (4,))
    line, circle = kind == 0, kind == 1
    o, d = coef[line, None, 0:2], coef[line, None, 2:4]
    out[line, :, :2], out[line, :, 2:] = o + t[line, :, None] * d, d
    c = coef[circle, None]
    cos, sin = c[..., 6:7] * np.cos(t[circle])[..., None], c[..., 6:7] * np.sin(t[circle])[..., None]
    out[circle, :, :2] = c[..., 0:2] + cos * c[..., 2:4] + sin * c[..., 4:6]
    out[circle, :, 2:] = -sin * c[..., 2:4] + cos * c[..., 4:6]
    p, dp = gp_Pnt2d(), gp_Vec2d()
    for rows, curve in others:
        for k in rows:
            for q, tq in enumerate(t[k].tolist()):
                curve.D1(tq, p, dp)
                out[k, q] = (p.X(), p.Y(), dp.X(), dp.Y())
    return out


def _boundary_rule(face, uv: np.ndarray, triangles: np.ndarray):
    """Points and weights of the strips along the trimming curves and of the gaps between their
    polygon and the triangulation's boundary."""
    s = strip_parameters()
    boundary = boundary_edges(uv, triangles)
    rows, others, count = [], [], 0
    for nodes, params, side, curve in _edge_chords(face):
        side = chain_side(boundary, nodes, side)  # the triangles' side where they border the chain
        kind, coef = _form(curve)
        m = len(nodes) - 1
        rows.append((nodes[:-1], nodes[1:], params[:-1], params[1:], np.full(m, side), np.full(m, kind),
                     np.tile(coef, (m, 1))))
        if kind == 2:
            others.append((range(count, count + m), curve))
        count += m
    if not rows:
        return [(np.zeros((0, 2)), np.zeros(0))]
    i, j, t0, t1, side, kind, coef = (np.concatenate(v) for v in zip(*rows))
    gaps = gap_rule(uv, triangles, np.where((side > 0)[:, None], np.stack([i, j], 1), np.stack([j, i], 1)), boundary)
    a, b = uv[i], uv[j]
    length = np.linalg.norm(b - a, axis=1)
    values = _curve_values(kind, coef, t0[:, None] + s[None] * (t1 - t0)[:, None], others)
    line = a[:, None] + s[None, :, None] * (b - a)[:, None]
    off = np.linalg.norm(values[..., :2] - line, axis=2).max(axis=1)
    # a straight curve needs no strip; one farther from its chord than the chord is long is on
    # another period of the surface's parameters than the nodes: none either
    bent = (off > STRAIGHT * length) & (off < length) & (t1 != t0)
    if not bent.any():
        return [gaps]
    return [gaps, strip_rule(a[bent], b[bent], side[bent].astype(float), values[bent, :, :2], values[bent, :, 2:],
                             (t1 - t0)[bent])]


def meshed_face_moments(face, uv: np.ndarray, triangles: np.ndarray) -> FaceMoments:
    """The moments of a face just meshed by OpenCascade (its triangulation still on it), for the
    surface's own normal; ``uv`` (n, 2) and ``triangles`` (m, 3, 0-based) are that triangulation."""
    uv = np.asarray(uv, float)
    triangles = np.asarray(triangles, np.int64)
    from OCP.BRepAdaptor import BRepAdaptor_Surface

    surface = BRepAdaptor_Surface(face, False)
    rules = [domain_rule(uv, triangles, _cuts(surface, uv))] + _boundary_rule(face, uv, triangles)
    points, weights = (np.concatenate(v) for v in zip(*rules))
    return face_moments(points, weights, _evaluator(surface))
