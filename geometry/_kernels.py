"""The compiled kernels of :mod:`geometry._jit` (numba), at module level so that numba's
on-disk cache (``cache=True``, in ``__pycache__``) keeps them between processes. Imported
only through :mod:`geometry._jit` (never by ``from ibfem import geometry``): importing this module
imports numba. See :mod:`geometry._jit` for the tables the kernels read.

The two projection kernels (curves, surfaces) write their traversal loop out each: moved
into a shared step function (its state and best point in small arrays) both ran 25-50 %
slower in alternating runs (numba's ``inline="always"`` did not recover it): the state then
lives in memory instead of registers."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

jit = njit(cache=True, nogil=True, fastmath=False, error_model="numpy")



@jit
def box_gap2(nodes, i, x0, x1, x2):
    d2 = 0.0
    for k in range(3):
        y = nodes[i, 3 * k] * x0 + nodes[i, 3 * k + 1] * x1 + nodes[i, 3 * k + 2] * x2 - nodes[i, 9 + k]
        g = abs(y) - nodes[i, 12 + k]
        if g > 0.0:
            d2 += g * g
    return d2

@jit
def field_bounds(nodes, i, x0, x1, x2, e):
    """Bounds of V . (S - p) over leaf cell i: S in its box, V in extra box e."""
    low = 0.0
    high = 0.0
    for k in range(3):
        y = nodes[i, 3 * k] * x0 + nodes[i, 3 * k + 1] * x1 + nodes[i, 3 * k + 2] * x2 - nodes[i, 9 + k]
        h = nodes[i, 12 + k]
        slo = -h - y
        shi = h - y
        vlo = nodes[i, 15 + 6 * e + k]
        vhi = nodes[i, 18 + 6 * e + k]
        a = vlo * slo
        b = vlo * shi
        c = vhi * slo
        d = vhi * shi
        low += min(min(a, b), min(c, d))
        high += max(max(a, b), max(c, d))
    return low, high

@jit
def push_children(nodes, level_start, branch, nd, p0, p1, p2, bound, stack, gstack, top):
    """Pushes the children of node nd closer than ``bound`` onto the stack, the
    nearest last (popped first); returns the new stack top."""
    lvl = 0
    while level_start[lvl + 1] <= nd:
        lvl += 1
    base = level_start[lvl + 1] + (nd - level_start[lvl]) * branch
    start = top
    for ch in range(branch):
        g = box_gap2(nodes, base + ch, p0, p1, p2)
        if g >= bound:
            continue
        # insertion: keep stack[start:top] sorted by decreasing gap
        b = top
        while b > start and gstack[b - 1] < g:
            stack[b] = stack[b - 1]
            gstack[b] = gstack[b - 1]
            b -= 1
        stack[b] = base + ch
        gstack[b] = g
        top += 1
    return top

@jit
def curve_eval(coef, c, k, D, rational, x, out):
    """out[0:3] C, out[3:6] C', out[6:9] C'' of cell c at local x (out[9:21]: scratch:
    value, first and second derivative of each homogeneous component)."""
    for d in range(D):
        c0 = coef[c, k * D + d]
        c1 = 0.0
        c2 = 0.0
        for i in range(k - 1, -1, -1):
            c2 = c2 * x + c1
            c1 = c1 * x + c0
            c0 = c0 * x + coef[c, i * D + d]
        out[9 + d] = c0
        out[13 + d] = c1
        out[17 + d] = 2.0 * c2
    if rational:
        w0 = out[12]
        w1 = out[16]
        w2 = out[20]
        for d in range(3):
            C = out[9 + d] / w0
            C1 = (out[13 + d] - w1 * C) / w0
            out[d] = C
            out[3 + d] = C1
            out[6 + d] = (out[17 + d] - 2.0 * w1 * C1 - w2 * C) / w0
    else:
        for d in range(3):
            out[d] = out[9 + d]
            out[3 + d] = out[13 + d]
            out[6 + d] = out[17 + d]

@jit
def curve_bracketed_newton(coef, c, k, D, rational, p0, p1, p2, lo, hi, x, tol, finish, max_iter, buf):
    """Newton on g = C'.(C - p) = 0 in the bracket [lo, hi] (g(lo) < 0 <= g(hi)) of cell
    c from x, bisection where a step leaves the bracket (see
    BSplineCurve._bracketed_newton): returns (local parameter, squared distance)."""
    f = np.inf
    for _ in range(max_iter):
        curve_eval(coef, c, k, D, rational, x, buf)
        r0 = buf[0] - p0
        r1 = buf[1] - p1
        r2 = buf[2] - p2
        f = r0 * r0 + r1 * r1 + r2 * r2
        g = buf[3] * r0 + buf[4] * r1 + buf[5] * r2
        if g == 0.0:
            return x, f
        sp2 = buf[3] * buf[3] + buf[4] * buf[4] + buf[5] * buf[5]
        h = sp2 + buf[6] * r0 + buf[7] * r1 + buf[8] * r2
        if g < 0.0:
            lo = x
        else:
            hi = x
        newton = False
        new = 0.5 * (lo + hi)
        if h > 0.0:
            trial = x - g / h
            if lo < trial < hi:
                new = trial
                newton = True
        move = abs(new - x) * np.sqrt(sp2)
        if newton and move <= finish:
            return new, f + g * (new - x)  # after the last step (second order)
        if move <= tol:
            return x, f
        x = new
    return x, f


@jit
def curve_cell_minima(coef, ends, stat, M, c, lo, length, k, D, rational, p0, p1, p2, tol, finish, max_iter,
                      max_depth, buf, bstack, sstack, tmp):
    """The closest point of cell c (local parameters [lo, lo + length]; see
    BSplineCurve._cell_minima): its ends and every stationary point isolated by the
    Bernstein coefficients of g over the cell (row c of ``stat``: G0, G1x, G1y, G1z, M + 1
    each); returns (local parameter, squared distance). Also the edges of surface cells."""
    ax = ends[c, 0] - p0
    ay = ends[c, 1] - p1
    az = ends[c, 2] - p2
    bx = ends[c, 3] - p0
    by = ends[c, 4] - p1
    bz = ends[c, 5] - p2
    fa = ax * ax + ay * ay + az * az
    fb = bx * bx + by * by + bz * bz
    best_x = lo if fa <= fb else lo + length
    best_f = min(fa, fb)
    n = M + 1
    for j in range(n):
        bstack[0, j] = stat[c, j] - p0 * stat[c, n + j] - p1 * stat[c, 2 * n + j] - p2 * stat[c, 3 * n + j]
    sstack[0, 0] = 0.0
    sstack[0, 1] = 1.0
    sstack[0, 2] = 0.0
    top = 1
    while top > 0:
        top -= 1
        first_negative = bstack[top, 0] < 0.0
        prev = first_negative
        changes = 0
        negatives = 0
        for j in range(n):
            neg = bstack[top, j] < 0.0
            if neg != prev:
                changes += 1
                prev = neg
            if neg:
                negatives += 1
        s0 = sstack[top, 0]
        w = sstack[top, 1]
        depth = sstack[top, 2]
        if changes == 0 or (changes == 1 and not first_negative):
            continue  # no stationary point, or one maximum
        if changes >= 2 and depth < max_depth:
            # de Casteljau at the middle: left half into this slot, right into the next
            for j in range(n):
                tmp[j] = bstack[top, j]
            for r in range(n):
                bstack[top, r] = tmp[0]
                bstack[top + 1, M - r] = tmp[M - r]
                for j in range(M - r):
                    tmp[j] = 0.5 * (tmp[j] + tmp[j + 1])
            half = 0.5 * w
            sstack[top, 1] = half
            sstack[top, 2] = depth + 1.0
            sstack[top + 1, 0] = s0 + half
            sstack[top + 1, 1] = half
            sstack[top + 1, 2] = depth + 1.0
            top += 2
            continue
        # one minimum (or the isolation depth reached): start where the control polygon of
        # g crosses zero
        i = min(max(negatives - 1, 0), M - 1)
        b_i = bstack[top, i]
        b_j = bstack[top, i + 1]
        frac = (i + (b_i / (b_i - b_j) if b_i != b_j else 0.5)) / M
        frac = min(max(frac, 0.0), 1.0)
        a = lo + length * s0
        b = lo + length * (s0 + w)
        x, f = curve_bracketed_newton(coef, c, k, D, rational, p0, p1, p2, a, b, a + frac * (b - a), tol, finish,
                                      max_iter, buf)
        if f < best_f:
            best_f = f
            best_x = x
    return best_x, best_f


@jit
def top_gaps(nodes, n_top, p0, p1, p2, gaps):
    """Box gaps of the top nodes; returns the index of the nearest."""
    first = 0
    for nd in range(n_top):
        gaps[nd] = box_gap2(nodes, nd, p0, p1, p2)
        if gaps[nd] < gaps[first]:
            first = nd
    return first

@jit
def curve_project(P, nodes, level_start, branch, coef, mids, edges, ends, stat, M, k, D, rational,
                  periodic, prune, tol, finish, max_iter, max_depth, cert, rep, rep_cell):
    """Per point: best-first over the top boxes, depth first below them; every leaf cell
    closer than the best distance so far (and not proved monotone) gets the cell
    Newton. Returns the parameter, C and C' (3 + 3 columns) of the best."""
    m = P.shape[0]
    n_cells = len(mids)
    n_levels = len(level_start) - 1
    leaf0 = level_start[n_levels - 1]
    n_top = level_start[1]
    out_t = np.empty(m)
    out_CC = np.empty((m, 6))
    buf = np.empty(21)
    bstack = np.empty((max_depth + 3, M + 1))
    sstack = np.empty((max_depth + 3, 3))
    tmp = np.empty(M + 1)
    gaps = np.empty(n_top)
    stack = np.empty(n_levels * branch + 1, dtype=np.int64)
    gstack = np.empty(n_levels * branch + 1)
    for i in range(m):
        p0 = P[i, 0]
        p1 = P[i, 1]
        p2 = P[i, 2]
        first = top_gaps(nodes, n_top, p0, p1, p2, gaps)
        best_f = np.inf
        best_c = -1
        best_x = 0.0
        # the nearest top node first (a tight bound early), then the others in order
        for a in range(-1, n_top):
            root = first if a < 0 else a
            if a == first or (best_c >= 0 and gaps[root] >= best_f * (1.0 - cert)):
                continue
            top = 0
            stack[top] = root
            gstack[top] = gaps[root]
            top += 1
            while top > 0:
                top -= 1
                nd = stack[top]
                if gstack[top] >= best_f * (1.0 - cert):
                    continue
                # a point of the curve in the node: an upper bound of the answer
                r0 = rep[nd, 0] - p0
                r1 = rep[nd, 1] - p1
                r2 = rep[nd, 2] - p2
                f = r0 * r0 + r1 * r1 + r2 * r2
                if f < best_f:
                    best_f = f
                    best_c = rep_cell[nd]
                    best_x = 0.0
                if nd < leaf0:
                    top = push_children(nodes, level_start, branch, nd, p0, p1, p2, best_f * (1.0 - cert), stack, gstack, top)
                    continue
                c = nd - leaf0
                if c >= n_cells:
                    continue
                if prune and best_c >= 0:
                    low, high = field_bounds(nodes, nd, p0, p1, p2, 0)
                    has_lo = periodic or c > 0
                    has_hi = periodic or c < n_cells - 1
                    if (low > 0.0 and has_lo) or (high < 0.0 and has_hi):
                        continue
                x, f = curve_cell_minima(coef, ends, stat, M, c, edges[c] - mids[c], edges[c + 1] - edges[c], k, D,
                                         rational, p0, p1, p2, tol, finish, max_iter, max_depth, buf, bstack, sstack,
                                         tmp)
                if f < best_f:
                    best_f = f
                    best_c = c
                    best_x = x
        curve_eval(coef, best_c, k, D, rational, best_x, buf)
        t = mids[best_c] + best_x
        out_t[i] = t
        for d in range(6):
            out_CC[i, d] = buf[d]
    return out_t, out_CC




@jit
def curve_project_flat(P, nodes, leaf0, balls, coef, mids, edges, ends, stat, M, k, D, rational,
                       periodic, prune, tol, finish, max_iter, max_depth, cert):
    """``curve_project`` for curves of few cells, without the hierarchy: per point the
    squared distances to every cell's middle (a loop over contiguous rows that the compiler
    vectorises), the nearest middle as the first bound and its cell solved first; every
    other cell is a candidate only if the ball about its middle (``balls``: x, y, z, radius
    rows; the radius bounds the cell's Bezier net, hence the cell) and then its oriented box
    (leaf ``leaf0 + c`` of ``nodes``) are closer than the best distance so far, and it is
    not proved monotone. Returns the parameter, C and C' (3 + 3 columns) of the best."""
    m = P.shape[0]
    n_cells = len(mids)
    out_t = np.empty(m)
    out_CC = np.empty((m, 6))
    buf = np.empty(21)
    bstack = np.empty((max_depth + 3, M + 1))
    sstack = np.empty((max_depth + 3, 3))
    tmp = np.empty(M + 1)
    d2 = np.empty(n_cells)
    bx = balls[0]
    by = balls[1]
    bz = balls[2]
    br = balls[3]
    for i in range(m):
        p0 = P[i, 0]
        p1 = P[i, 1]
        p2 = P[i, 2]
        for c in range(n_cells):
            dx = bx[c] - p0
            dy = by[c] - p1
            dz = bz[c] - p2
            d2[c] = dx * dx + dy * dy + dz * dz
        first = 0
        for c in range(1, n_cells):
            if d2[c] < d2[first]:
                first = c
        best_f = d2[first]  # the middle of cell ``first``: a point of the curve
        best_c = first
        best_x = 0.0
        for a in range(-1, n_cells):
            c = first if a < 0 else a
            if a == first:
                continue
            if a >= 0:
                low = math.sqrt(d2[c]) - br[c]
                if low > 0.0 and low * low >= best_f * (1.0 - cert):
                    continue
                if box_gap2(nodes, leaf0 + c, p0, p1, p2) >= best_f * (1.0 - cert):
                    continue
            if prune:
                low, high = field_bounds(nodes, leaf0 + c, p0, p1, p2, 0)
                has_lo = periodic or c > 0
                has_hi = periodic or c < n_cells - 1
                if (low > 0.0 and has_lo) or (high < 0.0 and has_hi):
                    continue
            x, f = curve_cell_minima(coef, ends, stat, M, c, edges[c] - mids[c], edges[c + 1] - edges[c], k, D,
                                     rational, p0, p1, p2, tol, finish, max_iter, max_depth, buf, bstack, sstack, tmp)
            if f < best_f:
                best_f = f
                best_c = c
                best_x = x
        curve_eval(coef, best_c, k, D, rational, best_x, buf)
        out_t[i] = mids[best_c] + best_x
        for d in range(6):
            out_CC[i, d] = buf[d]
    return out_t, out_CC


@jit
def surface_eval(coef, c, ku, kv, D, rational, x, y, out):
    """out[0:18]: S, S_u, S_v, S_uu, S_uv, S_vv (3 each) of cell c at local (x, y);
    out[18:42]: scratch (the six homogeneous derivatives, 4 each)."""
    for d in range(D):
        s00 = 0.0
        s10 = 0.0
        s20 = 0.0
        s01 = 0.0
        s11 = 0.0
        s02 = 0.0
        for a in range(ku, -1, -1):
            base = a * (kv + 1)
            w0 = coef[c, (base + kv) * D + d]
            w1 = 0.0
            w2 = 0.0
            for b in range(kv - 1, -1, -1):
                w2 = w2 * y + w1
                w1 = w1 * y + w0
                w0 = w0 * y + coef[c, (base + b) * D + d]
            s20 = s20 * x + s10
            s10 = s10 * x + s00
            s00 = s00 * x + w0
            s11 = s11 * x + s01
            s01 = s01 * x + w1
            s02 = s02 * x + 2.0 * w2
        out[18 + d] = s00
        out[22 + d] = s10
        out[26 + d] = s01
        out[30 + d] = 2.0 * s20
        out[34 + d] = s11
        out[38 + d] = s02
    if rational:
        w = out[21]
        wu = out[25]
        wv = out[29]
        wuu = out[33]
        wuv = out[37]
        wvv = out[41]
        for d in range(3):
            S = out[18 + d] / w
            Su = (out[22 + d] - wu * S) / w
            Sv = (out[26 + d] - wv * S) / w
            out[d] = S
            out[3 + d] = Su
            out[6 + d] = Sv
            out[9 + d] = (out[30 + d] - 2.0 * wu * Su - wuu * S) / w
            out[12 + d] = (out[34 + d] - wu * Sv - wv * Su - wuv * S) / w
            out[15 + d] = (out[38 + d] - 2.0 * wv * Sv - wvv * S) / w
    else:
        for j in range(6):
            for d in range(3):
                out[3 * j + d] = out[18 + 4 * j + d]

@jit
def dot3(out, i, j):
    return out[i] * out[j] + out[i + 1] * out[j + 1] + out[i + 2] * out[j + 2]

@jit
def surface_cell_newton(coef, cu_lo, cu_hi, cv_lo, cv_hi, c, ku, kv, D, rational, p0, p1, p2,
                        tol, finish, reach, max_iter, max_halvings, buf):
    """Safeguarded Newton kept inside cell c (local box [cu_lo, cu_hi] x [cv_lo, cv_hi]),
    from its middle: coordinates at a bound whose descent points out are frozen (the 1D
    problem along that edge); Gauss-Newton (first fundamental form) where the Hessian is
    not clearly positive definite. Returns (x, y, squared distance, whether it converged
    by Newton steps to a point inside the cell)."""
    tx = 0.5 * (cu_lo + cu_hi)
    ty = 0.5 * (cv_lo + cv_hi)
    xa = tx
    ya = ty
    f_acc = np.inf
    sdu = 0.0
    sdv = 0.0
    halvings = 0
    Sua0 = 0.0
    Sua1 = 0.0
    Sua2 = 0.0
    Sva0 = 0.0
    Sva1 = 0.0
    Sva2 = 0.0
    x_out = tx
    y_out = ty
    f_out = np.inf
    E = 0.0
    G = 0.0
    inner = False
    for _ in range(max_iter):
        surface_eval(coef, c, ku, kv, D, rational, tx, ty, buf)
        buf[0] -= p0
        buf[1] -= p1
        buf[2] -= p2
        f = dot3(buf, 0, 0)
        gu = dot3(buf, 3, 0)
        gv = dot3(buf, 6, 0)
        acc = True
        if f_acc < np.inf:
            acc = f <= f_acc + 8e-16 * (f_acc + 2.0 * np.sqrt(f_acc) * reach)
        newton = False
        if acc:
            xa = tx
            ya = ty
            f_acc = f
            halvings = 0
            Sua0 = buf[3]
            Sua1 = buf[4]
            Sua2 = buf[5]
            Sva0 = buf[6]
            Sva1 = buf[7]
            Sva2 = buf[8]
            E = dot3(buf, 3, 3)
            F = dot3(buf, 3, 6)
            G = dot3(buf, 6, 6)
            huu = E + dot3(buf, 9, 0)
            huv = F + dot3(buf, 12, 0)
            hvv = G + dot3(buf, 15, 0)
            det = huu * hvv - huv * huv
            newton = huu > 1e-6 * E and hvv > 1e-6 * G and det > 1e-6 * (E * G - F * F)
            if not newton:
                huu = E
                huv = F
                hvv = G
                det = E * G - F * F
            du = 0.0
            dv = 0.0
            if det > 0.0:
                du = -(hvv * gu - huv * gv) / det
                dv = -(huu * gv - huv * gu) / det
            fix_u = (xa <= cu_lo and gu > 0.0) or (xa >= cu_hi and gu < 0.0)
            fix_v = (ya <= cv_lo and gv > 0.0) or (ya >= cv_hi and gv < 0.0)
            if fix_u or fix_v:
                newton = False
                eu = E + dot3(buf, 9, 0)
                ev = G + dot3(buf, 15, 0)
                # 1D Newton along the edge; where f is not clearly convex along it, to the
                # end of the edge in the descent direction (halved back where worse)
                if fix_u:
                    du = 0.0
                elif eu > 1e-6 * E:
                    du = -gu / eu
                elif gu != 0.0:
                    du = (cu_lo if gu > 0.0 else cu_hi) - xa
                else:
                    du = 0.0
                if fix_v:
                    dv = 0.0
                elif ev > 1e-6 * G:
                    dv = -gv / ev
                elif gv != 0.0:
                    dv = (cv_lo if gv > 0.0 else cv_hi) - ya
                else:
                    dv = 0.0
        else:
            halvings += 1
            du = 0.5 * sdu
            dv = 0.5 * sdv
        # the largest fraction of the step that stays in the cell; where that is tiny
        # (the step starts at a bound) the coordinates are clipped instead
        frac = 1.0
        if du > 0.0 and xa + du > cu_hi:
            frac = min(frac, (cu_hi - xa) / du)
        if du < 0.0 and xa + du < cu_lo:
            frac = min(frac, (cu_lo - xa) / du)
        if dv > 0.0 and ya + dv > cv_hi:
            frac = min(frac, (cv_hi - ya) / dv)
        if dv < 0.0 and ya + dv < cv_lo:
            frac = min(frac, (cv_lo - ya) / dv)
        if acc and frac <= 1e-3:
            # the step leaves the cell at once (a coordinate at a bound that the coupled
            # step pushes out while its own descent points in): scaled steepest descent
            # instead, which points into the cell, cut at the cell's boundary
            newton = False
            du = -gu / E if E > 0.0 else 0.0
            dv = -gv / G if G > 0.0 else 0.0
            if (xa <= cu_lo and du < 0.0) or (xa >= cu_hi and du > 0.0):
                du = 0.0
            if (ya <= cv_lo and dv < 0.0) or (ya >= cv_hi and dv > 0.0):
                dv = 0.0
            frac = 1.0
            if du > 0.0 and xa + du > cu_hi:
                frac = min(frac, (cu_hi - xa) / du)
            if du < 0.0 and xa + du < cu_lo:
                frac = min(frac, (cu_lo - xa) / du)
            if dv > 0.0 and ya + dv > cv_hi:
                frac = min(frac, (cv_hi - ya) / dv)
            if dv < 0.0 and ya + dv < cv_lo:
                frac = min(frac, (cv_lo - ya) / dv)
        clamped = frac < 1.0
        nx = min(max(xa + frac * du, cu_lo), cu_hi)
        ny = min(max(ya + frac * dv, cv_lo), cv_hi)
        if clamped:  # onto the bound the step was cut at, exactly (not an ulp short)
            eu = 1e-12 * (cu_hi - cu_lo)
            ev = 1e-12 * (cv_hi - cv_lo)
            if du > 0.0 and nx >= cu_hi - eu:
                nx = cu_hi
            if du < 0.0 and nx <= cu_lo + eu:
                nx = cu_lo
            if dv > 0.0 and ny >= cv_hi - ev:
                ny = cv_hi
            if dv < 0.0 and ny <= cv_lo + ev:
                ny = cv_lo
        ex = nx - xa
        ey = ny - ya
        m0 = ex * Sua0 + ey * Sva0
        m1 = ex * Sua1 + ey * Sva1
        m2 = ex * Sua2 + ey * Sva2
        move = np.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
        if acc and newton and not clamped and move <= finish:
            x_out = nx
            y_out = ny
            f_out = f_acc + gu * ex + gv * ey  # after the last step (second order)
            inner = cu_lo < nx < cu_hi and cv_lo < ny < cv_hi
            break
        if move <= tol or halvings > max_halvings:
            x_out = xa
            y_out = ya
            f_out = f_acc
            inner = acc and newton and cu_lo < xa < cu_hi and cv_lo < ya < cv_hi
            break
        tx = nx
        ty = ny
        sdu = ex
        sdv = ey
        x_out = xa
        y_out = ya
        f_out = f_acc
    return x_out, y_out, f_out, inner

@jit
def edge_lower_bound(fnet, e, n, p0, p1, p2):
    """Lower bound of the squared distance from p to curve cell e: the smallest ratio of
    the Bernstein coefficients (row e of ``fnet``: F0, F1x, F1y, F1z, F2, n each; see
    geometry._bernstein.distance_nets)."""
    pp = p0 * p0 + p1 * p1 + p2 * p2
    low = np.inf
    for j in range(n):
        num = fnet[e, j] - 2.0 * (p0 * fnet[e, n + j] + p1 * fnet[e, 2 * n + j] + p2 * fnet[e, 3 * n + j])
        low = min(low, (num + pp * fnet[e, 4 * n + j]) / fnet[e, 4 * n + j])
    return low


@jit
def surface_project(P, nodes, level_start, branch, leaf_cell, coef, su, sv, ku, kv, D, rational,
                    prune_u, prune_v, tol, finish, extent, max_iter, max_halvings, cert,
                    ue_coef, ue_ends, ue_stat, ue_M, ue_fnet, ve_coef, ve_ends, ve_stat, ve_M, ve_fnet, max_depth,
                    rep, rep_cell):
    """Per point: best-first over the top boxes, depth first below them; every leaf cell
    closer than the best distance so far (and not proved monotone along u or v) gets the
    cell Newton. Returns u, v and S, S_u, S_v (9 columns) of the best."""
    m = P.shape[0]
    n_levels = len(level_start) - 1
    leaf0 = level_start[n_levels - 1]
    n_top = level_start[1]
    n_cells = len(leaf_cell)
    cv = len(sv) - 1
    cu = len(su) - 1
    out_uv = np.empty((m, 2))
    out_S = np.empty((m, 9))
    buf = np.empty(42)
    ebuf = np.empty(21)
    M = max(ue_M, ve_M)
    bstack = np.empty((max_depth + 3, M + 1))
    sstack = np.empty((max_depth + 3, 3))
    tmp = np.empty(M + 1)
    gaps = np.empty(n_top)
    stack = np.empty(n_levels * branch + 1, dtype=np.int64)
    gstack = np.empty(n_levels * branch + 1)
    for i in range(m):
        p0 = P[i, 0]
        p1 = P[i, 1]
        p2 = P[i, 2]
        reach = max(abs(p0), max(abs(p1), abs(p2))) + extent
        first = top_gaps(nodes, n_top, p0, p1, p2, gaps)
        best_f = np.inf
        best_c = -1
        best_x = 0.0
        best_y = 0.0
        for a in range(-1, n_top):
            root = first if a < 0 else a
            if a == first or (best_c >= 0 and gaps[root] >= best_f * (1.0 - cert)):
                continue
            top = 0
            stack[top] = root
            gstack[top] = gaps[root]
            top += 1
            while top > 0:
                top -= 1
                nd = stack[top]
                if gstack[top] >= best_f * (1.0 - cert):
                    continue
                # a point of the surface in the node: an upper bound of the answer
                r0 = rep[nd, 0] - p0
                r1 = rep[nd, 1] - p1
                r2 = rep[nd, 2] - p2
                f = r0 * r0 + r1 * r1 + r2 * r2
                if f < best_f:
                    best_f = f
                    best_c = rep_cell[nd]
                    best_x = 0.0
                    best_y = 0.0
                if nd < leaf0:
                    top = push_children(nodes, level_start, branch, nd, p0, p1, p2, best_f * (1.0 - cert), stack, gstack, top)
                    continue
                leaf = nd - leaf0
                if leaf >= n_cells:
                    continue
                c = leaf_cell[leaf]
                ci = c // cv
                cj = c % cv
                if best_c >= 0:
                    # monotone along u (v) over the cell: its smallest distance lies on the
                    # edge it shares with the neighbouring cell (not at the domain's edge)
                    if prune_u:
                        low, high = field_bounds(nodes, nd, p0, p1, p2, 0)
                        if (low > 0.0 and ci > 0) or (high < 0.0 and ci < cu - 1):
                            continue
                    if prune_v:
                        low, high = field_bounds(nodes, nd, p0, p1, p2, 1)
                        if (low > 0.0 and cj > 0) or (high < 0.0 and cj < cv - 1):
                            continue
                mu = 0.5 * (su[ci] + su[ci + 1])
                mv = 0.5 * (sv[cj] + sv[cj + 1])
                ulo = su[ci] - mu
                uhi = su[ci + 1] - mu
                vlo = sv[cj] - mv
                vhi = sv[cj + 1] - mv
                x, y, f, inner = surface_cell_newton(coef, ulo, uhi, vlo, vhi, c, ku, kv, D, rational, p0, p1, p2,
                                                     tol, finish, reach, max_iter, max_halvings, buf)
                if f < best_f:
                    best_f = f
                    best_c = c
                    best_x = x
                    best_y = y
                # the cell's edges, where the Bernstein bound of the distance along the edge
                # is below the best: their minima by isolation as for curve cells (a
                # minimum on an edge beside an inner one, or one the 2D descent missed)
                slack = 1e-15 * reach * reach
                for e in range(4):
                    along_u = e < 2
                    eid = 2 * c + (e % 2)
                    if along_u:
                        low = edge_lower_bound(ue_fnet, eid, 2 * ku + 1, p0, p1, p2)
                    else:
                        low = edge_lower_bound(ve_fnet, eid, 2 * kv + 1, p0, p1, p2)
                    if low - slack >= best_f * (1.0 - cert):
                        continue
                    if along_u:
                        fixed = vlo if e == 0 else vhi
                        z, f = curve_cell_minima(ue_coef, ue_ends, ue_stat, ue_M, eid, ulo, uhi - ulo, ku, D, rational,
                                                 p0, p1, p2, tol, finish, max_iter, max_depth, ebuf, bstack, sstack, tmp)
                    else:
                        fixed = ulo if e == 2 else uhi
                        z, f = curve_cell_minima(ve_coef, ve_ends, ve_stat, ve_M, eid, vlo, vhi - vlo, kv, D, rational,
                                                 p0, p1, p2, tol, finish, max_iter, max_depth, ebuf, bstack, sstack, tmp)
                    if f < best_f:
                        best_f = f
                        best_c = c
                        best_x = z if along_u else fixed
                        best_y = fixed if along_u else z
        ci = best_c // cv
        cj = best_c % cv
        mu = 0.5 * (su[ci] + su[ci + 1])
        mv = 0.5 * (sv[cj] + sv[cj + 1])
        surface_eval(coef, best_c, ku, kv, D, rational, best_x, best_y, buf)
        out_uv[i, 0] = mu + best_x
        out_uv[i, 1] = mv + best_y
        for d in range(9):
            out_S[i, d] = buf[d]
    return out_uv, out_S
