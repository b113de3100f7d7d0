"""The shape of body 1's contact face about the contact point, read before any solve: where the
face is present along rays from the point, and where the line of a line contact runs.

A flat contact's region and a line contact's region are star-shaped about the contact point
(solver.contact.star_region): each ray from the point meets the region's edge once, and the
region ends where the ray first leaves body 1's face (a free edge). Two faces break this:

- a flat face that is **not star-shaped about the point**: a ray leaves the face and enters it
  again within the candidate region (a washer's annulus or any face with a hole, seen across
  the hole; a non-convex outline such as an L-shaped punch, seen across its notch; a blind hole
  or a groove, whose floor lies above the face). Read on the rays' samples: a sample on the face
  after one off it (``on_face``: body 1's surface within RECESS_CELLS of the tangent plane;
  ``resumed_rays``);
- a line contact whose **line curves** (a ring or a torus on a flat: its touching line is a
  circle, which closes on itself): the coordinates of the region run along a straight line
  through the point. Read from the valley of the gap: at stations t along axis 0, the offset
  c(t) across the line (axis 1) where the gap between the bodies is least, found by Newton on
  three samples across (the gap across is quadratic about the valley, so they place it to
  round-off); c(t) = c0 + c1 t + kappa t^2 / 2 fitted by least squares tells a straight line
  (kappa 0: a roller, straight or tilted) from a bent one, whose curvature in the tangent plane
  is then 1 / R of the circle fitted through the points (t, c(t)) (``line_bend``): a torus's
  circle of radius R.
"""

from __future__ import annotations

import math

import numpy as np

from .ellipse_geometry import surface_point

__all__ = ["face_rays", "on_face", "resumed_rays", "line_bend", "RECESS_CELLS", "STATIONS", "BEND_CELLS",
           "ROUND_OFF_BEND"]

#: samples along each ray of the candidate region (the first is at 1/SAMPLES of its radius)
SAMPLES = 48
#: a flat face's sample whose surface lies more than this many finest cells from the tangent
#: plane is off the face (a recess: a blind hole's floor, a groove); a fillet or a chamfer rises
#: away from the face once and never comes back, a recess does
RECESS_CELLS = 0.05
#: Newton steps of the valley's offset at a station
VALLEY_STEPS = 6
#: stations along a line contact's line on either side of the point where its valley is read
STATIONS = 8
#: a line contact whose line departs from its chord by more than this many finest cells over
#: its length (its sagitta, kappa L^2 / 2 for the half-length L) is refused: the region's sides
#: are read across a straight line, and a half-width of a few cells would be bent by a share
#: of itself
BEND_CELLS = 0.25
#: a sagitta over the candidate region below this share of the finest cell is the valley's
#: round-off (a straight roller reads 1e-11 of the cell)
ROUND_OFF_BEND = 1e-6


def face_rays(solid1, frame, reach: float, extent: float,
              rays: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(psi (rays,), t (SAMPLES,), ok (rays, SAMPLES), height (rays, SAMPLES)): the directions
    psi of the tangent plane (from axis 0 towards axis 1), the distances t of the samples along
    each ray (up to ``extent``), whether body 1 has surface above each sample (within ``reach``
    along the normal), and that surface's height above the tangent plane (along the normal, into
    body 1; inf where there is none)."""
    psi = np.linspace(0.0, 2.0 * math.pi, rays, endpoint=False)
    direction = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    t = np.linspace(0.0, extent, SAMPLES + 1)[1:]
    s = (t[None, :, None] * direction[:, None, :]).reshape(-1, 2)
    x1, ok = surface_point(solid1, frame, s, reach)
    height = np.where(ok, (x1 - frame.point) @ frame.normal, math.inf)
    return psi, t, ok.reshape(len(psi), len(t)), height.reshape(len(psi), len(t))


def on_face(ok: np.ndarray, height: np.ndarray, h: float) -> np.ndarray:
    """Where the samples lie on the flat face itself: body 1 has surface there within
    RECESS_CELLS finest cells ``h`` of the tangent plane (a pocket's floor or a groove's bottom
    further up is not the face)."""
    return ok & (np.abs(height) <= RECESS_CELLS * h)


def resumed_rays(t: np.ndarray, ok: np.ndarray, inside: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(resumed (rays,), leaves (rays,), returns (rays,)): the rays (among ``inside``) on which
    body 1's face, after its first missing sample, has surface again further out; the distance of
    the last sample with surface before the gap (0 where the first sample has none) and of the
    first sample with surface after it (inf on the other rays)."""
    missing = ~ok
    first = np.where(missing.any(axis=1), np.argmax(missing, axis=1), ok.shape[1])
    after = np.arange(ok.shape[1])[None, :] > first[:, None]
    again = ok & after
    resumed = inside & again.any(axis=1)
    leaves = np.where(first > 0, t[np.maximum(first - 1, 0)], 0.0)
    returns = np.where(resumed, t[np.argmax(again, axis=1)], math.inf)
    return resumed, leaves, returns


def _valley(solid1, solid2, frame, reach: float, t: np.ndarray, d: float, most: float) -> tuple[np.ndarray, np.ndarray]:
    """(offset (m,), ok (m,)): at the stations t along axis 0, the offset across the line (along
    axis 1) of the gap's least value, by Newton steps (at most ``most`` each) on the parabola
    through the gap at the offset and +-d across it; ok where body 1 has surface at every sample,
    the gap curves up across the line and the last step is below a thousandth of d."""
    c = np.zeros(len(t))
    ok = np.ones(len(t), dtype=bool)
    step = np.full(len(t), np.inf)
    for _ in range(VALLEY_STEPS):
        s = np.stack([np.repeat(t, 3), (c[:, None] + np.array([-d, 0.0, d])[None, :]).ravel()], axis=1)
        x1, has = surface_point(solid1, frame, s, reach)
        gap = -np.asarray(solid2.signed_distance(x1), dtype=float).reshape(len(t), 3)
        bend = gap[:, 0] - 2.0 * gap[:, 1] + gap[:, 2]
        ok &= has.reshape(len(t), 3).all(axis=1) & (bend > 0.0)
        step = 0.5 * d * (gap[:, 0] - gap[:, 2]) / np.where(bend > 0.0, bend, 1.0)
        step = np.clip(step, -most, most)
        c = np.where(ok, c + step, c)
    return c, ok & (np.abs(step) <= 1e-3 * d)


def line_bend(solid1, solid2, frame, reach: float, length: float, h: float) -> tuple[float, float] | None:
    """(kappa, span): the curvature (1/m) in the tangent plane of the valley of the gap along
    axis 0 (the line of a line contact) over the stations within ``length`` of the point on
    both sides where body 1 has surface, and the largest |t| of those stations; None where fewer
    than three stations have a valley. ``h``: the finest cell (the samples across are a tenth of
    it apart)."""
    t = length * np.concatenate([-np.arange(STATIONS, 0, -1), np.arange(0, STATIONS + 1)]) / STATIONS
    c, ok = _valley(solid1, solid2, frame, reach, t, 0.1 * h, 0.1 * length)
    if int(ok.sum()) < 3:
        return None
    design = np.stack([np.ones(int(ok.sum())), t[ok], 0.5 * t[ok] ** 2], axis=1)
    kappa = float(np.linalg.lstsq(design, c[ok], rcond=None)[0][2])
    span = float(np.abs(t[ok]).max())
    if 0.5 * abs(kappa) * span**2 > 1e-9 * span:  # a bend: the circle through the valley's points
        kappa = math.copysign(1.0 / _circle_radius(t[ok], c[ok]), kappa)
    return kappa, span


def _circle_radius(x: np.ndarray, y: np.ndarray) -> float:
    """The radius of the circle x^2 + y^2 + D x + E y + F = 0 fitted to the points (x, y) by least
    squares (Kasa's fit: exact for points on a circle, where the quadratic's curvature is not: a
    ring of radius 0.5 read over +-0.28 m gave 0.458)."""
    D, E, F = np.linalg.lstsq(np.stack([x, y, np.ones(len(x))], axis=1), -(x**2 + y**2), rcond=None)[0]
    return float(math.sqrt(max(0.25 * (D * D + E * E) - F, 0.0)))
