"""Compiled kernels of a CAD body's tessellation queries (numba, the ``fast`` extra): the
generalised winding number of points (over every triangle, or by the box hierarchy of
:mod:`geometry.solids.winding_tree`), their distance to candidate triangles and their nearest
point on a polyline, point by point in registers instead of (point, triangle) array
temporaries. The arithmetic is that of the numpy paths in :mod:`geometry.solids.part_solid`
(``_winding``, ``point_triangle_distance``) and :mod:`geometry.solids.face_trim`
(``_nearest_on_polyline``), so the two agree to round-off. Imported only by
:func:`geometry.solids.mesh_jit.mesh_kernels` (never by ``import geometry``); each kernel works
on a range of the points (or on the points given) and releases the GIL, so
:func:`geometry._jit.run_ranges` spreads one call over the cores."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

jit = njit(cache=True, nogil=True, fastmath=False, error_model="numpy")


@jit
def _triangle_distance(px, py, pz, t):
    """Distance from the point to triangle t (3, 3): the foot in the plane where it falls
    inside, else the nearest of the three edges."""
    ax, ay, az = t[0, 0], t[0, 1], t[0, 2]
    bx, by, bz = t[1, 0], t[1, 1], t[1, 2]
    cx, cy, cz = t[2, 0], t[2, 1], t[2, 2]
    e1x, e1y, e1z = bx - ax, by - ay, bz - az
    e2x, e2y, e2z = cx - ax, cy - ay, cz - az
    nx, ny, nz = e1y * e2z - e1z * e2y, e1z * e2x - e1x * e2z, e1x * e2y - e1y * e2x
    nn = max(nx * nx + ny * ny + nz * nz, 1e-300)
    h = ((px - ax) * nx + (py - ay) * ny + (pz - az) * nz) / nn
    qx, qy, qz = px - h * nx, py - h * ny, pz - h * nz
    inside = True
    best = math.inf
    for k in range(3):
        ux, uy, uz = t[k, 0], t[k, 1], t[k, 2]
        vx, vy, vz = t[(k + 1) % 3, 0], t[(k + 1) % 3, 1], t[(k + 1) % 3, 2]
        ex, ey, ez = vx - ux, vy - uy, vz - uz
        wx, wy, wz = qx - ux, qy - uy, qz - uz
        side = (ey * wz - ez * wy) * nx + (ez * wx - ex * wz) * ny + (ex * wy - ey * wx) * nz
        if not side >= 0.0:
            inside = False
        ee = max(ex * ex + ey * ey + ez * ez, 1e-300)
        s = min(max(((px - ux) * ex + (py - uy) * ey + (pz - uz) * ez) / ee, 0.0), 1.0)
        dx, dy, dz = px - ux - s * ex, py - uy - s * ey, pz - uz - s * ez
        best = min(best, math.sqrt(dx * dx + dy * dy + dz * dz))
    if inside:
        return abs(h) * math.sqrt(nn)
    return best


@jit
def nearest_of_range(points, idx, tri, out, lo, hi):
    """out[i] = the smallest distance from points[i] to the triangles tri[idx[i]], i in [lo, hi)."""
    for i in range(lo, hi):
        best = math.inf
        for j in range(idx.shape[1]):
            best = min(best, _triangle_distance(points[i, 0], points[i, 1], points[i, 2], tri[idx[i, j]]))
        out[i] = best


@jit
def winding_range(points, tri, out, lo, hi):
    """out[i] = the sum over the oriented triangles of their solid angles seen from points[i]
    (Van Oosterom and Strackee's formula), i in [lo, hi)."""
    for i in range(lo, hi):
        total = 0.0
        for j in range(tri.shape[0]):
            total += _solid_angle(points[i, 0], points[i, 1], points[i, 2], tri[j])
        out[i] = total


@jit
def _solid_angle(px, py, pz, t):
    """Twice the arctangent of Van Oosterom and Strackee: the solid angle of triangle t (3, 3)
    seen from the point (the arithmetic of :func:`winding_range`)."""
    ax, ay, az = t[0, 0] - px, t[0, 1] - py, t[0, 2] - pz
    bx, by, bz = t[1, 0] - px, t[1, 1] - py, t[1, 2] - pz
    cx, cy, cz = t[2, 0] - px, t[2, 1] - py, t[2, 2] - pz
    la = math.sqrt(ax * ax + ay * ay + az * az)
    lb = math.sqrt(bx * bx + by * by + bz * bz)
    lc = math.sqrt(cx * cx + cy * cy + cz * cz)
    det = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
    den = (la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la
           + (cx * ax + cy * ay + cz * az) * lb)
    return 2.0 * math.atan2(det, den)


@jit
def tree_winding_range(points, tri, cone, lo_box, hi_box, child, span, cone_span, stack_size, out, lo, hi):
    """out[i] = the solid angle of the tessellation seen from points[i], i in [lo, hi), by the
    box hierarchy of :class:`geometry.solids.winding_tree.WindingTree`: a node's cone where the
    point lies outside its box and the node has one, else its children, or a leaf's triangles."""
    stack = np.empty(stack_size, np.int64)
    for i in range(lo, hi):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        total = 0.0
        stack[0] = 0
        top = 1
        while top > 0:
            top -= 1
            k = stack[top]
            outside = (px < lo_box[k, 0] or px > hi_box[k, 0] or py < lo_box[k, 1] or py > hi_box[k, 1]
                       or pz < lo_box[k, 2] or pz > hi_box[k, 2])
            if outside and cone_span[k, 0] >= 0:
                for j in range(cone_span[k, 0], cone_span[k, 1]):
                    total += _solid_angle(px, py, pz, cone[j])
            elif child[k, 0] < 0:
                for j in range(span[k, 0], span[k, 1]):
                    total += _solid_angle(px, py, pz, tri[j])
            else:
                stack[top] = child[k, 1]
                stack[top + 1] = child[k, 0]
                top += 2
        out[i] = total


@jit
def nearest_on_polyline(points, line, foot, best, segment):
    """For each point: the nearest point of the polyline (foot), its distance (best) and the
    index of the segment it lies on (the first of equally near ones), segment by segment as
    :func:`geometry.solids.face_trim._nearest_on_polyline`."""
    for i in range(points.shape[0]):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        b = math.inf
        for j in range(line.shape[0] - 1):
            ux, uy, uz = line[j, 0], line[j, 1], line[j, 2]
            ex, ey, ez = line[j + 1, 0] - ux, line[j + 1, 1] - uy, line[j + 1, 2] - uz
            t = ((px - ux) * ex + (py - uy) * ey + (pz - uz) * ez) / max(ex * ex + ey * ey + ez * ez, 1e-300)
            t = min(max(t, 0.0), 1.0)
            xx, xy, xz = ux + t * ex, uy + t * ey, uz + t * ez
            dx, dy, dz = px - xx, py - xy, pz - xz
            d = math.sqrt(dx * dx + dy * dy + dz * dz)
            if d < b:
                b = d
                foot[i, 0], foot[i, 1], foot[i, 2] = xx, xy, xz
                segment[i] = j
        best[i] = b


@jit
def box_gaps(points, lo, hi, out):
    """out[b, i]: the distance from point i to box b (lower corners lo (m, 3), upper hi (m, 3));
    0 inside. The arithmetic of ``np.linalg.norm(p - np.clip(p, lo, hi), axis=1)``, box by box
    and point by point, without the (boxes, points, 3) temporaries."""
    for b in range(lo.shape[0]):
        lx, ly, lz = lo[b, 0], lo[b, 1], lo[b, 2]
        ux, uy, uz = hi[b, 0], hi[b, 1], hi[b, 2]
        for i in range(points.shape[0]):
            px, py, pz = points[i, 0], points[i, 1], points[i, 2]
            dx = px - min(max(px, lx), ux)
            dy = py - min(max(py, ly), uy)
            dz = pz - min(max(pz, lz), uz)
            out[b, i] = math.sqrt(dx * dx + dy * dy + dz * dz)
