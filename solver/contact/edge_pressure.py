"""The contact pressure read on agglomerated cells: the squares of the finest cell's side in the
tangent plane, each square that the region fills less than three quarters merged with its
neighbour towards the region's centre; and read through the squares' corners (nodal_pressure:
each corner's share of the force over its share of the area), which a region of general shape
maps and judges its final check on.

Why. The band terms tie the two surfaces with a weak (penalty and consistency) condition
integrated over the region's part of each cell. Where the region's edge cuts a cell so that only
a sliver of it lies inside, the condition acts on that sliver alone while the rest of the cell
(outside the region) is free, and a trilinear field cannot close the gap over the sliver: the
traction there is tensile, down to several times the contact's peak over a tenth of a cell and
still tensile over cells filled 55 to 60 % (measured on a ball in a socket, a crowned roller and
a rounded punch), whatever the region's size. The force the sliver lacks is carried by the cell next to it (its
mean overshoots by as much), so the pressure's integrals (the force, the edge moments that fix
the region, the centroid) are accurate while point values and the sliver's own mean are not.
Read over the sliver and its inner neighbour together, the pressure is a mean over at least
three quarters of a cell that contains both the artefact and its balance (cell agglomeration, as cut-cell methods
do for small cut cells): a local L2 projection on piecewise constants over the merged cells.

The final check judges tension on these means at the edge, and the pressure map of a region of
general shape reports them. A region too large for its load carries tension over more than the
last cell (Q(1) < 0 in p = Q(r) / sqrt(1 - r^2)), which the merged means at the edge show: for a
rigid sphere pressed to a radius 10 % beyond Hertz's at 10 cells per radius (5 % at 20) the
smallest is tensile, where the mean over the last two cells along a ray stays compressive up to
10 % (20 % at 10 cells per radius)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["AgglomeratedCells", "agglomerated_cells", "nodal_pressure", "SLIVER_FRACTION", "FULL_FRACTION"]

#: a square the region fills less than this share of merges with its inner neighbour (cells filled
#: 55 to 60 % still carried tension on a rounded punch's edge)
SLIVER_FRACTION = 0.75
#: a square filled to less than this share is cut by the region's edge (or a free edge)
FULL_FRACTION = 0.98


@dataclass
class AgglomeratedCells:
    """Squares of the tangent plane and their groups (a group: a square with the slivers merged
    into it)."""

    point_group: np.ndarray  # (q,) the group of each quadrature point
    centres: np.ndarray  # (g, 2) each group's centroid in the tangent plane
    means: np.ndarray  # (g,) int p dA / int dA over the group
    areas: np.ndarray  # (g,) the region's area in the group
    cut: np.ndarray  # (g,) whether the group holds a square that the region's edge cuts
    keys: np.ndarray  # (g, 2) the integer keys of each group's own square (the one the slivers joined)
    square_keys: np.ndarray  # (m, 2) the squares' integer keys
    square_group: np.ndarray  # (m,) the group of each square


def _encode(keys: np.ndarray) -> np.ndarray:
    return keys[:, 0].astype(np.int64) * (1 << 32) + keys[:, 1].astype(np.int64)


def agglomerated_cells(s: np.ndarray, weights: np.ndarray, values: np.ndarray, size: float,
                       centre=(0.0, 0.0)) -> AgglomeratedCells:
    """Group the squares [k size, (k + 1) size) of the tangent plane (from the contact point;
    points a round-off below a square's edge count in it, as on a symmetry plane) holding the
    points ``s`` (q, 2) with area ``weights``: each square filled less than SLIVER_FRACTION
    joins the square one side inward, towards ``centre`` from its centroid (the nearest square
    filled to SLIVER_FRACTION where there is none), and follows that square where it merged in
    turn. ``values`` are averaged over each group."""
    s = np.asarray(s, dtype=float)
    key = np.floor(s / size + 1e-6).astype(np.int64)
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    m = len(uniq)
    area = np.bincount(inverse, weights=weights, minlength=m)
    centroid = np.stack([np.bincount(inverse, weights=weights * s[:, k], minlength=m) for k in (0, 1)], axis=1)
    centroid /= np.where(area > 0.0, area, 1.0)[:, None]
    fraction = area / size**2
    target = np.arange(m)
    sliver = np.flatnonzero(fraction < SLIVER_FRACTION)
    if len(sliver):
        d = np.asarray(centre, dtype=float)[None, :] - centroid[sliver]
        length = np.hypot(d[:, 0], d[:, 1])
        step = np.where(length[:, None] > 0.0, d / np.where(length > 0.0, length, 1.0)[:, None], 0.0)
        # the square holding the point one side inward from the sliver's centroid
        inward = _encode(np.floor((centroid[sliver] + size * step) / size + 1e-6).astype(np.int64))
        codes = _encode(uniq)
        order = np.argsort(codes)
        pos = np.minimum(np.searchsorted(codes[order], inward), m - 1)
        found = (codes[order][pos] == inward) & (length > 1e-9 * size)
        target[sliver[found]] = order[pos[found]]
        lost = sliver[~found]  # no square inward (a sliver at the centre, or across a gap): the nearest filled one
        filled = np.flatnonzero(fraction >= SLIVER_FRACTION)
        if len(lost) and len(filled):
            gap = np.hypot(*(centroid[lost][:, None, :] - centroid[filled][None, :, :]).transpose(2, 0, 1))
            target[lost] = filled[np.argmin(gap, axis=1)]
        for _ in range(m):  # follow the chains of merged slivers (pointer jumping)
            nxt = target[target]
            if (nxt == target).all():
                break
            target = nxt
    groups, square_group = np.unique(target, return_inverse=True)
    square_group = square_group.ravel()
    point_group = square_group[inverse]
    g = len(groups)
    g_area = np.bincount(point_group, weights=weights, minlength=g)
    total = np.bincount(point_group, weights=weights * values, minlength=g)
    g_centre = np.stack([np.bincount(point_group, weights=weights * s[:, k], minlength=g) for k in (0, 1)], axis=1)
    ok = np.where(g_area > 0.0, g_area, 1.0)
    cut = np.bincount(square_group, weights=(fraction < FULL_FRACTION).astype(float), minlength=g) > 0
    return AgglomeratedCells(point_group, g_centre / ok[:, None], total / ok, g_area, cut, uniq[groups], uniq,
                             square_group)


def _corner_weights(s: np.ndarray, size: float) -> tuple[np.ndarray, np.ndarray]:
    """(keys (4, q, 2), values (4, q)): the four corners k of the square [k size, (k + 1) size)
    holding each point (points a round-off below a square's edge count in it) and the bilinear hat
    of each corner at the point."""
    x = s / size + 1e-6
    k = np.floor(x).astype(np.int64)
    f = np.clip(x - k, 0.0, 1.0)
    corners = [(dx, dy) for dx in (0, 1) for dy in (0, 1)]
    keys = np.stack([k + np.array(c) for c in corners])
    hats = np.stack([(f[:, 0] if dx else 1.0 - f[:, 0]) * (f[:, 1] if dy else 1.0 - f[:, 1]) for dx, dy in corners])
    return keys, hats


def nodal_pressure(s: np.ndarray, weights: np.ndarray, values: np.ndarray, size: float) -> np.ndarray:
    """The pressure (q,) at the points ``s`` read through the corners of the squares of side
    ``size`` of the tangent plane: each corner's value is the mean int p phi dA / int phi dA
    weighted by its bilinear hat phi over the region (the corner's share of the contact force
    over its share of the area: a lumped L2 projection on the continuous bilinear functions), and
    the values are interpolated back to the points.

    Why. The band traction's penalty term holds what the trilinear jump leaves of a curved gap
    (up to h^2 / (8 R) over a cell of side h on a surface of radius R) times the penalty's
    stiffness, which swings within each cell and biases the cells' plain means where the gap's
    curvature starts (a punch's flat face meeting its rounded edge: the penalty part swings by
    3.2 GPa RMS on the rounded edge against 0.16 GPa on the flat, the stress flux part by 0.27 GPa),
    while the hat-weighted means, the corners' forces, are what the weak form balances where the
    squares are the grid's cells. The reading conserves the force (the hats are a partition of
    unity) and smooths a smooth pressure only at second order, by about p'' h^2 / 6 per direction:
    Hertz's peak by (h / a)^2 / 3, 0.33 % at 10 cells per radius."""
    s = np.asarray(s, dtype=float)
    keys, hats = _corner_weights(s, size)
    _, corner = np.unique(_encode(keys.reshape(-1, 2)), return_inverse=True)
    corner = corner.ravel()
    n = int(corner.max()) + 1 if len(corner) else 0
    hw = (hats * np.asarray(weights, dtype=float)[None, :]).ravel()
    share = np.bincount(corner, weights=hw, minlength=n)
    force = np.bincount(corner, weights=hw * np.tile(np.asarray(values, dtype=float), 4), minlength=n)
    node = force / np.where(share > 0.0, share, 1.0)
    return (node[corner].reshape(hats.shape) * hats).sum(axis=0)
