"""Compiled per-point kernels of B-spline projection (optional: numba, the ``fast`` extra).

The projection of :mod:`geometry.bspline` runs a branch and bound over Bezier cells with a
Newton solve per candidate cell. Vectorised with numpy it is bound by memory traffic:
every step gathers per-pair table rows and makes array temporaries (measured on the
2-core benchmark machine: ~1 ns per element and 3-8 ns per gathered element). These
kernels run the same algorithm point by point in compiled loops (one core, no threads),
with the bound tightened as soon as a cell gives a closer point. Without numba (or with
``IBFEM_NO_JIT=1`` in the environment) :mod:`geometry.bspline` uses its numpy path; the
two are tested against each other.

Tables (built once per spline in :mod:`geometry.bspline`):

* ``nodes`` (n_nodes, 21): per node of the box hierarchy (all levels, top first) its
  frame rows R (9), frame centre ``R origin + box centre`` (3), half widths (3), and for
  leaf cells the box of a tangent field's numerator in the same frame (lo 3, hi 3);
  ``level_start`` (levels + 1,): the first node of each level; node i of level l has the
  children ``level_start[l + 1] + branch i + c``; padding nodes have half widths -1e150;
* curves: ``coef`` (n_cells, (k + 1) D) Taylor coefficients of each cell's piece about
  its middle (row i D + d: coefficient of x^i of homogeneous component d), ``mids``,
  ``edges`` (n_cells + 1), ``ends`` (n_cells, 6): the cell's first and last point.
"""

from __future__ import annotations

import os

import numpy as np

_KERNELS = None


def enabled() -> bool:
    """Whether the compiled kernels are used: numba importable and ``IBFEM_NO_JIT`` unset."""
    global _KERNELS
    if os.environ.get("IBFEM_NO_JIT", "") not in ("", "0"):
        return False
    if _KERNELS is None:
        try:
            _KERNELS = _build()
        except ImportError:
            _KERNELS = False
    return _KERNELS is not False


def kernels():
    enabled()
    return _KERNELS


def _build():
    import numba  # noqa: F401  (ImportError: numpy path)
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
    def curve_cell_newton(coef, mids, edges, ends, c, k, D, rational, p0, p1, p2, tol, finish, reach, max_iter, max_halvings, buf):
        """Safeguarded Newton kept inside cell c (see BSplineCurve._cell_newton): returns
        (local parameter, squared distance)."""
        mid = mids[c]
        lo = edges[c] - mid
        hi = edges[c + 1] - mid
        ax = ends[c, 0] - p0
        ay = ends[c, 1] - p1
        az = ends[c, 2] - p2
        bx = ends[c, 3] - ends[c, 0]
        by = ends[c, 4] - ends[c, 1]
        bz = ends[c, 5] - ends[c, 2]
        fa = ax * ax + ay * ay + az * az
        ex = ax + bx
        ey = ay + by
        ez = az + bz
        fb = ex * ex + ey * ey + ez * ez
        bb = bx * bx + by * by + bz * bz
        frac = -(ax * bx + ay * by + az * bz) / bb if bb > 1e-300 else 0.0
        frac = min(max(frac, 0.0), 1.0)
        trial = lo + frac * (hi - lo)
        x_acc = trial
        f_acc = np.inf
        speed_acc = 0.0
        step = 0.0
        halvings = 0
        x_out = trial
        f_out = np.inf
        for _ in range(max_iter):
            curve_eval(coef, c, k, D, rational, trial, buf)
            r0 = buf[0] - p0
            r1 = buf[1] - p1
            r2 = buf[2] - p2
            f = r0 * r0 + r1 * r1 + r2 * r2
            g = buf[3] * r0 + buf[4] * r1 + buf[5] * r2
            sp2 = buf[3] * buf[3] + buf[4] * buf[4] + buf[5] * buf[5]
            h = sp2 + buf[6] * r0 + buf[7] * r1 + buf[8] * r2
            acc = f <= f_acc + 8e-16 * (f_acc + 2.0 * np.sqrt(f_acc) * reach) if f_acc < np.inf else True
            newton = h > 1e-6 * sp2
            if acc:
                x_acc = trial
                f_acc = f
                speed_acc = np.sqrt(sp2)
                halvings = 0
                if g == 0.0:
                    dx = 0.0
                elif newton:
                    dx = -g / h
                else:  # not clearly convex: descend to the cell's end (halved back if worse)
                    dx = (lo if g > 0.0 else hi) - trial
                new_step = dx
            else:
                halvings += 1
                new_step = 0.5 * step
            raw = x_acc + new_step
            new = min(max(raw, lo), hi)
            eff = new - x_acc
            move = abs(eff) * speed_acc
            if acc and newton and new == raw and move <= finish:
                x_out = new
                f_out = f_acc + g * eff  # after the last step (second order)
                break
            if move <= tol or halvings > max_halvings:
                x_out = x_acc
                f_out = f_acc
                break
            trial = new
            step = eff
            x_out = x_acc
            f_out = f_acc
        margin = 8e-16 * (f_out + 2.0 * np.sqrt(f_out) * reach)  # round-off of f
        if fa < f_out - margin or fb < f_out - margin:
            if fa <= fb:
                return lo, fa
            return hi, fb
        return x_out, f_out

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
    def curve_project(P, nodes, level_start, branch, coef, mids, edges, ends, k, D, rational,
                      periodic, prune, tol, finish, extent, max_iter, max_halvings, cert):
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
        gaps = np.empty(n_top)
        stack = np.empty(n_levels * branch + 1, dtype=np.int64)
        for i in range(m):
            p0 = P[i, 0]
            p1 = P[i, 1]
            p2 = P[i, 2]
            reach = max(abs(p0), max(abs(p1), abs(p2))) + extent
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
                top += 1
                while top > 0:
                    top -= 1
                    nd = stack[top]
                    if nd != root or best_c >= 0:
                        if box_gap2(nodes, nd, p0, p1, p2) >= best_f * (1.0 - cert):
                            continue
                    if nd < leaf0:
                        lvl = 0
                        while level_start[lvl + 1] <= nd:
                            lvl += 1
                        base = level_start[lvl + 1] + (nd - level_start[lvl]) * branch
                        for ch in range(branch):
                            stack[top] = base + ch
                            top += 1
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
                    x, f = curve_cell_newton(coef, mids, edges, ends, c, k, D, rational, p0, p1, p2, tol, finish,
                                             reach, max_iter, max_halvings, buf)
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

    return {"curve_project": curve_project, "curve_eval": curve_eval, "curve_cell_newton": curve_cell_newton, "box_gap2": box_gap2}
