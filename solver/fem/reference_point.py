"""The kinematics and statics of a rigid reference point coupled to boundary points (see
:mod:`solver.model.reference_point`): the rigid motion the point imposes, the traction that
distributes a force and moment at the point, the resultant of a traction about the point, and the
point's motion as the rigid motion that best fits the displacement of the coupled points.

In 2D a rotation and a moment are the scalars about e_z; in 3D they are vectors.
"""

from __future__ import annotations

import numpy as np

__all__ = ["rigid_motion", "distributing_traction", "resultant", "rigid_fit"]


def _cross(rotation: np.ndarray, arm: np.ndarray) -> np.ndarray:
    """rotation x arm for arms (q, d): in 2D rotation is the scalar about e_z."""
    if arm.shape[1] == 2:
        return float(np.ravel(rotation)[0]) * np.column_stack([-arm[:, 1], arm[:, 0]])
    return np.cross(np.asarray(rotation, dtype=float), arm)


def _moment(arm: np.ndarray, force: np.ndarray) -> np.ndarray:
    """arm x force summed over the rows: (1,) in 2D, (3,) in 3D."""
    if arm.shape[1] == 2:
        return np.array([np.sum(arm[:, 0] * force[:, 1] - arm[:, 1] * force[:, 0])])
    return np.cross(arm, force).sum(axis=0)


def rigid_motion(points: np.ndarray, point: np.ndarray, displacement, rotation) -> np.ndarray:
    """(q, d) displacement U + theta x (x - x0) of the points for a small rotation theta."""
    arm = np.asarray(points, dtype=float) - np.asarray(point, dtype=float)
    return np.asarray(displacement, dtype=float)[None, :] + _cross(np.asarray(rotation, dtype=float), arm)


def _polar_tensor(arm: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """J = sum w (|r|^2 I - r r^T) of arms r (the scalar sum w |r|^2 as (1, 1) in 2D)."""
    r2 = np.einsum("qi,qi->q", arm, arm)
    if arm.shape[1] == 2:
        return np.array([[np.sum(weights * r2)]])
    return np.sum(weights * r2) * np.eye(3) - np.einsum("q,qi,qj->ij", weights, arm, arm)


def distributing_traction(points: np.ndarray, weights: np.ndarray, point: np.ndarray, force, moment) -> np.ndarray:
    """(q, d) traction F / A + omega x (x - c) whose integral with ``weights`` is ``force`` and
    whose moment about ``point`` is ``moment`` (c the weighted centroid, A the weights' sum,
    J omega = M + (x0 - c) x F). Points of zero weight carry none. Raises ValueError when the
    points cannot carry the moment (all on one line through c in 3D, or one point)."""
    x = np.asarray(points, dtype=float)
    w = np.asarray(weights, dtype=float)
    area = float(w.sum())
    if not area > 0.0:
        raise ValueError("no boundary point is coupled to the reference point")
    c = (w[:, None] * x).sum(axis=0) / area
    f = np.asarray(force, dtype=float)
    m_c = np.asarray(moment, dtype=float) + _moment((np.asarray(point, dtype=float) - c)[None, :], f[None, :])
    arm = x - c
    j = _polar_tensor(arm, w)
    omega = np.linalg.pinv(j, rcond=1e-10) @ m_c
    if np.linalg.norm(j @ omega - m_c) > 1e-9 * max(np.linalg.norm(m_c), 1e-300):
        raise ValueError("the coupled points lie on one line: they cannot carry a moment about it")
    traction = f[None, :] / area + _cross(omega, arm)
    return np.where(w[:, None] > 0.0, traction, 0.0)


def resultant(points: np.ndarray, weights: np.ndarray, traction: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(force, moment about ``point``) of a traction (q, d) integrated with ``weights``."""
    f = np.asarray(traction, dtype=float) * np.asarray(weights, dtype=float)[:, None]
    arm = np.asarray(points, dtype=float) - np.asarray(point, dtype=float)
    return f.sum(axis=0), _moment(arm, f)


def rigid_fit(points: np.ndarray, weights: np.ndarray, u: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(U, theta): the rigid motion U + theta x (x - x0) closest to the displacements u (q, d) in
    the weighted least-squares sense (the reference point's motion under a distributing
    coupling). A rotation the points do not determine (all on one line) is left zero."""
    x = np.asarray(points, dtype=float)
    w = np.asarray(weights, dtype=float)
    u = np.asarray(u, dtype=float)
    d = x.shape[1]
    arm = x - np.asarray(point, dtype=float)
    n_rot = 1 if d == 2 else 3
    # columns: the d translations, then the rotations (the motion of a unit rotation about each axis)
    cols = [np.broadcast_to(np.eye(d)[k], x.shape) for k in range(d)]
    cols += [_cross(np.eye(n_rot)[k] if d == 3 else np.ones(1), arm) for k in range(n_rot)]
    a = np.stack([c.ravel() for c in cols], axis=1) * np.repeat(np.sqrt(w), d)[:, None]
    b = u.ravel() * np.repeat(np.sqrt(w), d)
    sol, *_ = np.linalg.lstsq(a, b, rcond=1e-10)
    return sol[:d], sol[d:]
