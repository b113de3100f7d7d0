"""The strips between a CAD face's tessellation and its exact trimming curves.

A face's triangles end on chords of its boundary edges; mapped onto the exact surface they
cover the face but for a thin strip along every curved trimming edge (a planar disc bounded by
a circle loses the segments between the circle and its chords: of order the chord sag times the
perimeter). Here each boundary chord (u, v) of the triangulation is closed against its edge's
exact curve by the triangle (v, u, m), m the curve's point nearest the chord's midpoint, and the
two halves (u, m), (m, v) likewise, until the halves' sag would be below a fraction of the part's
size; a chord's last triangle counts 4/3 (the segment of a parabola is 4/3 of its inscribed
triangle, Archimedes), which leaves an error of the fourth order in the chord's length. A
triangle wound against the face's (the curve bulges into the face: a hole, a concave trim)
counts negatively. With these strips the faces of a closed solid close up and its volume by
the divergence theorem is exact to about 1e-10 on a ball (5e-4 without them).
"""

from __future__ import annotations

import numpy as np

__all__ = ["boundary_chords", "strip_triangles", "closed_rule"]

#: strips are refined until the sag of every chord is below this fraction of the part's size
SAG_FRACTION = 1e-6
#: at most this many halvings of a boundary chord (2^5 pieces)
MAX_DEPTH = 5


def boundary_chords(triangles: np.ndarray):
    """The chords (u, v) of the triangulation's boundary (edges of one triangle only), in the
    triangles' winding, with their triangle's outward normal: (k, 3) each."""
    verts, ids = np.unique(triangles.reshape(-1, 3), axis=0, return_inverse=True)
    ids = ids.reshape(-1, 3)
    a, b = ids.ravel(), np.roll(ids, -1, axis=1).ravel()
    key = np.minimum(a, b) * len(verts) + np.maximum(a, b)
    _, first, count = np.unique(key, return_index=True, return_counts=True)
    once = first[count == 1]
    tri_of = once // 3
    normal = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    return verts[a[once]], verts[b[once]], normal[tri_of]


def _on_polyline(points: np.ndarray, line: np.ndarray, tol: float) -> np.ndarray:
    """Whether each point lies within ``tol`` of the polyline (n,)."""
    near = np.zeros(len(points), bool)
    for a, b in zip(line[:-1], line[1:]):
        e = b - a
        t = np.clip(((points - a) @ e) / max(float(e @ e), 1e-300), 0.0, 1.0)
        near |= np.linalg.norm(points - a - t[:, None] * e, axis=1) <= tol
    return near


def _owners(u: np.ndarray, v: np.ndarray, edges, tol: float) -> np.ndarray:
    """The index in ``edges`` of the edge each chord lies on (both ends within ``tol`` of its
    polyline, the edge's own tessellation, which the face's need not share; of
    several, the one whose exact curve passes nearest the chord's midpoint), -1 for none or an
    edge without an exact curve."""
    owner, best = np.full(len(u), -1), np.full(len(u), np.inf)
    mid = 0.5 * (u + v)
    for k, e in enumerate(edges):
        line = np.asarray(e.polyline, float)
        if e.curve is None or len(line) < 2:
            continue
        on = np.flatnonzero(_on_polyline(u, line, tol) & _on_polyline(v, line, tol))
        if not len(on):
            continue
        d = np.abs(np.asarray(e.curve.project(mid[on]).distances, float))
        closer = d < best[on]
        owner[on[closer]], best[on[closer]] = k, d[closer]
    return owner


def _feet(points: np.ndarray, owner: np.ndarray, edges) -> np.ndarray:
    """Each point's nearest point on the exact curve of its edge."""
    feet = np.array(points, dtype=float)
    for k in np.unique(owner):
        sel = owner == k
        feet[sel] = np.asarray(edges[k].curve.project(points[sel]).points, float)
    return feet


def strip_triangles(triangles: np.ndarray, edges, size: float, tol: float):
    """Triangles (k, 3, 3) filling the strips between the boundary chords and the exact curves
    of the edges they lie on (``edges``: the face's trimming edges) and their weights (k,): +1
    wound as the face, -1 against it, times 4/3 for a chord's last triangle. A chord on no edge
    with an exact curve gets no strip;
    ``tol``: how far the face's boundary vertices may lie from the edges' polylines."""
    u, v, normal = boundary_chords(triangles)
    owner = _owners(u, v, edges, tol)
    has = owner >= 0
    u, v, normal, owner = u[has], v[has], normal[has], owner[has]
    out, signs = [], []
    for depth in range(MAX_DEPTH):
        if not len(u):
            break
        mid = 0.5 * (u + v)
        m = _feet(mid, owner, edges)
        sag = np.linalg.norm(m - mid, axis=1)
        keep = (sag > SAG_FRACTION * size) & (sag < 0.5 * np.linalg.norm(v - u, axis=1))
        u, v, m, normal, owner, sag = u[keep], v[keep], m[keep], normal[keep], owner[keep], sag[keep]
        out.append(np.stack([v, u, m], axis=1))
        # the last triangle of a chord counts 4/3: the segment of a parabola is 4/3 of the
        # triangle inscribed on its chord (Archimedes), and the halves' sags are a quarter
        last = (0.25 * sag <= SAG_FRACTION * size) | (depth == MAX_DEPTH - 1)
        signs.append(np.sign((np.cross(u - v, m - v) * normal).sum(axis=1)) * np.where(last, 4.0 / 3.0, 1.0))
        go = ~last
        u, v = np.concatenate([u[go], m[go]]), np.concatenate([m[go], v[go]])
        normal, owner = np.concatenate([normal[go], normal[go]]), np.concatenate([owner[go], owner[go]])
    if not out:
        return np.zeros((0, 3, 3)), np.zeros(0)
    return np.concatenate(out), np.concatenate(signs)


def closed_rule(face, edges, size: float, tol: float):
    """The face's quadrature (points, weights, outward normals) on its triangles split to an
    eighth of ``size`` plus its trimming strips (weights signed): a rule that closes up with
    its neighbours' on a closed solid."""
    x, w, n = face.quadrature(size / 8)
    if face.surface is None:
        return x, w, n
    strips, signs = strip_triangles(face.triangles, edges, size, tol)
    if not len(strips):
        return x, w, n
    xs, ws, ns = face.mapped_rule(strips, size / 8)
    ws = ws * np.repeat(signs, len(ws) // len(signs))
    return np.concatenate([x, xs]), np.concatenate([w, ws]), np.concatenate([n, ns])
