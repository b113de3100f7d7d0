"""Units for the numbers on a plot: stresses in Pa, kPa, MPa or GPa and lengths in m, mm or um,
chosen so that the values shown lie between about 0.1 and 1000 (no '1e9' offsets on an axis)."""

from __future__ import annotations

import math

__all__ = ["stress_unit", "length_unit"]

_STRESS = (("GPa", 1e9), ("MPa", 1e6), ("kPa", 1e3), ("Pa", 1.0))
_LENGTH = (("m", 1.0), ("mm", 1e-3), ("um", 1e-6))


def _pick(value: float, units) -> tuple[str, float]:
    v = abs(float(value)) if value is not None and math.isfinite(float(value)) else 0.0
    for name, scale in units:
        if v >= 0.5 * scale:
            return name, scale
    return units[-1]


def stress_unit(largest: float) -> tuple[str, float]:
    """(name, Pa per unit) for stresses whose largest magnitude is ``largest`` Pa."""
    return _pick(largest, _STRESS)


def length_unit(extent: float) -> tuple[str, float]:
    """(name, m per unit) for a picture ``extent`` m across."""
    return _pick(extent, _LENGTH)
