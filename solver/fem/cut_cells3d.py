"""Cut cells of the octree (issue 14): which leaves the boundary of a solid crosses, and the
moments of their inside parts, from the solid's exact signed distance.

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
kinked at the last level take a plain 3 x 3 line rule: the solid's edges are integrated to about
1e-5 of the cut cells' volume (a turned box: 7e-6), which is what remains of the patch test
there (tests/test_solid_patch.py)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from .hexahedra import CORNERS, STIFFNESS_EXPONENTS, box_moments

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


def inside_moments(lower: np.ndarray, size: np.ndarray, signed_distance: SignedDistance, depth: int = 3) -> np.ndarray:
    """Moments (m, 27) of the inside parts of cells (local coordinates of each cell, the order of
    hexahedra.STIFFNESS_EXPONENTS)."""
    lower = np.asarray(lower, dtype=float).reshape(-1, 3)
    size = np.asarray(size, dtype=float).reshape(-1)
    out = np.zeros((len(size), 27))
    cell = np.arange(len(size))
    lo = np.full((len(size), 3), -1.0)  # sub-cube lower corners in local coordinates
    width = 2.0  # local width of the sub-cubes of this level
    for level in range(depth + EDGE_DEPTH + 1):
        half = 0.5 * width * 0.5 * size[cell]  # physical half edge of each sub-cube
        centre = lower[cell] + (lo + 0.5 * width + 1.0) * (0.5 * size[cell])[:, None]
        phi = np.asarray(signed_distance(centre), dtype=float)
        inside = phi >= np.sqrt(3.0) * half
        cut = ~inside & (phi > -np.sqrt(3.0) * half)
        np.add.at(out, cell[inside], box_moments(lo[inside], lo[inside] + width))
        if level >= depth:
            grad, kink = _linearity(signed_distance, centre[cut], phi[cut], half[cut])
            leaf = ~kink if level < depth + EDGE_DEPTH else np.ones(len(kink), dtype=bool)
            rows = np.nonzero(cut)[0]
            done, rows = rows[leaf], rows[~leaf]
            smooth = ~kink[leaf]  # kinked ones here are at the last level: the plain rule
            for rule, sel in ((_leaf_moments, smooth), (_simple_leaf, ~smooth)):
                d = done[sel]
                np.add.at(out, cell[d], rule(signed_distance, centre[d], phi[d], half[d], lo[d], width,
                                             0.5 * size[cell[d]], grad[leaf][sel]))
            cut = np.zeros(len(cut), dtype=bool)
            cut[rows] = True
            if not cut.any():
                break
        width *= 0.5
        cell = np.repeat(cell[cut], 8)
        lo = (lo[cut][:, None, :] + width * CORNERS[None]).reshape(-1, 3)
    return out


#: further subdivision levels where the distance is not linear across a sub-cube (the solid's
#: edges and vertices, where the boundary has a kink)
EDGE_DEPTH = 4
#: a sub-cube is kinked when a second difference of the distance over its half edge exceeds
#: this share of the half edge (a smooth face of radius R gives about half / R, a right-angled
#: edge about 1)
KINK = 0.3


def _linearity(signed_distance: SignedDistance, centre, phi, half):
    """Central-difference gradient (q, 3) of the distance over each sub-cube's half edge, and
    whether the distance bends there: a second difference along an axis, or the deviation of
    the distance at a corner from the linear model, above KINK of the half edge."""
    grad = np.empty_like(centre)
    bend = np.zeros(len(phi))
    for k in range(3):
        step = np.zeros(3)
        step[k] = 1.0
        plus = np.asarray(signed_distance(centre + half[:, None] * step), float)
        minus = np.asarray(signed_distance(centre - half[:, None] * step), float)
        grad[:, k] = (plus - minus) / (2.0 * half)
        bend = np.maximum(bend, np.abs(plus + minus - 2.0 * phi))
    for corner in 2.0 * CORNERS - 1.0:
        offset = half[:, None] * corner
        linear = phi + (grad * offset).sum(axis=1)
        bend = np.maximum(bend, np.abs(np.asarray(signed_distance(centre + offset), float) - linear))
    return grad, bend > KINK * half


#: Gauss points per smooth piece in each direction of the leaf rule
LINE_POINTS = 4
#: Gauss points per direction of the plain rule on kinked sub-cubes
EDGE_POINTS = 3
#: regula falsi (Illinois) steps of the root search along each line
ROOT_STEPS = 30


def _leaf_moments(signed_distance: SignedDistance, centre, phi, half, lo, width: float, scale, grad) -> np.ndarray:
    """Moments (q, 27) of the inside parts of the last sub-cubes by dimension reduction (after
    Saye, SIAM J. Sci. Comput. 37 (2015) A993): lines along the height axis k (largest gradient
    component) carry the exact zero of the distance and closed-form monomial integrals; their
    feet are Gauss points of the cross-section, split where the integrand has kinks: along the
    base height axis j at the zeros of the distance on the sub-cube's two k-faces, and along the
    last axis i at the zeros on the four edges those faces share with the j-faces. Between the
    splits everything is smooth, so the rule converges spectrally with LINE_POINTS on smooth
    surfaces (sphere volume to about 1e-12 at 4 points) and is exact for a plane."""
    q = len(phi)
    out = np.zeros((q, 27))
    if q == 0:
        return out
    cell_lower = centre - (lo + 0.5 * width + 1.0) * scale[:, None]
    g = np.abs(grad)
    k_axis = np.argmax(g, axis=1)
    for k in range(3):
        others = [a for a in range(3) if a != k]
        j_first = g[:, others[0]] >= g[:, others[1]]
        for j, i in ((others[0], others[1]), (others[1], others[0])):
            rows = np.nonzero((k_axis == k) & (j_first if j == others[0] else ~j_first))[0]
            if len(rows):
                out[rows] = _reduced_rule(signed_distance, cell_lower[rows], scale[rows], lo[rows], width, k, j, i)
    return out


def _gauss_on(lo_edges: np.ndarray, hi_edges: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss nodes and weights (r, s n) on the intervals [lo_edges, hi_edges] (r, s)."""
    x, w = np.polynomial.legendre.leggauss(n)
    mid, half = 0.5 * (lo_edges + hi_edges), 0.5 * (hi_edges - lo_edges)
    nodes = (mid[:, :, None] + half[:, :, None] * x).reshape(len(mid), -1)
    return nodes, (half[:, :, None] * w).reshape(len(mid), -1)


def _split_points(f_ends, f, lo_t: np.ndarray, hi_t: np.ndarray) -> np.ndarray:
    """Sorted break points (r, 2 + F) of [lo_t, hi_t]: the ends and the zero of each of F
    functions where it changes sign (the lower end where it does not). ``f_ends(which)`` gives
    (values at lo_t, values at hi_t) of function ``which``; ``f(which, t, rows)`` its values."""
    points = [lo_t, hi_t]
    which = 0
    while True:
        ends = f_ends(which)
        if ends is None:
            break
        fa, fb = ends
        root = _bracketed_root(lambda t, rows, w=which: f(w, t, rows), lo_t.copy(), hi_t.copy(), fa.copy(), fb.copy())
        points.append(np.where((fa < 0.0) != (fb < 0.0), root, lo_t))
        which += 1
    return np.sort(np.stack(points, axis=1), axis=1)


def _reduced_rule(signed_distance, cell_lower, scale, lo, width: float, k: int, j: int, i: int) -> np.ndarray:
    """_leaf_moments for sub-cubes with height axis k, base height axis j and last axis i."""
    n = LINE_POINTS
    m = len(lo)
    hi = lo + width

    def phi(local, leaf):
        return np.asarray(signed_distance(cell_lower[leaf] + (local + 1.0) * scale[leaf, None]), dtype=float)

    # 1. along i: zeros of the distance on the four edges (j end, k end) of the sub-cube
    corners = [(lo[:, j], lo[:, k]), (hi[:, j], lo[:, k]), (lo[:, j], hi[:, k]), (hi[:, j], hi[:, k])]

    def edge_point(which, t, rows):
        x = np.empty((len(rows), 3))
        x[:, i], x[:, j], x[:, k] = t, corners[which][0][rows], corners[which][1][rows]
        return x

    def edge_f(which, t, rows):
        return phi(edge_point(which, t, rows), rows)

    every = np.arange(m)
    edge_ends = lambda w: None if w == 4 else (edge_f(w, lo[:, i], every), edge_f(w, hi[:, i], every))  # noqa: E731
    breaks_i = _split_points(edge_ends, edge_f, lo[:, i].copy(), hi[:, i].copy())
    ti, wi = _gauss_on(breaks_i[:, :-1], breaks_i[:, 1:], n)  # (m, 5 n)
    leaf = np.repeat(every, ti.shape[1])
    keep = wi.ravel() > 0.0  # the split's empty intervals carry no nodes
    ti, wi, leaf = ti.ravel()[keep], wi.ravel()[keep], leaf[keep]
    # 2. along j at each node of i: zeros of the distance on the two k-faces
    kface = [lo[leaf, k], hi[leaf, k]]
    rows_all = np.arange(len(leaf))

    def face_f(which, t, rows):
        x = np.empty((len(rows), 3))
        x[:, i], x[:, j], x[:, k] = ti[rows], t, kface[which][rows]
        return phi(x, leaf[rows])

    face_ends = lambda w: None if w == 2 else (face_f(w, lo[leaf, j], rows_all), face_f(w, hi[leaf, j], rows_all))  # noqa: E731
    breaks_j = _split_points(face_ends, face_f, lo[leaf, j].copy(), hi[leaf, j].copy())
    tj, wj = _gauss_on(breaks_j[:, :-1], breaks_j[:, 1:], n)  # (M, 3 n)
    per = tj.shape[1]
    keep = wj.ravel() > 0.0
    leaf2 = np.repeat(leaf, per)[keep]
    ti2, w2 = np.repeat(ti, per)[keep], (np.repeat(wi, per) * wj.ravel())[keep]
    tj2 = tj.ravel()[keep]
    # 3. along k: the inside interval between the zero and the end where the distance is positive
    base = np.empty((len(leaf2), 3))
    base[:, i], base[:, j] = ti2, tj2

    def line_f(t, rows):
        x = base[rows].copy()
        x[:, k] = t
        return phi(x, leaf2[rows])

    a, b = lo[leaf2, k].copy(), hi[leaf2, k].copy()
    everything = np.arange(len(leaf2))
    fa, fb = line_f(a, everything), line_f(b, everything)
    root = _bracketed_root(line_f, a.copy(), b.copy(), fa.copy(), fb.copy())
    t0 = np.where(fa >= 0.0, a, np.where(fb >= 0.0, root, b))
    t1 = np.maximum(np.where(fb >= 0.0, b, np.where(fa >= 0.0, root, a)), t0)
    e = STIFFNESS_EXPONENTS
    along = np.stack([(t1 ** (p + 1) - t0 ** (p + 1)) / (p + 1) for p in range(3)], axis=1)
    pi = np.stack([ti2**p for p in range(3)], axis=1)
    pj = np.stack([tj2**p for p in range(3)], axis=1)
    vals = along[:, e[:, k]] * pi[:, e[:, i]] * pj[:, e[:, j]] * w2[:, None]
    starts = np.flatnonzero(np.r_[True, leaf2[1:] != leaf2[:-1]])  # each leaf's nodes are contiguous
    out = np.zeros((m, 27))
    out[leaf2[starts]] = np.add.reduceat(vals, starts, axis=0)
    return out


def _simple_leaf(signed_distance: SignedDistance, centre, phi, half, lo, width: float, scale, grad) -> np.ndarray:
    """Moments (q, 27) of the inside parts of sub-cubes where the distance bends (the solid's
    edges, at the last subdivision level) by a plain height-function rule: lines
    along the axis of the largest component of the distance's gradient, through LINE_POINTS^2
    Gauss points of the cross-section; on each line the exact zero of the signed distance (a
    bracketed root search) bounds the inside interval, over which the monomials are integrated in
    closed form. Exact where the boundary crosses every line of a sub-cube along a plane, high order
    on smooth curved faces."""
    q = len(phi)
    if q == 0:
        return np.zeros((0, 27))
    axis = np.argmax(np.abs(grad), axis=1)
    x, w = np.polynomial.legendre.leggauss(EDGE_POINTS)
    gu, gv = np.meshgrid(x, x, indexing="ij")
    gw = np.outer(w, w).ravel() * (0.5 * width) ** 2  # local units (EDGE_POINTS per direction)
    gu, gv = gu.ravel(), gv.ravel()
    n_line = len(gw)
    out = np.zeros((q, 27))
    for k in range(3):
        rows = np.nonzero(axis == k)[0]
        if len(rows):
            out[rows] = _lines_along(k, signed_distance, lo[rows], width, scale[rows], centre[rows], half[rows],
                                     gu, gv, gw, n_line)
    return out


def _lines_along(k: int, signed_distance: SignedDistance, lo, width, scale, centre, half, gu, gv, gw, n_line):
    """_simple_leaf for sub-cubes whose lines run along axis k."""
    u, v = [j for j in range(3) if j != k]
    m = len(lo)
    local = np.repeat(lo, n_line, axis=0)  # (m n, 3) local coordinates of each line's start
    local[:, u] += 0.5 * width * (np.tile(gu, m) + 1.0)
    local[:, v] += 0.5 * width * (np.tile(gv, m) + 1.0)
    cell_lower = np.repeat(centre - (lo + 0.5 * width + 1.0) * scale[:, None], n_line, axis=0)
    sc = np.repeat(scale, n_line)

    def phi_at(t, rows=slice(None)):  # t: local coordinate along k, on the lines ``rows``
        pts = local[rows].copy()
        pts[:, k] = t
        return np.asarray(signed_distance(cell_lower[rows] + (pts + 1.0) * sc[rows, None]), dtype=float)

    a = local[:, k].copy()
    b = a + width
    fa, fb = phi_at(a), phi_at(b)
    root = _bracketed_root(phi_at, a.copy(), b.copy(), fa.copy(), fb.copy())
    t0 = np.where(fa >= 0.0, a, np.where(fb >= 0.0, root, b))  # inside interval [t0, t1]
    t1 = np.where(fb >= 0.0, b, np.where(fa >= 0.0, root, a))
    t1 = np.maximum(t1, t0)
    powers = np.stack([(t1 ** (p + 1) - t0 ** (p + 1)) / (p + 1) for p in range(3)], axis=1)  # (m n, 3)
    pu = np.stack([local[:, u] ** p for p in range(3)], axis=1)
    pv = np.stack([local[:, v] ** p for p in range(3)], axis=1)
    e = STIFFNESS_EXPONENTS
    vals = powers[:, e[:, k]] * pu[:, e[:, u]] * pv[:, e[:, v]] * np.tile(gw, m)[:, None]
    return vals.reshape(m, n_line, 27).sum(axis=1)


def _bracketed_root(f, a, b, fa, fb):
    """Zeros of f(t, rows) on [a, b] where fa, fb differ in sign (Illinois regula falsi,
    vectorised over the lines still active, to a step of 1e-14 of the interval); the lower end
    elsewhere (unused there)."""
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
        fx = f(xi, i)
        left = (fx < 0.0) == (fa[i] < 0.0)  # the root lies in [x, b]
        li, ri = i[left], i[~left]
        a[li], fa[li] = xi[left], fx[left]
        fb[li[side[li] == 1]] *= 0.5  # Illinois: halve the stale end
        side[li] = 1
        b[ri], fb[ri] = xi[~left], fx[~left]
        fa[ri[side[ri] == -1]] *= 0.5
        side[ri] = -1
        i = i[(step > tol[i]) & (fx != 0.0) & (np.abs(b[i] - a[i]) > tol[i])]
    return x
