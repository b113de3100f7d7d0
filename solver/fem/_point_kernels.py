"""The compiled kernel of :meth:`solver.fem.space.BodyDiscretisation.cell_blocks` for trilinear
cells (numba): a point's shape values and its traction block sigma(N_a e_k) n over the cell's 24
node dofs in one pass, instead of the (q, 6, 24) strain matrices, their product with the
elasticity matrix and the traction's six (q, 24) combinations built one after the other in
memory (a contact region's tens of thousands of points, every trial). At module level so that
numba's on-disk cache (``cache=True``) keeps it between processes; it releases the GIL
(``nogil``), so two bodies' blocks are computed side by side on two threads."""

from __future__ import annotations

import numpy as np
from numba import njit

# the Voigt rows [xx, yy, zz, yz, xz, xy] of the strain of a unit displacement along k of node a:
# B[:, 3 a + k] has g_a[DIRECTION[k, r]] in row VOIGT_ROW[k, r], r = 0, 1, 2
_VOIGT_ROW = np.array([[0, 4, 5], [1, 3, 5], [2, 3, 4]], dtype=np.int64)
_DIRECTION = np.array([[0, 2, 1], [1, 2, 0], [2, 1, 0]], dtype=np.int64)


@njit(cache=True, nogil=True, error_model="numpy")
def _hexahedron_blocks(local, scale, corners, elasticity, normals, voigt_row, direction, shape, traction):
    """shape (q, 8) N_a at local coordinates (q, 3) and traction (q, 3, 24) sigma(N_a e_k) n
    (grad N = dN/dxi * scale, scale (q,) = 2 / cell size; elasticity (6, 6) Voigt; normals
    (q, 3))."""
    g = np.empty(3)
    s = np.empty(6)
    for q in range(local.shape[0]):
        nx, ny, nz = normals[q, 0], normals[q, 1], normals[q, 2]
        for a in range(8):
            f0 = 1.0 + local[q, 0] * corners[a, 0]
            f1 = 1.0 + local[q, 1] * corners[a, 1]
            f2 = 1.0 + local[q, 2] * corners[a, 2]
            shape[q, a] = 0.125 * f0 * f1 * f2
            c = 0.125 * scale[q]
            g[0] = c * corners[a, 0] * f1 * f2
            g[1] = c * corners[a, 1] * f0 * f2
            g[2] = c * corners[a, 2] * f0 * f1
            for k in range(3):
                r0, r1, r2 = voigt_row[k, 0], voigt_row[k, 1], voigt_row[k, 2]
                v0, v1, v2 = g[direction[k, 0]], g[direction[k, 1]], g[direction[k, 2]]
                for i in range(6):
                    s[i] = elasticity[i, r0] * v0 + elasticity[i, r1] * v1 + elasticity[i, r2] * v2
                col = 3 * a + k
                traction[q, 0, col] = nx * s[0] + ny * s[5] + nz * s[4]
                traction[q, 1, col] = nx * s[5] + ny * s[1] + nz * s[3]
                traction[q, 2, col] = nx * s[4] + ny * s[3] + nz * s[2]


def hexahedron_blocks(local: np.ndarray, scale: np.ndarray, corners: np.ndarray, elasticity: np.ndarray,
                      normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q, 8) shape values and (q, 3, 24) traction blocks of trilinear cells at points of local
    coordinates ``local`` (q, 3), ``scale`` = 2 / cell size, reference ``corners`` (8, 3)."""
    q = len(local)
    shape, traction = np.empty((q, 8)), np.empty((q, 3, 24))
    _hexahedron_blocks(np.ascontiguousarray(local, dtype=float), np.ascontiguousarray(scale, dtype=float),
                       np.ascontiguousarray(corners, dtype=float), np.ascontiguousarray(elasticity, dtype=float),
                       np.ascontiguousarray(normals, dtype=float), _VOIGT_ROW, _DIRECTION, shape, traction)
    return shape, traction
