"""Profiles of a 3D contact with friction history along its principal axes through the region's
centre: the state kept on the region's quadrature points (pressure, shear, zone, slip) read on
evenly spaced samples of each axis line, as the 2D contact records it on its sample chords. The
samples are fixed for the run (over the candidate region's reach on each side of the centre), so
that the steps' profiles line up when the normal load moves the region.

A sample's value is the mean over the quadrature points of a bin about it: the points within
half the samples' spacing along the axis and within STRIP_CELLS of a cell across it, weighted by
their areas on the tangent plane (the point tractions oscillate with the grid; a bin's mean
holds a dozen points). A bin without points (beyond the region, or on the missing side of a
symmetric model's sector) is not ``inside`` and holds zeros.

Vectors are given by their components along the loop's direction (the contact's first axis:
``shear``, ``slip_increment``, ``tangential_jump``) and across it (the second axis: the same
names with ``_across``). ``zone`` is 0 where every point of the bin sticks and the slipping
share of its area otherwise, signed by the slip's direction along the first axis (+1: the first
body slips on the second along +axes[0]).
"""

from __future__ import annotations

import numpy as np

__all__ = ["axis_profiles", "PROFILE_SAMPLES", "STRIP_CELLS"]

#: samples per half axis (each axis line has 2 PROFILE_SAMPLES + 1 samples over the region's width)
PROFILE_SAMPLES = 32
#: a bin reaches this share of a cell on each side of its axis line
STRIP_CELLS = 0.25


def _bins(local: np.ndarray, reach: float, cell: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(axis, s, bin of each point (q,) per axis line) for the samples of both axes."""
    axis, s, member, offset = [], [], [], 0
    for k, extent in enumerate((reach, reach)):
        r = np.linspace(-extent, extent, 2 * PROFILE_SAMPLES + 1)
        spacing = r[1] - r[0]
        near = np.abs(local[:, 1 - k]) <= STRIP_CELLS * cell
        j = np.rint((local[:, k] + extent) / spacing).astype(np.int64)
        member.append(np.where(near & (j >= 0) & (j < len(r)), offset + j, -1))
        axis.append(np.full(len(r), k))
        s.append(r)
        offset += len(r)
    return np.concatenate(axis), np.concatenate(s), np.stack(member)


def axis_profiles(local: np.ndarray, weights: np.ndarray, reach: float, cell: float, frame, centre: np.ndarray,
                  state: dict) -> dict:
    """The profiles along both axes (see the module's docstring).

    ``local`` (q, 2): the points' tangent-plane coordinates from the region's centre; ``weights``
    (q,): their areas on the tangent plane; ``reach``: the samples' half-length on each axis;
    ``cell``: the cell size at the contact; ``frame``: the contact's frame (point, normal, axes);
    ``centre`` (2,): the region's centre on the tangent plane; ``state``: per point the pressure
    (q,), shear, slip_increment, tangential_jump (q, 3), slip (q,) bool, direction (q, 3),
    accumulated_slip (q,) and the matched points on body 2, points (q, 3)."""
    axis, s, member = _bins(local, reach, cell)
    n = len(s)
    axes = np.asarray(frame.axes, dtype=float)
    columns = {"pressure": state["pressure"], "accumulated_slip": state["accumulated_slip"]}
    for name in ("shear", "slip_increment", "tangential_jump"):
        columns[name] = state[name] @ axes[0]
        columns[name + "_across"] = state[name] @ axes[1]
    sign = np.where(state["direction"] @ axes[0] >= 0.0, 1.0, -1.0)
    columns["zone"] = np.where(state["slip"], sign, 0.0)
    columns["points"] = state["points"]
    total = np.zeros(n)
    sums = {k: np.zeros((n,) + np.shape(v)[1:]) for k, v in columns.items()}
    for row in member:
        ok = row >= 0
        w = weights[ok]
        total += np.bincount(row[ok], weights=w, minlength=n)
        for k, v in columns.items():
            v = np.asarray(v, dtype=float)[ok]
            if v.ndim == 1:
                sums[k] += np.bincount(row[ok], weights=w * v, minlength=n)
            else:
                sums[k] += np.column_stack([np.bincount(row[ok], weights=w * v[:, j], minlength=n)
                                            for j in range(v.shape[1])])
    inside = total > 0.0
    out = {k: np.where(inside.reshape((n,) + (1,) * (v.ndim - 1)), v / np.where(total > 0.0, total, 1.0).reshape(
        (n,) + (1,) * (v.ndim - 1)), 0.0) for k, v in sums.items()}
    line = np.asarray(frame.point, float) + (np.asarray(centre, float) @ axes)[None, :] + s[:, None] * axes[axis]
    out["points"] = np.where(inside[:, None], out["points"], line)
    out.update(s=s, axis=axis, inside=inside, normal=np.tile(np.asarray(frame.normal, float), (n, 1)))
    return out
