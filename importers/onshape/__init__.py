"""Onshape import: REST client (``OnshapeClient``), wire-format models and the parser
(``load_part(directory) -> geometry.Part``). ``requests`` is imported only when the client
actually talks to a server; ``trimesh`` only when meshes are built."""

from __future__ import annotations

from .. import OnshapeError, OnshapeFormatError
from .client import DocumentUrl, OnshapeClient, parse_document_url
from .parser import load_part, parse_part

__all__ = ["OnshapeClient", "DocumentUrl", "parse_document_url", "load_part", "parse_part",
           "OnshapeError", "OnshapeFormatError"]
