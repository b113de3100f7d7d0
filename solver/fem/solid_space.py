"""A 3D body's function space (issue 14): the octree over a solid with exact cut cells, trilinear
cubes, and boundary points on the solid's faces for the step-boundary terms and loads.

The solid is anything with ``signed_distance(points (n, 3)) -> (n,)`` (positive inside),
``bounds -> (min (3,), max (3,))`` and ``faces`` (name -> face), each face with
``quadrature(resolution) -> (points (q, 3), weights (q,), normals (q, 3))``: Gauss points on the
exact trimmed face, every panel of the rule at most ``resolution`` across, outward normals. The
points are the face's own (never a tessellation's); a point is assigned to the leaf that holds
it (nudged into the material along the normal).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .assembly_blocks import assemble_blocks
from .cut_cells3d import CUT, INSIDE, classify_cells, inside_moments
from .grid import RefinementZone
from .hexahedra import cell_stiffness, full_cube_moments, monomial_stiffness
from .octree import build_octree
from .space import BodyDiscretisation
from .step_boundary import BoundaryPoints

__all__ = ["SolidDiscretisation", "discretise_solid"]

#: subdivision levels of the cut cells' moments (volume error ~ 4^-depth of the cut cells' share)
CUT_DEPTH = 3
#: boundary quadrature panels per cell width
PANELS_PER_CELL = 2


@dataclass
class SolidDiscretisation(BodyDiscretisation):
    """A solid on its octree: the cells' status (INSIDE / CUT) and the local moments (m, 27) of
    their inside parts; the rest as in 2D (dof block, point operators)."""

    status: np.ndarray = field(default=None, repr=False)
    moments: np.ndarray = field(default=None, repr=False)

    def stiffness(self, alpha: float) -> sp.csr_matrix:
        """Volume stiffness of the free dofs: moment-fitted cube parts, cut cells plus ``alpha``
        times their full stiffness (conditioning of tiny cut parts)."""
        g = self.grid
        km = monomial_stiffness(self.elasticity)
        moments = self.moments + np.where(self.status == CUT, alpha, 0.0)[:, None] * full_cube_moments()
        k = assemble_blocks(g.cells, cell_stiffness(moments, g.size, km), len(g.nodes))
        if g.n_hanging:
            t = sp.kron(g.constraint, sp.identity(3), format="csr")
            k = (t.T @ k @ t).tocsr()
        return k

    def edge_points(self, face: str, order: int = 2) -> BoundaryPoints:
        """Quadrature points on a face of the solid with their operators (the name follows the
        2D edge_points: boundary conditions call it for their ``edge``, a face name in 3D)."""
        faces = self.boundary.faces
        if face not in faces:
            raise ValueError(f"body {self.name!r} has no face {face!r}; faces: {', '.join(faces)}")
        resolution = self.grid.min_size / PANELS_PER_CELL
        points, weights, normals = faces[face].quadrature(resolution)
        cells = self.grid.locate(points - 1e-9 * self.grid.min_size * normals)
        keep = cells >= 0
        points, weights, normals, cells = points[keep], weights[keep], normals[keep], cells[keep]
        return BoundaryPoints(
            points=points,
            weights=weights,
            normals=normals,
            cell_size=self.grid.size[cells],
            displacement=self.displacement_operator(points, cells),
            traction=self.traction_operator(points, cells, normals),
        )

    def contains(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(self.boundary.signed_distance(points), dtype=float) >= -1e-9 * self.element_size


def discretise_solid(name: str, solid, material_lame: tuple[float, float], elasticity: np.ndarray,
                     poissons_ratio: float, element_size: float, zones: tuple[RefinementZone, ...] = (),
                     index: int = 0, offset=(0.0, 0.0, 0.0), depth: int = CUT_DEPTH) -> SolidDiscretisation:
    """The octree over ``solid`` (cells farther outside than their half diagonal dropped), the
    status and inside moments of its cells."""
    phi = solid.signed_distance
    reach = 0.5 * np.sqrt(3.0) * (1.0 + 1e-9)

    def keep(lower, size):
        return np.asarray(phi(lower + 0.5 * size[:, None]), dtype=float) > -reach * size

    tree = build_octree(solid.bounds, element_size, zones, keep, offset)
    status = classify_cells(tree.lower, tree.size, phi)
    moments = np.zeros((len(tree.size), 27))
    moments[status == INSIDE] = full_cube_moments()
    cut = status == CUT
    moments[cut] = inside_moments(tree.lower[cut], tree.size[cut], phi, depth)
    lam, mu = material_lame
    return SolidDiscretisation(
        name=name, index=index, grid=tree, boundary=solid, profile=solid, lam=lam, mu=mu, elasticity=elasticity,
        model="solid", poissons_ratio=poissons_ratio, element_size=float(element_size), status=status,
        moments=moments,
    )
