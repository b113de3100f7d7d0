"""A contact region of general shape between two solids: star-shaped about the touching point,
its edge r(phi) a periodic cubic spline through knots, each knot fixed by the pressure at its own
stretch of the edge; the region ends at body 1's free edges where it reaches them (complete
contact). It takes the contacts the ellipse (solver.contact.ellipse) cannot: line contacts of
finite length, such as a roller on a flat, where one relative curvature vanishes.

Coordinates: along the frame's axes, normalised by the scales (A, B): X = s0 / A, Y = s1 / B. A
is fixed: the distance from the contact point to body 1's free edge along axis 0 (the line's
end: a roller's end face); B is the size the region search finds (the half-width across the
line). The region is r <= rho(phi) in the normalised polar coordinates (r, phi) of (X, Y):
s = r rho(phi) (A cos phi, B sin phi), the area element A B rho^2 r dr dphi.

Edge conditions. Every pressure of the band formulation near a smooth edge behaves as
Q / sqrt(1 - r^2) along a ray, with Q = q0 + q2 r^2 a smooth factor; Hertz's pressure (of a line
contact: p0 sqrt(1 - y^2 / b^2)) has Q(1) = q0 + q2 = 0, the edge's square-root coefficient. The
moment of the pressure along a ray with the weight 5/2 r^2 - 1 in the measure r dr is
2/3 (q0 + q2) (int_0^1 r / sqrt(1 - r^2) dr = 1, of r^3: 2/3, of r^5: 8/15): zero exactly when the
edge is smooth, positive for a punch-like pressure (the region too small there). Each knot's
moment is taken over its stretch of the edge (the quadrature points weighted by the knot's hat
function in phi), normalised by the pressure's integral there. The region search sets B by the
mean moment of the knots with a smooth edge; then each such knot's log rho moves by a secant on
its moment less the mean, until all agree to KNOT_TOLERANCE; once they first agree, a line
contact's knots are spread along its edge, at most SPREAD_CELLS finest cells apart, and the
iteration goes on (``spread_knots``). A knot whose ray leaves body 1's
surface before its edge (the region reaches body 1's free edge there) has no edge condition: the
contact is complete there (the pressure is singular at a sharp edge), and it is reported as such.

A flat face that is not star-shaped about the contact point (a washer's annulus, an L-shaped
punch seen from a leg: solver.contact.face_shape) is taken whole, in complete contact, where the
candidate region holds all of it and its gaps are open holes: the region is the circle about its
centre that holds every sample of the face (``whole_face``), with no edge condition; a partial
contact on such a face is not supported, and other such faces are refused at set-up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .band import CandidateRegionExceeded
from .ellipse import (PANELS_PER_CELL, REGION_ORDER, EllipseContact, _judge, _quadrature_traction, _sample_state,
                      is_flat_contact, plane_weights)
from .ellipse_geometry import region_points, surface_point
from .face_shape import BEND_CELLS, ROUND_OFF_BEND, face_rays, line_bend, on_face, resumed_rays
from .graded_quadrature import leaf_size
from .region_report import mirror_images
from .roots import edge_search, settling_tolerance

__all__ = ["StarRegionContact", "configure_star_region", "free_edge_distance", "knots_inside", "reaches_free_end",
           "section_edges",
           "section_moments", "KNOTS", "KNOT_TOLERANCE"]

#: knots of the edge's spline over the full turn to start with (15 degrees apart); more are
#: inserted where the edge condition asks for them (``StarRegionContact.refine_knots``)
KNOTS = 24
#: a stretch of the edge between two knots is split only where it is longer than this many of
#: the grid's cells there (each half then spans at least one cell, the edge's resolution on the
#: grid; ``edge_cells``)
SPLIT_CELLS = 2.0
#: a new knot midway between two is kept where its edge moment differs from the knots' pooled
#: mean by more than this (four times the settled knots' tolerance: the edge between the two
#: knots is not where the pressure puts it)
SPLIT_MOMENT = 4.0 * 0.005
#: once the knots first agree, a line contact's stretches of smooth edge between two knots are cut
#: into equal lengths of at most this many of the grid's cells there along the edge
#: (``spread_knots``, ``edge_cells``)
SPREAD_CELLS = 2.0
#: neighbouring knots with a smooth edge whose edge points lie closer than this many finest cells
#: (the crowded knots at a long region's tips) share one edge condition: the grid cannot tell
#: their stretches apart, so each one's own moment is mostly the grid's noise
TIE_CELLS = 0.5
#: the most knots the edge's spline takes
MAX_KNOTS = 96
#: shape updates a load step may take beyond the options' max_stick_iterations per insertion of
#: knots (the secants start again), and the most insertions per load step
SPLIT_UPDATES = 12
#: shape updates after an insertion within which the knots must agree again; otherwise the
#: insertion is undone (the knots before it had agreed) and no more are tried in the load step
SPLIT_SETTLE = 10
MAX_SPLITS = 3
#: the knots' edge moments agree with their mean to this (the shape has settled)
KNOT_TOLERANCE = 0.005
#: a knot at a free edge whose moment (measured to the free edge) is below minus this has a
#: pressure falling to zero before the edge (a crowned roller): its edge moves inside
END_MOMENT = 0.05
#: the edge moment's window next to the edge along a ray, in cells (the whole ray if shorter)
EDGE_WINDOW_CELLS = 3.0
#: the largest step of a knot's log rho per shape update
KNOT_STEP = 0.3
#: ... and of its edge point, in finest cells: a long ray's log rho moves its edge far (0.3 at a
#: roller's tip, 80 mm from the contact point, is four 6.25 mm cells), beyond where the moment
#: it was measured with says anything
STEP_CELLS = 1.0
#: a knot's secant step in log rho is at most this many times its moment's difference from the
#: mean: a moment falls by about 1 per unit of log rho, so a step beyond twice the difference
#: comes from a secant through the grid's noise (one moved the crowned roller's side by 4 mm, 17 %
#: of its width, in one update after its knots were spread every cell)
SECANT_GAIN = 2.0
#: a line contact's knots whose edge runs within this angle of the line are read on sections
#: across it (radians)
SIDE_ANGLE = math.radians(30.0)
#: a knot read on sections goes back to its ray only where its edge turns beyond this angle from
#: the line (radians): a knot whose edge runs near SIDE_ANGLE (next to a region's tip) would
#: otherwise change its reading, and so its moment, from one shape update to the next
SIDE_ANGLE_LEAVE = math.radians(40.0)
#: rays around the contact point on which body 1's free edge is located
EDGE_RAYS = 720
#: rays on which a trial region is kept within the cells prepared for it (``largest_size``)
SIZE_ANGLES = 720
#: the prepared cells reach this share of the finest cell beyond the candidate disc (those a
#: quarter cell from its points: solver.contact.ellipse._near_cells)
PREPARED_REACH = 0.25


def free_edge_distance(solid1, frame, ranges, reach: float, extent: float, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """(psi (EDGE_RAYS,), distance (EDGE_RAYS,)): along each direction psi of the tangent plane
    (from axis 0 towards axis 1), how far from the contact point body 1's surface goes before it
    ends (a free edge; inf: beyond ``extent``; 0 outside the angular ``ranges``). The first
    missing sample of 48 along the ray, then bisection to a thousandth of ``scale``."""
    psi, t, ok, _ = face_rays(solid1, frame, reach, extent, EDGE_RAYS)
    return _edge_distance(solid1, frame, reach, scale, psi, t, ok, _inside_rays(psi, ranges))


def _nearest_inside(ends: np.ndarray) -> np.ndarray:
    """``free_edge_distance``'s distances with each ray outside body 1's angular ranges (0) given
    the distance of the nearest ray inside them (circularly): a region's ray along a range's own
    boundary (a quarter model's symmetry plane, its angle off the rays' by round-off) reads the
    free edge of the ray beside it, not none."""
    inside = np.nonzero(ends != 0.0)[0]
    if not len(inside) or len(inside) == len(ends):
        return ends
    n = len(ends)
    gap = np.abs(np.arange(n)[:, None] - inside[None, :])
    return ends[inside[np.argmin(np.minimum(gap, n - gap), axis=1)]]


def _inside_rays(psi: np.ndarray, ranges) -> np.ndarray:
    """(rays,) whether each direction psi lies in body 1's angular ranges about the point."""
    inside = np.zeros(len(psi), dtype=bool)
    for t0, t1 in ranges:
        inside |= ((psi - t0) % (2.0 * math.pi) <= (t1 - t0) + 1e-12)
    return inside


def _edge_distance(solid1, frame, reach: float, scale: float, psi: np.ndarray, t: np.ndarray, ok: np.ndarray,
                   inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``free_edge_distance`` from the rays' samples (``face_rays``)."""
    direction = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    missing = ~ok
    first = np.where(missing.any(axis=1), np.argmax(missing, axis=1), len(t))
    distance = np.full(len(psi), math.inf)
    ends = np.nonzero(inside & (first < len(t)))[0]
    lo = np.where(first[ends] > 0, t[np.maximum(first[ends] - 1, 0)], 0.0)
    hi = t[first[ends]]
    while len(ends) and float(np.max(hi - lo)) > 1e-3 * scale:
        mid = 0.5 * (lo + hi)
        has = surface_point(solid1, frame, mid[:, None] * direction[ends], reach)[1]
        lo, hi = np.where(has, mid, lo), np.where(has, hi, mid)
    distance[ends] = lo
    distance[~inside] = 0.0
    return psi, distance


@dataclass
class StarRegionContact(EllipseContact):
    """The band terms on a star-shaped region (see the module's docstring): ``a`` is the scale B
    across the line, ``length`` the fixed scale A along it."""

    #: the final check's tension judged on the pressure read through the squares' corners, as the map
    corner_reading = True
    length: float = 1.0
    isotropic: bool = False  # a flat contact: A = B, both the size the search finds
    knots: np.ndarray = field(default_factory=lambda: np.linspace(0.0, 2.0 * math.pi, KNOTS, endpoint=False))
    log_rho: np.ndarray = field(default_factory=lambda: np.zeros(KNOTS))
    edge_psi: np.ndarray = field(default_factory=lambda: np.zeros(0))
    edge_distance: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: a flat face that is not star-shaped about the contact point (a washer's annulus) taken
    #: whole in complete contact: its points on the rays' samples (m, 2), which the region must
    #: hold (``whole_face_uncovered``); None for every other contact
    whole_face: np.ndarray | None = None
    face_spacing: float = 0.0  # the whole face's samples' spacing along the rays
    #: (m, 2) the whole face's samples next to its edges (a sample on the face beside one off it)
    face_edges: np.ndarray | None = None
    _knot_history: list = field(default_factory=list)  # (log_rho, moments less their mean) per shape update
    # per knot: the first entry of _knot_history measured with its present reading (its secant's start)
    _knot_since: np.ndarray = field(default_factory=lambda: np.zeros(KNOTS, dtype=int))
    knot_moments: np.ndarray = field(default_factory=lambda: np.full(KNOTS, math.nan))
    free_knots: np.ndarray = field(default_factory=lambda: np.zeros(KNOTS, dtype=bool))
    _spline: tuple | None = None  # (log_rho bytes, the spline of log rho)
    _raw_moments: tuple = (np.zeros(0), np.zeros(0))  # (moment, pressure) per knot, not normalised
    # the knots read on sections across the line (a long region's sides), fixed between shape updates
    across: np.ndarray = field(default_factory=lambda: np.zeros(KNOTS, dtype=bool))
    #: shape updates this load step may take beyond the options' budget (knots inserted)
    extra_shape_updates: int = 0
    #: (knots, log rho, shape updates since) of the last insertion's settled knots, until the
    #: knots agree again
    _before_split: tuple | None = None
    #: the knots have been spread along the edge in this load step (``spread_knots``)
    _spread: bool = False
    #: (psi, distance) of body 1's free edges as far as the prepared cells reach (``largest_size``)
    _prepared_edges: tuple | None = None

    # ------------------------------------------------------------------ the region's shape

    def semi_axes(self, a: float) -> tuple[float, float]:
        return (a, a) if self.isotropic else (self.length, a)

    @property
    def inside_knots(self) -> np.ndarray:
        """(K,) whether each knot's angle lies in body 1's sectors about the contact point."""
        return knots_inside(self.knots, self.ranges)

    def rho(self, phi: np.ndarray) -> np.ndarray:
        """The edge's normalised radius rho(phi): a periodic cubic spline of log rho (made once
        per set of knot values)."""
        key = self.log_rho.tobytes() + self.knots.tobytes()
        if self._spline is None or self._spline[0] != key:
            values = np.append(self.log_rho, self.log_rho[0])
            from scipy.interpolate import CubicSpline  # imported when a region is made: scipy.interpolate

            self._spline = (key, CubicSpline(np.append(self.knots, 2.0 * math.pi), values, bc_type="periodic"))
        return np.exp(self._spline[1](np.mod(phi, 2.0 * math.pi)))

    def edge_points(self, phi: np.ndarray, a: float | None = None) -> np.ndarray:
        """(n, 2) the edge's points at the angles ``phi``: in the normalised coordinates (X, Y), or
        with ``a`` in the tangent plane's lengths along the region's axes (times its semi-axes)."""
        phi = np.asarray(phi, dtype=float)
        points = self.rho(phi)[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
        return points if a is None else points * np.array(self.semi_axes(a))

    def edge_cells(self, phi: np.ndarray, a: float) -> np.ndarray:
        """(n,) the grid's cell size at the edge's points at the angles ``phi``: the larger of the
        two bodies' leaves holding the point of the tangent plane (the finest cell where neither
        grid holds it). The refinement that follows a region refines its edge one level more
        where it turns, so the cells along one edge differ: the knots' spacing and their trial
        points follow the cells the edge crosses, not the finest one."""
        out = np.full(len(np.atleast_1d(phi)), float(self.h))
        grids = [g for g in (getattr(getattr(self, n, None), "grid", None) for n in ("b1", "b2")) if hasattr(g, "locate")]
        if not grids:
            return out
        s = self.centre + self.edge_points(phi, a)
        y = self.frame.point + s[:, :1] * self.frame.axes[0] + s[:, 1:] * self.frame.axes[1]
        for grid in grids:
            cell = grid.locate(y)
            found = cell >= 0
            out[found] = np.maximum(out[found], np.asarray(grid.size)[cell[found]])
        return out

    def knot_chords(self, a: float) -> np.ndarray:
        """(K,) the distance in the tangent plane from each knot's edge point to the next knot's."""
        edge = self.edge_points(self.knots, a)
        return np.hypot(*(np.roll(edge, -1, axis=0) - edge).T)

    def polar(self, s: np.ndarray, a: float) -> tuple[np.ndarray, np.ndarray]:
        """(r, phi) of tangent-plane points: r = 1 on the region's edge."""
        aa, bb = self.semi_axes(a)
        local = self.local(s)
        X, Y = local[:, 0] / aa, local[:, 1] / bb
        phi = np.arctan2(Y, X)
        return np.hypot(X, Y) / self.rho(phi), phi

    def normalised_radius(self, s: np.ndarray, a: float) -> np.ndarray:
        return self.polar(s, a)[0]

    def end_radius(self, phi: np.ndarray, a: float) -> np.ndarray:
        """The normalised radius r at which the ray at phi leaves body 1's surface (a free edge;
        inf where it does not within the candidate region)."""
        aa, bb = self.semi_axes(a)
        direction = np.stack([aa * np.cos(phi), bb * np.sin(phi)], axis=1)
        psi = np.mod(np.arctan2(direction[:, 1], direction[:, 0]), 2.0 * math.pi)
        k = np.rint(psi / (2.0 * math.pi) * len(self.edge_psi)).astype(int) % len(self.edge_psi)
        return self.edge_distance[k] / (np.hypot(direction[:, 0], direction[:, 1]) * self.rho(phi))

    def ray_length(self, phi: np.ndarray, a: float) -> np.ndarray:
        """The physical length of the ray at phi from the centre to the region's edge."""
        aa, bb = self.semi_axes(a)
        return self.rho(phi) * np.hypot(aa * np.cos(phi), bb * np.sin(phi))

    def region_quadrature(self, a: float):
        """The region's quadrature points on body 1, matched on body 2: panels that follow the
        cells they lie in (solver.contact.graded_quadrature), PANELS_PER_CELL per cell."""
        aa, bb = self.semi_axes(a)
        return region_points(*self.solids, self.frame, aa, bb, self.ranges, self.grids, self.h / PANELS_PER_CELL,
                             self.reach, REGION_ORDER, centre=self.centre, radius=self.rho, cells=self.leaf_sizes())

    def leaf_sizes(self):
        """Each body's leaf size at 3D points (None where a body has no octree: the finest cell's
        lattice everywhere)."""
        grids = [getattr(getattr(self, n, None), "grid", None) for n in ("b1", "b2")]
        if not all(hasattr(g, "locate") for g in grids):
            return None
        return tuple(leaf_size(g, spacing) for g, (_, spacing) in zip(grids, self.grids))

    def sample_edges(self, s: np.ndarray, axis: np.ndarray, a: float) -> tuple[np.ndarray, np.ndarray]:
        """(inside, distance beyond the edge along the ray from the centre) of samples."""
        r = self.polar(s + self.centre, a)[0]
        length = np.hypot(s[:, 0], s[:, 1])
        return r <= 1.0, length * (1.0 - 1.0 / np.maximum(r, 1e-300))

    # -------------------------------------------------- the formulation protocol

    def next_region(self, a: float, load_ratio: float) -> float:
        # a line contact's width grows as sqrt(load); a flat contact's radius less than a sphere's
        return max(a * load_ratio ** (1.0 / 3.0 if self.isotropic else 0.5), 2.0 * self.h)

    def region_search(self, a0: float, final: bool, max_iterations: int, estimate: bool = False):
        if self.whole_face is not None:
            return self._holding_search()
        tol = settling_tolerance(self.options, self.h, final)
        return edge_search(a0, self.h, tol, self.largest_size(), step0=0.05 * self.h if estimate else None)

    def largest_size(self) -> float:
        """The largest size a whose region lies in the cells prepared for the contact: on
        SIZE_ANGLES rays in body 1's sectors, the centre's offset plus the ray's length to the
        region's edge, or to body 1's free edge where that is nearer, at most the extent plus
        PREPARED_REACH of the finest cell (the prepared cells hold the candidate disc's points and
        those that far from them). A line contact's length A is fixed, so its rectangle's corners
        reach sqrt(A^2 + B^2) (times rho): bounding B rho by the extent alone let a trial leave
        the prepared cells."""
        room = max(self.extent + PREPARED_REACH * self.h - float(np.hypot(*self.centre)), 0.0)
        upper = max(self.extent - float(np.abs(self.centre).max()), 0.0) / float(np.exp(self.log_rho.max()))
        phi = np.linspace(0.0, 2.0 * math.pi, SIZE_ANGLES, endpoint=False)
        phi = phi[knots_inside(phi, self.ranges)]
        if not len(phi):
            return upper

        if self._prepared_edges is None:  # body 1's free edges as far as the prepared cells reach
            psi, ends = free_edge_distance(self.solids[0], self.frame, self.ranges, self.reach,
                                           self.extent + PREPARED_REACH * self.h, self.h)
            self._prepared_edges = psi, _nearest_inside(ends)

        def fits(a: float) -> bool:
            aa, bb = self.semi_axes(a)
            direction = np.stack([aa * np.cos(phi), bb * np.sin(phi)], axis=1)
            ray = self.rho(phi) * np.hypot(direction[:, 0], direction[:, 1])
            psi, ends = self._prepared_edges
            k = np.rint(np.mod(np.arctan2(direction[:, 1], direction[:, 0]), 2.0 * math.pi) / (2.0 * math.pi)
                        * len(psi)).astype(int) % len(psi)
            return bool(np.minimum(ray, np.where(ends[k] > 0.0, ends[k], np.inf)).max() <= room)

        if fits(upper):
            return upper
        lo, hi = 0.0, upper
        while hi - lo > 1e-9 * upper:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if fits(mid) else (lo, mid)
        return lo

    def _update_centre(self, x: np.ndarray, a: float, info, final: bool) -> bool:
        """A whole face's centre stays where it was set up (its samples' centroid: the region holds
        the whole face about any centre, and a centre that followed the pressure's centroid moved
        the quadrature's panels and so the centroid again: a rigid annular punch's centre swung
        by 1e-5 m, above the final tolerance, for 30 solves); any other region's follows the
        pressure."""
        return True if self.whole_face is not None else super()._update_centre(x, a, info, final)

    def _holding_search(self):
        """The size search of a whole face in complete contact: the one size whose region (about
        its present centre) holds every sample of the face, with one sample's spacing to spare
        (the face's edge lies between its last sample and the next; beyond it body 1 has no
        surface and the quadrature drops its points)."""
        a = float(self.polar(self.whole_face, 1.0)[0].max()) + self.face_spacing
        yield a
        return a, (a, a)

    def region_too_small(self) -> ValueError:
        where = "" if self.isotropic else " across the line"
        return CandidateRegionExceeded(self.model.bodies, "refinement radius", (
            f"{self.name}: the contact region reaches the candidate region's edge ({self.extent:.4g} m){where} and "
            "still penetrates; enlarge the contact refinement radius"))

    def judge(self, x: np.ndarray, a: float, info):
        gap, pressure, inside, edge_dist = _sample_state(self, x, a)
        v = _judge(self, gap, pressure, inside, edge_dist)
        self.knot_moments = self._moments(info, x, a)
        smooth = ~self.free_knots & np.isfinite(self.knot_moments) & knots_inside(self.knots, self.ranges)
        # the smooth knots' moments pooled by their pressure (a knot whose stretch carries little
        # pressure has a normalised moment dominated by noise: it must not steer the size)
        v.edge = self._pooled(smooth)
        v.edges = (v.edge, v.edge)
        # the overlap's reach beyond the region: across the line, or from the centre (a flat contact)
        over = (gap < 0.0) & ~inside & ((self.sample_axis == 1) | self.isotropic)
        local = self.local(self.samples.s)[over]
        reach = np.hypot(local[:, 0], local[:, 1]) if self.isotropic else np.abs(local[:, 1])
        v.overlap = float(reach.max()) if over.any() else math.nan
        return v

    def _pooled(self, smooth: np.ndarray) -> float:
        """The knots' edge moment pooled over the ``smooth`` ones by their pressure (-inf without)."""
        moment, total = self._raw_moments
        pool = float(total[smooth].sum()) if smooth.any() else 0.0
        return float(moment[smooth].sum()) / pool if pool > 0.0 else -math.inf

    def _moments(self, info, x: np.ndarray, a: float) -> np.ndarray:
        """Each knot's edge moment (nan where its stretch has no points; -inf where it carries net
        tension, or without a region); also marks the knots whose ray ends at body 1's free edge. On a ray that ends at
        a free edge, r is measured to the free edge: there the moment tells whether the pressure
        still grows towards the edge (complete contact, >= 0) or falls to zero before it (< 0)."""
        if info is None or a <= 0.0:
            return np.full(len(self.knots), -math.inf)
        pts = info[0]
        p = np.einsum("qi,qi->q", _quadrature_traction(self, info, x), pts.normal)
        r, phi = self.polar(pts.s, a)
        to_end = r / np.minimum(1.0, self.end_radius(phi, a))
        hat = _hats(self.knots, phi)  # (q, K)
        wp = (plane_weights(self, pts) * p)[:, None] * hat
        total = wp.sum(axis=0)
        # free: the knot's ray ends at body 1's free edge (outside body 1's sectors: no edge at all)
        self.free_knots = (self.end_radius(self.knots, a) < 1.0) | ~knots_inside(self.knots, self.ranges)
        if self.whole_face is not None:  # complete contact all round: no edge condition anywhere
            self.free_knots = np.ones(len(self.knots), dtype=bool)
        reach = self.ray_length(phi, a) * np.minimum(1.0, self.end_radius(phi, a))
        moment = np.where(self.free_knots, (wp * _edge_weight(to_end, reach, self.h)[:, None]).sum(axis=0),
                          (wp * _edge_weight(r, reach, self.h)[:, None]).sum(axis=0))
        covered = hat.sum(axis=0) > 0.0
        across = self.across & ~self.free_knots
        if across.any():  # a long region's sides: the 2D edge condition on its sections
            aa, bb = self.semi_axes(a)
            local = self.local(pts.s) / np.array([aa, bb])
            knot_xy = self.edge_points(self.knots)
            m, w, cover = section_moments(local, plane_weights(self, pts) * p, knot_xy,
                                          self.whole_boundary(a), across)
            moment, total, covered = np.where(across, m, moment), np.where(across, w, total), np.where(across, cover, covered)
        self._raw_moments = (moment, total)
        out = np.full(len(self.knots), math.nan)
        ok = total > 0.0
        out[ok] = moment[ok] / total[ok]
        out[(total < 0.0) & covered] = -math.inf  # net tension: the region too large there
        return out

    def _tied(self, m: np.ndarray, smooth: np.ndarray, a: float) -> np.ndarray:
        """The knots' edge moments ``m`` with each run of neighbouring ``smooth`` knots whose edge
        points lie within TIE_CELLS finest cells of each other given their run's moment, pooled by
        pressure (the sum of their moments over the sum of their pressures' integrals): at a long
        region's tips the normalised coordinates crowd several knots into a cell, whose
        stretches the grid cannot tell apart. Tied knots then move together."""
        chord = self.knot_chords(a)  # knot k to k + 1
        link = smooth & np.roll(smooth, -1) & (chord < TIE_CELLS * self.h)
        if not link.any():
            return m
        n = len(m)
        start = np.roll(~link, 1)  # knot k starts a run unless linked from k - 1
        if not start.any():
            start[0] = True
        label = np.cumsum(start) - 1
        label[label < 0] = label[-1]  # the run through the last knot continues at the first
        moment, total = self._raw_moments
        g_moment = np.bincount(label, weights=np.where(smooth, moment, 0.0), minlength=n)
        g_total = np.bincount(label, weights=np.where(smooth, total, 0.0), minlength=n)
        size = np.bincount(label, weights=smooth.astype(float), minlength=n)
        tied = smooth & (size[label] > 1) & (g_total[label] > 0.0)
        return np.where(tied, g_moment[label] / np.where(g_total[label] > 0.0, g_total[label], 1.0), m)

    def across_knots(self, a: float) -> np.ndarray:
        """(K,) the knots of a line contact where the region's edge runs within SIDE_ANGLE of the
        line (axis 0), in the tangent plane's lengths: a long region's sides, whose width changes
        slowly along the line, read on sections across it (none for a flat contact, nor on the
        line itself)."""
        return self._edge_slope(a) <= math.tan(SIDE_ANGLE)

    def _edge_slope(self, a: float) -> np.ndarray:
        """(K,) the tangent of the angle between the region's edge at each knot and the line, in
        the tangent plane's lengths (inf on a flat contact, and at a knot on the line itself: a
        tip of the region has no side to read)."""
        if self.isotropic:
            return np.full(len(self.knots), math.inf)
        aa, bb = self.semi_axes(a)
        rho = self.rho(self.knots)
        slope = self._spline[1](self.knots, 1)  # d log rho / d phi
        cos, sin = np.cos(self.knots), np.sin(self.knots)
        along = np.abs(rho * aa * (slope * cos - sin))  # the edge's tangent along axis 0
        across = np.abs(rho * bb * (slope * sin + cos))
        ratio = across / np.where(along > 0.0, along, 1e-300)
        # the sections under a knot's hat span its neighbours' stations: with a neighbour within a
        # cell along the line (an edge that turns across it there) they cannot read its edge
        x = rho * aa * cos
        near = np.minimum(np.abs(np.roll(x, 1) - x), np.abs(np.roll(x, -1) - x)) < self.h
        return np.where((np.abs(sin) > 1e-6) & ~near, ratio, math.inf)

    def whole_boundary(self, a: float, n: int = 1440) -> np.ndarray:
        """(m, 2) the whole region's edge in the normalised coordinates (X, Y): the spline's edge
        within body 1's sectors with its mirror images across a symmetric model's symmetry planes
        (the spline outside the sectors is only a placeholder); the whole spline otherwise."""
        aa, bb = self.semi_axes(a)
        phi = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
        s = self.rho(phi)[:, None] * np.stack([aa * np.cos(phi), bb * np.sin(phi)], axis=1)
        maps = mirror_images(self.ranges)
        if len(maps) > 1:
            s = s[knots_inside(np.arctan2(s[:, 1], s[:, 0]), self.ranges)]
            s = np.einsum("mij,qj->mqi", maps, s).reshape(-1, 2)
        return s / np.array([aa, bb])

    def update_stick_and_shape(self, x: np.ndarray, a: float, info, final: bool = True) -> bool:
        """After a size search: the centre (as the ellipse), then each knot with a smooth edge
        moved by a secant on its moment less the mean; True when they agree to KNOT_TOLERANCE."""
        if not self._update_centre(x, a, info, final):
            return False
        stuck = self._update_stick(x, a, info) if self.kind == "frictional" and info is not None else True
        if info is None or a <= 0.0:
            return stuck
        m = self._moments(info, x, a)
        if self.whole_face is not None:  # a whole face: its region's shape is the face's own
            return stuck
        inside = knots_inside(self.knots, self.ranges)
        tense = inside & (m == -math.inf)
        if tense.any():  # a stretch of the edge in net tension: the region is too large there
            self.log_rho[tense] -= KNOT_STEP
            self._mirror_outside()
            self._restart_secants()
            self._classify(a)
            return False
        retreat = self.free_knots & inside & np.isfinite(m) & (m < -END_MOMENT)
        if retreat.any():  # the pressure ends before the free edge there: a smooth edge, just inside it
            self.log_rho[retreat] += np.log(0.97 * self.end_radius(self.knots[retreat], a))
            self._mirror_outside()
            self._classify(a)
            return False
        smooth = ~self.free_knots & np.isfinite(m) & inside
        if not smooth.any():
            return stuck
        m = self._tied(m, smooth, a)
        d = np.where(smooth, m - self._pooled(smooth), 0.0)
        self._knot_history.append((self.log_rho.copy(), d))
        if self._before_split is not None:  # knots were inserted: they agree again, or are undone
            if float(np.abs(d).max()) <= KNOT_TOLERANCE:
                self._before_split = None
            elif self._undo_split(a):
                return False
        if float(np.abs(d).max()) <= KNOT_TOLERANCE and (self.spread_knots(a) or self.refine_knots(x, a, info)):
            return False
        if float(np.abs(d).max()) <= KNOT_TOLERANCE:
            return stuck
        step = 0.5 * d  # the first update: rho up where the edge is punch-like (d > 0)
        if len(self._knot_history) >= 2:  # then a secant per knot where rho up made its moment fall
            (l0, d0), (l1, d1) = self._knot_history[-2], self._knot_history[-1]
            change = d1 - d0
            slope = (l1 - l0) / np.where(np.abs(change) > 1e-12, change, np.inf)
            # a knot whose reading changed since the older entry has no secant yet
            valid = self._knot_since <= len(self._knot_history) - 2
            step = np.where((slope < 0.0) & valid, -d1 * slope, step)
            # a secant through two noisy moments can be nearly flat and send the edge far: no step
            # beyond SECANT_GAIN times the moment's difference (a section's moment falls by about
            # 1.1 to 1.3 per unit of log width, Hertz's pressure read on a region 1 to 2 % off)
            step = np.clip(step, -SECANT_GAIN * np.abs(d1), SECANT_GAIN * np.abs(d1))
        cap = np.minimum(KNOT_STEP, STEP_CELLS * self.h / np.maximum(self.ray_length(self.knots, a), 1e-300))
        self.log_rho = self.log_rho + np.where(smooth, np.clip(step, -cap, cap), 0.0)
        self._mirror_outside()
        self._classify(a)
        return False

    def refine_knots(self, x: np.ndarray, a: float, info) -> bool:
        """Once the knots nearly agree: insert knots where the edge condition asks for them (True:
        the shape is updated again). A knot is tried midway (in phi) between each two neighbours
        with a smooth edge within body 1's sectors whose edge points lie more than SPLIT_CELLS
        cells apart, and at the quarter points where they lie more than twice that apart: its edge moment is read in the present state with the hats of the refined
        knots. Where it differs from their pooled mean by more than SPLIT_MOMENT, the edge
        between the two knots is not where the pressure puts it (a bulge the spline rounds off,
        next to a crowned roller's crown), and the knot is inserted on the present edge (up to
        MAX_KNOTS). A region whose edge its knots already resolve (a circle, a straight side)
        keeps them, and so its shape and its cost. A flat contact keeps its 24 knots: at equal
        angles they lie evenly along an edge of aspect about 1 (on the rounded punch, two knots
        inserted by the pressure's noise at its edge moved the radius from +0.17 % to +1.08 % of
        the closed form's). The secants start again, and the load step may
        take SPLIT_UPDATES more shape updates (``extra_shape_updates``), at most MAX_SPLITS times."""
        inside = knots_inside(self.knots, self.ranges)
        turn = 2.0 * math.pi
        gap = (np.roll(self.knots, -1) - self.knots) % turn
        mid = np.mod(self.knots + 0.5 * gap, turn)
        chord = self.knot_chords(a)
        cells = self.edge_cells(mid, a)
        smooth = inside & ~self.free_knots
        candidate = (smooth & np.roll(smooth, -1) & knots_inside(mid, self.ranges) & (chord > SPLIT_CELLS * cells)
                     & (gap < math.pi))
        if (self.isotropic or not candidate.any() or len(self.knots) >= MAX_KNOTS
                or self.extra_shape_updates >= MAX_SPLITS * SPLIT_UPDATES):
            return False
        # on a stretch long enough for halves of two cells, the quarter points too: a bulge between
        # two knots whose midpoint reads both of its sides shows at one of them
        long = candidate & (chord > 2.0 * SPLIT_CELLS * cells)
        quarters = np.mod(np.concatenate([self.knots[long] + f * gap[long] for f in (0.25, 0.75)]), turn)
        trial = np.concatenate([self.knots, mid[candidate], quarters])
        order = np.argsort(trial, kind="stable")
        trial_rho = np.log(self.rho(trial))
        new = (np.arange(len(trial)) >= len(self.knots))[order]
        kept = (self.knots, self.log_rho, self.across, self.free_knots, self._raw_moments)
        self.knots, self.log_rho = trial[order], trial_rho[order]
        self.across = self.across_knots(a)
        m = self._moments(info, x, a)
        ok = ~self.free_knots & np.isfinite(m) & knots_inside(self.knots, self.ranges)
        split = new & ok & (np.abs(m - self._pooled(ok)) > SPLIT_MOMENT)
        self.knots, self.log_rho, self.across, self.free_knots, self._raw_moments = kept
        split &= np.cumsum(split) <= MAX_KNOTS - len(self.knots)
        if not split.any():
            return False
        self._insert(trial[order][new & split], a)
        return True

    def spread_knots(self, a: float) -> bool:
        """Once per load step, when the knots first agree: knots spread along a line contact's
        edge (True: the shape is updated again). The knots start at equal angles in the
        normalised coordinates, which crowds them at a long region's tips and leaves its sides
        few (on the crowned roller, two knots over the 58 mm of side before the crown's bulge):
        between them the spline's edge is an interpolation the edge conditions do not see, and
        each side knot's section moment averages the sections over its whole stretch, so its
        own edge point settles wherever the stretch's error averages out (the mid-length width
        moved by 5 % when knots were inserted elsewhere on the side). Each stretch of a smooth
        edge between two knots longer than SPREAD_CELLS of the grid's cells it crosses (the
        largest of them, ``edge_cells``) along the edge is
        therefore cut into equal lengths of at most that, new knots at the cuts on the present
        edge (the shape is unchanged by the insertion), so that the spline's edge everywhere is
        within a cell or so of a knot whose edge condition holds. A flat contact keeps its 24
        knots (see ``refine_knots``)."""
        if self.isotropic or self._spread or len(self.knots) >= MAX_KNOTS:
            return False
        self._spread = True
        turn = 2.0 * math.pi
        gap = (np.roll(self.knots, -1) - self.knots) % turn
        smooth = knots_inside(self.knots, self.ranges) & ~self.free_knots
        candidate = (smooth & np.roll(smooth, -1) & (gap < math.pi)
                     & knots_inside(np.mod(self.knots + 0.5 * gap, turn), self.ranges))
        new = []
        for k in np.flatnonzero(candidate):
            phi = self.knots[k] + gap[k] * np.linspace(0.0, 1.0, 129)
            edge = self.edge_points(phi, a)
            arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(edge, axis=0).T))])
            n = int(math.ceil(arc[-1] / (SPREAD_CELLS * float(self.edge_cells(phi, a).max())) - 1e-9))
            new.extend(np.interp(arc[-1] * np.arange(1, n) / n, arc, phi))
        new = np.mod(np.array(new[:max(MAX_KNOTS - len(self.knots), 0)]), turn)
        if not len(new):
            return False
        self._insert(new, a)
        return True

    def _insert(self, new: np.ndarray, a: float) -> None:
        """Insert knots at the angles ``new`` on the present edge; the secants start again, the
        load step may take SPLIT_UPDATES more shape updates, and the knots before are kept to
        undo the insertion (``_undo_split``)."""
        before = (self.knots.copy(), self.log_rho.copy())
        trial = np.concatenate([self.knots, new])
        order = np.argsort(trial, kind="stable")
        old = (np.arange(len(trial)) < len(self.knots))[order]
        self.knots, self.log_rho = trial[order], np.log(self.rho(trial[order]))
        free = np.zeros(len(self.knots), dtype=bool)
        free[old] = self.free_knots
        self.free_knots, self.knot_moments = free, np.full(len(self.knots), math.nan)
        self.across = self.across_knots(a)
        self._restart_secants()  # every knot's hat has changed: the secants start again
        self.extra_shape_updates += SPLIT_UPDATES
        self._before_split = (before[0], before[1], 0)

    def _undo_split(self, a: float) -> bool:
        """Count a shape update after an insertion; after SPLIT_SETTLE of them without the knots
        agreeing, restore the knots before it (they had agreed): True then."""
        knots, log_rho, updates = self._before_split
        if updates + 1 < SPLIT_SETTLE:
            self._before_split = (knots, log_rho, updates + 1)
            return False
        self.knots, self.log_rho = knots, log_rho
        self.free_knots, self.knot_moments = np.zeros(len(knots), dtype=bool), np.full(len(knots), math.nan)
        self.across = self.across_knots(a)
        self._restart_secants()
        self._before_split = None
        self.extra_shape_updates = MAX_SPLITS * SPLIT_UPDATES  # no more insertions in this step
        return True

    def _classify(self, a: float) -> None:
        """Fix which knots are read on sections (``across_knots``) until the next shape update,
        with hysteresis: a knot read on sections keeps that reading until its edge turns beyond
        SIDE_ANGLE_LEAVE from the line. A knot that changes its reading starts its own secant
        again (the others keep theirs: their moments are read as before)."""
        slope = self._edge_slope(a)
        across = np.where(self.across, slope <= math.tan(SIDE_ANGLE_LEAVE), slope <= math.tan(SIDE_ANGLE))
        self._knot_since = np.where(across != self.across, len(self._knot_history), self._knot_since)
        self.across = across

    def _restart_secants(self) -> None:
        """Every knot's secant starts again (its hat or its place has changed)."""
        self._knot_history = []
        self._knot_since = np.zeros(len(self.knots), dtype=int)

    def _mirror_outside(self) -> None:
        """Knots outside body 1's angular ranges (a symmetric model) take the value of the nearest
        knot inside, which keeps the spline flat across the symmetry plane."""
        inside = knots_inside(self.knots, self.ranges)
        if inside.all() or not inside.any():
            return
        gaps = np.abs((self.knots[:, None] - self.knots[None, inside] + math.pi) % (2.0 * math.pi) - math.pi)
        self.log_rho[~inside] = self.log_rho[inside][np.argmin(gaps[~inside], axis=1)]

    def start_step(self) -> None:
        super().start_step()
        self._restart_secants()
        self.extra_shape_updates = 0
        self._before_split = None
        self._spread = False

    def history_entry(self, v, a: float, step: int, iteration: int, tag: int, ratio: float) -> None:
        super().history_entry(v, a, step, iteration, tag, ratio)
        self.history[-1]["knot_rho"] = np.exp(self.log_rho).tolist()
        if len(self.knots) != KNOTS:  # knots inserted (refine_knots): their angles
            self.history[-1]["knot_phi"] = self.knots.tolist()

    def check_final(self, u: np.ndarray, a: float, info, bracket, block: dict) -> list[str]:
        messages = super().check_final(u, a, info, bracket, block)
        m = self._moments(info, u[self.dofs], a)
        smooth = ~self.free_knots & np.isfinite(m) & knots_inside(self.knots, self.ranges)
        if smooth.any():
            m = self._tied(m, smooth, a)
        spread = float(np.abs(m[smooth] - self._pooled(smooth)).max()) if smooth.any() else 0.0
        if spread > 2.0 * KNOT_TOLERANCE:
            messages.append(f"{self.name}: the region's shape did not settle (its knots' edge moments differ from "
                            f"their mean by up to {spread:.3g})")
        block["checks"]["knot_moments"] = [None if not np.isfinite(v) else float(v) for v in m]
        if self.whole_face is not None:
            outside = self.whole_face_uncovered(a)
            block["checks"]["face_samples_outside_region"] = int(len(outside))
            if len(outside):
                far = outside[np.argmax(np.hypot(outside[:, 0], outside[:, 1]))]
                messages.append(f"{self.name}: the region does not hold the whole face, which is not star-shaped about "
                                f"the contact point ({len(outside)} of its samples outside the region, the farthest "
                                f"{float(np.hypot(*far)):.4g} m from the point): such a face is taken whole in "
                                "complete contact only; a partial contact on it is not supported")
        return messages

    def whole_face_uncovered(self, a: float) -> np.ndarray:
        """(m, 2) the whole face's samples (``whole_face``) outside the region r <= 1."""
        return self.whole_face[self.polar(self.whole_face, a)[0] > 1.0]

    def summary_block(self, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
        from .region_report import region_block

        block = region_block(self, a, on2, u, info)
        if self.whole_face is not None:
            self._whole_face_report(block)
        return block

    def _whole_face_report(self, block: dict) -> None:
        """A whole face's region in the summary: its boundary the face's own edges (its samples
        beside a gap or its outline, to a sample's spacing; all free edges), its half-extents
        along the frame's axes from the contact point and its spans along the principal
        directions read off them (the region's circle about its centre, which the report draws
        otherwise, reaches beyond the face)."""
        x, ok = surface_point(self.solids[0], self.frame, self.face_edges, self.reach)
        edges = self.face_edges[ok]
        half = [float(np.abs(edges[:, k]).max()) for k in (0, 1)]
        directions = np.asarray(block["principal_directions"]) @ self.frame.axes.T
        span = edges @ directions.T
        block.update({"boundary": {"points": x[ok].tolist(), "free_edge": [True] * int(ok.sum())},
                      "semi_axes": half, "cells_per_semi_axis": [v / self.h for v in half],
                      "extents": (span.max(axis=0) - span.min(axis=0)).tolist(), "complete_contact": True})


def _edge_weight(r: np.ndarray, reach: np.ndarray, h: float) -> np.ndarray:
    """The edge moment's weight along a ray of physical length ``reach``, at the normalised radii
    r (1 at the edge): 5/2 (3T/5 - t) / T^(3/2) on the window t = 1 - r^2 <= T next to the edge,
    0 inside it. For Q(r) / sqrt(1 - r^2) with Q = q0 + q2 r^2 its moment in r dr is
    2/3 (q0 + q2) for every T (int_0^T t^(-1/2) (3T/5 - t) dt / 2 = 4/15 T^(3/2)), so only the
    window sees the pressure. The window spans the last EDGE_WINDOW_CELLS cells of the ray (the
    whole ray, T = 1 and the weight 5/2 r^2 - 1, when it is shorter): a pressure that is not
    Hertzian further inside (a crowned roller's peak where the crown starts) does not bias the
    edge."""
    inner = np.clip(1.0 - EDGE_WINDOW_CELLS * h / np.maximum(reach, 1e-300), 0.0, None)
    T = 1.0 - np.minimum(inner, 1.0) ** 2
    t = 1.0 - r**2
    return np.where(t <= T, 2.5 * (0.6 * T - t) / T**1.5, 0.0)


def section_edges(boundary: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) edges Y of the region's sections across the line at the stations X, read
    off the closed ``boundary`` (m, 2) in the coordinates (X, Y): its parts on either side of the
    line, each as a function of X (a region whose sides each cross a section once)."""
    def side(part: np.ndarray) -> np.ndarray:
        order = np.argsort(part[:, 0], kind="stable")
        return np.interp(X, part[order, 0], part[order, 1])

    upper, lower = boundary[boundary[:, 1] > 0.0], boundary[boundary[:, 1] < 0.0]
    up = side(upper) if len(upper) else np.zeros(len(X))
    return (side(lower) if len(lower) else -up), up


def section_moments(local: np.ndarray, wp: np.ndarray, knot_xy: np.ndarray, boundary: np.ndarray,
                    which: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(moment, pressure, covered) per knot (K,) of the 2D edge condition on the sections across
    the line, for the knots ``which`` (0 elsewhere). Points at (X, Y) = ``local`` (q, 2) carry
    the weighted pressures ``wp`` (pressure times area). A section at the station X runs across
    the whole region from its lower edge to its upper one (``section_edges``); t = (Y - centre) /
    half-width on it. A plane-strain contact's pressure there is Q(t) / sqrt(1 - t^2) with
    Q = q0 + q2 t^2 (Hertz's p0 sqrt(1 - t^2): Q(1) = 0), and from the centre to an edge

        int_0^1 Q(t) / sqrt(1 - t^2) (4 t^2 - 1) dt = pi / 2 (q0 + q2)

    (int_0^1 dt / sqrt(1 - t^2) = pi / 2, of t^2: pi / 4, of t^4: 3 pi / 16): zero exactly at a
    smooth edge, whatever the section's load. The weight is 2/3 (4 t^2 - 1), so that a flat
    punch's edge (Q = q0) gives 2/3 of its pressure's integral, as the rays' moment does. A knot
    takes the sections on its side of the line under its hat in X (1 at its edge point's
    station, 0 at its neighbours'): each section is read whole, whatever the pressure does along
    the line (a crown's peak)."""
    X, Y = local[:, 0], local[:, 1]
    lower, upper = section_edges(boundary, X)
    half = 0.5 * (upper - lower)
    t = np.clip((Y - 0.5 * (upper + lower)) / np.where(half > 0.0, half, np.inf), -1.0, 1.0)
    k = np.flatnonzero(which)
    xs = knot_xy[:, 0]
    left, right = xs[(k - 1) % len(xs)], xs[(k + 1) % len(xs)]
    lo, hi = np.minimum(left, right), np.maximum(left, right)
    spread = np.maximum(np.abs(left - xs[k]), np.abs(right - xs[k]))
    bad = ~((lo < xs[k]) & (xs[k] < hi))  # neighbours on one side: a symmetric hat
    lo, hi = np.where(bad, xs[k] - spread, lo), np.where(bad, xs[k] + spread, hi)
    d = X[:, None] - xs[None, k]
    hat = np.clip(np.where(d < 0.0, 1.0 + d / (xs[k] - lo), 1.0 - d / (hi - xs[k])), 0.0, None)
    hat *= (t[:, None] * np.sign(knot_xy[None, k, 1])) > 0.0  # the knot's side of the line
    moment, total, covered = np.zeros(len(xs)), np.zeros(len(xs)), np.zeros(len(xs), dtype=bool)
    moment[k] = (wp * (2.0 / 3.0) * (4.0 * t**2 - 1.0)) @ hat
    total[k] = wp @ hat
    covered[k] = hat.sum(axis=0) > 0.0
    return moment, total, covered


def _hats(knots: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(q, K) periodic hat functions of the ascending knots in [0, 2 pi) at the angles phi: 1 at
    its knot, falling linearly to 0 at the neighbouring knots (they sum to 1)."""
    turn = 2.0 * math.pi
    phi = np.mod(phi, turn)
    ext = np.append(knots, knots[0] + turn)
    k = np.searchsorted(ext, phi, side="right") - 1  # the interval [ext[k], ext[k + 1]) holding phi
    below = k < 0  # before the first knot: the interval from the last knot across 2 pi
    k = np.where(below, len(knots) - 1, k)
    lo = np.where(below, knots[-1] - turn, ext[k])
    share = (phi - lo) / (ext[k + 1] - ext[k])
    out = np.zeros((len(phi), len(knots)))
    rows = np.arange(len(phi))
    out[rows, k] += 1.0 - share
    out[rows, (k + 1) % len(knots)] += share
    return out


#: angles this close to a sector's edge (radians) count as inside it: a symmetric model's
#: symmetry plane through the contact point, whose angle in the frame carries the frame's round-off
#: (2e-8 rad measured on a revolved B-spline roller)
SECTOR_SLACK = 1e-6


def knots_inside(knots: np.ndarray, ranges) -> np.ndarray:
    inside = np.zeros(len(knots), dtype=bool)
    for t0, t1 in ranges:
        inside |= (knots - t0 + SECTOR_SLACK) % (2.0 * math.pi) <= (t1 - t0) + 2.0 * SECTOR_SLACK
    return inside


def _filled_outside(distance: np.ndarray) -> np.ndarray:
    """The free edge's distance per ray, the rays outside body 1's sectors (distance 0) given
    their nearest inside ray's: the region's points and boundary on a sector's edge (a symmetry
    plane) look up the ray nearest them, which may fall just outside."""
    inside = np.flatnonzero(distance > 0.0)
    if not len(inside) or len(inside) == len(distance):
        return distance
    n = len(distance)
    gap = np.abs(np.arange(n)[:, None] - inside[None, :])
    nearest = inside[np.argmin(np.minimum(gap, n - gap), axis=1)]
    return np.where(distance > 0.0, distance, distance[nearest])


#: the smaller relative curvature at most this share of the larger: an elongated contact, which
#: takes the region of general shape where body 1 ends along it (Hertz's ellipse for this ratio is
#: about 2.5 times longer than wide)
ELONGATED_RATIO = 0.25


def reaches_free_end(solid1, frame, ranges, reach: float, extent: float, h: float) -> bool:
    """Whether a contact with two positive relative curvatures, the one along axis 0 at most
    ELONGATED_RATIO of the other, lies on a body 1 that ends along axis 0 within the candidate
    region (a roller's end face): such a contact (a crowned roller) grows along the line under
    load until its gap there is no longer quadratic, which Hertz's ellipse assumes, and may reach
    the end. It takes the region of general shape, as a line contact."""
    k0, k1 = (float(k) for k in frame.curvatures)
    if not (k1 > 0.0 and 0.0 < k0 <= ELONGATED_RATIO * k1):
        return False
    psi, distance = free_edge_distance(solid1, frame, ranges, reach, extent, h)
    near = (np.abs(np.sin(psi)) <= 0.1) & (distance > 0.0)
    return bool(near.any() and np.isfinite(distance[near]).all())


def configure_star_region(c: StarRegionContact) -> StarRegionContact:
    """Set up a region of general shape: a flat contact (both relative curvatures 0) or a line
    contact."""
    return configure_flat_contact(c) if is_flat_contact(c.frame, c.extent) else configure_line_contact(c)


def configure_flat_contact(c: StarRegionContact) -> StarRegionContact:
    """A flat contact: the scales A = B both the size the search finds, the first edge a circle
    (rho = 1), body 1's free edges located as for a line contact (a punch's sharp corner ends the
    region there: complete contact)."""
    psi, t, ok, height = face_rays(c.solids[0], c.frame, c.reach, c.extent, EDGE_RAYS)
    inside = _inside_rays(psi, c.ranges)
    face = on_face(ok, height, c.h)
    if resumed_rays(t, face, inside)[0].any():
        c.whole_face, c.face_spacing = _whole_face(c, psi, t, ok, face, inside), float(t[1] - t[0])
        if c.centred:  # the face's centroid (the samples on the rays weighted by their area, r dr dpsi)
            c.centre = np.average(c.whole_face, axis=0, weights=np.hypot(*c.whole_face.T))
    c.edge_psi, distance = _edge_distance(c.solids[0], c.frame, c.reach, c.h, psi, t, ok, inside)
    c.edge_distance = _filled_outside(distance)
    c.isotropic = True
    c.log_rho = np.zeros(len(c.knots))
    c.ratio = 1.0
    c.circular = False
    return c


def _whole_face(c: StarRegionContact, psi: np.ndarray, t: np.ndarray, ok: np.ndarray, face: np.ndarray,
                inside: np.ndarray) -> np.ndarray:
    """The samples (m, 2) of a flat face that is not star-shaped about the contact point (a ray
    leaves the face and enters it again: a hole, a notch), to be taken whole in complete contact:
    only where the candidate region holds the whole face (no ray still on the face at its last
    sample) and every gap in it is open (no surface there: a recess's floor would be in the
    region's quadrature). Refused otherwise, naming the ray with the widest gap."""
    resumed, leaves, returns = resumed_rays(t, face, inside)
    last = np.where(face.any(axis=1), face.shape[1] - 1 - np.argmax(face[:, ::-1], axis=1), -1)
    before_last = np.arange(face.shape[1])[None, :] < last[:, None]
    recess = inside & (ok & ~face & before_last).any(axis=1)
    held = not (face[:, -1] & inside).any()
    if held and not recess.any():
        direction = np.stack([np.cos(psi), np.sin(psi)], axis=1)
        s = t[None, :, None] * direction[:, None, :]
        beside = np.zeros(face.shape, dtype=bool)
        beside[:, 1:] |= face[:, 1:] & ~face[:, :-1]
        beside[:, :-1] |= face[:, :-1] & ~face[:, 1:]
        c.face_edges = s[beside & inside[:, None]]
        return s[face & inside[:, None]]
    k = int(np.argmax(np.where(resumed, returns - leaves, -math.inf)))
    direction = math.cos(psi[k]) * c.frame.axes[0] + math.sin(psi[k]) * c.frame.axes[1]
    why = (_face_beyond(c, t[1] - t[0]) if not held else
           "a recess in the face (surface above it within a gap: a blind hole, a groove)")
    raise ValueError(
        f"{c.name}: body 1's flat face is not star-shaped about the contact point "
        f"{np.round(c.frame.point, 6).tolist()}: on {int(resumed.sum())} of {int(inside.sum())} rays from it within "
        f"the candidate region ({c.extent:.4g} m) the face ends and starts again (along "
        f"{np.round(direction, 4).tolist()}: it ends {leaves[k]:.4g} m from the point and starts again at "
        f"{returns[k]:.4g} m; a hole, a notch or a recess in the face). A flat contact's region is star-shaped "
        "about its centre (each ray from it meets its edge once); such a face is taken only whole, in complete contact, "
        f"where the candidate region holds all of it and its gaps are open holes. Not so here: {why}. "
        "Where the face is star-shaped about another point of it "
        "(an L-shaped punch about a point by its inner corner), give that point; where the parts and the load are "
        "symmetric, model a sector of both bodies (a partial revolution, `sliding` conditions on the cut faces) "
        "narrow enough that its face is star-shaped about a point in its middle (an annulus of inner radius r_i "
        "seen from radius r: a sector narrower than 2 arccos(r_i / r))")


def _face_beyond(c: StarRegionContact, spacing: float) -> str:
    """What to do where a flat face goes on beyond the candidate region: the refinement radius
    whose candidate region would hold the whole face, read on rays out to four times the
    region's radius (or that the face goes on beyond those)."""
    share = float(getattr(getattr(c, "options", None), "extent_fraction", 0.8))
    far = 4.0 * c.extent
    psi, t, ok, height = face_rays(c.solids[0], c.frame, c.reach, far, EDGE_RAYS)
    face = on_face(ok, height, c.h) & _inside_rays(psi, c.ranges)[:, None]
    if face[:, -1].any():
        return (f"the face goes on beyond the candidate region and beyond {far:.4g} m from the point: too large to "
                "be taken whole")
    reach = float(t[np.nonzero(face.any(axis=0))[0].max()]) + max(spacing, t[1] - t[0])
    return (f"the face goes on beyond the candidate region, up to {reach:.3g} m from the point: give the bodies an "
            f"`around = \"contact\"` refinement of radius {reach / share:.3g} m or more, so that the candidate "
            f"region ({share:g} of that radius) holds the whole face")


def _require_straight_line(c: StarRegionContact, length: float | None) -> None:
    """Refuse a line contact whose line curves in the tangent plane (``face_shape.line_bend``):
    by more than BEND_CELLS finest cells over its ``length`` (the free end's distance), or at all
    where it has no free end within the candidate region (None: a closed line, a ring's circle)."""
    bend = line_bend(c.solids[0], c.solids[1], c.frame, c.reach, c.extent if length is None else length, c.h)
    if bend is None:
        return
    kappa, span = bend
    sagitta = 0.5 * abs(kappa) * span**2
    if sagitta <= (ROUND_OFF_BEND if length is None else BEND_CELLS) * c.h:
        return
    where = (f"and does not end within the candidate region ({c.extent:.4g} m from the point): a closed line, "
             "such as the circle of a ring or a torus on a flat" if length is None else
             f"by {sagitta:.3g} m ({sagitta / c.h:.2g} finest cells) from its chord between body 1's free ends "
             f"{length:.4g} m from the point")
    raise ValueError(
        f"{c.name}: the line contact's line along {np.round(c.frame.axes[0], 6).tolist()} curves in the tangent "
        f"plane (radius {1.0 / abs(kappa):.3g} m, read on the valley of the gap within {span:.4g} m of the point) "
        f"{where}. A line contact's region is laid along the straight line through the contact point, so a curved "
        "line is not supported; a plane-strain section across the line (model = \"plane_strain\", the load per "
        "unit length of the line) models it where the line's radius is large against the contact's width")


def configure_line_contact(c: StarRegionContact) -> StarRegionContact:
    """Fix the scale A (body 1's free edge along the line) and the first edge, the rectangle
    rho = min(1 / |sin phi|, 1.15 / |cos phi|) reaching past the free edges."""
    c.edge_psi, distance = free_edge_distance(c.solids[0], c.frame, c.ranges, c.reach, c.extent, c.h)
    c.edge_distance = _filled_outside(distance)
    # the rays within about 6 degrees of the line inside body 1's sectors (a symmetric model's
    # symmetry plane may hold the line itself): the free edge's distance along the line
    near = (np.abs(np.sin(c.edge_psi)) <= 0.1) & (distance > 0.0)
    along = distance[near] * np.abs(np.cos(c.edge_psi[near]))
    ends = bool(len(along)) and bool(np.isfinite(along).all())
    _require_straight_line(c, float(along.max()) if ends else None)
    if not ends:
        raise ValueError(f"{c.name}: a line contact along {np.round(c.frame.axes[0], 6).tolist()} runs beyond the "
                         f"candidate region ({c.extent:.4g} m from the contact point): body 1 has no free end within "
                         "it; enlarge the contact refinement radius to cover the whole line")
    c.length = float(along.max())
    sin, cos = np.abs(np.sin(c.knots)), np.abs(np.cos(c.knots))
    c.log_rho = np.log(np.minimum(1.0 / np.maximum(sin, 1e-12), 1.15 / np.maximum(cos, 1e-12)))
    c.ratio = 1.0
    c.circular = False
    c.across = c.across_knots(c.length)  # the rectangle's sides
    return c
