"""Contact geometry of two bodies (thesis sections 5.1-5.2): the contact point and frame, the
chord-length matching of the two boundaries, Delta between matched points (eq. 5-2) and the
quadrature of body 1's contact curve split at both grids' cell lines.

Conventions (those of summary.json): ``normal`` is the outward unit normal of the SECOND body at the
contact point, ``tangent`` = (-n_y, n_x). A point of body 1's contact curve is labelled by its
signed chord s: |s| is the straight-line distance from body 1's contact point c1, the sign that
of the side along ``tangent``. Its matched point on body 2's curve has the same chord from c2
on the same side (cord-length matching of section 5.2); Delta = X1 - X2 (eq. 5-2), so contact
means u1 - u2 + Delta = 0 (eq. 5-3).

Everything works on any curve with ``evaluate``/``derivative``/``axis_crossings`` and
``t_start``/``t_end``: the exact ``geometry.bounded`` curves, or the ``Polyline`` of the
tessellated (``exact_geometry = false``) variant, whose facets then give the points, normals
and Delta (the thesis's non-projected results).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ibfem.geometry.chord_walk import first_crossing, walk_distances

from ..fem.integration import curve_gauss
from ..model.resolve import refined_maximum

__all__ = [
    "chord_table",
    "ContactGeometry",
    "ContactPoints",
    "closest_parameter",
    "parameter_at_chord",
    "contact_geometry",
    "touching_point",
    "match_points",
    "sample_points",
    "contact_quadrature",
]


def _unit_normal(curve, t: np.ndarray) -> np.ndarray:
    d = np.asarray(curve.derivative(np.asarray(t, dtype=float)), dtype=float).reshape(-1, 2)
    return np.stack([d[:, 1], -d[:, 0]], axis=1) / np.hypot(d[:, 0], d[:, 1])[:, None]


def closest_parameter(curve, point: np.ndarray, samples: int = 4097) -> float:
    """Parameter of the point of ``curve`` closest to ``point``: dense sampling, then golden
    section on the bracketing interval (works for exact curves and polylines alike; the exact
    curves' own projection is not available on polylines)."""
    lo, hi = float(curve.t_start), float(curve.t_end)
    t = np.linspace(lo, hi, samples)
    p = np.asarray(curve.evaluate(t), dtype=float).reshape(-1, 2)
    k = int(np.argmin(np.hypot(*(p - point).T)))
    a, b = t[max(k - 1, 0)], t[min(k + 1, samples - 1)]
    g = 0.5 * (np.sqrt(5.0) - 1.0)

    def dist(s):
        return float(np.hypot(*(np.asarray(curve.evaluate(np.array([s])), float).reshape(2) - point)))

    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = dist(c), dist(d)
    for _ in range(90):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = dist(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = dist(d)
    return 0.5 * (a + b)


def chord_table(curve, origin: np.ndarray, t_from: float, direction: int, samples: int = 2049,
                t_to: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Samples (t, chord) of the walk from ``t_from`` in ``direction`` (to the curve's end, or
    to ``t_to``): the bracketing table of :func:`parameter_at_chord`, computed once per side."""
    end = (float(curve.t_end) if direction > 0 else float(curve.t_start)) if t_to is None else float(t_to)
    t = np.linspace(float(t_from), end, samples)
    return t, walk_distances(curve, origin, t)


def parameter_at_chord(curve, origin: np.ndarray, chord: np.ndarray, t_from: float, direction: int,
                       samples: int = 2049, table: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Parameters t (m,) of the points whose straight-line distance from ``origin`` is ``chord``,
    walking from ``t_from`` in ``direction`` (+1 increasing t); the first crossing along the
    walk, NaN where the curve ends first (or beyond a given ``table``'s end): geometry's chord
    walk (:mod:`geometry.chord_walk`) on the sampled (or precomputed ``chord_table``) walk, one
    code path for exact curves and polylines."""
    chord = np.asarray(chord, dtype=float).ravel()
    t, d = table if table is not None else chord_table(curve, origin, t_from, direction, samples)
    out = first_crossing(curve, origin, chord, t, d)
    out[chord <= 0.0] = float(t_from)
    return out


@dataclass
class ContactGeometry:
    """One contact: frame, the two contact curves and where on them the contact point lies."""

    bodies: tuple[str, str]
    point: np.ndarray  # reported contact point: where the two curves are closest (the chords' origin)
    normal: np.ndarray  # outward normal of body 2 at the point
    tangent: np.ndarray  # (-n_y, n_x)
    edges: tuple[str, str]  # contact edge of each body
    curves: tuple  # the curves (exact or polyline) of those edges
    origins: tuple[np.ndarray, np.ndarray]  # c1, c2: the contact point on each curve
    t_origin: tuple[float, float]
    directions: tuple[int, int]  # parameter direction of +s (along tangent) on each curve
    s_limits: tuple[float, float]  # usable chord range on each side (candidate region), > 0
    tables: dict = field(default_factory=dict)  # (curve, side) -> chord_table over the candidate region
    # "frame": every pair is constrained along the contact frame's normal (the small-strain,
    # half-space assumption of Hertz theory: frictionless tractions have no component along
    # the tangent); "pair": along each matched pair's bisector normal (ContactPoints.normal)
    normal_mode: str = "frame"
    given_point: np.ndarray | None = None  # the scene's point, when the touching point lies off it

    def s_max(self) -> float:
        return min(self.s_limits)

    def table(self, which: int, sgn: int):
        """Chord table of curve ``which`` on side ``sgn`` covering the candidate region."""
        key = (which, sgn)
        if key not in self.tables:
            curve, c, t0 = self.curves[which], self.origins[which], self.t_origin[which]
            direction = sgn * self.directions[which]
            reach = 1.05 * self.s_limits[0 if sgn > 0 else 1]
            t_end = parameter_at_chord(curve, c, np.array([reach]), t0, direction)[0]
            self.tables[key] = chord_table(curve, c, t0, direction, 2049, None if np.isnan(t_end) else t_end)
        return self.tables[key]


def touching_point(bodies, point: np.ndarray, extent: float, samples: int = 257) -> np.ndarray:
    """The point near ``point`` where the two bodies' boundaries are closest (deepest where they
    overlap): the point of body 1's contact curve within chord ``extent`` of ``point`` that
    maximises body 2's signed distance, paired with its projection on body 2 (their midpoint).
    Chords are measured from here on both curves, so the matched points of equal chord are the
    pairs Hertz's gap pairs: from any other origin the two chords differ by O(d^2 s / R^2) and the
    pairs slide against each other (a frictional force 24 % off for a point 1.6 a off the
    touching point). ``point`` itself where the gap does not vary along the curve (a flat punch:
    every point is closest) or where the closest point lies at the search's end (none nearby)."""
    b1, b2 = bodies
    point = np.asarray(point, dtype=float)
    edge = b1.profile.edge_names[int(b1.profile.project(point[None, :]).edge_index[0])]
    curve = b1.boundary.curves[edge]
    t0 = closest_parameter(curve, point)
    c = np.asarray(curve.evaluate(np.array([t0])), dtype=float).reshape(2)
    ends = [parameter_at_chord(curve, c, np.array([extent]), t0, sgn)[0] for sgn in (1, -1)]
    lo = float(curve.t_start) if np.isnan(ends[1]) else float(ends[1])
    hi = float(curve.t_end) if np.isnan(ends[0]) else float(ends[0])

    def phi(t):
        return np.asarray(b2.profile.signed_distance(np.asarray(curve.evaluate(t), dtype=float).reshape(-1, 2)),
                          dtype=float)

    t = np.linspace(min(lo, hi), max(lo, hi), samples)
    values = phi(t)
    k = int(np.argmax(values))
    at_given = float(phi(np.array([t0]))[0])
    if not values[k] - at_given > 1e-10 * extent or k in (0, samples - 1):
        return point
    span = abs(float(curve.t_end) - float(curve.t_start))
    best = refined_maximum(phi, t[k - 1], t[k + 1], 1e-13 * max(span, 1.0))
    x1 = np.asarray(curve.evaluate(np.array([best])), dtype=float).reshape(2)
    x2 = np.asarray(b2.profile.project(x1[None, :]).points[0], dtype=float)
    return 0.5 * (x1 + x2)


def contact_geometry(bodies, names: tuple[str, str], point: np.ndarray, extent: float) -> ContactGeometry:
    """Frame and curves of the contact of ``names`` (two BodyDiscretisation-like objects with
    ``profile`` and ``boundary.curves``) at the touching point near ``point``
    (:func:`touching_point`); ``extent`` caps the candidate chord."""
    given = np.asarray(point, dtype=float)
    b1, b2 = bodies
    point = touching_point(bodies, given, extent)
    n2 = np.asarray(b2.profile.project(point[None, :]).normals[0], dtype=float)
    n2 /= np.linalg.norm(n2)
    tangent = np.array([-n2[1], n2[0]])
    edges, curves, origins, ts, dirs, limits = [], [], [], [], [], []
    for b in (b1, b2):
        proj = b.profile.project(point[None, :])
        edge = b.profile.edge_names[int(proj.edge_index[0])]
        curve = b.boundary.curves[edge]
        t0 = closest_parameter(curve, point)
        c = np.asarray(curve.evaluate(np.array([t0])), dtype=float).reshape(2)
        d = np.asarray(curve.derivative(np.array([t0])), dtype=float).reshape(2)
        direction = 1 if float(d @ tangent) >= 0.0 else -1
        lim = []
        for sgn in (1, -1):  # how far the edge reaches on each side (chord to its end)
            end = curve.t_end if sgn * direction > 0 else curve.t_start
            e = np.asarray(curve.evaluate(np.array([float(end)])), dtype=float).reshape(2)
            lim.append(float(np.hypot(*(e - c))))
        edges.append(edge)
        curves.append(curve)
        origins.append(c)
        ts.append(t0)
        dirs.append(direction)
        limits.append(lim)
    # candidate chord per side: the extent, within both edges (a little short of their ends)
    s_plus = min(extent, 0.98 * limits[0][0], 0.98 * limits[1][0])
    s_minus = min(extent, 0.98 * limits[0][1], 0.98 * limits[1][1])
    if not (s_plus > 0 and s_minus > 0):
        raise ValueError(
            f"contact {names[0]}/{names[1]}: the contact point {point.tolist()} sits at the end of edge "
            f"{edges[0]!r} or {edges[1]!r}; give a point inside an edge"
        )
    return ContactGeometry(
        bodies=tuple(names),
        point=point,
        normal=n2,
        tangent=tangent,
        edges=tuple(edges),
        curves=tuple(curves),
        origins=tuple(origins),
        t_origin=tuple(ts),
        directions=tuple(dirs),
        s_limits=(s_plus, s_minus),
        given_point=None if np.array_equal(point, given) else given,
    )


def _parameters_at_s(geom: ContactGeometry, which: int, s: np.ndarray) -> np.ndarray:
    s = np.asarray(s, dtype=float)
    out = np.empty(len(s))
    curve, c, t0, d = geom.curves[which], geom.origins[which], geom.t_origin[which], geom.directions[which]
    for sgn in (1, -1):
        sel = (s >= 0) if sgn > 0 else (s < 0)
        if sel.any():
            out[sel] = parameter_at_chord(curve, c, np.abs(s[sel]), t0, sgn * d, table=geom.table(which, sgn))
    return out


def _s_of_parameters(geom: ContactGeometry, which: int, t: np.ndarray) -> np.ndarray:
    curve, c, t0, d = geom.curves[which], geom.origins[which], geom.t_origin[which], geom.directions[which]
    p = np.asarray(curve.evaluate(np.asarray(t, dtype=float)), dtype=float).reshape(-1, 2)
    return np.sign((np.asarray(t) - t0) * d) * np.hypot(*(p - c).T)


@dataclass
class ContactPoints:
    """Points of body 1's contact curve with their matched points on body 2."""

    s: np.ndarray  # (q,) signed chord from c1
    x1: np.ndarray  # (q, 2)
    n1: np.ndarray  # (q, 2) outward normal of body 1
    x2: np.ndarray  # (q, 2) matched points
    n2: np.ndarray  # (q, 2) outward normal of body 2
    delta: np.ndarray  # (q, 2) X1 - X2
    weights: np.ndarray | None = None  # (q,) ds on curve 1 (quadrature only)
    frame_normal: np.ndarray | None = None  # (2,) the contact frame's normal, when it governs

    @property
    def normal(self) -> np.ndarray:
        """(q, 2) direction of each pair's normal constraint: the contact frame's normal when
        ``frame_normal`` is set (ContactGeometry.normal_mode "frame"), else the pair bisector."""
        if self.frame_normal is not None:
            return np.broadcast_to(self.frame_normal, self.n1.shape).copy()
        return self.pair_normal

    @property
    def pair_normal(self) -> np.ndarray:
        """(q, 2) contact normal of each matched pair: the bisector of body 2's outward normal
        and body 1's inward one, (n2 - n1) / |n2 - n1|. Along it a relative slide of the two
        surfaces leaves the normal gap unchanged to first order (n1 or n2 alone would turn a
        slide of d into a spurious gap d * s / R)."""
        v = self.n2 - self.n1
        return v / np.hypot(v[:, 0], v[:, 1])[:, None]


def match_points(geom: ContactGeometry, t1: np.ndarray) -> ContactPoints:
    """Matched points of the points at parameters ``t1`` of body 1's curve."""
    t1 = np.asarray(t1, dtype=float)
    c1 = geom.curves[0]
    x1 = np.asarray(c1.evaluate(t1), dtype=float).reshape(-1, 2)
    s = _s_of_parameters(geom, 0, t1)
    t2 = _parameters_at_s(geom, 1, s)
    if np.isnan(t2).any():
        raise ValueError(f"contact {geom.bodies}: body 2's edge {geom.edges[1]!r} ends inside the candidate region")
    x2 = np.asarray(geom.curves[1].evaluate(t2), dtype=float).reshape(-1, 2)
    frame = np.asarray(geom.normal, dtype=float) if geom.normal_mode == "frame" else None
    return ContactPoints(s=s, x1=x1, n1=_unit_normal(c1, t1), x2=x2, n2=_unit_normal(geom.curves[1], t2),
                         delta=x1 - x2, frame_normal=frame)


def sample_points(geom: ContactGeometry, s: np.ndarray) -> ContactPoints:
    """Points of body 1's curve at signed chords ``s`` and their matches."""
    return match_points(geom, _parameters_at_s(geom, 0, np.asarray(s, dtype=float)))


def _grid_lines_near(grid, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    lower, size = grid.lower[cells], grid.size[cells]
    xs = np.unique(np.round(np.concatenate([lower[:, 0], lower[:, 0] + size]), 13))
    ys = np.unique(np.round(np.concatenate([lower[:, 1], lower[:, 1] + size]), 13))
    return xs, ys


def grid_breakpoints(geom: ContactGeometry, grids, s_lo: float, s_hi: float) -> np.ndarray:
    """Signed chords in (s_lo, s_hi) where body 1's curve or the matched points of body 2's
    curve cross a cell line of their own grid: the integrand's kinks."""
    out = []
    for which, grid in enumerate(grids):
        curve = geom.curves[which]
        tl = _parameters_at_s(geom, which, np.array([s_lo, s_hi]))
        lo_t, hi_t = np.nanmin(tl), np.nanmax(tl)
        pc = grid.pieces
        sel = pc.of(geom.edges[which])
        near = sel[(np.maximum(pc.t0[sel], pc.t1[sel]) >= lo_t) & (np.minimum(pc.t0[sel], pc.t1[sel]) <= hi_t)]
        if len(near) == 0:
            continue
        xs, ys = _grid_lines_near(grid, pc.cell[near])
        ts = [np.asarray(curve.axis_crossings(0, float(v)), dtype=float).ravel() for v in xs]
        ts += [np.asarray(curve.axis_crossings(1, float(v)), dtype=float).ravel() for v in ys]
        brk = getattr(curve, "breakpoints", None)
        if brk is not None:
            ts.append(np.asarray(brk(), dtype=float))
        t = np.concatenate(ts) if ts else np.zeros(0)
        t = t[(t > lo_t) & (t < hi_t)]
        s = _s_of_parameters(geom, which, t)
        out.append(s[(s > s_lo) & (s < s_hi)])
    return np.unique(np.concatenate(out)) if out else np.zeros(0)


def contact_quadrature(geom: ContactGeometry, grids, s_lo: float, s_hi: float, order: int = 4,
                       breakpoints: np.ndarray | None = None) -> ContactPoints:
    """Gauss-Legendre rule on body 1's curve between chords s_lo < s_hi, in the curve's own
    parameter, on pieces split at both grids' cell lines (``breakpoints``, computed when None)."""
    if breakpoints is None:
        breakpoints = grid_breakpoints(geom, grids, s_lo, s_hi)
    b = np.asarray(breakpoints, dtype=float)
    s = np.unique(np.concatenate([[s_lo, s_hi], b[(b > s_lo) & (b < s_hi)]]))
    t = _parameters_at_s(geom, 0, s)
    _, w, _, tq = curve_gauss(geom.curves[0], t[:-1], t[1:], order)
    pts = match_points(geom, tq.ravel())
    pts.weights = w.ravel()
    return pts
