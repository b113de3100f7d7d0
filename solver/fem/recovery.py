"""Recovered (smoothed) stresses from the stresses at cell centroids.

Bilinear squares have their most accurate stresses at the cell centres (superconvergence).
Nodal values are least-squares fits to the centroid stresses around each node, evaluated at
the node (superconvergent patch recovery in the manner of Zienkiewicz and Zhu), weighted by the
cells' inside areas:

- nodes touching a cut cell (possibly outside the body, with a lopsided one-ring): a linear fit
  over the two-ring of cells, so that peaks at the boundary are extrapolated rather than averaged
  away;
- every other node: a quadratic fit over the two-ring (16 cells on a uniform patch). The plain
  mean of the four centroids around a node is off by about h^2/8 of the stress's Laplacian
  (it averages across the node); the quadratic fit removes that bias. Measured on examples 2
  and 3 (turned 25 degrees) against the same scenes two refinement levels finer: the stress error
  at 0.7 a below the contact 0.29 -> 0.16 % of p0 and the von Mises peak -0.46 / -0.49 % ->
  -0.24 / -0.21 % (benchmarks/tractions.py; docs/contact.md). A node whose patch cannot hold a
  quadratic (too few or collinear centroids) keeps the mean.

The recovered field is the bilinear interpolation of these nodal values. Both fits reproduce
linear stress fields exactly.

Planes of symmetry (:func:`sliding_symmetry`): a flat face (2D: a straight edge) held by a
sliding condition is a mirror of the solution (u_n = 0 and no tangential traction: the even
reflection continues the field), so the patches of the nodes on and near it are completed by the mirror images of the
centroid stresses (the components with one index normal to the plane change sign), and a cell
flagged cut only because one of its faces lies on such a plane counts as whole. The nodes on a
quarter model's symmetry planes and on its axis then take the quadratic fit of a whole patch
(or the mean of a whole one-ring) instead of a linear fit over a one-sided patch, biased by h^2
of the curvature across the plane. Measured on examples/solid/sphere_on_flat (11.6 cells along
a): the largest shear on the axis 0.3070 p0 at 0.5079 a -> 0.3093 p0 at 0.4846 a (Hertz
0.3100 p0 at 0.4847 a; the raw stress C B u peaks at 0.4854 a; one level finer the depth's
error is +1.02 % -> -0.03 %: the one-sided bias falls as h^2); on spherical_cavity's
equatorial plane 1 to 6 cells from the cavity, s_zz against Goodier's field +1.9 to +4.1 % ->
0.0 to +0.7 %. The linear fits next to cut cells keep their own cells: there the mirrored
patch is symmetric and its linear fit averages a boundary's peak across the node rather than
extrapolating it (spherical_cavity's Goodier point -1.42 % would become -2.49 %). Where the grid
is not aligned with the plane the images share no node with the grid and change nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .grid import CUT, Grid

__all__ = ["MirrorPlane", "mirrored_patches", "nodal_stress", "patch_recovery", "reflect_stress", "sliding_symmetry"]


def nodal_stress(grid: Grid, centroids: np.ndarray, stress: np.ndarray, boundary=None, sliding=()) -> np.ndarray:
    """(N, k) recovered nodal values of cell values ``stress`` (m, k) given at ``centroids``
    (a 2D grid: its cells' inside areas weigh the fits); the straight edges of ``boundary``
    named in ``sliding`` are mirrors (sliding_symmetry)."""
    planes, cut = [], grid.status == CUT
    if boundary is not None and len(sliding):
        planes, cut = sliding_symmetry(boundary, sliding, grid, cut, grid.inside_area, centroids)
    return patch_recovery(grid.cells, grid.nodes, grid.size, grid.inside_area, cut, centroids, stress, planes)


def patch_recovery(cells: np.ndarray, nodes: np.ndarray, sizes: np.ndarray, weights: np.ndarray, cut: np.ndarray,
                   centroids: np.ndarray, stress: np.ndarray, mirrors=()) -> np.ndarray:
    """The recovery of any dimension: cells (m, corners) of nodes (N, dim), the cells' sizes,
    inside measures (the fits' weights) and cut flags; values ``stress`` (m, k) at ``centroids``.
    ``mirrors``: MirrorPlane's completing the patches at symmetry planes (mirrored_patches)."""
    real_cells, real = len(cells), len(nodes)
    cells, nodes, sizes, w, cut, centroids, stress = mirrored_patches(
        cells, nodes, sizes, weights, cut, centroids, stress, mirrors)
    m, n = len(cells), len(nodes)
    corners = cells.shape[1]
    w = np.asarray(w, dtype=float)
    rows = cells.ravel()
    cols = np.repeat(np.arange(m), corners)
    inc = sp.csr_matrix((np.ones(corners * m), (rows, cols)), shape=(n, m))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = (inc[:real] @ (w[:, None] * stress)) / (inc[:real] @ w)[:, None]
    scale = np.full(n, np.inf)
    np.minimum.at(scale, rows, np.repeat(sizes, corners))
    cut = np.asarray(cut, dtype=float)
    # quadratic fits where the whole two-ring is uncut (cut cells' centroid stresses are not
    # superconvergent: measured on the turned Lame annulus, including them doubles the error
    # two cells inside the boundary); the mean stays between
    clear = ((inc[:real] @ (inc.T @ (inc @ cut))) == 0) & ((inc[:real] @ (w > 0).astype(float)) > 0)
    interior = np.nonzero(clear)[0]
    # linear fits next to cut cells over the real cells only: a patch completed across a plane
    # is symmetric there and its linear fit averages a boundary's peak across the node instead
    # of extrapolating it (measured: spherical_cavity's Goodier point -1.42 -> -2.49 %)
    boundary = np.nonzero((inc[:real] @ cut) > 0)[0]
    for subset, degree, patches in ((interior, 2, inc), (boundary, 1, inc[:, :real_cells])):
        if len(subset):
            ok, values = _patch_fit(patches, subset, nodes, scale, centroids, stress, w, degree)
            out[subset[ok]] = values
    return out


#: cells mirrored: centroids within this many of their sizes of the plane (a node's two-ring
#: reaches two cells across it)
MIRROR_BAND = 2.5
#: of the cell size: nodes this close coincide, a corner this close to a plane lies on it, a cell
#: missing no more of its volume is whole
ALIGNED = 1e-3


@dataclass(frozen=True)
class MirrorPlane:
    """A plane of mirror symmetry of the solution at the body's boundary (a planar sliding face:
    u_n = 0 and no tangential traction, so the even reflection continues the field): ``origin``
    and unit outward ``normal``; ``cells`` (m,) marks the cells whose mirror images may complete
    the patches there (the caller's: near the face, images outside the body)."""

    origin: np.ndarray
    normal: np.ndarray
    cells: np.ndarray


def reflect_stress(stress: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Voigt stresses (n, 3) in 2D ([sxx, syy, sxy]) or (n, 6) in 3D ([sxx, syy, szz, syz, sxz,
    sxy]) mirrored in the plane of unit ``normal``: R s R with R = I - 2 n n^T (aligned with an
    axis: the shear components with one index along it change sign). Several stress fields side
    by side, (n, 3 g) or (n, 6 g), are mirrored each in turn (the dimension is the normal's)."""
    s = np.asarray(stress, dtype=float)
    dim = len(normal)
    width = len(_VOIGT[dim])
    if s.shape[1] != width:  # g fields side by side: each row of width components on its own
        return reflect_stress(s.reshape(-1, width), normal).reshape(s.shape)
    pairs = _VOIGT[dim]
    t = np.zeros((len(s), dim, dim))
    for k, (i, j) in enumerate(pairs):
        t[:, i, j] = t[:, j, i] = s[:, k]
    n = np.asarray(normal, dtype=float)
    r = np.eye(dim) - 2.0 * np.outer(n, n)
    t = r @ t @ r
    return np.column_stack([t[:, i, j] for i, j in pairs])


_VOIGT = {2: ((0, 0), (1, 1), (0, 1)), 3: ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))}


def mirrored_patches(cells, nodes, sizes, weights, cut, centroids, stress, planes):
    """The cells of a grid completed by their mirror images in ``planes`` (each applied in turn
    to the real and the earlier images, so two planes at right angles fill the quadrant across
    both): images of the cells within MIRROR_BAND cells of a plane (and marked by it), their
    corners merged with the grid's nodes where they coincide (a grid aligned with the plane
    shares its nodes on the plane with the images; elsewhere the images stay apart and change
    nothing). Returns the same seven arrays, the real cells and nodes first."""
    cells, nodes = np.asarray(cells), np.asarray(nodes, dtype=float)
    sizes, weights, cut = (np.asarray(v) for v in (sizes, weights, cut))
    centroids, stress = np.asarray(centroids, dtype=float), np.asarray(stress, dtype=float)
    source = np.arange(len(cells))  # the real cell each (real or image) cell comes from
    tol = ALIGNED * float(np.min(sizes))
    for plane in planes:
        n = np.asarray(plane.normal, dtype=float)
        depth = (np.asarray(plane.origin, dtype=float) - centroids) @ n  # inside: > 0
        pick = np.nonzero(np.asarray(plane.cells, bool)[source] & (depth > 0.0) & (depth < MIRROR_BAND * sizes)
                          & (weights > 0))[0]
        if len(pick) == 0:
            continue
        used, local = np.unique(cells[pick], return_inverse=True)
        images = nodes[used] + 2.0 * ((plane.origin - nodes[used]) @ n)[:, None] * n
        index = _merge_nodes(nodes, images, tol)
        fresh = index < 0
        index[fresh] = len(nodes) + np.arange(fresh.sum())
        nodes = np.vstack([nodes, images[fresh]])
        cells = np.vstack([cells, index[local].reshape(cells[pick].shape)])
        centroids = np.vstack([centroids, centroids[pick] + 2.0 * depth[pick, None] * n])
        stress = np.vstack([stress, reflect_stress(stress[pick], n)])
        sizes, weights, cut = (np.concatenate([v, v[pick]]) for v in (sizes, weights, cut))
        source = np.concatenate([source, source[pick]])
    return cells, nodes, sizes, weights, cut, centroids, stress


#: bins along the longest side of the points' box at most in :func:`_merge_nodes` (the bins'
#: flat index, over three axes with their margins, stays below 2^63)
_MERGE_BINS = 2e6


def _merge_nodes(nodes: np.ndarray, points: np.ndarray, tol: float) -> np.ndarray:
    """Index of the nearest node within ``tol`` of each point, -1 where none is. The nodes in the
    points' box are binned on a lattice of bins at least ``tol`` wide (a node within ``tol`` of
    a point lies in the point's bin or a neighbouring one) and the bins are matched by sorting:
    no tree, and none of the tree's imports (a third of a second)."""
    nodes, points = np.asarray(nodes, dtype=float), np.asarray(points, dtype=float)
    index = np.full(len(points), -1, dtype=np.int64)
    if len(points) == 0 or len(nodes) == 0:
        return index
    lo, hi = points.min(axis=0) - tol, points.max(axis=0) + tol
    near = np.nonzero(np.all((nodes >= lo) & (nodes <= hi), axis=1))[0]
    if len(near) == 0:
        return index
    side = max(float(tol), float(np.max(hi - lo)) / _MERGE_BINS, np.finfo(float).tiny)
    shape = tuple(np.floor((hi - lo) / side).astype(np.int64) + 3)  # a bin of margin on each side

    def keys(x: np.ndarray, shift: np.ndarray) -> np.ndarray:
        bins = np.clip(np.floor((x - lo) / side).astype(np.int64) + 1, 0, np.asarray(shape) - 2)
        return np.ravel_multi_index((bins[:, None, :] + shift).reshape(-1, x.shape[1]).T, shape)

    dim = points.shape[1]
    node_keys = keys(nodes[near], np.zeros((1, dim), dtype=np.int64))
    order = np.argsort(node_keys, kind="stable")
    sorted_keys = node_keys[order]
    shifts = np.stack(np.meshgrid(*[(-1, 0, 1)] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    wanted = keys(points, shifts)
    first, last = np.searchsorted(sorted_keys, wanted, "left"), np.searchsorted(sorted_keys, wanted, "right")
    owner = np.repeat(np.arange(len(points)), len(shifts))
    found_point, found_node = [], []
    for k in range(int((last - first).max(initial=0))):  # the nodes sharing a bin, one at a time
        has = np.nonzero(first + k < last)[0]
        found_point.append(owner[has])
        found_node.append(near[order[first[has] + k]])
    if not found_point:
        return index
    p, n = np.concatenate(found_point), np.concatenate(found_node)
    dist = np.linalg.norm(nodes[n] - points[p], axis=1)
    close = dist <= tol
    p, n, dist = p[close], n[close], dist[close]
    nearest = np.lexsort((dist, p))  # by point, the nearest first
    p, n = p[nearest], n[nearest]
    head = np.ones(len(p), dtype=bool)
    head[1:] = p[1:] != p[:-1]
    index[p[head]] = n[head]
    return index


def sliding_symmetry(boundary, names, grid, status_cut: np.ndarray, inside: np.ndarray,
                     centroids: np.ndarray) -> tuple[list[MirrorPlane], np.ndarray]:
    """The mirror planes of a body's flat sliding faces (3D: ``boundary.faces``) or straight
    sliding edges (2D: ``boundary.curves``) named ``names``, and the cut flags the recovery
    should use with them: a cell flagged cut only because one of its faces lies on such a plane
    (whole, every corner on the boundary on a plane) is a whole cell of the mirrored grid."""
    sizes, cut = grid.size, np.asarray(status_cut, bool).copy()
    phi = boundary.signed_distance
    found = _face_planes(boundary.faces, names, phi, sizes) if hasattr(boundary, "faces") else \
        _edge_planes(boundary.curves, names, phi, sizes)
    planes = []
    for origin, normal, on_face in found:
        depth = (origin - centroids) @ normal
        band = np.nonzero((depth > 0.0) & (depth < MIRROR_BAND * sizes) & (inside > 0))[0]
        images = centroids[band] + 2.0 * depth[band, None] * normal
        near = on_face(centroids[band] + depth[band, None] * normal, ALIGNED * sizes[band])
        outside = np.asarray(phi(images), float) < 0.0
        marked = np.zeros(len(sizes), bool)
        marked[band[near & outside]] = True
        planes.append(MirrorPlane(origin, normal, marked))
    if planes:
        cut &= ~_on_planes_only(grid, cut, inside, phi, planes)
    return planes, cut


def _face_planes(faces: dict, names, signed_distance, sizes) -> list:
    """(origin, outward unit normal, on_face(feet, tol)) of the flat faces among ``names``. A
    foot on the plane is on the face where it is on the body's boundary (|signed distance| <=
    tol): the only face of the body in that plane holds it. Where another face of the body lies
    in the same plane (a plane split into faces), the face's projection must leave the foot in
    place (about a thousand times dearer than the signed distance)."""
    found = []
    for name in names:
        face = faces.get(name)
        plane = None if face is None else _plane_of(face, signed_distance, sizes)
        if plane is None:
            continue  # a curved sliding face is no mirror
        if hasattr(face, "project") and _shares_plane(faces, name, *plane, float(np.max(sizes))):
            def on_face(feet, tol, face=face):
                near = np.abs(np.asarray(signed_distance(feet), float)) <= tol
                hit = np.nonzero(near)[0]
                if len(hit):
                    foot = np.asarray(face.project(feet[hit]).points, float)
                    near[hit] = np.linalg.norm(foot - feet[hit], axis=1) <= tol[hit]
                return near
        else:
            def on_face(feet, tol):
                return np.abs(np.asarray(signed_distance(feet), float)) <= tol
        found.append(plane + (on_face,))
    return found


def _shares_plane(faces: dict, name: str, origin: np.ndarray, normal: np.ndarray, size: float) -> bool:
    """Whether a face other than ``name`` lies in the plane (origin, normal): all its
    quadrature points on it (a plane face by its exact plane)."""
    tol = ALIGNED * size
    for other, face in faces.items():
        if other == name:
            continue
        surface = getattr(face, "surface", None)
        if getattr(surface, "type", None) == "plane":
            o, n = np.asarray(surface.origin, float), np.asarray(surface.normal, float)
            if abs(abs(float(n @ normal)) - 1.0) <= 1e-9 and abs(float((o - origin) @ normal)) <= tol:
                return True
            continue
        points = np.asarray(face.quadrature(4.0 * size)[0], float)
        if len(points) and np.abs((points - origin) @ normal).max() <= tol:
            return True
    return False


def _edge_planes(curves: dict, names, signed_distance, sizes) -> list:
    """(origin, outward unit normal, on_edge(feet, tol)) of the straight edges among ``names``."""
    found = []
    for name in names:
        curve = curves.get(name)
        if curve is None:
            continue
        points = np.asarray(curve.evaluate(np.linspace(curve.t_start, curve.t_end, 9)), float)
        start, along = points[0], points[-1] - points[0]
        length = float(np.linalg.norm(along))
        if length == 0.0:
            continue
        along /= length
        normal = np.array([along[1], -along[0]])
        if np.abs((points - start) @ normal).max() > ALIGNED * float(np.min(sizes)):
            continue  # a curved sliding edge is no mirror
        normal = normal * _outward(start + 0.5 * length * along, normal, signed_distance, float(np.min(sizes)))
        found.append((start, normal, lambda feet, tol, s=start, a=along, n=length:
                      (((feet - s) @ a) >= -tol) & (((feet - s) @ a) <= n + tol)))
    return found


def _plane_of(face, signed_distance, sizes) -> tuple[np.ndarray, np.ndarray] | None:
    """(origin, unit outward normal) of a planar face, None for a curved one: its exact plane
    where the face names one, else its quadrature points' (all coplanar, one normal)."""
    surface = getattr(face, "surface", None)
    if getattr(surface, "type", None) == "plane" and hasattr(face, "project"):
        origin, normal = np.asarray(surface.origin, float), np.asarray(surface.normal, float)
        foot = np.asarray(face.project(origin[None]).points, float)[0]
        return origin, normal * _outward(foot, normal, signed_distance, float(np.min(sizes)))
    points, _, normals = face.quadrature(4.0 * float(np.max(sizes)))  # normals outward
    if len(points) == 0:
        return None
    normal = normals.mean(axis=0)
    normal /= np.linalg.norm(normal)
    flat = np.abs((points - points[0]) @ normal).max() <= ALIGNED * float(np.min(sizes))
    return (points[0], normal) if flat and np.abs(normals - normal).max() <= 1e-9 else None


def _outward(foot, normal, signed_distance, step: float) -> float:
    """+1 when ``normal`` points out of the body at ``foot`` on its boundary (a CAD face's
    surface may be oriented either way), else -1."""
    phi = np.asarray(signed_distance(np.array([foot + step * normal, foot - step * normal])), float)
    return 1.0 if phi[0] <= phi[1] else -1.0


def _on_planes_only(grid, cut, inside, signed_distance, planes) -> np.ndarray:
    """Whole cut cells whose corners on the boundary all lie on the mirror planes (at least one)."""
    whole = np.nonzero(cut & (inside >= (1.0 - ALIGNED) * grid.size ** grid.nodes.shape[1]))[0]
    corners = grid.nodes[grid.cells[whole]]  # (k, corners, dim)
    tol = ALIGNED * grid.size[whole][:, None]
    phi = np.asarray(signed_distance(corners.reshape(-1, corners.shape[2])), float).reshape(corners.shape[:2])
    on_plane = np.zeros(phi.shape, bool)
    for plane in planes:
        on_plane |= np.abs((corners - plane.origin) @ plane.normal) <= tol
    on_boundary = phi <= tol
    only = np.all(~on_boundary | on_plane, axis=1) & np.any(on_boundary & on_plane, axis=1)
    out = np.zeros(len(cut), bool)
    out[whole[only]] = True
    return out


def _patch_fit(inc, nodes, points, scale, centroids, stress, w, degree: int):
    """Weighted least-squares polynomial (degree 1 or 2) through the centroid values of the
    two-ring of cells of each node, evaluated at the node; returns (fitted mask, values)."""
    ring2 = (inc[nodes] @ inc.T @ inc).tocoo()
    node, cell = nodes[ring2.row], ring2.col
    d = (centroids[cell] - points[node]) / scale[node][:, None]
    dim = d.shape[1]
    terms = [np.ones(len(d))] + [d[:, i] for i in range(dim)]
    if degree == 2:
        terms += [d[:, i] * d[:, j] for i in range(dim) for j in range(i, dim)]
    basis = np.column_stack(terms)
    order = np.argsort(ring2.row, kind="stable")  # each node's entries together
    local, cell, basis = ring2.row[order], cell[order], basis[order]
    wb = w[cell][:, None] * basis
    mat = _node_sums(local, len(nodes), wb, basis)
    ev = np.linalg.eigvalsh(mat)
    ok = ev[:, 0] > 1e-8 * ev[:, -1]
    # the value at the node is the fit's first coefficient, e0^T M^-1 sum_e wb_e s_e: each entry's
    # weight in it is (M^-1 e0) . wb_e (M symmetric), so the fits are one sparse operator applied
    # to all the columns of ``stress`` at once, with no (entries x columns) temporary
    e0 = np.zeros((int(ok.sum()), basis.shape[1], 1))
    e0[:, 0, 0] = 1.0
    first = np.zeros((len(nodes), basis.shape[1]))
    first[ok] = np.linalg.solve(mat[ok], e0)[:, :, 0]
    weight = np.einsum("ea,ea->e", first[local], wb)
    fits = sp.csr_matrix((weight, (local, cell)), shape=(len(nodes), len(stress)))
    return ok, (fits @ stress)[ok]


#: nodes per block of :func:`_node_sums`
_NODES = 2048


def _node_sums(local: np.ndarray, n: int, left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """(n, a, b): the sum over each node's entries of left[e, :, None] * right[e, None, :]
    (``local``, sorted, the node of each entry). The nodes are taken in blocks of similar patch
    size, each node's entries padded with zeros to the block's largest patch, and each block
    summed by one batched matrix product left^T right."""
    a, b = left.shape[1], right.shape[1]
    counts = np.bincount(local, minlength=n)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    by_size = np.argsort(counts, kind="stable")
    out = np.zeros((n, a, b))
    for first in range(0, n, _NODES):
        block = by_size[first:first + _NODES]
        width = max(int(counts[block[-1]]), 1)
        position = np.arange(width)
        used = position[None, :] < counts[block, None]
        entry = np.where(used, starts[block, None] + position[None, :], 0)
        padded_left = np.where(used[:, None, :], left[entry].transpose(0, 2, 1), 0.0)  # (k, a, width)
        padded_right = np.where(used[:, :, None], right[entry], 0.0)  # (k, width, b)
        out[block] = np.matmul(padded_left, padded_right)
    return out
