"""The solid shapes of a 3D scene with exact signed distances (positive inside) and named
faces: box, sphere, half_sphere, cylinder, half_cylinder, extrusion (of any 2D profile),
revolution (of a 2D profile in the (r, z) half-plane), each optionally turned and moved
(:class:`Transformed`).

Signed distances are Euclidean and exact where the shape is convex in the sense that matters:
inside every shape, and outside box, sphere, half_sphere, cylinder, extrusions and full
revolutions. Outside a partial revolution (a wedge of angle < 360 degrees) the value is the
larger of the distances to the full revolution and to the wedge: a lower bound of the true
distance, which is what classifying grid cells needs (a cell is only called outside when it
truly is)."""

from __future__ import annotations

import functools
import math

import numpy as np

from .._curve_numerics import _norm2
from .faces import ParametricFace, PlanarRegionFace

__all__ = ["Solid", "Box", "Sphere", "HalfSphere", "Cylinder", "Extrusion", "Revolution", "Transformed"]


def _points(p) -> np.ndarray:
    p = np.asarray(p, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"points must be an (n, 3) array, got shape {p.shape}")
    return p


#: points per block of a distance computed in blocks (each of its temporary arrays then stays in
#: the processor's cache: a turned profile's distance on 200,000 points took 33 ms whole and
#: 15 ms in blocks of 16,384, the same numbers)
BLOCK_POINTS = 16384


def _in_blocks(distance):
    """``signed_distance(self, points)`` evaluated BLOCK_POINTS points at a time (every value
    depends on its own point only: the same numbers as in one pass)."""

    @functools.wraps(distance)
    def blocked(self, points) -> np.ndarray:
        p = _points(points)
        if len(p) <= BLOCK_POINTS:
            return distance(self, p)
        out = np.empty(len(p))
        for start in range(0, len(p), BLOCK_POINTS):
            out[start:start + BLOCK_POINTS] = distance(self, p[start:start + BLOCK_POINTS])
        return out

    return blocked


class Solid:
    """Base of the solids: ``faces`` (name -> face), ``bounds`` (lower, upper corners),
    ``signed_distance(points (n, 3)) -> (n,)``, ``volume``."""

    faces: dict
    volume: float = math.nan

    def signed_distance(self, points) -> np.ndarray:  # pragma: no cover - every shape overrides
        raise NotImplementedError

    def contains(self, points) -> np.ndarray:
        return self.signed_distance(points) >= 0.0


class Box(Solid):
    def __init__(self, lower, upper):
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)
        if not np.all(self.upper > self.lower):
            raise ValueError(f"max must exceed min on every axis, got min {self.lower.tolist()}, max {self.upper.tolist()}")
        self.bounds = (self.lower.copy(), self.upper.copy())
        self.volume = float(np.prod(self.upper - self.lower))
        self.faces = {}
        for k in range(3):
            for side, tag in ((0, "min"), (1, "max")):
                self.faces[f"{'xyz'[k]}_{tag}"] = self._face(k, side)

    def _face(self, k: int, side: int) -> ParametricFace:
        u, v = [j for j in range(3) if j != k]
        lo, hi = self.lower, self.upper
        level = hi[k] if side else lo[k]
        normal = np.zeros(3)
        normal[k] = 1.0 if side else -1.0

        def mapping(uv):
            x = np.empty((len(uv), 3))
            x[:, u], x[:, v], x[:, k] = uv[:, 0], uv[:, 1], level
            return x, np.broadcast_to(normal, x.shape).copy(), np.ones(len(uv))

        name = f"{'xyz'[k]}_{'max' if side else 'min'}"
        return ParametricFace(name, (lo[u], hi[u], lo[v], hi[v]), mapping, (hi[u] - lo[u], hi[v] - lo[v]),
                              surface=_primitive("plane", origin=np.where(normal != 0, level, 0.0), normal=normal))

    def signed_distance(self, points) -> np.ndarray:
        p = _points(points)
        d = np.minimum(p - self.lower, self.upper - p)
        # column by column (a reduction along the rows of an (n, 3) array is several times slower)
        inside = np.minimum(np.minimum(d[:, 0], d[:, 1]), d[:, 2])
        x, y, z = (np.minimum(d[:, k], 0.0) for k in range(3))
        return np.where(inside >= 0.0, inside, -np.sqrt(x * x + y * y + z * z))


def _primitive(kind: str, **fields):
    """A geometry primitive (geometry.surfaces) from plain values."""
    from .._base import primitive_from_dict

    d = {"type": kind}
    for key, value in fields.items():
        d[key] = np.asarray(value, float).tolist() if np.ndim(value) else float(value)
    return primitive_from_dict(d)


def _sphere_face(name, centre, radius, theta, phi, sign=1.0) -> ParametricFace:
    """Sphere surface over polar angle theta (from the -z pole) and azimuth phi."""

    def mapping(uv):
        t, f = uv[:, 0], uv[:, 1]
        d = np.stack([np.sin(t) * np.cos(f), np.sin(t) * np.sin(f), -np.cos(t)], axis=1)
        return centre + radius * d, sign * d, radius**2 * np.sin(t)

    return ParametricFace(name, (theta[0], theta[1], phi[0], phi[1]), mapping,
                          (radius * (theta[1] - theta[0]), radius * (phi[1] - phi[0])),
                          surface=_primitive("sphere", origin=centre, radius=radius))


def _disc_face(name, centre, radius, axis_frame, normal_sign, phi=(0.0, 2 * math.pi)) -> ParametricFace:
    """Disc of ``radius`` about ``centre`` in the plane of axis_frame[0], axis_frame[1]
    (normal normal_sign * axis_frame[2]), parameters (rho, phi)."""
    e0, e1, e2 = axis_frame

    def mapping(uv):
        r, f = uv[:, 0], uv[:, 1]
        x = centre + (r * np.cos(f))[:, None] * e0 + (r * np.sin(f))[:, None] * e1
        return x, np.broadcast_to(normal_sign * e2, x.shape).copy(), r

    return ParametricFace(name, (0.0, radius, phi[0], phi[1]), mapping, (radius, radius * (phi[1] - phi[0])),
                          surface=_primitive("plane", origin=centre, normal=normal_sign * e2))


class Sphere(Solid):
    def __init__(self, center, radius: float):
        self.center, self.radius = np.asarray(center, float), float(radius)
        self.bounds = (self.center - self.radius, self.center + self.radius)
        self.volume = 4.0 / 3.0 * math.pi * self.radius**3
        self.faces = {"surface": _sphere_face("surface", self.center, self.radius, (0.0, math.pi), (0.0, 2 * math.pi))}

    def signed_distance(self, points) -> np.ndarray:
        return self.radius - np.linalg.norm(_points(points) - self.center, axis=1)


class HalfSphere(Solid):
    """The half of a ball below (or above) the horizontal plane through its centre: faces
    ``dome`` and ``flat``."""

    def __init__(self, center, radius: float, side: str = "below"):
        if side not in ("below", "above"):
            raise ValueError(f"side must be 'below' or 'above', got {side!r}")
        self.center, self.radius, self.sign = np.asarray(center, float), float(radius), (-1.0 if side == "below" else 1.0)
        r = self.radius
        lo, hi = self.center - r, self.center + r
        (lo if side == "above" else hi)[2] = self.center[2]
        self.bounds = (lo, hi)
        self.volume = 2.0 / 3.0 * math.pi * r**3
        flip = np.diag([1.0, 1.0, -self.sign])  # the dome of "above" is the mirror of "below"'s
        dome = _sphere_face("dome", self.center, r, (0.0, 0.5 * math.pi), (0.0, 2 * math.pi))
        if side == "above":
            dome = _mirrored(dome, self.center, flip)
        frame = (np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 1.0]))
        self.faces = {"dome": dome, "flat": _disc_face("flat", self.center, r, frame, -self.sign)}

    @_in_blocks
    def signed_distance(self, points) -> np.ndarray:
        d = _points(points) - self.center
        height = self.sign * d[:, 2]  # distance into the kept half
        rho = np.linalg.norm(d, axis=1)
        inside = np.minimum(self.radius - rho, height)
        radial = _norm2(d[:, 0], d[:, 1])
        beyond_flat = np.where(radial <= self.radius, -height, _norm2(radial - self.radius, height))
        outside = np.where(height < 0.0, -beyond_flat, self.radius - rho)
        return np.where((rho <= self.radius) & (height >= 0.0), inside, outside)


def _mirrored(face: ParametricFace, centre, flip) -> ParametricFace:
    base = face._map

    def mapping(uv):
        x, n, j = base(uv)
        return centre + (x - centre) @ flip.T, n @ flip.T, j

    return ParametricFace(face.name, (face.u0, face.u1, face.v0, face.v1), mapping, face.lengths,
                          surface=face._surface)  # a sphere is its own mirror image


def _frame(axis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e_r, e_s, a): a the unit axis, e_r the first of x, y, z not parallel to it projected
    perpendicular to it, e_s = a x e_r (the frame of a ``revolution`` shape)."""
    a = np.asarray(axis, float)
    n = np.linalg.norm(a)
    if not n > 0:
        raise ValueError(f"axis must be a non-zero vector, got {list(axis)}")
    a = a / n
    for c in np.eye(3):
        t = c - (c @ a) * a
        if np.linalg.norm(t) > 1e-6:
            e_r = t / np.linalg.norm(t)
            return e_r, np.cross(a, e_r), a
    raise AssertionError("unreachable")  # pragma: no cover


class Cylinder(Solid):
    """Capped cylinder: ``center`` the middle of its axis; faces ``side``, ``end0`` (at center -
    axis length / 2), ``end1``."""

    def __init__(self, center, axis, radius: float, length: float):
        self.center, self.radius, self.length = np.asarray(center, float), float(radius), float(length)
        e_r, e_s, a = _frame(axis)
        self.frame = (e_r, e_s, a)
        r, half = self.radius, 0.5 * self.length
        ext = r * np.sqrt(np.maximum(0.0, 1.0 - a**2)) + half * np.abs(a)
        self.bounds = (self.center - ext, self.center + ext)
        self.volume = math.pi * r**2 * self.length

        def side(uv):
            f, h = uv[:, 0], uv[:, 1]
            radial = np.cos(f)[:, None] * e_r + np.sin(f)[:, None] * e_s
            return self.center + r * radial + h[:, None] * a, radial, np.full(len(f), r)

        cyl = _primitive("cylinder", origin=self.center, axis=a, radius=r)
        self.faces = {"side": ParametricFace("side", (0.0, 2 * math.pi, -half, half), side, (2 * math.pi * r, self.length),
                                             surface=cyl),
                      "end0": _disc_face("end0", self.center - half * a, r, (e_r, e_s, a), -1.0),
                      "end1": _disc_face("end1", self.center + half * a, r, (e_r, e_s, a), 1.0)}

    @_in_blocks
    def signed_distance(self, points) -> np.ndarray:
        d = _points(points) - self.center
        e_r, e_s, a = self.frame
        h = d @ a
        radial = np.linalg.norm(d - h[:, None] * a, axis=1)
        q = np.stack([radial - self.radius, np.abs(h) - 0.5 * self.length], axis=1)
        inside = -q.max(axis=1)
        return np.where(inside >= 0.0, inside, -np.linalg.norm(np.maximum(q, 0.0), axis=1))


def _no_clash(profile, names, what: str) -> None:
    clash = [n for n in names if n in profile.edge_names]
    if clash:
        raise ValueError(f"profile edge name(s) {', '.join(repr(n) for n in clash)} clash with the face names "
                         f"{' and '.join(names)} of {what}: rename the edge(s)")


class Extrusion(Solid):
    """A 2D profile (x, y) extruded along z from z0 to z0 + height: faces named by the profile's
    edges, ``bottom`` and ``top``."""

    def __init__(self, profile, z0: float, height: float):
        if not height > 0:
            raise ValueError(f"height must be positive, got {height!r}")
        _no_clash(profile, ("bottom", "top"), "an extrusion")
        self.profile, self.z0, self.height = profile, float(z0), float(height)
        lo, hi = (np.asarray(b, float) for b in profile.bounds)
        self.bounds = (np.array([lo[0], lo[1], self.z0]), np.array([hi[0], hi[1], self.z0 + self.height]))
        self.volume = float(profile.area) * self.height
        self.faces = {name: self._side(name) for name in profile.edge_names}
        z1 = self.z0 + self.height
        ex, ey, ez = np.eye(3)
        self.faces["bottom"] = PlanarRegionFace("bottom", profile, [0, 0, self.z0], ex, ey, -ez)
        self.faces["top"] = PlanarRegionFace("top", profile, [0, 0, z1], ex, ey, ez)

    def _side(self, name: str) -> ParametricFace:
        curve = self.profile.edge(name)
        z0, z1 = self.z0, self.z0 + self.height

        def mapping(uv):
            t, z = uv[:, 0], uv[:, 1]
            xy = np.asarray(curve.evaluate(t), float).reshape(-1, 2)
            d = np.asarray(curve.derivative(t), float).reshape(-1, 2)
            speed = np.linalg.norm(d, axis=1)
            n2 = np.stack([d[:, 1], -d[:, 0]], axis=1) / speed[:, None]  # right-hand normal: out of the material
            return (np.column_stack([xy, z]), np.column_stack([n2, np.zeros(len(t))]), speed)

        return ParametricFace(name, (curve.t_start, curve.t_end, z0, z1), mapping, (float(curve.length), self.height),
                              surface=_extruded_primitive(curve))

    @_in_blocks
    def signed_distance(self, points) -> np.ndarray:
        p = _points(points)
        d2 = np.asarray(self.profile.signed_distance(p[:, :2]), float)
        slab = np.minimum(p[:, 2] - self.z0, self.z0 + self.height - p[:, 2])
        inside = np.minimum(d2, slab)
        return np.where(inside >= 0.0, inside, -_norm2(np.minimum(d2, 0.0), np.minimum(slab, 0.0)))


def _extruded_primitive(curve):
    """The plane of an extruded segment, the cylinder of an extruded arc, else None."""
    from ..bounded import Arc, Segment

    if isinstance(curve, Segment):
        n = np.asarray(curve.normal(np.array([curve.t_start])), float).reshape(2)
        return _primitive("plane", origin=[*np.asarray(curve.start, float), 0.0], normal=[n[0], n[1], 0.0])
    if isinstance(curve, Arc):
        return _primitive("cylinder", origin=[*np.asarray(curve.center, float), 0.0], axis=[0.0, 0.0, 1.0],
                          radius=float(curve.radius))
    return None


class Revolution(Solid):
    """A 2D profile in the (r, z) half-plane (r >= 0) turned about ``axis`` through
    ``axis_origin`` by ``angle_deg`` (right-hand rule, from the r direction of :func:`_frame`):
    faces named by the profile's edges (an edge on the axis makes none), ``start`` and ``end``
    when the angle is below 360 degrees."""

    def __init__(self, profile, axis_origin, axis, angle_deg: float = 360.0):
        lo, hi = (np.asarray(b, float) for b in profile.bounds)
        if lo[0] < -1e-12 * max(1.0, hi[0]):
            raise ValueError(f"the profile must lie in r >= 0 (its r ranges from {lo[0]:.6g})")
        if not 0.0 < angle_deg <= 360.0:
            raise ValueError(f"angle_deg must lie in (0, 360], got {angle_deg!r}")
        if angle_deg < 360.0:
            _no_clash(profile, ("start", "end"), "a partial revolution")
        self.profile, self.origin = profile, np.asarray(axis_origin, float)
        self.frame = _frame(axis)
        self.angle = math.radians(float(angle_deg))
        self.full = angle_deg >= 360.0
        e_r, e_s, a = self.frame
        self.faces = {}
        for name in profile.edge_names:
            curve = profile.edge(name)
            r = np.asarray(curve.evaluate(np.linspace(curve.t_start, curve.t_end, 9)), float)[:, 0]
            if np.all(np.abs(r) <= 1e-12 * max(1.0, hi[0])):
                continue  # on the axis: no face
            self.faces[name] = self._turned(name, curve, hi[0])
        if not self.full:
            end_dir = math.cos(self.angle) * e_r + math.sin(self.angle) * e_s
            end_normal = -math.sin(self.angle) * e_r + math.cos(self.angle) * e_s
            self.faces["start"] = PlanarRegionFace("start", profile, self.origin, e_r, a, -e_s)
            self.faces["end"] = PlanarRegionFace("end", profile, self.origin, end_dir, a, end_normal)
        self.bounds = self._bounds(lo, hi)

    @functools.cached_property
    def volume(self) -> float:
        """The volume, by Pappus from a quadrature of the profile (on first use: a run needs none)."""
        return self._volume()

    def _turned(self, name, curve, r_max) -> ParametricFace:
        e_r, e_s, a = self.frame
        origin = self.origin

        def mapping(uv):
            t, f = uv[:, 0], uv[:, 1]
            rz = np.asarray(curve.evaluate(t), float).reshape(-1, 2)
            d = np.asarray(curve.derivative(t), float).reshape(-1, 2)
            speed = np.linalg.norm(d, axis=1)
            n_r, n_z = d[:, 1] / speed, -d[:, 0] / speed
            r, z, cos, sin = rz[:, 0], rz[:, 1], np.cos(f), np.sin(f)
            x, normal = np.empty((len(t), 3)), np.empty((len(t), 3))
            for k in range(3):  # column by column: (n, 1) x (3,) products take several times longer
                radial = cos * e_r[k] + sin * e_s[k]
                x[:, k] = origin[k] + r * radial + z * a[k]
                normal[:, k] = n_r * radial + n_z * a[k]
            return x, normal, np.abs(r) * speed

        return ParametricFace(name, (curve.t_start, curve.t_end, 0.0, self.angle), mapping,
                              (float(curve.length), r_max * self.angle))

    def _rz(self, p: np.ndarray):
        e_r, e_s, a = self.frame
        d = p - self.origin
        z = d @ a
        x, y = d @ e_r, d @ e_s
        return _norm2(x, y), z, x, y  # sqrt(x^2 + y^2): np.hypot takes 15 times as long

    @_in_blocks
    def signed_distance(self, points) -> np.ndarray:
        p = _points(points)
        r, z, x, y = self._rz(p)
        rz = np.empty((len(r), 2))
        rz[:, 0], rz[:, 1] = r, z
        whole = self._meridian_distance(rz)
        if self.full:
            return whole
        # the wedge 0 <= theta <= angle: signed distance to its two bounding half-planes
        theta = np.arctan2(y, x)
        theta = np.where(theta < 0.0, theta + 2 * math.pi, theta)  # theta % 2 pi (compared below only)
        q = r
        to_start = np.where(x >= 0.0, np.abs(y), q)
        c, s_ = math.cos(self.angle), math.sin(self.angle)
        to_end = np.where(x * c + y * s_ >= 0.0, np.abs(-x * s_ + y * c), q)
        near = np.minimum(to_start, to_end)
        wedge = np.where(theta <= self.angle, near, -near)
        inside = (whole >= 0.0) & (wedge >= 0.0)
        return np.where(inside, np.minimum(whole, wedge), -np.maximum(np.maximum(-whole, 0.0), np.maximum(-wedge, 0.0)))

    def _meridian_distance(self, rz: np.ndarray) -> np.ndarray:
        """The profile's signed distance in the meridian half-plane, its magnitude taken over
        the edges that make faces only when the revolution is full (an edge on the axis is then
        no boundary: the profile's own distance would be |r| near it, a gross underestimate;
        the mirror half-plane's edges are never nearer, as r' >= 0 there)."""
        whole = np.asarray(self.profile.signed_distance(rz), float)
        if not self.full or len(self.faces) == len(self.profile.edge_names):
            return whole
        best = np.full(len(rz), np.inf)
        for name in self.profile.edge_names:
            if name in self.faces:
                best = np.minimum(best, np.abs(np.asarray(self.profile.edge(name).project(rz).distances, float)))
        return np.where(whole >= 0.0, best, -best)

    def _bounds(self, lo, hi):
        e_r, e_s, a = self.frame
        f = np.linspace(0.0, self.angle, 721)
        radial = np.cos(f)[:, None] * e_r + np.sin(f)[:, None] * e_s
        pts = []
        for r in (lo[0], hi[0]):
            for z in (lo[1], hi[1]):
                pts.append(self.origin + r * radial + z * a)
        pts = np.concatenate(pts)
        pad = 1e-9 * max(1.0, float(hi[0]))
        return pts.min(axis=0) - pad, pts.max(axis=0) + pad

    def _volume(self) -> float:
        face = PlanarRegionFace("profile", self.profile, np.zeros(3), np.eye(3)[0], np.eye(3)[1], np.eye(3)[2])
        lo, hi = (np.asarray(b, float) for b in self.profile.bounds)
        pts, w, _ = face.quadrature(max(hi - lo) / 64)
        return float(self.angle * (w * pts[:, 0]).sum())  # Pappus: angle x int r dA


class Transformed(Solid):
    """A solid turned by ``rotation`` (3 x 3) about ``pivot``, then moved by ``translate``."""

    def __init__(self, base: Solid, rotation, pivot=(0.0, 0.0, 0.0), translate=(0.0, 0.0, 0.0)):
        self.base, self.rotation = base, np.asarray(rotation, float)
        self.pivot, self.translate = np.asarray(pivot, float), np.asarray(translate, float)
        lo, hi = base.bounds
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        w = self._world(corners)
        self.bounds = (w.min(axis=0), w.max(axis=0))
        self.faces = {name: _TransformedFace(face, self) for name, face in base.faces.items()}

    @property
    def volume(self) -> float:
        return self.base.volume

    def _world(self, x: np.ndarray) -> np.ndarray:
        return (x - self.pivot) @ self.rotation.T + self.pivot + self.translate

    def _local(self, p: np.ndarray) -> np.ndarray:
        return (p - self.pivot - self.translate) @ self.rotation + self.pivot

    @_in_blocks
    def signed_distance(self, points) -> np.ndarray:
        return self.base.signed_distance(self._local(_points(points)))


class _TransformedFace:
    def __init__(self, face, solid: Transformed):
        self.face, self.solid, self.name = face, solid, getattr(face, "name", "")
        if hasattr(face, "panels"):
            self.panels = face.panels
            self.evaluate = self._evaluate
            self.u0, self.u1, self.v0, self.v1 = face.u0, face.u1, face.v0, face.v1
        self.lengths = getattr(face, "lengths", None)

    def _evaluate(self, uv):
        x, n, j = self.face.evaluate(uv)
        return self.solid._world(x), n @ self.solid.rotation.T, j

    def quadrature(self, resolution: float):
        x, w, n = self.face.quadrature(resolution)
        return self.solid._world(x), w, n @ self.solid.rotation.T

    def graded_quadrature(self, resolution: float, cell_size=None, split=None):
        if not hasattr(self.face, "graded_quadrature"):
            return self.quadrature(resolution)
        size = None if cell_size is None else (lambda local: cell_size(self.solid._world(local)))
        cut = None if split is None else (lambda a, b: split(self.solid._world(a), self.solid._world(b)))
        x, w, n = self.face.graded_quadrature(resolution, size, cut)
        return self.solid._world(x), w, n @ self.solid.rotation.T

    def polygon(self):
        """The base face's straight-edged boundary (PlanarRegionFace.polygon), turned and moved."""
        base = self.face.polygon() if hasattr(self.face, "polygon") else None
        if base is None:
            return None
        origin, e0, e1, edges = base
        rot = self.solid.rotation
        return self.solid._world(np.asarray(origin, float)[None])[0], rot @ e0, rot @ e1, edges

    @property
    def normal(self):  # planar regions: the solver offsets points along it
        return self.solid.rotation @ self.face.normal

    def project(self, points):
        from .._base import Projection

        pr = self.face.project(self.solid._local(_points(points)))
        rot = self.solid.rotation
        return Projection(points=self.solid._world(pr.points), normals=pr.normals @ rot.T, distances=pr.distances,
                          parameters=pr.parameters)

    def curvature(self, points):
        k1, k2, d1, d2 = self.face.curvature(self.solid._local(_points(points)))
        rot = self.solid.rotation
        return k1, k2, d1 @ rot.T, d2 @ rot.T

    @property
    def surface(self):
        """The base face's primitive turned and moved (rebuilt from its dict), or this face."""
        base = self.face.surface
        if base is self.face or not hasattr(base, "to_dict"):
            return self
        from .._base import primitive_from_dict

        d = base.to_dict()
        for key in ("origin",):
            if key in d:
                d[key] = self.solid._world(np.asarray(d[key], float)[None])[0].tolist()
        for key in ("normal", "axis", "direction", "major_axis"):
            if key in d:
                d[key] = (self.solid.rotation @ np.asarray(d[key], float)).tolist()
        return primitive_from_dict(d)
