"""The cell types of the background grids, one class per type over a shared interface: the
bilinear square (quadtree, 2D) and the trilinear cube (octree, 3D). A body's function space
(solver.fem.space) takes its element from the grid's dimension."""

from __future__ import annotations

import numpy as np

from . import hexahedra, integration

__all__ = ["Element", "Quadrilateral", "Hexahedron", "element_for"]


class Element:
    """Shape functions on the reference cell [-1, 1]^dim and the strain matrix they give."""

    dim: int
    nodes: int

    @staticmethod
    def shape_functions(local: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """N (q, nodes) and dN/dlocal (q, nodes, dim) at local coordinates (q, dim)."""
        raise NotImplementedError

    @staticmethod
    def strain_matrix(grad: np.ndarray) -> np.ndarray:
        """B (q, n_voigt, nodes x dim) from physical gradients (q, nodes, dim)."""
        raise NotImplementedError


class Quadrilateral(Element):
    dim, nodes = 2, 4

    @staticmethod
    def shape_functions(local: np.ndarray):
        return integration.shape_functions(local[:, 0], local[:, 1])

    strain_matrix = staticmethod(integration.strain_matrix)


class Hexahedron(Element):
    dim, nodes = 3, 8
    shape_functions = staticmethod(hexahedra.shape_functions)
    strain_matrix = staticmethod(hexahedra.strain_matrix)


_BY_DIMENSION = {2: Quadrilateral, 3: Hexahedron}


def element_for(dim: int) -> type[Element]:
    try:
        return _BY_DIMENSION[dim]
    except KeyError:
        raise ValueError(f"no cell type for dimension {dim!r}") from None
