"""Cut cells of the octree (issue 14): which leaves the boundary of a solid crosses, and the
moments of their inside parts, from the solid's exact signed distance.

First version: adaptive subdivision. A sub-cube whose centre is farther inside than its half
diagonal contributes its exact box moments; one farther outside contributes nothing; the others
are split, down to ``depth`` levels below the cell, where the last ones are cut by the plane of
the linearised distance along its dominant axis (exact for a face-parallel plane): second order
in the finest sub-cube (measured in tests/test_octree.py). Moment fitting by the divergence theorem
over the exact surface pieces (exact to quadrature) replaces it once the solids' faces supply
surface quadrature (the thesis's future scope, docs/formulation.md)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from .hexahedra import CORNERS, box_moments

__all__ = ["INSIDE", "CUT", "OUTSIDE", "classify_cells", "inside_moments"]

INSIDE, CUT, OUTSIDE = 1, 2, 0
_HALF_DIAGONAL = 0.5 * np.sqrt(3.0) * (1.0 + 1e-9)

SignedDistance = Callable[[np.ndarray], np.ndarray]


def classify_cells(lower: np.ndarray, size: np.ndarray, signed_distance: SignedDistance) -> np.ndarray:
    """INSIDE / CUT / OUTSIDE per cell by the signed distance (positive inside) at its centre
    against its half diagonal."""
    phi = np.asarray(signed_distance(lower + 0.5 * size[:, None]), dtype=float)
    r = _HALF_DIAGONAL * size
    return np.where(phi >= r, INSIDE, np.where(phi <= -r, OUTSIDE, CUT)).astype(np.int8)


def inside_moments(lower: np.ndarray, size: np.ndarray, signed_distance: SignedDistance, depth: int = 3) -> np.ndarray:
    """Moments (m, 27) of the inside parts of cells (local coordinates of each cell, the order of
    hexahedra.STIFFNESS_EXPONENTS)."""
    lower = np.asarray(lower, dtype=float).reshape(-1, 3)
    size = np.asarray(size, dtype=float).reshape(-1)
    out = np.zeros((len(size), 27))
    cell = np.arange(len(size))
    lo = np.full((len(size), 3), -1.0)  # sub-cube lower corners in local coordinates
    width = 2.0  # local width of the sub-cubes of this level
    for level in range(depth + 1):
        half = 0.5 * width * 0.5 * size[cell]  # physical half edge of each sub-cube
        centre = lower[cell] + (lo + 0.5 * width + 1.0) * (0.5 * size[cell])[:, None]
        phi = np.asarray(signed_distance(centre), dtype=float)
        inside = phi >= np.sqrt(3.0) * half
        cut = ~inside & (phi > -np.sqrt(3.0) * half)
        np.add.at(out, cell[inside], box_moments(lo[inside], lo[inside] + width))
        if level == depth:
            lo_in, hi_in = _clipped_boxes(signed_distance, centre[cut], phi[cut], half[cut], lo[cut], width,
                                          0.5 * size[cell[cut]])
            np.add.at(out, cell[cut], box_moments(lo_in, hi_in))
            break
        width *= 0.5
        cell = np.repeat(cell[cut], 8)
        lo = (lo[cut][:, None, :] + width * CORNERS[None]).reshape(-1, 3)
    return out


def _clipped_boxes(signed_distance: SignedDistance, centre, phi, half, lo, width: float, scale):
    """The inside parts of the last sub-cubes as boxes: each sub-cube cut along the axis of the
    largest component of the distance's gradient (central differences over the half edge) at
    the plane through the zero of the linearised distance. Exact for a plane parallel to a face,
    second order otherwise. Returns their local lower and upper corners."""
    grad = np.empty_like(centre)
    for k in range(3):
        step = np.zeros(3)
        step[k] = 1.0
        plus = signed_distance(centre + half[:, None] * step)
        minus = signed_distance(centre - half[:, None] * step)
        grad[:, k] = (np.asarray(plus, float) - np.asarray(minus, float)) / (2.0 * half)
    axis = np.argmax(np.abs(grad), axis=1)
    rows = np.arange(len(phi))
    g = grad[rows, axis]
    g = np.where(np.abs(g) > 1e-300, g, 1e-300)
    local_centre = lo[rows, axis] + 0.5 * width
    zero = local_centre - (phi / g) / scale  # where the linearised distance vanishes, local units
    lower, upper = lo.copy(), lo + width
    rising = g > 0.0  # inside towards larger coordinates
    lower[rows, axis] = np.where(rising, np.clip(zero, lo[rows, axis], lo[rows, axis] + width), lo[rows, axis])
    upper[rows, axis] = np.where(rising, lo[rows, axis] + width, np.clip(zero, lo[rows, axis], lo[rows, axis] + width))
    return lower, upper
