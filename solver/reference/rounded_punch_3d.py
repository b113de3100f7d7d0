"""The axisymmetric flat punch with a rounded edge on an elastic half-space, frictionless (E* the
composite modulus 1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2).

The punch is flat out to the radius b and its edge is rounded with radius R: the gap
f(r) = 0 for r <= b and (r - b)^2 / (2 R) beyond (the circle's parabolic approximation, as in
Hertz's theory). Its contact is incomplete, r <= a with a > b, and the pressure falls to zero at
r = a with a square root. The closed form is Ciavarella, Hills and Monno, "The influence of rounded
edges on indentation by a flat punch", Proc. IMechE C 212 (1998) 319-328; it is derived here by
the classical method for an axisymmetric punch of profile f(r) (Sneddon, "The relation between load
and penetration in the axisymmetric Boussinesq problem for a punch of arbitrary profile",
Int. J. Eng. Sci. 3 (1965) 47-57; Johnson, Contact Mechanics, 1985, section 5.2):

    g(t) = d - t int_0^t f'(x) / sqrt(t^2 - x^2) dx,
    p(r) = (E* / pi) [g(a) / sqrt(a^2 - r^2) - int_r^a g'(t) / sqrt(t^2 - r^2) dt],
    P = 2 E* int_0^a x^2 f'(x) / sqrt(a^2 - x^2) dx,

with the approach d fixed by a pressure bounded at r = a (g(a) = 0). For f' = (x - b) / R beyond b,
int_b^t (x - b) / sqrt(t^2 - x^2) dx = sqrt(t^2 - b^2) - b arccos(b / t), so

    d = (a / R) (sqrt(a^2 - b^2) - b arccos(b / a)),
    g'(t) = -(2 sqrt(t^2 - b^2) - b arccos(b / t)) / R  for t > b (0 inside the flat),
    P = (2 E* / R) (sqrt(a^2 - b^2) (4 a^2 - b^2) / 6 - a^2 b arccos(b / a) / 2),
    p(r) = (E* / (pi R)) int_{max(r, b)}^a (2 sqrt(t^2 - b^2) - b arccos(b / t)) / sqrt(t^2 - r^2) dt.

b = 0 gives Hertz's sphere (P = 4 E* a^3 / (3 R), p = (2 E* / (pi R)) sqrt(a^2 - r^2)); R -> 0
the flat punch with sharp edges (p = P / (2 pi b sqrt(b^2 - r^2))). The pressure's integral is
evaluated by Gauss-Legendre in v with t = t0 + (a - t0) v^2, t0 = max(r, b), which removes both
the square-root singularity at t = r and the square-root onset at t = b.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from .abel import flat_punch_integral

__all__ = ["rounded_punch_3d_load", "rounded_punch_3d_radius", "rounded_punch_3d_approach",
           "rounded_punch_3d_pressure"]

#: Gauss-Legendre points of the pressure's integral
PRESSURE_POINTS = 96


def _check(a: float, b: float, radius: float) -> None:
    if not (b >= 0.0 and radius > 0.0 and a >= b):
        raise ValueError(f"a rounded punch needs 0 <= b <= a and R > 0 (got a = {a}, b = {b}, R = {radius})")


def rounded_punch_3d_load(a: float, b: float, radius: float, e_star: float) -> float:
    """The load P (N) that makes the contact radius a (a >= b) under a punch flat to the radius b
    with its edge rounded with radius R."""
    _check(a, b, radius)
    root = math.sqrt(max(a * a - b * b, 0.0))
    angle = math.acos(min(b / a, 1.0)) if a > 0.0 else 0.0
    return 2.0 * e_star / radius * (root * (4.0 * a * a - b * b) / 6.0 - 0.5 * a * a * b * angle)


def rounded_punch_3d_approach(a: float, b: float, radius: float) -> float:
    """The approach d of the two bodies (far points) at the contact radius a."""
    _check(a, b, radius)
    if a == 0.0:
        return 0.0
    return a / radius * (math.sqrt(a * a - b * b) - b * math.acos(min(b / a, 1.0)))


def rounded_punch_3d_radius(load: float, b: float, radius: float, e_star: float) -> float:
    """The contact radius a (m) under the load P (N): the root of P(a) = P, which grows with a."""
    if not load > 0.0:
        raise ValueError(f"a rounded punch's load must be positive (got {load} N)")
    hi = max(b, (3.0 * load * radius / (4.0 * e_star)) ** (1.0 / 3.0)) + 1e-12
    while rounded_punch_3d_load(hi, b, radius, e_star) < load:
        hi = b + 2.0 * (hi - b) + 1e-12
    return float(brentq(lambda a: rounded_punch_3d_load(a, b, radius, e_star) - load, b, hi, xtol=1e-15 * hi,
                        rtol=1e-14))


def rounded_punch_3d_pressure(r: np.ndarray, a: float, b: float, radius: float, e_star: float) -> np.ndarray:
    """The contact pressure p(r) (Pa) at the radii r (0 beyond a)."""
    _check(a, b, radius)

    def kernel(t, t_minus_b):  # 2 sqrt(t^2 - b^2) - b arccos(b / t)
        angle = np.arccos(np.clip(b / np.maximum(t, 1e-300), -1, 1))
        return 2.0 * np.sqrt(np.clip(t * t - b * b, 0.0, None)) - b * angle

    return e_star / (math.pi * radius) * flat_punch_integral(r, a, b, kernel, PRESSURE_POINTS)
