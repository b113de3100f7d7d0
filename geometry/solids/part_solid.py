"""The solid of one body of a CAD part (``geometry.Part``, from the Onshape importer now and the
STEP importer later): its faces' exact surfaces give every distance, foot, normal and
quadrature point; the tessellation only seeds searches and decides which side a point is on.

- ``signed_distance``: for each face, the foot on its exact surface counts when it lies on the
  face's trimmed region: within the tessellation's chord sag of the face's triangles and, near
  the face's boundary, on the inner side of its exact trimming edges (geometry.solids.face_trim);
  else the face's exact boundary edges (their curves' feet clipped to the edge's ends, else the
  end vertices). The sign: the side of the nearest face's exact normal where the foot is
  interior to a face (also where an edge is as near within round-off: the foot is on it), the
  generalised winding number of the closed tessellation (sum of the triangles' solid angles;
  compiled, the far triangles by the cones of geometry.solids.winding_tree) where the nearest
  feature is an edge or a vertex, outside at once beyond the tessellation's bounding box
  widened by the tolerance. Faces are searched best-first by the boxes of their triangles (a
  foot counts only near them), and only those nearer than the nearest edge end. A face without an
  exact surface falls back to its tessellation (distance minus the sag bound: a lower bound).
- faces (by id): ``quadrature`` by the tessellation's triangles, split to ``resolution`` (or
  graded: to a size asked per point, as fine as the solver's cells there), mapped onto the
  exact surface by its closest-point projection (points and normals exact, weights the area
  element of that map by differences): exact inside the face, off by the
  strips between the chords and the exact trimming curves (of order sag x perimeter).
  ``project`` and ``curvature`` as the other faces'.
- ``volume`` and ``centroid``: from the faces' moments over their parameter domains when the
  importer gave every face its moments (geometry.solids.domain_moments: exact however far the
  triangles stray from a sharply bent surface), else from the faces' quadrature with the strips
  added (geometry.solids.trim_strips); both about the body's own centre.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from .._base import Projection
from .face_trim import FaceTrim, TrimEdge
from .mesh_jit import box_gaps, mesh_kernels
from .shapes import Solid

__all__ = ["PartSolid", "PartFace", "point_triangle_distance"]

# symmetric 6-point rule on triangles, degree 4 (Dunavant 1985), barycentric (a, a, 1 - 2a)
_A = (0.445948490915965, 0.091576213509771)
_W = (0.223381589678011, 0.109951743655322)


def _triangle_rule():
    bary, w = [], []
    for a, wt in zip(_A, _W):
        b = 1.0 - 2.0 * a
        bary += [(a, a, b), (a, b, a), (b, a, a)]
        w += [wt] * 3
    return np.array(bary), 0.5 * np.array(w)  # weights sum to the reference area 1/2


def point_triangle_distance(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Distances (n,) from points p (n, 3) to triangles tri (n, 3, 3) (pairwise): the foot in
    the plane when it falls inside, else the nearest of the three edges."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    n = np.cross(b - a, c - a)
    nn = np.maximum((n * n).sum(1), 1e-300)
    h = ((p - a) * n).sum(1) / nn
    q = p - h[:, None] * n
    inside = np.ones(len(p), bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= (np.cross(v - u, q - u) * n).sum(1) >= 0.0
    best = np.full(len(p), np.inf)
    for u, v in ((a, b), (b, c), (c, a)):
        e = v - u
        t = np.clip(((p - u) * e).sum(1) / np.maximum((e * e).sum(1), 1e-300), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(p - u - t[:, None] * e, axis=1))
    return np.where(inside, np.abs(h) * np.sqrt(nn), best)


#: a face's tessellation of at most this many triangles is searched whole, without rounds
FEW_TRIANGLES = 32
#: a foot whose p - foot makes a cosine below this with the face's normal is no perpendicular foot
PERPENDICULAR = 1.0 - 1e-6


class _Mesh:
    """Triangles (m, 3, 3) with a KD-tree on their centroids for nearest-triangle queries."""

    def __init__(self, triangles: np.ndarray):
        from scipy.spatial import cKDTree

        self.tri = np.ascontiguousarray(triangles, dtype=float)
        self.centroid = triangles.mean(axis=1)
        self.radius = float(np.linalg.norm(triangles - self.centroid[:, None], axis=2).max()) if len(triangles) else 0.0
        self.tree = cKDTree(self.centroid)

    def distance(self, p: np.ndarray) -> np.ndarray:
        """Exact distance to the nearest triangle (see :meth:`_rounds`)."""
        return self._rounds(p, None)

    def within(self, p: np.ndarray, tol: float) -> np.ndarray:
        """Whether each point lies within ``tol`` of a triangle: as :meth:`distance`, but a point
        is settled as soon as a triangle within tol is found, or none can be any more."""
        return self._rounds(p, tol) <= tol

    def _rounds(self, p: np.ndarray, tol: float | None) -> np.ndarray:
        """Distances in rounds: the k nearest centroids' triangles, then, for the points where a
        triangle beyond them could still be nearer (its centroid closer than the best distance +
        the largest triangle's radius: big triangles next to small ones, a fan at a cone's tip),
        four times as many, up to all; vectorised over (point, triangle) pairs in chunks. With
        ``tol`` a point leaves once its best is within tol or no farther triangle can reach tol
        (its value then is only known to exceed tol)."""
        p = np.asarray(p, dtype=float).reshape(-1, 3)
        m = len(self.tri)
        best = np.full(len(p), np.inf)
        todo = np.arange(len(p))
        # a foot on the face mostly lies on its nearest centroid's triangle; a face of few triangles
        # (a plane's) is taken whole at once: rounds would end there for the points off it anyway
        k = m if m <= FEW_TRIANGLES else min(m, 16 if tol is None else 1)
        while len(todo) and k > 0:
            dc, idx = self.tree.query(p[todo], k=k)
            dc, idx = dc.reshape(len(todo), k), idx.reshape(len(todo), k)
            best[todo] = self._nearest_of(p[todo], idx)
            if k == m:
                break
            bound = best[todo] if tol is None else np.where(best[todo] <= tol, -np.inf, tol)
            todo = todo[dc[:, -1] < bound + self.radius]
            k = min(m, 4 * k)
        return best

    def _nearest_of(self, p: np.ndarray, idx: np.ndarray, pairs: int = 1 << 18) -> np.ndarray:
        """Smallest distance (n,) from each point to its candidate triangles idx (n, k)."""
        n, k = idx.shape
        out = np.empty(n)
        kernels = mesh_kernels()
        if kernels is not None and n:
            from .._jit import run_ranges

            q, ids = np.ascontiguousarray(p, float), np.ascontiguousarray(idx, np.int64)
            run_ranges(lambda lo, hi: kernels.nearest_of_range(q, ids, self.tri, out, lo, hi), n)
            return out
        step = max(1, pairs // k)
        for s in range(0, n, step):
            q, ids = p[s:s + step], idx[s:s + step]
            d = point_triangle_distance(np.repeat(q, k, axis=0), self.tri[ids.ravel()])
            out[s:s + step] = d.reshape(len(q), k).min(axis=1)
        return out


def _winding(points: np.ndarray, triangles: np.ndarray, chunk: int = 2000, pairs: int = 1 << 18) -> np.ndarray:
    """Generalised winding numbers (n,) of the points w.r.t. the oriented triangles (the sum of
    their solid angles by Van Oosterom and Strackee's formula, over 4 pi); point-triangle pairs
    taken ``pairs`` at a time (about 100 MB of temporaries)."""
    kernels = mesh_kernels()
    if kernels is not None and len(points):
        from .._jit import run_ranges

        p, t, out = np.ascontiguousarray(points, float), np.ascontiguousarray(triangles, float), np.zeros(len(points))
        run_ranges(lambda lo, hi: kernels.winding_range(p, t, out, lo, hi), len(p), per_thread=2)
        return out / (4.0 * math.pi)
    out = np.zeros(len(points))
    for s in range(0, len(triangles), chunk):
        t = triangles[s:s + chunk]
        step = max(1, pairs // len(t))
        for r in range(0, len(points), step):
            a, b, c = (t[None, :, k, :] - points[r:r + step, None, :] for k in range(3))
            la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
            det = (a * np.cross(b, c)).sum(2)
            den = la * lb * lc + (a * b).sum(2) * lc + (b * c).sum(2) * la + (c * a).sum(2) * lb
            out[r:r + step] += 2.0 * np.arctan2(det, den).sum(axis=1)
    return out / (4.0 * math.pi)


class PartFace:
    """One face of a CAD body: ``surface`` (exact primitive, or None), ``orientation`` (+1 when
    the solid's outward normal is the surface's own), its triangles (m, 3, 3) wound outward."""

    #: ``quadrature`` takes a size per point (``panel_size``): a solver grades its panels by its cells
    graded_panels = True

    def __init__(self, face, sag: float):
        self.name, self.surface, self.orientation = face.id, face.surface, int(face.orientation)
        mesh = face.mesh
        self.triangles = np.asarray(mesh.vertices, float)[np.asarray(mesh.faces)]
        self.mesh = _Mesh(self.triangles)
        self.sag = sag
        #: the exact trimming test (geometry.solids.face_trim.FaceTrim), set by the solid that
        #: knows the face's edges; without it a foot counts within ``sag`` of the triangles
        self.trim = None

    def _normals(self, pr: Projection) -> np.ndarray:
        return self.orientation * np.asarray(pr.normals, float)

    def project_surface(self, points: np.ndarray):
        pr = self.surface.project(points)
        return np.asarray(pr.points, float), self._normals(pr)

    def on_face(self, feet: np.ndarray) -> np.ndarray:
        """Whether each foot (n, 3) on the untrimmed surface lies on the trimmed face."""
        if self.trim is not None:
            return self.trim.contains(feet)
        return self.mesh.within(feet, self.sag)

    def quadrature(self, resolution: float, panel_size=None):
        """Points, weights (area) and outward normals: the triangles split to ``resolution``
        and mapped onto the exact surface. With ``panel_size`` (points (n, 3), outward normals
        (n, 3) -> largest edge (n,)), a triangle is split only until its edges are within the
        size asked at its centroid (never below ``resolution``): graded like the cells it lies in."""
        if panel_size is None:
            tri = _split(self.triangles, resolution)
        else:
            tri = _split_graded(self.triangles, panel_size, resolution)
        return self.mapped_rule(tri, resolution)

    def mapped_rule(self, tri: np.ndarray, resolution: float):
        """Points, weights and outward normals of the 6-point rule on the triangles (m, 3, 3)
        mapped onto the exact surface (flat where the face has none)."""
        bary, w = _triangle_rule()
        e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
        x = np.einsum("gk,tkd->tgd", bary, tri).reshape(-1, 3)
        if self.surface is None:
            n = np.cross(e1, e2)
            area2 = np.linalg.norm(n, axis=1)
            normals = np.repeat(n / area2[:, None], len(w), axis=0)
            return x, (area2[:, None] * w[None]).ravel(), normals
        h = 1e-5 * max(min(resolution, self.mesh.radius), 1e-12)  # ~ cbrt(eps) x the size: 1e-10 relative
        du = (self.project_surface(x + h * np.repeat(e1 / np.linalg.norm(e1, axis=1)[:, None], len(w), 0))[0]
              - self.project_surface(x - h * np.repeat(e1 / np.linalg.norm(e1, axis=1)[:, None], len(w), 0))[0]) / (2 * h)
        t2 = np.cross(np.cross(e1, e2), e1)
        t2 /= np.linalg.norm(t2, axis=1)[:, None]
        dv = (self.project_surface(x + h * np.repeat(t2, len(w), 0))[0]
              - self.project_surface(x - h * np.repeat(t2, len(w), 0))[0]) / (2 * h)
        flat_area = np.linalg.norm(np.cross(e1, e2), axis=1)  # twice the triangle's area
        jac = np.linalg.norm(np.cross(du, dv), axis=1)
        points, normals = self.project_surface(x)
        return points, (flat_area[:, None] * w[None]).ravel() * jac, normals

    def project(self, points) -> Projection:
        """Closest points on the face: the exact foot where it lies on the face, else the
        nearest of its tessellation's points pulled onto the exact surface (a seed-quality
        foot near the trimming curves)."""
        p = np.asarray(points, float).reshape(-1, 3)
        if self.surface is None:
            raise ValueError(f"face {self.name}: no exact surface (tessellation only)")
        feet, normals = self.project_surface(p)
        off = ~self.on_face(feet)
        if off.any():
            from scipy.spatial import cKDTree

            verts = self.triangles.reshape(-1, 3)
            _, idx = cKDTree(verts).query(p[off])
            feet[off], normals[off] = self.project_surface(verts[idx])
        r = p - feet
        sign = np.where((r * normals).sum(1) < 0.0, -1.0, 1.0)
        return Projection(points=feet, normals=normals, distances=sign * np.linalg.norm(r, axis=1))

    def curvature(self, points):
        """Principal curvatures (positive where convex from outside) and directions, from
        differences of the exact normals about the feet."""
        p = np.asarray(points, float).reshape(-1, 3)
        feet, n = self.project_surface(p)
        t1 = np.cross(n, np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]]))
        t1 /= np.linalg.norm(t1, axis=1)[:, None]
        t2 = np.cross(n, t1)
        h = 1e-5 * max(self.mesh.radius, 1e-9)
        shape = np.zeros((len(p), 2, 2))
        for j, t in enumerate((t1, t2)):
            dn = (self.project_surface(feet + h * t)[1] - self.project_surface(feet - h * t)[1]) / (2 * h)
            shape[:, 0, j], shape[:, 1, j] = (dn * t1).sum(1), (dn * t2).sum(1)
        k, vec = np.linalg.eigh(0.5 * (shape + np.swapaxes(shape, 1, 2)))
        d = [vec[:, 0, j, None] * t1 + vec[:, 1, j, None] * t2 for j in (0, 1)]
        return k[:, 0], k[:, 1], d[0], d[1]


def _bisected(tri: np.ndarray) -> np.ndarray:
    """Each triangle (a, b, c) split in two at the midpoint m of its longest edge ab: (a, m, c)
    and (m, b, c), wound as the parent. Longest-edge bisection keeps the triangles' shapes within
    a bounded set (Rosenberg and Stenger, Math. Comp. 29 (1975) 390): a sliver of a fan (a planar
    face's tessellation: triangles 25 mm long and 2 mm wide) becomes triangles of about the size
    asked, where splitting into four at the midpoints keeps every piece a sliver and asks
    (length / size)^2 of them whatever their area."""
    k = np.argmax(np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2), axis=1)  # edge (k - 1, k)
    rows = np.arange(len(tri))
    a, b, c = tri[rows, (k + 2) % 3], tri[rows, k], tri[rows, (k + 1) % 3]
    m = 0.5 * (a + b)
    return np.concatenate([np.stack([a, m, c], axis=1), np.stack([m, b, c], axis=1)])


def _split(tri: np.ndarray, resolution: float) -> np.ndarray:
    """Triangles bisected at their longest edges until no edge exceeds ``resolution``."""
    for _ in range(40):
        long = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1) > resolution
        if not long.any():
            break
        tri = np.concatenate([tri[~long], _bisected(tri[long])])
    return tri


def _split_graded(tri: np.ndarray, panel_size, resolution: float) -> np.ndarray:
    """Triangles bisected at their longest edges until no edge exceeds ``panel_size`` at the
    triangle's centroid (or ``resolution``, the finest asked anywhere)."""
    done = []
    for _ in range(80):
        edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
        limit = np.maximum(np.asarray(panel_size(tri.mean(axis=1), normal), dtype=float), resolution)
        long = edge > limit
        done.append(tri[~long])
        if not long.any():
            break
        tri = _bisected(tri[long])
    else:
        done.append(tri)
    return np.concatenate(done)


def _surface_sag(face, triangles: np.ndarray) -> float:
    """Largest distance from the triangles' centroids and edge midpoints to the exact surface."""
    if face.surface is None or not len(triangles):
        return 0.0
    probes = np.concatenate([triangles.mean(axis=1), 0.5 * (triangles + np.roll(triangles, 1, axis=1)).reshape(-1, 3)])
    return float(np.abs(np.asarray(face.surface.project(probes).distances, float)).max())


def _edge_sag(edge) -> float:
    if edge.curve is None or len(edge.polyline) < 2:
        return 0.0
    mid = 0.5 * (edge.polyline[1:] + edge.polyline[:-1])
    return float(np.abs(np.asarray(edge.curve.project(mid).distances, float)).max())


def _polyline_distance(p: np.ndarray, line: np.ndarray) -> np.ndarray:
    best = np.full(len(p), np.inf)
    for u, v in zip(line[:-1], line[1:]):
        e = v - u
        t = np.clip(((p - u) @ e) / max(float(e @ e), 1e-300), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(p - u - t[:, None] * e, axis=1))
    return best


class PartSolid(Solid):
    """The solid of one body of a ``geometry.Part`` (``body``: its id or name; optional when
    the part has one body). Faces keyed by their CAD ids."""

    def __init__(self, part, body=None):
        self.body = _pick_body(part, body)
        faces = [part.faces[i] for i in self.body.face_ids if i in part.faces]
        missing = [f.id for f in faces if f.mesh is None or not len(f.mesh.faces)]
        if not faces or missing:
            raise ValueError(f"body {self.body.id!r} ({self.body.name}): faces without a tessellation: "
                             f"{', '.join(missing) or 'no faces'}")
        tri = [np.asarray(f.mesh.vertices, float)[np.asarray(f.mesh.faces)] for f in faces]
        allv = np.concatenate([t.reshape(-1, 3) for t in tri])
        size = float(np.linalg.norm(np.ptp(allv, axis=0)))
        self.edges = [part.edges[i] for i in self.body.edge_ids if i in part.edges]
        sag = max([_surface_sag(f, t) for f, t in zip(faces, tri)] + [_edge_sag(e) for e in self.edges])
        #: how far the tessellation may stray from the exact faces (2 x the measured sag + round-off)
        self.tolerance = 2.0 * sag + 1e-9 * size
        self.faces = {f.id: PartFace(f, self.tolerance) for f in faces}
        #: each face's trimming edges (those of its loops)
        self._loops = {f.id: [part.edges[c.edge_id] for loop in f.loops for c in loop.coedges
                              if c.edge_id in part.edges] for f in faces}
        for k, face in self.faces.items():
            if face.surface is not None and self._loops[k]:
                face.trim = FaceTrim(face, self._loops[k], self.tolerance, size)
        self.triangles = np.concatenate(tri)
        self.bounds = (allv.min(axis=0) - self.tolerance, allv.max(axis=0) + self.tolerance)
        self.size = size
        self._face_moments = [f.moments for f in faces]

    @cached_property
    def _volume_centroid(self) -> tuple[float, np.ndarray]:
        """By the divergence theorem: over the faces' parameter domains when the importer gave
        every face its moments (geometry.solids.domain_moments), else over the faces' quadrature
        with the strips between the chords and the exact trimming curves
        (geometry.solids.trim_strips); both about the body's own centre."""
        if all(m is not None for m in self._face_moments):
            from .domain_moments import solid_moments

            return solid_moments(self._face_moments)
        from .trim_strips import closed_rule

        rules = [closed_rule(f, self._loops[k], self.size, self.tolerance) for k, f in self.faces.items()]
        x, w, n = (np.concatenate(v) for v in zip(*rules))
        centre = 0.5 * (self.bounds[0] + self.bounds[1])
        y = x - centre
        volume = float(((y * n).sum(axis=1) @ w) / 3.0)
        return volume, centre + 0.5 * (w @ (y * y * n)) / volume

    @property
    def volume(self) -> float:
        return self._volume_centroid[0]

    @property
    def centroid(self) -> np.ndarray:
        """The centre of the solid's volume (m)."""
        return self._volume_centroid[1]

    @cached_property
    def _face_boxes(self) -> tuple[np.ndarray, np.ndarray]:
        """Boxes (faces, 3) holding every foot each exact face may accept: its triangles' box
        widened by the tolerance (a foot counts only within it of the triangles), and by round-off."""
        pad = 1.001 * self.tolerance + 1e-9 * self.size
        tri = [f.triangles.reshape(-1, 3) for f in self._exact_faces]
        return (np.array([t.min(axis=0) - pad for t in tri]).reshape(-1, 3),
                np.array([t.max(axis=0) + pad for t in tri]).reshape(-1, 3))

    @cached_property
    def _exact_faces(self) -> list:
        return [f for f in self.faces.values() if f.surface is not None]

    @cached_property
    def _vertices(self) -> np.ndarray:
        """The ends of every edge (points of the exact boundary)."""
        ends = []
        for e in self.edges:
            line = np.asarray(e.polyline, float).reshape(-1, 3)
            ends += [np.asarray(v, float) for v in (e.start, e.end) if v is not None] or [line[0], line[-1]]
        return np.array(ends).reshape(-1, 3)

    @cached_property
    def _vertex_tree(self):
        from scipy.spatial import cKDTree

        return cKDTree(self._vertices)

    def _vertex_bound(self, p: np.ndarray) -> np.ndarray:
        """An upper bound of the distance to the nearest edge: that to the nearest edge end
        (widened by round-off)."""
        if not len(self._vertices):
            return np.full(len(p), np.inf)
        return self._vertex_tree.query(p)[0] * (1.0 + 1e-12) + 4e-12 * self.size

    def _faces_nearest(self, p: np.ndarray, edge_bound: np.ndarray):
        """Distance to the nearest face (its exact foot on the trimmed face), the side of that
        face's normal (+1 inside) and whether such a foot was found. The face is the one whose
        foot on its untrimmed surface is nearest among those lying on their trimmed face (ties to
        the face listed first). Such a foot lies in the face's box (:attr:`_face_boxes`), so the
        distance to the box bounds it from below: a point is projected first onto the face of
        the nearest box, then onto every face whose box is nearer than the best foot so far
        (and than ``edge_bound`` + round-off, an upper bound of the edges' distance: a face
        farther than the nearest edge loses to it whatever its foot)."""
        n = len(p)
        best = np.full(n, np.inf)
        sign = np.ones(n)
        interior = np.zeros(n, bool)
        for face in self.faces.values():
            if face.surface is None:  # tessellation only: a lower bound, never interior
                d = np.maximum(face.mesh.distance(p) - self.tolerance, 0.0)
                better = d < best
                best[better], sign[better] = d[better], 1.0
        exact = self._exact_faces
        if not exact or not n:
            return best, sign, interior
        lo, hi = self._face_boxes
        gap = box_gaps(p, lo, hi) * (1.0 - 1e-12)  # (faces, n)
        key = np.full(n, np.inf)  # the nearest foot on its face so far
        face_of = np.full(n, len(exact))
        feet, normals = np.zeros((n, 3)), np.zeros((n, 3))
        asked = np.zeros_like(gap, bool)
        first = np.zeros_like(gap, bool)
        first[np.argmin(gap, axis=0), np.arange(n)] = True
        for todo in (first, None):
            if todo is None:  # every face whose box is within the best distance so far
                todo = ~asked & (gap <= np.minimum(np.minimum(key, best), edge_bound)[None])
            else:
                todo &= gap <= np.minimum(best, edge_bound)[None]
            asked |= todo
            for i in np.flatnonzero(todo.any(axis=1)):
                pts = np.flatnonzero(todo[i])
                pts = pts[gap[i, pts] <= key[pts]]  # the feet found so far, on earlier faces, as bounds
                if not len(pts):
                    continue
                x, nx = exact[i].project_surface(p[pts])
                d = np.linalg.norm(p[pts] - x, axis=1)
                # the trimming test only for the feet that would be nearest (ties to the face listed first)
                could = np.flatnonzero((d < key[pts]) | ((d == key[pts]) & (i < face_of[pts])))
                better = could[exact[i].on_face(x[could])]
                k = pts[better]
                key[k], face_of[k], feet[k], normals[k] = d[better], i, x[better], nx[better]
        hit = np.flatnonzero(key < best)  # a tessellation-only face's bound as near wins
        r = p[hit] - feet[hit]
        along = (r * normals[hit]).sum(1)
        best[hit], sign[hit] = key[hit], np.where(along < 0.0, 1.0, -1.0)
        # the normal's side holds where p - foot lies along the normal: not where the
        # surface's projection stopped at the end of its parameter domain (a B-spline
        # face's edge there), which leaves the side to the edges' test
        length = np.linalg.norm(r, axis=1)
        interior[hit] = (np.abs(along) >= PERPENDICULAR * length) | (length <= 1e-12 * self.size)
        return best, sign, interior

    def _edges_nearest(self, p: np.ndarray, bound: np.ndarray) -> np.ndarray:
        """Distance to the nearest edge or vertex, exact where it is below ``bound`` (the faces'
        nearest distance); elsewhere only known to be at least ``bound``."""
        best = np.array(bound, dtype=float)
        lo, hi = (np.array([box[k] for box in self._edge_boxes]).reshape(-1, 3) for k in (0, 1))
        gaps = box_gaps(p, lo, hi)  # (edges, n)
        for k, e in enumerate(self.edges):
            # the edge (its curve and end vertices) lies in its polyline's box widened by the
            # tolerance, and within the tolerance of its polyline: a point at least its best
            # distance from that box, or from the polyline less the tolerance, is not asked
            near = np.flatnonzero(gaps[k] < best)
            if len(near):
                upper = float(best[near].max())
                near = near[self._trim_edges[e.id].lower_bound(p[near], upper) < best[near]]
            if len(near):
                best[near] = np.minimum(best[near], self._edge_distance(e, p[near], best[near]))
        return best

    @cached_property
    def _edge_boxes(self) -> list[tuple[np.ndarray, np.ndarray]]:
        lines = [np.asarray(e.polyline, float).reshape(-1, 3) for e in self.edges]
        return [(x.min(axis=0) - self.tolerance, x.max(axis=0) + self.tolerance) for x in lines]

    @cached_property
    def _trim_edges(self) -> dict:
        return {e.id: TrimEdge(e, self.tolerance) for e in self.edges}

    def _edge_distance(self, e, p: np.ndarray, best: np.ndarray) -> np.ndarray:
        """Distance from points p to the edge e: exact where below ``best``."""
        line = np.asarray(e.polyline, float)
        ends = [v for v in (e.start, e.end) if v is not None] or [line[0], line[-1]]
        d = np.min([np.linalg.norm(p - np.asarray(v, float), axis=1) for v in ends], axis=0)
        if e.curve is None:
            return np.minimum(d, np.maximum(_polyline_distance(p, line) - self.tolerance, 0.0))
        pr = e.curve.project(p)
        dc = np.abs(np.asarray(pr.distances, float))
        ask = np.flatnonzero(dc < np.minimum(best, d))  # only a foot on the edge could be nearer
        if len(ask):  # the curve's foot clipped to the edge's ends (exact, not the polyline's band)
            foot, _ = self._trim_edges[e.id].clipped(p[ask], np.asarray(pr.points, float)[ask])
            d[ask] = np.minimum(d[ask], np.linalg.norm(p[ask] - foot, axis=1))
        return d

    def signed_distance(self, points, chunk: int = 1 << 16) -> np.ndarray:
        p = np.asarray(points, float).reshape(-1, 3)
        if len(p) > chunk:  # bounded temporaries (the candidate triangles of every point)
            return np.concatenate([self.signed_distance(p[s:s + chunk], chunk) for s in range(0, len(p), chunk)])
        bound = self._vertex_bound(p)  # the edges are at most this far
        best, sign, interior = self._faces_nearest(p, bound)
        edge = self._edges_nearest(p, np.minimum(best, bound))
        # an edge nearer than the face's foot by round-off only (a point over a face's trimming
        # curve, as on a quarter model's symmetry plane): the foot is on that edge and p - foot
        # lies along the face's normal, so the face's side holds and no winding number is needed
        at_edge = edge < best - 1e-12 * self.size
        best = np.minimum(best, edge)
        ask = at_edge | ~interior
        if ask.any():  # nearest feature an edge or a vertex: the side by the winding number
            sign[ask] = self._side(p[ask])
        return sign * best

    def _side(self, p: np.ndarray) -> np.ndarray:
        """+1 inside, -1 outside: outside without further work beyond the tessellation's bounding
        box widened by the tolerance (the closed triangles' winding number is 0 there, and the exact
        surface lies within that box), else by the winding number (its cost grows with points x
        triangles: a quarter model's points off its symmetry planes are mostly of the first kind)."""
        lo, hi = self.bounds
        boxed = np.all((p >= lo) & (p <= hi), axis=1)
        side = np.full(len(p), -1.0)
        if boxed.any():
            kernels = mesh_kernels()
            if kernels is not None:  # the box hierarchy's cones for the far triangles (the same to round-off)
                w = self._winding_tree.winding(p[boxed], kernels) / (4.0 * math.pi)
            else:
                w = _winding(p[boxed], self._winding_triangles)
            side[boxed] = np.where(w > 0.5, 1.0, -1.0)
        return side

    @cached_property
    def _winding_triangles(self) -> np.ndarray:
        """The triangles with the vertices the faces share along their edges welded (they differ
        by round-off, the faces being meshed one by one): within a hundredth of the tolerance and a
        tenth of the shortest triangle edge (geometry.solids.winding_tree.welded). The winding
        number moves by the solid angle of the closed cracks only (the M8 socket screw: 2.4e-4 at
        most at 20,000 points in its box, no side changed), and the tree's cones no longer carry
        every edge of every face (19 times faster there)."""
        from .winding_tree import welded

        edges = np.linalg.norm(self.triangles - np.roll(self.triangles, 1, axis=1), axis=2)
        shortest = float(edges[edges > 0.0].min()) if (edges > 0.0).any() else 0.0
        return welded(self.triangles, min(1e-2 * self.tolerance, 0.1 * shortest))

    @cached_property
    def _winding_tree(self):
        from .winding_tree import WindingTree

        return WindingTree(self._winding_triangles)


def _pick_body(part, body):
    """The body ``body`` names: its id, its name, or ``name#k`` (the k-th body of that name, in id
    order) when several share the name. A sheet body (open shell, loose faces) is no solid."""
    bodies = list(part.bodies.values())
    listing = ", ".join(f"{b.id} ({b.name})" for b in bodies)
    if body is None:
        if len(bodies) > 1 and all(b.body_type != "SOLID" for b in bodies):
            raise ValueError(f"the part has no closed solid: its {len(bodies)} bodies are all "
                             f"{' or '.join(sorted({b.body_type.lower() for b in bodies}))} bodies (open shells or "
                             "loose faces, not sewn into a solid), which bound no volume")
        if len(bodies) != 1:
            raise ValueError(f"the part has {len(bodies)} bodies; choose one by id or name: {listing}")
        return _solid_body(bodies[0])
    by_id = [b for b in bodies if b.id == body]
    name, _, k = str(body).rpartition("#") if "#" in str(body) else (str(body), "", "")
    named = [b for b in bodies if b.name == (name if k else body)]
    if by_id:
        return _solid_body(by_id[0])
    if k.isdigit() and 1 <= int(k) <= len(named):
        return _solid_body(named[int(k) - 1])
    if len(named) == 1 and not k:
        return _solid_body(named[0])
    if len(named) > 1 and not k:
        choices = ", ".join(f"{body}#{i} ({b.id})" for i, b in enumerate(named, 1))
        raise ValueError(f"body = {body!r}: {len(named)} bodies have this name; choose one: {choices}")
    raise ValueError(f"body = {body!r}: no such body; the part's bodies: {listing}")


def _solid_body(b):
    if b.body_type != "SOLID":
        raise ValueError(f"body {b.id!r} ({b.name}) is a {b.body_type.lower()} body (an open shell or loose faces), "
                         "not a closed solid: it bounds no volume")
    return b
