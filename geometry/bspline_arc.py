"""B-spline (NURBS) pieces of plane curve as bounded curves: t is the spline parameter on
[knots[degree], knots[-degree-1]]."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .bounded_curve import BoundedCurve, BoundedProjection
from ._curve_numerics import (
    _params,
    _points2,
    _rotation,
)

__all__ = ["BSplineArc"]

# ---------------------------------------------------------------------------------------
# B-spline piece
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class BSplineArc(BoundedCurve):
    """Clamped-or-not B-spline (NURBS when ``weights`` are given) plane curve on its full
    parameter domain [knots[degree], knots[-degree-1]]; evaluation by scipy's BSpline."""

    degree: int
    control_points: np.ndarray
    knots: np.ndarray
    weights: np.ndarray | None = None
    name: str = ""
    type = "bspline"
    cost = 8

    def __post_init__(self) -> None:
        # the checks and the projection engine of geometry.bspline (one set of value checks)
        from .bspline import BSplineCurve

        owner = f"bspline {self.name!r}"
        try:
            engine = BSplineCurve(self.degree, self.knots, self.control_points, self.weights)
        except ValueError as exc:
            raise ValueError(f"{owner}: {str(exc).removeprefix('bspline_curve: ')}") from None
        if engine.dim != 2:
            raise ValueError(f"{owner}: control_points must be a list of [x, y] points, got shape {engine.control_points.shape}")
        object.__setattr__(self, "degree", engine.degree)
        object.__setattr__(self, "control_points", engine.control_points)
        object.__setattr__(self, "knots", engine.knots)
        object.__setattr__(self, "weights", engine.weights)
        object.__setattr__(self, "_engine", engine)

    @cached_property
    def _splines(self):
        from scipy.interpolate import BSpline  # lazy: keeps `from ibfem import geometry` light

        if self.weights is None:
            c = self.control_points
        else:
            c = np.column_stack([self.control_points * self.weights[:, None], self.weights])
        # derivatives by evaluating with nu (piecewise, so repeated interior knots are fine;
        # BSpline.derivative refuses those)
        return BSpline(self.knots, c, self.degree, extrapolate=False)

    @property
    def t_start(self) -> float:
        return float(self.knots[self.degree])

    @property
    def t_end(self) -> float:
        return float(self.knots[-self.degree - 1])

    def _clip(self, t: Any) -> np.ndarray:
        return np.clip(_params(t), self.t_start, self.t_end)

    def _eval_all(self, t: np.ndarray, nu: int):
        s = self._splines
        H = s(t)
        H1 = s(t, nu=1) if nu >= 1 else None
        if nu >= 2:
            H2 = s(t, nu=2) if self.degree >= 2 else np.zeros_like(H)
        else:
            H2 = None
        return H, H1, H2

    def evaluate(self, t: Any) -> np.ndarray:
        t = self._clip(t)
        H, _, _ = self._eval_all(t, 0)
        if self.weights is None:
            return H
        return H[:, :2] / H[:, 2:3]

    def derivative(self, t: Any) -> np.ndarray:
        t = self._clip(t)
        H, H1, _ = self._eval_all(t, 1)
        if self.weights is None:
            return H1
        w = H[:, 2:3]
        X = H[:, :2] / w
        return (H1[:, :2] - X * H1[:, 2:3]) / w

    def second_derivative(self, t: Any) -> np.ndarray:
        t = self._clip(t)
        H, H1, H2 = self._eval_all(t, 2)
        if self.weights is None:
            return H2
        w = H[:, 2:3]
        X = H[:, :2] / w
        X1 = (H1[:, :2] - X * H1[:, 2:3]) / w
        return (H2[:, :2] - 2.0 * X1 * H1[:, 2:3] - X * H2[:, 2:3]) / w

    def _derivatives2(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = self._clip(t)
        H, H1, H2 = self._eval_all(t, 2)
        if self.weights is None:
            return H, H1, H2
        w = H[:, 2:3]
        X = H[:, :2] / w
        X1 = (H1[:, :2] - X * H1[:, 2:3]) / w
        X2 = (H2[:, :2] - 2.0 * X1 * H1[:, 2:3] - X * H2[:, 2:3]) / w
        return X, X1, X2

    def _breakpoints(self) -> np.ndarray:
        k = self.knots
        return np.unique(k[(k >= self.t_start) & (k <= self.t_end)])

    def breakpoints(self) -> np.ndarray:
        return self._breakpoints()

    def _sample_grid(self) -> np.ndarray:
        bp = self._breakpoints()
        per = max(6, 2 * (self.degree + 1))
        pieces = [np.linspace(a, b, per + 1)[:-1] for a, b in zip(bp[:-1], bp[1:])]
        return np.concatenate(pieces + [[self.t_end]])

    @cached_property
    def kinks(self) -> np.ndarray:
        """Interior knots of multiplicity >= degree, where the curve may have a corner."""
        k = self.knots
        inner, counts = np.unique(k[(k > self.t_start) & (k < self.t_end)], return_counts=True)
        return inner[counts >= self.degree]


    def _nearest_signed(self, P: np.ndarray, upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        pr = self._project(P, upper)
        return pr.distances, pr.parameters

    def project(self, points: Any) -> BoundedProjection:
        """The certified closest-point search of :class:`geometry.bspline.BSplineCurve`
        (branch and bound over the knot spans, compiled when numba is there); where the
        closest point is a corner (a kink at a knot of multiplicity >= degree) the sign of the
        distance comes from the pseudo-normal n_left + n_right there, as at the vertices of a
        profile."""
        return self._project(_points2(points))

    def _project(self, P: np.ndarray, upper: np.ndarray | None = None) -> BoundedProjection:
        # the certified search of geometry.bspline (compiled when numba is there); ``upper``
        # is not needed: the search is exact for every point
        P3 = np.zeros((len(P), 3))
        P3[:, :2] = P
        t = np.clip(self._engine.closest_parameters(P3)[0], self.t_start, self.t_end)
        pr = self._projection_at(P, t)
        if self.kinks.size and len(P):
            span = self.t_end - self.t_start
            j = np.clip(np.searchsorted(self.kinks, t), 0, self.kinks.size - 1)
            jl = np.clip(j - 1, 0, self.kinks.size - 1)
            near_r = np.abs(t - self.kinks[j]) <= 1e-9 * span
            near_l = np.abs(t - self.kinks[jl]) <= 1e-9 * span
            kk = np.where(near_r, self.kinks[j], self.kinks[jl])
            at = np.flatnonzero(near_r | near_l)
            if at.size:
                h = 1e-9 * span
                pseudo = self.normal(kk[at] - h) + self.normal(kk[at] + h)
                d = P[at] - pr.points[at]
                s = d[:, 0] * pseudo[:, 0] + d[:, 1] * pseudo[:, 1]
                dist = np.abs(pr.distances[at])
                pr.distances[at] = np.where(s < 0.0, -dist, dist)
        return pr

    def trimmed(self, t0: float, t1: float) -> "BSplineArc":
        """The piece on [t0, t1] (inside the domain) as a clamped B-spline of its own: knots
        inserted up to multiplicity ``degree`` at t0 and t1 (exact, scipy's FITPACK insertion,
        in homogeneous coordinates for NURBS), then the control points between them. The
        parameter keeps its values (the piece's domain is [t0, t1]); the name is kept."""
        from scipy.interpolate import insert  # lazy: keeps `from ibfem import geometry` light

        t0, t1 = float(t0), float(t1)
        if not (self.t_start <= t0 < t1 <= self.t_end):
            raise ValueError(
                f"bspline {self.name!r}: trim range [{t0}, {t1}] must be increasing and inside the domain "
                f"[{self.t_start}, {self.t_end}]"
            )
        p = self.degree
        if self.weights is None:
            coef = self.control_points
        else:
            coef = np.column_stack([self.control_points * self.weights[:, None], self.weights])
        T = self.knots
        C = [coef[:, j].copy() for j in range(coef.shape[1])]
        for x in (t0, t1):
            mult = int(np.count_nonzero(T == x))
            if mult < p:
                T, C, _ = insert(x, (T, C, p), m=p - mult)
                C = [np.asarray(c[: len(T) - p - 1]) for c in C]
        C = np.column_stack(C)
        i_last = int(np.flatnonzero(T == t0)[-1])
        j_first = int(np.flatnonzero(T == t1)[0])
        cp = C[i_last - p : j_first]
        knots = np.concatenate([[t0] * (p + 1), T[(T > t0) & (T < t1)], [t1] * (p + 1)])
        if self.weights is None:
            return BSplineArc(p, cp, knots, None, self.name)
        return BSplineArc(p, cp[:, :2] / cp[:, 2:3], knots, cp[:, 2], self.name)

    def reversed(self) -> "BSplineArc":
        a, b = self.knots[0], self.knots[-1]
        return BSplineArc(
            self.degree,
            self.control_points[::-1],
            (a + b) - self.knots[::-1],
            None if self.weights is None else self.weights[::-1],
            self.name,
        )

    def transformed(self, rotate_deg: float = 0.0, pivot: Any = (0.0, 0.0), translate: Any = (0.0, 0.0)) -> "BSplineArc":
        R = _rotation(float(rotate_deg))
        pivot = np.asarray(pivot, dtype=float)
        cp = (self.control_points - pivot) @ R.T + pivot + np.asarray(translate, dtype=float)
        return BSplineArc(self.degree, cp, self.knots, self.weights, self.name)

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "name": self.name,
            "type": "bspline",
            "degree": self.degree,
            "control_points": self.control_points.tolist(),
            "knots": self.knots.tolist(),
        }
        if self.weights is not None:
            d["weights"] = self.weights.tolist()
        return d
