"""The touching point of two solids nearest a given point (3D; the 2D counterpart is
:func:`solver.contact.geometry.touching_point`).

A scene's contact ``point`` need not be where the two surfaces touch. The contact frame takes the
normal of body 2 at the point of body 2 closest to it, so a point off the touching point by d tilts
the normal by about d / R2 on a curved body 2, and the ellipse is laid on a tilted tangent plane
(measured: a full ball on a ball, the point 0.011 m off with a = 0.031 m, the same grid: the normal
0.64 degrees off, b -0.014 %, N -0.008 %). Here the point moves to where body 2's signed distance is
greatest over body 1's surface (zero where the bodies touch, positive where they overlap): a
stationary point of the overlap phi_2(x_1(s)) over the tangent-plane coordinates s.

Newton in the tangent plane: the overlap's gradient by central differences of body 1's surface
points at +-step along the frame's axes, its Hessian minus the frame's relative curvature
(diag(k0, k1) in the axes' basis: the overlap of two surfaces is -1/2 s^T K s about their
touching point), the frame rebuilt at every new point. Only where body 1 has surface all around
the point: a symmetric model's point lies on its symmetry planes, where the touching point is by
symmetry.
"""

from __future__ import annotations

import numpy as np

from .ellipse_geometry import (ContactFrame3D, closest_on, contact_frame_3d, sectors, surface_point, surrounds,
                               tangent_basis)

__all__ = ["touching_frame_3d", "closest_points_3d", "TOUCH_ROUNDS"]

#: Newton rounds at most
TOUCH_ROUNDS = 8
#: a round moving the point by less than this share of the finest cell ends the search
TOUCH_TOLERANCE = 1e-7


def touching_frame_3d(solid1, solid2, point: np.ndarray, scale: float, reach: float,
                      tangential_direction: np.ndarray | None = None):
    """(frame, moved, ranges): the contact frame at the touching point nearest ``point``
    (``scale``: the finest cell, ``reach``: how far along the normal body 1's surface is looked
    for), whether the point moved, and body 1's angular ranges around the frame's point
    (:func:`sectors` at half a cell, which the contact uses too). The given point's frame where
    the refinement does not apply: body 1 not all around it, a relative curvature that is not
    positive (no isolated touching point), or an overlap that does not grow along the Newton
    steps."""
    frame = contact_frame_3d(solid1, solid2, np.asarray(point, dtype=float), scale, tangential_direction)
    ranges = sectors(solid1, frame, 0.5 * scale, reach)
    if not surrounds(ranges):
        return frame, False, ranges
    frame, moved = _newton(solid1, solid2, frame, scale, reach, tangential_direction)
    return frame, moved, sectors(solid1, frame, 0.5 * scale, reach) if moved else ranges


def _newton(solid1, solid2, frame: ContactFrame3D, scale: float, reach: float, tangential_direction):
    """(frame, moved) of the Newton steps towards the overlap's maximum from ``frame``."""
    step = 1e-2 * scale
    moved = False
    for _ in range(TOUCH_ROUNDS):
        k0, k1 = frame.curvatures
        if not (k0 > 0.0 and k1 > 0.0):
            break
        gradient, overlap0 = _overlap_gradient(solid1, solid2, frame, step, reach)
        if gradient is None:
            break
        s = gradient / np.array([k0, k1])  # the overlap's maximum: -K s + gradient = 0
        length = float(np.hypot(*s))
        if length <= TOUCH_TOLERANCE * scale:
            break
        s *= min(1.0, 0.25 * reach / length)  # never more than a quarter of the reach at once
        x1, ok = surface_point(solid1, frame, s[None], reach)
        if not ok[0] or float(np.asarray(solid2.signed_distance(x1))[0]) < overlap0 - 1e-12 * reach:
            break  # the overlap does not grow: keep the last point
        frame = contact_frame_3d(solid1, solid2, x1[0], scale, tangential_direction)
        moved = True
    return frame, moved


def _overlap_gradient(solid1, solid2, frame: ContactFrame3D, step: float, reach: float):
    """(gradient (2,) of phi_2 over body 1's surface along the frame's axes, the overlap at the
    frame's point), or (None, None) where body 1's surface is missing around the point."""
    s = np.array([[0.0, 0.0], [step, 0.0], [-step, 0.0], [0.0, step], [0.0, -step]])
    x1, ok = surface_point(solid1, frame, s, reach)
    if not ok.all():
        return None, None
    phi = np.asarray(solid2.signed_distance(x1), dtype=float)
    gradient = np.array([phi[1] - phi[2], phi[3] - phi[4]]) / (2.0 * step)
    return gradient, float(phi[0])


#: alternating projections of the closest-point search before its Newton steps
PROJECTION_ROUNDS = 20
#: Newton rounds of the closest-point search at most
CLOSEST_ROUNDS = 30


def closest_points_3d(solid1, solid2, start: np.ndarray, size: float) -> np.ndarray:
    """The midpoint of the two solids' closest points (the touching point of touching solids, the
    deepest point of overlapping ones) from ``start`` (``size``: the scene's element size).

    Alternating exact projections bring the point onto both surfaces near the contact; they alone
    converge sublinearly for surfaces that touch tangentially (each round moves a point at
    distance d from the touching point by about d^3 / (4 R^2)). Newton steps then find the
    maximum of body 2's signed distance phi_2 over body 1's surface (zero at a touching point,
    positive where the bodies overlap): its gradient and Hessian over the tangent-plane
    coordinates of body 1's surface by central differences, a step along the directions where
    phi_2 curves down, halved until phi_2 grows. A step leaving body 1's surface (a symmetric
    model's symmetry plane, a free edge) stops at the surface's edge, found by bisection: the
    closest point of a symmetric model lies on its symmetry plane."""
    x = np.asarray(start, dtype=float).reshape(3)
    step = 1e-6 * size
    for _ in range(PROJECTION_ROUNDS):
        x1, _ = closest_on(solid1, x[None], step)
        x2, _ = closest_on(solid2, x1, step)
        new = 0.5 * (x1[0] + x2[0])
        if np.linalg.norm(new - x) <= 1e-12 * size:
            break
        x = new
    x1 = closest_on(solid1, x[None], step)[0][0]
    for _ in range(CLOSEST_ROUNDS):
        frame = _surface_frame(solid1, x1, step)
        s = _newton_step(solid1, solid2, frame, size)
        if s is None:
            break
        x1 = surface_point(solid1, frame, s[None], size)[0][0]
        if float(np.hypot(*s)) <= 1e-9 * size:
            break
    x2 = closest_on(solid2, x1[None], step)[0][0]
    return 0.5 * (x1 + x2)


def _surface_frame(solid, x1: np.ndarray, step: float) -> ContactFrame3D:
    """A frame on a solid's surface at x1: its normal into the solid (the direction
    :func:`surface_point` looks along), any tangent axes."""
    _, n1 = closest_on(solid, x1[None], step, sweeps=1)
    normal = -n1[0]
    axes = tangent_basis(normal, None)
    return ContactFrame3D(point=x1, normal=normal, axes=axes, curvatures=np.zeros(2))


def _newton_step(solid1, solid2, frame: ContactFrame3D, size: float) -> np.ndarray | None:
    """The tangent-plane step (2,) towards the maximum of phi_2 over body 1's surface, or None
    where there is none (phi_2 flat or stationary, body 1's surface missing around the point)."""
    d = 1e-3 * size
    grid = np.array([(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)], dtype=float) * d
    x, ok = surface_point(solid1, frame, grid, size)
    if not ok.all():
        return None
    f = np.asarray(solid2.signed_distance(x), dtype=float).reshape(3, 3)
    gradient = np.array([f[2, 1] - f[0, 1], f[1, 2] - f[1, 0]]) / (2.0 * d)
    hessian = np.array([[f[2, 1] + f[0, 1] - 2.0 * f[1, 1], 0.25 * (f[2, 2] - f[2, 0] - f[0, 2] + f[0, 0])],
                        [0.0, f[1, 2] + f[1, 0] - 2.0 * f[1, 1]]]) / d**2
    hessian[1, 0] = hessian[0, 1]
    values, vectors = np.linalg.eigh(hessian)
    scale = float(np.abs(values).max())
    if not scale > 0.0:
        return None
    down = values < -1e-6 * scale  # phi_2 curves down: Newton; flat or up: no step
    g = vectors.T @ gradient
    s = vectors @ np.where(down, -g / np.where(down, values, 1.0), 0.0)
    length = float(np.hypot(*s))
    if not length > 0.0:
        return None
    s *= min(1.0, size / length)  # at most one element per round
    return _accepted(solid1, solid2, frame, s, float(f[1, 1]), size)


def _accepted(solid1, solid2, frame: ContactFrame3D, s: np.ndarray, f0: float, size: float) -> np.ndarray | None:
    """The step s, or the part of it on body 1's surface (the surface's edge by bisection), halved
    until phi_2 does not fall; None where no part of it helps."""
    x, ok = surface_point(solid1, frame, s[None], size)
    if not ok[0]:
        lo, hi = 0.0, 1.0  # surface at lo, none at hi
        for _ in range(45):
            mid = 0.5 * (lo + hi)
            if surface_point(solid1, frame, (mid * s)[None], size)[1][0]:
                lo = mid
            else:
                hi = mid
        s = lo * s
    for _ in range(30):
        x, ok = surface_point(solid1, frame, s[None], size)
        if ok[0] and float(np.asarray(solid2.signed_distance(x), dtype=float)[0]) >= f0 - 1e-14 * size:
            return s
        s = 0.5 * s
    return None
