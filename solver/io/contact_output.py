"""The contact region for output, from a contact block of ``summary.json``: the pressure on a
body's surface points (point data of the body's VTU file) and the region itself as polygonal
data on the first body's surface (pressure, shear where the block gives it, stick flag).

2D: the region is the curve |s - e| <= a about the contact point (s along ``tangent``, e the
region's centre), its pressure and shear the block's profiles. 3D: the ellipse of ``semi_axes``
about ``region_centre`` in the tangent plane, its pressure the fitted
sqrt(1 - X^2 - Y^2) x quadratic of ``profile_recovery.pressure_coefficients``; the 3D shear is
given along the two axes only (the block's profiles), so the region's polydata carries none."""

from __future__ import annotations

from typing import Any, Callable, Mapping

import numpy as np

__all__ = ["surface_pressure", "region_polydata"]

#: rings and points per ring of the 3D region's polar grid
RINGS, SPOKES = 24, 72


def _ellipse_pressure(c: Mapping[str, Any], X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    coef = np.asarray((c.get("profile_recovery") or {}).get("pressure_coefficients") or [], dtype=float)
    if coef.size != 6:
        return np.full(len(X), np.nan)
    root = np.sqrt(np.clip(1.0 - X**2 - Y**2, 0.0, None))
    basis = np.stack([np.ones_like(X), X, Y, X**2, X * Y, Y**2], axis=1)
    return np.clip(root * (basis @ coef), 0.0, None)


def _frame(c: Mapping[str, Any], dim: int):
    point = np.asarray(c["point"], dtype=float)
    normal = np.asarray(c["normal"], dtype=float)
    if dim == 2:
        axes = np.asarray(c.get("tangent") or [-normal[1], normal[0]], dtype=float)[None]
        half = np.array([float(c.get("half_width") or 0.0)])
        centre = np.array([float(c.get("region_centre") or 0.0)])
        stick = np.array([float(c.get("stick_half_width") or 0.0)])
    else:
        axes = np.asarray(c["axes"], dtype=float)
        half = np.asarray(c.get("semi_axes") or [0.0, 0.0], dtype=float)
        centre = np.asarray(c.get("region_centre") or [0.0, 0.0], dtype=float)
        stick = np.asarray(c.get("stick_semi_axes") or [0.0, 0.0], dtype=float)
    return point, normal, axes, half, centre, stick


def _usable(c: Mapping[str, Any]) -> bool:
    return c.get("point") is not None and None not in c["point"] and c.get("normal") is not None


def surface_pressure(c: Mapping[str, Any], points: np.ndarray, on_surface: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """The contact pressure of block ``c`` at ``points`` (n, dim) of one of its bodies: the
    region's pressure at the surface points near it (``on_surface(points)`` tells which lie on
    the body's surface), 0 elsewhere."""
    p = np.asarray(points, dtype=float)
    out = np.zeros(len(p))
    if not _usable(c):
        return out
    dim = p.shape[1]
    point, normal, axes, half, centre, _ = _frame(c, dim)
    if not np.all(half > 0):
        return out
    rel = p - point
    local = rel @ axes.T - centre
    near = (np.abs(rel @ normal) <= half.max()) & np.all(np.abs(local) <= half, axis=1)
    rows = np.nonzero(near)[0]
    if len(rows):
        rows = rows[np.asarray(on_surface(p[rows]), dtype=bool)]
    if dim == 2:
        prof = c.get("pressure") or {}
        s, value = np.asarray(prof.get("s") or [], float), np.asarray(prof.get("value") or [], float)
        if s.size:
            out[rows] = np.interp(local[rows, 0] + centre[0], s, value, left=0.0, right=0.0)
    else:
        X, Y = local[rows, 0] / half[0], local[rows, 1] / half[1]
        out[rows] = _ellipse_pressure(c, X, Y)
    return out


def _onto_surface(x: np.ndarray, normal: np.ndarray, signed_distance) -> np.ndarray:
    """Points moved along ``normal`` onto the zero of a signed distance that grows along it."""
    if signed_distance is None:
        return x
    t = np.zeros(len(x))
    for _ in range(4):  # Newton with the slope 1 of a distance along the surface's normal
        t -= np.asarray(signed_distance(x + t[:, None] * normal), dtype=float)
    return x + t[:, None] * normal


def region_polydata(c: Mapping[str, Any], dim: int, signed_distance=None) -> dict | None:
    """The contact region on the first body's surface (``signed_distance`` of that body, positive
    inside): ``points``, ``lines`` (2D, a polyline) or ``polys`` (3D, triangles), ``point_data``
    with pressure, shear (2D) and stick (1 in the stick region, 0 where it slips). None without a
    region."""
    if not _usable(c):
        return None
    point, normal, axes, half, centre, stick = _frame(c, dim)
    if not np.all(half > 0):
        return None
    if dim == 2:
        s = centre[0] + half[0] * np.linspace(-1.0, 1.0, 201)
        x = point + s[:, None] * axes[0]
        data = {}
        for key in ("pressure", "shear"):
            prof = c.get(key) or {}
            ss, value = np.asarray(prof.get("s") or [], float), np.asarray(prof.get("value") or [], float)
            data[key] = np.interp(s, ss, value) if ss.size else np.zeros(len(s))
        data["stick"] = (np.abs(s - centre[0]) <= stick[0]).astype(np.uint8)
        return {"points": _onto_surface(x, normal, signed_distance), "lines": np.arange(len(s)), "point_data": data}
    r = np.linspace(0.0, 1.0, RINGS + 1)[1:]
    theta = np.linspace(0.0, 2.0 * np.pi, SPOKES, endpoint=False)
    X = np.concatenate([[0.0], (r[:, None] * np.cos(theta)).ravel()])
    Y = np.concatenate([[0.0], (r[:, None] * np.sin(theta)).ravel()])
    local = np.column_stack([centre[0] + half[0] * X, centre[1] + half[1] * Y])
    x = point + local @ axes
    polys = _polar_triangles(RINGS, SPOKES)
    if np.all(stick > 0):
        stuck = (X * half[0] / stick[0]) ** 2 + (Y * half[1] / stick[1]) ** 2 <= 1.0
    else:
        stuck = np.zeros(len(X), dtype=bool)
    data = {"pressure": _ellipse_pressure(c, X, Y), "stick": stuck.astype(np.uint8)}
    return {"points": _onto_surface(x, normal, signed_distance), "polys": polys, "point_data": data}


def _polar_triangles(rings: int, spokes: int) -> np.ndarray:
    """Triangles of a polar grid: point 0 the centre, ring k's j-th point 1 + k spokes + j."""
    j = np.arange(spokes)
    nxt = (j + 1) % spokes
    tris = [np.column_stack([np.zeros(spokes, dtype=np.int64), 1 + j, 1 + nxt])]
    for k in range(rings - 1):
        a, b = 1 + k * spokes + j, 1 + k * spokes + nxt
        c, d = a + spokes, b + spokes
        tris += [np.column_stack([a, c, d]), np.column_stack([a, d, b])]
    return np.concatenate(tris)
