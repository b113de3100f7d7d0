"""Resolution of what a scene leaves implicit, done once before anything is discretised: the
contact points (given, or the closest points of the two exact boundaries: one search, one
sampling spacing) and the centres of ``around = "contact"`` refinement zones. A 2D contact point at a
convex corner of body 1 (a tilted punch touching at its edge) moves into the edge of body 1 that
faces body 2 (:func:`point_off_corner`): the region then runs from the corner along that edge.
:func:`resolve_problem` returns a :class:`Problem` in which both are explicit; the scene layer
calls it (so the rigid-body check judges the point that is solved), and ``solve`` calls it again
for problems built by hand (a no-op on a resolved one)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .junctions import CORNER_ANGLE, nearest_junction
from .problem import BodyModel, ContactModel, Problem, Sliding, check_problem

__all__ = ["CONTACT_SEARCH_SPACING", "closest_boundary_point", "contact_point", "contact_frame", "resolve_problem",
           "finest_size_at", "corner_distance", "boundary_gap", "refined_maximum", "point_off_corner",
           "CORNER_OFFSET_CELLS", "CORNER_STEEPNESS"]

#: sampling spacing of the closest-point search, as a fraction of the finer element size
CONTACT_SEARCH_SPACING = 0.05
#: a contact point at a convex corner of body 1 moves this many finest cells into the edge facing
#: body 2 (the contact region's corner end is then found by the region search)
CORNER_OFFSET_CELLS = 2.0
#: ... when the corner's other edge is at least this many times as steep against body 2's surface
#: (a tilted flat punch: 2 mrad and 1.57 rad); both edges alike (a wedge) contact on both sides of
#: the corner, which one region along one edge cannot hold: such a point stays refused
CORNER_STEEPNESS = 10.0


def contact_point(problem: Problem, contact: ContactModel) -> np.ndarray:
    """The contact's point: given, or the midpoint of the closest points of the two exact
    boundaries (the deepest point of body 1 when they overlap)."""
    if contact.point is not None:
        p = np.asarray(contact.point, dtype=float)
        if p.shape != (2,) or not np.isfinite(p).all():
            raise ValueError(f"contacts.point must be [x, y], got {contact.point!r}")
        return p
    first = problem.body(contact.bodies[0]).profile
    second = problem.body(contact.bodies[1]).profile
    size = min(problem.body(n).element_size for n in contact.bodies)
    xa = closest_boundary_point(first, second, CONTACT_SEARCH_SPACING * size)
    xb = np.asarray(second.project(xa[None, :]).points[0], dtype=float)
    return 0.5 * (xa + xb)


def contact_frame(problem: Problem, contact: ContactModel) -> tuple[np.ndarray, np.ndarray]:
    """Contact point and the outward unit normal of the second body there."""
    point = contact_point(problem, contact)
    second = problem.body(contact.bodies[1]).profile
    normal = np.asarray(second.project(point[None, :]).normals[0], dtype=float)
    return point, normal / np.linalg.norm(normal)


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def _resolved_body(body: BodyModel, points: list[np.ndarray]) -> BodyModel:
    """Every ``around = "contact"`` zone without a centre becomes one zone per contact point."""
    refs = []
    for k, r in enumerate(body.refinements):
        if r.center is None:
            if not points:
                raise ValueError(
                    f"bodies[{body.name}].refinement[{k}].around is 'contact' but the body has no contact"
                )
            refs += [dataclasses.replace(r, center=_frozen(p)) for p in points]
        else:
            refs.append(r)
    return dataclasses.replace(body, refinements=tuple(refs))


def refined_maximum(f, lo: float, hi: float, tol: float, samples: int = 17) -> float:
    """Parameter of the largest value of the vectorised ``f`` on [lo, hi]: sample, keep the
    neighbours of the best sample, repeat while the values still differ by more than round-off,
    then take the vertex of the parabola fitted to the last samples (a smooth maximum is flat
    to round-off over about sqrt(eps) of the scale: the fit locates it far better than the
    best sample). No scipy.optimize, whose import costs 0.25 s."""
    while hi - lo > tol:
        t = np.linspace(lo, hi, samples)
        v = f(t)
        if hi - lo <= 1e7 * tol:  # about 1e-6 of the scale: still above round-off, fit the vertex
            c2, c1, _ = np.polyfit(t - t[samples // 2], v, 2)
            if c2 < 0.0:
                vertex = t[samples // 2] - c1 / (2.0 * c2)
                if lo <= vertex <= hi:
                    return float(vertex)
        k = int(np.argmax(v))
        lo, hi = t[max(k - 1, 0)], t[min(k + 1, samples - 1)]
    return 0.5 * (lo + hi)


def resolve_problem(problem: Problem) -> Problem:
    """``problem`` with every contact point and every refinement centre explicit."""
    check_problem(problem)
    contacts = tuple(
        c if c.point is not None else dataclasses.replace(c, point=_frozen(contact_point(problem, c)))
        for c in problem.contacts
    )
    bodies = []
    for body in problem.bodies:
        if any(r.center is None for r in body.refinements):
            mine = [np.asarray(c.point, dtype=float) for c in contacts if body.name in c.bodies]
            body = _resolved_body(body, mine)
        bodies.append(body)
    problem = dataclasses.replace(problem, bodies=tuple(bodies))
    return dataclasses.replace(problem, contacts=tuple(_off_corner(problem, c) for c in contacts))


def _off_corner(problem: Problem, contact: ContactModel) -> ContactModel:
    """``contact`` with its point moved off a convex corner of body 1 (``moved_from`` the point
    before), or unchanged."""
    point = np.asarray(contact.point, dtype=float)
    moved = point_off_corner(problem, contact, point)
    if np.array_equal(moved, point):
        return contact
    return dataclasses.replace(contact, point=_frozen(moved), moved_from=_frozen(point))


def point_off_corner(problem: Problem, contact: ContactModel, point: np.ndarray) -> np.ndarray:
    """``point``, or, when it lies within one finest cell of a convex corner of body 1's profile
    (not on a symmetry line: neither edge has a sliding condition), the point CORNER_OFFSET_CELLS
    finest cells from that corner along the flatter of its two edges against body 2's surface (a
    quarter of that edge at most), provided the other is CORNER_STEEPNESS times as steep.
    Unchanged where body 2's boundary has a junction too (a half model cut through the contact)
    and in 3D problems."""
    first, second = (problem.body(n) for n in contact.bodies)
    profile = getattr(first, "profile", None)
    if profile is None or not hasattr(profile, "loops"):
        return point
    h = finest_size_at(first, point)
    if corner_distance(second.profile, point)[0] < finest_size_at(second, point):
        return point  # both bodies end there (a half model's symmetry line): nothing to move into
    symmetry = {bc.edge for bc in problem.boundary_conditions if isinstance(bc, Sliding) and bc.body == first.name}
    j = nearest_junction(profile, point)
    if j is None or not j.distance < h or {j.before.name, j.after.name} & symmetry or j.turn <= CORNER_ANGLE:
        return point  # no corner there, a half model's symmetry corner, or a tangent or concave junction
    n2 = np.asarray(second.profile.project(j.point[None, :]).normals[0], dtype=float)
    # each edge's angle to body 2's surface (the material lies to the left of the tangent)
    angles = [float(np.arccos(np.clip(-(np.array([t[1], -t[0]]) @ n2), -1.0, 1.0))) for t in j.tangents]
    if max(angles) < CORNER_STEEPNESS * min(angles):
        return point  # a wedge: the contact spreads on both sides of the corner
    edge, sign = (j.before, -1.0) if angles[0] <= angles[1] else (j.after, 1.0)
    t0 = float(edge.t_end if sign < 0 else edge.t_start)
    length = float(np.hypot(*np.diff(np.asarray(edge.evaluate(np.array([float(edge.t_start), float(edge.t_end)])),
                                                dtype=float), axis=0)[0]))
    speed = float(np.linalg.norm(np.asarray(edge.derivative(np.array([t0])), dtype=float)))
    step = min(CORNER_OFFSET_CELLS * h, 0.25 * length) / speed
    return np.asarray(edge.evaluate(np.array([t0 + sign * step])), dtype=float).reshape(2)


def closest_boundary_point(first: Any, second: Any, spacing: float) -> np.ndarray:
    """The point of ``first``'s boundary that maximises ``second``'s signed distance phi
    (positive inside): the point closest to ``second`` when they are apart, the deepest one
    when they overlap. Each edge is sampled in its own parameter about every ``spacing``
    (one vectorised phi call per edge), then a bounded scalar search in the exact parameter
    between the neighbours of the best sample refines it."""
    best_phi, best, plateau = -np.inf, None, None
    for name in first.edge_names:  # a handful of edges
        curve = first.edges[name]
        n = int(np.clip(np.ceil(float(curve.length) / spacing) + 1, 9, 20001))
        t = np.linspace(curve.t_start, curve.t_end, n)
        phi = np.asarray(second.signed_distance(curve.evaluate(t)), dtype=float)
        k = int(np.argmax(phi))
        if phi[k] > best_phi:
            best_phi, best = phi[k], (curve, t[max(k - 1, 0)], t[min(k + 1, n - 1)])
            plateau = _plateau(t, phi, k, 1e-9 * spacing)
    if plateau is not None:  # a flat against a flat: every point of the stretch is closest
        curve = best[0]
        return np.asarray(curve.evaluate(np.array([0.5 * (plateau[0] + plateau[1])]))[0], dtype=float)
    curve, t0, t1 = best
    x = refined_maximum(lambda s: np.asarray(second.signed_distance(curve.evaluate(s)), dtype=float),
                         min(t0, t1), max(t0, t1), 1e-13 * max(abs(curve.t_end - curve.t_start), 1.0))
    x = np.asarray(curve.evaluate(np.array([x]))[0], dtype=float)
    # the bounded search never returns the interval ends: keep a better sample end point
    ends = np.asarray(curve.evaluate(np.array([t0, t1])), dtype=float)
    candidates = np.vstack([x[None, :], ends])
    phi = np.asarray(second.signed_distance(candidates), dtype=float)
    return candidates[int(np.argmax(phi))]




def _plateau(t: np.ndarray, phi: np.ndarray, k: int, tol: float) -> tuple[float, float] | None:
    """The parameters (first, last) of the run of samples about the best one, ``k``, whose phi
    lies within ``tol`` of the best (a flat edge parallel to the other body's flat, where every
    point is closest and the search would return whichever end it meets first: a flat punch's
    corner, where no region can be centred), or None where the best is a single sample or two
    (a curve, or a tilted flat, whose phi varies by far more than ``tol`` per sample)."""
    close = phi >= phi[k] - tol
    lo, hi = k, k
    while lo > 0 and close[lo - 1]:
        lo -= 1
    while hi < len(t) - 1 and close[hi + 1]:
        hi += 1
    return (float(t[lo]), float(t[hi])) if hi - lo >= 2 else None


def finest_size_at(body: BodyModel, point: np.ndarray) -> float:
    """The cell size the body's grid will have at ``point``: its element size halved once per
    level of the deepest refinement zone (centre resolved) whose radius reaches the point."""
    levels = [r.levels for r in body.refinements
              if r.center is not None and float(np.hypot(*(np.asarray(r.center, dtype=float) - point))) <= r.radius]
    return float(body.element_size) / 2.0 ** max(levels, default=0)


def corner_distance(profile: Any, point: np.ndarray) -> tuple[float, str]:
    """Distance from the closest boundary point of ``point`` to the nearer end of the edge it
    lies on (inf on a closed edge), and that edge's name: how far a contact there is from a
    corner of the body."""
    proj = profile.project(np.asarray(point, dtype=float)[None, :])
    name = profile.edge_names[int(proj.edge_index[0])]
    curve = profile.edges[name]
    if getattr(curve, "is_closed", False):
        return np.inf, name
    ends = np.asarray(curve.evaluate(np.array([curve.t_start, curve.t_end])), dtype=float)
    c = np.asarray(proj.points[0], dtype=float)
    return float(np.min(np.hypot(*(ends - c).T))), name


def boundary_gap(first: Any, second: Any, point: np.ndarray | None, spacing: float) -> float:
    """The gap between the bodies (negative: overlap) at the point of ``first``'s boundary
    nearest ``point``, or, with ``point`` None, the smallest gap anywhere (the closest-point
    search of :func:`closest_boundary_point`)."""
    if point is None:
        x = closest_boundary_point(first, second, spacing)
    else:
        x = np.asarray(first.project(np.asarray(point, dtype=float)[None, :]).points[0], dtype=float)
    return -float(np.asarray(second.signed_distance(x[None, :]), dtype=float)[0])
