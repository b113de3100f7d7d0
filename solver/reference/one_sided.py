"""A contact region with one complete and one incomplete end on an elastic half-plane (plane
strain or stress, frictionless, E* the composite plane modulus): a punch that reaches one of its
sharp corners while its other end lies on a smooth, rounded stretch (a flat punch with one sharp
and one rounded edge, a tilted flat punch), held against rotation, pressed by P per unit
thickness. A numerical reference built here from the half-plane's singular integral equation.

With the region lo <= s <= hi, s = e + a x (-1 <= x <= 1), the pressure satisfies
(1 / pi) PV int p(t) / (x - t) dt = (E* / 2) h'(e + a x) =: g(x) (Johnson, Contact Mechanics,
1985, eq. 2.25; h the gap, its rigid approach has no slope). With g = b_0 / 2 + sum_k b_k T_k(x)
and the finite Hilbert transform pairs (1/pi) PV int sqrt(1 - t^2) U_(k-1)(t) / (x - t) dt = T_k(x),
(1/pi) PV int T_1(t) / (sqrt(1 - t^2) (x - t)) dt = -1 and (1/pi) PV int dt / (sqrt(1 - t^2) (x - t)) = 0,
every solution is

    p(x) = sqrt(1 - x^2) sum_(k>=1) b_k U_(k-1)(x) - (b_0 / 2) x / sqrt(1 - x^2) + C / sqrt(1 - x^2),

and the end at x = -c (c = +1: the upper end complete) is incomplete, p bounded there, for
C = -c b_0 / 2:

    p(x) = sqrt(1 - x^2) sum_(k>=1) b_k U_(k-1)(x) - c (b_0 / 2) (1 + c x) / sqrt(1 - x^2),
    P = pi a (b_1 / 2 - c b_0 / 2),   K = lim p sqrt(2 pi r) = -c b_0 sqrt(pi a)  (the complete end).

A flat punch tilted by eps (h' = -c eps) gives p = (E* eps / 2) sqrt((1 + c x) / (1 - c x)),
P = pi E* eps a / 2 (Johnson, 1985, sec. 2.8; Barber, Contact Mechanics, 2018, sec. 8.3). The b_k
are computed by Gauss-Chebyshev quadrature on NODES nodes (a kinked gap slope: errors of order
NODES^-2).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

__all__ = ["NODES", "one_sided_coefficients", "one_sided_load", "one_sided_pressure", "one_sided_region",
           "one_sided_stress_intensity"]

#: Gauss-Chebyshev nodes of the gap slope's coefficients
NODES = 1024


def one_sided_coefficients(slope, lo: float, hi: float, e_star: float) -> np.ndarray:
    """b_k (k = 0 .. NODES - 1): the Chebyshev coefficients of (E* / 2) h'(s) on lo <= s <= hi
    (``slope(s)`` = h'(s), vectorised)."""
    theta = (np.arange(NODES) + 0.5) * np.pi / NODES
    x = np.cos(theta)
    g = 0.5 * e_star * np.asarray(slope(0.5 * (lo + hi) + 0.5 * (hi - lo) * x), dtype=float)
    return (2.0 / NODES) * (np.cos(np.outer(np.arange(NODES), theta)) @ g)


def one_sided_pressure(s, slope, lo: float, hi: float, e_star: float, complete: int = 1) -> np.ndarray:
    """The pressure (Pa) at the chords ``s`` of the region lo..hi whose ``complete`` end (+1: hi,
    -1: lo) is singular and the other incomplete; zero outside."""
    b = one_sided_coefficients(slope, lo, hi, e_star)
    a, e = 0.5 * (hi - lo), 0.5 * (hi + lo)
    x = (np.asarray(s, dtype=float) - e) / a
    inside = np.abs(x) < 1.0
    theta = np.arccos(np.clip(x, -1.0, 1.0))
    bounded = np.sin(np.outer(theta, np.arange(1, NODES))) @ b[1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        singular = -complete * 0.5 * b[0] * (1.0 + complete * x) / np.sqrt(1.0 - x * x)
    return np.where(inside, bounded + np.where(inside, singular, 0.0), 0.0)


def one_sided_load(slope, lo: float, hi: float, e_star: float, complete: int = 1) -> float:
    """P (N/m) of the region lo..hi: pi a (b_1 / 2 - c b_0 / 2)."""
    b = one_sided_coefficients(slope, lo, hi, e_star)
    return math.pi * 0.5 * (hi - lo) * 0.5 * (b[1] - complete * b[0])


def one_sided_stress_intensity(slope, lo: float, hi: float, e_star: float, complete: int = 1) -> float:
    """K (Pa m^0.5) of the complete end: -c b_0 sqrt(pi a)."""
    b = one_sided_coefficients(slope, lo, hi, e_star)
    return -complete * float(b[0]) * math.sqrt(math.pi * 0.5 * (hi - lo))


def one_sided_region(load: float, slope, corner: float, e_star: float, complete: int = 1,
                     longest: float = 1.0) -> tuple[float, float]:
    """(lo, hi) of the region with the complete end at the ``corner`` chord that carries ``load``
    (the free end found between the corner and ``longest`` from it)."""
    def excess(length):
        lo, hi = (corner - length, corner) if complete > 0 else (corner, corner + length)
        return one_sided_load(slope, lo, hi, e_star, complete) - load

    length = brentq(excess, 1e-9 * longest, longest, xtol=1e-14 * longest, rtol=1e-13)
    return (corner - length, corner) if complete > 0 else (corner, corner + length)
