"""The contact block of a region of general shape (solver.contact.star_region): the frame, the
forces, the region's boundary as a closed polyline on body 1's surface (which stretches of it are
body 1's free edges: complete contact), its extents along its principal directions, area and
centroid, and the pressure as cell means (a map, and along both axes) with its peak.

The band traction at the quadrature points oscillates from cell to cell (trilinear fields) while
its integrals are accurate: the map holds the pressure's mean over each finest cell's square of
the tangent plane (int p dA / int dA), not point values."""

from __future__ import annotations

import math

import numpy as np

from .ellipse_geometry import sector_share, surface_point

__all__ = ["region_block", "boundary_polyline", "cell_means"]

#: points of the boundary polyline over the full turn
BOUNDARY_POINTS = 360


def boundary_polyline(c, a: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(s (n, 2) tangent-plane points, x (n, 3) on body 1, free (n,) at body 1's free edge) of the
    region's boundary, closed through the contact point where body 1 is a symmetric model's
    sector (its symmetry planes bound the region there)."""
    s_parts, free_parts = [], []
    for t0, t1 in c.ranges:
        n = max(8, int(math.ceil(BOUNDARY_POINTS * (t1 - t0) / (2.0 * math.pi))))
        full = t1 - t0 >= 2.0 * math.pi - 1e-9
        psi = np.linspace(t0, t1, n, endpoint=not full)
        margin = 1e-6 if not full else 0.0  # just inside a symmetry plane
        psi = np.clip(psi, t0 + margin, t1 - margin)
        aa, bb = c.semi_axes(a)
        phi = np.arctan2(np.sin(psi) / bb, np.cos(psi) / aa)  # the normalised angle of direction psi
        end = c.end_radius(phi, a)
        r = np.minimum(1.0, end * (1.0 - 1e-9))
        rho = c.rho(phi)
        s = c.centre + (r * rho)[:, None] * np.stack([aa * np.cos(phi), bb * np.sin(phi)], axis=1)
        free = end <= 1.0
        if not full:  # close through the contact point
            s = np.vstack([np.zeros((1, 2)), s])
            free = np.concatenate([[False], free])
        s_parts.append(s)
        free_parts.append(free)
    s, free = np.concatenate(s_parts), np.concatenate(free_parts)
    x, ok = surface_point(c.solids[0], c.frame, s, c.reach)
    return s[ok], x[ok], free[ok]


def cell_means(s: np.ndarray, weights: np.ndarray, values: np.ndarray, size: float):
    """(centres (m, 2), means (m,), areas (m,), keys (m, 2)) of values over the squares of side
    ``size`` of the tangent plane, [k size, (k + 1) size) along each axis from the contact point
    (points a round-off below a square's edge, such as those on a symmetry plane, count in it):
    int v dA / int dA over each square holding quadrature points, the squares' integer keys k."""
    key = np.floor(s / size + 1e-6).astype(np.int64)
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    area = np.bincount(inverse, weights=weights, minlength=len(uniq))
    total = np.bincount(inverse, weights=weights * values, minlength=len(uniq))
    centre = np.stack([np.bincount(inverse, weights=weights * s[:, k], minlength=len(uniq)) for k in (0, 1)], axis=1)
    good = area > 0.0
    return centre[good] / area[good, None], total[good] / area[good], area[good], uniq[good]


def _principal(s: np.ndarray, weights: np.ndarray, boundary: np.ndarray):
    """(directions (2, 2) in the tangent plane, extents (2,)) of the region: the eigenvectors of
    its second moment of area about its centroid, and the boundary's span along each."""
    centroid = weights @ s / weights.sum()
    d = s - centroid
    moment = (d * weights[:, None]).T @ d
    _, vectors = np.linalg.eigh(moment)
    directions = vectors.T[::-1]  # the larger spread first
    span = boundary @ directions.T
    return directions, span.max(axis=0) - span.min(axis=0)


def _profiles(centres: np.ndarray, means: np.ndarray, keys: np.ndarray) -> dict:
    """The cell means along each axis through the contact point: the squares beside the axis
    (keys -1 and 0 across it), by their centroid along it."""
    out = {}
    for k in (0, 1):
        on = np.isin(keys[:, 1 - k], (-1, 0))
        order = np.argsort(centres[on, k])
        out[f"axis{k}"] = {"s": centres[on, k][order].tolist(), "value": means[on][order].tolist()}
    return out


def region_block(c, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
    frame = c.frame
    aa, bb = c.semi_axes(a)
    out = {"bodies": list(c.model.bodies), "type": c.kind, "friction": float(getattr(c.model, "friction", 0.0) or 0.0),
           "point": frame.point.tolist(), "normal": frame.normal.tolist(), "axes": frame.axes.tolist(),
           "region_shape": "star-shaped (line contact)", "scales": [float(aa), float(bb)],
           "region_centre": [float(v) for v in c.centre], "model_share": sector_share(c.ranges),
           "relative_curvatures": [float(k) for k in frame.curvatures],
           "normal_force": float(-on2 @ frame.normal),
           "tangential_force": [float(on2 @ frame.axes[0]), float(on2 @ frame.axes[1])],
           "knots": {"phi": c.knots.tolist(), "rho": np.exp(c.log_rho).tolist(),
                     "free_edge": [bool(v) for v in c.free_knots],
                     "inside": [bool(v) for v in c.inside_knots]}}
    if c.given_point is not None:
        out["given_point"] = c.given_point.tolist()
    if info is None or a <= 0.0:
        out.update(semi_axes=[0.0, 0.0], stick_semi_axes=[0.0, 0.0], pressure={}, shear={})
        return out
    pts = info[0]
    p = np.einsum("qi,qi->q", c.quadrature_traction(info, u[c.dofs]), pts.normal)
    s_edge, x_edge, free = boundary_polyline(c, a)
    directions, extents = _principal(pts.s, pts.weights, s_edge)
    centres, means, areas, keys = cell_means(pts.s, pts.weights, p, c.h)
    peak = int(np.argmax(means))
    peak_x = surface_point(c.solids[0], frame, centres[peak:peak + 1], c.reach)[0][0]
    half = [float(np.abs(s_edge[:, k]).max()) for k in (0, 1)]
    out.update({
        # the region's half-extents along the frame's axes from the contact point
        "semi_axes": half, "stick_semi_axes": [0.0, 0.0],
        "cells_per_semi_axis": [v / c.h for v in half],
        "boundary": {"points": x_edge.tolist(), "free_edge": [bool(v) for v in free]},
        "complete_contact": bool(free.any()),
        "principal_directions": (directions @ frame.axes).tolist(),
        "extents": extents.tolist(),
        "area": float(pts.weights.sum()),
        "centroid": (pts.weights @ pts.x1 / pts.weights.sum()).tolist(),
        "peak_pressure": float(means[peak]), "peak_at": peak_x.tolist(),
        "pressure_map": {"cell": c.h, "s": centres.tolist(), "value": means.tolist(), "area": areas.tolist()},
        "pressure": _profiles(centres, means, keys),
        "shear": {f"axis{k}": {"s": [], "value": []} for k in (0, 1)},
    })
    return out
