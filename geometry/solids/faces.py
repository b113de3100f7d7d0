"""Faces of exact solids: a parametric face over a rectangle of (u, v) (``panels`` and
``evaluate``, which the solver cuts at its octree's planes), and a planar region bounded by a
2D profile (``quadrature`` only: its points from a height-function rule on the profile's exact
signed distance)."""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..bisection import bisection_tree

__all__ = ["ParametricFace", "PlanarRegionFace", "gauss_panels"]

Map = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


def gauss_panels(lower: np.ndarray, upper: np.ndarray, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Tensor Gauss nodes (n, 2) and weights in (u, v) on the rectangles [lower, upper]."""
    x, w = np.polynomial.legendre.leggauss(order)
    half = 0.5 * (upper - lower)
    mid = 0.5 * (upper + lower)
    gu, gv = np.meshgrid(x, x, indexing="ij")
    uv = mid[:, None, :] + half[:, None, :] * np.stack([gu.ravel(), gv.ravel()], axis=1)[None]
    wt = np.outer(w, w).ravel()[None, :] * (half[:, 0] * half[:, 1])[:, None]
    return uv.reshape(-1, 2), wt.ravel()


class ParametricFace:
    """A face X(u, v) over [u0, u1] x [v0, v1]: ``evaluate(uv) -> (points, outward normals,
    area element |X_u x X_v|)``; ``lengths`` (Lu, Lv) the largest extents in space along u and v
    (to size the panels)."""

    def __init__(self, name: str, bounds: tuple[float, float, float, float], mapping: Map,
                 lengths: tuple[float, float], surface=None):
        self.name = name
        self.u0, self.u1, self.v0, self.v1 = (float(b) for b in bounds)
        self._map = mapping
        self.lengths = (float(lengths[0]), float(lengths[1]))
        self._surface = surface
        self._periodic = None

    @property
    def surface(self):
        """The exact untrimmed primitive (geometry.surfaces) the face lies on where one exists
        (plane, sphere, cylinder), else the face itself (its own exact map)."""
        return self if self._surface is None else self._surface

    @property
    def periodic(self) -> tuple[bool, bool]:
        if self._periodic is None:
            from .face_ops import periodic_flags

            self._periodic = periodic_flags(self)
        return self._periodic

    @property
    def collapsed(self):
        if getattr(self, "_collapsed", None) is None:
            from .face_ops import collapsed_ends

            self._collapsed = collapsed_ends(self)
        return self._collapsed

    def project(self, points):
        """Closest points on the trimmed face (a geometry.Projection: points, outward normals,
        signed distances, parameters (u, v))."""
        from .face_ops import project_face

        return project_face(self, points, self.periodic)

    def curvature(self, points):
        """Principal curvatures k1 <= k2 (n,) and directions d1, d2 (n, 3) at the feet of
        ``points`` on the face (positive where convex seen from outside)."""
        from .face_ops import face_curvature

        return face_curvature(self, self.project(points).parameters)

    def evaluate(self, uv: np.ndarray):
        return self._map(np.asarray(uv, dtype=float).reshape(-1, 2))

    def panels(self, resolution: float) -> tuple[np.ndarray, np.ndarray]:
        nu = max(1, int(math.ceil(self.lengths[0] / resolution)))
        nv = max(1, int(math.ceil(self.lengths[1] / resolution)))
        eu, ev = np.linspace(self.u0, self.u1, nu + 1), np.linspace(self.v0, self.v1, nv + 1)
        a0, b0 = np.meshgrid(eu[:-1], ev[:-1], indexing="ij")
        a1, b1 = np.meshgrid(eu[1:], ev[1:], indexing="ij")
        return np.column_stack([a0.ravel(), b0.ravel()]), np.column_stack([a1.ravel(), b1.ravel()])

    def quadrature(self, resolution: float):
        """Gauss points (3 x 3 per panel), weights (area) and outward normals."""
        uv, w = gauss_panels(*self.panels(resolution))
        points, normals, jac = self.evaluate(uv)
        return points, w * jac, normals

    @property
    def area(self) -> float:
        return float(self.quadrature(min(self.lengths) / 16)[1].sum())


class PlanarRegionFace:
    """The region of a 2D profile placed in space: x = origin + p0 e0 + p1 e1 (profile
    coordinates p), outward normal ``normal``. Points by a height-function rule on the profile's
    exact signed distance: Gauss lines along p0 through Gauss points of strips in p1, the zeros
    of the distance on each line bound its inside intervals."""

    def __init__(self, name: str, profile, origin, e0, e1, normal, order: int = 4):
        self.name = name
        self.profile = profile
        self.origin, self.e0, self.e1 = (np.asarray(v, dtype=float) for v in (origin, e0, e1))
        self.normal = np.asarray(normal, dtype=float)
        self.order = order

    @property
    def surface(self):
        """The exact plane of the region (geometry.surfaces.Plane, normal outward)."""
        from ..surfaces import Plane

        return Plane(origin=tuple(self.origin), normal=tuple(self.normal))

    def project(self, points):
        """Closest points on the region: the foot on the plane where it falls inside the profile,
        else the nearest point of the profile's boundary (exact), as a geometry.Projection with
        the profile coordinates as parameters."""
        from .._base import Projection

        p = np.asarray(points, dtype=float).reshape(-1, 3)
        r = p - self.origin
        q = np.column_stack([r @ self.e0, r @ self.e1])
        inside = np.asarray(self.profile.signed_distance(q), float) >= 0.0
        edge = self.profile.project(q)
        q_foot = np.where(inside[:, None], q, np.asarray(edge.points, float))
        foot = self._place(q_foot)
        height = r @ self.normal
        dist = np.linalg.norm(p - foot, axis=1)
        sign = np.where(height < 0.0, -1.0, 1.0)
        normals = np.broadcast_to(self.normal, foot.shape).copy()
        return Projection(points=foot, normals=normals, distances=sign * dist, parameters=q_foot)

    def curvature(self, points):
        """Zero curvatures; directions the profile's axes in space."""
        from .face_ops import planar_curvature

        return planar_curvature(len(np.asarray(points).reshape(-1, 3)), self.e0, self.e1)

    def quadrature(self, resolution: float):
        """Points, weights (area) and normals with lines and segments about ``resolution`` apart."""
        return self.graded_quadrature(resolution, None)

    def graded_quadrature(self, resolution: float, cell_size=None, split=None):
        """As :meth:`quadrature`, with strips and segments no longer than ``cell_size(points
        (n, 3)) -> (n,)`` where that is smaller than ``resolution`` (a cap crossing coarse and
        fine cells gets its points where the cells are). ``split(a (n, 3), b (n, 3)) -> (n, k)``
        (fractions in [0, 1], 1 for none) cuts each inside interval of a line between its ends
        a and b instead (e.g. at a grid's cell faces, so that every segment lies in one cell)."""
        x, w = np.polynomial.legendre.leggauss(self.order)
        y, wy = self._strips(resolution, x, w, cell_size)
        lines = self._intervals(y, resolution)
        line, lo_s, hi_s = [], [], []  # every segment of every inside interval, all lines at once
        for k, edges in enumerate(lines):
            for a0, b0 in zip(edges[0::2], edges[1::2]):
                if b0 > a0:
                    n = 1 if split is not None else max(1, int(math.ceil((b0 - a0) / resolution)))
                    seg = np.linspace(a0, b0, n + 1)
                    line.append(np.full(n, k))
                    lo_s.append(seg[:-1])
                    hi_s.append(seg[1:])
        if not line:
            return np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3))
        line, lo_s, hi_s = np.concatenate(line), np.concatenate(lo_s), np.concatenate(hi_s)
        if split is not None:
            line, lo_s, hi_s = self._split_segments(line, lo_s, hi_s, y, split)
        for _ in range(16 if cell_size is not None and split is None else 0):  # split segments longer than their cells
            mid = 0.5 * (lo_s + hi_s)
            size = np.asarray(cell_size(self._place(np.column_stack([mid, y[line]]))), float)
            split_here = hi_s - lo_s > 1.0001 * size
            if not split_here.any():
                break
            line = np.concatenate([line[~split_here], line[split_here], line[split_here]])
            lo_s, hi_s = (np.concatenate([lo_s[~split_here], lo_s[split_here], mid[split_here]]),
                          np.concatenate([hi_s[~split_here], mid[split_here], hi_s[split_here]]))
        half = 0.5 * (hi_s - lo_s)
        xs = (0.5 * (lo_s + hi_s))[:, None] + half[:, None] * x
        ws = half[:, None] * w * wy[line][:, None]
        p = np.column_stack([xs.ravel(), np.repeat(y[line], len(x))])
        points = self._place(p)
        return points, ws.ravel(), np.broadcast_to(self.normal, points.shape).copy()

    def _split_segments(self, line, lo_s, hi_s, y, split):
        """Segments cut at the fractions ``split`` gives for their ends in space, again on the
        pieces until it gives no cut inside any (a grid's finer cells seen on the pieces)."""
        done = []
        for _ in range(32):
            a = self._place(np.column_stack([lo_s, y[line]]))
            b = self._place(np.column_stack([hi_s, y[line]]))
            cuts = np.asarray(split(a, b), dtype=float).reshape(len(line), -1)
            inner = (cuts > 1e-12) & (cuts < 1.0 - 1e-12)
            again = inner.any(axis=1)
            done.append((line[~again], lo_s[~again], hi_s[~again]))
            if not again.any():
                break
            cuts = np.where(inner, cuts, 1.0)[again]
            line, lo_s, hi_s = line[again], lo_s[again], hi_s[again]
            fr = np.sort(np.column_stack([np.zeros(len(line)), cuts, np.ones(len(line))]), axis=1)
            keep = fr[:, 1:] - fr[:, :-1] > 1e-13
            length = (hi_s - lo_s)[:, None]
            lo_s, hi_s = (lo_s[:, None] + fr[:, :-1] * length)[keep], (lo_s[:, None] + fr[:, 1:] * length)[keep]
            line = np.broadcast_to(line[:, None], keep.shape)[keep]
        else:
            done.append((line, lo_s, hi_s))
        return tuple(np.concatenate(parts) for parts in zip(*done))

    def polygon(self):
        """(origin, e0, e1, edges (k, 2, 2)): the region's boundary as straight edges in profile
        coordinates (x = origin + p0 e0 + p1 e1) when every curve of the profile is a segment;
        None otherwise (a split rule then integrates it exactly cell by cell)."""
        curves = [c for loop in self.profile.loops for c in loop]
        if not all(getattr(c, "type", "") == "line" for c in curves):
            return None
        return self.origin, self.e0, self.e1, np.array([[c.p0, c.p1] for c in curves], dtype=float)

    def _place(self, p: np.ndarray) -> np.ndarray:
        return self.origin + p[:, :1] * self.e0 + p[:, 1:] * self.e1

    def _intervals(self, y: np.ndarray, resolution: float) -> list[list[float]]:
        """Per line p1 = y: the sorted ends of its inside intervals (zeros of the profile's
        distance on a fine sampling, refined by bisection, all lines at once)."""
        lo, hi = (np.asarray(b, dtype=float) for b in self.profile.bounds)
        n0 = max(2, int(math.ceil((hi[0] - lo[0]) / resolution)))
        t = np.linspace(lo[0], hi[0], 8 * n0 + 1)
        grid = np.stack(np.broadcast_arrays(t[None, :], y[:, None]), axis=-1).reshape(-1, 2)
        f = np.asarray(self.profile.signed_distance(grid), float).reshape(len(y), len(t))
        inside = f >= 0
        line, col = np.nonzero(inside[:, :-1] != inside[:, 1:])
        a, b = t[col], t[col + 1]
        fa_in = inside[line, col]
        _bisect_crossings(lambda x, rows: np.asarray(self.profile.signed_distance(np.column_stack([x, y[line[rows]]])),
                                                     float) >= 0, a, b, fa_in)
        zeros = 0.5 * (a + b)
        out = []
        for k in range(len(y)):
            edges = ([lo[0]] if inside[k, 0] else []) + list(np.sort(zeros[line == k]))
            if inside[k, -1]:
                edges.append(hi[0])
            out.append(edges)
        return out

    def _breaks(self) -> np.ndarray:
        """p1 values where the region's width along p0 has a kink or a square-root end: the
        edges' ends and the extremes of p1 along each edge."""
        out = []
        for name in self.profile.edge_names:
            c = self.profile.edge(name)
            t = np.linspace(c.t_start, c.t_end, 257)
            y = np.asarray(c.evaluate(t), float)[:, 1]
            out += [y[0], y[-1]]
            dy = np.asarray(c.derivative(t), float)[:, 1]
            for k in np.nonzero((dy[:-1] > 0) != (dy[1:] > 0))[0]:
                a, b = t[k], t[k + 1]
                for _ in range(60):
                    m = 0.5 * (a + b)
                    if (float(np.asarray(c.derivative(np.array([m])), float)[0, 1]) > 0) == (dy[k] > 0):
                        a = m
                    else:
                        b = m
                out.append(float(np.asarray(c.evaluate(np.array([0.5 * (a + b)])), float)[0, 1]))
        return np.unique(np.round(np.asarray(out), 14))

    def _strips(self, resolution: float, x: np.ndarray, w: np.ndarray, cell_size=None):
        """Lines p1 (Gauss in a cosine-stretched coordinate within each range between breaks,
        so the width's square-root ends are integrated smoothly) and their weights; strips
        split further where ``cell_size`` along them is below their height."""
        ys, ws = [], []
        br = self._breaks()
        for a, b in zip(br[:-1], br[1:]):
            if b - a <= 1e-14 * max(1.0, abs(b)):
                continue
            n = max(2, int(math.ceil((b - a) / resolution)))
            edges = np.linspace(0.0, 1.0, n + 1)
            if cell_size is not None:
                edges = self._graded_strips(edges, a, b, cell_size)
            xi = (0.5 * (edges[:-1] + edges[1:])[:, None] + 0.5 * np.diff(edges)[:, None] * x).ravel()
            wxi = (0.5 * np.diff(edges)[:, None] * w).ravel()
            ys.append(a + (b - a) * 0.5 * (1.0 - np.cos(math.pi * xi)))
            ws.append(wxi * (b - a) * 0.5 * math.pi * np.sin(math.pi * xi))
        return np.concatenate(ys), np.concatenate(ws)

    def _graded_strips(self, edges: np.ndarray, a: float, b: float, cell_size) -> np.ndarray:
        """Strip ends (in the cosine coordinate) split while a strip is taller than the
        smallest cell met along its middle line."""
        for _ in range(16):
            mid = 0.5 * (edges[:-1] + edges[1:])
            yk = a + (b - a) * 0.5 * (1.0 - np.cos(math.pi * mid))
            height = (b - a) * 0.5 * (np.cos(math.pi * edges[:-1]) - np.cos(math.pi * edges[1:]))
            lines = self._intervals(yk, max(height.max(), 1e-12))
            smallest = np.full(len(mid), np.inf)
            crossed = [k for k, ends in enumerate(lines) if len(ends) >= 2]
            if crossed:  # 33 points along each line, one call for all lines
                xs = np.concatenate([np.linspace(min(lines[k]), max(lines[k]), 33) for k in crossed])
                owner = np.repeat(crossed, 33)
                sizes = np.asarray(cell_size(self._place(np.column_stack([xs, yk[owner]]))), float)
                np.minimum.at(smallest, owner, sizes)
            split = height > 1.0001 * smallest
            if not split.any():
                break
            edges = np.sort(np.concatenate([edges, mid[split]]))
        return edges

    @property
    def area(self) -> float:
        return float(self.profile.area)


#: bisection steps of a crossing at most (a bracket is final well before, but near zero)
BISECTION_STEPS = 55
#: bisection steps per call of the test: the 2^k - 1 midpoints the next k steps may take are
#: tested together, and the steps walk them (the same brackets as one step per call)
BISECTION_LEVELS = 4


def _bisect_crossings(inside, a: np.ndarray, b: np.ndarray, a_inside: np.ndarray) -> None:
    """Bisect the brackets [a, b] (changed in place) of crossings of ``inside(x, rows) -> bool``
    (rows: which crossings the points x belong to) whose lower end's value is ``a_inside``, until
    a step leaves a bracket unchanged (it is final) or after BISECTION_STEPS steps."""
    live = np.arange(len(a))  # the crossings whose bracket still moves
    steps = 0
    while live.size and steps < BISECTION_STEPS:
        levels = min(BISECTION_LEVELS, BISECTION_STEPS - steps)
        tree = bisection_tree(a[live], b[live], levels)
        value = inside(tree.ravel(), np.repeat(live, tree.shape[1])).reshape(tree.shape)
        rows, node = np.arange(len(live)), np.zeros(len(live), dtype=np.int64)
        for _ in range(levels):
            m = tree[rows, node]
            same = value[rows, node] == a_inside[live]
            new_a, new_b = np.where(same, m, a[live]), np.where(same, b[live], m)
            moved = (new_a != a[live]) | (new_b != b[live])
            a[live], b[live] = new_a, new_b
            # a bracket a step left unchanged stays so: it is final
            live, rows, node = live[moved], rows[moved], np.where(same, 2 * node + 1, 2 * node + 2)[moved]
        steps += levels
