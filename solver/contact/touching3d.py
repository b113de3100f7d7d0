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

from .ellipse_geometry import ContactFrame3D, contact_frame_3d, sectors, surface_point, surrounds

__all__ = ["touching_frame_3d", "TOUCH_ROUNDS"]

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
