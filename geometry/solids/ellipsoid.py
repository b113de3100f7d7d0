"""Ellipsoids and half ellipsoids with exact Euclidean signed distances.

The closest point of an ellipse or an ellipsoid follows D. Eberly, "Distance from a Point to an
Ellipse, an Ellipsoid, or a Hyperellipsoid" (Geometric Tools, 2013-2020): in the first octant,
with semi-axes sorted e0 >= e1 >= e2, the foot is x_i = e_i^2 y_i / (t + e_i^2) where t is the
unique root of F(t) = sum (e_i y_i / (t + e_i^2))^2 - 1 on t > -e_min^2, found by bisection
(monotone, so it cannot fail); points on a coordinate plane take the lower-dimensional problem
or, inside, the closed-form foot on the evolute's interior. Written here, vectorised over
points, from the formulas of that note."""

from __future__ import annotations

import math

import numpy as np

from .faces import ParametricFace
from .shapes import Solid

__all__ = ["Ellipsoid", "HalfEllipsoid", "ellipse_foot", "ellipsoid_foot"]

_TINY = 1e-13
_BISECTIONS = 160  # float64 halves an interval at most ~1100 times; this reaches round-off for t


def _bisect(f, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Root of the decreasing functions f on [lo, hi] (vectorised bisection)."""
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        done = (mid == lo) | (mid == hi)
        if np.all(done):
            break
        with np.errstate(divide="ignore", invalid="ignore"):  # at the bracket's end F is +inf: still "above"
            pos = ~(f(mid) <= 0.0)
        lo, hi = np.where(pos, mid, lo), np.where(pos, hi, mid)
    return 0.5 * (lo + hi)


def ellipse_foot(y: np.ndarray, e: tuple[float, float]) -> np.ndarray:
    """Closest points (n, 2) on the ellipse x0^2/e0^2 + x1^2/e1^2 = 1 (e0 >= e1 > 0) of points
    y (n, 2) with y >= 0 (first quadrant)."""
    e0, e1 = float(e[0]), float(e[1])
    y = np.asarray(y, dtype=float)
    x = np.zeros_like(y)
    # coordinates below 1e-13 of their semi-axis count as zero (the root's bracket would
    # otherwise collapse onto a pole of F; the foot moves by that much at most)
    pos0, pos1 = y[:, 0] > _TINY * e0, y[:, 1] > _TINY * e1
    gen = pos0 & pos1
    x[pos1 & ~gen, 1] = e1  # on the minor axis
    if gen.any():
        z0, z1 = y[gen, 0] / e0, y[gen, 1] / e1
        r0 = (e0 / e1) ** 2
        g = z0**2 + z1**2 - 1.0
        n0 = r0 * z0
        lo, hi = z1 - 1.0, np.where(g < 0.0, 0.0, np.hypot(n0, z1) - 1.0)
        s = _bisect(lambda s: (n0 / (s + r0)) ** 2 + (z1 / (s + 1.0)) ** 2 - 1.0, lo, hi)
        s = np.where(g == 0.0, 0.0, s)
        x[gen, 0] = r0 * y[gen, 0] / (s + r0)
        x[gen, 1] = y[gen, 1] / (s + 1.0)
    axis = ~pos1  # on the major axis
    if axis.any():
        numer, denom = e0 * y[axis, 0], e0**2 - e1**2
        inner = numer < denom
        xde = np.where(inner, numer / max(denom, 1e-300), 1.0)
        x[axis, 0] = e0 * xde
        x[axis, 1] = np.where(inner, e1 * np.sqrt(np.maximum(0.0, 1.0 - xde**2)), 0.0)
    return x


def ellipsoid_foot(y: np.ndarray, e: tuple[float, float, float]) -> np.ndarray:
    """Closest points (n, 3) on the ellipsoid sum x_i^2 / e_i^2 = 1 (e0 >= e1 >= e2 > 0) of
    points y (n, 3) with y >= 0 (first octant)."""
    e0, e1, e2 = (float(v) for v in e)
    y = np.asarray(y, dtype=float)
    x = np.zeros_like(y)
    p0, p1, p2 = y[:, 0] > _TINY * e0, y[:, 1] > _TINY * e1, y[:, 2] > _TINY * e2
    gen = p0 & p1 & p2
    if gen.any():
        z = y[gen] / np.array([e0, e1, e2])
        r0, r1 = (e0 / e2) ** 2, (e1 / e2) ** 2
        g = (z**2).sum(axis=1) - 1.0
        n0, n1 = r0 * z[:, 0], r1 * z[:, 1]
        lo = z[:, 2] - 1.0
        hi = np.where(g < 0.0, 0.0, np.sqrt(n0**2 + n1**2 + z[:, 2] ** 2) - 1.0)
        s = _bisect(lambda s: (n0 / (s + r0)) ** 2 + (n1 / (s + r1)) ** 2 + (z[:, 2] / (s + 1.0)) ** 2 - 1.0, lo, hi)
        s = np.where(g == 0.0, 0.0, s)
        x[gen] = y[gen] * np.array([r0, r1, 1.0]) / (s[:, None] + np.array([r0, r1, 1.0]))
    for keep, sel in (((1, 2), p2 & p1 & ~p0), ((0, 2), p2 & ~p1 & p0)):
        if sel.any():  # on a coordinate plane through the smallest axis: the ellipse there
            foot = ellipse_foot(y[sel][:, list(keep)], (e[keep[0]], e[keep[1]]))
            x[np.ix_(sel, keep)] = foot
    x[p2 & ~p1 & ~p0, 2] = e2
    flat = ~p2  # on the plane of the two largest axes
    if flat.any():
        yf = y[flat]
        d0, d1 = e0**2 - e2**2, e1**2 - e2**2
        n0, n1 = e0 * yf[:, 0], e1 * yf[:, 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            a0, a1 = n0 / d0, n1 / d1
            disc = 1.0 - a0**2 - a1**2
        interior = (n0 < d0) & (n1 < d1) & (disc > 0.0)
        foot = np.zeros_like(yf)
        foot[:, :2] = ellipse_foot(yf[:, :2], (e0, e1))
        foot[interior] = np.column_stack([e0 * a0, e1 * a1, e2 * np.sqrt(np.maximum(disc, 0.0))])[interior]
        x[flat] = foot
    return x


def _sorted_axes(semi_axes: np.ndarray):
    order = np.argsort(-semi_axes, kind="stable")
    return order, tuple(float(v) for v in semi_axes[order])


class Ellipsoid(Solid):
    """An axis-aligned ellipsoid (turn it with ``rotate``): face ``surface``."""

    def __init__(self, center, semi_axes):
        self.center, self.semi_axes = np.asarray(center, float), np.asarray(semi_axes, float)
        if self.semi_axes.shape != (3,) or not np.all(self.semi_axes > 0):
            raise ValueError(f"semi_axes must be three positive numbers, got {self.semi_axes.tolist()}")
        self._order, self._e = _sorted_axes(self.semi_axes)
        self.bounds = (self.center - self.semi_axes, self.center + self.semi_axes)
        self.volume = 4.0 / 3.0 * math.pi * float(np.prod(self.semi_axes))
        self.faces = {"surface": _ellipsoid_face("surface", self.center, self.semi_axes, (0.0, math.pi))}

    def foot(self, points) -> tuple[np.ndarray, np.ndarray]:
        """Closest points on the surface (n, 3) and the inside mask."""
        d = np.asarray(points, float).reshape(-1, 3) - self.center
        local = np.abs(d[:, self._order])
        x = ellipsoid_foot(local, self._e)
        back = np.empty_like(x)
        back[:, self._order] = x
        inside = ((d / self.semi_axes) ** 2).sum(axis=1) <= 1.0
        return self.center + np.copysign(back, d), inside

    def signed_distance(self, points) -> np.ndarray:
        p = np.asarray(points, float).reshape(-1, 3)
        foot, inside = self.foot(p)
        dist = np.linalg.norm(p - foot, axis=1)
        return np.where(inside, dist, -dist)


class HalfEllipsoid(Ellipsoid):
    """The half of an ellipsoid below (or above) the plane z = center[2]: faces ``dome`` and
    ``flat``. Exact distances: the plane is a symmetry plane of the ellipsoid, so the foot of a
    point of the kept side on the whole surface lies on the dome, and a point beyond the plane
    meets the solid on its flat ellipse (the outward normals of the dome point into the kept
    side)."""

    def __init__(self, center, semi_axes, side: str = "below"):
        if side not in ("below", "above"):
            raise ValueError(f"side must be 'below' or 'above', got {side!r}")
        super().__init__(center, semi_axes)
        self.sign = -1.0 if side == "below" else 1.0
        c, a = self.center, self.semi_axes
        lo, hi = c - a, c + a
        (lo if side == "above" else hi)[2] = c[2]
        self.bounds = (lo, hi)
        self.volume *= 0.5
        theta = (0.0, 0.5 * math.pi) if side == "below" else (0.5 * math.pi, math.pi)
        self.faces = {"dome": _ellipsoid_face("dome", c, a, theta), "flat": _elliptic_disc("flat", c, a[:2], -self.sign)}
        self._order2, self._e2 = _sorted_axes(a[:2])

    def _to_flat(self, d: np.ndarray) -> np.ndarray:
        """Distances (n,) within the plane from (x, y) to the flat ellipse (0 inside it)."""
        a = self.semi_axes[:2]
        xy = d[:, :2]
        inside = ((xy / a) ** 2).sum(axis=1) <= 1.0
        local = np.abs(xy[:, self._order2])
        foot = ellipse_foot(local, self._e2)
        return np.where(inside, 0.0, np.linalg.norm(local - foot, axis=1))

    def signed_distance(self, points) -> np.ndarray:
        p = np.asarray(points, float).reshape(-1, 3)
        d = p - self.center
        height = self.sign * d[:, 2]
        whole = super().signed_distance(p)
        beyond = -np.hypot(self._to_flat(d), np.minimum(height, 0.0))
        inside = np.minimum(whole, height)
        return np.where(height < 0.0, beyond, np.where(whole >= 0.0, inside, whole))


def _ellipsoid_face(name: str, centre, a, theta) -> ParametricFace:
    """X = centre + (a0 sin t cos f, a1 sin t sin f, -a2 cos t), t from the -z pole."""
    ax, ay, az = (float(v) for v in a)

    def mapping(uv):
        t, f = uv[:, 0], uv[:, 1]
        st, ct, sf, cf = np.sin(t), np.cos(t), np.sin(f), np.cos(f)
        x = centre + np.stack([ax * st * cf, ay * st * sf, -az * ct], axis=1)
        m = st[:, None] * np.stack([ay * az * st * cf, ax * az * st * sf, -ax * ay * ct], axis=1)  # X_f x X_t
        jac = np.linalg.norm(m, axis=1)
        n = np.stack([st * cf / ax, st * sf / ay, -ct / az], axis=1)  # gradient of the implicit form
        return x, n / np.linalg.norm(n, axis=1)[:, None], jac

    big = float(max(a))
    return ParametricFace(name, (theta[0], theta[1], 0.0, 2 * math.pi), mapping,
                          (big * (theta[1] - theta[0]), 2 * math.pi * big))


def _elliptic_disc(name: str, centre, a, normal_sign: float) -> ParametricFace:
    ax, ay = (float(v) for v in a)
    normal = np.array([0.0, 0.0, normal_sign])

    def mapping(uv):
        r, f = uv[:, 0], uv[:, 1]
        x = centre + np.stack([ax * r * np.cos(f), ay * r * np.sin(f), np.zeros(len(r))], axis=1)
        return x, np.broadcast_to(normal, x.shape).copy(), ax * ay * r

    return ParametricFace(name, (0.0, 1.0, 0.0, 2 * math.pi), mapping, (max(ax, ay), 2 * math.pi * max(ax, ay)))
