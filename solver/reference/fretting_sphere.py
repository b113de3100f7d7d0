"""Closed forms for a sphere on a flat (3D point contact, elastically similar bodies) under a
constant normal load N and a tangential load Q that varies: Cattaneo-Mindlin on first loading and
Mindlin-Deresiewicz's superposition along a load history.

Sources: R. D. Mindlin, H. Deresiewicz, "Elastic spheres in contact under varying oblique forces",
J. Appl. Mech. 20 (1953) 327-344; K. L. Johnson, *Contact Mechanics*, Cambridge University Press,
1985, sections 7.2 (Cattaneo-Mindlin for spheres) and 7.3 (oscillating tangential force).

Hertz: a^3 = 3 N R / (4 E*), p(r) = p0 sqrt(1 - r^2 / a^2), p0 = 3 N / (2 pi a^2). With
g(r; b) = (3 mu N / (2 pi a^3)) sqrt(b^2 - r^2) (zero for r > b), first loading to Q gives the
shear q = g(r; a) - g(r; c) along Q, c / a = (1 - |Q| / (mu N))^(1/3). A branch from a turning
point Q_t to Q adds 2 sign(Q - Q_t) [g(r; a) - g(r; c')] with c' / a = (1 - |Q - Q_t| / (2 mu N))^(1/3).

Tangential compliance (the relative displacement delta of distant points of the two bodies along
Q), with 1 / G* = (2 - nu1) / G1 + (2 - nu2) / G2 (for similar bodies (2 - nu) / G = 1 / (2 G*)):

    first loading   delta = sign(Q) (3 mu N / (16 a G*)) [1 - (1 - |Q| / (mu N))^(2/3)]
    a branch        delta = delta_t + sign(Q - Q_t) (3 mu N / (8 a G*)) [1 - (1 - |Q - Q_t| / (2 mu N))^(2/3)]

so the tangential stiffness dQ / d delta is 8 a G* (c / a) on every branch (c the branch's stick
radius), 8 a G* at its start (Mindlin). The energy per cycle of Q between +Q* and -Q* is the area
of the loop these branches draw (Masing's rule: each branch is the first loading curve scaled by
two), x = Q* / (mu N):

    W = (9 mu^2 N^2 / (10 a G*)) [1 - (1 - x)^(5/3) - (5 x / 6) (1 + (1 - x)^(2/3))],

the form of Mindlin and Deresiewicz's result (Johnson's eq. 7.47) with its coefficient fixed by
the compliance above; its small-amplitude limit is W = Q*^3 / (36 a G* mu N), from the quadratic
term of the first loading curve, delta = Q / (8 a G*) + Q^2 / (48 a G* mu N) + ...
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["hertz_radius", "effective_shear_modulus", "stick_ratio", "branch_stick_ratio", "history_shear",
           "tangential_displacement", "tangential_stiffness", "energy_per_cycle", "small_amplitude_energy",
           "displacement_from_stick_radii"]


def _check(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def hertz_radius(N: float, R: float, E_eff: float) -> float:
    """Hertz's contact radius a = (3 N R / (4 E*))^(1/3) of a sphere of radius R on a flat."""
    return (3.0 * _check("N", N) * _check("R", R) / (4.0 * _check("E_eff", E_eff))) ** (1.0 / 3.0)


def effective_shear_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """G* with 1 / G* = (2 - nu1) / G1 + (2 - nu2) / G2, G = E / (2 (1 + nu))."""
    g1, g2 = _check("E1", E1) / (2.0 * (1.0 + nu1)), _check("E2", E2) / (2.0 * (1.0 + nu2))
    return 1.0 / ((2.0 - nu1) / g1 + (2.0 - nu2) / g2)


def _ratio(dq: float, limit: float) -> float:
    return max(0.0, 1.0 - abs(dq) / limit) ** (1.0 / 3.0)


def stick_ratio(Q: float, N: float, mu: float) -> float:
    """Cattaneo-Mindlin c / a = (1 - |Q| / (mu N))^(1/3) on first loading (0 at gross slip)."""
    return _ratio(float(Q), _check("mu", mu) * _check("N", N))


def branch_stick_ratio(Q: float, Q_turn: float, N: float, mu: float) -> float:
    """c' / a = (1 - |Q - Q_turn| / (2 mu N))^(1/3) on a branch that left the turning point Q_turn."""
    return _ratio(float(Q) - float(Q_turn), 2.0 * _check("mu", mu) * _check("N", N))


def _branches(turning: list[float], Q: float):
    """(weight, Q at the branch's start, Q now or at its end) of the first loading and each branch."""
    points = [0.0] + [float(t) for t in turning] + [float(Q)]
    return [(1.0 if i == 0 else 2.0, qa, qb) for i, (qa, qb) in enumerate(zip(points[:-1], points[1:]))]


def history_shear(r, a: float, N: float, mu: float, turning: list[float], Q: float) -> tuple[np.ndarray, float]:
    """Shear q(r) along the direction of Q (on the flat) after the turning points ``turning``
    (the extremes reached so far, the first from 0) at the current Q, and the stick radius of the
    current branch. Constant N; each branch's range within gross slip (2 mu N after the first)."""
    a, N, mu = _check("a", a), _check("N", N), _check("mu", mu)
    r = np.asarray(r, dtype=float)
    k = 3.0 * mu * N / (2.0 * math.pi * a ** 3)

    def g(b):
        return k * np.sqrt(np.clip(b * b - r * r, 0.0, None))

    q, c = np.zeros_like(r), a
    for weight, qa, qb in _branches(turning, Q):
        c = a * _ratio(qb - qa, weight * mu * N)
        if qb != qa:
            q = q + math.copysign(weight, qb - qa) * (g(a) - g(c))
    return q, c


def tangential_displacement(Q: float, N: float, mu: float, a: float, G_eff: float, turning: list[float] = ()) -> float:
    """delta at Q after the turning points ``turning`` (the module's compliance, summed per branch)."""
    N, mu, a, G_eff = _check("N", N), _check("mu", mu), _check("a", a), _check("G_eff", G_eff)
    scale = 3.0 * mu * N / (16.0 * a * G_eff)
    delta = 0.0
    for weight, qa, qb in _branches(list(turning), Q):
        if qb != qa:
            delta += math.copysign(weight, qb - qa) * scale * (1.0 - _ratio(qb - qa, weight * mu * N) ** 2)
    return delta


def tangential_stiffness(Q: float, N: float, mu: float, a: float, G_eff: float, turning: list[float] = ()) -> float:
    """dQ / d delta = 8 a G* (c / a) on the current branch (c its stick radius)."""
    _, c = history_shear(np.zeros(1), a, N, mu, list(turning), Q)
    return 8.0 * _check("a", a) * _check("G_eff", G_eff) * c / a


def energy_per_cycle(Q_amplitude: float, N: float, mu: float, a: float, G_eff: float) -> float:
    """W dissipated by one cycle of Q between +Q* and -Q* under constant N (module's docstring)."""
    N, mu, a, G_eff = _check("N", N), _check("mu", mu), _check("a", a), _check("G_eff", G_eff)
    x = abs(float(Q_amplitude)) / (mu * N)
    if x >= 1.0:
        raise ValueError(f"Q_amplitude = {Q_amplitude!r} reaches gross slip (mu N = {mu * N:g})")
    if x < 0.1:  # the bracket cancels to 5 x^3 / 162 + ...: its power series avoids the round-off
        bracket = _bracket_series(x)
    else:
        bracket = 1.0 - (1.0 - x) ** (5.0 / 3.0) - (5.0 * x / 6.0) * (1.0 + (1.0 - x) ** (2.0 / 3.0))
    return 9.0 * mu * mu * N * N / (10.0 * a * G_eff) * bracket


def _binomial_terms(alpha: float, n: int) -> np.ndarray:
    """Coefficients of x^k, k < n, in (1 - x)^alpha."""
    out = np.ones(n)
    for k in range(1, n):
        out[k] = out[k - 1] * (k - 1 - alpha) / k
    return out


def _bracket_series(x: float, terms: int = 40) -> float:
    """1 - (1 - x)^(5/3) - (5 x / 6) (1 + (1 - x)^(2/3)) as its power series (from x^3)."""
    b53, b23 = _binomial_terms(5.0 / 3.0, terms), _binomial_terms(2.0 / 3.0, terms)
    k = np.arange(3, terms)
    return float(np.sum((-b53[k] - (5.0 / 6.0) * b23[k - 1]) * x ** k))


def small_amplitude_energy(Q_amplitude: float, N: float, mu: float, a: float, G_eff: float) -> float:
    """The limit W = Q*^3 / (36 a G* mu N) of small amplitudes."""
    return abs(float(Q_amplitude)) ** 3 / (36.0 * _check("a", a) * _check("G_eff", G_eff)
                                           * _check("mu", mu) * _check("N", N))


def displacement_from_stick_radii(Q, stick_ratios, branch_starts, a: float, G_eff: float) -> np.ndarray:
    """delta at each step of a sampled load history, from the stick radius c of each step:
    Mindlin's incremental stiffness dQ / d delta = 8 a G* (c / a) integrated over each step by the
    trapezoid rule in a / c. ``Q`` and ``stick_ratios`` (c / a) are per step, the first step at
    Q = 0; ``branch_starts`` are the steps where Q turned (a branch starts fully stuck, c = a,
    as the first loading does). With the closed form's stick radii it converges to
    ``tangential_displacement`` at second order in the step; with a computed contact's radii it
    is the loop a Mindlin contact with those zones would draw, which separates the zones' share
    of a loop's error from the compliance's."""
    a, G_eff = _check("a", a), _check("G_eff", G_eff)
    q, c = np.asarray(Q, dtype=float), np.asarray(stick_ratios, dtype=float)
    if q.shape != c.shape or q.ndim != 1:
        raise ValueError(f"Q and stick_ratios must be 1D of one length, got {q.shape} and {c.shape}")
    if np.any(c <= 0.0) or np.any(c > 1.0 + 1e-12):
        raise ValueError("stick_ratios must lie in (0, 1]")
    start = np.r_[1.0, c[:-1]]
    start[[int(k) + 1 for k in branch_starts if int(k) + 1 < len(c)]] = 1.0
    step = np.diff(q, prepend=q[0]) * 0.5 * (1.0 / start + 1.0 / c)
    return np.cumsum(step) / (8.0 * a * G_eff)
