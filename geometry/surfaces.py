"""Closed-form surfaces: plane, sphere, cylinder, cone, torus (closest points in closed form).

Every projection works in the primitive's local frame (e1, e2, axis) and reduces to a problem
in the meridian half-plane (rho >= 0, t) of the query point, where rho is the distance from the
axis: for any surface point X at (rho', angle', t'),
``|p - X|^2 >= (rho - rho')^2 + (t - t')^2``, with equality when X is in p's half-plane, so the
closest point of a surface of revolution lies in that half-plane (thesis: "the plane m").

Normals point away from the centre or axis (sphere, cylinder, cone: away from the axis;
torus: away from the core circle) and along the given normal for the plane;
``distances = (p - closest) . normal``, negative inside.

Degenerate points get deterministic answers with a valid unit normal: the sphere's centre
(closest point origin + radius e_z), points on an axis (the meridian half-plane of e1, the first
axis of ``orthonormal_frame(axis)``), the torus's core circle (normal away from the axis), the
cone's apex region (see ``Cone``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ._base import (
    Projection,
    Surface,
    as_points,
    finite,
    orthonormal_frame,
    positive,
    register_primitive,
    unit_vector,
    vector,
)
from .curves import (
    blocks,
    check_fields,
    compiled_projection,
    frame_matrix,
    frozen,
    kernel_parameters,
    result_arrays,
    set_fields,
    to_global,
    to_global3,
    to_local,
    unit_radial,
)

__all__ = ["Plane", "Sphere", "Cylinder", "Cone", "Torus"]


def _axis_frame(axis: np.ndarray) -> np.ndarray:
    """Rows e1, e2, axis with (e1, e2) from ``orthonormal_frame(axis)``."""
    e1, e2 = orthonormal_frame(axis)
    return frame_matrix(e1, e2, axis)


class _Revolved(Surface):
    """Shared projection of the surfaces of revolution (cylinder, cone, torus): each point is
    taken to its meridian half-plane (rho, t) in the local frame (e1, e2, axis), the subclass's
    ``_meridian_foot`` solves the 2D problem there, and the answer is turned back about the axis.
    Parameters: (angle about the axis from e1, the subclass's second parameter)."""

    def _meridian_foot(self, rho: np.ndarray, t: np.ndarray) -> tuple[Any, Any, Any, Any, np.ndarray, np.ndarray]:
        """Closest point (rho_c, t_c), unit normal (n_rho, n_t), signed distance and second
        parameter for meridian-plane points (rho, t); the first four may be scalars."""
        raise NotImplementedError

    def project(self, points: ArrayLike, out: Projection | None = None) -> Projection:
        """Closest points, normals, signed distances, parameters; ``out``: a Projection of as
        many points from an earlier call to write the results into."""
        pts, _ = as_points(points)
        n = len(pts)
        fast = compiled_projection(self.type, pts, self._prm, 2, out)
        if fast is not None:
            return fast
        frame = self._frame
        closest, normals, dist, uv = result_arrays(n, 2, out)
        uv = uv.reshape(n, 2)
        for s in blocks(n):
            x, y, t = to_local(pts[s], frame, self._o)
            rho, cx, cy = unit_radial(x, y)
            rc, tc, nr, nt, d, v = self._meridian_foot(rho, t)
            to_global3(nr * cx, nr * cy, nt, frame, None, normals[s])
            to_global3(rc * cx, rc * cy, tc, frame, self._o, closest[s])
            dist[s] = d
            uv[s, 0] = np.arctan2(cy, cx)
            uv[s, 1] = v
        return Projection(points=closest, normals=normals, distances=dist, parameters=uv)


# ---------------------------------------------------------------------------------------
# plane
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Plane(Surface):
    """Plane through ``origin`` with unit ``normal``; parameters (u, v) are the coordinates
    along e1, e2 of ``orthonormal_frame(normal)`` measured from the origin."""

    origin: tuple[float, ...]
    normal: tuple[float, ...]
    type: ClassVar[str] = "plane"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "plane")
        nrm = unit_vector(self.normal, "normal", "plane")
        frame = _axis_frame(nrm)
        set_fields(self, origin=tuple(map(float, o)), normal=tuple(map(float, nrm)))
        set_fields(self, _o=o, _n=nrm, _frame=frame, _prm=kernel_parameters(o, frame))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Plane":
        f = check_fields(d, "plane", ("origin", "normal"))
        return cls(origin=f["origin"], normal=f["normal"])

    def to_dict(self) -> dict[str, Any]:
        return {"type": "plane", "origin": list(self.origin), "normal": list(self.normal)}

    def project(self, points: ArrayLike, out: Projection | None = None) -> Projection:
        """Closest points, normals, signed distances, parameters; ``out``: a Projection of as
        many points from an earlier call to write the results into."""
        pts, _ = as_points(points)
        n = len(pts)
        fast = compiled_projection("plane", pts, self._prm, 2, out)
        if fast is not None:
            return fast
        nrm = self._n
        closest, normals, dist, uv = result_arrays(n, 2, out)
        uv = uv.reshape(n, 2)
        for s in blocks(n):
            u, v, h = to_local(pts[s], self._frame, self._o)
            np.multiply(h[:, None], nrm, out=closest[s])
            np.subtract(pts[s], closest[s], out=closest[s])
            dist[s] = h
            uv[s, 0] = u
            uv[s, 1] = v
        normals[:] = nrm
        return Projection(points=closest, normals=normals, distances=dist, parameters=uv)


# ---------------------------------------------------------------------------------------
# sphere
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Sphere(Surface):
    """Sphere of ``radius`` about ``origin``; parameters (longitude, latitude) about the global
    z axis. The centre projects to origin + radius e_z."""

    origin: tuple[float, ...]
    radius: float
    type: ClassVar[str] = "sphere"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "sphere")
        r = positive(self.radius, "radius", "sphere")
        set_fields(self, origin=tuple(map(float, o)), radius=r)
        set_fields(self, _o=o, _prm=kernel_parameters(o, np.eye(3), r))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Sphere":
        f = check_fields(d, "sphere", ("origin", "radius"))
        return cls(origin=f["origin"], radius=f["radius"])

    def to_dict(self) -> dict[str, Any]:
        return {"type": "sphere", "origin": list(self.origin), "radius": self.radius}

    def project(self, points: ArrayLike, out: Projection | None = None) -> Projection:
        """Closest points, normals, signed distances, parameters; ``out``: a Projection of as
        many points from an earlier call to write the results into."""
        pts, _ = as_points(points)
        n = len(pts)
        fast = compiled_projection("sphere", pts, self._prm, 2, out)
        if fast is not None:
            return fast
        R = self.radius
        closest, normals, dist, uv = result_arrays(n, 2, out)
        uv = uv.reshape(n, 2)
        eye = np.eye(3)
        for s in blocks(n):
            c = pts[s].T - self._o[:, None]  # (3, m), rows contiguous
            x, y, z = c
            with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
                rxy = x * x
                rxy += y * y
                rho = rxy + z * z
                np.sqrt(rho, out=rho)
                c /= rho
            bad = (rho < 1e-150) | (rho > 1e150)
            if bad.any():
                # squares under- or overflowed: rescale by a power of two (exact) first
                ct = (pts[s][bad] - self._o).T
                scale = np.where(np.max(np.abs(ct), axis=0) < 1e-140, 2.0**600, 2.0**-600)
                ct *= scale
                rt = np.sqrt(np.einsum("ij,ij->j", ct, ct))
                zero = rt == 0.0
                ct[:, zero] = np.array([[0.0], [0.0], [1.0]])  # the centre: fixed direction e_z
                rt[zero] = 1.0
                c[:, bad] = ct / rt
                rho[bad] = np.where(zero, 0.0, rt / scale)
            np.subtract(rho, R, out=dist[s])
            uv[s, 0] = np.arctan2(y, x)
            np.multiply(x, x, out=rxy)  # x, y, z are the unit normal's components now
            rxy += y * y
            np.sqrt(rxy, out=rxy)
            uv[s, 1] = np.arctan2(z, rxy)
            to_global(c, eye, normals[s])
            c *= R
            to_global3(c[0], c[1], c[2], eye, self._o, closest[s])
        return Projection(points=closest, normals=normals, distances=dist, parameters=uv)


# ---------------------------------------------------------------------------------------
# cylinder
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Cylinder(_Revolved):
    """Infinite circular cylinder of ``radius`` about the line through ``origin`` along
    ``axis``; parameters (angle about the axis from e1, axial coordinate from the origin)."""

    origin: tuple[float, ...]
    axis: tuple[float, ...]
    radius: float
    type: ClassVar[str] = "cylinder"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "cylinder")
        ax = unit_vector(self.axis, "axis", "cylinder")
        r = positive(self.radius, "radius", "cylinder")
        frame = _axis_frame(ax)
        set_fields(self, origin=tuple(map(float, o)), axis=tuple(map(float, ax)), radius=r)
        set_fields(self, _o=o, _frame=frame, _prm=kernel_parameters(o, frame, r))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Cylinder":
        f = check_fields(d, "cylinder", ("origin", "axis", "radius"))
        return cls(origin=f["origin"], axis=f["axis"], radius=f["radius"])

    def to_dict(self) -> dict[str, Any]:
        return {"type": "cylinder", "origin": list(self.origin), "axis": list(self.axis), "radius": self.radius}

    def _meridian_foot(self, rho: np.ndarray, t: np.ndarray) -> tuple[Any, Any, Any, Any, np.ndarray, np.ndarray]:
        R = self.radius
        return R, t, 1.0, 0.0, rho - R, t


# ---------------------------------------------------------------------------------------
# cone
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Cone(_Revolved):
    """Cone about the line through ``origin`` along ``axis``: radius ``radius`` (>= 0) at the
    origin, growing along +axis as radius + t tan(half_angle), 0 < half_angle < pi/2. Only the
    nappe that carries the surface (radius >= 0, i.e. t >= t_apex = -radius / tan(half_angle))
    exists.

    In the meridian half-plane the surface is the ray from the apex A along
    g = (sin a, cos a) (rho, t) and its outward normal is m = (cos a, -sin a). A query point q
    with (q - A) . g > 0 projects onto the ray; otherwise the apex itself is the closest point,
    with normal (p - A)/|p - A| (a unit vector in the apex's normal cone, continuous with m on
    the boundary of that region; for p = A it is m in the e1 half-plane). Parameters: (angle
    about the axis from e1, axial coordinate t of the closest point).
    """

    origin: tuple[float, ...]
    axis: tuple[float, ...]
    radius: float
    half_angle: float
    type: ClassVar[str] = "cone"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "cone")
        ax = unit_vector(self.axis, "axis", "cone")
        r = finite(self.radius, "radius", "cone")
        if r < 0.0:
            raise ValueError(f"cone: field 'radius' must be >= 0, got {self.radius!r}")
        alpha = finite(self.half_angle, "half_angle", "cone")
        if not 0.0 < alpha < math.pi / 2:
            raise ValueError(f"cone: field 'half_angle' must be in (0, pi/2) radians, got {self.half_angle!r}")
        frame = _axis_frame(ax)
        set_fields(self, origin=tuple(map(float, o)), axis=tuple(map(float, ax)), radius=r, half_angle=alpha)
        t_apex = -r / math.tan(alpha)
        set_fields(self, _o=o, _frame=frame, _sin=math.sin(alpha), _cos=math.cos(alpha))
        set_fields(self, _t_apex=t_apex, _apex=frozen(o + t_apex * ax))
        set_fields(self, _prm=kernel_parameters(o, frame, r, self._sin, self._cos, t_apex))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Cone":
        f = check_fields(d, "cone", ("origin", "axis", "radius", "half_angle"))
        return cls(origin=f["origin"], axis=f["axis"], radius=f["radius"], half_angle=f["half_angle"])

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "cone",
            "origin": list(self.origin),
            "axis": list(self.axis),
            "radius": self.radius,
            "half_angle": self.half_angle,
        }

    @property
    def apex(self) -> np.ndarray:
        return self._apex

    def _meridian_foot(self, rho: np.ndarray, t: np.ndarray) -> tuple[Any, Any, Any, Any, np.ndarray, np.ndarray]:
        R, sa, ca, ta = self.radius, self._sin, self._cos, self._t_apex
        # signed distance to the generator line, written without the apex coordinate so that
        # small half-angles (apex far away) keep full accuracy near the surface
        dg = rho * ca - t * sa - R * ca
        # closest point on the generator line: q - dg m
        rc = rho - dg * ca
        tc = t + dg * sa
        apex = rc <= 0.0  # foot at or behind the apex: the apex is the closest point
        if not apex.any():
            return rc, tc, ca, -sa, dg, tc
        da, nr_a, nt_a = unit_radial(rho[apex], t[apex] - ta)  # p - apex in (rho, t)
        at = da == 0.0  # the apex itself: the generator's normal in the e1 half-plane
        nr_a[at] = ca
        nt_a[at] = -sa
        nr = np.full_like(rho, ca)  # meridian normal (rho, t) components
        nt = np.full_like(rho, -sa)
        nr[apex] = nr_a
        nt[apex] = nt_a
        dg[apex] = da
        rc[apex] = 0.0
        tc[apex] = ta
        return rc, tc, nr, nt, dg, tc


# ---------------------------------------------------------------------------------------
# torus
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True)
class Torus(_Revolved):
    """Torus about ``origin`` and ``axis``: core circle of ``major_radius`` in the plane normal to
    the axis, tube of ``minor_radius`` (0 < minor_radius <= major_radius). Normals point away from
    the core circle. Parameters: (angle about the axis from e1, angle about the core circle from
    the outward radial direction toward +axis)."""

    origin: tuple[float, ...]
    axis: tuple[float, ...]
    major_radius: float
    minor_radius: float
    type: ClassVar[str] = "torus"

    def __post_init__(self) -> None:
        o = vector(self.origin, "origin", "torus")
        ax = unit_vector(self.axis, "axis", "torus")
        R = positive(self.major_radius, "major_radius", "torus")
        r = positive(self.minor_radius, "minor_radius", "torus")
        if r > R:
            raise ValueError(
                f"torus: field 'minor_radius' = {r!r} must not exceed field 'major_radius' = {R!r}"
                " (self-intersecting spindle tori are not supported)"
            )
        frame = _axis_frame(ax)
        set_fields(self, origin=tuple(map(float, o)), axis=tuple(map(float, ax)), major_radius=R, minor_radius=r)
        set_fields(self, _o=o, _frame=frame, _prm=kernel_parameters(o, frame, R, r))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Torus":
        f = check_fields(d, "torus", ("origin", "axis", "major_radius", "minor_radius"))
        return cls(origin=f["origin"], axis=f["axis"], major_radius=f["major_radius"], minor_radius=f["minor_radius"])

    def to_dict(self) -> dict[str, Any]:
        return {
            "type": "torus",
            "origin": list(self.origin),
            "axis": list(self.axis),
            "major_radius": self.major_radius,
            "minor_radius": self.minor_radius,
        }

    def _meridian_foot(self, rho: np.ndarray, h: np.ndarray) -> tuple[Any, Any, Any, Any, np.ndarray, np.ndarray]:
        R, r = self.major_radius, self.minor_radius
        dq, nr, nh = unit_radial(rho - R, h)  # on the core circle: (1, 0), away from the axis
        rc = nr * r
        rc += R
        return rc, r * nh, nr, nh, dq - r, np.arctan2(nh, nr)
