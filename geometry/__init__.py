"""Exact CAD geometry: primitives with vectorised closest-point projection, exact normals
and signed distances (2D and 3D), bounded curves and closed 2D profiles, and the ``Part``
container for imported CAD.

Importing this package imports numpy and scipy only: no solver, importer, plotting or
network code (``trimesh`` is imported lazily by the functions that need it).
"""

from ._base import Curve, Primitive, Projection, Surface, primitive_from_dict
from .part import Body, Coedge, Edge, Face, Loop, Part

# Each module below defines __all__ and registers its primitives on import.
from .curves import *  # noqa: F401,F403  line, circle
from .ellipse import *  # noqa: F401,F403
from .surfaces import *  # noqa: F401,F403  plane, sphere, cylinder, cone, torus
from .bspline import *  # noqa: F401,F403  bspline_curve, bspline_surface
from .sweep import *  # noqa: F401,F403
from .bounded import *  # noqa: F401,F403  2D segments, arcs, elliptic arcs, B-spline pieces
from .profile import *  # noqa: F401,F403  closed 2D profiles
from .shapes import *  # noqa: F401,F403  scene-file 2D shapes -> profiles
from .verify import *  # noqa: F401,F403  verify_projection
from ._jit import release_threads  # noqa: F401  the projections' thread pool stopped before a fork

__version__ = "0.1.0"

#: names of geometry.solids (the 3D shapes of a scene) reachable from the package, imported on first use
_SOLIDS = ("solid_from_dict", "PartSolid", "SOLID_TYPES")


def __getattr__(name: str):
    if name in _SOLIDS:
        from . import solids

        return getattr(solids, name)
    raise AttributeError(f"module 'ibfem.geometry' has no attribute {name!r}")
