"""Two bodies that touch at several places: each place is a contact of its own, and their
regions must stay apart (one region found twice would carry its load twice).

:func:`overlapping_regions` compares the contacts of each pair of bodies by the discs that hold
their regions: about the contact point, of the region's reach (2D: the farther end along the
tangent; 3D: the semi-axes' corner plus the region's centre offset). Discs that meet are
reported; a run with them is not converged.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["region_reach", "overlapping_regions"]


def region_reach(block: dict) -> float:
    """How far from the contact point the region of a contact block reaches (m; 0 without one)."""
    if block.get("semi_axes") is not None:  # 3D: the ellipse or the star region's half-extents
        a, b = (float(v) for v in block["semi_axes"])
        centre = block.get("region_centre") or [0.0, 0.0]
        return math.hypot(a, b) + math.hypot(float(centre[0]), float(centre[1]))
    region = block.get("region")
    if region:  # 2D: the region's ends along the tangent from the contact point
        return max(abs(float(v)) for v in region)
    return float(block.get("half_width") or 0.0)


def overlapping_regions(blocks: list[dict]) -> list[str]:
    """One message per two contacts of the same bodies whose regions' discs meet."""
    problems = []
    for j, second in enumerate(blocks):
        for i, first in enumerate(blocks[:j]):
            if frozenset(first.get("bodies") or ()) != frozenset(second.get("bodies") or ()):
                continue
            gap = float(np.linalg.norm(np.subtract(first["point"], second["point"])))
            r1, r2 = region_reach(first), region_reach(second)
            if r1 > 0.0 and r2 > 0.0 and gap < r1 + r2:
                problems.append(
                    f"contacts {i} and {j} of {' / '.join(first['bodies'])}: their regions may overlap (reaching "
                    f"{r1:.4g} m and {r2:.4g} m from points {gap:.4g} m apart); two contacts of the same bodies "
                    "must touch at separate places: give one contact there")
    return problems
