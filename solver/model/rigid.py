"""Rigid-body motion left free by a problem's supports and contacts (checked before any
assembly, from the exact geometry alone): :func:`rigid_body_modes`."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import problem as pb
from .reference_point import ReferencePoint
from .resolve import contact_frame

__all__ = ["rigid_body_modes"]

#: points sampled along each essential edge for the rigid-body check
_EDGE_SAMPLES = 17
#: singular values below this fraction of the largest count as zero (rows are O(1): unit
#: directions and positions scaled by the scene size)
_RANK_TOLERANCE = 1e-6


def _edge_samples(profile: Any, edge: str) -> tuple[np.ndarray, np.ndarray]:
    """Points (m, 2) and outward unit normals (m, 2) spread along an edge of a profile."""
    curve = profile.edges[edge]
    t = np.linspace(curve.t_start, curve.t_end, _EDGE_SAMPLES)
    return np.asarray(curve.evaluate(t), dtype=float), np.asarray(curve.normal(t), dtype=float)


def _support_rows(problem: pb.Problem, body: pb.BodyModel) -> tuple[np.ndarray, np.ndarray]:
    """Points and directions along which an essential condition holds the body."""
    points, dirs = [], []
    ex, ey = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    for bc in problem.boundary_conditions:
        if isinstance(bc, ReferencePoint) and bc.body == body.name and bc.kinematic:
            x, _ = _edge_samples(body.profile, bc.edge)  # coupled samples held in every direction
            x = x[bc.mask(x)]
            points += [x, x]
            dirs += [np.broadcast_to(ex, x.shape), np.broadcast_to(ey, x.shape)]
            continue
        if getattr(bc, "body", None) != body.name or not isinstance(bc, (pb.Fixed, pb.Displacement, pb.Sliding)):
            continue
        x, n = _edge_samples(body.profile, bc.edge)
        if isinstance(bc, pb.Sliding):
            points.append(x)
            dirs.append(n)
            continue
        held = (True, True) if isinstance(bc, pb.Fixed) else (bc.value[0] is not None, bc.value[1] is not None)
        for keep, d in zip(held, (ex, ey)):
            if keep:
                points.append(x)
                dirs.append(np.broadcast_to(d, x.shape))
    if not points:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.concatenate(points), np.concatenate(dirs)


def _motion_rows(points: np.ndarray, dirs: np.ndarray, origin: np.ndarray, scale: float) -> np.ndarray:
    """Rows d . (t + omega e_z x (x - x0)) of a constraint on the rigid motion (tx, ty, omega*scale)."""
    r = (points - origin) / scale
    return np.column_stack([dirs[:, 0], dirs[:, 1], dirs[:, 1] * r[:, 0] - dirs[:, 0] * r[:, 1]])


def rigid_body_modes(
    problem: pb.Problem, contact_frames: list[tuple[np.ndarray, np.ndarray]] | None = None
) -> dict[str, str]:
    """Bodies whose rigid motions (tx, ty, omega) are not all prevented, with a description
    of a free motion. Empty when every body is held.

    Rule: each essential condition contributes rows d . (t + omega e_z x (x - x0)) = 0 sampled
    along its edge (fixed: x and y; displacement: the prescribed components; sliding: the
    exact local normal). Contacts couple the motions of their two bodies at the contact
    point: frictionless in the normal direction, frictional in the normal and tangential
    directions (a stick zone forms under load), tied in both directions at the point and at
    two points a cell size either side along the tangent (a tied patch also resists relative
    rotation). Bodies linked by contacts are checked together: the stacked rows of a group of
    k bodies must have rank 3k. A unilateral contact is treated as holding, so a body
    pressed only through a frictionless contact passes (the solver checks the contact set).
    """
    bodies = list(problem.bodies)
    index = {b.name: i for i, b in enumerate(bodies)}
    if contact_frames is None:
        contact_frames = [contact_frame(problem, c) for c in problem.contacts]
    lo = np.min([np.asarray(b.profile.bounds[0], dtype=float) for b in bodies], axis=0)
    hi = np.max([np.asarray(b.profile.bounds[1], dtype=float) for b in bodies], axis=0)
    origin, scale = 0.5 * (lo + hi), max(float(np.max(hi - lo)), 1e-300)

    # groups of bodies joined by contacts (union-find over a handful of bodies)
    parent = list(range(len(bodies)))

    def root(i: int) -> int:
        while parent[i] != i:
            i = parent[i]
        return i

    for c in problem.contacts:
        a, b = index[c.bodies[0]], index[c.bodies[1]]
        parent[root(a)] = root(b)
    groups: dict[int, list[int]] = {}
    for i in range(len(bodies)):
        groups.setdefault(root(i), []).append(i)

    free: dict[str, str] = {}
    for members in groups.values():
        slot = {m: k for k, m in enumerate(members)}
        blocks = []
        for m in members:
            x, d = _support_rows(problem, bodies[m])
            rows = np.zeros((len(x), 3 * len(members)))
            rows[:, 3 * slot[m] : 3 * slot[m] + 3] = _motion_rows(x, d, origin, scale)
            blocks.append(rows)
        for c, (point, normal) in zip(problem.contacts, contact_frames):
            a, b = index[c.bodies[0]], index[c.bodies[1]]
            if a not in slot:
                continue
            tangent = np.array([-normal[1], normal[0]])
            if c.type == "frictionless":
                pts, dirs = point[None, :], normal[None, :]
            elif c.type == "frictional":
                pts, dirs = np.array([point, point]), np.array([normal, tangent])
            else:
                h = min(bodies[a].element_size, bodies[b].element_size)
                pts = np.repeat(np.array([point, point + h * tangent, point - h * tangent]), 2, axis=0)
                dirs = np.tile(np.array([normal, tangent]), (3, 1))
            coupling = _motion_rows(pts, dirs, origin, scale)
            rows = np.zeros((len(pts), 3 * len(members)))
            rows[:, 3 * slot[a] : 3 * slot[a] + 3] = coupling
            rows[:, 3 * slot[b] : 3 * slot[b] + 3] = -coupling
            blocks.append(rows)
        A = np.concatenate(blocks) if blocks else np.zeros((0, 3 * len(members)))
        # null space by SVD: a 3k-column matrix with a few hundred rows
        if A.shape[0]:
            _, s, vt = np.linalg.svd(A, full_matrices=True)
            rank = int(np.sum(s > _RANK_TOLERANCE * max(s[0], 1e-300)))
        else:
            vt, rank = np.eye(A.shape[1]), 0
        null = vt[rank:]
        for m in members:
            block = null[:, 3 * slot[m] : 3 * slot[m] + 3]
            if block.size and np.max(np.abs(block)) > 1e-6:
                k = int(np.argmax(np.linalg.norm(block, axis=1)))
                free[bodies[m].name] = _describe(block[k], origin, scale, len(members) > 1)
    return free


def _describe(mode: np.ndarray, origin: np.ndarray, scale: float, grouped: bool) -> str:
    t, omega = mode[:2], mode[2] / scale
    via = " (together with the bodies it touches)" if grouped else ""
    if abs(mode[2]) < 1e-6 * max(np.max(np.abs(mode)), 1e-300):
        d = t / np.linalg.norm(t)
        return f"free translation along [{d[0]:.3g}, {d[1]:.3g}]{via}"
    centre = origin + np.array([-t[1], t[0]]) / omega
    return f"free rotation about [{centre[0]:.4g}, {centre[1]:.4g}]{via}"
