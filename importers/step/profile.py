"""2D profiles from a STEP/IGES part: the ``step`` scene shape of SPEC sections 4 and 9.

``{type = "step", path, face = "F3"}`` (a face id, or the face's name in the file) or ``{type = "step", path, section = {origin, normal},
body = "B1"}``, with the same keys, frame and meaning as the ``onshape`` shape
(:mod:`importers.onshape.profile`, whose face and section builders work on any
``geometry.Part``); ``path`` is the .step/.stp/.iges/.igs file or a directory written by
``ibfem import``. Face ids are the importer's ``F1..Fn``, edge names its ``E1..Em`` (section
edges are named by the side face they cut). Parts are kept in memory per (file, modification
time), so a scene naming the same file twice parses it once.
"""

from __future__ import annotations

import math
import os
from functools import lru_cache
from pathlib import Path

import numpy as np

from geometry import Part
from geometry.profile import Profile

from ..onshape.profile import SHAPE_KEYS, _vec, face_profile, section_profile

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


def _section(shape: dict, where: str, part: Part, x_axis) -> Profile:
    sec = shape["section"]
    if not isinstance(sec, dict) or set(sec) - {"origin", "normal"} or "normal" not in sec:
        raise ValueError(f"expected {{origin = [x, y, z], normal = [x, y, z]}}, got {sec!r}")
    o = _vec(sec.get("origin", [0.0, 0.0, 0.0]), f"{where}.section.origin")
    n = _vec(sec["normal"], f"{where}.section.normal")
    return section_profile(part, o, n, shape.get("body"), x_axis)


def profile_from_shape(shape: dict, where: str = "shape") -> Profile:
    """The profile of a ``step`` scene shape: ``{type = "step", path, face = "<face id>"}`` or
    ``{type = "step", path, section = {origin = [x, y, z], normal = [x, y, z]}, body = "<id or
    name>"}``, optional ``x_axis``, ``rotate_deg``, ``pivot``, ``translate``."""
    if not isinstance(shape, dict):
        raise ValueError(f"{where}: expected a table, got {shape!r}")
    shape = {k: v for k, v in shape.items() if v is not None}
    unknown = sorted(set(shape) - set(SHAPE_KEYS))
    if unknown:
        raise ValueError(f"{where}.{unknown[0]}: unknown key for a step shape (known: {', '.join(SHAPE_KEYS)})")
    if "path" not in shape:
        raise ValueError(f"{where}.path: missing (the .step/.stp/.iges/.igs file or its import directory)")
    if ("face" in shape) == ("section" in shape):
        raise ValueError(f"{where}: give exactly one of 'face' (a planar face id) or 'section' "
                         f"({{origin, normal}})")
    try:
        part = _load(str(shape["path"]))
    except ValueError as exc:  # StepFormatError, StepUnavailableError included
        raise ValueError(f"{where}.path: {exc}") from None
    x_axis = _vec(shape["x_axis"], f"{where}.x_axis") if "x_axis" in shape else None
    try:
        if "face" in shape:
            if not isinstance(shape["face"], str):
                raise ValueError(f"expected a face id string, got {shape['face']!r}")
            prof = face_profile(part, _face_id(part, shape["face"]), x_axis)
        else:
            prof = _section(shape, where, part, x_axis)
    except ValueError as exc:
        key = "face" if "face" in shape else "section"
        msg = str(exc).replace("bodydetails.json", "the file")
        raise ValueError(msg if msg.startswith(where) else f"{where}.{key}: {msg}") from None
    rot = shape.get("rotate_deg", 0.0)
    pivot = _vec(shape.get("pivot", [0.0, 0.0]), f"{where}.pivot", 2)
    translate = _vec(shape.get("translate", [0.0, 0.0]), f"{where}.translate", 2)
    if not isinstance(rot, (int, float)) or isinstance(rot, bool) or not math.isfinite(rot):
        raise ValueError(f"{where}.rotate_deg: expected a number, got {rot!r}")
    if rot or np.any(translate):
        prof = prof.transformed(rot, pivot, translate)
    return prof
