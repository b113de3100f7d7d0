"""The ellipse and its robust, vectorised 2D closest-point kernel.

Kernel (``ellipse_closest_point_2d``). Following Eberly, "Distance from a point to an ellipse,
an ellipsoid, or a hyperellipsoid" (Geometric Tools, 2013), reflect the query point into the
first quadrant, y = (y0, y1) >= 0, semi-axes e0 >= e1 > 0, and write the closest point as

    x_i = e_i^2 y_i / (t + e_i^2),   with t the unique root of   sum_i (e_i y_i / (t + e_i^2))^2 = 1

on t > -e1^2 (t is the Lagrange multiplier; p - x = t (x0/e0^2, x1/e1^2), so t > 0 outside).
In Eberly's scaled variables z_i = y_i / e_i, r0 = (e0/e1)^2 and with s = t/e1^2 we use the
shifted unknown X = s + 1 > 0 and

    u0 = r0 z0 / (X + r0 - 1),   u1 = z1 / X,   closest point = (e0 u0, e1 u1),   root: u0^2 + u1^2 = 1.

Eberly bisects on G(X) = u0^2 + u1^2 - 1, which is safe but needs ~60 halvings. Instead we
solve Phi(X) = (u0^2 + u1^2)^(-1/2) - 1 = 0 by Newton's method: Phi + 1 is the power mean of
exponent -2 of the two positive affine functions X/z1 and (X + r0 - 1)/(r0 z0), hence concave and
increasing in X, and (unlike G, which has a double pole at X = 0) nearly linear when one of
them dominates. For a concave increasing function Newton's iterates from any point left of the
root (Phi <= 0, i.e. u0^2 + u1^2 >= 1) increase monotonically to the root, and a Newton step
from any point right of the root lands left of it. So:

1. lower bound lb = max(z1, r0 z0 - r0 + 1) (each of u0, u1 <= 1 there, so Phi(lb) <= 0);
   upper bound ub from freezing one term: X = z1 / sqrt(1 - u0(lb)^2), or
   X = r0 z0 / sqrt(1 - u1(lb)^2) - (r0 - 1), or Eberly's |(r0 z0, z1)|, whichever is smallest;
2. start = max(lb, Newton(ub)) (left of the root: safe);
3. monotone Newton steps until the step is below 2 ulp, continued only on the points that
   have not converged (the bracket needs no further safeguard: steps never leave it).

Special cases: z1 = 0 inside the evolute (r0 z0 < r0 - 1, the root is the pole X = 0) gives
x0 = e0^2 y0 / (e0^2 - e1^2), x1 = e1 sqrt(1 - (x0/e0)^2) (Eberly's formula); the centre
gives the co-vertex (0, e1). The iteration never forms squares of the query coordinates, so
it neither overflows nor loses accuracy far away, and r0 - 1 = (e0 - e1)(e0 + e1)/e1^2 keeps
nearly circular ellipses (aspect 1.0001) exact. Typical cost: 3-5 evaluations of the Newton
step per point (including the one that detects convergence).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ._base import (
    Curve,
    Projection,
    as_points,
    positive,
    register_primitive,
    restore_dim,
    signed_hypot,
    unit_vector,
    vector,
)
from .curves import (
    blocks,
    check_fields,
    compiled_projection,
    frame_matrix,
    kernel_parameters,
    require_planar_z0,
    result_arrays,
    set_fields,
    to_global3,
    to_local,
)

__all__ = ["Ellipse", "ellipse_closest_point_2d"]

_MAX_NEWTON = 200  # never reached in practice: convergence is monotone and at least linear
_STEP_TOL = 4.5e-16  # relative step size below which the iteration has converged (2 ulp)


def _newton_step(X: np.ndarray, c0: np.ndarray, z1: np.ndarray, d: float) -> np.ndarray:
    """Newton step for Phi(X) = (u0^2 + u1^2)^(-1/2) - 1 (module docstring), for X > 0.

    The result can only be NaN where the squares under- or overflow completely (|query| beyond
    1e300 lengths); callers combine it with np.fmax, which ignores NaN.
    """
    with np.errstate(invalid="ignore", divide="ignore", over="ignore", under="ignore"):
        xd = X + d
        u0 = c0 / xd
        u1 = z1 / X
        u0 *= u0
        u1 *= u1
        w = u0 + u1
        # -Phi / Phi' = w (sqrt(w) - 1) / (u0^2/(X + d) + u1^2/X), sqrt(w) - 1 written stably
        u0 /= xd
        u1 /= X
        u0 += u1  # denominator
        step = np.sqrt(w)
        step += 1.0
        step *= u0
        w1 = w - 1.0
        w1 *= w
        w1 /= step
    return w1


#: scaled heights above the major axis treated as on it (see _first_quadrant_block)
AXIS_HEIGHT = 1e-100


def _first_quadrant_block(e0: float, e1: float, y0: np.ndarray, y1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u0, u1) with closest point (e0 u0, e1 u1) for y0, y1 >= 0 and e0 >= e1 > 0."""
    r0 = (e0 / e1) ** 2
    d = (e0 - e1) * (e0 + e1) / (e1 * e1)  # r0 - 1, without cancellation
    z0 = y0 / e0
    z1 = y1 / e1
    c0 = z0 * r0
    # on the major axis inside the evolute, or the centre; within 1e-100 of the axis counts as on
    # it (the foot moves by that much; Newton from a denormal height loses the root)
    special = (z1 <= AXIS_HEIGHT) & (c0 <= d)
    any_special = special.any()
    if any_special:
        z1[special] = 1.0  # a placeholder keeping X > 0; the answer is set in closed form below
    lb = np.maximum(z1, c0 - d)  # > 0 for every point now
    with np.errstate(invalid="ignore", divide="ignore", over="ignore", under="ignore"):
        # upper bounds from freezing one of u0, u1 at its value at lb (both only shrink as X grows)
        u0 = c0 / (lb + d)
        u1 = z1 / lb
        ub = z1 / np.sqrt(1.0 - u0 * u0)
        np.fmin(ub, c0 / np.sqrt(1.0 - u1 * u1) - d, out=ub)
        # and Eberly's bracket end |(r0 z0, z1)| (u0^2 + u1^2 <= 1 there): best for near-circles
        np.fmin(ub, np.sqrt(c0 * c0 + z1 * z1), out=ub)
        np.fmax(ub, lb, out=ub)  # also where a bound is NaN
        np.minimum(ub, 1e300, out=ub)
        ub += _newton_step(ub, c0, z1, d)
        X = np.fmax(lb, ub)  # a Newton step from anywhere lands left of the root

    # monotone Newton; after each step keep iterating only the points that moved
    idx = None
    Xa, c0a, z1a = X, c0, z1
    for _ in range(_MAX_NEWTON):
        step = _newton_step(Xa, c0a, z1a, d)
        np.fmax(step, 0.0, out=step)  # round-off may give a tiny negative step at the root
        Xa += step
        moving = step > _STEP_TOL * Xa
        if idx is not None:
            X[idx] = Xa
        if not moving.any():
            break
        if moving.mean() > 0.5:
            continue  # compressing costs more than it saves
        idx = np.flatnonzero(moving) if idx is None else idx[moving]
        Xa, c0a, z1a = X[idx], c0[idx], z1[idx]

    with np.errstate(invalid="ignore", divide="ignore"):
        u0 = c0 / (X + d)
        u1 = z1 / X
    if any_special:
        v0 = c0[special] / d if d > 0.0 else np.zeros(int(special.sum()))
        u0[special] = v0
        u1[special] = np.sqrt(np.maximum(1.0 - v0 * v0, 0.0))
    # u0^2 + u1^2 = 1 to a few ulp at convergence; normalising puts the point exactly on the
    # ellipse also where denormal inputs leave too few bits for the iteration (e.g. a circle
    # queried at (5e-324, 5e-324))
    w = u0 * u0
    w += u1 * u1
    np.sqrt(w, out=w)
    u0 /= w
    u1 /= w
    return u0, u1


def ellipse_closest_point_2d(a: float, b: float, x: Any, y: Any) -> tuple[np.ndarray, np.ndarray]:
    """Closest points (cx, cy) on the ellipse (x/a)^2 + (y/b)^2 = 1 to the points (x, y).

    Vectorised over x, y (any broadcastable shapes); all quadrants (the answer takes the signs
    of x and y, so +b for y = +0.0 on the major axis inside the evolute and at the centre);
    ``a < b`` is allowed. Accurate to a few ulp in position (see the module docstring).
    """
    a = positive(a, "a", "ellipse_closest_point_2d")
    b = positive(b, "b", "ellipse_closest_point_2d")
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    shape = x.shape
    xf = x.ravel()
    yf = y.ravel()
    swap = b > a
    if swap:
        a, b, xf, yf = b, a, yf, xf
    cx = np.empty(xf.shape)
    cy = np.empty(xf.shape)
    for s in blocks(len(xf)):
        u0, u1 = _first_quadrant_block(a, b, np.abs(xf[s]), np.abs(yf[s]))
        np.copysign(a * u0, xf[s], out=cx[s])
        np.copysign(b * u1, yf[s], out=cy[s])
    if swap:
        cx, cy = cy, cx
    return cx.reshape(shape), cy.reshape(shape)


@register_primitive
@dataclass(frozen=True)
class Ellipse(Curve):
    """Ellipse about ``origin`` in the plane normal to ``normal`` (optional in the dict,
    default +z), semi-axis ``major_radius`` along ``major_axis`` (made orthogonal to the
    normal) and ``minor_radius`` along ``normal x major_axis``.

    ``project``: closest point of the ellipse (for 3D points: of the query point's projection
    onto the ellipse's plane, which is the 3D closest point); normal: the in-plane outward normal
    of the ellipse (away from the centre); distances: signed Euclidean distances,
    ``hypot(in-plane signed distance, height above the plane)`` with the in-plane sign;
    parameter: the eccentric angle t with closest = origin + a cos t e1 + b sin t e2.
    """

    origin: tuple[float, ...]
    normal: tuple[float, ...]
    major_axis: tuple[float, ...]
    major_radius: float
    minor_radius: float
    type: ClassVar[str] = "ellipse"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "ellipse", dims=(2, 3))
        nrm = unit_vector(self.normal, "normal", "ellipse")
        major = unit_vector(self.major_axis, "major_axis", "ellipse", dims=(2, 3))
        a = positive(self.major_radius, "major_radius", "ellipse")
        b = positive(self.minor_radius, "minor_radius", "ellipse")
        if b > a:
            raise ValueError(
                f"ellipse: field 'minor_radius' = {b!r} must not exceed field 'major_radius' = {a!r}"
            )
        e1 = major - np.dot(major, nrm) * nrm
        norm = float(np.linalg.norm(e1))
        if norm < 1e-9:
            raise ValueError(f"ellipse: field 'major_axis' = {list(self.major_axis)!r} is parallel to the normal")
        e1 = e1 / norm
        e2 = np.cross(nrm, e1)
        frame = frame_matrix(e1, e2, nrm)
        set_fields(
            self,
            origin=tuple(map(float, o)),
            normal=tuple(map(float, nrm)),
            major_axis=tuple(map(float, e1)),
            major_radius=a,
            minor_radius=b,
        )
        set_fields(self, _o=o, _n=nrm, _frame=frame, _prm=kernel_parameters(o, frame, a, b))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Ellipse":
        f = check_fields(d, "ellipse", ("origin", "major_axis", "major_radius", "minor_radius"), ("normal",))
        return cls(
            origin=f["origin"],
            normal=f.get("normal", [0.0, 0.0, 1.0]),
            major_axis=f["major_axis"],
            major_radius=f["major_radius"],
            minor_radius=f["minor_radius"],
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "ellipse",
            "origin": list(self.origin),
            "normal": list(self.normal),
            "major_axis": list(self.major_axis),
            "major_radius": self.major_radius,
            "minor_radius": self.minor_radius,
        }

    def project(self, points: ArrayLike, out: Projection | None = None) -> Projection:
        """See the class doc; ``out``: a Projection of as many 3D points from an earlier
        call to write the results into (3D queries)."""
        pts, dim = as_points(points, dims=(2, 3))
        if dim == 2:
            require_planar_z0(self._o, self._n, "ellipse")
            out = None
        n = len(pts)
        fast = compiled_projection("ellipse", pts, self._prm, 1, out)
        if fast is not None:
            return restore_dim(fast, dim)
        a, b = self.major_radius, self.minor_radius
        k = (b / a) ** 2
        frame = self._frame
        closest, normals, dist, t = result_arrays(n, 1, out)
        for s in blocks(n):
            x, y, h = to_local(pts[s], frame, self._o)
            u0, u1 = _first_quadrant_block(a, b, np.abs(x), np.abs(y))
            cx = np.copysign(a * u0, x)  # back to the query's quadrant
            cy = np.copysign(b * u1, y)
            # outward normal along (cx/a^2, cy/b^2), i.e. along ((b/a)^2 cx, cy)
            nx = k * cx
            norm = np.sqrt(nx * nx + cy * cy)
            nx /= norm
            ny = cy / norm
            to_global3(cx, cy, 0, frame, self._o, closest[s])
            to_global3(nx, ny, 0, frame, None, normals[s])
            dd = (x - cx) * nx
            dd += (y - cy) * ny
            dist[s] = signed_hypot(dd, h)
            t[s] = np.arctan2(np.copysign(u1, y), np.copysign(u0, x))
        return restore_dim(Projection(points=closest, normals=normals, distances=dist, parameters=t), dim)

