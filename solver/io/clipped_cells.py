"""The cells of a body as they are, for output: the background grid's cells clipped by the body's
exact surface, so that no output cell lies outside the body.

Whole cells (wholly inside) are kept as they are. A cut cell is split into sub-cubes (squares in
2D), level by level:

- a sub-cube whose centre is farther inside than its half diagonal is whole (kept as a hexahedron
  or quadrilateral); one farther outside is dropped;
- the others are split again until the signed distance is linear across them to ``tolerance``
  (the mean of the corner values differs from the centre value by less than it: a plane is linear
  at once, a sphere of radius R once the sub-cube's width s satisfies s^2 / (4 R) < tolerance),
  or ``max_depth`` levels below the cell; a sub-cube no wider than ``resolution`` on one of the
  solid's edges (its deviation fell by less than 0.35 with the split: a kink's halves, a smooth
  surface's falls by 4) is split no further: the volume missed there is of the order of the
  leaves' width squared times the edge's length;
- the last sub-cubes (leaves) are split into simplices (6 tetrahedra or 2 triangles, Kuhn's
  split along the main diagonal), and each simplex is clipped at the zero of the exact signed
  distance on its edges (a bracketed root search, not a linear interpolation): the pieces inside
  are simplices again (a clipped prism gives three tetrahedra, a clipped quadrilateral two
  triangles).

The pieces' vertices on the surface lie on the exact surface; between them the output follows the
surface's chords, so a convex surface loses the sagitta of its leaves' facets (relative volume of
the order tolerance x area / volume). Where the surface is concave the chords pass just outside
the body: the thin pieces whose centroid falls outside are dropped, so every output cell's
centroid lies in the body. Every piece is judged so, and a sub-cell is kept whole only when its
centre is inside as well as its corners: a CAD part's distance can misjudge a corner (near a
degenerate edge), and a piece of such corners would otherwise poke out. Points shared by
several cells are merged.
"""

from __future__ import annotations

from itertools import permutations
from typing import Callable

import numpy as np

__all__ = ["clip_cells", "unique_rows", "CELL_CORNERS", "VTK_TYPES"]

#: corners of a unit cell in VTK's (and the grids') order: quadrilateral in 2D, hexahedron in 3D
CELL_CORNERS = {
    2: np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float),
    3: np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
                dtype=float),
}
#: VTK cell type numbers: (box, simplex) per dimension
VTK_TYPES = {2: (9, 5), 3: (12, 10)}
#: Illinois steps of the root search on each clipped edge, and the distance from the surface (in
#: edge lengths) that ends it: far below the chords' sagitta, a few steps on smooth surfaces
ROOT_STEPS, ROOT_TOLERANCE = 40, 1e-9
#: levels a sub-cube holding a point the output must hold (a probe) is split past the others'
#: deepest: down to a millionth of its cell, far below any probe's distance from the surface
#: that a user sets
POINT_LEVELS = 20
#: points per call of the signed distance (bounds the memory of a CAD solid's distance)
CHUNK = 20000


def _chunked(signed_distance: Callable) -> Callable:
    def phi(points: np.ndarray) -> np.ndarray:
        points = np.asarray(points, dtype=float)
        if len(points) <= CHUNK:
            return np.asarray(signed_distance(points), dtype=float).reshape(-1)
        return np.concatenate([np.asarray(signed_distance(points[k:k + CHUNK]), dtype=float).reshape(-1)
                               for k in range(0, len(points), CHUNK)])

    return phi


def unique_rows(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The first occurrence of each distinct row (in order of first occurrence) and each row's
    index among them (a lexicographic sort: several times faster than np.unique(axis=0))."""
    keys = np.asarray(keys)
    if not len(keys):
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    packed = _packed(keys)
    if packed is not None:  # integer rows in a small box: one sort of one column
        order = np.argsort(packed, kind="stable")
        s = packed[order]
        new = np.concatenate([[True], s[1:] != s[:-1]])
    else:
        order = np.lexsort(keys.T[::-1])
        s = keys[order]
        new = np.concatenate([[True], np.any(s[1:] != s[:-1], axis=1)])
    group = np.cumsum(new) - 1
    first = order[new]  # the sort is stable: a group's first row is its first occurrence
    rank = np.empty(len(first), dtype=np.int64)
    by_first = np.argsort(first, kind="stable")
    rank[by_first] = np.arange(len(first))
    inverse = np.empty(len(keys), dtype=np.int64)
    inverse[order] = rank[group]
    return first[by_first], inverse


def _packed(keys: np.ndarray) -> np.ndarray | None:
    """Integer rows as one int64 each (mixed radix over the rows' ranges), None when they are not
    integers or their box has more than 2^62 cells."""
    if keys.dtype.kind not in "iu":
        return None
    low = keys.min(axis=0)
    span = (keys.max(axis=0) - low + 1).astype(float)
    if np.prod(span) >= 2.0**62:
        return None
    packed = np.zeros(len(keys), dtype=np.int64)
    for k in range(keys.shape[1]):
        packed = packed * np.int64(span[k]) + (keys[:, k] - low[k])
    return packed


def _kuhn_simplices(dim: int) -> np.ndarray:
    """(dim!, dim + 1) corner indices (CELL_CORNERS order) of Kuhn's simplices of the unit cell:
    the paths from corner 0 to the opposite corner, one axis at a time."""
    corners = CELL_CORNERS[dim].astype(int)
    index = {tuple(c): k for k, c in enumerate(corners)}
    out = []
    for order in permutations(range(dim)):
        p = np.zeros(dim, dtype=int)
        path = [index[tuple(p)]]
        for axis in order:
            p[axis] = 1
            path.append(index[tuple(p)])
        out.append(path)
    return np.array(out)


def clip_cells(lower: np.ndarray, size: np.ndarray, whole: np.ndarray, signed_distance: Callable,
               tolerance: float, resolution: float = 0.0, max_depth: int = 4,
               points: np.ndarray | None = None) -> tuple[np.ndarray, list[np.ndarray]]:
    """Split and clip the cells not flagged ``whole``: returns the whole cells' indices (the
    cells to keep as they are, the cut cells found whole included) and the pieces as
    ``[box_corners (k, 2^d, d), box_parent, simplex_vertices (j, d+1, d), simplex_parent,
    simplex_on_surface (j, d+1)]``. ``points`` (k, d): points the output must hold (probes):
    a sub-cube holding one is split on, past ``max_depth`` by up to :data:`POINT_LEVELS` levels,
    until it is whole (its centre farther inside than its half diagonal), so that a point inside
    the body, however close to a concave surface or an edge, lies in an output cell."""
    lower = np.asarray(lower, dtype=float)
    dim = lower.shape[1]
    signed_distance = _chunked(signed_distance) if signed_distance is not None else None
    corners = CELL_CORNERS[dim]
    cut_cells = np.nonzero(~np.asarray(whole, dtype=bool))[0]
    kept = [np.nonzero(whole)[0]]
    boxes, box_parent, leaves = [], [], []
    cell, lo, s = cut_cells, lower[cut_cells], np.asarray(size, dtype=float)[cut_cells]
    previous = np.full(len(cell), np.inf)  # the parent sub-cube's deviation from linearity
    held = np.zeros((0, dim)) if points is None else np.asarray(points, dtype=float).reshape(-1, dim)
    for level in range(max_depth + 1 + (POINT_LEVELS if len(held) else 0)):
        if not len(cell):
            break
        at = lo[:, None, :] + s[:, None, None] * corners[None]
        phi_corner = _shared_values(at.reshape(-1, dim), s.min(), signed_distance).reshape(len(cell), -1)
        phi_centre = np.asarray(signed_distance(lo + 0.5 * s[:, None]), dtype=float)
        reach = 0.5 * np.sqrt(dim) * s * (1.0 + 1e-9)
        inside, outside = phi_centre >= reach, phi_centre <= -reach
        deviation = np.abs(phi_corner.mean(axis=1) - phi_centre)
        # a smooth surface's deviation falls by 4 per split, a kink's (the solid's edges) by 2 only
        kink = (deviation > 0.35 * previous) & (s <= resolution * (1.0 + 1e-9))
        leaf = ~inside & ~outside & ((deviation <= tolerance) | kink | (level >= max_depth))
        if len(held) and level < max_depth + POINT_LEVELS:  # split on while it holds a point
            leaf &= ~_holding(lo, s, held)
        eps = 1e-12 * s[:, None]
        whole_leaf = leaf & np.all(phi_corner >= -eps, axis=1) & (phi_centre >= 0.0)  # its centroid inside too
        full = inside | whole_leaf
        if level == 0:
            kept.append(cell[full])
        else:
            boxes.append(at[full])
            box_parent.append(cell[full])
        clip = leaf & ~whole_leaf & np.any(phi_corner > eps, axis=1)
        leaves.append((cell[clip], at[clip], phi_corner[clip]))
        split = ~inside & ~outside & ~leaf
        previous = np.repeat(deviation[split], len(corners))
        half = 0.5 * s[split]
        lo = (lo[split][:, None, :] + half[:, None, None] * corners[None]).reshape(-1, dim)
        s = np.repeat(half, len(corners))
        cell = np.repeat(cell[split], len(corners))
    simplices, simplex_parent, on_surface = _clip_leaves(leaves, dim, signed_distance)
    if len(simplices):  # pieces of no measure (all vertices on a face the grid's planes hold)
        edges = simplices[:, 1:] - simplices[:, :1]
        scale = np.max(np.abs(edges), axis=(1, 2)) ** dim
        solid = np.abs(np.linalg.det(edges)) > 1e-12 * scale
        simplices, simplex_parent, on_surface = simplices[solid], simplex_parent[solid], on_surface[solid]
    if len(simplices):  # where the surface is concave its chords leave the body: drop those slivers
        # (every piece is judged, not only those touching the surface: a CAD part's distance may
        # misjudge a corner near a degenerate edge, and a piece of such corners then pokes out)
        keep = np.asarray(signed_distance(simplices.mean(axis=1)), dtype=float) >= 0.0
        simplices, simplex_parent, on_surface = simplices[keep], simplex_parent[keep], on_surface[keep]
    pieces = [
        np.concatenate(boxes) if boxes else np.zeros((0, len(corners), dim)),
        np.concatenate(box_parent) if box_parent else np.zeros(0, dtype=np.int64),
        simplices, simplex_parent, on_surface,
    ]
    return np.sort(np.concatenate(kept)), pieces


def _holding(lower: np.ndarray, size: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Whether each box (lower corner, width) holds one of ``points`` (its faces included)."""
    found = np.zeros(len(lower), dtype=bool)
    pad = 1e-12 * size[:, None]
    for p in points:  # a few probes: one vectorised pass over the boxes each
        found |= np.all((p >= lower - pad) & (p <= lower + size[:, None] + pad), axis=1)
    return found


def _shared_values(points: np.ndarray, spacing: float, signed_distance: Callable) -> np.ndarray:
    """The signed distance at points many of which coincide (the corners sub-cubes share), each
    distinct point evaluated once: the corners lie on the lattice of the finest sub-cubes
    (``spacing``), so rounding to a quarter of it tells them apart."""
    first, inverse = unique_rows(np.round(points / (0.25 * spacing)).astype(np.int64))
    return np.asarray(signed_distance(points[first]), dtype=float)[inverse]


def _clip_leaves(leaves, dim: int, signed_distance: Callable):
    """Kuhn simplices of the leaves, clipped at the surface: vertices, parents, surface flags."""
    kuhn = _kuhn_simplices(dim)
    cell = np.concatenate([lv[0] for lv in leaves]) if leaves else np.zeros(0, dtype=np.int64)
    if not len(cell):
        return np.zeros((0, dim + 1, dim)), np.zeros(0, dtype=np.int64), np.zeros((0, dim + 1), dtype=bool)
    at = np.concatenate([lv[1] for lv in leaves])
    phi = np.concatenate([lv[2] for lv in leaves])
    verts = at[:, kuhn].reshape(-1, dim + 1, dim)  # (leaves * dim!, dim + 1, dim)
    values = phi[:, kuhn].reshape(-1, dim + 1)
    parent = np.repeat(cell, len(kuhn))
    inside = values >= 0.0
    n_in = inside.sum(axis=1)
    keep = n_in > 0
    verts, values, parent, inside, n_in = verts[keep], values[keep], parent[keep], inside[keep], n_in[keep]
    order = np.argsort(~inside, axis=1, kind="stable")  # inside vertices first
    verts = np.take_along_axis(verts, order[:, :, None], axis=1)
    values = np.take_along_axis(values, order, axis=1)
    out_v, out_p, out_s = [], [], []
    for count in range(1, dim + 2):
        sel = n_in == count
        if not sel.any():
            continue
        v, f = verts[sel], values[sel]
        if count == dim + 1:
            pieces = [list(range(dim + 1))]
            new = np.zeros((len(v), 0, dim))
        else:
            pairs = [(i, j) for i in range(count) for j in range(count, dim + 1)]
            a = np.stack([v[:, i] for i, _ in pairs], axis=1)
            b = np.stack([v[:, j] for _, j in pairs], axis=1)
            fa = np.stack([f[:, i] for i, _ in pairs], axis=1)
            fb = np.stack([f[:, j] for _, j in pairs], axis=1)
            new = _edge_roots(a.reshape(-1, dim), b.reshape(-1, dim), fa.ravel(), fb.ravel(),
                              signed_distance).reshape(len(v), len(pairs), dim)
            pieces = _piece_table(dim, count, pairs)
        allv = np.concatenate([v[:, :count], new], axis=1)  # inside vertices, then the roots
        surf = np.concatenate([np.abs(f[:, :count]) <= 0.0, np.ones(new.shape[:2], dtype=bool)], axis=1)
        for piece in pieces:
            out_v.append(allv[:, piece])
            out_p.append(parent[sel])
            out_s.append(surf[:, piece])
    return np.concatenate(out_v), np.concatenate(out_p), np.concatenate(out_s)


def _piece_table(dim: int, count: int, pairs: list[tuple[int, int]]) -> list[list[int]]:
    """The simplices of a simplex's inside part with ``count`` vertices inside, as indices into
    [inside vertices..., roots on ``pairs``...]."""
    root = {pair: count + k for k, pair in enumerate(pairs)}
    if dim == 2:
        if count == 1:
            return [[0, root[0, 1], root[0, 2]]]
        return [[0, 1, root[1, 2]], [0, root[1, 2], root[0, 2]]]  # count 2: a quadrilateral
    if count == 1:
        return [[0, root[0, 1], root[0, 2], root[0, 3]]]
    if count == 2:  # a prism: triangles (0, r02, r03) and (1, r12, r13)
        p, q = [0, root[0, 2], root[0, 3]], [1, root[1, 2], root[1, 3]]
    else:  # count 3: a prism: triangles (0, 1, 2) and (r03, r13, r23)
        p, q = [0, 1, 2], [root[0, 3], root[1, 3], root[2, 3]]
    return [[p[0], p[1], p[2], q[2]], [p[0], p[1], q[1], q[2]], [p[0], q[0], q[1], q[2]]]


def _edge_roots(a: np.ndarray, b: np.ndarray, fa: np.ndarray, fb: np.ndarray, signed_distance: Callable) -> np.ndarray:
    """Zero of the signed distance on each segment a -> b (fa >= 0 > fb): Illinois' false
    position, all segments in one call per step; each distinct segment searched once."""
    first, inverse = unique_rows(np.concatenate([a, b], axis=1))
    a, b, fa, fb = a[first], b[first], fa[first].copy(), fb[first].copy()
    hi = np.ones(len(a))
    side = np.zeros(len(a), dtype=np.int8)
    length = np.linalg.norm(b - a, axis=1)
    lo, fa = _leave_the_surface(a, b, fa, length, signed_distance)
    active = np.ones(len(a), dtype=bool)
    for _ in range(ROOT_STEPS):
        active &= (hi - lo) > 1e-13
        if not active.any():
            break
        t = np.where(fa - fb != 0.0, lo + (hi - lo) * fa / np.where(fa - fb != 0.0, fa - fb, 1.0), 0.5 * (lo + hi))
        t = np.clip(t, lo, hi)
        idx = np.nonzero(active)[0]
        ft = np.asarray(signed_distance(a[idx] + t[idx, None] * (b[idx] - a[idx])), dtype=float)
        pos = ft >= 0.0
        i_pos, i_neg = idx[pos], idx[~pos]
        lo[i_pos], fa[i_pos] = t[i_pos], ft[pos]
        hi[i_neg], fb[i_neg] = t[i_neg], ft[~pos]
        converged = np.abs(ft) <= ROOT_TOLERANCE * length[idx]
        lo[idx[converged]] = t[idx[converged]]
        active[idx[converged]] = False
        # Illinois: halve the value kept twice in a row on the same side
        fb[i_pos] = np.where(side[i_pos] == 1, 0.5 * fb[i_pos], fb[i_pos])
        fa[i_neg] = np.where(side[i_neg] == -1, 0.5 * fa[i_neg], fa[i_neg])
        side[i_pos], side[i_neg] = 1, -1
    # the inside end of the bracket: a root never lies outside the body
    return (a + lo[:, None] * (b - a))[inverse]


def _leave_the_surface(a: np.ndarray, b: np.ndarray, fa: np.ndarray, length: np.ndarray, signed_distance: Callable):
    """Start of each bracket: a segment whose inside end lies on the surface itself (a face the
    grid's planes hold) may run inside before it leaves the body; its crossing is the one after
    the first point found inside (t = 1/2, 1/4, ...), t = 0 when none is."""
    lo = np.zeros(len(a))
    fa = fa.copy()
    on = np.nonzero(fa <= 1e-12 * length)[0]
    for k in range(1, 6):
        if not len(on):
            break
        t = 0.5**k
        f = np.asarray(signed_distance(a[on] + t * (b[on] - a[on])), dtype=float)
        found = f > 1e-12 * length[on]
        lo[on[found]], fa[on[found]] = t, f[found]
        on = on[~found]
    return lo, fa
