"""Volume and centroid of a CAD solid by the divergence theorem, each face integrated over its
own parameter domain with its exact surface.

A face is x = S(u, v) over a trimmed domain D of the (u, v) plane; m = S_u x S_v is the surface's
own normal times its area element. About a reference point c of the face (y = x - c), its
moments are

    N = int_D m du dv,   H_i = int_D y_i m_i du dv,   G_i = 1/2 int_D y_i^2 m_i du dv   (no sum),

and over the outward-oriented faces of a closed solid (sign s_f = +1 or -1 for a face whose
outward normal is the surface's own or the opposite), with d = c_f - c0 for any point c0,

    V = 1/3 sum_f s_f (H_1 + H_2 + H_3 + d . N),
    int_V (x - c0)_i dV = sum_f s_f (G_i + d_i H_i + d_i^2 N_i / 2)

(divergence theorem with the fields (x - c0) / 3 and (x - c0)_i^2 e_i / 2). Every face is
integrated about its own point and the solid about its own centre, so the result does not depend
on where the part is placed.

The domain D is the tessellation's triangles in (u, v), which the mesher builds there, plus the
strips between its boundary chords and the trimming curves in (u, v) (the edges' curves on the
surface). In (u, v) the triangles tile the domain exactly however far their 3D images stray from
a sharply bent surface; the strips are the only approximation of the domain, and each is
integrated as the ruled region between its chord and its curve. Where the mesher's boundary
leaves the curves' polygon (a shortcut between two of its nodes), fans of triangles fill the
difference (:func:`gap_rule`). Triangles across a line of u or v where the surface's derivatives
jump (a B-spline's multiple knots) are cut along it, so each piece is integrated where the
surface is smooth. Gauss rules: Dunavant's 6-point rule of degree 4 on the triangles
(D. A. Dunavant, Int. J. Numer. Meth. Eng. 21 (1985) 1129-1148), Gauss-Legendre along and
across each strip.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..quadrature import gauss_legendre, quartered

__all__ = ["FaceMoments", "triangle_rule", "domain_rule", "strip_rule", "gap_rule", "strip_parameters",
           "boundary_edges", "chain_side", "face_moments", "solid_moments", "STRIP_NODES"]

# symmetric 6-point rule on triangles, degree 4 (Dunavant 1985), barycentric (a, a, 1 - 2a)
_A = (0.445948490915965, 0.091576213509771)
_W = (0.223381589678011, 0.109951743655322)
#: Gauss-Legendre nodes along a strip (its chord) and across it (chord to curve)
STRIP_NODES = (6, 3)


def triangle_rule() -> tuple[np.ndarray, np.ndarray]:
    """Barycentric points (6, 3) and weights (6,) summing to 1 (a fraction of the triangle's area)."""
    bary, w = [], []
    for a, wt in zip(_A, _W):
        b = 1.0 - 2.0 * a
        bary += [(a, a, b), (a, b, a), (b, a, a)]
        w += [wt] * 3
    return np.array(bary), np.array(w)


def _unit_nodes(order: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = gauss_legendre(order)
    return 0.5 * (x + 1.0), 0.5 * w


def strip_parameters() -> np.ndarray:
    """The fractions s in [0, 1] along a chord at which its trimming curve is sampled."""
    return _unit_nodes(STRIP_NODES[0])[0]


def _cut(corners: np.ndarray, axis: int, at: float) -> np.ndarray:
    """Triangles (m, 3, 2) with the ones that straddle the line (u or v, ``axis``) = ``at`` cut
    into three along it (the corner alone on its side, the two points where the line crosses
    its edges, the other two corners)."""
    s = corners[:, :, axis] - at
    below, above = (s < 0).sum(axis=1), (s > 0).sum(axis=1)
    cross = (below > 0) & (above > 0)
    if not cross.any():
        return corners
    tri, s = corners[cross], s[cross]
    lone = np.where((s < 0).sum(axis=1) == 1, np.argmax(s < 0, axis=1), np.argmax(s > 0, axis=1))
    order = (lone[:, None] + np.arange(3)[None]) % 3  # the lone corner first, the winding kept
    tri = np.take_along_axis(tri, order[:, :, None], axis=1)
    s = np.take_along_axis(s, order, axis=1)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    p = a + (s[:, 0] / (s[:, 0] - s[:, 1]))[:, None] * (b - a)
    q = a + (s[:, 0] / (s[:, 0] - s[:, 2]))[:, None] * (c - a)
    pieces = [np.stack(t, axis=1) for t in ((a, p, q), (p, b, c), (p, c, q))]
    return np.concatenate([corners[~cross]] + pieces)


def domain_rule(uv: np.ndarray, triangles: np.ndarray, cuts: tuple = ((), ())) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 2) and weights (n,) of the triangle rule on a triangulation of the (u, v) plane
    (``uv`` (k, 2) nodes, ``triangles`` (m, 3) node indices); weights are (u, v) areas.
    ``cuts``: the values of u and of v where the surface's derivatives jump (a B-spline's knots
    of low continuity); triangles across them are cut there, so that every piece is integrated
    over a smooth part of the surface."""
    corners = np.asarray(uv, float)[np.asarray(triangles)]
    for axis in (0, 1):
        for at in cuts[axis]:
            corners = _cut(corners, axis, float(at))
    bary, w = triangle_rule()
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    points = np.einsum("gk,tkd->tgd", bary, corners).reshape(-1, 2)
    return points, (area[:, None] * w[None]).ravel()


def strip_rule(a: np.ndarray, b: np.ndarray, side: np.ndarray, curve: np.ndarray, tangent: np.ndarray,
               span: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points and signed weights (in (u, v) area) of the strips between boundary chords and their
    trimming curves.

    ``a``, ``b`` (k, 2): the chords' ends; ``side`` (k,): +1 where the domain lies to the left of
    a -> b, -1 to the right; ``curve``, ``tangent`` (k, S, 2): the trimming curve C(t) and dC/dt at
    t = t0 + s (t1 - t0), s the :func:`strip_parameters`, C(t0) and C(t1) at (or next to) a and
    b; ``span`` (k,): t1 - t0. The strip is the ruled region M(s, r) = L(s) + r (C(t(s)) - L(s)),
    L(s) = a + s (b - a), r in [0, 1]; it counts positively where the curve lies beyond the chord
    (outside the polygon of the chords) and negatively where it lies inside. Where the curve's end
    misses its node, the neighbouring chord's strip starts from the same point of the curve, so
    the strips still close up.
    """
    s, ws = _unit_nodes(STRIP_NODES[0])
    r, wr = _unit_nodes(STRIP_NODES[1])
    chord = b - a
    line = a[:, None, :] + s[None, :, None] * chord[:, None, :]  # (k, S, 2)
    gap = curve - line  # M_r
    along = tangent * span[:, None, None]  # dC/ds
    # M_s = (1 - r) (b - a) + r dC/ds, at every (s, r): (k, S, R, 2)
    m_s = (1.0 - r)[None, None, :, None] * chord[:, None, None, :] + r[None, None, :, None] * along[:, :, None, :]
    det = m_s[..., 0] * gap[:, :, None, 1] - m_s[..., 1] * gap[:, :, None, 0]
    points = line[:, :, None, :] + r[None, None, :, None] * gap[:, :, None, :]
    weights = -side[:, None, None] * det * ws[None, :, None] * wr[None, None, :]
    return points.reshape(-1, 2), weights.ravel()


def boundary_edges(uv: np.ndarray, triangles: np.ndarray) -> set[tuple[int, int]]:
    """The triangulation's boundary edges (those of one triangle), directed with the triangle on
    their left in (u, v)."""
    corners = uv[triangles]
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    ccw = np.where((e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] >= 0.0)[:, None], triangles, triangles[:, ::-1])
    a, b = ccw.ravel(), np.roll(ccw, -1, axis=1).ravel()
    key = np.minimum(a, b) * len(uv) + np.maximum(a, b)
    _, first, count = np.unique(key, return_index=True, return_counts=True)
    once = first[count == 1]
    return set(zip(a[once].tolist(), b[once].tolist()))


def _split(corners: np.ndarray, size: float, budget: int, rounds: int = 8) -> np.ndarray:
    """Triangles (k, 3, 2) split into four at their edges' midpoints until no edge spans more
    than ``size`` in u or v (the triangulation's own size: a fan's long thin triangles get as
    many Gauss points as the mesh has there), or until there would be more than ``budget``."""
    for _ in range(rounds):
        long = np.abs(corners - np.roll(corners, 1, axis=1)).max(axis=(1, 2)) > size
        if not long.any() or len(corners) + 3 * int(long.sum()) > budget:
            break
        corners = np.concatenate([corners[~long], quartered(corners[long])])
    return corners


def chain_side(boundary: set[tuple[int, int]], nodes: np.ndarray, default: int) -> int:
    """+1 when the domain lies to the left of the chain of nodes (a trimming curve's polygon, in
    its order), -1 to the right: by its chords on the triangulation's ``boundary`` (which side
    their triangles are on), ``default`` when none of them is on it."""
    pairs = list(zip(nodes[:-1].tolist(), nodes[1:].tolist()))
    vote = sum((i, j) in boundary for i, j in pairs) - sum((j, i) in boundary for i, j in pairs)
    return default if vote == 0 else (1 if vote > 0 else -1)


def _cycles(edges: list[tuple[int, int]]) -> list[list[int]]:
    """Closed walks covering the directed ``edges`` (each used once); edges that close no walk
    are left out."""
    out: dict[int, list[int]] = {}
    for a, b in edges:
        out.setdefault(a, []).append(b)
    cycles = []
    for start in list(out):
        while out.get(start):
            walk, node = [start], out[start].pop()
            while node != start and out.get(node):
                walk.append(node)
                node = out[node].pop()
            if node == start:
                cycles.append(walk)
    return cycles


def gap_rule(uv: np.ndarray, triangles: np.ndarray, chords: np.ndarray,
             boundary: set[tuple[int, int]] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Points and signed weights of the regions between the polygon of the trimming curves'
    chords and the triangulation's boundary, where the two differ (a mesher that joins two
    boundary nodes by a shortcut instead of following the curve's polygon).

    ``chords`` (k, 2): the polygon's chords as node pairs directed with the domain on their left;
    ``boundary``: :func:`boundary_edges`, when already known.
    The chords not on the triangulation's boundary and the boundary edges not among the chords
    (reversed) form closed walks; the fan of triangles from each walk's first node, with signed
    areas, weighs every point by the polygon's winding number minus the triangulation's.
    """
    boundary = boundary_edges(uv, triangles) if boundary is None else boundary
    polygon = set(map(tuple, np.asarray(chords, int).tolist()))
    extra = [e for e in polygon if e not in boundary] + [(b, a) for a, b in boundary if (a, b) not in polygon]
    fans = [(walk[0], p, q) for walk in _cycles(extra) for p, q in zip(walk[1:-1], walk[2:])]
    if not fans:
        return np.zeros((0, 2)), np.zeros(0)
    bary, w = triangle_rule()
    mesh = uv[triangles]
    size = float(np.median(np.abs(mesh - np.roll(mesh, 1, axis=1)).max(axis=(1, 2))))
    corners = _split(uv[np.array(fans)], size, budget=max(len(triangles), 1024))
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return np.einsum("gk,tkd->tgd", bary, corners).reshape(-1, 2), (area[:, None] * w[None]).ravel()


@dataclass(frozen=True)
class FaceMoments:
    """Moments of one face about its ``reference`` point (see the module docstring): ``area``,
    ``normal`` (N), ``first`` (H), ``second`` (G), for the surface's own normal S_u x S_v."""

    reference: tuple[float, float, float]
    area: float
    normal: tuple[float, float, float]
    first: tuple[float, float, float]
    second: tuple[float, float, float]

    def oriented(self, sign: int) -> "FaceMoments":
        """The moments for the normal ``sign`` x S_u x S_v (the area stays positive)."""
        if sign > 0:
            return self
        return FaceMoments(self.reference, self.area, tuple(-v for v in self.normal),
                           tuple(-v for v in self.first), tuple(-v for v in self.second))

    def to_dict(self) -> dict:
        return {"reference": list(self.reference), "area": self.area, "normal": list(self.normal),
                "first": list(self.first), "second": list(self.second)}

    @classmethod
    def from_dict(cls, d: dict) -> "FaceMoments":
        vec = lambda key: tuple(float(v) for v in d[key])  # noqa: E731
        return cls(vec("reference"), float(d["area"]), vec("normal"), vec("first"), vec("second"))


def face_moments(points: np.ndarray, weights: np.ndarray,
                 evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]) -> FaceMoments:
    """The moments of a face from a rule on its (u, v) domain (``points`` (n, 2), ``weights`` (n,),
    from :func:`domain_rule` and :func:`strip_rule`); ``evaluate(uv)`` -> (S, S_u, S_v), (n, 3)
    each, the exact surface and its first derivatives. The reference point is the mean of the
    rule's points on the surface."""
    x, xu, xv = (np.asarray(v, float) for v in evaluate(points))
    m = np.cross(xu, xv)
    ref = x.mean(axis=0)
    y = x - ref
    vec = lambda v: tuple(float(c) for c in v)  # noqa: E731
    return FaceMoments(vec(ref), float(np.linalg.norm(m, axis=1) @ weights), vec(weights @ m),
                       vec(weights @ (y * m)), vec(0.5 * (weights @ (y * y * m))))


def solid_moments(faces: list[FaceMoments]) -> tuple[float, np.ndarray]:
    """(volume, centroid) of a closed solid from its faces' outward-oriented moments, integrated
    about the centre of the faces' reference points."""
    ref = np.array([f.reference for f in faces], float)
    centre = 0.5 * (ref.min(axis=0) + ref.max(axis=0))
    d = ref - centre
    n = np.array([f.normal for f in faces], float)
    h = np.array([f.first for f in faces], float)
    g = np.array([f.second for f in faces], float)
    volume = float((h.sum(axis=1) + (d * n).sum(axis=1)).sum() / 3.0)
    first = (g + d * h + 0.5 * d * d * n).sum(axis=0)
    return volume, centre + first / volume
