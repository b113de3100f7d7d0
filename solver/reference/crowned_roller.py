"""The crowned roller on a flat (a straight middle and circular crowns at its ends) as a
half-space contact of the same gap (solver.reference.halfspace), and the readings of its
region: the length along the axis, the half-width at each station along it, and the widest.

The gap of a roller of radius R whose radius drops beyond |x| = straight along a circular arc of
radius crown_radius in the axial section, on a flat, is R - sqrt(r(x)^2 - y^2) with r(x) the
crowned radius; no material beyond the end faces |x| = length. Each edge of the half-space's
region is read where p^2, linear next to a smooth edge (p ~ sqrt(distance)), extrapolates to zero
from the last four loaded centres of its row or column.
"""

from __future__ import annotations

import numpy as np

__all__ = ["crowned_gap", "edge_from_row", "half_widths", "half_length", "solid_bottom"]


def crowned_gap(radius: float = 0.5, crown_radius: float = 0.5, straight: float = 0.05, length: float = 0.1):
    """gap(X, Y): the crowned roller's height above the flat at (X, Y), X along its axis from
    mid-length."""
    def gap(X, Y):
        over = np.clip(np.abs(X) - straight, 0.0, None)
        r = radius - (crown_radius - np.sqrt(crown_radius**2 - np.minimum(over, crown_radius) ** 2))
        return np.where(np.abs(X) > length, 1.0, radius - np.sqrt(np.maximum(r**2 - Y**2, 0.0)))

    return gap


def edge_from_row(coords: np.ndarray, row: np.ndarray) -> float:
    """Where p^2 along a row of centres, linear next to the edge, extrapolates to zero from the
    last four loaded centres (nan with fewer than two loaded; the outermost loaded centre plus
    half a spacing when the fit does not slope down)."""
    loaded = np.flatnonzero(row > 0.0)
    if len(loaded) < 2:
        return float("nan")
    last = loaded[-4:]
    slope, offset = np.polyfit(coords[last], row[last] ** 2, 1)
    if slope >= 0.0:
        return float(coords[loaded[-1]] + 0.5 * (coords[1] - coords[0]))
    return float(-offset / slope)


def half_length(result) -> float:
    """The region's end along the axis (the first column of centres, y next to 0)."""
    return edge_from_row(result.x, result.pressure[:, 0])


def half_widths(result) -> np.ndarray:
    """(nx,) the region's half-width across the axis at each station x of the grid (nan where
    fewer than two centres are loaded)."""
    return np.array([edge_from_row(result.y, result.pressure[i, :]) for i in range(len(result.x))])


def square_means(block: dict, result) -> np.ndarray:
    """The half-space pressure's mean over each group of merged squares of a 3D region's
    pressure map (``block``: a contact block of summary.json; the rectangles whose centres, in the
    frame's coordinates, fall in the group's squares; nan where none does)."""
    m = block["pressure_map"]
    X, Y = np.meshgrid(result.x, result.y, indexing="ij")
    axes = np.array(block["axes"])[:, :2]
    keys = np.stack([np.floor((X * axes[0, 0] + Y * axes[0, 1]) / m["cell"] + 1e-6),
                     np.floor((X * axes[1, 0] + Y * axes[1, 1]) / m["cell"] + 1e-6)], axis=-1)
    out = np.full(len(m["merged"]), np.nan)
    for i, group in enumerate(m["merged"]):
        same = (keys[..., None, :] == np.array(group)[None, None]).all(axis=-1).any(axis=-1)
        if same.any():
            out[i] = float(result.pressure[same].mean())
    return out


def region_half_widths(block: dict, stations: np.ndarray) -> np.ndarray:
    """A 3D region's half-width across its axis 0 at the ``stations`` along it, for a region
    symmetric about that axis (a quarter model's): the boundary polyline of summary.json in the
    frame's coordinates, |s1| off the axis interpolated along |s0| (0 beyond its end)."""
    frame_axes = np.array(block["axes"])
    s = np.abs((np.array(block["boundary"]["points"]) - np.array(block["point"])) @ frame_axes[:2].T)
    upper = s[s[:, 1] > 1e-12]
    order = np.argsort(upper[:, 0])
    return np.interp(stations, upper[order, 0], upper[order, 1], right=0.0)


def solid_bottom(solid, X: np.ndarray, Y: np.ndarray, below: float = -0.005, above: float = 0.02,
                 steps: int = 50) -> np.ndarray:
    """The height of a solid's lower surface above z = 0 at (X, Y), the gap of an exact solid to a
    flat at z = 0: bisection of its signed distance (positive inside) along vertical lines between
    z = ``below`` and ``above`` (Y kept off the symmetry plane y = 0 by 1e-7)."""
    pts = np.stack([np.ravel(X), np.maximum(np.ravel(Y), 1e-7)], axis=1)
    lo, hi = np.full(len(pts), below), np.full(len(pts), above)
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        inside = solid.signed_distance(np.column_stack([pts, mid])) > 0.0
        hi, lo = np.where(inside, mid, hi), np.where(inside, lo, mid)
    return (0.5 * (lo + hi)).reshape(np.shape(X))
