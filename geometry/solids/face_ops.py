"""Closest points and principal curvatures on a parametric face X(u, v) over its parameter
rectangle (the trimming of every face of the 3D scene shapes).

Projection: seeds from the nearest of a grid of samples, then Gauss-Newton steps in (u, v) with
the rectangle as bounds (a coordinate at a bound whose step leaves the rectangle is held there;
a coordinate spanning a whole period is wrapped instead) and Levenberg damping at degenerate
points (poles). The residual is the tangential part of p - X(u, v) taken with the face's exact
normal, so a foot inside the face is exact to round-off whatever the accuracy of the difference
Jacobian (which only sets the convergence rate); a foot on the face's boundary is stationary
along the boundary to the accuracy of that Jacobian (about 1e-10 relative).

Curvatures: the Weingarten map from central differences of the exact unit normal and of the
points (steps 1e-5 of the parameter range: about 1e-8 relative), positive where the face is
convex seen from outside (a sphere of radius R: 1/R, 1/R)."""

from __future__ import annotations

import numpy as np

from .._base import Projection

__all__ = ["periodic_flags", "project_face", "face_curvature"]

_SEED_GRID = 40
_ITERATIONS = 60


def periodic_flags(face) -> tuple[bool, bool]:
    """Per parameter: whether the face closes on itself across that parameter's range (the
    two ends map to the same points), so that projection wraps it instead of clamping."""
    out = []
    for axis in (0, 1):
        other = np.linspace(*(face.v0, face.v1) if axis == 0 else (face.u0, face.u1), 7)
        ends = (face.u0, face.u1) if axis == 0 else (face.v0, face.v1)
        a = np.column_stack([np.full(7, ends[0]), other]) if axis == 0 else np.column_stack([other, np.full(7, ends[0])])
        b = a.copy()
        b[:, axis] = ends[1]
        xa, xb = face.evaluate(a)[0], face.evaluate(b)[0]
        size = max(face.lengths) + float(np.abs(xa).max())
        out.append(bool(np.abs(xa - xb).max() <= 1e-12 * size))
    return out[0], out[1]


def collapsed_ends(face) -> np.ndarray:
    """(2, 2) bool: [k, end] true where the edge at parameter k = lower/upper end maps to one
    point (a pole of a sphere or an ellipsoid, the centre of a disc, a profile's end on the
    axis of a revolution)."""
    out = np.zeros((2, 2), bool)
    for k in (0, 1):
        lo, hi = (face.v0, face.v1) if k == 0 else (face.u0, face.u1)
        other = np.linspace(lo, hi, 7)
        for e, end in enumerate((face.u0, face.u1) if k == 0 else (face.v0, face.v1)):
            uv = np.column_stack([np.full(7, end), other]) if k == 0 else np.column_stack([other, np.full(7, end)])
            x = face.evaluate(uv)[0]
            out[k, e] = bool(np.ptp(x, axis=0).max() <= 1e-12 * (max(face.lengths) + float(np.abs(x).max())))
    return out


def _differences(face, uv: np.ndarray, step: np.ndarray, values: int):
    """d(values)/du, d/dv (n, 3) each, for values 0 (points) or 1 (normals): central
    differences (wrapped across a periodic parameter's seam), second-order one-sided ones
    within a step of a bound."""
    lower, upper = np.array([face.u0, face.v0]), np.array([face.u1, face.v1])
    periodic = getattr(face, "periodic", (False, False))
    out = []
    for k in (0, 1):
        h = step[k]
        a, b = uv.copy(), uv.copy()
        a[:, k] -= h
        b[:, k] += h
        if periodic[k]:
            span = upper[k] - lower[k]
            a[:, k] = lower[k] + np.mod(a[:, k] - lower[k], span)
            b[:, k] = lower[k] + np.mod(b[:, k] - lower[k], span)
            out.append((face.evaluate(b)[values] - face.evaluate(a)[values]) / (2 * h))
            continue
        low, high = a[:, k] < lower[k], b[:, k] > upper[k]
        d = np.empty((len(uv), 3))
        mid = ~(low | high)
        d[mid] = (face.evaluate(b[mid])[values] - face.evaluate(a[mid])[values]) / (2 * h)
        for side, sel in ((1.0, low), (-1.0, high)):
            if sel.any():
                q0 = uv[sel].copy()
                q0[:, k] = uv[sel, k]
                q1, q2 = q0.copy(), q0.copy()
                q1[:, k] += side * h
                q2[:, k] += side * 2 * h
                f0, f1, f2 = (face.evaluate(q)[values] for q in (q0, q1, q2))
                d[sel] = side * (-3 * f0 + 4 * f1 - f2) / (2 * h)
        out.append(d)
    return out[0], out[1]


def _seeds(face, p: np.ndarray) -> np.ndarray:
    from scipy.spatial import cKDTree

    nu = max(8, int(_SEED_GRID * face.lengths[0] / max(face.lengths)))
    nv = max(8, int(_SEED_GRID * face.lengths[1] / max(face.lengths)))
    u, v = np.meshgrid(np.linspace(face.u0, face.u1, nu), np.linspace(face.v0, face.v1, nv), indexing="ij")
    grid = np.column_stack([u.ravel(), v.ravel()])
    _, idx = cKDTree(face.evaluate(grid)[0]).query(p)
    return grid[idx]


def _second_form(xu, xv, nu, nv) -> np.ndarray:
    b = np.stack([np.stack([(xu * nu).sum(1), (xu * nv).sum(1)], 1), np.stack([(xv * nu).sum(1), (xv * nv).sum(1)], 1)], 1)
    return 0.5 * (b + np.swapaxes(b, 1, 2))


def _gram(xu, xv) -> np.ndarray:
    return np.stack([np.stack([(xu * xu).sum(1), (xu * xv).sum(1)], 1), np.stack([(xu * xv).sum(1), (xv * xv).sum(1)], 1)], 1)


def _bounded(face, uv: np.ndarray, delta: np.ndarray, g: np.ndarray, h: np.ndarray, periodic) -> np.ndarray:
    """uv + delta kept on the rectangle: periodic coordinates wrapped; a coordinate leaving
    its range held at the bound while the other takes its own 1D Newton step."""
    lower, upper = np.array([face.u0, face.v0]), np.array([face.u1, face.v1])
    new = uv + delta
    poles = getattr(face, "collapsed", np.zeros((2, 2), bool))
    for k in (0, 1):
        j = 1 - k
        if periodic[j]:  # through a pole: the other side, half a turn on
            for e, bound in ((0, lower[k]), (1, upper[k])):
                cross = poles[k, e] & ((new[:, k] < bound) if e == 0 else (new[:, k] > bound))
                new[cross, k] = 2 * bound - new[cross, k]
                new[cross, j] += 0.5 * (upper[j] - lower[j])
    for k in (0, 1):
        if periodic[k]:
            new[:, k] = lower[k] + np.mod(new[:, k] - lower[k], upper[k] - lower[k])
            continue
        held = (new[:, k] < lower[k]) | (new[:, k] > upper[k])
        if held.any():
            j = 1 - k
            new[held, k] = np.clip(new[held, k], lower[k], upper[k])
            hj = h[held, j, j]
            new[held, j] = uv[held, j] + g[held, j] / np.where(hj > 0, hj, 1.0)
    for k in (0, 1):
        if not periodic[k]:
            new[:, k] = np.clip(new[:, k], lower[k], upper[k])
    return new


def project_face(face, points, periodic: tuple[bool, bool]) -> Projection:
    """Closest points on the trimmed face, its outward normals there, signed distances
    ((p - foot) . normal sign) and the parameters (u, v). Newton steps with the full Hessian
    of the squared distance (first form plus (r . n) times the second form; the first form
    alone where that is not positive definite), halved while they do not reduce the distance."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    uv = _seeds(face, p)
    span = np.array([face.u1 - face.u0, face.v1 - face.v0])
    step = 1e-6 * span
    for _ in range(_ITERATIONS):
        x, n, _jac = face.evaluate(uv)
        r = p - x
        f0 = (r * r).sum(1)
        rn = (r * n).sum(axis=1)
        r_t = r - rn[:, None] * n
        xu, xv = _differences(face, uv, step, 0)
        nu, nv = _differences(face, uv, step, 1)
        g = np.stack([(xu * r_t).sum(1), (xv * r_t).sum(1)], axis=1)
        a = _gram(xu, xv)
        h = a + rn[:, None, None] * _second_form(xu, xv, nu, nv)
        det, tr = np.linalg.det(h), h[:, 0, 0] + h[:, 1, 1]
        h = np.where(((det > 1e-12 * tr**2) & (tr > 0))[:, None, None], h, a)
        h = h + 1e-12 * (h[:, 0, 0] + h[:, 1, 1])[:, None, None] * np.eye(2) + 1e-300 * np.eye(2)
        delta = np.linalg.solve(h, g[:, :, None])[:, :, 0]
        new = _bounded(face, uv, delta, g, h, periodic)
        for _half in range(30):
            worse = ((p - face.evaluate(new)[0]) ** 2).sum(1) > f0 * (1 + 1e-14) + 1e-300
            if not worse.any():
                break
            delta[worse] *= 0.5
            new[worse] = _bounded(face, uv[worse], delta[worse], 0.5 * g[worse], h[worse], periodic)
        moved = np.abs(new - uv).max(axis=1) / span.max()
        uv = new
        if moved.max() < 1e-15:
            break
    x, n, _ = face.evaluate(uv)
    r = p - x
    dist = np.linalg.norm(r, axis=1)
    sign = np.where((r * n).sum(axis=1) < 0.0, -1.0, 1.0)
    return Projection(points=x, normals=n, distances=sign * dist, parameters=uv)


def face_curvature(face, uv: np.ndarray):
    """Principal curvatures k1 <= k2 (n,) and unit directions d1, d2 (n, 3) at parameters uv."""
    uv = np.asarray(uv, dtype=float).reshape(-1, 2).copy()
    span = np.array([face.u1 - face.u0, face.v1 - face.v0])
    poles = getattr(face, "collapsed", np.zeros((2, 2), bool))
    for k, (lo, hi) in enumerate(((face.u0, face.u1), (face.v0, face.v1))):  # just off a pole
        if poles[k, 0]:
            uv[:, k] = np.maximum(uv[:, k], lo + 1e-4 * span[k])
        if poles[k, 1]:
            uv[:, k] = np.minimum(uv[:, k], hi - 1e-4 * span[k])
    step = 1e-5 * span
    xu, xv = _differences(face, uv, step, 0)
    nu, nv = _differences(face, uv, step, 1)
    first, second = _gram(xu, xv), _second_form(xu, xv, nu, nv)
    # generalised symmetric eigenproblem II a = k I a via the Cholesky factor of I
    ell = np.linalg.cholesky(first)
    inv = np.linalg.inv(ell)
    m = inv @ second @ np.swapaxes(inv, 1, 2)
    k, vec = np.linalg.eigh(m)
    coef = np.swapaxes(inv, 1, 2) @ vec  # columns: (a_u, a_v) of each direction
    d = [coef[:, 0, j, None] * xu + coef[:, 1, j, None] * xv for j in (0, 1)]
    d = [v / np.linalg.norm(v, axis=1)[:, None] for v in d]
    return k[:, 0], k[:, 1], d[0], d[1]


def planar_curvature(n: int, e0: np.ndarray, e1: np.ndarray):
    zeros = np.zeros(n)
    return zeros, zeros.copy(), np.tile(e0, (n, 1)), np.tile(e1, (n, 1))
