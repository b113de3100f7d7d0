"""Small tensor helpers of the constitutive law on Voigt arrays, any dimension."""

from __future__ import annotations

import numpy as np

__all__ = ["traction_of_voigt"]


def traction_of_voigt(stress: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """sigma n for Voigt stresses ``stress`` (q, nv, ...) and unit normals (q, dim): (q, dim, ...).

    2D Voigt [xx, yy, xy]; 3D [xx, yy, zz, yz, xz, xy]."""
    n = [normals[:, k].reshape((-1,) + (1,) * (stress.ndim - 2)) for k in range(normals.shape[1])]
    s = [stress[:, k] for k in range(stress.shape[1])]
    if len(n) == 2:
        sxx, syy, sxy = s
        nx, ny = n
        rows = [nx * sxx + ny * sxy, nx * sxy + ny * syy]
    else:
        sxx, syy, szz, syz, sxz, sxy = s
        nx, ny, nz = n
        rows = [nx * sxx + ny * sxy + nz * sxz, nx * sxy + ny * syy + nz * syz, nx * sxz + ny * syz + nz * szz]
    return np.stack(rows, axis=1)
