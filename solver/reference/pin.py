"""A pin in a bore: the conformal contact of an elastic disk of radius R in a hole of radius
R + dR in an infinite plate of the same material, frictionless, plane strain or stress (Persson,
"On the stress distribution of cylindrical elastic bodies in contact", Chalmers, 1964; the
formulation of Ciavarella and Decuzzi, Int. J. Solids Struct. 38, 2001, 4507-4523). The relation
between the load P (per unit thickness) and the contact semi-angle alpha, derived here from
Michell's harmonic solutions and solved to round-off:

A pressure p(theta) = p_0 + sum_n p_n cos(n theta) on the interface (theta from the contact's
centre) moves the plate's hole out and the pin's rim in by, together (E* the composite plane
modulus 1 / E* = 1 / E1' + 1 / E2', here E' / 2),

    n = 0: p_0 R / E*,     n >= 2: (2 R / E*) p_n n / (n^2 - 1)     (times cos(n theta)),

(the disk's rim under p_n cos(n theta): -(p_n R / 2 mu) (1 / (2 (n - 1)) + kappa / (2 (n + 1))),
the hole's: +(p_n R / 2 mu) (1 / (2 (n + 1)) + kappa / (2 (n - 1))); large n gives the two
half-planes' 2 p_n R / (E* n)); the n = 1 terms (the load's) only translate the pin. In contact,
|theta| <= alpha,

    dR (1 - cos theta) - d cos theta + p_0 R / E* + (2 R / E*) sum_(n>=2) p_n n / (n^2 - 1) cos(n theta) = 0

with d the pin's approach, and P = pi R p_1. Differentiated, sum_n p_n sin(n theta) is the circle's
Cauchy integral (1 / 2 pi) PV int p(phi) cot((theta - phi) / 2) dphi, which y = tan(theta / 2)
maps to the straight one (1 / pi) PV int p dy / (y_theta - y) (for an even p); the pressure
bounded at both ends is sought as p = sum_k c_k sqrt(1 - y^2 / b^2) U_(k - 1)(y / b),
b = tan(alpha / 2), k odd (each term's Cauchy integral is T_k(y / b)), with the remaining
series summed over the harmonics. Least squares at collocation points with the equation at
theta = 0 for d; 12 terms and 1500 harmonics give P to 1e-8 relative (checked against 24 and
3000). Small angles give Hertz's P = pi E* dR alpha^2 / 4 (R* = R (R + dR) / dR): 1.0014 of it at
0.05 rad; at 0.55 rad Persson's P is 1.19 times Hertz's, so for a given load Hertz's angle is 9 %
too large.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq

__all__ = ["MAX_ANGLE", "pin_in_bore_load", "pin_in_bore_angle", "pin_in_bore_pressure"]

#: the largest contact semi-angle (rad) solved: towards pi / 2 the load grows without bound and
#: the truncated series loses accuracy (the solution is monotone and converged to 1e-8 up to here)
MAX_ANGLE = 1.4


@lru_cache(maxsize=16)
def _solution(alpha: float, terms: int = 12, harmonics: int = 1500, nodes: int = 8192):
    """The pressure's coefficients c_k (k = 1, 3, ..: p / (E* dR / R) = sum c_k sin(k u),
    y = b cos(u)) and P / (E* dR) for the contact semi-angle alpha (independent of R)."""
    b = math.tan(0.5 * alpha)
    tau = (np.arange(nodes) + 0.5) * np.pi / nodes
    phi = 2.0 * np.arctan(b * np.cos(tau))
    ks = np.arange(1, 2 * terms, 2)
    weight = (2.0 * b / np.pi) * np.sin(tau) / (1.0 + (b * np.cos(tau)) ** 2) * (np.pi / nodes)
    n = np.arange(harmonics + 1)
    pn = (np.sin(np.outer(ks, tau)) * weight) @ np.cos(np.outer(phi, n))  # (terms, n): (1/pi) int p cos(n phi)
    m = 3 * terms
    y = b * np.cos((np.arange(m) + 0.5) * np.pi / (2 * m))  # collocation in 0 < theta < alpha
    theta = 2.0 * np.arctan(y)
    higher = n[2:]
    cauchy = np.cos(np.outer(np.arccos(np.clip(y / b, -1.0, 1.0)), ks))
    rest = np.sin(np.outer(theta, higher)) @ (pn[:, 2:] / (higher**2 - 1.0)).T
    a = np.zeros((m + 1, terms + 1))
    rhs = np.zeros(m + 1)
    a[:m, :terms] = -2.0 * (cauchy - np.outer(np.sin(theta), pn[:, 1]) + rest)
    a[:m, terms] = np.sin(theta)
    rhs[:m] = -np.sin(theta)
    a[m, :terms] = 0.5 * pn[:, 0] + 2.0 * pn[:, 2:] @ (higher / (higher**2 - 1.0))
    a[m, terms] = -1.0
    solution = np.linalg.lstsq(a, rhs, rcond=None)[0]
    return solution[:terms], math.pi * float(solution[:terms] @ pn[:, 1])


def _dimensionless_load(alpha: float, terms: int = 12, harmonics: int = 1500) -> float:
    """P / (E* dR) for the contact semi-angle alpha."""
    return _solution(float(alpha), terms, harmonics)[1]


def pin_in_bore_load(angle: float, clearance: float, e_star: float) -> float:
    """Load per unit thickness P (N/m) that makes the contact semi-angle ``angle`` (rad, below pi / 2)
    for the radial ``clearance`` dR (m) and composite plane modulus E* (Pa)."""
    if not 0.0 < angle <= MAX_ANGLE:
        raise ValueError(f"the contact semi-angle must lie in (0, {MAX_ANGLE}] rad, got {angle}")
    return e_star * clearance * _dimensionless_load(angle)


def pin_in_bore_angle(load: float, clearance: float, e_star: float) -> float:
    """Contact semi-angle (rad) of the load P (the root of pin_in_bore_load, increasing in the angle)."""
    if not load > 0.0:
        raise ValueError(f"the load must be positive, got {load}")
    if not load <= pin_in_bore_load(MAX_ANGLE, clearance, e_star):
        raise ValueError(f"the load {load} N/m makes a contact semi-angle beyond {MAX_ANGLE} rad (not tabulated)")
    return float(brentq(lambda t: pin_in_bore_load(t, clearance, e_star) - load, 1e-4, MAX_ANGLE,
                        xtol=1e-13, rtol=1e-13))


def pin_in_bore_pressure(theta, angle: float, radius: float, clearance: float, e_star: float) -> np.ndarray:
    """The contact pressure (Pa) at the angles ``theta`` (rad, from the contact's centre) for the
    contact semi-angle ``angle``, pin ``radius`` R and radial ``clearance`` dR: sum_k c_k sin(k u)
    with tan(theta / 2) = tan(angle / 2) cos(u), times E* dR / R; zero outside the region."""
    if not 0.0 < angle <= MAX_ANGLE:
        raise ValueError(f"the contact semi-angle must lie in (0, {MAX_ANGLE}] rad, got {angle}")
    coefficients = _solution(float(angle))[0]
    x = np.tan(0.5 * np.asarray(theta, dtype=float)) / math.tan(0.5 * angle)
    u = np.arccos(np.clip(x, -1.0, 1.0))
    p = np.sin(np.outer(u, np.arange(1, 2 * len(coefficients), 2))) @ coefficients
    return np.where(np.abs(x) < 1.0, p.reshape(np.shape(x)) * e_star * clearance / radius, 0.0)
