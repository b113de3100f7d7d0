"""The axisymmetric flat punch with a conical chamfer on an elastic half-space, frictionless (E* the
composite modulus 1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2): the flat face, out to the radius
b, meets the chamfer at an angle, so the region crosses an edge of the punch where its two faces
are not tangent.

The gap is f(r) = 0 for r <= b and k (r - b) beyond (k the chamfer's slope, the tangent of its
angle to the face). By the classical method for an axisymmetric punch of profile f(r) (Sneddon,
"The relation between load and penetration in the axisymmetric Boussinesq problem for a punch of
arbitrary profile", Int. J. Eng. Sci. 3 (1965) 47-57; Johnson, Contact Mechanics, 1985, section
5.2), with int_b^t k / sqrt(t^2 - x^2) dx = k arccos(b / t):

    g(t) = d - k t arccos(b / t)  (t > b),
    d = k a arccos(b / a)  (the pressure bounded at r = a),
    P = 2 E* int_b^a k x^2 / sqrt(a^2 - x^2) dx = E* k (a^2 arccos(b / a) + b sqrt(a^2 - b^2)),
    p(r) = (E* k / pi) int_{max(r, b)}^a (arccos(b / t) + b / sqrt(t^2 - b^2)) / sqrt(t^2 - r^2) dt.

b = 0 is the cone, P = pi E* k a^2 / 2 and p = (E* k / 2) arccosh(a / r) (Johnson eq. 5.25); the
pressure is infinite (logarithmically) at the edge r = b, as at the tip of a cone. The integral is
evaluated by Gauss-Legendre in v with t = t0 + (a - t0) v^2, t0 = max(r, b), which removes the
inverse square root at t0.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from .abel import flat_punch_integral

__all__ = ["chamfered_punch_3d_load", "chamfered_punch_3d_radius", "chamfered_punch_3d_approach",
           "chamfered_punch_3d_pressure"]

#: Gauss-Legendre points of the pressure's integral
PRESSURE_POINTS = 128


def _check(a: float, b: float, slope: float) -> None:
    if not (b >= 0.0 and slope > 0.0 and a >= b):
        raise ValueError(f"a chamfered punch needs 0 <= b <= a and a slope k > 0 (got a = {a}, b = {b}, k = {slope})")


def chamfered_punch_3d_load(a: float, b: float, slope: float, e_star: float) -> float:
    """The load P (N) that makes the contact radius a (a >= b) under a punch flat to the radius b
    with a chamfer of slope k beyond."""
    _check(a, b, slope)
    if a == 0.0:
        return 0.0
    return e_star * slope * (a * a * math.acos(min(b / a, 1.0)) + b * math.sqrt(max(a * a - b * b, 0.0)))


def chamfered_punch_3d_approach(a: float, b: float, slope: float) -> float:
    """The approach d of the two bodies (far points) at the contact radius a."""
    _check(a, b, slope)
    return slope * a * math.acos(min(b / a, 1.0)) if a > 0.0 else 0.0


def chamfered_punch_3d_radius(load: float, b: float, slope: float, e_star: float) -> float:
    """The contact radius a (m) under the load P (N): the root of P(a) = P, which grows with a."""
    if not load > 0.0:
        raise ValueError(f"a chamfered punch's load must be positive (got {load} N)")
    hi = max(2.0 * b, math.sqrt(2.0 * load / (math.pi * e_star * slope))) + 1e-12
    while chamfered_punch_3d_load(hi, b, slope, e_star) < load:
        hi *= 2.0
    return float(brentq(lambda a: chamfered_punch_3d_load(a, b, slope, e_star) - load, b, hi, xtol=1e-15 * hi,
                        rtol=1e-14))


def chamfered_punch_3d_pressure(r: np.ndarray, a: float, b: float, slope: float, e_star: float) -> np.ndarray:
    """The contact pressure p(r) (Pa) at the radii r (0 beyond a; infinite at r = b)."""
    _check(a, b, slope)

    def kernel(t, t_minus_b):  # arccos(b / t) + b / sqrt(t^2 - b^2)
        tb = np.sqrt(t_minus_b * (t + b))
        k = np.arccos(np.clip(b / np.maximum(t, 1e-300), -1.0, 1.0))
        return k + np.divide(b, tb, out=np.zeros_like(tb), where=tb > 0.0)

    return e_star * slope / math.pi * flat_punch_integral(r, a, b, kernel, PRESSURE_POINTS)
