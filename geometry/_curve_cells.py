"""Closest points on polynomial (or rational) curve cells, vectorised over (point, cell)
pairs: the numpy counterpart of the compiled ``curve_cell_minima`` (:mod:`geometry._kernels`).
Used for the cells of B-spline curves and for the edges of B-spline surface cells.

A curve cell is one polynomial piece, given by the rows of kernel-layout tables (one row
per cell, see :mod:`geometry._jit`): ``coef`` (n_cells, (k + 1) D) Taylor coefficients about
the cell's middle (column i D + d: coefficient of x^i of homogeneous component d; D = 4 for
rational pieces ``(w C, w)``), ``ends`` (n_cells, 6) its first and last point, ``stat``
(n_cells, 4 (M + 1)) the Bernstein coefficients ``G0, G1x, G1y, G1z`` of a positive multiple
of ``g = C'.(C - p) = G0 - p.G1`` over the cell, and ``fnet`` (n_cells, 5 (2k + 1)) those of
the squared distance (:func:`geometry._bernstein.distance_nets`).

The closest point of a cell is at one of its ends or at a minimum inside it. The Bernstein
coefficients of g isolate the stationary points: no sign change, none; one, from - to +,
exactly one minimum (Newton in the bracket); more, the interval is halved (de Casteljau)
until each part has at most one. Arrays inside are component-major ((3, n), see
:mod:`geometry._cell_boxes`).
"""

from __future__ import annotations

import numpy as np

from . import _bernstein
from ._cell_boxes import coldot, rows_as_columns


def homogeneous_values(G: np.ndarray, x: np.ndarray, k: int, order: int) -> list[np.ndarray]:
    """Values and derivatives up to ``order`` (<= 2), each (D, n), of polynomials with
    Taylor coefficients ``G`` ((k + 1) D, n; row i D + d: coefficient of x^i of component
    d) at ``x`` (n,), by Horner's rule."""
    D = G.shape[0] // (k + 1)
    top = G[k * D :]
    c0 = top * x  # Horner's rule with its first step done
    c0 += G[(k - 1) * D : k * D]
    c1 = top.copy() if order >= 1 else None
    c2 = np.zeros_like(c0) if order >= 2 else None
    for i in range(k - 2, -1, -1):
        if order >= 2:
            c2 *= x
            c2 += c1
        if order >= 1:
            c1 *= x
            c1 += c0
        c0 *= x
        c0 += G[i * D : (i + 1) * D]
    if order >= 2:
        c2 *= 2.0
    return [c0, c1, c2][: order + 1]


def piece_values(G: np.ndarray, x: np.ndarray, k: int, order: int) -> list[np.ndarray]:
    """C and its derivatives up to ``order`` (<= 2), each (3, n), of pieces with Taylor
    coefficients ``G`` ((k + 1) D, n) at local parameters ``x`` (n,): the homogeneous
    values, then the quotient rule for rational pieces (D = 4)."""
    H = homogeneous_values(G, x, k, order)
    if G.shape[0] // (k + 1) == 3:
        return H
    inv = 1.0 / H[0][3]
    out = [H[0][:3] * inv]
    if order >= 1:
        out.append((H[1][:3] - H[1][3] * out[0]) * inv)
    if order >= 2:
        out.append((H[2][:3] - 2.0 * H[1][3] * out[1] - H[2][3] * out[0]) * inv)
    return out


def bracketed_newton(p, G, lo, hi, x, k, tol, finish, max_iter):
    """Newton on ``g(x) = C'.(C - p) = 0`` in brackets [lo, hi] of local parameters with
    ``g(lo) < 0 <= g(hi)`` (one root inside), from ``x``; a step that leaves the bracket
    (or where g' <= 0) is replaced by bisection, and the bracket shrinks with every
    evaluation. Stops when the next step moves the point by less than ``tol``, or after a
    Newton step below ``finish`` (the error left is of the order of its square). ``p``
    (3, n), ``G`` ((k + 1) D, n). Returns x and the squared distance there."""
    n = len(x)
    out_x, out_f = x.copy(), np.full(n, np.inf)
    idx = np.arange(n)
    for _ in range(max_iter):
        if len(idx) == 0:
            break
        C, C1, C2 = piece_values(G, x, k, 2)
        C -= p  # r = C - p
        f, g, sp2 = coldot(C, C), coldot(C1, C), coldot(C1, C1)
        h = sp2 + coldot(C2, C)
        below = g < 0.0
        lo = np.where(below, x, lo)
        hi = np.where(below, hi, x)
        trial = x - g / np.where(h > 0.0, h, 1.0)
        newton = (h > 0.0) & (trial > lo) & (trial < hi)
        new = np.where(newton, trial, 0.5 * (lo + hi))
        move = np.abs(new - x) * np.sqrt(sp2)
        taylor = newton & (move <= finish)
        done = taylor | (move <= tol) | (g == 0.0)
        out_x[idx] = np.where(taylor, new, x)
        # after a final (Taylor) step f has dropped by about -g . step (second order)
        out_f[idx] = f + np.where(taylor, g * (new - x), 0.0)
        if done.any():
            keep = np.flatnonzero(~done)
            idx, p, G, lo, hi, new = idx[keep], np.take(p, keep, axis=1), np.take(G, keep, axis=1), lo[keep], hi[keep], new[keep]
        x = new
    return out_x, out_f


def cell_minima(p, cell, lo, length, coef, ends, stat, k, tol, finish, max_iter, max_depth):
    """The closest point to ``p`` (3, n) on each pair's cell ``cell`` (n,) (local
    parameters [lo, lo + length], (n,) each): its ends and every minimum inside, isolated by
    the Bernstein coefficients of g (see the module doc), to ``max_depth`` halvings (then
    Newton in the part). Returns the local parameter and the squared distance (n,) each."""
    n = len(cell)
    M = stat.shape[1] // 4 - 1
    S = rows_as_columns(stat, cell)
    b = S[: M + 1] - p[0] * S[M + 1 : 2 * M + 2] - p[1] * S[2 * M + 2 : 3 * M + 3] - p[2] * S[3 * M + 3 :]
    E = rows_as_columns(ends, cell)
    ra, rb = E[:3] - p, E[3:] - p
    fa, fb = coldot(ra, ra), coldot(rb, rb)
    pairs, xs, fs = [np.arange(n)], [np.where(fa <= fb, lo, lo + length)], [np.minimum(fa, fb)]
    # isolation: items (pair, s0, width, coefficients over [s0, s0 + width])
    item, s0, width = np.arange(n), np.zeros(n), np.ones(n)
    br_item, br_lo, br_hi, br_start = [], [], [], []
    for depth in range(max_depth + 1):
        V = _bernstein.sign_changes(b)
        negative = b < 0.0
        last = depth == max_depth
        solve = np.flatnonzero(((V == 1) & negative[0]) | ((V >= 2) & last))
        if len(solve):
            # start: where the control polygon of g crosses zero
            bs = b[:, solve]
            i = np.clip(np.count_nonzero(negative[:, solve], axis=0) - 1, 0, M - 1)
            cols = np.arange(len(solve))
            b_i, b_j = bs[i, cols], bs[i + 1, cols]
            with np.errstate(divide="ignore", invalid="ignore"):
                frac = np.clip((i + np.where(b_i != b_j, b_i / (b_i - b_j), 0.5)) / M, 0.0, 1.0)
            br_item.append(item[solve])
            br_lo.append(s0[solve])
            br_hi.append(s0[solve] + width[solve])
            br_start.append(s0[solve] + frac * width[solve])
        split = np.flatnonzero(V >= 2) if not last else np.empty(0, dtype=np.int64)
        if len(split) == 0:
            break
        left, right = _bernstein.halves(b[:, split])
        half = 0.5 * width[split]
        item = np.concatenate([item[split], item[split]])
        s0 = np.concatenate([s0[split], s0[split] + half])
        width = np.concatenate([half, half])
        b = np.concatenate([left, right], axis=1)
    if br_item:
        it = np.concatenate(br_item)
        a, L = lo[it], length[it]
        x, f = bracketed_newton(
            np.take(p, it, axis=1), rows_as_columns(coef, cell[it]), a + L * np.concatenate(br_lo),
            a + L * np.concatenate(br_hi), a + L * np.concatenate(br_start), k, tol, finish, max_iter,
        )
        pairs.append(it)
        xs.append(x)
        fs.append(f)
    pi, x, f = np.concatenate(pairs), np.concatenate(xs), np.concatenate(fs)
    best = np.full(n, np.inf)
    np.minimum.at(best, pi, f)
    win = np.flatnonzero(f == best[pi])
    out_x = np.empty(n)
    out_x[pi[win]] = x[win]
    return out_x, best


def cell_rows(coef: np.ndarray, lo: np.ndarray, hi: np.ndarray, k: int, D: int, distance: bool = False) -> dict:
    """The row-per-cell tables of curve cells (see the module doc) with Taylor coefficients
    ``coef`` ((k + 1) D, n) on local parameters [lo, hi] (n,) each: ``coef`` rows, the end
    points ``ends``, the Bernstein coefficients of ``C'.(C - p)`` (``stat``) and, with
    ``distance``, those of the squared distance (``fnet``)."""
    length = hi - lo
    G0, G1 = _bernstein.stationary_nets(coef, length, k, D)
    ends = [piece_values(coef, x, k, 0)[0] for x in (lo, hi)]
    out = dict(
        coef=np.ascontiguousarray(coef.T), ends=np.ascontiguousarray(np.concatenate(ends).T),
        stat=np.ascontiguousarray(np.concatenate([G0, G1[0], G1[1], G1[2]]).T),
    )
    if distance:
        F = _bernstein.distance_nets(coef, length, k, D)
        out["fnet"] = np.ascontiguousarray(F.reshape(-1, F.shape[-1]).T)
    return out


def distance_lower_bound(p, cell, fnet):
    """Lower bound of the squared distance from ``p`` (3, n) to each pair's cell: the
    smallest ratio of the Bernstein coefficients of ``|C - p|^2 w^2`` and ``w^2``."""
    F = rows_as_columns(fnet, cell)
    m = F.shape[0] // 5
    num = F[:m] - 2.0 * (p[0] * F[m : 2 * m] + p[1] * F[2 * m : 3 * m] + p[2] * F[3 * m : 4 * m])
    num += coldot(p, p) * F[4 * m :]
    return (num / F[4 * m :]).min(axis=0)
