"""The plane-strain edge condition of a long region's side read by a fit of the pressure's
square-root form on merged cells, instead of its moment on the quadrature points.

Why. On a section across the line a smooth edge's pressure is Q(t) / sqrt(1 - t^2) with
Q = q0 + q2 t^2, and the edge is right where Q(1) = q0 + q2 = 0. The moment of the point traction
with the weight 2/3 (4 t^2 - 1) (``section_moments``) measures q0 + q2 when the pressure has that
form point by point. On cells cut by the edge it has not: the band terms leave a sliver of a cell
at the edge tensile and its inner neighbour overshooting by the same force
([edge_pressure](edge_pressure.py)). Their sum is right, but the moment weighs the sliver (t
near 1, weight near 2) more than its neighbour (weight near 1): the pair reads as a pressure
falling too fast, and the edge is pulled inward by a fraction of a cell.

The fit reads the section only through what the grid resolves: the squares of the local cell's
side in the tangent plane, each square filled less than three quarters merged with the square
one side towards the line (as the merged cells of ``edge_pressure`` do towards the centre), and
in each column of squares along the line (q0, q2) fitted by least squares to the merged squares'
forces, each compared with the integral of the model over the same points. A pair of sliver and
neighbour that keeps its force leaves the fit unchanged. The knot's moment is then the column's
force times the moment of the fitted pressure over its integral, 2/3 (pi / 2) (q0 + q2) over
(pi / 2) q0 + (pi / 4) q2: for a pressure of the model's form, the moment on the points."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["SECTION_FIT", "MIN_GROUPS", "column_fit_moments"]

#: read a long region's sides by the fit (True) or by the point traction's moment (False)
SECTION_FIT = False
#: a column of squares is fitted only where its merged squares number at least this (two
#: parameters and one degree of freedom to spare); otherwise its points' moment is kept
MIN_GROUPS = 3


def _groups(key: np.ndarray, area: np.ndarray, size: float) -> np.ndarray:
    """(q,) the merged square of each point: the squares ``key`` (q, 2) filled less than
    SLIVER_FRACTION by the points' ``area`` join the square one row towards the line (row 0 from
    above, row -1 from below) in the same column where it holds points, following it where it
    merged in turn."""
    from .edge_pressure import SLIVER_FRACTION

    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    m = len(uniq)
    fill = np.bincount(inverse, weights=area, minlength=m) / size**2
    codes = uniq[:, 0] * (1 << 32) + uniq[:, 1]
    order = np.argsort(codes)
    row = uniq[:, 1]
    inward = uniq[:, 0] * (1 << 32) + np.where(row > 0, row - 1, np.where(row < -1, row + 1, row))
    pos = np.minimum(np.searchsorted(codes[order], inward), m - 1)
    found = (codes[order][pos] == inward) & (inward != codes)
    target = np.where((fill < SLIVER_FRACTION) & found, order[pos], np.arange(m))
    for _ in range(m):
        nxt = target[target]
        if (nxt == target).all():
            break
        target = nxt
    return target[inverse]


def column_fit_moments(s: np.ndarray, area: np.ndarray, wp: np.ndarray, t: np.ndarray, hat: np.ndarray,
                       sizes: np.ndarray) -> np.ndarray:
    """(K,) each knot's moment of the 2D edge condition from the fit on merged squares. ``s``
    (q, 2) are the points in the tangent plane (axis 0 along the line), ``area`` their areas,
    ``wp`` their pressures times areas, ``t`` their places across their sections (1 at the
    edge), ``hat`` (q, K) each knot's weight on them (0 off its side and stretch) and ``sizes``
    (K,) the cell at each knot's edge point. Columns with fewer than MIN_GROUPS merged squares,
    or whose fitted pressure has no positive integral, keep the points' moment."""
    u = np.clip(1.0 - t**2, 1e-12, None)
    basis = np.stack([1.0 / np.sqrt(u), t**2 / np.sqrt(u)], axis=1)  # (q, 2)
    raw = wp * (2.0 / 3.0) * (4.0 * t**2 - 1.0)
    out = np.zeros(hat.shape[1])
    cache: dict = {}
    for k in np.flatnonzero((hat > 0.0).any(axis=0)):
        size = float(sizes[k])
        if size not in cache:
            key = np.floor(s / size + 1e-6).astype(np.int64)
            cache[size] = (key[:, 0], _groups(key, area, size))
        column, group = cache[size]
        on = hat[:, k] > 0.0
        h = hat[on, k]
        for c in np.unique(column[on]):
            pick = column[on] == c
            g = np.unique(group[on][pick], return_inverse=True)[1].ravel()
            n = int(g.max()) + 1
            moment = float(raw[on][pick] @ h[pick])
            if n >= MIN_GROUPS:
                force = np.bincount(g, weights=wp[on][pick] * h[pick], minlength=n)
                model = np.stack([np.bincount(g, weights=area[on][pick] * h[pick] * basis[on][pick, j], minlength=n)
                                  for j in (0, 1)], axis=1)
                weight = np.bincount(g, weights=area[on][pick] * h[pick], minlength=n)
                scale = 1.0 / np.sqrt(np.where(weight > 0.0, weight, np.inf))
                q = np.linalg.lstsq(model * scale[:, None], force * scale, rcond=None)[0]
                integral = 0.5 * math.pi * q[0] + 0.25 * math.pi * q[1]
                if integral > 0.0:
                    moment = float(force.sum()) * (math.pi / 3.0) * (q[0] + q[1]) / integral
            out[k] += moment
    return out
