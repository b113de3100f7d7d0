"""Closed forms of 2D punches on an elastic half-plane (plane strain or stress, frictionless,
E* the composite plane modulus 1 / E* = 1 / E1' + 1 / E2').

Rounded flat punch: a flat of half-width b whose edges are rounded with radius R, the gap
h(x) = 0 for |x| <= b and (|x| - b)^2 / (2 R) beyond, pressed by P per unit thickness; an
incomplete contact |x| <= a (Ciavarella, Hills and Monno, "The influence of rounded edges on
indentation by a flat punch", Proc. IMechE C 212 (1998) 319-328). With the half-plane relation
int p(t) / (x - t) dt = (pi E* / 2) h'(x) and the pressure bounded at both ends,

    P = (E* a^2 / (2 R)) (pi / 2 - phi0 - sin(phi0) cos(phi0)),   sin(phi0) = b / a,

    p(x) = (E* / (2 pi)) sqrt(a^2 - x^2) PV int h'(t) / (sqrt(a^2 - t^2) (t - x)) dt,

the principal value in closed form with the antiderivative
int dt / ((t - x) sqrt(a^2 - t^2)) = -ln|(a^2 - x t + sqrt(a^2 - x^2) sqrt(a^2 - t^2)) / (t - x)| / sqrt(a^2 - x^2).
b = 0 is Hertz's cylinder, p = (E* / (2 R)) sqrt(a^2 - x^2).

Sharp flat punch, rigid against the half-plane (Sadowsky 1928, Z. angew. Math. Mech. 8, 107-121;
Johnson, Contact Mechanics, 1985, eq. 2.64): p(x) = P / (pi sqrt(b^2 - x^2)), square-root
singular at the corners; the stress intensity of each corner K = lim p sqrt(2 pi r) = P / sqrt(pi b).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

__all__ = [
    "rounded_punch_load",
    "rounded_punch_half_width",
    "rounded_punch_pressure",
    "flat_punch_pressure",
    "flat_punch_stress_intensity",
]


def rounded_punch_load(a: float, b: float, radius: float, e_star: float) -> float:
    """Load per unit thickness P (N/m) that makes the contact half-width a (a >= b)."""
    if not a >= b >= 0.0:
        raise ValueError(f"the contact half-width a = {a} must reach the flat's half-width b = {b}")
    phi0 = math.asin(b / a) if a > 0.0 else 0.0
    return e_star * a * a / (2.0 * radius) * (0.5 * math.pi - phi0 - math.sin(phi0) * math.cos(phi0))


def rounded_punch_half_width(load: float, b: float, radius: float, e_star: float) -> float:
    """Contact half-width a of the load P (the root of rounded_punch_load, increasing in a)."""
    if not load > 0.0:
        raise ValueError(f"the load must be positive, got {load}")
    hi = max(2.0 * b, 1e-300)
    while rounded_punch_load(hi, b, radius, e_star) < load:
        hi *= 2.0
    return float(brentq(lambda a: rounded_punch_load(a, b, radius, e_star) - load, b, hi, xtol=1e-15 * hi, rtol=1e-15))


def _log_part(t, x, a):
    r = np.sqrt(a * a - x * x)
    return -np.log(np.abs((a * a - x * t + r * np.sqrt(np.maximum(a * a - t * t, 0.0))) / (t - x))) / r


def rounded_punch_pressure(x, a: float, b: float, radius: float, e_star: float) -> np.ndarray:
    """Pressure (Pa) at x (|x| < a; zero outside) of the rounded flat punch with contact half-width a."""
    x = np.asarray(x, dtype=float)
    inside = np.abs(x) < a
    xi = np.where(inside, x, 0.0)
    phi0 = math.asin(b / a)
    with np.errstate(divide="ignore", invalid="ignore"):
        right = _log_part(a, xi, a) - _log_part(b, xi, a)
        left = _log_part(-b, xi, a) - _log_part(-a, xi, a)
        total = (2.0 * (0.5 * math.pi - phi0) + (xi - b) * np.nan_to_num(right) + (xi + b) * np.nan_to_num(left)) / radius
    return np.where(inside, e_star / (2.0 * math.pi) * np.sqrt(np.maximum(a * a - xi * xi, 0.0)) * total, 0.0)


def flat_punch_pressure(x, load: float, b: float) -> np.ndarray:
    """Sadowsky's pressure P / (pi sqrt(b^2 - x^2)) of a rigid flat punch of half-width b (zero outside)."""
    x = np.asarray(x, dtype=float)
    inside = np.abs(x) < b
    return np.where(inside, load / (math.pi * np.sqrt(np.where(inside, b * b - x * x, 1.0))), 0.0)


def flat_punch_stress_intensity(load: float, b: float) -> float:
    """K = lim p sqrt(2 pi r) = P / sqrt(pi b) at each corner of a rigid flat punch (Pa m^0.5)."""
    return load / math.sqrt(math.pi * b)
