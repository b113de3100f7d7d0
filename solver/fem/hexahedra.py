"""Trilinear hexahedra on cube cells (the 3D counterpart of the bilinear squares in
solver.fem.integration): shape functions, the strain matrix, the stiffness and body-force
vector of a full cell. Voigt order [xx, yy, zz, yz, xz, xy] with engineering shears
(solver.model.elasticity); dofs [u1x, u1y, u1z, u2x, ...] in the corner order of
solver.fem.octree.CORNERS."""

from __future__ import annotations

import numpy as np

from geometry.quadrature import gauss_legendre

from .octree import CORNERS

__all__ = ["REFERENCE_CORNERS", "shape_functions", "strain_matrix", "cube_stiffness", "cube_body_force"]

#: the corners in reference coordinates (-1 or 1)
REFERENCE_CORNERS = 2.0 * CORNERS - 1.0


def shape_functions(local: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Trilinear N (..., 8) and dN/d(xi, eta, zeta) (..., 8, 3) at local coordinates (..., 3)."""
    x = np.asarray(local, dtype=float)[..., None, :]  # (..., 1, 3)
    c = REFERENCE_CORNERS  # (8, 3)
    f = 1.0 + x * c  # (..., 8, 3) the three linear factors
    n = 0.125 * f[..., 0] * f[..., 1] * f[..., 2]
    dn = 0.125 * np.stack(
        [c[:, 0] * f[..., 1] * f[..., 2], c[:, 1] * f[..., 0] * f[..., 2], c[:, 2] * f[..., 0] * f[..., 1]], axis=-1
    )
    return n, dn


def strain_matrix(grad: np.ndarray) -> np.ndarray:
    """B (..., 6, 24) acting on [u1x, u1y, u1z, ...] -> [exx, eyy, ezz, 2eyz, 2exz, 2exy] from
    grad N (..., 8, 3)."""
    b = np.zeros(grad.shape[:-2] + (6, 24))
    gx, gy, gz = grad[..., 0], grad[..., 1], grad[..., 2]
    b[..., 0, 0::3] = gx
    b[..., 1, 1::3] = gy
    b[..., 2, 2::3] = gz
    b[..., 3, 1::3], b[..., 3, 2::3] = gz, gy
    b[..., 4, 0::3], b[..., 4, 2::3] = gz, gx
    b[..., 5, 0::3], b[..., 5, 1::3] = gy, gx
    return b


def _gauss_cube(order: int = 2):
    x, w = gauss_legendre(order)
    pts = np.stack(np.meshgrid(x, x, x, indexing="ij"), axis=-1).reshape(-1, 3)
    wts = np.einsum("i,j,k->ijk", w, w, w).ravel()
    return pts, wts


def cube_stiffness(elasticity: np.ndarray, size: float = 1.0) -> np.ndarray:
    """(24, 24) stiffness of a full cube of edge ``size`` (2-point Gauss per direction: exact
    for trilinear fields, whose B^T C B has degree <= 2 in each coordinate). It scales as size^1
    (grad N ~ 1/size, volume ~ size^3)."""
    pts, wts = _gauss_cube(2)
    _, dn = shape_functions(pts)
    b = strain_matrix(dn * (2.0 / size))
    jac = (0.5 * size) ** 3
    return np.einsum("q,qki,kl,qlj->ij", wts * jac, b, np.asarray(elasticity, float), b)


def cube_body_force(force, size: float = 1.0) -> np.ndarray:
    """(24,) consistent nodal load of a uniform body force (3,) over a full cube: each corner
    carries an eighth of the cube's total."""
    f = np.asarray(force, dtype=float).reshape(3)
    return np.tile(f * size**3 / 8.0, 8)
