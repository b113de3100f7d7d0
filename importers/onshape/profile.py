"""2D profiles from a cached Onshape import (the ``onshape`` shape of a scene):
``{type = "onshape", path, face = "<face id>"}`` or ``{type = "onshape", path, section = {origin,
normal}, body = "<id or name>"}``, optional ``x_axis``, ``rotate_deg``, ``pivot``, ``translate``.
The face and section builders work on any ``geometry.Part`` (:mod:`importers.part_profile`,
shared with the STEP importer). Parts are kept in memory per (directory, modification times).
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path

from ibfem.geometry import Part
from ibfem.geometry.profile import Profile

from ..part_profile import SHAPE_KEYS, face_profile, plane_frame, profile_from_part_shape, section_profile

__all__ = ["profile_from_shape", "face_profile", "section_profile", "plane_frame", "SHAPE_KEYS"]


@lru_cache(maxsize=16)
def _cached_part(path: str, stamp: tuple) -> Part:
    from .parser import load_part

    return load_part(path)


def _load(path: str) -> Part:
    p = Path(path)
    files = ("tessellatedfaces.json", "tessellatededges.json", "bodydetails.json")
    stamp = tuple(os.stat(p / f).st_mtime_ns if (p / f).exists() else 0 for f in files)
    return _cached_part(str(p.resolve()), stamp)


def profile_from_shape(shape: dict, where: str = "shape") -> Profile:
    """The profile of an ``onshape`` scene shape (module docstring)."""
    return profile_from_part_shape(shape, where, "onshape", _load, "the cached import directory")
