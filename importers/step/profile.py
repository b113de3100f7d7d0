"""2D profiles from a STEP/IGES part: the 2D ``step`` scene shape.

``{type = "step", path, face = "F3"}`` (a face id, or the face's name in the file) or ``{type = "step", path, section = {origin, normal},
body = "B1"}``, with the same keys, frame and meaning as the ``onshape`` shape
(:mod:`importers.part_profile`, whose face and section builders work on any
``geometry.Part``); ``path`` is the .step/.stp/.iges/.igs file or a directory written by
``ibfem import``. Face ids are the importer's ``F1..Fn``, edge names its ``E1..Em`` (section
edges are named by the side face they cut). Parts are kept in memory per (file, modification
time), so a scene naming the same file twice parses it once.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path

from ibfem.geometry import Part
from ibfem.geometry.profile import Profile

from ..part_profile import SHAPE_KEYS, profile_from_part_shape

__all__ = ["profile_from_shape", "SHAPE_KEYS"]


@lru_cache(maxsize=16)
def _cached_part(path: str, stamp: tuple) -> Part:
    from .loader import load_part

    return load_part(path)


def _load(path: str) -> Part:
    p = Path(path)
    target = p / "part.json" if p.is_dir() else p
    try:
        st = os.stat(target)
        stamp = (st.st_mtime_ns, st.st_size)
    except OSError:
        stamp = (0, 0)
    return _cached_part(str(p.resolve()), stamp)


def _face_id(part: Part, face: str) -> str:
    """The id of a face given by id (F3) or by its name in the file (ADVANCED_FACE('top', ...))."""
    if face in part.faces:
        return face
    named = [fid for fid, name in part.metadata.get("face_names", {}).items() if name == face]
    if len(named) > 1:
        raise ValueError(f"{len(named)} faces are named {face!r} in the file ({', '.join(named)}): give the id")
    return named[0] if named else face


def profile_from_shape(shape: dict, where: str = "shape") -> Profile:
    """The profile of a ``step`` scene shape: ``{type = "step", path, face = "<face id or name>"}`` or
    ``{type = "step", path, section = {origin = [x, y, z], normal = [x, y, z]}, body = "<id or
    name>"}``, optional ``x_axis``, ``rotate_deg``, ``pivot``, ``translate``."""
    return profile_from_part_shape(shape, where, "step", _load, "the .step/.stp/.iges/.igs file or its import directory",
                                   _face_id)
