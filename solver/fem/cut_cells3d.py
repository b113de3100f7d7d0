"""Cut cells of the octree: which leaves the boundary of a solid crosses, and the
moments of their inside parts, from the solid's exact signed distance.

Cells bounded by planar faces, edges and corners included, are integrated exactly
(solver.fem.planar_cells: the planes recovered from the distance, the cell's part as pieces of
their arrangement, each a convex polyhedron): with ``depth`` 0 (the solver's), the cut cells
where the distance is not linear try that model first; the others, and those where it fails
(curved faces), take the adaptive rule below.

Adaptive subdivision: a sub-cube whose centre is farther inside than its half diagonal
contributes its exact box moments, one farther outside nothing; the others are split down to
``depth`` levels below the cell, and EDGE_DEPTH more where the distance is not smooth across the
sub-cube (the solid's edges and vertices: a second difference or a corner's deviation from the
linear model above KINK of the half edge). The leaves take a dimension-reducing rule after Saye
(2015): lines along the height axis through Gauss points of the cross-section, the exact zero of
the signed distance on each (bracketed root search) and the monomials in closed form between
them, the cross-section split at the kinks of that integrand (the zeros on the sub-cube's faces
and edges). Spectral on smooth surfaces: sphere volume and second moment to 2e-11 one level
below cells of R/4, a torus to 1e-12 (tests/test_octree.py); exact for planes. Leaves still
kinked at the last level take a plain 3 x 3 line rule: where a curved face meets another face
(a cylinder's rim) the edge is integrated to about second order in the last sub-cube's size (a
turned cylinder's volume to 4e-8 with cells of a third of its radius, docs/solids.md).

The distance is called on whole batches: two calls per subdivision level, then each rule once for
the leaves of all levels together (lines along all three axes in one pass, the root searches of
all lines sharing their calls), LEAF_CHUNK leaves at a time: some fifty to a few hundred calls
per ``inside_moments`` (tests/test_cut_cells3d.py)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from .hexahedra import CORNERS, STIFFNESS_EXPONENTS, box_moments
from .planar_cells import planar_moments

__all__ = ["INSIDE", "CUT", "OUTSIDE", "classify_cells", "inside_moments"]

INSIDE, CUT, OUTSIDE = 1, 2, 0
_HALF_DIAGONAL = 0.5 * np.sqrt(3.0) * (1.0 + 1e-9)

SignedDistance = Callable[[np.ndarray], np.ndarray]


def classify_cells(lower: np.ndarray, size: np.ndarray, signed_distance: SignedDistance) -> np.ndarray:
    """INSIDE / CUT / OUTSIDE per cell by the signed distance (positive inside) at its centre
    against its half diagonal."""
    phi = np.asarray(signed_distance(lower + 0.5 * size[:, None]), dtype=float)
    r = _HALF_DIAGONAL * size
    return np.where(phi >= r, INSIDE, np.where(phi <= -r, OUTSIDE, CUT)).astype(np.int8)


def inside_moments(lower: np.ndarray, size: np.ndarray, signed_distance: SignedDistance, depth: int = 3,
                   planar: bool = True) -> np.ndarray:
    """Moments (m, 27) of the inside parts of cells (local coordinates of each cell, the order of
    hexahedra.STIFFNESS_EXPONENTS). Cells bounded by planar faces are exact at once (``planar``:
    False keeps the general rule only); the subdivision runs level by level (two calls of the
    distance per level); the leaves of all levels then take their rules together."""
    lower = np.asarray(lower, dtype=float).reshape(-1, 3)
    size = np.asarray(size, dtype=float).reshape(-1)
    out = np.zeros((len(size), 27))
    cell = np.arange(len(size))
    lo = np.full((len(size), 3), -1.0)  # sub-cube lower corners in local coordinates
    width = 2.0  # local width of the sub-cubes of this level
    leaves = []  # per level: cell, lower corner, width, gradient and kink of each leaf
    for level in range(depth + EDGE_DEPTH + 1):
        if len(cell) == 0:
            break
        half = 0.5 * width * 0.5 * size[cell]  # physical half edge of each sub-cube
        centre = lower[cell] + (lo + 0.5 * width + 1.0) * (0.5 * size[cell])[:, None]
        phi = np.asarray(signed_distance(centre), dtype=float)
        inside = phi >= np.sqrt(3.0) * half
        cut = ~inside & (phi > -np.sqrt(3.0) * half)
        np.add.at(out, cell[inside], box_moments(lo[inside], lo[inside] + width))
        if level >= depth:
            grad, bend = _linearity(signed_distance, lower[cell[cut]], 0.5 * size[cell[cut]], cell[cut], lo[cut], width,
                                    phi[cut])
            kink = bend > KINK * half[cut]
            bent = bend > PLANAR_BEND * half[cut]  # not one plane: an edge, a vertex or a curved face
            if planar and level == 0 and bent.any():  # whole cells (depth 0, the solver's)
                rows = np.flatnonzero(cut)[bent]
                moments, exact = planar_moments(signed_distance, lower[cell[rows]], 0.5 * size[cell[rows]],
                                                lo[rows], np.full(len(rows), width), PLANAR_SAMPLES)
                np.add.at(out, cell[rows[exact]], moments[exact])
                keep = np.ones(len(kink), dtype=bool)
                keep[np.flatnonzero(bent)[exact]] = False
                grad, kink = grad[keep], kink[keep]
                cut[rows[exact]] = False
            leaf = ~kink if level < depth + EDGE_DEPTH else np.ones(len(kink), dtype=bool)
            rows = np.nonzero(cut)[0]
            done, rows = rows[leaf], rows[~leaf]
            leaves.append((cell[done], lo[done], np.full(len(done), width), grad[leaf], kink[leaf]))
            cut = np.zeros(len(cut), dtype=bool)
            cut[rows] = True
            if not cut.any():
                break
        width *= 0.5
        cell = np.repeat(cell[cut], 8)
        lo = (lo[cut][:, None, :] + width * CORNERS[None]).reshape(-1, 3)
    if leaves:
        cell, lo, width, grad, kink = (np.concatenate(part) for part in zip(*leaves))
        # kinked leaves are those of the last level: the plain rule
        for rule, sel in ((_leaf_moments, ~kink), (_simple_leaf, kink)):
            for start in range(0, int(sel.sum()), LEAF_CHUNK):
                d = np.flatnonzero(sel)[start:start + LEAF_CHUNK]
                np.add.at(out, cell[d], rule(signed_distance, lower[cell[d]], 0.5 * size[cell[d]], lo[d], width[d],
                                             grad[d]))
    return out


#: sample lattice points per direction of the planar model on whole cells
PLANAR_SAMPLES = 5
#: the cut cells (sub-cubes of the first leaf level) whose distance bends by more than this share
#: of the half edge try the planar model; below it the leaf rule is exact already (one plane)
PLANAR_BEND = 1e-7
#: further subdivision levels where the distance is not linear across a sub-cube (the solid's
#: edges and vertices, where the boundary has a kink)
EDGE_DEPTH = 4
#: a sub-cube is kinked when a second difference of the distance over its half edge exceeds
#: this share of the half edge (a smooth face of radius R gives about half / R, a right-angled
#: edge about 1)
KINK = 0.3
#: leaves per pass of a rule (bounds the memory of its lines; each pass calls the distance
#: about a hundred times)
LEAF_CHUNK = 20000


def _linearity(signed_distance: SignedDistance, cell_lower, scale, owner, lo, width: float, phi):
    """Central-difference gradient (q, 3) of the distance over each sub-cube's half edge, and
    how much the distance bends there: the largest second difference along an axis, or
    deviation of the distance at a corner from the linear model. The sub-cubes [lo, lo + width]
    in the local coordinates of cells with lower corners ``cell_lower`` and half edges ``scale``
    (the cells' indices ``owner``). One call of the distance on the 14 q points, each point
    asked once: the sub-cubes of one cell share corners and face centres (their local
    coordinates are exact binary fractions, so a shared point is the same number each time)."""
    q = len(phi)
    offsets = np.concatenate([np.vstack([np.eye(3), -np.eye(3)])[[0, 3, 1, 4, 2, 5]], 2.0 * CORNERS - 1.0])
    half = 0.5 * width * scale
    offset = half[None, :, None] * offsets[:, None, :]  # (14, q, 3): +-x, +-y, +-z, the corners
    local = (lo + 0.5 * width)[None] + 0.5 * width * offsets[:, None, :]  # (14, q, 3), exact
    first, inverse = _shared_points(np.broadcast_to(owner, (14, q)).reshape(-1), local.reshape(-1, 3), width)
    rows = first % q  # any of the points' sub-cubes: they share the cell
    points = cell_lower[rows] + (local.reshape(-1, 3)[first] + 1.0) * scale[rows, None]
    values = np.asarray(signed_distance(points), float)[inverse].reshape(14, q)
    plus, minus = values[0:6:2], values[1:6:2]  # (3, q)
    grad = ((plus - minus) / (2.0 * half)).T
    bend = np.abs(plus + minus - 2.0 * phi).max(axis=0, initial=0.0)
    linear = phi + (grad[None] * offset[6:]).sum(axis=2)  # (8, q)
    bend = np.maximum(bend, np.abs(values[6:] - linear).max(axis=0, initial=0.0))
    return grad, bend


def _shared_points(owner: np.ndarray, local: np.ndarray, width: float):
    """The distinct points among local coordinates ``local`` (p, 3) of cells ``owner`` (p,), all
    on the lattice of step width / 2 from -1 (exact binary fractions): the index of one
    occurrence of each (in the order of (owner, local) sorted row by row) and, per point, which
    distinct point it is. Sorted as one integer key per point (a sort of rows as records takes
    ten times longer)."""
    steps = int(round(4.0 / width)) + 1  # lattice points per axis
    if (int(owner.max(initial=0)) + 1) * steps**3 >= 2**62:  # keys beyond int64 (very deep levels): rows
        _, first, inverse = np.unique(np.column_stack([owner, local]), axis=0, return_index=True,
                                      return_inverse=True)
        return first, inverse.reshape(-1)
    index = np.rint((local + 1.0) * (2.0 / width)).astype(np.int64)
    key = ((owner.astype(np.int64) * steps + index[:, 0]) * steps + index[:, 1]) * steps + index[:, 2]
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    return first, inverse.reshape(-1)


#: Gauss points per smooth piece in each direction of the leaf rule
LINE_POINTS = 4
#: Gauss points per direction of the plain rule on kinked sub-cubes
EDGE_POINTS = 3
#: regula falsi (Illinois) steps of the root search along each line
ROOT_STEPS = 30
#: the two axes across each axis, in increasing order
_ACROSS = np.array([[1, 2], [0, 2], [0, 1]])


def _leaf_moments(signed_distance: SignedDistance, cell_lower, scale, lo, width, grad) -> np.ndarray:
    """Moments (q, 27) of the inside parts of the last sub-cubes (lower corners ``lo`` and widths
    ``width`` in the local coordinates of cells with lower corners ``cell_lower`` and half edges
    ``scale``) by dimension reduction (after Saye, SIAM J. Sci. Comput. 37 (2015) A993): lines
    along the height axis k (largest gradient component) carry the exact zero of the distance and
    closed-form monomial integrals; their feet are Gauss points of the cross-section, split where
    the integrand has kinks: along the base height axis j (the larger of the other two gradient
    components) at the zeros of the distance on the sub-cube's two k-faces, and along the last
    axis i at the zeros on the four edges those faces share with the j-faces. Between the splits
    everything is smooth, so the rule converges spectrally with LINE_POINTS on smooth surfaces
    (sphere volume to about 1e-12 at 4 points) and is exact for a plane. All leaves in one pass
    whatever their axes."""
    q = len(lo)
    if q == 0:
        return np.zeros((0, 27))
    g = np.abs(grad)
    k = np.argmax(g, axis=1)
    across = _ACROSS[k]
    rows = np.arange(q)
    j_first = g[rows, across[:, 0]] >= g[rows, across[:, 1]]
    j = np.where(j_first, across[:, 0], across[:, 1])
    i = np.where(j_first, across[:, 1], across[:, 0])
    return _reduced_rule(signed_distance, cell_lower, scale, lo, width, np.stack([k, j, i], axis=1))


def _gauss_nodes(breaks: np.ndarray, owner: np.ndarray, n: int):
    """Gauss nodes, weights and owners of n points on each interval between consecutive
    ``breaks`` (r, s) of rows owned by ``owner`` (r,); the split's empty intervals carry none."""
    x, w = np.polynomial.legendre.leggauss(n)
    lo_edges, hi_edges = breaks[:, :-1], breaks[:, 1:]
    mid, half = 0.5 * (lo_edges + hi_edges), 0.5 * (hi_edges - lo_edges)
    nodes = (mid[:, :, None] + half[:, :, None] * x).ravel()
    weights = (half[:, :, None] * w).ravel()
    keep = weights > 0.0
    return nodes[keep], weights[keep], np.repeat(owner, (len(x) * (breaks.shape[1] - 1)))[keep]


def _split_points(f, lo_t: np.ndarray, hi_t: np.ndarray, count: int) -> np.ndarray:
    """Sorted break points (r, 2 + count) of the intervals [lo_t, hi_t] (r,): the ends and the
    zero of each of ``count`` functions where it changes sign (the lower end where it does not).
    ``f(t, lines)`` gives the values at t on the lines ``lines``, line ``count r + c`` being
    function c of row r; one root search for all of them."""
    a, b = np.repeat(lo_t, count), np.repeat(hi_t, count)
    lines = np.arange(len(a))
    ends = f(np.concatenate([a, b]), np.concatenate([lines, lines]))
    fa, fb = ends[: len(a)], ends[len(a):]
    root = _bracketed_root(f, a.copy(), b.copy(), fa.copy(), fb.copy())
    roots = np.where((fa < 0.0) != (fb < 0.0), root, a).reshape(-1, count)
    return np.sort(np.concatenate([lo_t[:, None], hi_t[:, None], roots], axis=1), axis=1)


def _reduced_rule(signed_distance, cell_lower, scale, lo, width, axes) -> np.ndarray:
    """_leaf_moments for sub-cubes with height axis k, base height axis j and last axis i, the
    columns of ``axes`` (q, 3)."""
    n = LINE_POINTS
    m = len(lo)
    every = np.arange(m)
    k, j, i = axes.T
    lo_i, lo_j, lo_k = lo[every, i], lo[every, j], lo[every, k]
    hi_i, hi_j, hi_k = lo_i + width, lo_j + width, lo_k + width

    def lines(leaf, ti, tj, tk, along):  # lines along axis ``along`` through local points (ti, tj, tk)
        local = np.empty((len(leaf), 3))
        r = np.arange(len(leaf))
        local[r, i[leaf]], local[r, j[leaf]], local[r, k[leaf]] = ti, tj, tk
        return _line_function(signed_distance, cell_lower[leaf], scale[leaf], local, along[leaf])

    # 1. along i: zeros of the distance on the four edges (j end, k end) of each sub-cube
    le, corner = np.repeat(every, 4), np.tile(np.arange(4), m)
    ej = np.where(corner % 2 == 1, hi_j[le], lo_j[le])
    ek = np.where(corner // 2 == 1, hi_k[le], lo_k[le])
    breaks_i = _split_points(lines(le, lo_i[le], ej, ek, i), lo_i, hi_i, 4)
    ti, wi, leaf = _gauss_nodes(breaks_i, every, n)
    # 2. along j at each node of i: zeros of the distance on the two k-faces
    lf, face = np.repeat(np.arange(len(leaf)), 2), np.tile(np.arange(2), len(leaf))
    fk = np.where(face == 1, hi_k[leaf[lf]], lo_k[leaf[lf]])
    breaks_j = _split_points(lines(leaf[lf], ti[lf], lo_j[leaf[lf]], fk, j), lo_j[leaf], hi_j[leaf], 2)
    tj, wj, node = _gauss_nodes(breaks_j, np.arange(len(leaf)), n)
    leaf2, ti2, w2 = leaf[node], ti[node], wi[node] * wj
    # 3. along k: the inside interval between the zero and the end where the distance is positive
    t0, t1 = _inside_interval(lines(leaf2, ti2, tj, lo_k[leaf2], k), lo_k[leaf2], hi_k[leaf2])
    return _monomial_sums(t0, t1, ti2, tj, w2, axes[leaf2], leaf2, m)


def _line_function(signed_distance, cell_lower, scale, local, axis):
    """``f(t, lines)``: the distance at the local coordinate t along ``axis`` (r,) of lines
    through the local points ``local`` (r, 3) of cells with lower corners ``cell_lower`` (r, 3)
    and half edges ``scale`` (r,); ``lines`` picks the lines."""
    rows = np.arange(len(axis))
    start = cell_lower + (local + 1.0) * scale[:, None]
    lower = cell_lower[rows, axis]

    def f(t, s):
        x = start[s]
        x[np.arange(len(s)), axis[s]] = lower[s] + (t + 1.0) * scale[s]
        return np.asarray(signed_distance(x), dtype=float)

    return f


def _inside_interval(line_f, a: np.ndarray, b: np.ndarray):
    """Ends (t0, t1) of the inside part of the lines [a, b] (one crossing at most): the zero of
    ``line_f(t, lines)`` by a bracketed root search, the end where the distance is positive."""
    everything = np.arange(len(a))
    ends = line_f(np.concatenate([a, b]), np.concatenate([everything, everything]))
    fa, fb = ends[: len(a)], ends[len(a):]
    root = _bracketed_root(line_f, a.copy(), b.copy(), fa.copy(), fb.copy())
    t0 = np.where(fa >= 0.0, a, np.where(fb >= 0.0, root, b))
    t1 = np.maximum(np.where(fb >= 0.0, b, np.where(fa >= 0.0, root, a)), t0)
    return t0, t1


def _monomial_sums(t0, t1, t_first, t_second, weight, axes, owner, m: int) -> np.ndarray:
    """Moments (m, 27): the closed-form integrals of the monomials along each line over [t0, t1]
    (along axes[:, 0]) times the weight and the powers of the line's foot (t_first along
    axes[:, 2], t_second along axes[:, 1]), summed over the lines of each owner (contiguous)."""
    out = np.zeros((m, 3, 9))
    if len(owner) == 0:
        return out.reshape(m, 27)
    powers = np.empty((len(owner), 3, 3))  # (line, axis, exponent)
    r = np.arange(len(owner))
    # t^2 and t^3 as products (a power of 3 calls pow(): 5 ms for 100,000 lines, the products 0.03)
    t0_2, t1_2 = t0 * t0, t1 * t1
    powers[r, axes[:, 0]] = np.stack([t1 - t0, (t1_2 - t0_2) / 2, (t1_2 * t1 - t0_2 * t0) / 3], axis=1)
    powers[r, axes[:, 2]] = np.stack([np.ones_like(t_first), t_first, t_first * t_first], axis=1)
    powers[r, axes[:, 1]] = np.stack([np.ones_like(t_second), t_second, t_second * t_second], axis=1)
    starts = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1]])
    yz = (powers[:, 1, :, None] * powers[:, 2, None, :]).reshape(-1, 9) * weight[:, None]
    for a in range(3):  # monomial 9 a + 3 b + c is x^a y^b z^c (hexahedra.STIFFNESS_EXPONENTS)
        out[owner[starts], a] = np.add.reduceat(powers[:, 0, a, None] * yz, starts, axis=0)
    return out.reshape(m, 27)


def _simple_leaf(signed_distance: SignedDistance, cell_lower, scale, lo, width, grad) -> np.ndarray:
    """Moments (q, 27) of the inside parts of sub-cubes where the distance bends (the solid's
    edges, at the last subdivision level) by a plain height-function rule: lines along the axis
    of the largest component of the distance's gradient, through EDGE_POINTS^2 Gauss points of
    the cross-section; on each line the exact zero of the signed distance (a bracketed root
    search) bounds the inside interval, over which the monomials are integrated in closed form.
    Exact where the boundary crosses every line of a sub-cube along a plane, high order on smooth
    curved faces. All sub-cubes in one pass whatever their axes."""
    q = len(lo)
    if q == 0:
        return np.zeros((0, 27))
    x, w = np.polynomial.legendre.leggauss(EDGE_POINTS)
    gu, gv = (g.ravel() for g in np.meshgrid(x, x, indexing="ij"))
    n_line = len(gu)
    k = np.argmax(np.abs(grad), axis=1)
    axes = np.column_stack([k, _ACROSS[k][:, ::-1]])  # height k, then v, then u (as k, j, i)
    line = np.repeat(np.arange(q), n_line)
    half_width = 0.5 * width[line]
    r = np.arange(len(line))
    local = lo[line].copy()  # (q n, 3) local coordinates of each line's start
    local[r, axes[line, 2]] += half_width * (np.tile(gu, q) + 1.0)
    local[r, axes[line, 1]] += half_width * (np.tile(gv, q) + 1.0)
    gw = np.tile(np.outer(w, w).ravel(), q) * half_width**2  # local units
    a = local[r, axes[line, 0]]
    f = _line_function(signed_distance, cell_lower[line], scale[line], local, axes[line, 0])
    t0, t1 = _inside_interval(f, a, a + width[line])
    return _monomial_sums(t0, t1, local[r, axes[line, 2]], local[r, axes[line, 1]], gw, axes[line], line, q)


def _bracketed_root(f, a, b, fa, fb):
    """Zeros of f(t, rows) on [a, b] where fa, fb differ in sign (Illinois regula falsi,
    vectorised over the lines still active, to a step of 1e-14 of the interval: a line whose
    next step is below it takes that step without evaluating f there); the lower end elsewhere
    (unused there)."""
    x = a.copy()
    side = np.zeros(len(a), dtype=np.int8)
    i = np.nonzero((fa < 0.0) != (fb < 0.0))[0]
    tol = 1e-14 * np.maximum(np.abs(b - a), 1e-300)
    for _ in range(ROOT_STEPS):
        if len(i) == 0:
            break
        denom = np.where(fb[i] != fa[i], fb[i] - fa[i], 1.0)
        xi = np.clip(b[i] - fb[i] * (b[i] - a[i]) / denom, np.minimum(a[i], b[i]), np.maximum(a[i], b[i]))
        step = np.abs(xi - x[i])
        x[i] = xi
        moving = step > tol[i]  # the others have converged: no call for them
        i, xi = i[moving], xi[moving]
        if len(i) == 0:
            break
        fx = f(xi, i)
        left = (fx < 0.0) == (fa[i] < 0.0)  # the root lies in [x, b]
        li, ri = i[left], i[~left]
        a[li], fa[li] = xi[left], fx[left]
        fb[li[side[li] == 1]] *= 0.5  # Illinois: halve the stale end
        side[li] = 1
        b[ri], fb[ri] = xi[~left], fx[~left]
        fa[ri[side[ri] == -1]] *= 0.5
        side[ri] = -1
        i = i[(fx != 0.0) & (np.abs(b[i] - a[i]) > tol[i])]
    return x
