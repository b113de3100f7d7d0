"""The constitutive law of linear isotropic elasticity, written once for any dimension: the
shape of the Voigt stress (3 components in 2D, 6 in 3D) gives the dimension.

Voigt order: 2D [xx, yy, xy], 3D [xx, yy, zz, yz, xz, xy]; engineering shear strains (2 e_xy).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

__all__ = ["Model", "MODELS", "dimension", "lame_parameters", "elasticity_matrix", "plane_modulus", "dundurs_beta", "von_mises"]

Model = Literal["plane_strain", "plane_stress", "solid"]
MODELS = ("plane_strain", "plane_stress", "solid")
_DIMENSION = {"plane_strain": 2, "plane_stress": 2, "solid": 3}


def dimension(model: str) -> int:
    """Spatial dimension of an analysis model."""
    try:
        return _DIMENSION[model]
    except KeyError:
        raise ValueError(f"model must be one of {', '.join(_DIMENSION)}, got {model!r}") from None


def lame_parameters(youngs_modulus: float, poissons_ratio: float, model: str) -> tuple[float, float]:
    """(lambda, mu). Plane strain and 3D use the 3D Lame constants; plane stress the reduced
    lambda* = 2 lambda mu / (lambda + 2 mu)."""
    E, nu = youngs_modulus, poissons_ratio
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    if model == "plane_stress":
        lam = 2.0 * lam * mu / (lam + 2.0 * mu)
    return lam, mu


def elasticity_matrix(lam: float, mu: float, dim: int) -> np.ndarray:
    """C in Voigt form: normal block lambda + 2 mu on the diagonal and lambda off it, mu on
    the shear diagonal ((3, 3) in 2D, (6, 6) in 3D)."""
    n_normal = dim
    n_voigt = dim * (dim + 1) // 2
    c = np.zeros((n_voigt, n_voigt))
    c[:n_normal, :n_normal] = lam
    c[range(n_normal), range(n_normal)] = lam + 2 * mu
    c[range(n_normal, n_voigt), range(n_normal, n_voigt)] = mu
    return c


def plane_modulus(elasticity: np.ndarray) -> float:
    """E / (1 - nu^2) of a plane-strain matrix (the modulus of Hertz's E*), from C itself."""
    return float(elasticity[0, 0] - elasticity[0, 1] ** 2 / elasticity[0, 0])


def dundurs_beta(first: tuple[float, float], second: tuple[float, float]) -> float:
    """Dundurs' beta of two bodies from their Lame constants (lambda, mu) as :func:`lame_parameters`
    gives them for the model (plane stress: the reduced lambda): with kappa = (lambda + 3 mu) /
    (lambda + mu), beta = [(kappa1 - 1) / mu1 - (kappa2 - 1) / mu2] / [(kappa1 + 1) / mu1 +
    (kappa2 + 1) / mu2] (K. L. Johnson, Contact Mechanics, 1985, eq. 5.4). It measures how a
    pressure between the bodies moves their surfaces apart tangentially: 0 for one material; its
    sign follows the order."""
    def parts(lame):
        lam, mu = lame
        kappa = (lam + 3.0 * mu) / (lam + mu)
        return (kappa - 1.0) / mu, (kappa + 1.0) / mu

    (d1, s1), (d2, s2) = parts(first), parts(second)
    return float((d1 - d2) / (s1 + s2))


def von_mises(stress: np.ndarray, model: str, poissons_ratio: float | np.ndarray) -> np.ndarray:
    """Von Mises stress of Voigt stresses (..., 3) in 2D (plane strain adds szz = nu (sxx +
    syy), plane stress has szz = 0) or (..., 6) in 3D."""
    s = np.asarray(stress, dtype=float)
    if s.shape[-1] == 6:
        sxx, syy, szz, syz, sxz, sxy = (s[..., k] for k in range(6))
        shear = syz**2 + sxz**2 + sxy**2
    else:
        sxx, syy, sxy = s[..., 0], s[..., 1], s[..., 2]
        szz = np.asarray(poissons_ratio) * (sxx + syy) if model == "plane_strain" else np.zeros_like(sxx)
        shear = sxy**2
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * shear)
