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
``surface_cell_newton``), and where that does not converge inside the cell, 1D Newton along
the cell's four edges (the kernel instead solves every edge whose Bernstein lower bound of
the distance is below the best as a curve cell, by isolation); the closest result per point
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

from ._cell_boxes import CellSearch, best_per_point

# (point, cell) pairs per Newton run: the gathered Taylor coefficients ((ku + 1) (kv + 1) D
# rows) of a run then stay within a few MB
PAIR_BLOCK = 8192
# a step whose largest part inside the cell is below this fraction starts at a bound it
# would leave at once
_LEAVES_AT_ONCE = 1e-3
# a step cut at a bound and ending within this fraction of the cell's width of it is put
# exactly onto it
_SNAP = 1e-12


def _coldot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Column-wise dot product of (3, n) arrays."""
    return np.einsum("ij,ij->j", x, y)


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


def edge_polynomials(G: np.ndarray, along_u: bool, fixed: np.ndarray, ku: int, kv: int, D: int) -> np.ndarray:
    """Taylor coefficients (k + 1, D, n) in the free coordinate of the patches ``G`` along
    the lines v = ``fixed`` (``along_u``) or u = ``fixed``."""
    n = G.shape[1]
    G4 = G.reshape(ku + 1, kv + 1, D, n)
    if along_u:  # sum over b of G[a, b] fixed^b
        c = G4[:, kv].copy()
        for b in range(kv - 1, -1, -1):
            c *= fixed
            c += G4[:, b]
        return c
    c = G4[ku].copy()  # sum over a of G[a, b] fixed^a
    for a in range(ku - 1, -1, -1):
        c *= fixed
        c += G4[a]
    return c


def _line_values(c: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """C, C', C'' (3, n) of the curves with Taylor coefficients ``c`` (k + 1, D, n) at x."""
    k, D = c.shape[0] - 1, c.shape[1]
    s0, s1, s2 = c[k].copy(), np.zeros_like(c[k]), np.zeros_like(c[k])
    for i in range(k - 1, -1, -1):
        s2 *= x
        s2 += s1
        s1 *= x
        s1 += s0
        s0 *= x
        s0 += c[i]
    s2 *= 2.0
    if D == 3:
        return s0, s1, s2
    inv = 1.0 / s0[3]
    C = s0[:3] * inv
    C1 = (s1[:3] - s1[3] * C) * inv
    C2 = (s2[:3] - 2.0 * s1[3] * C1 - s2[3] * C) * inv
    return C, C1, C2


# ---------------------------------------------------------------------------------------
# Newton kept inside a cell (2D) and along a cell's edge (1D)
# ---------------------------------------------------------------------------------------


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
        f = _coldot(S, S)
        gu, gv = _coldot(Su, S), _coldot(Sv, S)
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
        E, F, Gf = _coldot(Su, Su), _coldot(Su, Sv), _coldot(Sv, Sv)
        huu, hvv = E + _coldot(Suu, S), Gf + _coldot(Svv, S)
        huv = F + _coldot(Suv, S)
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
        move = np.sqrt(_coldot(dS, dS))
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


def edge_newton(c, lo, hi, p, reach, tol, finish, max_iter, max_halvings):
    """Safeguarded 1D Newton along cell edges (Taylor coefficients ``c`` (k + 1, D, n) in the
    free coordinate, kept in [lo, hi]), as the curve cells' Newton once was: from the
    middle, halving where worse, to the edge's end where f is not clearly convex. Returns
    the free coordinate and the squared distance."""
    n = p.shape[1]
    out_x, out_f = np.empty(n), np.empty(n)
    idx = np.arange(n)
    trial = 0.5 * (lo + hi)
    x_acc, f_acc = trial, np.full(n, np.inf)
    speed, step = np.zeros(n), np.zeros(n)
    halvings = np.zeros(n, dtype=np.int64)
    for _ in range(max_iter):
        if len(idx) == 0:
            break
        C, C1, C2 = _line_values(c, trial)
        C -= p
        f, g, sp2 = _coldot(C, C), _coldot(C1, C), _coldot(C1, C1)
        h = sp2 + _coldot(C2, C)
        acc = f <= f_acc + _roundoff(f_acc, reach)
        newton = h > 1e-6 * sp2
        x_acc, f_acc = np.where(acc, trial, x_acc), np.where(acc, f, f_acc)
        speed = np.where(acc, np.sqrt(sp2), speed)
        halvings = np.where(acc, 0, halvings + 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = np.where(newton, -g / h, np.where(g > 0.0, lo, hi) - trial)
        dx = np.where(g == 0.0, 0.0, dx)
        raw = x_acc + np.where(acc, dx, 0.5 * step)
        new = np.clip(raw, lo, hi)
        eff = new - x_acc
        move = np.abs(eff) * speed
        last = acc & newton & (new == raw) & (move <= finish)
        done = last | (move <= tol) | (halvings > max_halvings)
        if done.any():
            d = np.flatnonzero(done)
            ld = last[d]
            out_x[idx[d]] = np.where(ld, new[d], x_acc[d])
            out_f[idx[d]] = f_acc[d] + np.where(ld, g[d] * eff[d], 0.0)
            keep = np.flatnonzero(~done)
            idx, c, p, reach = idx[keep], np.take(c, keep, axis=2), np.take(p, keep, axis=1), reach[keep]
            lo, hi, new, eff = lo[keep], hi[keep], new[keep], eff[keep]
            x_acc, f_acc, speed, halvings = x_acc[keep], f_acc[keep], speed[keep], halvings[keep]
        trial, step = new, eff
    if len(idx):
        out_x[idx], out_f[idx] = x_acc, f_acc
    return out_x, out_f


def solve_cells(coef, su, sv, cv, cell, p, reach, ku, kv, D, tol, finish, max_iter, max_halvings):
    """The closest point of each pair's cell (``cell`` indices i cv + j into the Taylor
    coefficients ``coef`` (n_cells, (ku + 1) (kv + 1) D), ``p`` (3, n)):
    the 2D cell Newton, and where that does not converge inside the cell, 1D Newton along
    its four edges (a minimum on an edge the 2D iteration did not reach); the best.
    Returns local x, y (offsets from the cell's middle) and the squared distance."""
    ci, cj = cell // cv, cell % cv
    mu, mv = 0.5 * (su[ci] + su[ci + 1]), 0.5 * (sv[cj] + sv[cj + 1])
    ulo, uhi, vlo, vhi = su[ci] - mu, su[ci + 1] - mu, sv[cj] - mv, sv[cj + 1] - mv
    # a cell's coefficients are one contiguous row of coef: gathered as rows, then turned
    G = np.ascontiguousarray(np.take(coef, cell, axis=0).T)
    args = (tol, finish, max_iter, max_halvings)
    x, y, f, inner = cell_newton(G, ulo, uhi, vlo, vhi, p, reach, ku, kv, D, *args)
    rows = np.flatnonzero(~inner)
    if len(rows):
        Gr, pr, rr = np.take(G, rows, axis=1), np.take(p, rows, axis=1), reach[rows]
        Gr2, pr2, rr2 = np.concatenate([Gr, Gr], axis=1), np.concatenate([pr, pr], axis=1), np.concatenate([rr, rr])
        n = len(rows)
        for along_u, fixed, lo, hi in (
            (True, np.concatenate([vlo[rows], vhi[rows]]), ulo[rows], uhi[rows]),
            (False, np.concatenate([ulo[rows], uhi[rows]]), vlo[rows], vhi[rows]),
        ):
            c = edge_polynomials(Gr2, along_u, fixed, ku, kv, D)
            z, fe = edge_newton(c, np.concatenate([lo, lo]), np.concatenate([hi, hi]), pr2, rr2, *args)
            for half in (slice(0, n), slice(n, 2 * n)):
                better = np.flatnonzero(fe[half] < f[rows])
                r = rows[better]
                f[r] = fe[half][better]
                if along_u:
                    x[r], y[r] = z[half][better], fixed[half][better]
                else:
                    x[r], y[r] = fixed[half][better], z[half][better]
    return x, y, f


# ---------------------------------------------------------------------------------------
# the projection of a block of points
# ---------------------------------------------------------------------------------------


def project_block(p, j_sample, bound2, search: CellSearch, leaf_cell, coef, su, sv, ku, kv, D, rational, prune_u,
                  prune_v, tol, finish, extent, max_iter, max_halvings, pair_block=PAIR_BLOCK):
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
    S, Su, Sv = patch_values(np.ascontiguousarray(np.take(coef, bc, axis=0).T), bx, by, ku, kv, D, 1)
    uv = np.stack([0.5 * (su[ci] + su[ci + 1]) + bx, 0.5 * (sv[cj] + sv[cj + 1]) + by])
    return uv, np.concatenate([S, Su, Sv])
