"""The geometry checks of a 3D scene, before anything is discretised (the 2D scene's
``_check_geometry`` counterparts for solids): a grid coarser than the body, a prescribed
displacement larger than the body (a unit typo), a probe outside every body and a contact
``point`` off the bodies' surfaces are errors naming the key and its value; bodies that do not
touch, or overlap, at their contact are warned of (a gap the loads must close, an interference the
solve presses out), with the gap's size.

Unchecked, a grid of 5 m cells on bodies of 0.01 m (a scene written in millimetres by mistake)
and a contact point 2.5 m off both bodies passed ``--check`` and then failed inside the contact's
set-up with "body 1 has no surface over the contact point's tangent plane", naming no key.
"""

from __future__ import annotations

import numpy as np

from ibfem.solver.model import problem as pb

from .scene import CONTACT_POINT_REACH, _show

__all__ = ["solid_geometry_problems", "solid_contact_notes", "CONTACT_GAP_NOTE", "SOLID_COARSE_GRID_RATIO"]

#: a solid's element_size may be at most this multiple of its smallest bounding-box side (2D
#: scenes allow half of it; a refined 3D grid coarser than a body's thinnest side still solves:
#: the quarter roller examples have 0.1 m cells on a 0.1 m long quarter, a coarse roller test 0.1 m
#: cells on a 0.06 m thin one; a scene in millimetres by mistake is a thousand times over)
SOLID_COARSE_GRID_RATIO = 4.0

#: a gap or overlap at a contact larger than this share of the finer element size is warned of
#: (rounding in a CAD part's placement stays silent)
CONTACT_GAP_NOTE = 1e-3


def _extent(solid) -> tuple[float, float]:
    """(smallest side, diagonal) of a solid's bounding box."""
    lo, hi = (np.asarray(v, dtype=float) for v in solid.bounds)
    return float(np.min(hi - lo)), float(np.linalg.norm(hi - lo))


def solid_geometry_problems(spec, problem: pb.Problem, label: str) -> list[str]:
    """Every geometry error of a 3D scene, one line each (empty: none)."""
    problems = []
    for i, body in enumerate(problem.bodies):
        smallest, _ = _extent(body.profile)
        if body.element_size > SOLID_COARSE_GRID_RATIO * smallest:
            problems.append(f"{label}: bodies[{i}].element_size = {_show(body.element_size)}: grid coarser than the "
                            f"body (its smallest bounding-box dimension is {smallest:.6g} m; element_size must be at "
                            f"most {SOLID_COARSE_GRID_RATIO:g} times it; lengths are in metres)")
    problems += _displacement_problems(spec, problem, label)
    problems += _probe_problems(spec, problem, label)
    for k, (given, c) in enumerate(zip(spec.contacts, problem.contacts)):
        if given.point is not None:
            text = _point_distance_problem(problem, c)
            if text:
                problems.append(f"{label}: contacts[{k}].point = {_show(list(given.point))}: {text}")
    return problems


def _displacement_problems(spec, problem: pb.Problem, label: str) -> list[str]:
    """A prescribed displacement (or reference point's displacement) larger than its body."""
    problems = []
    for i, bc in enumerate(spec.boundary_conditions):
        moves = [v for v in (getattr(bc, "value", None) or ()) if v is not None] if bc.type == "displacement" else []
        moves += [bc.normal_displacement] if bc.type == "sliding" else []
        moves += list(getattr(bc, "displacement", None) or ()) if bc.type == "reference_point" else []
        if not moves:
            continue
        _, size = _extent(problem.body(bc.body).profile)
        largest = max(abs(float(v)) for v in moves)
        if largest > size:
            problems.append(f"{label}: boundary_conditions[{i}]: a prescribed displacement of {largest:.4g} m exceeds "
                            f"the size of body {bc.body!r} ({size:.4g} m): small-strain linear elasticity needs "
                            "displacements far below the body's size (a unit typo? lengths are in metres)")
    return problems


def _probe_problems(spec, problem: pb.Problem, label: str) -> list[str]:
    if not spec.output.probes:
        return []
    points = np.asarray(spec.output.probes, dtype=float).reshape(-1, 3)
    inside = np.zeros(len(points), dtype=bool)
    for body in problem.bodies:  # points on a boundary count as inside
        _, size = _extent(body.profile)
        inside |= np.asarray(body.profile.signed_distance(points), dtype=float) >= -1e-9 * size
    return [f"{label}: output.probes[{k}] = {_show(list(spec.output.probes[k]))}: outside every body"
            for k in np.flatnonzero(~inside)]


def _point_distance_problem(problem: pb.Problem, c) -> str | None:
    """Why a given contact point is too far from either body's surface (None: it is not)."""
    p = np.asarray(c.point, dtype=float)[None, :]
    reach = CONTACT_POINT_REACH * min(problem.body(n).element_size for n in c.bodies)
    far = []
    for name in c.bodies:
        distance = abs(float(np.asarray(problem.body(name).profile.signed_distance(p), dtype=float)[0]))
        if not distance <= reach:
            far.append(f"{distance:.4g} m from the surface of body {name!r}")
    if not far:
        return None
    return ("not on the bodies' surfaces: " + "; ".join(far) + f" (allowed: {reach:.4g} m, {CONTACT_POINT_REACH:g} "
            "elements); give a point where the bodies touch, or leave the point out to use the closest points of "
            "the two surfaces")


def solid_contact_notes(spec, problem: pb.Problem, label: str) -> list[str]:
    """Warnings for contacts whose bodies are apart, or overlap, where they are closest (the
    midpoint of their closest points from the contact's point: closest_points_3d): the gap is the
    sum of the two surfaces' distances from it."""
    from ibfem.solver.contact.touching3d import closest_points_3d

    notes = []
    for k, c in enumerate(problem.contacts):
        first, second = (problem.body(n) for n in c.bodies)
        size = min(first.element_size, second.element_size)
        x = closest_points_3d(first.profile, second.profile, np.asarray(c.point, dtype=float), size)
        gap = -sum(float(np.asarray(b.profile.signed_distance(x[None]), dtype=float)[0]) for b in (first, second))
        if abs(gap) <= CONTACT_GAP_NOTE * size:
            continue
        where = f"contacts[{k}] ({c.bodies[0]!r} on {c.bodies[1]!r})"
        if gap > 0:
            notes.append(f"{label}: {where}: the bodies do not touch: {gap:.4g} m apart where they are closest "
                         f"({_show([round(float(v), 9) for v in x])}); the loads must close that gap first (no "
                         "contact force until they do)")
        else:
            notes.append(f"{label}: {where}: the bodies overlap by {-gap:.4g} m where they are deepest "
                         f"({_show([round(float(v), 9) for v in x])}); the solve presses that interference out "
                         "along with the loads (move a body if they were meant to touch)")
    return notes
