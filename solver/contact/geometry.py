"""Contact geometry of two bodies (thesis sections 5.1-5.2): the contact point and frame, the
pairing of the two boundaries' points, Delta between matched points (eq. 5-2) and the
quadrature of body 1's contact curve split at both grids' cell lines.

Conventions (those of summary.json): ``normal`` is the outward unit normal of the SECOND body at the
contact point, ``tangent`` = (-n_y, n_x). A point of body 1's contact curve is labelled by its
signed chord s: |s| is the straight-line distance from body 1's contact point c1, the sign that
of the side along ``tangent``. Its matched point on body 2's curve depends on the contact normal
(``ContactGeometry.normal_mode``): with the frame's normal ("frame", the default: Hertz's
small-strain gap) it lies straight across along that normal, at the same tangential offset
(X - c) . tangent from c2 as the point from c1, so Delta = X1 - X2 is the initial gap along the
normal and has no tangential part; with each pair's own normal ("pair", conformal contacts) it
has the same chord from c2 on the same side (cord-length matching of section 5.2). Contact means
u1 - u2 + Delta = 0 (eq. 5-3).

Everything works on any curve with ``evaluate``/``derivative``/``axis_crossings`` and
``t_start``/``t_end``: the exact ``geometry.bounded`` curves, or the ``Polyline`` of the
tessellated (``exact_geometry = false``) variant, whose facets then give the points, normals
and Delta (the thesis's non-projected results).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ibfem.geometry.chord_walk import first_crossing, walk_distances

from ..fem.integration import curve_gauss
from ..model.resolve import refined_maximum
from .chain import CORNER_ANGLE, contact_chain

__all__ = [
    "chord_table",
    "ContactGeometry",
    "SideLimit",
    "ContactPoints",
    "closest_parameter",
    "parameter_at_chord",
    "contact_geometry",
    "touching_point",
    "match_points",
    "sample_points",
    "contact_quadrature",
    "chain_pieces",
    "chord_weights",
    "grid_breakpoints",
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
    brk = getattr(curve, "breakpoints", None)
    if brk is not None:  # junctions are samples: a corner at the walk's farthest point is reached exactly
        b = np.asarray(brk(), dtype=float)
        lo, hi = min(float(t_from), end), max(float(t_from), end)
        t = np.unique(np.concatenate([t, b[(b > lo) & (b < hi)]]))
        t = t if end >= float(t_from) else t[::-1]
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
class SideLimit:
    """How far the candidate region reaches on one side of the contact point: the chord and
    what bounds it ("refinement radius", "corner of body 1", "far side of body <name>")."""

    chord: float
    cause: str
    corner: bool = False  # a convex corner of body 1 ends the region there (a complete contact end)


@dataclass
class ContactGeometry:
    """One contact: frame, the two contact curves and where on them the contact point lies."""

    bodies: tuple[str, str]
    point: np.ndarray  # reported contact point: where the two curves are closest (the chords' origin)
    normal: np.ndarray  # outward normal of body 2 at the point
    tangent: np.ndarray  # (-n_y, n_x)
    edges: tuple[str, str]  # the edge of each body through the contact point
    curves: tuple  # the contact curves: each body's chain of edges (solver.contact.chain)
    origins: tuple[np.ndarray, np.ndarray]  # c1, c2: the contact point on each curve
    t_origin: tuple[float, float]
    directions: tuple[int, int]  # parameter direction of +s (along tangent) on each curve
    s_limits: tuple[float, float]  # usable chord range on each side (candidate region), >= 0
    tables: dict = field(default_factory=dict)  # (curve, side) -> chord_table over the candidate region
    # "frame": every pair is constrained along the contact frame's normal (the small-strain,
    # half-space assumption of Hertz theory: frictionless tractions have no component along
    # the tangent); "pair": along each matched pair's bisector normal (ContactPoints.normal)
    normal_mode: str = "frame"
    given_point: np.ndarray | None = None  # the scene's point, when the touching point lies off it
    limits: tuple = ()  # SideLimit of the + and - side

    def s_max(self) -> float:
        return min(self.s_limits)

    def mirror_side(self) -> int:
        """+1 / -1: the side the region extends to when the contact point lies on a corner of
        body 1 (a half model's symmetry line: the region is mirrored there); 0 otherwise."""
        if not self.limits:
            return 0
        plus, minus = self.limits
        if minus.corner and minus.chord <= 0.0 < plus.chord:
            return 1
        if plus.corner and plus.chord <= 0.0 < minus.chord:
            return -1
        return 0

    def table(self, which: int, sgn: int):
        """Chord table of curve ``which`` on side ``sgn`` covering the candidate region."""
        key = (which, sgn)
        if key not in self.tables:
            curve, c, t0 = self.curves[which], self.origins[which], self.t_origin[which]
            direction = sgn * self.directions[which]
            reach = 1.05 * max(self.s_limits[0 if sgn > 0 else 1], 1e-12)
            t_end = parameter_at_chord(curve, c, np.array([reach]), t0, direction, samples=4097)[0]
            self.tables[key] = chord_table(curve, c, t0, direction, 2049, None if np.isnan(t_end) else t_end)
        return self.tables[key]


def _body_chain(body, edge: str):
    return contact_chain(body.profile, body.boundary.curves, edge)


def _on_chain(body, point: np.ndarray):
    """(chain, T) of the point of ``body``'s boundary closest to ``point``."""
    edge = body.profile.edge_names[int(body.profile.project(point[None, :]).edge_index[0])]
    chain = _body_chain(body, edge)
    k = chain.middle
    return chain, float(chain.to_chain(k, closest_parameter(chain.curves[k], point)))


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
    curve, t0 = _on_chain(b1, point)
    c = np.asarray(curve.evaluate(np.array([t0])), dtype=float).reshape(2)
    ends = [parameter_at_chord(curve, c, np.array([extent]), t0, sgn, samples=4097)[0] for sgn in (1, -1)]
    lo = float(curve.t_start) if np.isnan(ends[1]) else float(ends[1])
    hi = float(curve.t_end) if np.isnan(ends[0]) else float(ends[0])
    corners = curve.corners()
    lo = max([lo] + [t for t in corners if t <= t0])  # the search stays between body 1's corners
    hi = min([hi] + [t for t in corners if t >= t0])

    def phi(t):
        return np.asarray(b2.profile.signed_distance(np.asarray(curve.evaluate(t), dtype=float).reshape(-1, 2)),
                          dtype=float)

    if not hi > lo:
        return point
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


def _leaves_along(chain, t0: float, direction: int, along: np.ndarray) -> bool:
    """Whether the walk from ``t0`` in ``direction`` starts along the unit vector ``along``
    (within CORNER_ANGLE): at a corner on the contact point, the side the region extends to."""
    d = direction * np.asarray(chain.derivative(np.array([t0 + direction * 1e-9])), dtype=float).reshape(2)
    return float(d @ along) >= math.cos(CORNER_ANGLE) * float(np.linalg.norm(d))


def _side_limit(chain, c: np.ndarray, t0: float, direction: int, body: str, first: bool,
                along: np.ndarray) -> SideLimit:
    """How far the walk from ``t0`` along ``direction`` may go: to body 1's first convex corner
    (``first``; a corner on the point itself only where the walk does not start ``along`` the
    contact's tangent on that side), else to where the chord from ``c`` stops growing (the far
    side of the body)."""
    end = chain.t_end if direction > 0 else chain.t_start
    t = np.linspace(t0, end, 2049)
    d = walk_distances(chain, c, t)
    falls = np.nonzero(np.diff(d) <= 0.0)[0]
    k_far = int(falls[0]) if len(falls) else len(d) - 1
    far = SideLimit(0.98 * float(d[k_far]), f"far side of body {body!r}")
    if first:
        span = 1e-9 * max(abs(end - t0), 1.0)
        corners = [T for T in chain.corners() if direction * (T - t0) > span
                   or (abs(T - t0) <= span and not _leaves_along(chain, t0, direction, along))]
        if corners:
            T = min(corners, key=lambda T: direction * (T - t0))
            if direction * (T - t[k_far]) <= 0.0:
                x = np.asarray(chain.evaluate(np.array([T])), dtype=float).reshape(2)
                chord = float(np.hypot(*(x - c)))
                return SideLimit(chord if chord > 1e-9 * max(float(d.max()), 1e-300) else 0.0,
                                 f"corner of body {body!r} (edge {chain.edge_at(T - 0.5 * direction)!r} ends)",
                                 corner=True)
    return far


def contact_geometry(bodies, names: tuple[str, str], point: np.ndarray, extent: float) -> ContactGeometry:
    """Frame and curves of the contact of ``names`` (two BodyDiscretisation-like objects with
    ``profile`` and ``boundary.curves``) at the touching point near ``point``
    (:func:`touching_point`); ``extent`` caps the candidate chord. Each body's contact curve is
    the chain of its edges through the point (:mod:`solver.contact.chain`): the region may cross
    junctions and seams; it ends at a corner of body 1."""
    given = np.asarray(point, dtype=float)
    b1, b2 = bodies
    point = touching_point(bodies, given, extent)
    n2 = np.asarray(b2.profile.project(point[None, :]).normals[0], dtype=float)
    n2 /= np.linalg.norm(n2)
    tangent = np.array([-n2[1], n2[0]])
    edges, curves, origins, ts, dirs, limits = [], [], [], [], [], []
    for which, (b, name) in enumerate(zip((b1, b2), names)):
        chain, t0 = _on_chain(b, point)
        c = np.asarray(chain.evaluate(np.array([t0])), dtype=float).reshape(2)
        d = np.asarray(chain.derivative(np.array([t0])), dtype=float).reshape(2)
        direction = 1 if float(d @ tangent) >= 0.0 else -1
        edges.append(chain.edge_at(t0))
        curves.append(chain)
        origins.append(c)
        ts.append(t0)
        dirs.append(direction)
        limits.append([_side_limit(chain, c, t0, sgn * direction, name, which == 0, sgn * tangent) for sgn in (1, -1)])
    sides = []
    for k in range(2):  # candidate chord per side: the extent, within both bodies
        options = [SideLimit(extent, "refinement radius")] + [limits[0][k], limits[1][k]]
        sides.append(min(options, key=lambda lim: (lim.chord, not lim.corner)))
    geom = ContactGeometry(
        bodies=tuple(names),
        point=point,
        normal=n2,
        tangent=tangent,
        edges=tuple(edges),
        curves=tuple(curves),
        origins=tuple(origins),
        t_origin=tuple(ts),
        directions=tuple(dirs),
        s_limits=(sides[0].chord, sides[1].chord),
        given_point=None if np.array_equal(point, given) else given,
        limits=tuple(sides),
    )
    if not (sides[0].chord > 0.0 or sides[1].chord > 0.0) or (min(geom.s_limits) <= 0.0 and not geom.mirror_side()):
        why = " and ".join(f"{lim.cause} at the point on the {side} side" for side, lim in zip("+-", sides)
                           if lim.chord <= 0.0)
        raise ValueError(
            f"contact {names[0]}/{names[1]}: no room for a contact region at the contact point {point.tolist()} "
            f"(edges {edges[0]!r} / {edges[1]!r}): {why}"
        )
    return geom


def _chord_parameters(geom: ContactGeometry, which: int, s: np.ndarray) -> np.ndarray:
    """Parameters on curve ``which`` of the points at signed chord ``s`` from its own origin."""
    s = np.asarray(s, dtype=float)
    out = np.empty(len(s))
    curve, c, t0, d = geom.curves[which], geom.origins[which], geom.t_origin[which], geom.directions[which]
    for sgn in (1, -1):
        sel = (s >= 0) if sgn > 0 else (s < 0)
        if sel.any():
            out[sel] = parameter_at_chord(curve, c, np.abs(s[sel]), t0, sgn * d, table=geom.table(which, sgn))
    return out


def _chord_of_parameters(geom: ContactGeometry, which: int, t: np.ndarray) -> np.ndarray:
    curve, c, t0, d = geom.curves[which], geom.origins[which], geom.t_origin[which], geom.directions[which]
    p = np.asarray(curve.evaluate(np.asarray(t, dtype=float)), dtype=float).reshape(-1, 2)
    return np.sign((np.asarray(t) - t0) * d) * np.hypot(*(p - c).T)


def _offsets(geom: ContactGeometry, which: int, t: np.ndarray) -> np.ndarray:
    """Tangential offsets (X(t) - c) . tangent of curve ``which``'s points from its origin."""
    p = np.asarray(geom.curves[which].evaluate(np.asarray(t, dtype=float)), dtype=float).reshape(-1, 2)
    return (p - geom.origins[which]) @ np.asarray(geom.tangent, dtype=float)


def _offset_parameters(geom: ContactGeometry, which: int, offset: np.ndarray, iterations: int = 30) -> np.ndarray:
    """Parameters on curve ``which`` of the points at tangential ``offset`` from its origin: the
    first crossing along the candidate region's walk on each side (bracketed on its sampled
    table), refined by safeguarded Newton on (X(t) - c) . tangent - offset. NaN where the walk
    does not reach the offset."""
    offset = np.asarray(offset, dtype=float).ravel()
    out = np.full(offset.shape, np.nan)
    curve, tangent = geom.curves[which], np.asarray(geom.tangent, dtype=float)
    out[offset == 0.0] = geom.t_origin[which]
    for sgn in (1, -1):
        sel = np.nonzero(sgn * offset > 0.0)[0]
        if len(sel) == 0:
            continue
        t, _ = geom.table(which, sgn)
        reach = np.maximum.accumulate(sgn * _offsets(geom, which, t))
        target = sgn * offset[sel]
        j = np.searchsorted(reach, target, side="left")
        ok = (j > 0) & (j < len(t))
        sel, target, j = sel[ok], target[ok], j[ok]
        a, b = t[j - 1], t[j]
        fa, fb = reach[j - 1] - target, reach[j] - target
        with np.errstate(divide="ignore", invalid="ignore"):
            x = np.where(fb != fa, a - fa * (b - a) / (fb - fa), 0.5 * (a + b))
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        for _ in range(iterations):
            f = sgn * _offsets(geom, which, x) - target
            df = sgn * (np.asarray(curve.derivative(x), dtype=float).reshape(-1, 2) @ tangent)
            with np.errstate(divide="ignore", invalid="ignore"):
                nx = x - f / df
            nx = np.where(np.isfinite(nx) & (nx >= lo) & (nx <= hi), nx, 0.5 * (lo + hi))
            done = np.abs(nx - x) <= 1e-15 * np.maximum(1.0, np.abs(nx))
            x = nx
            if np.all(done):
                break
        out[sel] = x
    return out


def _parameters_at_s(geom: ContactGeometry, which: int, s: np.ndarray) -> np.ndarray:
    """Parameters on curve ``which`` of the points labelled ``s`` (body 1's signed chord): on
    body 1 the chord itself; on body 2 the matched point, at the same tangential offset
    ("frame": along the frame's normal) or at the same chord ("pair")."""
    if which == 0 or geom.normal_mode != "frame":
        return _chord_parameters(geom, which, s)
    return _offset_parameters(geom, 1, _offsets(geom, 0, _chord_parameters(geom, 0, s)))


def _s_of_parameters(geom: ContactGeometry, which: int, t: np.ndarray) -> np.ndarray:
    """The label s (body 1's signed chord) of curve ``which``'s points at parameters ``t``."""
    if which == 0 or geom.normal_mode != "frame":
        return _chord_of_parameters(geom, which, t)
    return _chord_of_parameters(geom, 0, _offset_parameters(geom, 0, _offsets(geom, 1, t)))


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
        raise ValueError(f"contact {geom.bodies[0]}/{geom.bodies[1]}: no point of body {geom.bodies[1]!r}'s boundary "
                         f"lies at chord {float(np.abs(s[np.isnan(t2)]).max()):.4g} m from the contact point on that "
                         "side (the body is smaller than the candidate region)")
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


def chain_pieces(geom: ContactGeometry, which: int, grid, s_lo: float, s_hi: float) -> np.ndarray:
    """Indices of the grid's boundary pieces (``grid.pieces``) on curve ``which``'s chain
    between the chords s_lo < s_hi."""
    chain = geom.curves[which]
    T = _parameters_at_s(geom, which, np.array([s_lo, s_hi]))
    lo_T, hi_T = np.nanmin(T), np.nanmax(T)
    pc = grid.pieces
    out = []
    for k in range(int(np.floor(lo_T)), int(np.floor(hi_T)) + 1):
        k = min(max(k, 0), len(chain.curves) - 1)
        a, b = chain.local(k, np.array([max(lo_T, k), min(hi_T, k + 1)]))
        lo_t, hi_t = min(a, b), max(a, b)
        sel = pc.of(chain.names[k])
        out.append(sel[(np.maximum(pc.t0[sel], pc.t1[sel]) >= lo_t) & (np.minimum(pc.t0[sel], pc.t1[sel]) <= hi_t)])
    return np.unique(np.concatenate(out)) if out else np.zeros(0, dtype=np.intp)


def grid_breakpoints(geom: ContactGeometry, grids, s_lo: float, s_hi: float) -> np.ndarray:
    """Signed chords in (s_lo, s_hi) where body 1's curve or the matched points of body 2's
    curve cross a cell line of their own grid, or an edge junction or kink: the integrand's kinks."""
    out = []
    for which, grid in enumerate(grids):
        curve = geom.curves[which]
        tl = _parameters_at_s(geom, which, np.array([s_lo, s_hi]))
        lo_t, hi_t = np.nanmin(tl), np.nanmax(tl)
        near = chain_pieces(geom, which, grid, s_lo, s_hi)
        if len(near) == 0:
            continue
        xs, ys = _grid_lines_near(grid, grid.pieces.cell[near])
        ts = [np.asarray(curve.axis_crossings(0, float(v), lo_t, hi_t), dtype=float).ravel() for v in xs]
        ts += [np.asarray(curve.axis_crossings(1, float(v), lo_t, hi_t), dtype=float).ravel() for v in ys]
        ts.append(np.asarray(curve.breakpoints(), dtype=float))
        t = np.concatenate(ts)
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


def chord_weights(geom: ContactGeometry, pts: ContactPoints) -> np.ndarray:
    """The quadrature weights (q,) in the chord coordinate s: ds = |cos| of the angle between the
    chord from c1 and the curve's tangent times the arc length (1 at the contact point; cos(theta / 2)
    on a circle at the angle theta from it). Moments in s (the region's end values and centre) need
    them; forces take the arc length."""
    d = pts.x1 - geom.origins[0]
    r = np.hypot(d[:, 0], d[:, 1])
    tangent = np.stack([-pts.n1[:, 1], pts.n1[:, 0]], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.abs(np.einsum("qi,qi->q", d, tangent)) / r
    return pts.weights * np.where(r > 0.0, cos, 1.0)
