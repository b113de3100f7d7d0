"""A star-shaped contact region's quadrature graded by the cells it lies in.

The region s = r rho(phi) (a cos phi, b sin phi), r <= 1, is integrated on polar panels cut at
the planes of both bodies' octrees and a collapsed Gauss rule on the pieces
(solver.contact.ellipse_geometry.region_points). Spaced by the finest cell everywhere, a region
that lies mostly in coarser cells (a roller's band of one level with finer cells where its edge
turns) gets four times the points it needs in every cell one level coarser, and its trials cost
as much. Here the panels follow the cells instead:

- angular strips are cut every panel of the edge's length, the panel at each edge point the
  cells' size there (the finer of the two bodies' leaves), so a strip spans about one cell at
  the edge;
- each strip is cut radially into pieces of the cells' size along its rays (the finest of the
  strip's two sides and its middle ray at each radius);
- each panel is cut at the planes of its own cells (the finest leaf at its corners and centre, of
  each body) and again at a finer cell's planes where a piece's centroid lies in one (octree cells
  lie on the lattices origin + j h0 / 2^l, so a piece cut at its box of a level lies in one leaf
  or in a box split into finer leaves; ``clip_to_cells``).

Every piece lies in one cell of each body, as on the finest lattice, so the integrand (trilinear
fields times the smooth gap) is integrated the same way per cell; a region whose cells are all of
the finest size gets the panels of the uniform rule (to round-off).
"""

from __future__ import annotations

import math

import numpy as np

from ..fem.surface_quadrature import MAX_VERTICES, clip_to_grid

__all__ = ["graded_star_panels", "clip_to_cells", "leaf_size", "points_per_cell_face"]

#: radial samples of a strip's cell size per finest panel along its longest ray
RADIAL_SAMPLES_PER_PANEL = 4
#: quadrature points per cell face of the region's area in each cell size, measured on the crowned
#: roller (see docs/contact-3d.md, "The region's quadrature follows the cells")
POINTS_PER_CELL_FACE = 200.0


def leaf_size(grid, finest: float):
    """The cell size at 3D points (n, 3) in an octree ``grid``: its leaf's side, ``finest`` where
    no leaf holds the point."""
    def size(points: np.ndarray) -> np.ndarray:
        cell = grid.locate(np.asarray(points, dtype=float).reshape(-1, 3))
        out = np.full(len(cell), float(finest))
        found = cell >= 0
        out[found] = np.asarray(grid.size)[cell[found]]
        return out

    return size


def graded_star_panels(ranges, a: float, b: float, radius, panel: float, panel_at, samples: int):
    """(r, phi) panels of the star-shaped region over the angular ``ranges``: ``panel_at(s)`` the
    panel's size at tangent-plane points s (n, 2) from the region's centre (at least ``panel``),
    ``samples`` angles per range on which the edge's length is measured."""
    lowers, uppers = [], []
    for t0, t1 in ranges:
        phi = np.linspace(t0, t1, samples + 1)
        edge = radius(phi)[:, None] * np.stack([a * np.cos(phi), b * np.sin(phi)], axis=1)
        steps = np.linalg.norm(np.diff(edge, axis=0), axis=1) / panel_at(0.5 * (edge[1:] + edge[:-1]))
        measure = np.concatenate([[0.0], np.cumsum(steps)])  # the edge's length in local panels
        n_theta = max(2, int(math.ceil(measure[-1])))
        cuts = np.interp(np.linspace(0.0, measure[-1], n_theta + 1), measure, phi)
        ray = np.linalg.norm(edge, axis=1)
        strip = np.clip(np.searchsorted(cuts, phi, side="right") - 1, 0, n_theta - 1)
        longest = np.zeros(n_theta)
        np.maximum.at(longest, strip, ray)
        for k, r in enumerate(_radial_cuts(a, b, radius, cuts, longest, panel, panel_at)):
            lowers.append(np.column_stack([r[:-1], np.full(len(r) - 1, cuts[k])]))
            uppers.append(np.column_stack([r[1:], np.full(len(r) - 1, cuts[k + 1])]))
    return lowers, uppers


def _radial_cuts(a: float, b: float, radius, cuts: np.ndarray, longest: np.ndarray, panel: float, panel_at) -> list:
    """Per strip [cuts[k], cuts[k + 1]], the radii r in [0, 1] cutting it into pieces of the local
    panel's size along its longest ray (``longest[k]``): equal steps of the measure
    int longest / panel_at dr, the panel the smallest on the strip's sides and middle ray."""
    n = RADIAL_SAMPLES_PER_PANEL * max(1, int(math.ceil(float(longest.max()) / panel)))
    r = np.linspace(0.0, 1.0, n + 1)
    mid_r = 0.5 * (r[1:] + r[:-1])
    angles = np.stack([cuts[:-1], 0.5 * (cuts[:-1] + cuts[1:]), cuts[1:]], axis=1)  # (strips, 3)
    direction = radius(angles.ravel())[:, None] * np.stack([a * np.cos(angles.ravel()), b * np.sin(angles.ravel())],
                                                          axis=1)
    s = mid_r[None, :, None] * direction[:, None, :]  # (strips * 3, n, 2)
    local = panel_at(s.reshape(-1, 2)).reshape(len(longest), 3, n).min(axis=1)
    out = []
    for k in range(len(longest)):
        measure = np.concatenate([[0.0], np.cumsum(longest[k] / local[k] / n)])
        n_rho = max(2, int(math.ceil(measure[-1] - 1e-9)))
        out.append(np.interp(np.linspace(0.0, measure[-1], n_rho + 1), measure, r))
    return out


def clip_to_cells(poly, count, owner, lower, upper, corner_points, origin, finest: float, cell_size):
    """Pieces of panels cut at the planes of the cells they lie in, of one body's octree (its
    lattice ``origin``, its ``finest`` cell, ``cell_size(points)`` its leaf size at 3D points):
    each panel first at the planes of the finest leaf at its corners and centre, then each panel
    again at a finer leaf's planes where a piece's centroid lies in one, until none does
    (:func:`solver.fem.surface_quadrature.clip_to_grid` on the panels' affine maps from
    ``corner_points`` (p, 4, 3))."""
    probes = np.concatenate([corner_points, corner_points.mean(axis=1, keepdims=True)], axis=1)
    spacing = np.maximum(cell_size(probes.reshape(-1, 3)).reshape(-1, 5).min(axis=1), finest)
    poly, count, owner = clip_to_grid(poly, count, owner, lower, upper, corner_points, origin, spacing)
    extent = np.where(upper - lower != 0.0, upper - lower, 1.0)
    a_u = (corner_points[:, 1] - corner_points[:, 0]) / extent[:, :1]
    a_v = (corner_points[:, 3] - corner_points[:, 0]) / extent[:, 1:]
    while len(poly):
        valid = np.arange(MAX_VERTICES)[None, :] < count[:, None]
        uv = (poly * valid[:, :, None]).sum(axis=1) / count[:, None]
        d = uv - lower[owner]
        centroid = corner_points[owner, 0] + a_u[owner] * d[:, :1] + a_v[owner] * d[:, 1:]
        finer = np.full(len(lower), np.inf)
        np.minimum.at(finer, owner, cell_size(centroid))
        redo = finer < (1.0 - 1e-9) * spacing
        if not redo.any():
            break
        spacing[redo] = np.maximum(finer[redo], finest)
        sel = redo[owner]
        p2, c2, o2 = clip_to_grid(poly[sel], count[sel], owner[sel], lower, upper, corner_points, origin, spacing)
        poly, count, owner = (np.concatenate([x[~sel], y]) for x, y in ((poly, p2), (count, c2), (owner, o2)))
    return poly, count, owner


def points_per_cell_face(areas_by_cell) -> float:
    """The region quadrature's points estimated from the region's area in each cell size:
    ``areas_by_cell`` pairs (area m^2, cell size m); POINTS_PER_CELL_FACE per cell face of each."""
    return float(sum(POINTS_PER_CELL_FACE * area / size**2 for area, size in areas_by_cell))
