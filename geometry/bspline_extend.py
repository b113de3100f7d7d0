"""Extending a clamped B-spline beyond its parameter domain by the natural continuation of its end
spans (the polynomial, or rational, piece of the first and last span carried on), exactly.

CAD systems trim B-spline faces with curves that may run slightly outside the surface's parameter
domain; the kernels that wrote them evaluate the end spans' polynomials there. Clamping the
parameter into the domain instead moves such points by up to the end span's slope times the
overshoot. The extended spline has the same pieces on the old domain and the continued end pieces
beyond it, so every point of the trimmed face has its exact (u, v).

Method (blossoming, Ramshaw 1989; Piegl and Tiller, The NURBS Book, 2nd ed., section 5.2):
a control point of a degree-k spline is the blossom of any of the pieces in its support at its k
knots, ``P_i = F_j(t_{i+1}, ..., t_{i+k})``. Moving the k + 1 equal end knots from ``b`` to
``b' > b`` changes only the last k control points; each is the last piece's blossom at its new
knots. Rational splines are extended in homogeneous coordinates ``(w P, w)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["blossom", "extend_clamped", "extend_surface_dict"]


def blossom(t: np.ndarray, k: int, P: np.ndarray, j: int, args) -> np.ndarray:
    """The blossom of the degree-``k`` piece on span ``[t_j, t_{j+1})`` (control points
    ``P[j-k..j]`` along axis 0) at the ``k`` arguments ``args`` (de Boor's recursion with one
    argument per level)."""
    d = [np.asarray(P[j - k + m], float) for m in range(k + 1)]
    for r in range(1, k + 1):
        x = args[r - 1]
        for m in range(k, r - 1, -1):
            i = j - k + m
            alpha = (x - t[i]) / (t[i + k + 1 - r] - t[i])
            d[m] = (1.0 - alpha) * d[m - 1] + alpha * d[m]
    return d[k]


def _clamped(t: np.ndarray, k: int) -> bool:
    n = len(t) - k - 1
    return bool(np.all(t[: k + 1] == t[k]) and np.all(t[n:] == t[n]) and t[k + 1] > t[k] and t[n - 1] < t[n])


def extend_clamped(t, k: int, P, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """(knots, control points) of the clamped degree-``k`` spline (knots ``t``, control points
    ``P`` along axis 0, any trailing shape: homogeneous for rational splines) extended to the
    domain ``[min(lo, a), max(hi, b)]`` (``[a, b]`` its own); the spline is unchanged on
    ``[a, b]``. Raises ValueError for a knot vector that is not clamped (end knots repeated
    ``k + 1`` times)."""
    t = np.asarray(t, float)
    P = np.asarray(P, float)
    if not _clamped(t, k):
        raise ValueError("extend_clamped: the knot vector is not clamped (end knots repeated degree + 1 times)")
    n = len(P)
    a, b = float(t[k]), float(t[n])
    new_t, new_P = t.copy(), P.copy()
    if hi > b:
        new_t[n:] = hi
        for i in range(n - k, n):
            new_P[i] = blossom(t, k, P, n - 1, new_t[i + 1: i + k + 1])
    if lo < a:
        new_t[: k + 1] = lo
        for i in range(k):
            new_P[i] = blossom(t, k, P, k, new_t[i + 1: i + k + 1])
    return new_t, new_P


def extend_surface_dict(d: dict[str, Any], u_range, v_range) -> dict[str, Any]:
    """A ``bspline_surface`` dict whose domain covers ``u_range`` x ``v_range`` (each (lo, hi)),
    extended by :func:`extend_clamped` in each direction; the same surface on the old domain."""
    P = np.asarray(d["control_points"], float)
    w = np.asarray(d["weights"], float) if d.get("weights") is not None else None
    H = P if w is None else np.concatenate([P * w[..., None], w[..., None]], axis=2)
    tu, H = extend_clamped(d["knots_u"], int(d["degree_u"]), H, *u_range)
    tv, Ht = extend_clamped(d["knots_v"], int(d["degree_v"]), np.swapaxes(H, 0, 1), *v_range)
    H = np.swapaxes(Ht, 0, 1)
    out = dict(d, knots_u=tu.tolist(), knots_v=tv.tolist())
    if w is None:
        out["control_points"] = H.tolist()
    else:
        out["weights"] = H[..., 3].tolist()
        out["control_points"] = (H[..., :3] / H[..., 3:4]).tolist()
    return out
