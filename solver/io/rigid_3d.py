"""The rigid-body check of a 3D scene, before anything is discretised: the 2D rule
(solver.model.rigid) with six rigid motions per body, v(x) = t + omega x (x - x0).

Each essential condition contributes rows d . v(x) = 0 at its face's quadrature points (fixed:
every direction; displacement: the components that are not free; sliding: the exact outward
normal; a kinematic reference point: every direction, at the points inside its region). A contact
couples its two bodies' motions on a patch about its point, rows d . (v_first - v_second) = 0 at
the point and one element size either way along both tangents: the normal there for a
frictionless contact, the normal and both tangents for a frictional or tied one (a pressed patch
resists rocking, a sticking one twisting too). Bodies joined by contacts are checked together.
The rule errs towards passing: the solver's own check after assembly judges what it lets through.

Unchecked, a ball whose top face was held with its x component free, pressed through a
frictionless contact, passed ``ibfem run --check`` and failed in the run's assembly with
"body 'ball' is not held against rigid-body motion", naming no key.
"""

from __future__ import annotations

import numpy as np

from ibfem.solver.model import problem as pb
from ibfem.solver.model.reference_point import ReferencePoint

__all__ = ["rigid_body_problems", "RANK_TOLERANCE"]

#: singular values below this share of the largest count as zero
RANK_TOLERANCE = 1e-6
#: quadrature panels about this share of a face's larger extent
FACE_SAMPLING = 1.0 / 8.0


def _face_samples(solid, face: str) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = (np.asarray(v, dtype=float) for v in solid.bounds)
    f, resolution = solid.faces[face], FACE_SAMPLING * float(np.max(hi - lo))
    if hasattr(f, "quadrature"):
        points, _, normals = f.quadrature(resolution)
    else:  # a face given by its parameter panels and map only: the panels' middles
        lower, upper = (np.asarray(v, dtype=float) for v in f.panels(resolution))
        points, normals, _ = f.evaluate(0.5 * (lower + upper))
    return np.asarray(points, dtype=float).reshape(-1, 3), np.asarray(normals, dtype=float).reshape(-1, 3)


def _support_rows(problem: pb.Problem, body: pb.BodyModel) -> tuple[np.ndarray, np.ndarray]:
    """Points and directions along which the body's essential conditions hold it."""
    points, dirs = [], []
    for bc in problem.boundary_conditions:
        if getattr(bc, "body", None) != body.name:
            continue
        if isinstance(bc, ReferencePoint):
            held = (True,) * 3 if bc.kinematic else (False,) * 3
        elif isinstance(bc, pb.Fixed):
            held = (True,) * 3
        elif isinstance(bc, pb.Displacement):
            held = tuple(v is not None for v in bc.value)
        elif isinstance(bc, pb.Sliding):
            held = None
        else:
            continue
        if held is not None and not any(held):
            continue
        x, n = _face_samples(body.profile, bc.edge)
        if isinstance(bc, ReferencePoint):
            x = x[bc.mask(x)]
        if held is None:
            points.append(x)
            dirs.append(n)
            continue
        for keep, d in zip(held, np.eye(3)):
            if keep:
                points.append(x)
                dirs.append(np.broadcast_to(d, x.shape))
    if not points:
        return np.zeros((0, 3)), np.zeros((0, 3))
    return np.concatenate(points), np.concatenate(dirs)


def _motion_rows(points: np.ndarray, dirs: np.ndarray, origin: np.ndarray, scale: float) -> np.ndarray:
    """Rows d . (t + omega x r) = [d, r x d] . (t, omega * scale), r = (x - x0) / scale."""
    r = (points - origin) / scale
    return np.concatenate([dirs, np.cross(r, dirs)], axis=1)


def _contact_rows(problem: pb.Problem, contact) -> tuple[np.ndarray, np.ndarray]:
    """The patch's points and directions (module docstring); the normal is body 2's outward one
    at its surface point closest to the contact point."""
    from ibfem.solver.contact.ellipse_geometry import closest_on, tangent_basis

    first, second = (problem.body(n) for n in contact.bodies)
    h = min(first.element_size, second.element_size)
    point = np.asarray(contact.point, dtype=float)
    normal = closest_on(second.profile, point[None], 1e-6 * h)[1][0]
    t0, t1 = tangent_basis(normal, None)
    pts = np.array([point, point + h * t0, point - h * t0, point + h * t1, point - h * t1])
    along = [normal] if contact.type == "frictionless" else [normal, t0, t1]
    return np.repeat(pts, len(along), axis=0), np.tile(np.array(along), (len(pts), 1))


def _groups(problem: pb.Problem) -> list[list[int]]:
    """Indices of the bodies joined by contacts, one list per group."""
    index = {b.name: i for i, b in enumerate(problem.bodies)}
    group = list(range(len(problem.bodies)))
    for c in problem.contacts:
        a, b = (group[index[n]] for n in c.bodies)
        group = [a if g == b else g for g in group]
    return [[i for i, g in enumerate(group) if g == k] for k in sorted(set(group))]


def _free_motion(v: np.ndarray) -> str:
    """Words for a null vector (t, omega) of one body."""
    t, w = v[:3], v[3:]
    if np.linalg.norm(w) <= 1e-6 * max(np.linalg.norm(t), 1e-300):
        return f"a translation along {(np.round(t / np.linalg.norm(t), 3) + 0.0).tolist()}"
    return f"a rotation about {(np.round(w / np.linalg.norm(w), 3) + 0.0).tolist()}"


def rigid_body_problems(problem: pb.Problem, label: str) -> list[str]:
    """One line per body that can still move rigidly (empty: every body is held)."""
    lo = np.min([np.asarray(b.profile.bounds[0], dtype=float) for b in problem.bodies], axis=0)
    hi = np.max([np.asarray(b.profile.bounds[1], dtype=float) for b in problem.bodies], axis=0)
    origin, scale = 0.5 * (lo + hi), max(float(np.max(hi - lo)), 1e-300)
    problems = []
    for members in _groups(problem):
        slot = {m: 6 * k for k, m in enumerate(members)}
        blocks = []
        for m in members:
            x, d = _support_rows(problem, problem.bodies[m])
            rows = np.zeros((len(x), 6 * len(members)))
            rows[:, slot[m]:slot[m] + 6] = _motion_rows(x, d, origin, scale)
            blocks.append(rows)
        for c in problem.contacts:
            a, b = (next(i for i, body in enumerate(problem.bodies) if body.name == n) for n in c.bodies)
            if a in slot:
                coupling = _motion_rows(*_contact_rows(problem, c), origin, scale)
                rows = np.zeros((len(coupling), 6 * len(members)))
                rows[:, slot[a]:slot[a] + 6], rows[:, slot[b]:slot[b] + 6] = coupling, -coupling
                blocks.append(rows)
        A = np.concatenate(blocks + [np.zeros((6 * len(members), 6 * len(members)))])  # rows >= columns
        _, s, vt = np.linalg.svd(A, full_matrices=False)  # thin: thousands of rows, 6k columns
        null = vt[int(np.sum(s > RANK_TOLERANCE * max(s[0], 1e-300))):]
        for m in members:
            block = null[:, slot[m]:slot[m] + 6]
            if block.size and np.max(np.abs(block)) > 1e-6:
                motion = _free_motion(block[int(np.argmax(np.abs(block).max(axis=1)))])
                problems.append(f"{label}: bodies[{m}].name = {problem.bodies[m].name!r}: rigid-body motion not "
                                f"prevented ({motion}); add fixed, displacement or sliding conditions, or a contact "
                                "that holds it (a frictionless contact holds only along its normal)")
    return problems
