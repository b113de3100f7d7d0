"""Sweep: a curve extruded along a direction (Onshape SWEEP), S(t, h) = C(t) + h d.

Closest point. For fixed t the best h is (p - C(t)) . d, after which the remaining distance
is the distance, in the plane normal to d, between the projections of p and of C(t). So the
3D problem is exactly the 2D problem of the *section*: the profile projected along d onto the
plane through the origin normal to d (``P = I - d d^T``). The section is

* for a ``bspline_curve`` profile: the B-spline (or NURBS, same weights and knots) with
  control points ``P c_i``, projected with :class:`geometry.bspline.BSplineCurve`;
* for a ``line`` profile: the line through ``P o`` along ``P u`` (closed form);
* for a ``circle`` / ``ellipse`` profile: the affine image of a conic, i.e. an ellipse whose
  principal axes come from the SVD of the projected conjugate semi-diameters; it is
  projected with the registry's ``ellipse`` primitive (any orientation of the profile's plane
  relative to d is allowed, only d in that plane is degenerate).

The closest point is then ``q + (p . d) d`` for the section's closest point q.

Parameters returned: (t, h) with t the profile's own parameter (B-spline parameter; for a
line ``C(t) = origin + t * direction``; for a circle the angle from
``orthonormal_frame(normal)[0]`` about the normal; for an ellipse the eccentric angle from
the major axis about the normal) and h = (p - C(t)) . d.

Normals (unit, perpendicular to d):

* line and B-spline profiles: ``unit(C'(t) x d)``, i.e. ``unit(S_t x S_h)``, the
  surface convention for the parametrisation (t, h);
* circle and ellipse profiles: away from the sweep's axis (like a cylinder),
  whatever the sense of the profile's normal.

Distances are signed Euclidean distances: ``|p - closest|`` with the sign of
``(p - closest) . normal`` (they differ from the dot product beyond the ends of a bounded
B-spline profile). The sweep is unbounded in h; in t it is bounded by
the profile (B-spline domain) or not at all (line), or closed (circle, ellipse).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from ._base import (
    Curve,
    Primitive,
    Projection,
    Surface,
    as_points,
    orthonormal_frame,
    primitive_from_dict,
    register_primitive,
    signed_lengths,
    unit_vector,
)
from .bspline import BSplineCurve
from .curves import check_fields

__all__ = ["Sweep"]

_OWNER = "sweep"


def _unit_rows(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = np.sqrt(np.einsum("ij,ij->i", v, v))
    return v / np.where(n > 0, n, 1.0)[:, None], n


@register_primitive
@dataclass(frozen=True, eq=False)
class Sweep(Surface):
    """The extrusion of ``profile`` (a curve primitive or its dict) along ``direction``
    (normalised). See the module doc for the parameters and the normal convention."""

    type: ClassVar[str] = "sweep"
    profile: Any
    direction: Any

    def __post_init__(self) -> None:
        prof = self.profile
        if isinstance(prof, dict):
            try:
                prof = primitive_from_dict(prof)
            except ValueError as exc:
                raise ValueError(f"{_OWNER}: field 'profile': {exc}") from None
        if not isinstance(prof, Primitive) or prof.kind != "curve":
            got = getattr(prof, "type", type(prof).__name__)
            raise ValueError(
                f"{_OWNER}: field 'profile' must be a curve (line, circle, ellipse, bspline_curve), got {got!r}"
            )
        d = unit_vector(self.direction, "direction", _OWNER)
        raw = np.asarray(self.direction, dtype=float)
        if raw.shape == d.shape and np.allclose(raw, d, rtol=0, atol=1e-15):
            d = raw.copy()  # already unit: keep it bit for bit so to_dict round-trips exactly
            d.setflags(write=False)
        object.__setattr__(self, "profile", prof)
        object.__setattr__(self, "direction", d)
        spec = prof.to_dict()
        kind = spec["type"]
        if kind == "bspline_curve":
            self._init_bspline(prof)
        elif kind == "line":
            self._init_line(spec)
        elif kind in ("circle", "ellipse"):
            self._init_conic(spec)
        else:
            raise ValueError(
                f"{_OWNER}: field 'profile' of type {kind!r} is not supported "
                "(line, circle, ellipse, bspline_curve)"
            )
        object.__setattr__(self, "_kind", kind)

    # -- sections ---------------------------------------------------------------------------

    def _flatten(self, x: np.ndarray) -> np.ndarray:
        """Project points/vectors (rows) along d onto the plane through 0 normal to d."""
        d = self.direction
        return x - np.outer(x @ d, d)

    def _init_bspline(self, prof: BSplineCurve) -> None:
        P = np.zeros((len(prof.control_points), 3))
        P[:, : prof.control_points.shape[1]] = prof.control_points
        flat = self._flatten(P)
        if np.ptp(flat, axis=0).max() <= 1e-12 * max(prof.scale, 1e-300):
            raise ValueError(f"{_OWNER}: field 'profile' is a straight segment along 'direction': degenerate sweep")
        section = BSplineCurve(
            degree=prof.degree,
            knots=prof.knots,
            control_points=flat,
            weights=prof.weights,
            periodic=prof.periodic,
        )
        object.__setattr__(self, "_section", section)

    def _init_line(self, spec: dict[str, Any]) -> None:
        o = np.asarray(spec["origin"], dtype=float)
        u = np.asarray(spec["direction"], dtype=float)
        if len(o) == 2:
            o = np.append(o, 0.0)
            u = np.append(u, 0.0)
        u = u / np.linalg.norm(u)
        u_flat = self._flatten(u[None, :])[0]
        if np.linalg.norm(u_flat) < 1e-12:
            raise ValueError(f"{_OWNER}: field 'profile' is a line along 'direction': degenerate sweep")
        object.__setattr__(self, "_line", (o, u, self._flatten(o[None, :])[0], u_flat))

    def _init_conic(self, spec: dict[str, Any]) -> None:
        def vec(key: str) -> np.ndarray:
            v = np.asarray(spec[key], dtype=float)
            return np.append(v, 0.0) if len(v) == 2 else v

        c = vec("origin")
        n = vec("normal")
        n = n / np.linalg.norm(n)
        if spec["type"] == "circle":
            e1, e2 = orthonormal_frame(n)
            A, B = spec["radius"] * e1, spec["radius"] * e2
        else:
            a = vec("major_axis")
            a = a - np.dot(a, n) * n
            e1 = a / np.linalg.norm(a)
            e2 = np.cross(n, e1)
            A, B = spec["major_radius"] * e1, spec["minor_radius"] * e2
        # profile C(theta) = c + A cos(theta) + B sin(theta); its section c' + M (cos, sin)
        M = self._flatten(np.column_stack([A, B]).T).T  # (3, 2)
        U, sigma, _ = np.linalg.svd(M, full_matrices=False)
        if sigma[1] <= 1e-12 * sigma[0]:
            raise ValueError(
                f"{_OWNER}: field 'profile': the {spec['type']}'s plane contains 'direction': degenerate sweep"
            )
        centre = self._flatten(c[None, :])[0]
        section = primitive_from_dict(
            {
                "type": "ellipse",
                "origin": centre.tolist(),
                "normal": self.direction.tolist(),
                "major_axis": U[:, 0].tolist(),
                "major_radius": float(sigma[0]),
                "minor_radius": float(min(sigma[1], sigma[0])),
            }
        )
        object.__setattr__(self, "_section", section)
        object.__setattr__(self, "_conic", (c, A, B, centre, np.linalg.pinv(M)))

    # -- dict round trip ------------------------------------------------------------------

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Sweep":
        d = check_fields(d, _OWNER, ("profile", "direction"))
        if not isinstance(d["profile"], dict):
            raise ValueError(f"{_OWNER}: field 'profile' must be a curve dict, got {d['profile']!r}")
        return cls(profile=d["profile"], direction=d["direction"])

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.type, "profile": self.profile.to_dict(), "direction": self.direction.tolist()}

    # -- evaluation -------------------------------------------------------------------------

    def evaluate(self, th: Any) -> np.ndarray:
        """Points S(t, h) = C(t) + h d at (m, 2) parameters (t, h)."""
        th = np.atleast_2d(np.asarray(th, dtype=float))
        return self._profile_points(th[:, 0]) + th[:, 1:2] * self.direction

    def _profile_points(self, t: np.ndarray) -> np.ndarray:
        if self._kind == "bspline_curve":
            return self.profile.derivatives(t, 0)[0]
        if self._kind == "line":
            o, u, _, _ = self._line
            return o + t[:, None] * u
        c, A, B, _, _ = self._conic
        return c + np.cos(t)[:, None] * A + np.sin(t)[:, None] * B

    # -- projection -------------------------------------------------------------------------

    def project(self, points: ArrayLike) -> Projection:
        p, _ = as_points(points, dims=(3,), finite=self._kind == "bspline_curve")
        d = self.direction
        height = p @ d
        p_flat = p - height[:, None] * d
        if self._kind == "bspline_curve":
            t, q, q1 = self._section.closest_parameters(p_flat)
            normals, nn = _unit_rows(np.cross(q1, d))
            bad = nn <= 1e-14 * self._section.scale
            if np.any(bad):  # zero-speed parametrisation: fall back to the offset direction
                off, dd = _unit_rows(p_flat[bad] - q[bad])
                off[dd == 0] = orthonormal_frame(d)[0]
                normals[bad] = off
        elif self._kind == "line":
            o, u, o_flat, u_flat = self._line
            t = (p_flat - o_flat) @ u_flat / np.dot(u_flat, u_flat)
            q = o_flat + t[:, None] * u_flat
            normals = np.broadcast_to(np.cross(u_flat, d) / np.linalg.norm(np.cross(u_flat, d)), p.shape).copy()
        else:
            sec = self._section.project(p_flat)
            q, normals = sec.points, sec.normals
            _, _, _, centre, M_pinv = self._conic
            cs = (q - centre) @ M_pinv.T
            t = np.arctan2(cs[:, 1], cs[:, 0])
        closest = q + height[:, None] * d
        h = height - self._profile_points(t) @ d
        distances = signed_lengths(p - closest, normals)
        return Projection(points=closest, normals=normals, distances=distances, parameters=np.column_stack([t, h]))
