"""Trilinear hexahedra on cube cells (the 3D counterpart of the bilinear squares in
solver.fem.integration): shape functions, the strain matrix, the stiffness and body-force
vector of a full cell. Voigt order [xx, yy, zz, yz, xz, xy] with engineering shears
(solver.model.elasticity); dofs [u1x, u1y, u1z, u2x, ...] in the corner order of
solver.fem.octree.CORNERS."""

from __future__ import annotations

import numpy as np

from ibfem.geometry.quadrature import gauss_legendre

from .octree import CORNERS

__all__ = [
    "REFERENCE_CORNERS",
    "shape_functions",
    "strain_matrix",
    "traction_blocks",
    "cube_stiffness",
    "cube_body_force",
    "STIFFNESS_EXPONENTS",
    "monomial_stiffness",
    "full_cube_moments",
    "cell_stiffness",
    "box_moments",
]

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


#: per displacement component j of a node: the strain rows (Voigt) it enters and the gradient
#: component each is multiplied by (the non-zeros of strain_matrix's column 3 a + j)
_STRAIN_ROWS = (((0, 0), (4, 2), (5, 1)), ((1, 1), (3, 2), (5, 0)), ((2, 2), (3, 1), (4, 0)))


def traction_blocks(grad: np.ndarray, normals: np.ndarray, elasticity: np.ndarray) -> np.ndarray:
    """sigma(.) n as blocks (q, 3, 24) on [u1x, u1y, u1z, ...] from grad N (q, 8, 3), unit normals
    (q, 3) and the Voigt elasticity (6, 6): (N_n C) B with N_n the normal's (3, 6) Voigt matrix,
    using only B's non-zeros (three per column) instead of forming B."""
    q = len(grad)
    nx, ny, nz = normals[:, 0], normals[:, 1], normals[:, 2]
    zero = np.zeros(q)
    voigt_normal = np.stack([np.stack([nx, zero, zero, zero, nz, ny], axis=1),
                             np.stack([zero, ny, zero, nz, zero, nx], axis=1),
                             np.stack([zero, zero, nz, ny, nx, zero], axis=1)], axis=1)  # (q, 3, 6)
    m = voigt_normal @ elasticity  # (q, 3, 6)
    out = np.empty((q, 3, 8, 3))
    for j, ((r0, g0), (r1, g1), (r2, g2)) in enumerate(_STRAIN_ROWS):
        out[..., j] = (m[:, :, r0, None] * grad[:, None, :, g0] + m[:, :, r1, None] * grad[:, None, :, g1]
                       + m[:, :, r2, None] * grad[:, None, :, g2])
    return out.reshape(q, 3, 24)


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


# --------------------------------------------------------------------------- moment fitting

#: exponents (a, b, c) of the monomials xi^a eta^b zeta^c in B^T C B of a trilinear cube
STIFFNESS_EXPONENTS = np.array([(a, b, c) for a in range(3) for b in range(3) for c in range(3)])
_SIGNS = 2.0 * CORNERS - 1.0  # the 8 corners of [-1, 1]^3
_MULTILINEAR = np.array([(p, q, r) for p in range(2) for q in range(2) for r in range(2)])


def monomial_stiffness(elasticity: np.ndarray) -> np.ndarray:
    """(27, 24, 24) matrices K_abc with B^T C B = sum xi^a eta^b zeta^c K_abc on the reference
    cube (B in local units, d/dxi). B is multilinear, B = sum_e x^e B_e over e in {0, 1}^3, with
    B_e = (1/8) sum over the corners s of s^e B(s); then K_abc = sum over e + f = (a, b, c) of
    B_e^T C B_f. The stiffness of any part of a cell of size h is (h / 2) sum m_abc K_abc, m the
    part's moments in local coordinates: one table for every level of the octree."""
    _, dn = shape_functions(_SIGNS)
    b_corner = strain_matrix(dn)  # (8, 6, 24) at the corners, local units
    powers = np.prod(_SIGNS[:, None, :] ** _MULTILINEAR[None, :, :], axis=2)  # (8 corners, 8 e)
    b_e = np.einsum("se,sij->eij", powers, b_corner) / 8.0
    c = np.asarray(elasticity, dtype=float)
    index = {tuple(e): k for k, e in enumerate(STIFFNESS_EXPONENTS)}
    k_abc = np.zeros((27, 24, 24))
    for i, e in enumerate(_MULTILINEAR):
        for j, f in enumerate(_MULTILINEAR):
            k_abc[index[tuple(e + f)]] += b_e[i].T @ c @ b_e[j]
    return k_abc


def full_cube_moments() -> np.ndarray:
    """Moments m_abc (27,) of the whole reference cube, in STIFFNESS_EXPONENTS order."""
    one_d = np.array([2.0, 0.0, 2.0 / 3.0])
    return np.prod(one_d[STIFFNESS_EXPONENTS], axis=1)


def cell_stiffness(moments: np.ndarray, sizes: np.ndarray, k_monomial: np.ndarray) -> np.ndarray:
    """Stiffness (..., 24, 24) of cell parts with local moments (..., 27) in cells of ``sizes``."""
    moments = np.asarray(moments, dtype=float)
    k = k_monomial.shape
    flat = moments.reshape(-1, k[0]) @ k_monomial.reshape(k[0], -1)  # one matrix product (BLAS)
    flat *= 0.5 * np.broadcast_to(np.asarray(sizes, dtype=float), moments.shape[:-1]).reshape(-1, 1)
    return flat.reshape(moments.shape[:-1] + k[1:])


def box_moments(lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Exact moments (..., 27) of axis-aligned boxes [lower, upper] (local coordinates)."""
    lo, hi = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    one_d = np.stack([(hi**k - lo**k) / k for k in (1, 2, 3)], axis=-1)  # (..., 3 axes, 3 powers)
    e = STIFFNESS_EXPONENTS
    return one_d[..., 0, e[:, 0]] * one_d[..., 1, e[:, 1]] * one_d[..., 2, e[:, 2]]
