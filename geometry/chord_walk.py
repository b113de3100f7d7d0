"""The chord walk: along a curve from a start parameter, the first point whose straight-line
distance from a given origin equals a given chord (the thesis's cord-length matching of the two
contact boundaries, section 5.2, and ``BoundedCurve.parameter_at_chord``).

One implementation for every curve that offers ``evaluate(t) -> (n, 2)`` and
``derivative(t) -> (n, 2)`` (the exact bounded curves, and the solver's polylines of tessellated
boundaries): the distance is sampled along the walk (a table that may be computed once and reused
for many chords), the first sample interval where distance - chord changes sign (or a sample on
it) brackets the point, and safeguarded Newton on |X(t) - origin|^2 - chord^2 refines it to
round-off (bisection where a Newton step leaves the bracket; quadratic convergence, ~4
evaluations).
"""

from __future__ import annotations

import numpy as np

__all__ = ["walk_distances", "first_crossing"]


def walk_distances(curve, origin: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Distances (m,) from ``origin`` of the curve's points at the walk's parameters ``t``."""
    p = np.asarray(curve.evaluate(np.asarray(t, dtype=float)), dtype=float).reshape(-1, 2)
    return np.hypot(p[:, 0] - origin[0], p[:, 1] - origin[1])


def first_crossing(curve, origin: np.ndarray, chord: np.ndarray, t: np.ndarray, d: np.ndarray,
                   iterations: int = 40) -> np.ndarray:
    """Parameters (n,) of the first point along the walk ``t`` (samples in walk order, within
    which the parameter is continuous: a closed curve's seam must be a sample) whose distance
    from ``origin`` equals each ``chord``; ``d`` the distances at the samples (walk_distances).
    NaN where the walk ends first. Distances within 1e-14 of the chord count as on it."""
    origin = np.asarray(origin, dtype=float)
    chord = np.asarray(chord, dtype=float).ravel()
    t, d = np.asarray(t, dtype=float), np.asarray(d, dtype=float)
    out = np.full(chord.shape, np.nan)
    tol = 1e-14 * (d.max() + np.abs(chord))
    # the first sample on the chord's other side than the walk's start: where the running
    # maximum (a walk starting nearer than the chord) or minimum (farther) first reaches it
    up = d[0] < chord - tol
    j = np.zeros(len(chord), dtype=np.intp)
    j[up] = np.searchsorted(np.maximum.accumulate(d), chord[up] - tol[up], side="left")
    down = d[0] > chord + tol
    j[down] = np.searchsorted(-np.minimum.accumulate(d), -(chord[down] + tol[down]), side="left")
    found = j < len(t)
    j = np.minimum(j, len(t) - 1)
    exact = found & (np.abs(d[j] - chord) <= tol)
    out[exact] = t[j[exact]]
    todo = found & ~exact
    if np.any(todo):
        jj = j[todo]
        out[todo] = _newton_in_bracket(curve, origin, chord[todo], t[jj - 1], t[jj], d[jj - 1], d[jj], iterations)
    return out


def _newton_in_bracket(curve, origin, chord, ta, tb, da, db, iterations: int) -> np.ndarray:
    """Root of g(t) = |X(t) - origin|^2 - chord^2 between ta (g < 0 or > 0) and tb (the other
    sign): Newton from the linear interpolation, bisection where a step leaves the bracket."""
    lo_is_a = da < chord  # the end where g < 0
    a, b = np.where(lo_is_a, ta, tb), np.where(lo_is_a, tb, ta)  # g(a) < 0 <= g(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.clip(np.where(db != da, (chord - da) / (db - da), 0.5), 0.0, 1.0)
    t = ta + frac * (tb - ta)
    for _ in range(iterations):
        x = np.asarray(curve.evaluate(t), float).reshape(-1, 2) - origin
        g = np.einsum("ij,ij->i", x, x) - chord**2
        dg = 2.0 * np.einsum("ij,ij->i", x, np.asarray(curve.derivative(t), float).reshape(-1, 2))
        below = g < 0.0
        a = np.where(below, t, a)
        b = np.where(below, b, t)
        with np.errstate(divide="ignore", invalid="ignore"):
            nt = t - g / dg
        lo_, hi_ = np.minimum(a, b), np.maximum(a, b)
        nt = np.where(np.isfinite(nt) & (nt >= lo_) & (nt <= hi_), nt, 0.5 * (a + b))
        done = np.abs(nt - t) <= 1e-15 * np.maximum(1.0, np.abs(nt))
        t = nt
        if np.all(done):
            break
    return t
