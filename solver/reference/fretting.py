"""Closed forms for a cylinder on a flat (2D line contact, elastically similar bodies) under a
constant normal load N and a tangential load Q that varies: the Cattaneo-Mindlin solution and its
superposition along a load history (the 2D form of Mindlin-Deresiewicz's).

Source: K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985, ch. 7: section 7.1
(Cattaneo-Mindlin for cylinders, the shear as the difference of two semi-ellipses) and section 7.3
(oscillating tangential force: each change of direction adds twice a Cattaneo solution of half
the change in Q). Here derived per unit length for the line contact.

Per unit length, with p0 = 2 N / (pi a) and k = mu p0 / a, let the semi-ellipse of half-width b be

    f(x; b) = k sqrt(b^2 - x^2)   (|x| < b),   0 outside.

Loading from 0 to Q (Cattaneo): q = f(x; a) - f(x; c), c / a = sqrt(1 - |Q| / (mu N)). A branch
from a turning point Q_t to Q adds 2 sign(Q - Q_t) [f(x; a) - f(x; c')] with
c' / a = sqrt(1 - |Q - Q_t| / (2 mu N)): the shear of a
history is the first loading term plus one such term per branch.

Slip. The relative tangential surface displacement h of two similar half-planes under the shear
q obeys dh/dx = (2 / (pi E*)) PV int q(xi) / (x - xi) dxi (the normal pressure does not couple for
similar materials). For f(x; b) the principal value is pi k x inside |x| < b and
pi k (x - sign(x) sqrt(x^2 - b^2)) outside, so a Cattaneo term f(a) - f(b) slips only at |x| > b,
by

    S(x; b) = (mu / (2 R)) [|x| sqrt(x^2 - b^2) - b^2 ln((|x| + sqrt(x^2 - b^2)) / b)]

(k / E* = mu / (2 R) with a^2 = 4 N R / (pi E*)), the slip relative to the stick zone.

Energy per cycle of Q between +Q* and -Q*: on each branch the annulus c* < |x| < a slips, each
point against mu p(x), by 2 S(x; c*) at the branch's end, so

    W = 2 int_{c* < |x| < a} mu p(x) 2 S(x; c*) dx,   c* / a = sqrt(1 - Q* / (mu N)),

evaluated by Gauss-Legendre quadrature in the variable sqrt(x - c*) (S vanishes as (x - c*)^{3/2}).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["semi_ellipse", "stick_ratio", "branch_stick_ratio", "history_shear", "cattaneo_slip",
           "energy_per_cycle"]


def _check(name: str, value: float, positive: bool = True) -> float:
    v = float(value)
    if not math.isfinite(v) or (positive and not v > 0.0):
        raise ValueError(f"{name} must be a {'positive ' if positive else ''}finite number, got {value!r}")
    return v


def semi_ellipse(x, b: float, k: float) -> np.ndarray:
    """f(x; b) = k sqrt(b^2 - x^2) inside |x| < b, zero outside."""
    x = np.asarray(x, dtype=float)
    return k * np.sqrt(np.clip(b * b - x * x, 0.0, None))


def stick_ratio(Q: float, N: float, mu: float) -> float:
    """Cattaneo-Mindlin c / a = sqrt(1 - |Q| / (mu N)) on first loading (0 at gross slip)."""
    N, mu = _check("N", N), _check("mu", mu)
    return math.sqrt(max(0.0, 1.0 - abs(float(Q)) / (mu * N)))


def branch_stick_ratio(Q: float, Q_turn: float, N: float, mu: float) -> float:
    """c' / a = sqrt(1 - |Q - Q_turn| / (2 mu N)) on a branch that left the turning point Q_turn."""
    N, mu = _check("N", N), _check("mu", mu)
    return math.sqrt(max(0.0, 1.0 - abs(float(Q) - float(Q_turn)) / (2.0 * mu * N)))


def history_shear(x, a: float, N: float, mu: float, turning: list[float], Q: float) -> tuple[np.ndarray, float]:
    """Shear q(x) (the traction applied to the flat along +x, in the direction of Q) after the
    turning points ``turning`` (Q_1, Q_2, ...: the extremes reached so far, the first from 0) at the
    current Q; and the stick half-width of the current branch. Constant N; each branch's range
    within the gross-slip limit (2 mu N after the first)."""
    a, N, mu = _check("a", a), _check("N", N), _check("mu", mu)
    k = mu * (2.0 * N / (math.pi * a)) / a
    points = [0.0] + [float(t) for t in turning] + [float(Q)]
    q = np.zeros_like(np.asarray(x, dtype=float))
    c = a
    for i, (qa, qb) in enumerate(zip(points[:-1], points[1:])):
        weight = 1.0 if i == 0 else 2.0
        ratio = math.sqrt(max(0.0, 1.0 - abs(qb - qa) / (weight * mu * N)))
        c = ratio * a
        if qb != qa:
            q = q + math.copysign(weight, qb - qa) * (semi_ellipse(x, a, k) - semi_ellipse(x, c, k))
    return q, c


def cattaneo_slip(x, b: float, mu: float, R: float) -> np.ndarray:
    """S(x; b): slip of a Cattaneo term f(a) - f(b) relative to its stick zone |x| < b (zero there)."""
    x = np.abs(np.asarray(x, dtype=float))
    b, mu, R = _check("b", b), _check("mu", mu), _check("R", R)
    root = np.sqrt(np.clip(x * x - b * b, 0.0, None))
    out = x * root - b * b * np.log(np.maximum(x + root, b) / b)
    return np.where(x > b, mu / (2.0 * R) * out, 0.0)


def energy_per_cycle(Q_amplitude: float, N: float, mu: float, R: float, E_eff: float, points: int = 64) -> float:
    """W per unit length dissipated by one cycle of Q between +Q* and -Q* under constant N."""
    N, mu, R, E_eff = _check("N", N), _check("mu", mu), _check("R", R), _check("E_eff", E_eff)
    qs = abs(float(Q_amplitude))
    if qs >= mu * N:
        raise ValueError(f"Q_amplitude = {Q_amplitude!r} reaches gross slip (mu N = {mu * N:g})")
    a = math.sqrt(4.0 * N * R / (math.pi * E_eff))
    p0 = 2.0 * N / (math.pi * a)
    c = a * math.sqrt(1.0 - qs / (mu * N))
    if c >= a:
        return 0.0
    g, wg = np.polynomial.legendre.leggauss(points)
    r = 0.5 * (g + 1.0) * math.sqrt(a - c)  # x = c + r^2, dx = 2 r dr
    x = c + r * r
    integrand = mu * p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None)) * 2.0 * cattaneo_slip(x, c, mu, R)
    one_side = float(np.sum(wg * 0.5 * math.sqrt(a - c) * integrand * 2.0 * r))
    return 2.0 * 2.0 * one_side
