"""Exact solids (SPEC section 7): signed distances (positive inside), bounds and named faces
with exact parametrisations, for the 3D solver. ``solid_from_dict`` builds the shapes of a scene
file. Imports numpy only (and geometry's 2D profiles for extrusions and revolutions)."""

from .build import SOLID_TYPES, rotation_matrix, solid_from_dict
from .faces import ParametricFace, PlanarRegionFace
from .shapes import Box, Cylinder, Extrusion, HalfSphere, Revolution, Solid, Sphere, Transformed

__all__ = ["solid_from_dict", "SOLID_TYPES", "rotation_matrix", "Solid", "Box", "Sphere", "HalfSphere", "Cylinder",
           "Extrusion", "Revolution", "Transformed", "ParametricFace", "PlanarRegionFace"]
