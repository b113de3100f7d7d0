"""The pressure that Coulomb's law uses on a contact ellipse with friction history (3D): the
point pressures of the region's quadrature points replaced by the region's own edge-consistent
representation.

Why: the point pressure is the normal component of the band terms' traction, the mean of the two
bodies' trilinear stresses plus the tie's penalty on the remaining gap. A trilinear cell cannot
follow the square root with which the pressure vanishes at the region's edge: on the half
sphere at a / h = 5.8 the point pressures carry 0.6 % of N beyond 0.95 a (Hertz: 3.0 %) and
5 % too much between 0.8 a and 0.95 a, and about 1.2 % of N is tensile. The friction of a slip
annulus, mu p within a fraction of a cell of the edge, is then too small.

What: a region of size a is searched until its edge coefficient vanishes, i.e. until the
pressure has no inverse square root at the edge (solver.contact.ellipse). A pressure with a
vanishing edge coefficient is p = sqrt(1 - X^2 - Y^2) P(X, Y) (X = s0 / a, Y = s1 / b from the
ellipse's centre); with P quadratic this holds Hertz's p0 sqrt(1 - X^2 - Y^2) and its tilts and
second-order changes. The fitted pressure is the member of that family with the point
pressures' moments up to the second order:

    int p_fit X^i Y^j dA = int p X^i Y^j dA,   i + j <= 2,

so it transmits the same normal force and the same moments as the terms' traction (a
Petrov-Galerkin projection, linear in the contact dofs: p_fit = B (R x + r0), B (q, 6) the
basis at the points, R (6, m) and r0 (6,) the moments' rows, m the contact dofs).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["PressureFit", "pressure_fit", "low_rank"]

#: the moment matrix's condition number above which the fit falls back to the constant alone
#: (a region of a few points)
MAX_CONDITION = 1e10


@dataclass
class PressureFit:
    """p_fit = basis @ (rows @ x + load) at a region's quadrature points."""

    basis: np.ndarray  # (q, k) sqrt(1 - rho^2) times the monomials at the points
    rows: np.ndarray  # (k, m) the fitted coefficients' rows on the contact dofs
    load: np.ndarray  # (k,) their constant part

    def pressure(self, x: np.ndarray) -> np.ndarray:
        """The fitted pressure (q,) for contact dof values x."""
        return self.basis @ (self.rows @ x + self.load)


def _monomials(local: np.ndarray, semi_axes: tuple[float, float]) -> np.ndarray:
    """1, X, Y, X^2, X Y, Y^2 at points (q, 2) of the tangent plane from the ellipse's centre."""
    x, y = local[:, 0] / semi_axes[0], local[:, 1] / semi_axes[1]
    return np.column_stack([np.ones_like(x), x, y, x * x, x * y, y * y])


def pressure_fit(local: np.ndarray, semi_axes: tuple[float, float], weights: np.ndarray, rows,
                 load: np.ndarray) -> PressureFit:
    """The fit of the point pressures p = rows x + load (rows a sparse (q, m) operator) at points
    ``local`` (q, 2) with quadrature weights (q,) on the ellipse of ``semi_axes``."""
    mono = _monomials(local, semi_axes)
    rho2 = mono[:, 1] ** 2 + mono[:, 2] ** 2
    basis = np.sqrt(np.clip(1.0 - rho2, 0.0, None))[:, None] * mono
    tests = mono * weights[:, None]  # (q, 6): the moments' weights
    moments = tests.T @ basis  # (6, 6): int X^i Y^j basis_k dA
    if not np.isfinite(moments).all() or np.linalg.cond(moments) > MAX_CONDITION:
        basis, tests, moments = basis[:, :1], tests[:, :1], moments[:1, :1]
    solve = np.linalg.solve(moments, tests.T)  # (k, q): coefficients from point pressures
    return PressureFit(basis=basis, rows=np.asarray((rows.T @ solve.T).T), load=solve @ load)


def low_rank(left: np.ndarray, right: np.ndarray, m: int):
    """left (m, k) @ right (k, m) as a sparse matrix over the rows and columns the factors touch."""
    r = np.flatnonzero(np.any(left != 0.0, axis=1))
    c = np.flatnonzero(np.any(right != 0.0, axis=0))
    if not len(r) or not len(c):
        return sp.csr_matrix((m, m))
    block = left[r] @ right[:, c]
    rr = np.repeat(r, len(c))
    cc = np.tile(c, len(r))
    return sp.csr_matrix((block.ravel(), (rr, cc)), shape=(m, m))
