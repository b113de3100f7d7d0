"""The pressure integral of an axisymmetric punch with a flat of radius b on a half-space:

    I(r) = int_{max(r, b)}^a K(t) / sqrt(t^2 - r^2) dt,

with K the profile's kernel (the closed forms of the rounded and the chamfered punch supply their
own). Evaluated by Gauss-Legendre in v with t = t0 + (a - t0) v^2, t0 = max(r, b): dt /
sqrt(t^2 - r^2) = 2 (a - t0) v dv / sqrt((t - r) (t + r)), which removes the inverse square root
at t = r and a square-root onset of K at t = b. The differences t - r and t - b are formed as
(t0 - r) + (a - t0) v^2 and (t0 - b) + (a - t0) v^2, apart from round-off.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["flat_punch_integral"]


def flat_punch_integral(r: np.ndarray, a: float, b: float, kernel: Callable[[np.ndarray, np.ndarray], np.ndarray],
                        points: int) -> np.ndarray:
    """I(r) at the radii r (0 at and beyond a); ``kernel(t, t - b)`` the profile's K on arrays of
    the quadrature's t (one row per radius), ``points`` Gauss-Legendre points."""
    r = np.abs(np.asarray(r, dtype=float))
    v, w = np.polynomial.legendre.leggauss(points)
    v, w = 0.5 * (v + 1.0), 0.5 * w
    t0 = np.maximum(r, b)[:, None]
    span = np.clip(a - t0, 0.0, None)
    t = t0 + span * v[None, :] ** 2
    rr = np.minimum(r, a)[:, None]
    root = np.sqrt((t0 - rr + span * v[None, :] ** 2) * (t + rr))
    jac = np.divide(2.0 * span * v[None, :], root, out=np.zeros_like(root), where=root > 0.0)
    integral = (kernel(t, t0 - b + span * v[None, :] ** 2) * jac) @ w
    return np.where(r < a, integral, 0.0)
