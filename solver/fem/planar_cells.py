"""Cut cells bounded by planar faces, integrated exactly: where the faces of a solid that cross
a (sub-)cube are planes, its inside part is a union of pieces of the arrangement of those
planes in the cube, each a convex polyhedron whose moments solver.fem.polyhedra gives exactly.
This makes the edges and corners of solids (two or three faces meeting inside a cell) as exact
as a single planar cut, which a rule along lines is not: the height of the boundary has a kink
along the edge.

The planes come from the exact signed distance alone. Where the distance is affine around a
point (its second differences and the deviation of the corners of a small stencil from the
linear model vanish to rounding, and its gradient has unit length), the nearest boundary point
lies on a planar face and phi(p) + grad(p) . (x - p) is that face's plane; points near an edge,
outside a convex edge (the distance is to the edge line there) or near a curved face give
nothing. The distinct planes of a sample lattice (at most MAX_PLANES) cut the cube into the
pieces of every sign pattern; each non-empty piece is inside or outside as the distance at its
centroid says. The model is accepted only when it reproduces the sign of the distance at every
sampled point in the cube and the distance vanishes where the model puts the boundary (the
samples projected on each plane where the pieces on its two sides differ); otherwise the cell
keeps the general rule (curved faces, more planes, features between the samples). A cube where
one piece holds sample centres of both signs fails the sign check for sure: it is dropped before
its pieces are clipped and integrated (where a curved face meets a planar one)."""

from __future__ import annotations

import numpy as np

from .polyhedra import clip_cubes, tetrahedron_moments

__all__ = ["planar_moments", "MAX_PLANES"]

#: most distinct planes in one (sub-)cube (2^MAX_PLANES pieces are clipped)
MAX_PLANES = 6
#: stencil of each sample: the point, +-x, +-y, +-z, the eight corners (in units of the step)
_STENCIL = np.concatenate([np.zeros((1, 3)), np.vstack([np.eye(3), -np.eye(3)])[[0, 3, 1, 4, 2, 5]],
                           np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float)])
#: stencil step in units of the cube's half edge
_STEP = 0.05
#: affine tolerance in units of the half edge (plus rounding of the coordinates)
_AFFINE = 1e-9
#: two planes are one when their unit normals and offsets (half edges) agree to this
_SAME = 1e-7
#: the distance must vanish to this (half edges) where the model puts the boundary
_ZERO = 1e-8
#: the vertices of each piece checked are moved this share of the way to its centroid
_PULL = 1e-5
#: pieces clipped at once (bounds the memory of their tetrahedra)
JOBS_PER_CLIP = 256
#: distance points per call (a CAD solid's distance holds kilobytes per point of a call: the
#: Onshape ball on a block peaked at 3.6 GB with 200,000, 0.55 GB with 5,000)
PASS_POINTS = 5000
#: stencil points of the cubes handled in one pass (their arrays hold about 100 bytes per point;
#: the distance is still called PASS_POINTS at a time): larger passes spend less per cube on
#: numpy's per-call overhead
PASS_STENCIL_POINTS = 60000


def planar_moments(signed_distance, cell_lower, scale, lo, width, samples: int = 4):
    """Moments (q, 27) of the inside parts of the cubes [lo, lo + width] (local coordinates of
    cells with lower corners ``cell_lower`` (q, 3) and half edges ``scale`` (q,)) where the
    planar model holds, and whether it held (q,) (moments of the others are zero). ``samples``:
    lattice points per direction over the cube enlarged by a quarter on each side."""
    q = len(lo)
    out, ok = np.zeros((q, 27)), np.zeros(q, dtype=bool)
    # first the corners of the enlarged cube alone: where none sees a plane (a curved face), stop
    corners = np.array([-0.25, 1.25])
    some = np.zeros(q, dtype=bool)
    for start in range(0, q, _chunk(corners)):
        s = slice(start, start + _chunk(corners))
        some[s] = _local_planes(signed_distance, cell_lower[s], scale[s], lo[s], width[s], corners)[4] > 0
    rows = np.flatnonzero(some)
    lattice = np.linspace(-0.25, 1.25, samples)
    for start in range(0, len(rows), _chunk(lattice)):
        r = rows[start:start + _chunk(lattice)]
        out[r], ok[r] = _planar_chunk(signed_distance, cell_lower[r], scale[r], lo[r], width[r], lattice)
    return out, ok


def _distance(signed_distance, points: np.ndarray) -> np.ndarray:
    """The distance at points (n, 3), PASS_POINTS at a time."""
    if len(points) <= PASS_POINTS:
        return np.asarray(signed_distance(points), dtype=float)
    return np.concatenate([np.asarray(signed_distance(points[i:i + PASS_POINTS]), dtype=float)
                           for i in range(0, len(points), PASS_POINTS)])


def _chunk(lattice) -> int:
    """Cubes per pass: PASS_STENCIL_POINTS stencil points."""
    return max(1, int(PASS_STENCIL_POINTS // (len(_STENCIL) * len(lattice) ** 3)))


def _local_planes(signed_distance, cell_lower, scale, lo, width, lattice):
    """Sample points (q, n, 3) and their distances, and the distinct planes found around them in
    local coordinates: normals (q, MAX_PLANES, 3), offsets (q, MAX_PLANES) with
    normal . t + offset >= 0 inside (unused slots: no constraint), and their count (q,)."""
    q = len(lo)
    half = 0.5 * width * scale  # physical half edge of each cube
    corner = cell_lower + (lo + 1.0) * scale[:, None]
    frac = np.stack(np.meshgrid(lattice, lattice, lattice, indexing="ij"), axis=-1).reshape(-1, 3)
    centre = corner[:, None, :] + frac[None] * (2.0 * half)[:, None, None]  # (q, n, 3)
    step = _STEP * half
    pts = centre[:, :, None, :] + step[:, None, None, None] * _STENCIL[None, None]
    phi = _distance(signed_distance, pts.reshape(-1, 3)).reshape(pts.shape[:3])
    f0, plus, minus = phi[..., 0], phi[..., 1:7:2], phi[..., 2:7:2]
    grad = (plus - minus) / (2.0 * step)[:, None, None]
    linear = f0[..., None] + (grad @ _STENCIL[7:].T) * step[:, None, None]
    deviation = np.maximum(np.abs(plus + minus - 2.0 * f0[..., None]).max(axis=-1),
                           np.abs(phi[..., 7:] - linear).max(axis=-1))
    rounding = 64.0 * np.finfo(float).eps * (np.abs(centre).max(axis=(1, 2)) + 2.0 * half)
    length = np.linalg.norm(grad, axis=-1)
    affine = (deviation <= (_AFFINE * half + rounding)[:, None]) & (np.abs(length - 1.0) < 1e-6)
    normal = grad / np.where(length > 0.0, length, 1.0)[..., None]
    offset = (f0 - np.einsum("qnk,qnk->qn", normal, centre)) / half[:, None]  # n . x + c half >= 0
    # distinct planes, greedily: the first affine sample not yet matched is the next plane
    rows = np.arange(q)
    open_ = affine.copy()
    pick = np.zeros((q, MAX_PLANES), dtype=np.int64)
    count = np.zeros(q, dtype=np.int64)
    for slot in range(MAX_PLANES + 1):
        has = open_.any(axis=1)
        if not has.any():
            break
        first = np.argmax(open_, axis=1)
        if slot < MAX_PLANES:
            pick[has, slot] = first[has]
        count += has
        match = (np.abs(normal - normal[rows, first][:, None]).max(axis=-1) < _SAME) \
            & (np.abs(offset - offset[rows, first][:, None]) < _SAME)
        open_ &= ~(match & has[:, None])
    used = np.arange(MAX_PLANES)[None] < count[:, None]
    rows = rows[:, None]
    n_sel = np.where(used[..., None], normal[rows, pick], 0.0)
    # local coordinates t: x = cell_lower + (t + 1) scale
    c_sel = offset[rows, pick] * half[:, None] + np.einsum("qpk,qk->qp", n_sel, cell_lower + scale[:, None])
    local_offset = np.where(used, c_sel / scale[:, None], 1.0)
    return pts, phi, n_sel, local_offset, count


def _pattern(values, tol):
    """Index of the sign pattern (bit i set where plane i is negative) of values (..., k), and
    whether every value is clear of its plane by tol (broadcast to values.shape[:-1])."""
    index = np.zeros(values.shape[:-1], dtype=np.int64)
    clear = np.ones(values.shape[:-1], dtype=bool)
    for i in range(values.shape[-1]):  # plane by plane: faster than reductions along the short last axis
        index |= (values[..., i] < 0.0).astype(np.int64) << i
        clear &= np.abs(values[..., i]) > tol
    return index, clear


def _planar_chunk(signed_distance, cell_lower, scale, lo, width, lattice):
    """Moments and whether the model held."""
    q = len(lo)
    pts, phi, normal, offset, count = _local_planes(signed_distance, cell_lower, scale, lo, width, lattice)
    some = (count >= 1) & (count <= MAX_PLANES)  # the others: no planar model
    if some.any():  # nor where one piece holds points of both signs (the model's checks would fail)
        some[some] = ~_mixed_pieces(pts[some, :, 0], phi[some, :, 0], normal[some], offset[some], cell_lower[some],
                                    scale[some], lo[some], width[some])
    some = np.flatnonzero(some)
    result, ok = np.zeros((q, 27)), np.zeros(q, dtype=bool)
    if len(some):
        result[some], ok[some] = _arrangement_moments(signed_distance, pts[some], phi[some], normal[some],
                                                      offset[some], count[some], cell_lower[some], scale[some],
                                                      lo[some], width[some])
    return result, ok


#: margin (share of the cube's width) by which the points of :func:`_mixed_pieces` clear the
#: planes and the cube's faces: a piece holding one holds a ball of that radius, far more than the
#: arrangement's smallest piece (1e-13 of the cube's volume)
_CLEAR = 1e-4


def _mixed_pieces(pts, phi, normal, offset, cell_lower, scale, lo, width) -> np.ndarray:
    """Cubes (q,) where one piece of the planes' arrangement holds two of the points ``pts``
    (q, n, 3) (well inside the cube and clear of every plane) with distances ``phi`` (q, n) of
    opposite signs: the model's inside (one truth per piece) contradicts one of them, so
    :func:`_signs_agree` would reject the cube. Found before the pieces are clipped and
    integrated (the cubes where a curved face meets a planar one)."""
    q, pieces = len(lo), 2 ** normal.shape[1]
    t = _local(pts, cell_lower, scale)
    margin = _CLEAR * width
    index, clear = _pattern(t @ normal.transpose(0, 2, 1) + offset[:, None, :], margin[:, None])
    low, high = (lo + margin[:, None])[:, None], (lo + (width - margin)[:, None])[:, None]
    for k in range(3):  # axis by axis: faster than .all(axis=-1) over three entries
        clear &= (t[..., k] > low[..., k]) & (t[..., k] < high[..., k])
    clear &= np.abs(phi) > (_AFFINE * 0.5 * width * scale)[:, None]
    cube, point = np.nonzero(clear)
    key = cube * pieces + index[cube, point]
    positive = np.bincount(key, weights=phi[cube, point] > 0.0, minlength=q * pieces)
    total = np.bincount(key, minlength=q * pieces)
    return ((positive > 0) & (positive < total)).reshape(q, pieces).any(axis=1)


def _arrangement_moments(signed_distance, pts, phi, normal, offset, count, cell_lower, scale, lo, width):
    """Moments (q, 27) of the cubes' inside parts as the inside pieces of the planes'
    arrangement, and whether the model passed its checks (q,)."""
    q = len(lo)
    k = MAX_PLANES
    patterns = np.arange(2**k)
    sign = 1.0 - 2.0 * ((patterns[:, None] >> np.arange(k)[None]) & 1)  # (P, k)
    used = np.arange(k)[None] < count[:, None]
    valid = ((count >= 1) & (count <= k))[:, None] & ~((sign[None] < 0) & ~used[:, None, :]).any(axis=2)
    job_cube, job_pattern = np.nonzero(valid)
    jn = normal[job_cube] * sign[job_pattern][:, :, None]
    jc = offset[job_cube] * sign[job_pattern]
    tet_parts, owner_parts = [], []
    for start in range(0, len(job_cube), JOBS_PER_CLIP):  # a piece cut by k planes: up to 6 3^k tetrahedra
        j = slice(start, start + JOBS_PER_CLIP)
        t, o = clip_cubes(lo[job_cube[j]], width[job_cube[j]], jn[j], jc[j])
        tet_parts.append(t)
        owner_parts.append(o + start)
    tets = np.concatenate(tet_parts) if tet_parts else np.zeros((0, 4, 3))
    owner = np.concatenate(owner_parts) if owner_parts else np.zeros(0, dtype=np.int64)
    volume, first = _volumes_and_first_moments(tets, owner, len(job_cube))
    filled = volume > 1e-13 * width[job_cube] ** 3
    centroid_local = first[filled] / volume[filled, None]
    centroid = cell_lower[job_cube[filled]] + (centroid_local + 1.0) * scale[job_cube[filled], None]
    truth = np.full((q, 2**k), -1, dtype=np.int8)  # 1 inside, 0 outside, -1 no piece
    truth[job_cube[filled], job_pattern[filled]] = _distance(signed_distance, centroid) > 0.0
    half = 0.5 * width * scale
    ok = (count >= 1) & (count <= k)
    ok &= _signs_agree(pts, phi, normal, offset, truth, cell_lower, scale, lo, width, half)
    ok &= _zero_on_boundary(signed_distance, pts[:, :, 0], normal, offset, truth, cell_lower, scale, lo, width, half)
    ok &= _vertices_agree(signed_distance, tets, owner, filled, centroid_local, truth[job_cube, job_pattern],
                          job_cube, cell_lower, scale, half)
    # the full moments of the inside pieces of the cubes that passed, alone
    inside = filled.copy()
    inside[filled] = truth[job_cube[filled], job_pattern[filled]] == 1
    inside &= ok[job_cube]
    piece = np.full(len(job_cube), -1)
    piece[inside] = np.arange(int(inside.sum()))
    sel = piece[owner] >= 0
    result = np.zeros((q, 27))
    np.add.at(result, job_cube[inside], tetrahedron_moments(tets[sel], piece[owner[sel]], int(inside.sum())))
    return result, ok


def _volumes_and_first_moments(tets: np.ndarray, owner: np.ndarray, m: int):
    """Volumes (m,) and first moments (m, 3) of the pieces made of the tetrahedra (t, 4, 3) with
    owners (t,), from the vertices (a tetrahedron's centroid is the mean of its four)."""
    volume = np.abs(np.linalg.det(tets[:, 1:] - tets[:, :1])) / 6.0
    centre = 0.25 * (tets[:, 0] + tets[:, 1] + tets[:, 2] + tets[:, 3])
    first = np.column_stack([np.bincount(owner, volume * centre[:, k], minlength=m) for k in range(3)])
    return np.bincount(owner, volume, minlength=m), first


def _vertices_agree(signed_distance, tets, owner, filled, centroid_local, job_truth, job_cube, cell_lower, scale,
                    half):
    """Whether the distance has the sign of each non-empty piece at the piece's vertices (the
    tetrahedra's), moved a little towards its centroid. A plane the model misses splits some
    piece, and each part of a convex polyhedron cut by a plane holds one of its vertices."""
    where = np.full(len(filled), -1)
    where[np.flatnonzero(filled)] = np.arange(int(filled.sum()))
    sel = where[owner] >= 0
    t, job = tets[sel], owner[sel]
    centre = centroid_local[where[job]]
    pulled = t + _PULL * (centre[:, None, :] - t)
    cube = np.repeat(job_cube[job], 4)
    x = cell_lower[cube] + (pulled.reshape(-1, 3) + 1.0) * scale[cube, None]
    phi = _distance(signed_distance, x)
    expect = np.repeat(job_truth[job], 4) == 1
    bad = (np.abs(phi) > _AFFINE * half[cube]) & ((phi > 0.0) != expect)
    return np.bincount(cube[bad], minlength=len(half)) == 0


def _local(points, cell_lower, scale):
    return (points - cell_lower[:, None]) / scale[:, None, None] - 1.0


def _in_cube(t, lo, width):
    eps = 1e-12 * width[:, None]
    low, high = lo[:, None] - eps[..., None], (lo + width[:, None])[:, None] + eps[..., None]
    inside = np.ones(t.shape[:-1], dtype=bool)
    for k in range(t.shape[-1]):  # axis by axis: faster than .all(axis=-1) over three entries
        inside &= (t[..., k] >= low[..., k]) & (t[..., k] <= high[..., k])
    return inside


def _signs_agree(pts, phi, normal, offset, truth, cell_lower, scale, lo, width, half):
    """Whether the model's inside (the truth of each point's piece) is the distance's sign at
    every stencil point in the cube clear of the planes and of the zero set."""
    t = _local(pts.reshape(len(lo), -1, 3), cell_lower, scale)
    values = t @ normal.transpose(0, 2, 1) + offset[:, None, :]  # matrix products: einsum is 10x slower
    tol = _AFFINE * half / scale
    index, clear = _pattern(values, tol[:, None])
    model = np.take_along_axis(truth, index, axis=1)
    f = phi.reshape(len(lo), -1)
    check = _in_cube(t, lo, width) & clear & (np.abs(f) > _AFFINE * half[:, None]) & (model >= 0)
    return ~(check & (model != (f > 0.0))).any(axis=1)


def _zero_on_boundary(signed_distance, samples, normal, offset, truth, cell_lower, scale, lo, width, half):
    """Whether the distance vanishes at the samples projected on each plane where the pieces on
    its two sides (both non-empty) differ."""
    q, n, k = len(lo), samples.shape[1], normal.shape[1]
    t = _local(samples, cell_lower, scale)  # (q, n, 3)
    values = t @ normal.transpose(0, 2, 1) + offset[:, None, :]
    proj = t[:, :, None, :] - values[..., None] * normal[:, None, :, :]  # (q, n, k, 3) on plane i
    at = (proj.reshape(q, -1, 3) @ normal.transpose(0, 2, 1)).reshape(q, n, k, k) + offset[:, None, None, :]
    own = np.eye(k, dtype=bool)[None, None]
    at = np.where(own, 1.0, at)
    index, _ = _pattern(at, 0.0)
    flipped = index | (1 << np.arange(k))[None, None, :]
    a = np.take_along_axis(truth, index.reshape(q, -1), axis=1).reshape(q, n, k)
    b = np.take_along_axis(truth, flipped.reshape(q, -1), axis=1).reshape(q, n, k)
    used = (np.abs(normal).sum(axis=-1) > 0.0)[:, None, :]
    boundary = used & (a >= 0) & (b >= 0) & (a != b) & _in_cube(proj.reshape(q, -1, 3), lo, width).reshape(q, n, k)
    cube, sample, plane = np.nonzero(boundary)
    if len(cube) == 0:
        return np.ones(q, dtype=bool)
    x = cell_lower[cube] + (proj[cube, sample, plane] + 1.0) * scale[cube, None]
    bad = np.abs(_distance(signed_distance, x)) > _ZERO * half[cube]
    return np.bincount(cube[bad], minlength=q) == 0
