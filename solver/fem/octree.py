"""Background grid of a 3D body: a 2:1-graded octree of cube cells (the quadtree of
solver.fem.grid in one more dimension).

Refinement follows the same rule as in 2D (``grid.refinement_radii``): around each zone's
centre, cells of level l (size h0 / 2^l) are split while their box is closer than R_l to the
centre; each level's zone reaches GRADING_CELLS = 2 cells of the next level beyond the next one,
more than the sqrt(3) a cube's diagonal needs, so the tree is 2:1 balanced by construction
(:func:`level_jumps` checks it). Cells the ``keep`` test rejects (farther than their half
diagonal outside the body) are dropped as they are made.

Nodes are the corners of the leaves. A node hangs when it lies inside an edge of a coarser leaf
(then u = (u_a + u_b) / 2 with the edge's ends) or inside one of its faces (u = the mean of the
face's four corners); chains are resolved by composing the constraints, as in 2D. The constraint
matrix T (nodes x free nodes) gives u = T u_free, so trilinear fields stay conforming. A body's
aggregation of its ill-supported cut cells (solver.fem.aggregation) then takes the unknowns of
some free nodes away (:meth:`Octree.extend`): T stays the map from the unknowns to every node.

Corner order of a cell (x fastest): (0,0,0), (1,0,0), (1,1,0), (0,1,0), (0,0,1), (1,0,1),
(1,1,1), (0,1,1), the reference corners of solver.fem.hexahedra.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse as sp

from .aggregation import ExtendableNodes
from .grid import RefinementZone, grid_origin, refinement_radii

__all__ = ["Octree", "build_octree", "level_jumps", "CORNERS"]

CORNERS = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.int64
)
# the 12 edges and 6 faces of a cell as corner indices
EDGES = np.array([[0, 1], [1, 2], [3, 2], [0, 3], [4, 5], [5, 6], [7, 6], [4, 7], [0, 4], [1, 5], [2, 6], [3, 7]])
FACES = np.array([[0, 3, 7, 4], [1, 2, 6, 5], [0, 1, 5, 4], [3, 2, 6, 7], [0, 1, 2, 3], [4, 5, 6, 7]])


@dataclass
class Octree(ExtendableNodes):
    origin: np.ndarray  # (3,)
    h0: float
    shape: tuple[int, int, int]
    max_level: int
    level: np.ndarray  # (m,) leaf levels
    index: np.ndarray  # (m, 3) leaf (i, j, k) at their level
    nodes: np.ndarray = field(repr=False, default=None)  # (N, 3)
    cells: np.ndarray = field(repr=False, default=None)  # (m, 8) node indices, CORNERS order
    constraint: sp.csr_matrix = field(repr=False, default=None)  # (N, Nf): u_nodes = T u_free
    free_nodes: np.ndarray = field(repr=False, default=None)

    @functools.cached_property
    def size(self) -> np.ndarray:
        return self.h0 / 2.0**self.level

    @functools.cached_property
    def lower(self) -> np.ndarray:
        return self.origin + self.index * self.size[:, None]

    @functools.cached_property
    def center(self) -> np.ndarray:
        return self.lower + 0.5 * self.size[:, None]

    @functools.cached_property
    def min_size(self) -> float:
        return float(self.size.min())

    @functools.cached_property
    def _level_keys(self) -> list[tuple[int, np.ndarray, np.ndarray, np.ndarray]]:
        """Per level: (level, index dims, sorted keys of its leaves, the leaves in that order)
        (the octree does not change once built: computed on the first :meth:`locate`)."""
        out = []
        for lv in np.unique(self.level):
            idx = np.flatnonzero(self.level == lv)
            dims = np.asarray(self.shape, dtype=np.int64) * 2 ** int(lv)
            keys = _keys(self.index[idx], dims)
            order = np.argsort(keys)
            out.append((int(lv), dims, keys[order], idx[order]))
        return out

    def locate(self, points: np.ndarray) -> np.ndarray:
        """Leaf index of each point (n,), -1 where no leaf holds it (points on a shared face go
        to the cell on its upper side)."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        cell = np.full(len(points), -1, dtype=np.int64)
        left = None  # the points no finer level holds (None: all of them)
        # finest level first, each point looked up until a leaf holds it (a point that rounds into
        # leaves of two levels goes to the finer, as when every level was looked up coarsest first
        # and the later hit kept): the refined contact's points leave after one level
        for lv, dims, keys, idx in reversed(self._level_keys):
            p = points if left is None else points[left]
            if not len(p):
                break
            ijk = np.floor((p - self.origin) / (self.h0 / 2.0**lv)).astype(np.int64)
            ok = (ijk[:, 0] >= 0) & (ijk[:, 0] < dims[0]) & (ijk[:, 1] >= 0) & (ijk[:, 1] < dims[1]) \
                & (ijk[:, 2] >= 0) & (ijk[:, 2] < dims[2])  # column by column: faster than .all(axis=1)
            key = _keys(np.where(ok[:, None], ijk, 0), dims)
            pos = np.minimum(np.searchsorted(keys, key), len(keys) - 1)
            hit = ok & (keys[pos] == key)
            rows = np.flatnonzero(hit) if left is None else left[hit]
            cell[rows] = idx[pos[hit]]
            left = np.flatnonzero(~hit) if left is None else left[~hit]
        return cell

    def local_coordinates(self, points: np.ndarray, cell: np.ndarray) -> np.ndarray:
        """(xi, eta, zeta) in [-1, 1]^3 of points in their cells."""
        return 2.0 * (points - self.center[cell]) / self.size[cell, None]


def _keys(ijk: np.ndarray, dims) -> np.ndarray:
    ijk = np.asarray(ijk, dtype=np.int64)
    return (ijk[:, 0] * dims[1] + ijk[:, 1]) * dims[2] + ijk[:, 2]


def _box_distance(lower: np.ndarray, size: np.ndarray, center: np.ndarray) -> np.ndarray:
    d = np.maximum(np.maximum(lower - center, center - (lower + size[:, None])), 0.0)
    return np.sqrt((d * d).sum(axis=1))


KeepTest = Callable[[np.ndarray, np.ndarray], np.ndarray]


def build_octree(bounds, element_size: float, refinements: tuple[RefinementZone, ...] = (),
                 keep: KeepTest | None = None, offset=(0.0, 0.0, 0.0)) -> Octree:
    """Octree of spacing ``element_size`` over ``bounds`` = (min (3,), max (3,)), refined around
    the zones; ``keep(lower (k, 3), size (k,)) -> bool (k,)`` drops cells (all kept when None).
    ``offset`` shifts the origin down by fractions of ``element_size`` (any finite shift, taken
    modulo one cell by :func:`solver.fem.grid.grid_origin`, so the octree covers ``bounds``)."""
    h0 = float(element_size)
    if not (h0 > 0.0 and np.isfinite(h0)):
        raise ValueError(f"element_size must be a positive number, got {element_size!r}")
    bmin, bmax = (np.asarray(b, dtype=float).reshape(3) for b in bounds)
    origin = grid_origin(bmin, offset, h0)
    shape = np.floor((bmax - origin) / h0).astype(np.int64) + 1
    keep = keep or (lambda lower, size: np.ones(len(size), dtype=bool))
    grid = np.stack(np.meshgrid(*(np.arange(n) for n in shape), indexing="ij"), axis=-1).reshape(-1, 3)
    index = grid[keep(origin + grid * h0, np.full(len(grid), h0))]
    level = np.zeros(len(index), dtype=np.int64)
    max_level = max([int(z.levels) for z in refinements], default=0)
    zones = [(z, refinement_radii(z, h0)) for z in refinements]
    for lv in range(max_level):
        h = h0 / 2.0**lv
        idx = np.flatnonzero(level == lv)
        lower = origin + index[idx] * h
        split = np.zeros(len(level), dtype=bool)
        for z, radii in zones:
            if z.levels > lv:
                split[idx] |= _box_distance(lower, np.full(len(idx), h), np.asarray(z.center, float)) < radii[lv]
        if not split.any():
            continue
        child = (2 * index[split][:, None, :] + CORNERS[None]).reshape(-1, 3)
        kept = keep(origin + child * (h / 2.0), np.full(len(child), h / 2.0))
        index = np.concatenate([index[~split], child[kept]])
        level = np.concatenate([level[~split], np.full(int(kept.sum()), lv + 1)])
    tree = Octree(origin=origin, h0=h0, shape=tuple(int(n) for n in shape), max_level=max_level, level=level,
                  index=index)
    _nodes_and_constraints(tree)
    return tree


def _corner_keys(tree: Octree, offsets: np.ndarray, cells: np.ndarray | None = None) -> np.ndarray:
    """Keys at the finest level of points ``lower + offsets * size`` of cells (offsets in cell
    units, integers or halves: (..., 3) scaled by 2 to stay integer)."""
    L = tree.max_level
    sel = np.arange(len(tree.level)) if cells is None else cells
    s = (2 ** (L - tree.level[sel])).astype(np.int64)  # cell size in finest units
    base = tree.index[sel] * s[:, None]
    pts = base[:, None, :] + (offsets[None] * s[:, None, None]) // 2
    dims = np.asarray(tree.shape, dtype=np.int64) * 2**L + 1
    return _keys(pts.reshape(-1, 3), dims).reshape(len(sel), len(offsets))


def _nodes_and_constraints(tree: Octree) -> None:
    L = tree.max_level
    keys = _corner_keys(tree, 2 * CORNERS)
    node_keys, inverse = np.unique(keys.ravel(), return_inverse=True)
    tree.cells = inverse.reshape(-1, 8)
    dims = np.asarray(tree.shape, dtype=np.int64) * 2**L + 1
    ijk = np.stack([node_keys // (dims[1] * dims[2]), (node_keys // dims[2]) % dims[1], node_keys % dims[2]], axis=1)
    tree.nodes = tree.origin + (tree.h0 / 2.0**L) * ijk
    n = len(node_keys)
    big = np.flatnonzero(tree.level < L)  # cells whose edges and faces may carry finer nodes
    parents = []  # (hanging node, its parent nodes)
    for groups in (EDGES, FACES):
        centre = 2 * CORNERS[groups].sum(axis=1) // len(groups[0])  # midpoints, in half cells
        mkey = _corner_keys(tree, centre, big).ravel()
        pos = np.minimum(np.searchsorted(node_keys, mkey), n - 1)
        hit = node_keys[pos] == mkey
        corners = tree.cells[big][:, groups].reshape(-1, groups.shape[1])
        parents.append((pos[hit], corners[hit]))
    _constraints(tree, n, parents)


def _constraints(tree: Octree, n: int, parents) -> None:
    """T (nodes x free nodes) from the hanging nodes and their parent nodes, chains resolved."""
    hanging, rows, cols, vals = [], [], [], []
    seen = np.zeros(n, dtype=bool)
    for nodes, corners in parents:
        nodes, first = np.unique(nodes, return_index=True)
        fresh = ~seen[nodes]
        nodes, corners = nodes[fresh], corners[first][fresh]
        seen[nodes] = True
        hanging.append(nodes)
        k = corners.shape[1]
        rows.append(np.repeat(nodes, k))
        cols.append(corners.ravel())
        vals.append(np.full(corners.size, 1.0 / k))
    hang = np.concatenate(hanging) if hanging else np.zeros(0, dtype=np.int64)
    free = np.ones(n, dtype=bool)
    free[hang] = False
    f = np.flatnonzero(free)
    p = sp.csr_matrix((np.concatenate([np.ones(len(f))] + vals), (np.concatenate([f] + rows), np.concatenate([f] + cols))),
                      shape=(n, n))
    t = p
    for _ in range(64):  # resolve chains: hanging parents of hanging nodes
        if not t[:, hang].count_nonzero():
            break
        t = (t @ p).tocsr()
    else:  # pragma: no cover - impossible for a balanced tree
        raise RuntimeError("hanging-node constraints do not resolve")
    tree.free_nodes = f
    tree.constraint = t[:, f].tocsr()


def level_jumps(tree: Octree) -> int:
    """The largest level difference between two leaves that touch (by a face, an edge or a
    corner; 1 for a 2:1 balanced tree): probes just outside each cell towards its 26 neighbours."""
    off = np.array([-1e-7, 0.5, 1.0 + 1e-7])
    grid = np.stack(np.meshgrid(off, off, off, indexing="ij"), axis=-1).reshape(-1, 3)
    grid = grid[~np.all(grid == 0.5, axis=1)]
    probes = tree.lower[:, None, :] + grid[None] * tree.size[:, None, None]
    owner = tree.locate(probes.reshape(-1, 3)).reshape(len(tree.level), -1)
    ok = owner >= 0
    jumps = np.abs(tree.level[np.maximum(owner, 0)] - tree.level[:, None])
    return int(jumps[ok].max()) if ok.any() else 0
