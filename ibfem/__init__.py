"""ibfem: contact stresses on exact CAD geometry with immersed-boundary finite elements.

Subpackages (each imported on first use, so ``from ibfem import geometry`` loads no solver,
importer, plotting or network code):

- ``ibfem.geometry``: exact CAD primitives with vectorised projection, normals and signed
  distances; bounded curves, closed 2D profiles, 3D solids and the ``Part`` container.
- ``ibfem.importers``: Onshape (REST API and cached responses), STEP/IGES files, meshes.
- ``ibfem.solver``: the immersed-boundary FEM with contact, scene files, results, the CLI.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__all__ = ["geometry", "importers", "solver", "__version__"]
_SUBPACKAGES = ("geometry", "importers", "solver")


def _installed_version() -> str:
    """The installed distribution's version (read on first use: importlib.metadata and the
    look-up cost a run some 20 ms it does not need)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("ibfem")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "0+unknown"


def __getattr__(name: str) -> Any:
    if name in _SUBPACKAGES:
        return import_module(f"{__name__}.{name}")
    if name == "__version__":
        globals()["__version__"] = value = _installed_version()
        return value
    raise AttributeError(f"module 'ibfem' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
