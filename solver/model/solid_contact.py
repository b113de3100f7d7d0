"""A contact between two solids: the 2D contact model plus the direction that
fixes the contact frame's first axis where the geometry does not (a circular contact)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .problem import ContactModel

__all__ = ["SolidContactModel"]


@dataclass(frozen=True)
class SolidContactModel(ContactModel):
    #: (3,) or None: axes[0] of a circular contact (projected onto the tangent plane)
    tangential_direction: np.ndarray | None = None
