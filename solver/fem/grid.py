"""Background grid of one body: a balanced quadtree of square cells over the body's bounds.

Choice (documented in docs/formulation.md): local refinement by a quadtree. Around each
refinement centre, cells of level l (size h0 / 2^l) are split while their box is closer than
R_l = radius + 2 * sum_{k=l+1}^{levels-1} h_k to the centre. Each level's zone reaches at least
sqrt(2) h_{l+1} beyond the next one, which makes the tree 2:1 balanced by construction (no
balancing pass): a cell never meets a neighbour more than one level finer, so every hanging
node sits at the midpoint of a coarser cell's side and is tied to that side's end nodes,
u_hang = (u_a + u_b) / 2. The constraint matrix T (nodes x free nodes) gives u = T u_free;
chains (a hanging node's parent itself hanging) are resolved by composing T. Every cell keeps
the exact square stiffness of its size.

Cells are classified with the exact boundary curves, not only corner values: each curve is cut
at its exact crossings with the grid lines of the cells near the boundary, so every piece of the
boundary lies in exactly one leaf. A leaf holding a piece is a cut cell (slivers and bulges
through one side included); a piece running along a grid line is given to the cell on the
material side (its midpoint nudged inward). Other cells are inside or outside by the sign of
the signed distance at their centre (they are farther than their half diagonal from the
boundary, or hold no piece of it). Outside cells are dropped.

Cut cells whose inside part is less than ``aggregation_threshold`` (QUADTREE_AGGREGATION_THRESHOLD)
of the square join the
aggregate of a well-supported cell (solver.fem.aggregation, shared with the octree): the nodes
only such cells hold lose their unknowns and follow the root cell's bilinear field, composed with
the hanging-node constraint as T' = T E; the band thickness of a cell is its aggregate's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np
import scipy.sparse as sp

from .aggregation import ExtendableNodes, aggregate_thickness
from .integration import (
    Polyline,
    curve_gauss,
    full_cell_moments,
    piece_moments,
    polygon_contains,
    vertical_side_moments,
)

__all__ = [
    "INSIDE",
    "CUT",
    "RefinementZone",
    "Boundary",
    "Pieces",
    "Grid",
    "build_grid",
    "refinement_radii",
    "grid_origin",
    "assign_to_material_side",
    "QUADTREE_AGGREGATION_THRESHOLD",
]

INSIDE = 1
CUT = 2

#: inside area share of its square below which a quadtree cell joins an aggregate
#: (solver.fem.aggregation). Lower than the octree's 0.05: it removes the slivers an edge a
#: round-off above a grid line leaves (inside share ~1e-9, indefinite K0: 21-102 negative pivots
#: in the shipped examples with grid_offset [0, 1e-9]; none after, min|pivot| / max 1.7e-7 ...
#: 1.4e-5 as with the default offset) and leaves the ordinary curved cuts alone (the default
#: offset's a, c and N move by < 1e-5 relative; 0.05 moves them up to 7e-4, see docs/formulation.md)
QUADTREE_AGGREGATION_THRESHOLD = 1e-3

# Transition width per level in cells of that level (>= sqrt(2) keeps the tree 2:1 balanced).
GRADING_CELLS = 2.0


@dataclass(frozen=True)
class RefinementZone:
    levels: int
    radius: float
    center: np.ndarray


class Curve(Protocol):  # the part of geometry.bounded.BoundedCurve the grid needs
    name: str
    t_start: float
    t_end: float

    def evaluate(self, t): ...
    def derivative(self, t): ...
    def axis_crossings(self, axis: int, value: float): ...


@dataclass
class Boundary:
    """The boundary a grid is cut by: named oriented curves (material on their left, normals
    outward), the signed distance (positive inside) and, for a tessellated boundary, the
    polygon loops used for inside tests (the curves then deviate from the signed distance's
    zero set by up to ``tolerance``)."""

    curves: dict[str, Curve]
    signed_distance: Callable[[np.ndarray], np.ndarray]
    bounds: tuple[np.ndarray, np.ndarray]
    tolerance: float = 0.0
    polygon_loops: list[np.ndarray] | None = None

    @property
    def exact(self) -> bool:
        return self.polygon_loops is None

    def inside(self, points: np.ndarray, phi: np.ndarray | None = None) -> np.ndarray:
        """Inside test consistent with the curves (exact: phi > 0; tessellated: the polygon)."""
        if phi is None:
            phi = self.signed_distance(points)
        if self.polygon_loops is None:
            return phi > 0.0
        result = phi > 0.0
        near = np.abs(phi) <= 2.0 * self.tolerance
        if near.any():
            result[near] = polygon_contains(points[near], self.polygon_loops)
        return result


@dataclass
class Pieces:
    """Pieces of the boundary curves, each inside one leaf cell: curve name per piece (via
    ``curve_names[curve]``), parameter interval [t0, t1], and the cell holding it."""

    curve_names: list[str]
    curve: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    cell: np.ndarray

    def of(self, name: str) -> np.ndarray:
        """Indices of the pieces of one curve."""
        if name not in self.curve_names:
            raise KeyError(name)
        return np.nonzero(self.curve == self.curve_names.index(name))[0]


@dataclass
class Grid(ExtendableNodes):
    origin: np.ndarray
    h0: float
    shape: tuple[int, int]
    max_level: int
    level: np.ndarray  # (m,) leaf levels
    index: np.ndarray  # (m, 2) leaf (i, j) at their level
    status: np.ndarray  # (m,) INSIDE or CUT
    moments: np.ndarray  # (m, 3, 3) local moments of the inside part
    pieces: Pieces
    boundary_length: np.ndarray = field(repr=False, default=None)  # (m,) boundary length inside each cell
    nodes: np.ndarray = field(repr=False, default=None)  # (N, 2)
    cells: np.ndarray = field(repr=False, default=None)  # (m, 4) CCW node indices
    constraint: sp.csr_matrix = field(repr=False, default=None)  # (N, Nf): u_nodes = T u_free
    free_nodes: np.ndarray = field(repr=False, default=None)

    @property
    def size(self) -> np.ndarray:
        """Cell sizes (computed once per cell table: ``level`` is replaced, never edited)."""
        cached = self.__dict__.get("_size")
        if cached is None or cached[0] is not self.level:
            cached = (self.level, self.h0 / 2.0 ** self.level)
            self.__dict__["_size"] = cached
        return cached[1]

    @property
    def lower(self) -> np.ndarray:
        return self.origin + self.index * self.size[:, None]

    @property
    def center(self) -> np.ndarray:
        return self.lower + 0.5 * self.size[:, None]

    @property
    def inside_fraction(self) -> np.ndarray:
        return self.moments[:, 0, 0] / 4.0

    @property
    def inside_area(self) -> np.ndarray:
        return self.moments[:, 0, 0] * (0.5 * self.size) ** 2

    @property
    def material_thickness(self) -> np.ndarray:
        """Local size available to a boundary band: min(h, 2 A / L) with A the inside area and L
        the boundary length (h for a cell cut in half by a straight line, the sliver's width for a
        sliver), taken over the cell's aggregate when the cells are aggregated (a sliver's points
        then see its root cell's field: their band is sized by the aggregate, not by the sliver)."""
        return aggregate_thickness(self.cell_roots, self.size, self.inside_area, self.boundary_length)

    @property
    def min_size(self) -> float:
        return float(self.size.min())

    def locate(self, points: np.ndarray) -> np.ndarray:
        """Leaf index of each point (n,), -1 where no active cell holds it. Points on a shared
        side go to the cell above/right; points on the grid's upper/right border are found by
        retrying with a tiny downward/leftward nudge."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        cell = self._locate(points)
        eps = 1e-9 * self.min_size
        for shift in ((-eps, 0.0), (0.0, -eps), (-eps, -eps)):
            miss = cell < 0
            if not miss.any():
                break
            cell[miss] = self._locate(points[miss] + np.array(shift))
        return cell

    def _locate(self, points: np.ndarray) -> np.ndarray:
        cell = np.full(len(points), -1, dtype=np.int64)
        for lv, (keys, order, ny_l, nx_l) in self._level_tables().items():
            h = self.h0 / 2.0**lv
            ij = np.floor((points - self.origin) / h).astype(np.int64)
            ok = (ij[:, 0] >= 0) & (ij[:, 1] >= 0) & (ij[:, 0] < nx_l) & (ij[:, 1] < ny_l)
            key = ij[:, 0] * ny_l + ij[:, 1]
            pos = np.searchsorted(keys, key)
            pos = np.minimum(pos, len(keys) - 1)
            hit = ok & (keys[pos] == key)
            cell[hit] = order[pos[hit]]
        return cell

    def _level_tables(self):
        if getattr(self, "_tables", None) is None:
            tables = {}
            for lv in np.unique(self.level):
                idx = np.nonzero(self.level == lv)[0]
                ny_l = self.shape[1] * 2 ** int(lv)
                nx_l = self.shape[0] * 2 ** int(lv)
                keys = self.index[idx, 0].astype(np.int64) * ny_l + self.index[idx, 1]
                o = np.argsort(keys)
                tables[int(lv)] = (keys[o], idx[o], ny_l, nx_l)
            self._tables = tables
        return self._tables

    def local_coordinates(self, points: np.ndarray, cell: np.ndarray) -> np.ndarray:
        """(xi, eta) in [-1, 1]^2 of points in their cells."""
        return 2.0 * (points - self.center[cell]) / self.size[cell, None]


def refinement_radii(zone: RefinementZone, h0: float) -> np.ndarray:
    """R_l for l = 0..levels-1: cells of level l closer than R_l to the centre are split."""
    h = h0 / 2.0 ** np.arange(zone.levels + 1)
    radii = np.empty(zone.levels)
    for lv in range(zone.levels):
        radii[lv] = zone.radius + GRADING_CELLS * h[lv + 1 : zone.levels].sum()
    return radii


def grid_origin(lower, offset, h0: float) -> np.ndarray:
    """Origin of a background grid of spacing ``h0`` over a box whose lower corner is ``lower``,
    shifted down/left by ``offset`` fractions of ``h0`` (per axis). A shift outside [0, 1] is
    first brought into [0, 1) by whole cells: the grid lines are the same, and the origin stays at
    or below the box's lower corner, so the grid still covers the box (a negative shift would
    otherwise leave the box's lower strip, and the boundary in it, outside every cell)."""
    f = np.asarray(offset, dtype=float)
    if not np.all(np.isfinite(f)):
        raise ValueError(f"grid offset must be finite numbers (fractions of the element size), got {offset!r}")
    f = np.where((f >= 0.0) & (f <= 1.0), f, f - np.floor(f))
    return np.asarray(lower, dtype=float) - f * h0


def _box_distance(lower, size, center):
    d = np.maximum(np.maximum(lower - center, 0.0), center - (lower + size[:, None]))
    return np.hypot(d[:, 0], d[:, 1])


def build_grid(
    boundary: Boundary,
    element_size: float,
    refinements: tuple[RefinementZone, ...] = (),
    offset: tuple[float, float] = (0.0, 0.0),
    curve_order: int = 8,
    aggregation_threshold: float | None = QUADTREE_AGGREGATION_THRESHOLD,
) -> Grid:
    """Quadtree grid of spacing ``element_size`` over the boundary's bounds, refined around
    the zones, classified and with the cut cells' moments on the given boundary.

    ``offset`` shifts the grid origin down/left by a fraction of ``element_size`` (grid
    placement studies; any finite shift, taken modulo one cell by :func:`grid_origin`); ``curve_order`` is the Gauss order on each boundary piece; cells whose
    inside part is less than ``aggregation_threshold`` of the square are aggregated to
    well-supported ones (solver.fem.aggregation; None: not at all).
    """
    h0 = float(element_size)
    if not (h0 > 0.0 and math.isfinite(h0)):
        raise ValueError(f"element_size must be a positive number, got {element_size!r}")
    for z in refinements:
        if int(z.levels) != z.levels or z.levels < 0:
            raise ValueError(f"refinement levels must be a non-negative integer, got {z.levels!r}")
        if not (z.radius >= 0.0):
            raise ValueError(f"refinement radius must be >= 0, got {z.radius!r}")
    bmin, bmax = (np.asarray(b, dtype=float) for b in boundary.bounds)
    origin = grid_origin(bmin, offset, h0)
    # floor + 1: the grid covers the bounds strictly, whatever the round-off (a column of cells
    # beyond an edge lying on a grid line holds no material and is dropped)
    shape = np.floor((bmax - origin) / h0).astype(int) + 1
    max_level = max([int(z.levels) for z in refinements], default=0)
    tol = boundary.tolerance

    def keep(lower, size):
        c = lower + 0.5 * size[:, None]
        phi = boundary.signed_distance(c)
        return phi > -(size * (0.5 * math.sqrt(2.0) * (1 + 1e-9)) + tol + 1e-12 * h0), phi

    index, level, phi = _quadtree_cells(origin, shape, h0, refinements, keep)

    grid = Grid(
        origin=origin,
        h0=h0,
        shape=(int(shape[0]), int(shape[1])),
        max_level=max_level,
        level=level,
        index=index,
        status=np.zeros(len(level), dtype=np.int8),
        moments=np.zeros((len(level), 3, 3)),
        pieces=None,
    )
    _classify(grid, boundary, phi, h0)
    _cut_moments(grid, boundary, curve_order)
    _nodes_and_constraints(grid)
    if aggregation_threshold is not None:
        grid.aggregate_cells(grid.inside_fraction, aggregation_threshold)
    return grid



def _quadtree_cells(origin, shape, h0: float, refinements, keep):
    """Cells (index, level, phi at the centre) of the background grid kept by ``keep`` and
    split level by level where a zone asks for finer cells."""
    ii, jj = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
    index = np.stack([ii.ravel(), jj.ravel()], axis=1)
    level = np.zeros(len(index), dtype=np.int64)
    size0 = np.full(len(index), h0)
    k, phi = keep(origin + index * h0, size0)
    index, level, phi = index[k], level[k], phi[k]
    max_level = max([int(z.levels) for z in refinements], default=0)
    zones = [(z, refinement_radii(z, h0)) for z in refinements]
    for lv in range(max_level):
        at = level == lv
        split = np.zeros(len(level), dtype=bool)
        idx = np.nonzero(at)[0]
        h = h0 / 2.0**lv
        lower = origin + index[idx] * h
        for z, radii in zones:
            if z.levels > lv:
                split[idx] |= _box_distance(lower, np.full(len(idx), h), np.asarray(z.center, float)) < radii[lv]
        if not split.any():
            continue
        parents = index[split]
        child = (2 * parents[:, None, :] + np.array([[0, 0], [1, 0], [0, 1], [1, 1]])[None]).reshape(-1, 2)
        hc = h / 2.0
        kc, phic = keep(origin + child * hc, np.full(len(child), hc))
        index = np.concatenate([index[~split], child[kc]])
        level = np.concatenate([level[~split], np.full(kc.sum(), lv + 1)])
        phi = np.concatenate([phi[~split], phic[kc]])
    return index, level, phi


def _classify(grid: Grid, boundary: Boundary, phi: np.ndarray, h0: float) -> None:
    """Cut (the boundary crosses the cell), inside or dropped; cells renumbered, pieces kept."""
    level, index, tol = grid.level, grid.index, boundary.tolerance
    size = grid.size
    candidate = np.abs(phi) <= size * (0.5 * math.sqrt(2.0) * (1 + 1e-9)) + tol + 1e-12 * h0
    pieces = _cut_pieces(grid, boundary, candidate)
    has_piece = np.zeros(len(level), dtype=bool)
    has_piece[pieces.cell] = True
    inside = phi > 0.0
    amb = candidate & ~has_piece
    if amb.any():
        inside[amb] = boundary.inside(grid.center[amb], phi[amb])
    active = has_piece | inside
    # drop outside cells and renumber
    new_id = np.cumsum(active) - 1
    grid.level, grid.index = level[active], index[active]
    grid.status = np.where(has_piece[active], CUT, INSIDE).astype(np.int8)
    pieces.cell = new_id[pieces.cell]
    grid.pieces = pieces
    grid._tables = None
    grid.moments = np.broadcast_to(full_cell_moments(), (len(grid.level), 3, 3)).copy()
    grid.boundary_length = np.zeros(len(grid.level))


def _curve_bbox(curve, pad):
    t = np.linspace(curve.t_start, curve.t_end, 257)
    p = np.asarray(curve.evaluate(t), dtype=float)
    lo, hi = p.min(axis=0), p.max(axis=0)
    span = float(np.max(hi - lo))
    return lo - pad - 1e-3 * span, hi + pad + 1e-3 * span


def _kinks(curve) -> np.ndarray:
    """Parameters where the curve may not be smooth (polyline vertices, spline knots): pieces
    are split there so the Gauss rule on each piece sees a smooth integrand."""
    f = getattr(curve, "breakpoints", None) or getattr(curve, "_breakpoints", None)
    return np.asarray(f(), dtype=float).ravel() if f is not None else np.zeros(0)


def _crossings(curve, axis: int, values: np.ndarray) -> np.ndarray:
    """Parameters of the curve's crossings with lines coordinate[axis] = value. One call per
    grid line (the BoundedCurve API takes one value): O(sqrt(cells)) calls, not per cell."""
    out = []
    for v in values:
        t = np.asarray(curve.axis_crossings(axis, float(v)), dtype=float).ravel()
        if t.size:
            out.append(t)
    return np.concatenate(out) if out else np.zeros(0)


def _grid_lines(values: np.ndarray, h_min: float) -> np.ndarray:
    """The distinct cell-line coordinates among ``values`` (the same line from two cells may
    differ in its last bits), each kept exact: merged within 1e-9 of the finest cell, not
    rounded to a number of decimals (a line rounded to 1e-12 m lies 2.5e-6 of a 4e-7 m cell off
    the cell's side, beyond the side's own tolerance of 1e-6 of the cell, and the cut cell's
    area came out 7 % of the cell wrong: negative stiffness on deep refinements)."""
    v = np.sort(np.asarray(values, dtype=float))
    if len(v) == 0:
        return v
    keep = np.concatenate([[True], np.diff(v) > 1e-9 * h_min])
    return v[keep]


def _cut_pieces(grid: Grid, boundary: Boundary, candidate: np.ndarray) -> Pieces:
    lower = grid.lower[candidate]
    size = grid.size[candidate]
    h_min = grid.h0 / 2.0**grid.max_level
    xs = _grid_lines(np.concatenate([lower[:, 0], lower[:, 0] + size]), h_min)
    ys = _grid_lines(np.concatenate([lower[:, 1], lower[:, 1] + size]), h_min)
    names = list(boundary.curves)
    cid, t0s, t1s, cells = [], [], [], []
    for k, name in enumerate(names):
        curve = boundary.curves[name]
        lo, hi = _curve_bbox(curve, grid.h0)
        tx = _crossings(curve, 0, xs[(xs >= lo[0]) & (xs <= hi[0])])
        ty = _crossings(curve, 1, ys[(ys >= lo[1]) & (ys <= hi[1])])
        ta, tb = float(curve.t_start), float(curve.t_end)
        kinks = _kinks(curve)
        t = np.concatenate([[ta, tb], tx, ty, kinks])
        t = t[np.isfinite(t) & (t >= min(ta, tb)) & (t <= max(ta, tb))]
        t = np.unique(t)
        if tb < ta:
            t = t[::-1]
        t0, t1 = t[:-1], t[1:]
        # drop pieces shorter than round-off (double crossings at corners)
        p0 = np.asarray(curve.evaluate(t0), float).reshape(-1, 2)
        p1 = np.asarray(curve.evaluate(t1), float).reshape(-1, 2)
        tm = 0.5 * (t0 + t1)
        pm = np.asarray(curve.evaluate(tm), float).reshape(-1, 2)
        extent = np.maximum(np.hypot(*(p1 - p0).T), np.hypot(*(pm - p0).T))
        ok = extent > 1e-12 * h_min
        t0, t1, tm, pm = t0[ok], t1[ok], tm[ok], pm[ok]
        d = np.asarray(curve.derivative(tm), float).reshape(-1, 2)
        n = np.stack([d[:, 1], -d[:, 0]], axis=1) / np.hypot(d[:, 0], d[:, 1])[:, None]
        cell = assign_to_material_side(grid, pm, -n)
        if (cell < 0).any():
            bad = pm[cell < 0][0]
            raise RuntimeError(f"boundary piece of {name!r} near {bad.tolist()} lies in no grid cell")
        cid.append(np.full(len(t0), k))
        t0s.append(t0)
        t1s.append(t1)
        cells.append(cell)
    cat = lambda a, dt: np.concatenate(a).astype(dt) if a else np.zeros(0, dt)  # noqa: E731
    return Pieces(names, cat(cid, np.int64), cat(t0s, float), cat(t1s, float), cat(cells, np.int64))


# Relative distance (in local cell coordinates) below which a point counts as lying on a side.
ON_SIDE = 1e-11


def assign_to_material_side(grid: Grid, points: np.ndarray, inward: np.ndarray) -> np.ndarray:
    """Cell holding each piece midpoint; a midpoint on a cell side (a piece along a grid line)
    goes to the cell on the material side (``inward`` direction)."""
    cell = grid.locate(points)
    off = np.flatnonzero(cell < 0)
    if len(off):  # a midpoint on the grid's own border, outside it by round-off only (a curve's extreme
        # point on the body's box: the grid starts there) belongs to the border's cell
        box_lo = np.asarray(grid.origin, float)
        box_hi = box_lo + np.asarray(grid.shape, float) * grid.h0
        eps = 1e-9 * grid.h0
        near = np.all((points[off] > box_lo - eps) & (points[off] < box_hi + eps), axis=1)
        cell[off[near]] = grid.locate(np.clip(points[off[near]], box_lo + eps, box_hi - eps))
        if (cell < 0).any():
            return cell
    lower, size = grid.lower[cell], grid.size[cell]
    loc = 2.0 * (points - lower) / size[:, None] - 1.0
    moved = points.copy()
    for axis in (0, 1):
        down = (loc[:, axis] <= -1.0 + ON_SIDE) & (inward[:, axis] < -1e-6)
        up = (loc[:, axis] >= 1.0 - ON_SIDE) & (inward[:, axis] > 1e-6)
        moved[down, axis] = lower[down, axis] - 1e-9 * size[down]
        moved[up, axis] = lower[up, axis] + size[up] * (1.0 + 1e-9)
    change = np.nonzero(np.any(moved != points, axis=1))[0]
    if len(change):
        # a midpoint on the grid's own border (a piece ending at a corner of the body's box, whose
        # normal leans outwards) has no cell beyond: it stays in the cell that holds it
        across = grid.locate(moved[change])
        keep = across >= 0
        cell[change[keep]] = across[keep]
    return cell


def _cut_moments(grid: Grid, boundary: Boundary, order: int) -> None:
    cut = np.nonzero(grid.status == CUT)[0]
    if len(cut) == 0:
        return
    mom = np.zeros((len(grid.level), 3, 3))
    center, size = grid.center, grid.size
    pc = grid.pieces
    ends = []  # (cell, point) of piece end points
    for k, name in enumerate(pc.curve_names):
        sel = np.nonzero(pc.curve == k)[0]
        if len(sel) == 0:
            continue
        curve = boundary.curves[name]
        cell = pc.cell[sel]
        pts, w, nrm, _ = curve_gauss(curve, pc.t0[sel], pc.t1[sel], order)
        contrib = piece_moments(pts, w, nrm, center[cell], size[cell])
        np.add.at(mom, cell, contrib)
        np.add.at(grid.boundary_length, cell, w.sum(axis=1))
        ends.append((cell, np.asarray(curve.evaluate(pc.t0[sel]), float).reshape(-1, 2)))
        ends.append((cell, np.asarray(curve.evaluate(pc.t1[sel]), float).reshape(-1, 2)))
    # vertical sides: breakpoints = side ends + piece end points lying on the side
    lower = grid.lower
    rec_cell, rec_side, rec_y = [], [], []
    for side, xoff in ((-1, 0.0), (1, 1.0)):
        rec_cell += [cut, cut]
        rec_side += [np.full(len(cut), side)] * 2
        rec_y += [lower[cut, 1], lower[cut, 1] + size[cut]]
        for cell, p in ends:
            xs = lower[cell, 0] + xoff * size[cell]
            on = np.abs(p[:, 0] - xs) <= 1e-6 * size[cell]  # generous: extra breakpoints are harmless
            rec_cell.append(cell[on])
            rec_side.append(np.full(on.sum(), side))
            rec_y.append(np.clip(p[on, 1], lower[cell[on], 1], lower[cell[on], 1] + size[cell[on]]))
    c = np.concatenate(rec_cell)
    s = np.concatenate(rec_side)
    y = np.concatenate(rec_y)
    o = np.lexsort((y, s, c))
    c, s, y = c[o], s[o], y[o]
    same = (c[1:] == c[:-1]) & (s[1:] == s[:-1])
    y0, y1, c, s = y[:-1][same], y[1:][same], c[:-1][same], s[:-1][same]
    long_enough = (y1 - y0) > 1e-12 * size[c]
    y0, y1, c, s = y0[long_enough], y1[long_enough], c[long_enough], s[long_enough]
    x = lower[c, 0] + (s > 0) * size[c]
    mid = np.stack([x, 0.5 * (y0 + y1)], axis=1)
    phi = boundary.signed_distance(mid)
    on_boundary = np.abs(phi) <= 0.5 * ON_SIDE * size[c]
    ins = boundary.inside(mid, phi) & ~on_boundary
    c, s, y0, y1 = c[ins], s[ins], y0[ins], y1[ins]
    eta0 = 2.0 * (y0 - center[c, 1]) / size[c]
    eta1 = 2.0 * (y1 - center[c, 1]) / size[c]
    np.add.at(mom, c, vertical_side_moments(eta0, eta1, s))
    grid.moments[cut] = mom[cut]


def _nodes_and_constraints(grid: Grid) -> None:
    L = grid.max_level
    s = (2 ** (L - grid.level)).astype(np.int64)
    i0, j0 = grid.index[:, 0] * s, grid.index[:, 1] * s
    ny_f = grid.shape[1] * 2**L + 1
    cx = np.stack([i0, i0 + s, i0 + s, i0], axis=1)
    cy = np.stack([j0, j0, j0 + s, j0 + s], axis=1)
    keys = cx * ny_f + cy
    node_keys, inverse = np.unique(keys.ravel(), return_inverse=True)
    grid.cells = inverse.reshape(-1, 4)
    h_f = grid.h0 / 2.0**L
    grid.nodes = grid.origin + h_f * np.stack([node_keys // ny_f, node_keys % ny_f], axis=1)
    n = len(node_keys)
    # side midpoints of cells bigger than the finest: a node there hangs on the side's ends
    big = np.nonzero(s >= 2)[0]
    half = s[big] // 2
    mx = np.stack([i0[big] + half, i0[big] + s[big], i0[big] + half, i0[big]], axis=1)
    my = np.stack([j0[big], j0[big] + half, j0[big] + s[big], j0[big] + half], axis=1)
    mkey = (mx * ny_f + my).ravel()
    pos = np.minimum(np.searchsorted(node_keys, mkey), n - 1)
    hit = node_keys[pos] == mkey
    corners = grid.cells[big]
    pa = corners[:, [0, 1, 2, 3]].ravel()
    pb = corners[:, [1, 2, 3, 0]].ravel()
    hang, first = np.unique(pos[hit], return_index=True)
    a, b = pa[hit][first], pb[hit][first]
    free = np.ones(n, dtype=bool)
    free[hang] = False
    rows = np.concatenate([np.nonzero(free)[0], hang, hang])
    cols = np.concatenate([np.nonzero(free)[0], a, b])
    vals = np.concatenate([np.ones(free.sum()), np.full(len(hang), 0.5), np.full(len(hang), 0.5)])
    p = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    t = p
    for _ in range(64):  # resolve chains: hanging parents of hanging nodes
        if not t[:, hang].count_nonzero():
            break
        t = (t @ p).tocsr()
    else:  # pragma: no cover - impossible for a balanced tree
        raise RuntimeError("hanging-node constraints do not resolve")
    grid.free_nodes = np.nonzero(free)[0]
    grid.constraint = t[:, grid.free_nodes].tocsr()


def polyline_boundary(loops: list[dict[str, np.ndarray]], signed_distance=None, tolerance: float = 0.0) -> Boundary:
    """Boundary made of polylines: ``loops`` is a list of {edge name: vertices} in loop order
    (material on the left). Used for the tessellated variant and for geometry-free tests; the
    signed distance defaults to the exact distance to the polygon."""
    curves = {}
    polys = []
    for loop in loops:
        verts = []
        for name, v in loop.items():
            curves[name] = Polyline(name, np.asarray(v, dtype=float))
            verts.append(np.asarray(v, dtype=float)[:-1])
        polys.append(np.concatenate(verts))
    allv = np.concatenate(polys)
    bounds = (allv.min(axis=0), allv.max(axis=0))

    if signed_distance is None:

        def signed_distance(points):
            points = np.asarray(points, dtype=float).reshape(-1, 2)
            a = np.concatenate(polys)
            b = np.concatenate([np.roll(lp, -1, axis=0) for lp in polys])
            d = np.full(len(points), np.inf)
            step = max(1, 2_000_000 // len(a))
            for s0 in range(0, len(points), step):
                p = points[s0 : s0 + step, None, :]
                ab = b - a
                t = np.clip(np.einsum("pkd,kd->pk", p - a, ab) / np.einsum("kd,kd->k", ab, ab), 0, 1)
                q = a + t[..., None] * ab
                d[s0 : s0 + step] = np.min(np.hypot(*(p - q).transpose(2, 0, 1)), axis=1)
            sign = np.where(polygon_contains(points, polys), 1.0, -1.0)
            return sign * d

        return Boundary(curves, signed_distance, bounds, 0.0, None)
    return Boundary(curves, signed_distance, bounds, tolerance, polys)
