"""Exact solids (the 3D shapes of a scene): signed distances (positive inside), bounds, volumes and named
faces with exact surfaces (quadrature, closest points, curvatures), for the 3D solver.
``solid_from_dict`` builds the shapes of a scene file; ``PartSolid`` the solid of a CAD part's
body. Imports numpy (scipy within functions) and geometry's own modules only."""

from .build import SOLID_TYPES, rotation_matrix, solid_from_dict
from .ellipsoid import Ellipsoid, HalfEllipsoid
from .faces import ParametricFace, PlanarRegionFace
from .part_solid import PartFace, PartSolid
from .shapes import Box, Cylinder, Extrusion, HalfSphere, Revolution, Solid, Sphere, Transformed

__all__ = ["solid_from_dict", "SOLID_TYPES", "rotation_matrix", "Solid", "Box", "Sphere", "HalfSphere", "Ellipsoid",
           "HalfEllipsoid", "Cylinder", "Extrusion", "Revolution", "Transformed", "ParametricFace", "PlanarRegionFace",
           "PartSolid", "PartFace"]
