"""Importers: Onshape REST client and parser (``importers.onshape``), STL/OBJ meshes
(``importers.mesh``). Depends on ``geometry`` only; heavy dependencies (trimesh, requests)
are imported lazily by the functions that need them."""

from __future__ import annotations

__all__ = ["OnshapeFormatError", "OnshapeError"]


class OnshapeFormatError(ValueError):
    """A cached/fetched Onshape response that cannot be read. The message names the file
    and the JSON path of the offending value, e.g.
    ``bodydetails.json: bodies[0].faces[3].surface.radius: expected a number, got 'abc'``."""


class OnshapeError(RuntimeError):
    """A request to the Onshape REST API failed (authentication, permission, ids, network,
    rate limit after all retries). The message says what to check; it never holds a key."""
