"""A box hierarchy over a closed tessellation for its generalised winding number, exact (to
round-off) and cheaper than the sum over every triangle.

The solid angle an oriented patch C of triangles subtends at p depends only on its boundary
when p lies outside a convex region holding C: with c a point of that region, C and the cone
K from c over C's boundary edges (triangles (c, a, b) for each boundary edge a -> b) bound
together a closed surface C - K (its boundary cancels) lying inside the region, whose winding
number at p is 0, so the solid angle of C at p equals that of K. Each node of the hierarchy
(the triangles split at the median of their centroids along the longest side of their box, down
to ``LEAF`` triangles) keeps its box and its cone (apex the box's centre), used for the points
outside the box widened by ``MARGIN`` of its diagonal; inside it, its children are visited, and
a leaf sums its triangles. A node whose cone has as many triangles as the node is never
replaced by it. The root's boundary is empty (a closed surface): the points outside its box
add nothing, the winding number 0.

Boundary edges are counted on vertices identified by their exact coordinates, so a patch whose
triangles share vertices by value only (the faces of a CAD part, meshed one by one, meet on
their edges' common polygons) has the boundary of the 2-chain they form: always a cycle, so the
cone closes it whatever the mesh.

A CAD part's faces are meshed one by one, and the vertices two faces share along an edge differ
by round-off (the M8 socket screw of docs/real-cad.md: median 6e-9 m): every edge of the faces'
edge polygons is then a boundary edge of any patch, and the cones carry all of them (9,398 of the
screw's 13,974 triangles' edges). :func:`welded` snaps such vertices onto one before the tree is
built (the screw: 30 boundary edges left); the welded triangles are a tessellation of the same
solid, moved by less than the weld radius.
"""

from __future__ import annotations

import numpy as np

__all__ = ["WindingTree", "welded", "LEAF", "MARGIN"]

#: a node of at most this many triangles is a leaf
LEAF = 32
#: a node's cone is used for points beyond its box widened by this fraction of its diagonal
MARGIN = 1e-3


def welded(triangles: np.ndarray, radius: float) -> np.ndarray:
    """The triangles (m, 3, 3) with every cluster of vertices closer than ``radius`` (chained:
    the clusters are the connected sets of the pairs closer than it) moved onto its vertex
    listed first; triangles left with two equal corners are dropped (no solid angle)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    tri = np.asarray(triangles, float)
    verts, ids = np.unique(tri.reshape(-1, 3), axis=0, return_inverse=True)
    if radius <= 0.0 or len(verts) < 2:
        return tri
    pairs = cKDTree(verts).query_pairs(radius, output_type="ndarray")
    if not len(pairs):
        return tri
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(verts), len(verts)))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, len(verts))
    np.minimum.at(first, label, np.arange(len(verts)))
    snapped = first[label][ids.reshape(-1, 3)]
    keep = (snapped[:, 0] != snapped[:, 1]) & (snapped[:, 1] != snapped[:, 2]) & (snapped[:, 2] != snapped[:, 0])
    return verts[snapped[keep]]


def _boundary(ids: np.ndarray) -> np.ndarray:
    """The boundary edges (k, 2) (vertex ids, oriented) of the triangles ids (m, 3): each
    edge's count one way minus its count the other, that many times in the prevailing direction."""
    a = ids.reshape(-1)
    b = np.roll(ids, -1, axis=1).reshape(-1)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    sign = np.where(a < b, 1, -1)
    pairs, inverse = np.unique(np.stack([lo, hi], axis=1), axis=0, return_inverse=True)
    net = np.bincount(inverse.reshape(-1), weights=sign, minlength=len(pairs)).astype(np.int64)
    keep = np.flatnonzero(net)
    rep = np.abs(net[keep])
    edges = np.where((net[keep] > 0)[:, None], pairs[keep], pairs[keep][:, ::-1])
    return np.repeat(edges, rep, axis=0)


class WindingTree:
    """Box hierarchy of ``triangles`` (m, 3, 3) (a closed, outward-wound tessellation) with the
    arrays of the compiled walk (:func:`geometry.solids._mesh_kernels.tree_winding_range`)."""

    def __init__(self, triangles: np.ndarray):
        tri = np.ascontiguousarray(triangles, float)
        verts, ids = np.unique(tri.reshape(-1, 3), axis=0, return_inverse=True)
        ids = ids.reshape(-1, 3)
        centroid = tri.mean(axis=1)
        order, lo, hi, child, span, cones, cone_span = [], [], [], [], [], [], []
        ncone = 0
        stack = [(np.arange(len(tri)), -1, 0)]
        while stack:  # depth first, children after their parent
            idx, parent, slot = stack.pop()
            k = len(lo)
            if parent >= 0:
                child[parent][slot] = k
            t = tri[idx]
            a, b = t.min(axis=(0, 1)), t.max(axis=(0, 1))
            pad = MARGIN * float(np.linalg.norm(b - a))
            lo.append(a - pad)
            hi.append(b + pad)
            edges = _boundary(ids[idx])
            if len(edges) < len(idx):
                centre = 0.5 * (a + b)
                cones.append(np.stack([np.broadcast_to(centre, (len(edges), 3)), verts[edges[:, 0]], verts[edges[:, 1]]], axis=1))
                cone_span.append((ncone, ncone + len(edges)))
                ncone += len(edges)
            else:
                cone_span.append((-1, -1))
            child.append([-1, -1])
            if len(idx) <= LEAF:
                start = sum(len(o) for o in order)
                order.append(idx)
                span.append((start, start + len(idx)))
                continue
            span.append((-1, -1))
            axis = int(np.argmax(b - a))
            s = idx[np.argsort(centroid[idx, axis], kind="stable")]
            half = len(s) // 2
            stack.append((s[half:], k, 1))
            stack.append((s[:half], k, 0))
        self.tri = np.ascontiguousarray(tri[np.concatenate(order)])
        self.cone = np.ascontiguousarray(np.concatenate(cones) if cones else np.zeros((0, 3, 3)))
        self.lo, self.hi = np.array(lo), np.array(hi)
        self.child = np.array(child, np.int64)
        self.span = np.array(span, np.int64)
        self.cone_span = np.array(cone_span, np.int64)
        self.depth = self._depth()

    def _depth(self) -> int:
        depth = np.zeros(len(self.child), np.int64)
        for k in range(len(self.child)):
            for c in self.child[k]:
                if c >= 0:
                    depth[c] = depth[k] + 1
        return int(depth.max()) + 1

    def winding(self, points: np.ndarray, kernels) -> np.ndarray:
        """Sums (n,) of the solid angles (4 pi x the winding numbers) seen from the points."""
        from .._jit import run_ranges

        p, out = np.ascontiguousarray(points, float), np.zeros(len(points))
        stack_size = 2 * self.depth + 2
        run_ranges(lambda lo, hi: kernels.tree_winding_range(p, self.tri, self.cone, self.lo, self.hi, self.child,
                                                            self.span, self.cone_span, stack_size, out, lo, hi),
                   len(p), per_thread=2)
        return out
