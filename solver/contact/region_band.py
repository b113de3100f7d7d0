"""Where the refinement that follows a line contact's region puts its balls, read off the coarse
pass's region (a contact block of summary.json: its point, axes and boundary polyline).

- The **band**: balls centred on the line through the contact point, spread over the region's
  extent along it at most one radius apart, of radius the region's half-width plus a margin (the
  coarse region's uncertainty), at the scene's levels.
- **Where the edge turns**: the stretches along the line where the region's smooth edge runs at
  more than TURNING_SLOPE to the line (its half-width changes by more than that per unit length:
  a crowned roller's ends, where the width falls to zero, and next to them the bulge by the
  crown's junction) get balls one level finer about the edge. A stretch is widened by the margin
  along the line on both sides; its balls are centred on the edge and reach the margin (where the
  edge may lie) plus the window the edge condition reads inside it. The edge on body 1's free
  edges and next to them (within the margin) is left out: there the region ends at the body's
  corner (complete contact), its width does not follow the pressure, and the pressure is
  singular, so finer cells there only raise the end's peak.
- **About a pressure peak next to where the edge turns** (peak_balls): a ball one level finer,
  of the turning balls' radius, centred where the coarse pass's pressure peaks within a ball's
  radius of a turning stretch (a crowned roller's end peak lies just before its end narrows), so
  that the finer cells' border does not cross the peak (a border through the top of a peak lifts
  it and moves it by several millimetres onto the coarser side).
- **Along the straight sides** (side_balls): thinner balls one level finer on the rest of the
  smooth edge, away from the free edges, where the band's cells are too coarse for the width
  (the caller decides where).
"""

from __future__ import annotations

import math

import numpy as np

from .region_report import mirror_images, peak_place

__all__ = ["TURNING_SLOPE", "band_balls", "ellipse_band_balls", "turning_balls", "peak_balls", "side_balls", "region_edge",
           "turning_stretches", "symmetry_maps"]

#: the smooth edge's slope to the line (the half-width's change per unit length) beyond which the
#: region's edge is refined one level more (tan 14 degrees)
TURNING_SLOPE = 0.25


def region_edge(block: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (n, 2) of the boundary polyline in the frame's tangent axes, from the contact
    point; per segment i (points i to i + 1, closed): whether it is smooth edge; per point:
    on body 1's free edge). The segments that start or end at the contact point are a symmetric
    model's cuts along its symmetry planes, not edge."""
    point, axes = np.asarray(block["point"], float), np.asarray(block["axes"], float)
    xy = (np.asarray(block["boundary"]["points"], float) - point) @ axes[:2].T
    free = np.asarray(block["boundary"].get("free_edge", [False] * len(xy)), bool)
    nxt = np.roll(np.arange(len(xy)), -1)
    scale = float(np.abs(xy).max()) if len(xy) else 0.0
    centre = np.hypot(xy[:, 0], xy[:, 1]) <= 1e-9 * max(scale, 1e-300)
    smooth = ~(free | free[nxt] | centre | centre[nxt])
    return xy, smooth, free


def band_balls(block: dict, margin: float) -> tuple[np.ndarray, float]:
    """(centres (k,) along the line from the contact point, radius) of the band over the whole
    region: its half-width plus ``margin``, its centres at most a radius apart."""
    xy, _, _ = region_edge(block)
    radius = float(np.abs(xy[:, 1]).max()) + margin
    lo, hi = float(xy[:, 0].min()), float(xy[:, 0].max())
    count = max(2, int(math.ceil((hi - lo) / radius)) + 1)
    return np.linspace(lo, hi, count), radius


def ellipse_band_balls(block: dict, margin: float) -> tuple[np.ndarray, float]:
    """(centres (k, 2) in the tangent plane's coordinates along the frame's axes from the contact
    point, radius) of the band over an elliptical region (an elongated point contact's summary
    block): its short semi-axis plus ``margin``, its centres on the long axis through the
    ellipse's centre at most a radius apart, from end to end of the long semi-axis plus the
    margin."""
    a, b = (float(v) for v in block["semi_axes"])
    centre = np.asarray(block.get("region_centre") or [0.0, 0.0], float)
    radius = b + margin
    reach = a + margin
    count = max(2, int(math.ceil(2.0 * reach / radius)) + 1)
    along = np.linspace(-reach, reach, count)
    return centre + np.c_[along, np.zeros(count)], radius


def turning_stretches(block: dict, margin: float) -> list[tuple[float, float, float]]:
    """The stretches (start, end along the line, widest half-width there) where the smooth edge
    runs at more than TURNING_SLOPE to the line, each widened by ``margin`` along it on both
    sides and merged where they overlap; the edge within ``margin`` of a free edge left out."""
    xy, smooth, free = region_edge(block)
    nxt = np.roll(np.arange(len(xy)), -1)
    d = xy[nxt] - xy
    steep = smooth & (np.abs(d[:, 1]) > TURNING_SLOPE * np.abs(d[:, 0]))
    if free.any():
        near = np.hypot(*(xy[:, None, :] - xy[free][None, :, :]).transpose(2, 0, 1)).min(axis=1) <= margin
        steep &= ~(near | near[nxt])
    if not steep.any():
        return []
    lo = np.minimum(xy[steep, 0], xy[nxt][steep, 0]) - margin
    hi = np.maximum(xy[steep, 0], xy[nxt][steep, 0]) + margin
    order = np.argsort(lo)
    merged: list[list[float]] = []
    for a, b in zip(lo[order], hi[order]):
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
        else:
            merged.append([float(a), float(b)])
    width = np.abs(xy[:, 1])
    out = []
    for a, b in merged:
        inside = (xy[:, 0] >= a) & (xy[:, 0] <= b)
        out.append((a, b, float(width[inside].max()) if inside.any() else float(width.max())))
    return out


def turning_balls(block: dict, margin: float, window: float, reach: float | None = None
                  ) -> list[tuple[np.ndarray, float]]:
    """Per stretch of turning_stretches (widened by ``margin`` along the line): (centres (k, 2) in
    the tangent plane, radius) of balls one level finer along the region's smooth edge there: of
    radius ``reach`` (how far from the coarse edge the edge may lie; ``margin`` if not given) plus
    ``window`` (how far inside it the edge condition reads the pressure), centred on the edge's
    points at most half a radius apart, so that the edge and that much on either side of it are
    covered."""
    xy, smooth, _ = region_edge(block)
    on_edge = smooth | np.roll(smooth, 1)  # a point of a smooth segment
    radius = (margin if reach is None else reach) + window
    out = []
    for a, b, _ in turning_stretches(block, margin):
        centres = _spaced(xy[on_edge & (xy[:, 0] >= a) & (xy[:, 0] <= b)], radius)  # in the polyline's order
        if len(centres):
            out.append((centres, radius))
    return out


def symmetry_maps(block: dict) -> np.ndarray:
    """The tangent-plane maps that rebuild the whole region from a symmetric model's share of it
    (region_report.mirror_images): the sector between the symmetry cuts through the contact
    point, the boundary's segments that leave and reach it, spanning the block's model share of
    the turn; the identity alone for a whole model."""
    xy, _, _ = region_edge(block)
    share = float(block.get("model_share") or 1.0)
    centre = np.flatnonzero(np.hypot(xy[:, 0], xy[:, 1]) <= 1e-9 * max(float(np.abs(xy).max()), 1e-300))
    if not len(centre) or share > 1.0 - 1e-6:
        return np.eye(2)[None]
    after = xy[(centre[0] + 1) % len(xy)]
    t0 = math.atan2(after[1], after[0])
    return mirror_images([(t0, t0 + 2.0 * math.pi * share)])


def peak_balls(block: dict, margin: float, radius: float) -> np.ndarray:
    """(k, 2) centres in the tangent plane of balls one level finer of ``radius`` (the turning
    balls') about the coarse pass's pressure peaks next to the stretches where the edge turns
    (turning_stretches, widened by ``margin``): per stretch, the coarse map's squares within
    ``radius`` of it along the line; where their largest is a peak of the whole map (no square
    within ``radius`` of it higher: not the rise towards a plateau elsewhere), a ball at its place
    (region_report.peak_place: the plateau's centroid, a symmetric model's mirror images
    included). A finer cells' border through a peak's top lifts it and moves it onto the coarser
    side; so the peak and ``radius`` about it lie in the finer cells."""
    squares = block.get("pressure_map") or {}
    if not squares.get("value"):
        return np.zeros((0, 2))
    s, value = np.asarray(squares["s"], float), np.asarray(squares["value"], float)
    area, keys = np.asarray(squares["area"], float), np.asarray(squares["square"])
    maps = symmetry_maps(block)
    images = np.concatenate([s @ m.T for m in maps])
    image_values = np.tile(value, len(maps))
    out: list[np.ndarray] = []
    for a, b, _ in turning_stretches(block, margin):
        near = (s[:, 0] >= a - radius) & (s[:, 0] <= b + radius)
        if not near.any():
            continue
        top = np.flatnonzero(near)[int(np.argmax(value[near]))]
        around = np.hypot(*(images - s[top]).T) <= radius
        if image_values[around].max() > value[top]:
            continue
        place = peak_place(s[near], value[near], area[near], keys[near], float(squares["cell"]), maps)
        if not any(np.hypot(*(place - c)) <= 1e-9 * radius for c in out):
            out.append(place)
    return np.asarray(out).reshape(-1, 2)


def side_balls(block: dict, margin: float, radius: float) -> tuple[np.ndarray, float]:
    """(centres (k, 2) in the tangent plane, ``radius``) of balls one level finer along the
    region's smooth edge outside the stretches where it turns (turning_stretches, widened by
    ``margin``) and more than ``margin`` from body 1's free edges: the straight sides, centred on
    the edge's points at most half a radius apart."""
    xy, smooth, free = region_edge(block)
    on_edge = smooth | np.roll(smooth, 1)
    keep = on_edge.copy()
    for a, b, _ in turning_stretches(block, margin):
        keep &= ~((xy[:, 0] >= a) & (xy[:, 0] <= b))
    if free.any():
        keep &= np.hypot(*(xy[:, None, :] - xy[free][None, :, :]).transpose(2, 0, 1)).min(axis=1) > margin
    return _spaced(xy[keep], radius), radius


def _spaced(points: np.ndarray, radius: float) -> np.ndarray:
    """(k, 2) the ``points`` (in order) kept where none kept before lies within half ``radius``:
    balls of that radius on them cover the points' line and ``radius`` / 2 on either side."""
    centres: list[np.ndarray] = []
    for p in points:
        if not centres or np.hypot(*(np.asarray(centres) - p).T).min() > 0.5 * radius:
            centres.append(p)
    return np.asarray(centres).reshape(-1, 2)
