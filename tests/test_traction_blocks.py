"""The trilinear cell's traction blocks sigma(.) n (solver.fem.hexahedra.traction_blocks, used by
3D bodies' boundary and contact points) against sigma n of a linear displacement field, which the
trilinear cell reproduces exactly: sigma from the strain by Lame's law, and by a general
(anisotropic) Voigt matrix."""

from __future__ import annotations

import numpy as np
import pytest

from ibfem.solver.fem.hexahedra import REFERENCE_CORNERS, shape_functions, traction_blocks

_VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def _stress(strain: np.ndarray, elasticity: np.ndarray) -> np.ndarray:
    """The stress tensor of a strain tensor through a Voigt matrix (engineering shear strains)."""
    e = np.array([strain[i, j] * (1.0 if i == j else 2.0) for i, j in _VOIGT])
    s = elasticity @ e
    out = np.zeros((3, 3))
    for k, (i, j) in enumerate(_VOIGT):
        out[i, j] = out[j, i] = s[k]
    return out


def _isotropic(lam: float, mu: float) -> np.ndarray:
    c = np.zeros((6, 6))
    c[:3, :3] = lam
    c[np.arange(3), np.arange(3)] += 2.0 * mu
    c[np.arange(3, 6), np.arange(3, 6)] = mu
    return c


@pytest.mark.parametrize("kind", ["lame", "anisotropic"])
def test_traction_blocks_give_sigma_n_of_a_linear_field(kind):
    rng = np.random.default_rng(11)
    lam, mu = 1.15e11, 7.7e10
    if kind == "lame":
        elasticity = _isotropic(lam, mu)
    else:
        a = rng.normal(size=(6, 6))
        elasticity = a @ a.T + 6.0 * np.eye(6)
    h, centre = 0.3, np.array([0.2, -1.1, 0.7])
    gradient = rng.normal(size=(3, 3))  # u(x) = G x + c
    corners = centre + 0.5 * h * REFERENCE_CORNERS
    nodal = (corners @ gradient.T + rng.normal(size=3)).ravel()  # [u1x, u1y, u1z, ...]
    local = rng.uniform(-1.0, 1.0, size=(50, 3))
    _, dn = shape_functions(local)
    normals = rng.normal(size=(50, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    blocks = traction_blocks(dn * (2.0 / h), normals, elasticity)
    strain = 0.5 * (gradient + gradient.T)
    sigma = _stress(strain, elasticity)
    if kind == "lame":
        assert np.allclose(sigma, lam * np.trace(strain) * np.eye(3) + 2.0 * mu * strain, rtol=1e-14, atol=0)
    expected = normals @ sigma.T
    assert np.max(np.abs(blocks @ nodal - expected)) <= 1e-13 * np.max(np.abs(expected))
