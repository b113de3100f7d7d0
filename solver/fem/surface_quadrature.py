"""Quadrature on a parametric surface split at the planes of the octree: the
boundary integrals of the step-boundary method and of 3D contact integrate trilinear fields,
which have kinks on every cell face, so a rule is exact only on pieces that lie in one cell.

A face supplies its parameter domain as rectangles (``panels(resolution)``: lower and upper
corners (p, 2) in (u, v), each at most ``resolution`` across in space) and its exact map
(``evaluate(uv) -> points (n, 3), normals (n, 3), area element (n,)``). Each panel is cut by the
preimages of the grid planes x_k = origin_k + j h (h the finest cell size: every cell face of the
octree lies on one of them) taken on the panel's affine approximation, as convex polygons in
(u, v) (Sutherland-Hodgman, vectorised over the panels); each piece is split into triangles
with a collapsed Gauss rule (Gauss-Jacobi x Gauss-Legendre, exact to degree 2n - 1). The points
and normals are the exact surface's; the weights carry its exact area element. On a planar face
the pieces are exactly the face's parts in each cell, so a trilinear integrand is integrated
exactly (the patch test); on a curved face the cut lines are chords of the preimage curves,
second order in the panel size, which the panels keep below the cells.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["split_panels", "clip_to_grid", "triangle_nodes", "cell_split_quadrature", "gauss_jacobi", "MAX_VERTICES",
           "slab_trapezoids", "polygon_split_quadrature"]

#: most vertices of a clipped panel (a rectangle cut by six lines has at most ten)
MAX_VERTICES = 12


def gauss_jacobi(n: int, alpha: float, beta: float) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Jacobi nodes and weights for the weight (1 - x)^alpha (1 + x)^beta on [-1, 1]
    (alpha + beta > 0): Golub-Welsch, the eigenvalues of the Jacobi matrix of the monic
    recurrence and the first eigenvector components squared times mu_0 = int w. Written here
    because scipy.special costs every run 35 ms to import."""
    k = np.arange(n, dtype=float)
    s = 2.0 * k + alpha + beta
    diag = (beta**2 - alpha**2) / (s * (s + 2.0))
    k1, s1 = k[1:], s[1:]
    off = np.sqrt(4.0 * k1 * (k1 + alpha) * (k1 + beta) * (k1 + alpha + beta) / (s1**2 * (s1 + 1.0) * (s1 - 1.0)))
    nodes, vectors = np.linalg.eigh(np.diag(diag) + np.diag(off, 1) + np.diag(off, -1))
    mu0 = 2.0 ** (alpha + beta + 1.0) * np.exp(math.lgamma(alpha + 1.0) + math.lgamma(beta + 1.0)
                                              - math.lgamma(alpha + beta + 2.0))
    return nodes, mu0 * vectors[0] ** 2


def _triangle_rule(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric-free rule on the reference triangle (0,0), (1,0), (0,1): points (n^2, 2) and
    weights summing to 1/2 (collapsed Gauss, exact to degree 2n - 1)."""
    xj, wj = gauss_jacobi(n, 1.0, 0.0)
    xl, wl = np.polynomial.legendre.leggauss(n)
    r = 0.5 * (1.0 + xj)
    s = 0.5 * (1.0 + xl)
    rr, ss = np.meshgrid(r, s, indexing="ij")
    pts = np.stack([rr.ravel(), ((1.0 - rr) * ss).ravel()], axis=1)
    return pts, (np.outer(wj, wl) / 8.0).ravel()


def _clip(poly: np.ndarray, count: np.ndarray, a: np.ndarray, b: np.ndarray, keep_positive: bool):
    """Sutherland-Hodgman: the part of each convex polygon (n, K, 2) with ``count`` vertices where
    a . uv + b >= 0 (or <= 0); returns the clipped polygons and counts."""
    n, k = poly.shape[:2]
    f = np.einsum("nkj,nj->nk", poly, a) + b[:, None]
    if not keep_positive:
        f = -f
    out = np.zeros_like(poly)
    out_count = np.zeros(n, dtype=np.int64)
    rows = np.arange(n)
    for i in range(k):
        valid = i < count
        j = np.where(i + 1 < count, i + 1, 0)
        p, q = poly[:, i], poly[rows, j]
        fp, fq = f[:, i], f[rows, j]
        keep_p = valid & (fp >= 0.0)
        out[rows[keep_p], out_count[keep_p]] = p[keep_p]
        out_count += keep_p
        cross = valid & ((fp >= 0.0) != (fq >= 0.0))
        t = np.where(cross, fp / np.where(cross, fp - fq, 1.0), 0.0)
        x = p + t[:, None] * (q - p)
        out[rows[cross], np.minimum(out_count[cross], k - 1)] = x[cross]
        out_count += cross
    return out, np.minimum(out_count, k)


def _rectangles(lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """(p, 4, 2) corners (u0, v0), (u1, v0), (u1, v1), (u0, v1) of parameter rectangles."""
    return np.stack([lower, np.column_stack([upper[:, 0], lower[:, 1]]), upper,
                     np.column_stack([lower[:, 0], upper[:, 1]])], axis=1)


def split_panels(lower: np.ndarray, upper: np.ndarray, corner_points: np.ndarray, origin: np.ndarray,
                 spacing) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Convex pieces (m, K, 2) in (u, v) of the panels [lower, upper], cut at the grid planes
    x_k = origin_k + j spacing as seen on each panel's affine approximation (from its corner
    points (p, 4, 3): (u0, v0), (u1, v0), (u1, v1), (u0, v1)); returns the pieces, their vertex
    counts and the panel each came from."""
    p = len(lower)
    poly = np.zeros((p, MAX_VERTICES, 2))
    poly[:, :4] = _rectangles(lower, upper)
    count = np.full(p, 4, dtype=np.int64)
    return clip_to_grid(poly, count, np.arange(p), lower, upper, corner_points, origin, spacing)


def clip_to_grid(poly: np.ndarray, count: np.ndarray, owner: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                 corner_points: np.ndarray, origin: np.ndarray, spacing: float):
    """Cut convex pieces (n, K, 2) of panels (``owner``: the panel of each) at the grid planes
    x_k = origin_k + j spacing, seen on each panel's affine map from its corner points (p, 4, 3)
    over [lower, upper]; (pieces, counts, owners). Applied twice, it cuts at two grids (contact:
    the planes of both bodies)."""
    origin = np.asarray(origin, dtype=float)
    spacing = np.broadcast_to(np.asarray(spacing, dtype=float), (len(lower),))  # per panel
    c = corner_points[:, 0]
    extent = upper - lower
    extent = np.where(extent != 0.0, extent, 1.0)
    a_u = (corner_points[:, 1] - corner_points[:, 0]) / extent[:, :1]
    a_v = (corner_points[:, 3] - corner_points[:, 0]) / extent[:, 1:]
    for k in range(3):
        lo = (corner_points[:, :, k].min(axis=1) - origin[k]) / spacing
        hi = (corner_points[:, :, k].max(axis=1) - origin[k]) / spacing  # per panel, in its spacing
        first = np.floor(lo).astype(np.int64) + 1
        last = np.ceil(hi).astype(np.int64) - 1
        for step in range(int(max(0, (last - first).max(initial=-1) + 1))):
            plane = first + step  # the step-th plane inside each panel's range
            cut = plane[owner] <= last[owner]
            if not cut.any():
                continue
            idx = np.nonzero(cut)[0]
            o = owner[idx]
            level = origin[k] + plane[o] * spacing[o]
            # X_k(uv) - level = a . uv + b on the affine map
            a = np.stack([a_u[o, k], a_v[o, k]], axis=1)
            b = c[o, k] - level - a_u[o, k] * lower[o, 0] - a_v[o, k] * lower[o, 1]
            pos, npos = _clip(poly[idx], count[idx], a, b, True)
            neg, nneg = _clip(poly[idx], count[idx], a, b, False)
            poly[idx], count[idx] = pos, npos
            poly = np.concatenate([poly, neg])
            count = np.concatenate([count, nneg])
            owner = np.concatenate([owner, o])
            keep = count >= 3
            poly, count, owner = poly[keep], count[keep], owner[keep]
    return poly, count, owner


def triangle_nodes(poly: np.ndarray, count: np.ndarray, order: int = 4) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes (N, 2) and weights (N,) of the collapsed Gauss rule on the fan triangles of convex
    pieces (n, K, 2), and the piece of each node."""
    ref, ref_w = _triangle_rule(order)
    uv, w, piece = [], [], []
    for t in range(1, MAX_VERTICES - 1):  # fan triangles (0, t, t + 1)
        has = count > t + 1
        if not has.any():
            break
        p0, p1, p2 = poly[has, 0], poly[has, t], poly[has, t + 1]
        e1, e2 = p1 - p0, p2 - p0
        area2 = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])  # twice the triangle's area in (u, v)
        uv.append((p0[:, None, :] + ref[None, :, :1] * e1[:, None, :] + ref[None, :, 1:] * e2[:, None, :]).reshape(-1, 2))
        w.append((area2[:, None] * ref_w[None, :]).ravel())
        piece.append(np.repeat(np.nonzero(has)[0], len(ref_w)))
    if not uv:
        return np.zeros((0, 2)), np.zeros(0), np.zeros(0, dtype=np.int64)
    return np.concatenate(uv), np.concatenate(w), np.concatenate(piece)


def cell_split_quadrature(face, resolution: float, origin: np.ndarray, spacing: float, order: int = 4,
                          cell_size=None, levels: int = 12):
    """Points (q, 3), weights (q,), outward normals (q, 3) on ``face`` (``panels`` / ``evaluate``),
    every point's rule lying in one cell of a grid whose faces lie on the planes origin + j
    spacing. ``cell_size(points, normals) -> sizes``: the local cell size at face points; panels start at ``resolution``
    and are split in four (up to ``levels`` times) while larger than the cells at their corners
    and centre, so a face crossing coarse cells gets few points."""
    lower, upper = (np.asarray(x, dtype=float).reshape(-1, 2) for x in face.panels(resolution))
    panel_spacing = np.full(len(lower), float(spacing))
    if cell_size is not None:
        lower, upper, local = _graded_panels(face, lower, upper, cell_size, levels)
        panel_spacing = np.maximum(local, float(spacing))  # the planes of the panel's own cells
    corners = _rectangles(lower, upper)
    corner_points = face.evaluate(corners.reshape(-1, 2))[0].reshape(-1, 4, 3)
    origin = np.asarray(origin, dtype=float)
    poly, count, owner = split_panels(lower, upper, corner_points, origin, panel_spacing)
    if cell_size is not None:
        poly, count = _split_at_finer_cells(face, cell_size, (poly, count, owner), (lower, upper, corner_points),
                                            origin, panel_spacing, float(spacing))
    uv, w, _ = triangle_nodes(poly, count, order)
    points, normals, jacobian = face.evaluate(uv)
    weights = w * np.asarray(jacobian, dtype=float)
    keep = weights > 0.0
    return points[keep], weights[keep], normals[keep]


def _split_at_finer_cells(face, cell_size, pieces, panels, origin, panel_spacing, spacing: float):
    """Pieces cut at the planes of their panel's cells, cut again where a cell is finer: a
    piece lies in one lattice box of its panel's spacing, which is one cell, part of a coarser
    one, or split into finer cells, one of which then holds the piece's centroid (octree cells
    lie on the lattices origin + j h0 / 2^l). Panels holding such a piece are cut at the finer
    cells' planes (2:1 balance: once, in practice)."""
    poly, count, owner = pieces
    lower, upper, corner_points = panels
    panel_spacing = panel_spacing.copy()
    while len(poly):
        valid = np.arange(MAX_VERTICES)[None, :] < count[:, None]
        centroid = (poly * valid[:, :, None]).sum(axis=1) / count[:, None]
        pts, nrm, _ = face.evaluate(centroid)
        finer = np.full(len(lower), np.inf)
        np.minimum.at(finer, owner, np.asarray(cell_size(pts, nrm), dtype=float))
        redo = finer < (1.0 - 1e-9) * panel_spacing
        if not redo.any():
            break
        panel_spacing[redo] = np.maximum(finer[redo], spacing)
        sel = redo[owner]
        p2, c2, o2 = clip_to_grid(poly[sel], count[sel], owner[sel], lower, upper, corner_points, origin,
                                  panel_spacing)
        poly, count, owner = (np.concatenate([x[~sel], y]) for x, y in ((poly, p2), (count, c2), (owner, o2)))
    return poly, count


def _graded_panels(face, lower, upper, cell_size, levels: int):
    """Panels split in four while a side's length in space exceeds the smallest cell at their
    corners and centre."""
    done_lo, done_hi, done_size = [], [], []
    size = np.zeros(len(lower))
    for _ in range(levels + 1):
        if len(lower) == 0:
            break
        corners = np.concatenate([_rectangles(lower, upper), (0.5 * (lower + upper))[:, None, :]], axis=1)
        pts, nrm, _ = face.evaluate(corners.reshape(-1, 2))
        size = np.asarray(cell_size(pts, nrm), dtype=float).reshape(-1, 5).min(axis=1)
        pts = pts.reshape(-1, 5, 3)
        # the longest side (a panel as large as its cells: a cell holds about one panel's piece)
        sides = np.roll(pts[:, :4], -1, axis=1) - pts[:, :4]
        extent = np.linalg.norm(sides, axis=2).max(axis=1)
        split = extent > 1.0001 * size
        done_lo.append(lower[~split])
        done_hi.append(upper[~split])
        done_size.append(size[~split])
        lo, hi = lower[split], upper[split]
        mid = 0.5 * (lo + hi)
        lower = np.concatenate([lo, np.column_stack([mid[:, 0], lo[:, 1]]), mid, np.column_stack([lo[:, 0], mid[:, 1]])])
        upper = np.concatenate([mid, np.column_stack([hi[:, 0], mid[:, 1]]), hi, np.column_stack([mid[:, 0], hi[:, 1]])])
    done_lo.append(lower)
    done_hi.append(upper)
    done_size.append(np.tile(size[split], 4) if len(lower) else np.zeros(0))  # panels left at the last level
    return np.concatenate(done_lo), np.concatenate(done_hi), np.concatenate(done_size)


def slab_trapezoids(edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Convex pieces (n, MAX_VERTICES, 2) and vertex counts of a region bounded by straight
    edges (k, 2, 2) (any number of loops, convex or not, holes included): between consecutive
    vertex heights p1 the edges crossing the slab, ordered along p0, bound the inside trapezoids
    in pairs (the even-odd rule)."""
    edges = np.asarray(edges, dtype=float)
    y = edges[:, :, 1]
    lo, hi = y.min(axis=1), y.max(axis=1)
    levels = np.unique(y)
    pieces = []
    for y0, y1 in zip(levels[:-1], levels[1:]):
        span = (lo <= y0) & (hi >= y1) & (hi > lo)
        e = edges[span]
        if len(e) < 2:
            continue
        slope = (e[:, 1, 0] - e[:, 0, 0]) / (e[:, 1, 1] - e[:, 0, 1])
        x0 = e[:, 0, 0] + (y0 - e[:, 0, 1]) * slope
        x1 = e[:, 0, 0] + (y1 - e[:, 0, 1]) * slope
        order = np.argsort(0.5 * (x0 + x1), kind="stable")
        x0, x1 = x0[order], x1[order]
        a, b = slice(0, len(order) - 1, 2), slice(1, len(order), 2)
        n = len(x0[a])
        quad = np.stack([np.column_stack([x0[a], np.full(n, y0)]), np.column_stack([x0[b], np.full(n, y0)]),
                         np.column_stack([x1[b], np.full(n, y1)]), np.column_stack([x1[a], np.full(n, y1)])], axis=1)
        pieces.append(quad)
    if not pieces:
        return np.zeros((0, MAX_VERTICES, 2)), np.zeros(0, dtype=np.int64)
    quads = np.concatenate(pieces)
    poly = np.zeros((len(quads), MAX_VERTICES, 2))
    poly[:, :4] = quads
    return poly, np.full(len(quads), 4, dtype=np.int64)


def _affine_panels(poly: np.ndarray, count: np.ndarray, place):
    """Each piece as its own panel: the bounding rectangle in (u, v) and its corners placed by
    the affine map ``place(uv) -> points``."""
    valid = np.arange(MAX_VERTICES)[None, :] < count[:, None]
    lower = np.where(valid[:, :, None], poly, np.inf).min(axis=1)
    upper = np.where(valid[:, :, None], poly, -np.inf).max(axis=1)
    corners = place(_rectangles(lower, upper).reshape(-1, 2)).reshape(-1, 4, 3)
    return lower, upper, corners


def polygon_split_quadrature(polygon, normal, resolution: float, origin: np.ndarray, spacing: float,
                             order: int = 4, cell_size=None):
    """Points (q, 3), weights (q,) and normals (q, 3) on a planar region bounded by straight
    edges, ``polygon`` = (plane origin, axes e0, e1, edges (k, 2, 2) in plane coordinates), every
    piece cut at the planes of the cell holding it: the region's trapezoids (:func:`slab_trapezoids`)
    cut at the grid of spacing ``resolution``, then each piece again at the planes of a finer cell
    holding its centroid (``cell_size(points, normals) -> sizes``) until none is finer (at least
    ``spacing``). The pieces are exactly the region's parts in each cell, so a trilinear integrand
    is integrated exactly."""
    plane_origin, e0, e1, edges = polygon
    plane_origin, e0, e1 = (np.asarray(v, dtype=float) for v in (plane_origin, e0, e1))
    normal = np.asarray(normal, dtype=float).reshape(3)

    def place(uv):
        return plane_origin + uv[:, :1] * e0 + uv[:, 1:] * e1

    origin = np.asarray(origin, dtype=float)
    poly, count = slab_trapezoids(edges)
    piece_spacing = np.full(len(poly), float(resolution))  # the planes each piece has been cut at
    cut = np.ones(len(poly), dtype=bool)
    while cut.any():
        lower, upper, corners = _affine_panels(poly[cut], count[cut], place)
        p2, c2, owner = clip_to_grid(poly[cut], count[cut], np.arange(int(cut.sum())), lower, upper, corners,
                                     origin, piece_spacing[cut])
        poly, count = np.concatenate([poly[~cut], p2]), np.concatenate([count[~cut], c2])
        piece_spacing = np.concatenate([piece_spacing[~cut], piece_spacing[cut][owner]])
        if cell_size is None:
            break
        valid = np.arange(MAX_VERTICES)[None, :] < count[:, None]
        centroid = place((poly * valid[:, :, None]).sum(axis=1) / count[:, None])
        local = np.maximum(np.asarray(cell_size(centroid, np.broadcast_to(normal, centroid.shape)), float), spacing)
        cut = local < (1.0 - 1e-9) * piece_spacing
        piece_spacing = np.where(cut, local, piece_spacing)
    uv, w, _ = triangle_nodes(poly, count, order)
    area = float(np.linalg.norm(np.cross(e0, e1)))
    points = place(uv)
    keep = w > 0.0
    return points[keep], w[keep] * area, np.broadcast_to(normal, points.shape).copy()[keep]
