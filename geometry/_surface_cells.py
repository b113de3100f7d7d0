"""Closest points on a B-spline surface by cells, vectorised over (point, cell) pairs: the
numpy path of :meth:`geometry.bspline.BSplineSurface.closest_parameters`, the cell-wise
design of the compiled kernel ``surface_project`` (:mod:`geometry._kernels`) run over whole
arrays.

The surface is cut into the cells of its sample grid (each inside one knot span in both
directions, so one polynomial or rational tensor patch), every cell kept as its Taylor
polynomial about its middle. Per block of points: the nearest grid sample gives a bound;
every cell whose box lies closer than the bound, and over which neither ``S_u.(S - p)``
nor ``S_v.(S - p)`` provably keeps one sign, is a candidate; each candidate (point, cell)
pair gets the safeguarded 2D Newton kept inside the cell (the kernel's
``surface_cell_newton``); then every edge of a candidate whose Bernstein lower bound of the
distance is below its point's best is solved as a curve cell (every minimum along it, by
isolation: :mod:`geometry._curve_cells`, as the kernel does); the closest result per point
wins. The kernel runs this per point with the bound tightened as cells are solved;
here every candidate of the first bound is solved, all pairs at once, which costs more
Newton solves but few numpy calls per solve.

Arrays are component-major (see :mod:`geometry._cell_boxes`): n vectors are (3, n), the
Taylor coefficients of n cells ``((ku + 1) (kv + 1) D, n)`` (row ``(a (kv + 1) + b) D + d``:
the coefficient of ``x^a y^b`` of homogeneous component d, x and y the offsets from the
cell's middle). Pure functions over arrays; no numba.
"""

from __future__ import annotations

import numpy as np

from . import _curve_cells
from ._cell_boxes import CellSearch, best_per_point, coldot, rows_as_columns

# (point, cell) pairs per Newton run: the gathered Taylor coefficients ((ku + 1) (kv + 1) D
# rows) of a run then stay within a few MB
PAIR_BLOCK = 8192
# a step whose largest part inside the cell is below this fraction starts at a bound it
# would leave at once
_LEAVES_AT_ONCE = 1e-3
# a step cut at a bound and ending within this fraction of the cell's width of it is put
# exactly onto it
_SNAP = 1e-12


def _roundoff(f: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Round-off level of a squared distance ``f`` with coordinates of size ``reach``: a
    trial within it of the accepted value counts as no increase (as in the kernel)."""
    return 8e-16 * (f + 2.0 * np.sqrt(f) * reach)


# ---------------------------------------------------------------------------------------
# evaluation of the cells' Taylor polynomials
# ---------------------------------------------------------------------------------------


def patch_values(G: np.ndarray, x: np.ndarray, y: np.ndarray, ku: int, kv: int, D: int, order: int = 2) -> list[np.ndarray]:
    """S, S_u, S_v (and S_uu, S_uv, S_vv when ``order`` is 2), each (3, n), of the patches
    with Taylor coefficients ``G`` ((ku + 1) (kv + 1) D, n) at local (x, y) (n,)."""
    n = G.shape[1]
    G4 = G.reshape(ku + 1, kv + 1, D, n)
    # Horner in y for all powers of x at once (long rows: few numpy calls); w1 and w2 the
    # first derivative and half the second
    w0 = G4[:, kv].copy()
    w1 = np.zeros_like(w0)
    w2 = np.zeros_like(w0) if order >= 2 else None
    for b in range(kv - 1, -1, -1):
        if order >= 2:
            w2 *= y
            w2 += w1
        w1 *= y
        w1 += w0
        w0 *= y
        w0 += G4[:, b]
    # then Horner in x: s_ij the derivative i times in u and j times in v (s20 halved)
    s00, s01 = w0[ku].copy(), w1[ku].copy()
    s10 = np.zeros_like(s00)
    if order >= 2:
        s20, s11, s02 = np.zeros_like(s00), np.zeros_like(s00), 2.0 * w2[ku]
    for a in range(ku - 1, -1, -1):
        if order >= 2:
            s20 *= x
            s20 += s10
            s11 *= x
            s11 += s01
            s02 *= x
            s02 += 2.0 * w2[a]
        s10 *= x
        s10 += s00
        s00 *= x
        s00 += w0[a]
        s01 *= x
        s01 += w1[a]
    if order >= 2:
        s20 *= 2.0
    if D == 3:
        return [s00, s10, s01, s20, s11, s02] if order >= 2 else [s00, s10, s01]
    # rational: S = A / w by the quotient rule (Leibniz on A = w S)
    inv = 1.0 / s00[3]
    S = s00[:3] * inv
    Su = (s10[:3] - s10[3] * S) * inv
    Sv = (s01[:3] - s01[3] * S) * inv
    if order < 2:
        return [S, Su, Sv]
    Suu = (s20[:3] - 2.0 * s10[3] * Su - s20[3] * S) * inv
    Suv = (s11[:3] - s10[3] * Sv - s01[3] * Su - s11[3] * S) * inv
    Svv = (s02[:3] - 2.0 * s01[3] * Sv - s02[3] * S) * inv
    return [S, Su, Sv, Suu, Suv, Svv]


def _inside_fraction(xa, ya, du, dv, ulo, uhi, vlo, vhi) -> np.ndarray:
    """The largest fraction (<= 1) of the steps (du, dv) from (xa, ya) that stays in the
    cells [ulo, uhi] x [vlo, vhi]."""
    frac = np.ones(len(xa))
    with np.errstate(divide="ignore", invalid="ignore"):
        for z, dz, lo, hi in ((xa, du, ulo, uhi), (ya, dv, vlo, vhi)):
            over = ((dz > 0.0) & (z + dz > hi)) | ((dz < 0.0) & (z + dz < lo))
            if over.any():
                cut = np.where(dz > 0.0, hi - z, lo - z) / dz
                frac = np.where(over, np.minimum(frac, cut), frac)
    return frac


def cell_newton(G, ulo, uhi, vlo, vhi, p, reach, ku, kv, D, tol, finish, max_iter, max_halvings):
    """Safeguarded Newton on ``(S - p).S_u = (S - p).S_v = 0`` kept inside one cell per
    pair (Taylor coefficients ``G``, local box [ulo, uhi] x [vlo, vhi], points ``p`` (3, n))
    from the cell's middle, as the kernel's ``surface_cell_newton``: a coordinate at a bound
    its descent points out of is frozen (1D Newton along that edge, or to the edge's end
    where f is not clearly convex along it); Gauss-Newton (first fundamental form) where the
    Hessian is not clearly positive definite; scaled steepest descent where the step would
    leave the cell at once; steps cut at the cell's boundary, exactly onto the bound; a
    trial that increases the squared distance beyond round-off is halved. Stops after a
    plain Newton step below ``finish`` (length of the step on the surface) or a step below
    ``tol``. Returns x, y, the squared distance and whether Newton converged to a point
    strictly inside the cell."""
    n = p.shape[1]
    out_x, out_y, out_f = np.empty(n), np.empty(n), np.empty(n)
    out_inner = np.zeros(n, dtype=bool)
    idx = np.arange(n)
    tx, ty = 0.5 * (ulo + uhi), 0.5 * (vlo + vhi)
    xa, ya = tx, ty
    f_acc = np.full(n, np.inf)
    sdu, sdv = np.zeros(n), np.zeros(n)
    halvings = np.zeros(n, dtype=np.int64)
    Sua, Sva = np.zeros((3, n)), np.zeros((3, n))
    for _ in range(max_iter):
        if len(idx) == 0:
            break
        S, Su, Sv, Suu, Suv, Svv = patch_values(G, tx, ty, ku, kv, D, 2)
        S -= p  # r = S - p
        f = coldot(S, S)
        gu, gv = coldot(Su, S), coldot(Sv, S)
        acc = f <= f_acc + _roundoff(f_acc, reach)
        every = bool(acc.all())
        if every:
            xa, ya, f_acc, Sua, Sva = tx, ty, f, Su, Sv
            halvings = np.zeros(len(idx), dtype=np.int64)
        else:
            xa, ya, f_acc = np.where(acc, tx, xa), np.where(acc, ty, ya), np.where(acc, f, f_acc)
            Sua, Sva = np.where(acc, Su, Sua), np.where(acc, Sv, Sva)
            halvings = np.where(acc, 0, halvings + 1)
        # at accepted trials: the Newton step (Gauss-Newton where the Hessian is not
        # clearly positive definite)
        E, F, Gf = coldot(Su, Su), coldot(Su, Sv), coldot(Sv, Sv)
        huu, hvv = E + coldot(Suu, S), Gf + coldot(Svv, S)
        huv = F + coldot(Suv, S)
        det = huu * hvv - huv * huv
        newton = (huu > 1e-6 * E) & (hvv > 1e-6 * Gf) & (det > 1e-6 * (E * Gf - F * F))
        if not newton.all():
            det = np.where(newton, det, E * Gf - F * F)
            huv = np.where(newton, huv, F)
            hu, hv = np.where(newton, huu, E), np.where(newton, hvv, Gf)
        else:
            hu, hv = huu, hvv
        solvable = det > 0.0
        inv = np.where(solvable, 1.0 / np.where(solvable, det, 1.0), 0.0)
        du = -(hv * gu - huv * gv) * inv
        dv = -(hu * gv - huv * gu) * inv
        # a coordinate at a bound whose descent points out of the cell is frozen: the 1D
        # problem along that edge (the other coordinate by its own 1D rule)
        fix_u = ((xa <= ulo) & (gu > 0.0)) | ((xa >= uhi) & (gu < 0.0))
        fix_v = ((ya <= vlo) & (gv > 0.0)) | ((ya >= vhi) & (gv < 0.0))
        frozen = fix_u | fix_v
        if frozen.any():
            with np.errstate(divide="ignore", invalid="ignore"):
                eu = np.where(huu > 1e-6 * E, -gu / huu, np.where(gu > 0.0, ulo - xa, uhi - xa))
                ev = np.where(hvv > 1e-6 * Gf, -gv / hvv, np.where(gv > 0.0, vlo - ya, vhi - ya))
            eu = np.where(fix_u | ((gu == 0.0) & ~(huu > 1e-6 * E)), 0.0, eu)
            ev = np.where(fix_v | ((gv == 0.0) & ~(hvv > 1e-6 * Gf)), 0.0, ev)
            du, dv = np.where(frozen, eu, du), np.where(frozen, ev, dv)
            newton &= ~frozen
        # not accepted: half the last step back
        if not every:
            newton &= acc
            du, dv = np.where(acc, du, 0.5 * sdu), np.where(acc, dv, 0.5 * sdv)
        frac = _inside_fraction(xa, ya, du, dv, ulo, uhi, vlo, vhi)
        steep = acc & (frac <= _LEAVES_AT_ONCE)
        if steep.any():
            # the step leaves the cell at once (a coordinate at a bound that the coupled
            # step pushes out while its own descent points in): scaled steepest descent
            # instead, which points into the cell, cut at the cell's boundary
            newton &= ~steep
            with np.errstate(divide="ignore", invalid="ignore"):
                su_ = np.where(E > 0.0, -gu / E, 0.0)
                sv_ = np.where(Gf > 0.0, -gv / Gf, 0.0)
            su_ = np.where(((xa <= ulo) & (su_ < 0.0)) | ((xa >= uhi) & (su_ > 0.0)), 0.0, su_)
            sv_ = np.where(((ya <= vlo) & (sv_ < 0.0)) | ((ya >= vhi) & (sv_ > 0.0)), 0.0, sv_)
            du, dv = np.where(steep, su_, du), np.where(steep, sv_, dv)
            frac = _inside_fraction(xa, ya, du, dv, ulo, uhi, vlo, vhi)
        clamped = frac < 1.0
        nx = np.clip(xa + frac * du, ulo, uhi)
        ny = np.clip(ya + frac * dv, vlo, vhi)
        if clamped.any():  # onto the bound the step was cut at, exactly (not an ulp short)
            eu, ev = _SNAP * (uhi - ulo), _SNAP * (vhi - vlo)
            nx = np.where(clamped & (du > 0.0) & (nx >= uhi - eu), uhi, nx)
            nx = np.where(clamped & (du < 0.0) & (nx <= ulo + eu), ulo, nx)
            ny = np.where(clamped & (dv > 0.0) & (ny >= vhi - ev), vhi, ny)
            ny = np.where(clamped & (dv < 0.0) & (ny <= vlo + ev), vlo, ny)
        ex, ey = nx - xa, ny - ya
        dS = ex * Sua
        dS += ey * Sva
        move = np.sqrt(coldot(dS, dS))
        # a plain Newton step (accepted, not cut) this small is the last one
        last = acc & newton & ~clamped & (move <= finish)
        done = last | (move <= tol) | (halvings > max_halvings)
        if done.any():
            d = np.flatnonzero(done)
            ld = last[d]
            rx, ry = np.where(ld, nx[d], xa[d]), np.where(ld, ny[d], ya[d])
            out_x[idx[d]], out_y[idx[d]] = rx, ry
            # after a final step f has dropped by about -grad . step (second order)
            out_f[idx[d]] = f_acc[d] + np.where(ld, gu[d] * ex[d] + gv[d] * ey[d], 0.0)
            out_inner[idx[d]] = (ld | (acc[d] & newton[d])) & (ulo[d] < rx) & (rx < uhi[d]) & (vlo[d] < ry) & (ry < vhi[d])
            keep = np.flatnonzero(~done)
            idx, G, p, reach = idx[keep], np.take(G, keep, axis=1), np.take(p, keep, axis=1), reach[keep]
            ulo, uhi, vlo, vhi = ulo[keep], uhi[keep], vlo[keep], vhi[keep]
            nx, ny, ex, ey, xa, ya, f_acc = nx[keep], ny[keep], ex[keep], ey[keep], xa[keep], ya[keep], f_acc[keep]
            Sua, Sva, halvings = np.take(Sua, keep, axis=1), np.take(Sva, keep, axis=1), halvings[keep]
        tx, ty, sdu, sdv = nx, ny, ex, ey
    if len(idx):  # iteration limit: the best accepted point, not counted as converged
        out_x[idx], out_y[idx], out_f[idx] = xa, ya, f_acc
    return out_x, out_y, out_f, out_inner


def solve_cells(coef, su, sv, cv, cell, p, reach, ku, kv, D, tol, finish, max_iter, max_halvings):
    """The 2D cell Newton for each pair (``cell`` indices i cv + j into the Taylor
    coefficients ``coef`` (n_cells, (ku + 1) (kv + 1) D), ``p`` (3, n)). Returns local x, y
    (offsets from the cell's middle) and the squared distance."""
    ci, cj = cell // cv, cell % cv
    mu, mv = 0.5 * (su[ci] + su[ci + 1]), 0.5 * (sv[cj] + sv[cj + 1])
    ulo, uhi, vlo, vhi = su[ci] - mu, su[ci + 1] - mu, sv[cj] - mv, sv[cj + 1] - mv
    G = rows_as_columns(coef, cell)
    x, y, f, _ = cell_newton(G, ulo, uhi, vlo, vhi, p, reach, ku, kv, D, tol, finish, max_iter, max_halvings)
    return x, y, f


def solve_edges(p, pi, cell, best, su, sv, cv, ku, kv, reach, cert, tol, finish, max_iter, edges):
    """The edges of the pairs' cells whose Bernstein lower bound of the distance is below
    the best distance of their point (``best`` (m,)), solved as curve cells (every minimum
    along the edge, :func:`geometry._curve_cells.cell_minima`): a minimum on an edge beside
    an inner one, or one the 2D descent did not reach. ``edges``: the surface's edge tables
    (``ue_*`` along u, edge 2 c + s at the lower / upper v bound; ``ve_*`` along v). Returns
    (pair index, x, y, f) of the edge results."""
    ci, cj = cell // cv, cell % cv
    half_u, half_v = 0.5 * (su[ci + 1] - su[ci]), 0.5 * (sv[cj + 1] - sv[cj])
    out = [], [], [], []
    for along_u in (True, False):
        name, k = ("ue", ku) if along_u else ("ve", kv)
        for side in (0, 1):
            eid = 2 * cell + side
            q = np.take(p, pi, axis=1)
            low = _curve_cells.distance_lower_bound(q, eid, edges[f"{name}_fnet"])
            rows = np.flatnonzero(low - 1e-15 * reach[pi] ** 2 < best[pi] * (1.0 - cert))
            if len(rows) == 0:
                continue
            h_along = (half_u if along_u else half_v)[rows]
            h_fixed = (half_v if along_u else half_u)[rows]
            z, fe = _curve_cells.cell_minima(
                np.take(q, rows, axis=1), eid[rows], -h_along, 2.0 * h_along, edges[f"{name}_coef"],
                edges[f"{name}_ends"], edges[f"{name}_stat"], k, tol, finish, max_iter, edges["max_depth"],
            )
            fixed = h_fixed if side else -h_fixed
            out[0].append(rows)
            out[1].append(z if along_u else fixed)
            out[2].append(fixed if along_u else z)
            out[3].append(fe)
    if not out[0]:
        return np.empty(0, dtype=np.int64), np.empty(0), np.empty(0), np.empty(0)
    return tuple(np.concatenate(a) for a in out)


# ---------------------------------------------------------------------------------------
# the projection of a block of points
# ---------------------------------------------------------------------------------------


def project_block(p, j_sample, bound2, search: CellSearch, leaf_cell, coef, su, sv, ku, kv, D, rational, prune_u,
                  prune_v, tol, finish, extent, max_iter, max_halvings, edges, cert, pair_block=PAIR_BLOCK):
    """Closest points of the points ``p`` (3, m) whose nearest grid sample is
    ``j_sample`` (index i len(sv) + j of the sample (su[i], sv[j])), ``bound2`` the
    squared distance to it; ``search`` the box hierarchy over the cells (leaf i: cell
    ``leaf_cell[i]``), the other arguments the kernel's tables (rational: D == 4). Returns
    the parameters (2, m) and S, S_u, S_v (9, m)."""
    m = p.shape[1]
    cu, cv = len(su) - 1, len(sv) - 1
    reach = np.abs(p).max(axis=0) + extent
    pi, node, bounds = search.pairs(p, bound2)
    cell = leaf_cell[node]
    keep = np.ones(len(pi), dtype=bool)
    # a cell where S_u.(S - p) (or S_v.(S - p)) keeps one sign holds no minimum of its own:
    # its smallest distance lies on the edge it shares with the neighbouring cell, which is
    # a candidate too where that edge is closer than the bound (f_u is continuous across C1
    # knot lines, so two neighbours cannot both point at their shared edge); not at the
    # domain's edges, nor across creases (prune_u / prune_v false)
    for e, prune, index, count in ((0, prune_u, cell // cv, cu), (1, prune_v, cell % cv, cv)):
        if prune:
            low, high = bounds[e]
            keep &= ~(((low > 0.0) & (index > 0)) | ((high < 0.0) & (index < count - 1)))
    pi, cell = pi[keep], cell[keep]
    # the nearest sample is a point of the surface: every point keeps its cell (round-off
    # safety net: without a candidate the sample itself is the closest to round-off)
    ns = len(sv)
    i_s, j_s = j_sample // ns, j_sample % ns
    ci_s, cj_s = np.minimum(i_s, cu - 1), np.minimum(j_s, cv - 1)
    orphan = np.ones(m, dtype=bool)
    orphan[pi] = False
    rows = np.flatnonzero(orphan)
    pi, cell = np.concatenate([pi, rows]), np.concatenate([cell, ci_s[rows] * cv + cj_s[rows]])
    x, y, f = np.empty(len(pi)), np.empty(len(pi)), np.empty(len(pi))
    for i0 in range(0, len(pi), pair_block):
        sl = slice(i0, i0 + pair_block)
        q = np.take(p, pi[sl], axis=1)
        x[sl], y[sl], f[sl] = solve_cells(coef, su, sv, cv, cell[sl], q, reach[pi[sl]], ku, kv, D, tol, finish,
                                          max_iter, max_halvings)
    # the cells' edges where they can hold a closer point (solved as curve cells)
    best_f = np.full(m, np.inf)
    np.minimum.at(best_f, pi, f)
    er, ex, ey, ef = solve_edges(p, pi, cell, best_f, su, sv, cv, ku, kv, reach, cert, tol, finish, max_iter, edges)
    pi, cell = np.concatenate([pi, pi[er]]), np.concatenate([cell, cell[er]])
    x, y, f = np.concatenate([x, ex]), np.concatenate([y, ey]), np.concatenate([f, ef])
    best = best_per_point(pi, f, m)
    bx, by, bf, bc = x[best], y[best], f[best], cell[best]
    # where Newton found nothing closer than the sample, the sample (a corner of its cell)
    worse = np.flatnonzero(bf > bound2)
    if len(worse):
        ci, cj = ci_s[worse], cj_s[worse]
        bc[worse] = ci * cv + cj
        bx[worse] = su[i_s[worse]] - 0.5 * (su[ci] + su[ci + 1])
        by[worse] = sv[j_s[worse]] - 0.5 * (sv[cj] + sv[cj + 1])
    ci, cj = bc // cv, bc % cv
    S, Su, Sv = patch_values(rows_as_columns(coef, bc), bx, by, ku, kv, D, 1)
    uv = np.stack([0.5 * (su[ci] + su[ci + 1]) + bx, 0.5 * (sv[cj] + sv[cj + 1]) + by])
    return uv, np.concatenate([S, Su, Sv])
