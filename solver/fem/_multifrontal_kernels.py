"""The compiled kernels of :mod:`solver.fem.multifrontal` (numba), at module level so that
numba's on-disk cache (``cache=True``) keeps them between processes. Imported only by
:mod:`solver.fem.multifrontal` on the first factorisation: importing this module imports numba.

Conventions (all indices int64, columns in the elimination order):

* the matrix is its lower triangle, CSC (``colptr``, ``rowind``, ``values``: rows >= column);
* a front of F rows is a row-major (F, F) array ``t`` whose row j holds column j of the front's
  lower triangle: ``t[j, i]`` = entry (i, j), i >= j (the upper part of ``t`` is used);
* the factor K = L D L^T (unit L, no pivoting) of supernode s (nc columns, F front rows) is an
  (nc, F) row-major block of the flat ``factor`` array at ``factor_ptr[s]``: row k is column
  c0 + k of L on the front rows, D in place of its unit diagonal.

References: J. W. H. Liu, "The multifrontal method for sparse matrix solution: theory and
practice", SIAM Review 34 (1992); the elimination tree by path compression (Liu 1986) and the
column counts by the skeleton-matrix / least-common-ancestor algorithm of Gilbert, Ng and
Peyton (1994), as described in T. A. Davis, "Direct Methods for Sparse Linear Systems" (SIAM
2006), chapter 4. Written here from those descriptions."""

from __future__ import annotations

import ctypes
import math

import numpy as np
from numba import njit
from numba.extending import get_cython_function_address

jit = njit(cache=True, nogil=True, error_model="numpy")

_P = ctypes.c_void_p
#: BLAS dgemm (SciPy's, Fortran interface: every argument by address), passed to the kernels as
#: an argument (a first-class function: numba's cache keeps its signature, not its address), so
#: that a front's updates accumulate in place with the front's own leading dimension
DGEMM = ctypes.CFUNCTYPE(None, _P, _P, _P, _P, _P, _P, _P, _P, _P, _P, _P, _P, _P)(
    get_cython_function_address("scipy.linalg.cython_blas", "dgemm"))

#: columns of a panel factored by compiled loops; block columns of a BLAS update
PANEL = 48
BLOCK = 256
#: pivot columns of an outer block: its panels update only the block's own rows, then the rows
#: below it take one BLAS update of inner dimension OUTER (a large front's update matrix is
#: read and written once per OUTER pivots instead of once per PANEL)
OUTER = 256
#: trailing updates of fewer multiply-adds than this run in compiled loops (no BLAS call)
SMALL_UPDATE = 32768


@jit
def elimination_tree(rowptr, colind, n):
    """Parent of every column (-1 for roots) from the lower triangle by rows (CSR: row k
    holds columns j <= k): Liu's algorithm with path compression."""
    parent = np.full(n, -1, np.int64)
    ancestor = np.full(n, -1, np.int64)
    for k in range(n):
        for p in range(rowptr[k], rowptr[k + 1]):
            i = colind[p]
            while i != -1 and i < k:
                nxt = ancestor[i]
                ancestor[i] = k
                if nxt == -1:
                    parent[i] = k
                i = nxt
    return parent


@jit
def postorder(parent):
    """A postorder of the forest: children in increasing order, roots in increasing order
    (so the tree of the last column comes last)."""
    n = len(parent)
    head = np.full(n, -1, np.int64)
    nxt = np.full(n, -1, np.int64)
    for j in range(n - 1, -1, -1):
        if parent[j] != -1:
            nxt[j] = head[parent[j]]
            head[parent[j]] = j
    post = np.empty(n, np.int64)
    stack = np.empty(n, np.int64)
    k = 0
    for root in range(n):
        if parent[root] != -1:
            continue
        top = 0
        stack[0] = root
        while top >= 0:
            p = stack[top]
            child = head[p]
            if child == -1:
                top -= 1
                post[k] = p
                k += 1
            else:
                head[p] = nxt[child]
                top += 1
                stack[top] = child
    return post


@jit
def _leaf(i, j, first, maxfirst, prevleaf, ancestor):
    """(q, jleaf) of Davis's cs_leaf: whether j is a leaf of row i's subtree, and the least
    common ancestor of j and the previous leaf."""
    if i <= j or first[j] <= maxfirst[i]:
        return -1, 0
    maxfirst[i] = first[j]
    jprev = prevleaf[i]
    prevleaf[i] = j
    if jprev == -1:
        return i, 1
    q = jprev
    while q != ancestor[q]:
        q = ancestor[q]
    s = jprev
    while s != q:
        sparent = ancestor[s]
        ancestor[s] = q
        s = sparent
    return q, 2


@jit
def column_counts(colptr, rowind, parent, post, m):
    """Nonzeros of every column of L (diagonal included) for the lower triangle by columns,
    with the trailing m x m block taken as dense and every other column whose parent is in it
    given a virtual entry in row n - m (the root supernode)."""
    n = len(parent)
    first = np.full(n, -1, np.int64)
    delta = np.zeros(n, np.int64)
    for k in range(n):
        j = post[k]
        delta[j] = 1 if first[j] == -1 else 0
        while j != -1 and first[j] == -1:
            first[j] = k
            j = parent[j]
    maxfirst = np.full(n, -1, np.int64)
    prevleaf = np.full(n, -1, np.int64)
    ancestor = np.arange(n)
    top = n - m
    for k in range(n):
        j = post[k]
        if parent[j] != -1:
            delta[parent[j]] -= 1
        extra = 0
        if m > 0 and j < top and parent[j] == top:
            extra = 1
        elif j >= top:
            extra = n - 1 - j
        for p in range(colptr[j], colptr[j + 1] + extra):
            if p < colptr[j + 1]:
                i = rowind[p]
            elif j < top:
                i = top
            else:
                i = j + 1 + p - colptr[j + 1]
            q, jleaf = _leaf(i, j, first, maxfirst, prevleaf, ancestor)
            if jleaf >= 1:
                delta[j] += 1
            if jleaf == 2:
                delta[q] -= 1
        if parent[j] != -1:
            ancestor[j] = parent[j]
    for j in range(n):
        if parent[j] != -1:
            delta[parent[j]] += delta[j]
    return delta


@jit
def supernodes(parent, counts, m, nrelax, zrelax):
    """Supernode partition of postordered columns: fundamental supernodes (a chain of single
    children with nested structures), the last m columns one supernode, then relaxed
    amalgamation of a child into its parent when their columns are contiguous and the zeros
    it adds stay small (``nrelax`` three column limits, ``zrelax`` three zero fractions, as in
    CHOLMOD's defaults). Returns the first column of every supernode (plus n) and the number
    of front rows below each supernode's columns."""
    n = len(parent)
    top = n - m
    nchild = np.zeros(n, np.int64)
    for j in range(n):
        if parent[j] != -1:
            nchild[parent[j]] += 1
    start = np.empty(n + 1, np.int64)
    ns = 0
    for j in range(n):
        fresh = j == 0 or j == top
        if not fresh and j < top:
            fresh = not (parent[j - 1] == j and counts[j - 1] == counts[j] + 1 and nchild[j] == 1)
        if fresh:
            start[ns] = j
            ns += 1
    start[ns] = n
    # per fundamental supernode: columns, rows below, parent supernode, entries in its trapezoid
    sn_of = np.empty(n, np.int64)
    for s in range(ns):
        sn_of[start[s]:start[s + 1]] = s
    ncol = np.empty(ns, np.int64)
    nrow = np.empty(ns, np.int64)
    snp = np.full(ns, -1, np.int64)
    first = start[:ns].copy()
    nz = np.empty(ns, np.float64)  # true nonzeros of the (merged) supernode's columns
    for s in range(ns):
        ncol[s] = start[s + 1] - start[s]
        nrow[s] = counts[start[s]] - ncol[s]
        last = start[s + 1] - 1
        if parent[last] != -1:
            snp[s] = sn_of[parent[last]]
        nz[s] = ncol[s] * (ncol[s] + 1) / 2.0 + ncol[s] * nrow[s]
    rep = np.arange(ns)
    for s in range(ns - 2, -1, -1):
        if snp[s] == -1:
            continue
        p = rep[snp[s]]
        if (m > 0 and p == ns - 1) or start[s + 1] != first[p]:
            continue
        nc = ncol[s] + ncol[p]
        total = nc * (nc + 1) / 2.0 + nc * nrow[p]
        frac = (total - nz[s] - nz[p]) / total
        merge = nc <= nrelax[0] or (nc <= nrelax[1] and frac < zrelax[0]) or \
            (nc <= nrelax[2] and frac < zrelax[1]) or frac < zrelax[2]
        if merge:
            rep[s] = p
            first[p] = first[s]
            ncol[p] = nc
            nz[p] += nz[s]
    out = np.empty(ns + 1, np.int64)
    below = np.empty(ns, np.int64)
    k = 0
    for s in range(ns):
        if rep[s] == s:
            out[k] = first[s]
            below[k] = nrow[s]
            k += 1
    out[k] = n
    return out[: k + 1].copy(), below[:k].copy()


@jit
def row_structure(colptr, rowind, sn_start, sn_below, parent):
    """Rows below every supernode's columns (sorted, flat with offsets) and the parent
    supernode of each (-1 for roots): the union of the matrix's rows and the children's
    rows, by a marker. A mismatch with the counted sizes (a bug) returns an empty parent."""
    ns = len(sn_below)
    n = sn_start[ns]
    row_ptr = np.zeros(ns + 1, np.int64)
    for s in range(ns):
        row_ptr[s + 1] = row_ptr[s] + sn_below[s]
    rows = np.empty(row_ptr[ns], np.int64)
    sn_of = np.empty(n, np.int64)
    for s in range(ns):
        sn_of[sn_start[s]:sn_start[s + 1]] = s
    sn_parent = np.full(ns, -1, np.int64)
    head = np.full(ns, -1, np.int64)
    nxt = np.full(ns, -1, np.int64)
    for s in range(ns):
        last = sn_start[s + 1] - 1
        if parent[last] != -1:
            p = sn_of[parent[last]]
            sn_parent[s] = p
            nxt[s] = head[p]
            head[p] = s
    mark = np.full(n, -1, np.int64)
    failed = (row_ptr, rows, np.empty(0, np.int64))
    for s in range(ns):
        c1 = sn_start[s + 1]
        k = row_ptr[s]
        end = row_ptr[s + 1]
        for j in range(sn_start[s], c1):
            for p in range(colptr[j], colptr[j + 1]):
                k = _push_row(rowind[p], s, c1, mark, rows, k, end)
                if k < 0:
                    return failed
        c = head[s]
        while c != -1:
            for p in range(row_ptr[c], row_ptr[c + 1]):
                k = _push_row(rows[p], s, c1, mark, rows, k, end)
                if k < 0:
                    return failed
            c = nxt[c]
        if parent[c1 - 1] != -1:  # the virtual entry of a child of the root supernode (its first column)
            k = _push_row(parent[c1 - 1], s, c1, mark, rows, k, end)
        if k != end:
            return failed
        rows[row_ptr[s]:end].sort()
    return row_ptr, rows, sn_parent


@jit
def _push_row(i, s, c1, mark, rows, k, end):
    """Append row i (below the supernode's last column c1 - 1, not yet marked for s) to the
    structure being written at rows[k]; the next k, or -1 when the counted size is exceeded."""
    if i < c1 or mark[i] == s:
        return k
    if k == end:
        return -1
    mark[i] = s
    rows[k] = i
    return k + 1


@jit
def _panel(t, k0, k1, f, definite):
    """Right-looking L D L^T of front columns k0..k1-1 (updates inside the panel only); the
    panel's rows keep D L^T (scaled by :func:`_scale` after the trailing update). Returns the
    first column with a zero or non-finite pivot (non-positive when ``definite``), or -1."""
    for k in range(k0, k1):
        d = t[k, k]
        if not (d > 0.0 or (not definite and d < 0.0)) or not math.isfinite(d):
            return k
        inv = 1.0 / d
        for j in range(k + 1, k1):
            ljk = t[k, j] * inv
            if ljk != 0.0:
                for i in range(j, f):
                    t[j, i] -= ljk * t[k, i]
    return -1


@jit
def _gemm_update(gemm, t, k0, k1, j0, j1, f, ls, ld):
    """Columns j0..j1-1 of the front, rows j0..f-1 (t[j, i], i >= j0), less L D L^T of the
    pivots k0..k1-1: one dgemm into the front in place. In Fortran terms the row-major front is
    its transpose T (leading dimension f); T[j0:f, j0:j1] -= T[j0:f, k0:k1] Ls^T, with Ls
    (j1 - j0 rows, leading dimension ``ld``) the scaled L of those columns, ``ls`` starting at
    its first row. Entries above the diagonal of T's block are written too (t's unused lower
    part)."""
    ints = np.empty(6, np.int32)
    ints[0], ints[1], ints[2] = f - j0, j1 - j0, k1 - k0
    ints[3], ints[4], ints[5] = f, ld, f
    chars = np.empty(2, np.uint8)
    chars[0], chars[1] = 78, 84  # "N", "T"
    scalars = np.empty(2)
    scalars[0], scalars[1] = -1.0, 1.0
    gemm(chars[0:1].ctypes, chars[1:2].ctypes, ints[0:1].ctypes, ints[1:2].ctypes, ints[2:3].ctypes,
         scalars[0:1].ctypes, t[k0:, j0:].ctypes, ints[3:4].ctypes, ls.ctypes, ints[4:5].ctypes,
         scalars[1:2].ctypes, t[j0:, j0:].ctypes, ints[5:6].ctypes)


@jit
def _trailing(gemm, t, k0, k1, j_end, f):
    """Update front rows k1..j_end-1 (columns from the row's own on, rows >= column) by the
    factored pivots k0..k1-1 (rows D L^T): :func:`trailing_rows` from row k1."""
    trailing_rows(gemm, t, k0, k1, k1, j_end, f)


@jit
def trailing_rows(gemm, t, k0, k1, j_lo, j_hi, f):
    """Update front rows j_lo..j_hi-1 (j_lo >= k1; columns from the row's own on) by the
    factored pivots k0..k1-1 (rows D L^T): loops when small, else BLAS products into the front
    by blocks of BLOCK rows from j_lo. Disjoint row ranges touch disjoint entries of the front,
    so two threads may update two of them at once."""
    if f <= j_lo or j_hi <= j_lo:
        return
    if (k1 - k0) * (j_hi - j_lo) * (f - j_lo) < 2 * SMALL_UPDATE:
        for k in range(k0, k1):
            inv = 1.0 / t[k, k]
            for j in range(j_lo, j_hi):
                ljk = t[k, j] * inv
                if ljk != 0.0:
                    for i in range(j, f):
                        t[j, i] -= ljk * t[k, i]
        return
    width = j_hi - j_lo
    ls = np.empty((k1 - k0, width))  # Fortran view: (width x pivots), the scaled L of the rows updated
    for k in range(k0, k1):
        inv = 1.0 / t[k, k]
        for jj in range(width):
            ls[k - k0, jj] = t[k, j_lo + jj] * inv
    for j0 in range(j_lo, j_hi, BLOCK):
        j1 = min(j0 + BLOCK, j_hi)
        _gemm_update(gemm, t, k0, k1, j0, j1, f, ls[:, j0 - j_lo:], width)


@jit
def _partial_ldlt(gemm, t, nc, f, definite):
    """L D L^T of the first nc columns of the front (rows: D on the diagonal, L^T right of
    it); the update matrix left in t[nc:, nc:]. Returns the failed column or -1.

    Two levels of blocking: within an outer block of OUTER pivots, panels of PANEL columns are
    factored by compiled loops and update the outer block's remaining rows only
    (:func:`outer_block`); the outer block then updates every row below it by BLAS products of
    inner dimension OUTER that accumulate in the front (its update matrix, most of a large
    front, is swept once per outer block), and its rows are scaled (:func:`scale_rows`)."""
    for b0 in range(0, nc, OUTER):
        b1 = min(b0 + OUTER, nc)
        bad = outer_block(gemm, t, b0, b1, f, definite)
        if bad >= 0:
            return bad
        _trailing(gemm, t, b0, b1, f, f)
        scale_rows(t, b0, b1, f)
    return -1


@jit
def outer_block(gemm, t, b0, b1, f, definite):
    """The panels of pivots b0..b1-1 of the front factored, each updating the block's own rows
    below it: :func:`_partial_ldlt`'s step before the update of the rows below the block.
    Returns the failed column or -1."""
    for k0 in range(b0, b1, PANEL):
        k1 = min(k0 + PANEL, b1)
        bad = _panel(t, k0, k1, f, definite)
        if bad >= 0:
            return bad
        _trailing(gemm, t, k0, k1, b1, f)
    return -1


@jit
def scale_rows(t, b0, b1, f):
    """Rows b0..b1-1 of the front from D L^T to L^T (D stays on the diagonal)."""
    for k in range(b0, b1):
        inv = 1.0 / t[k, k]
        for i in range(k + 1, f):
            t[k, i] *= inv


@jit
def numeric_work(n, ns, stack_size, max_front):
    """The work space of :func:`multifrontal_range`, kept between its calls: (update-matrix
    stack, front buffer, positions of the rows in the current front, stack's supernodes, their
    offsets, stack depth)."""
    st_off = np.empty(ns + 1, np.int64)
    st_off[0] = 0
    return (np.empty(stack_size, np.float64), np.empty(max_front * max_front, np.float64), np.empty(n, np.int64),
            np.empty(ns, np.int64), st_off, np.zeros(1, np.int64))


@jit
def multifrontal_range(colptr, rowind, values, sn_start, row_ptr, rows, sn_parent, factor_ptr, s0, s1,
                       segment, base, work, schur, definite, gemm):
    """The numeric factorisation of supernodes s0..s1-1 (in postorder, continuing from
    s0 - 1 with the work space ``work`` of :func:`numeric_work`): assemble each front from the
    matrix and the children's update matrices (popped off a stack), factor its columns,
    push its update matrix (L D L^T without pivoting: D on the factor's diagonal; a zero pivot
    fails, a negative one too when ``definite``). Supernode s's block is written to
    ``segment[factor_ptr[s] - base:]``, so a caller may hold one range of the factor at a time.
    The last supernode's assembled front is copied into ``schur`` when that has its size (the
    root of the contact dofs). Roots are assembled in their factor blocks, other fronts in the
    front buffer. Returns the failed column or -1."""
    for s in range(s0, s1):
        t = assemble_front(colptr, rowind, values, sn_start, row_ptr, rows, sn_parent, factor_ptr, s, segment,
                           base, work, schur)
        nc = sn_start[s + 1] - sn_start[s]
        bad = _partial_ldlt(gemm, t, nc, t.shape[0], definite)
        if bad >= 0:
            return sn_start[s] + bad
        store_front(sn_start, row_ptr, sn_parent, factor_ptr, s, t, segment, base, work)
    return -1


@jit
def assemble_front(colptr, rowind, values, sn_start, row_ptr, rows, sn_parent, factor_ptr, s, segment, base,
                   work, schur):
    """The front of supernode s (:func:`multifrontal_range`'s first step): the matrix's columns
    and the children's update matrices popped off the stack, in the front buffer (a root: in
    its factor block); the root of the contact dofs copied into ``schur``. Returns the front."""
    stack, buf, relpos, st_sn, st_off, state = work
    ns = len(sn_parent)
    depth = state[0]
    c0, c1 = sn_start[s], sn_start[s + 1]
    nc = c1 - c0
    nr = row_ptr[s + 1] - row_ptr[s]
    f = nc + nr
    off = factor_ptr[s] - base
    if nr == 0:  # a root: its front is its factor block (no copy)
        t = segment[off:off + f * f].reshape(f, f)
    else:
        t = buf[: f * f].reshape(f, f)
    for j in range(f):
        t[j, j:] = 0.0
    for k in range(nc):
        relpos[c0 + k] = k
    for k in range(nr):
        relpos[rows[row_ptr[s] + k]] = nc + k
    for j in range(c0, c1):
        for p in range(colptr[j], colptr[j + 1]):
            t[j - c0, relpos[rowind[p]]] += values[p]
    while depth > 0 and sn_parent[st_sn[depth - 1]] == s:
        c = st_sn[depth - 1]
        at = st_off[depth - 1]
        cr = rows[row_ptr[c]:row_ptr[c + 1]]
        w = len(cr)
        for a in range(w):
            pa = relpos[cr[a]]
            for b in range(a, w):
                t[pa, relpos[cr[b]]] += stack[at + a * w + b]
        depth -= 1
    state[0] = depth
    if s == ns - 1 and schur.shape[0] == nc and nr == 0:
        for j in range(nc):
            for i in range(j, nc):
                schur[i, j] = t[j, i]
                schur[j, i] = t[j, i]
    return t


@jit
def store_front(sn_start, row_ptr, sn_parent, factor_ptr, s, t, segment, base, work):
    """The factored front of supernode s (:func:`multifrontal_range`'s last step): its pivot
    rows into its factor block, its update matrix pushed on the stack."""
    stack, buf, relpos, st_sn, st_off, state = work
    depth = state[0]
    nc = sn_start[s + 1] - sn_start[s]
    nr = row_ptr[s + 1] - row_ptr[s]
    f = nc + nr
    off = factor_ptr[s] - base
    for k in range(nc):
        for i in range(k):
            segment[off + k * f + i] = 0.0
        if nr > 0:
            for i in range(k, f):
                segment[off + k * f + i] = t[k, i]
    if nr > 0 and sn_parent[s] != -1:
        at = st_off[depth]
        for a in range(nr):
            for b in range(a, nr):
                stack[at + a * nr + b] = t[nc + a, nc + b]
        st_sn[depth] = s
        st_off[depth + 1] = at + nr * nr
        state[0] = depth + 1


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def _solve_vector(factor, factor_ptr, sn_start, row_ptr, rows, b):
    """:func:`solve` for one right-hand side: :func:`forward_range` then :func:`backward_range`
    over every supernode of a factor held in memory (``base`` 0)."""
    ns = len(row_ptr) - 1
    forward_range(factor, 0, 0, ns, factor_ptr, sn_start, row_ptr, rows, b)
    backward_range(factor, 0, 0, ns, factor_ptr, sn_start, row_ptr, rows, b)


@jit
def solve(factor, factor_ptr, sn_start, row_ptr, rows, b):
    """Overwrite b (n, r) with K^-1 b: L z = b forward and y = D^-1 z, then L^T x = y
    backward, supernode by supernode (unit L; columns in the factor's numbering)."""
    if b.shape[1] == 1:
        _solve_vector(factor, factor_ptr, sn_start, row_ptr, rows, b.reshape(b.shape[0]))
        return
    ns = len(row_ptr) - 1
    r = b.shape[1]
    for s in range(ns):
        c0, c1 = sn_start[s], sn_start[s + 1]
        nc = c1 - c0
        f = nc + row_ptr[s + 1] - row_ptr[s]
        off = factor_ptr[s]
        for k in range(nc):
            j = c0 + k
            for p in range(k + 1, f):
                g = c0 + p if p < nc else rows[row_ptr[s] + p - nc]
                l = factor[off + k * f + p]
                for q in range(r):
                    b[g, q] -= l * b[j, q]
            d = factor[off + k * f + k]
            for q in range(r):
                b[j, q] /= d
    for s in range(ns - 1, -1, -1):
        c0, c1 = sn_start[s], sn_start[s + 1]
        nc = c1 - c0
        f = nc + row_ptr[s + 1] - row_ptr[s]
        off = factor_ptr[s]
        for k in range(nc - 1, -1, -1):
            j = c0 + k
            for p in range(k + 1, f):
                g = c0 + p if p < nc else rows[row_ptr[s] + p - nc]
                l = factor[off + k * f + p]
                for q in range(r):
                    b[j, q] -= l * b[g, q]


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def forward_range(segment, base, s0, s1, factor_ptr, sn_start, row_ptr, rows, b):
    """The forward solve (L z = b, then z / D) over supernodes s0..s1-1
    only, their factor blocks read from ``segment`` (the factor from offset ``base`` on): a
    factor held on disk is solved chunk by chunk."""
    nr_max = 0
    for s in range(s0, s1):
        nr_max = max(nr_max, row_ptr[s + 1] - row_ptr[s])
    tmp = np.empty(nr_max, np.float64)
    for s in range(s0, s1):
        c0, c1 = sn_start[s], sn_start[s + 1]
        nc = c1 - c0
        nr = row_ptr[s + 1] - row_ptr[s]
        f = nc + nr
        off = factor_ptr[s] - base
        tmp[:nr] = 0.0
        for k in range(nc):
            x = b[c0 + k]
            row = segment[off + k * f:off + (k + 1) * f]
            for p in range(k + 1, nc):
                b[c0 + p] -= row[p] * x
            for p in range(nr):
                tmp[p] -= row[nc + p] * x
            b[c0 + k] = x / row[k]
        for p in range(nr):
            b[rows[row_ptr[s] + p]] += tmp[p]


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def backward_range(segment, base, s0, s1, factor_ptr, sn_start, row_ptr, rows, b):
    """The backward solve (L^T x = y) over supernodes s1-1 down to s0,
    their blocks read from ``segment`` as in :func:`forward_range`."""
    nr_max = 0
    for s in range(s0, s1):
        nr_max = max(nr_max, row_ptr[s + 1] - row_ptr[s])
    tmp = np.empty(nr_max, np.float64)
    for s in range(s1 - 1, s0 - 1, -1):
        c0, c1 = sn_start[s], sn_start[s + 1]
        nc = c1 - c0
        nr = row_ptr[s + 1] - row_ptr[s]
        f = nc + nr
        off = factor_ptr[s] - base
        for p in range(nr):
            tmp[p] = b[rows[row_ptr[s] + p]]
        for k in range(nc - 1, -1, -1):
            row = segment[off + k * f:off + (k + 1) * f]
            acc = 0.0
            for p in range(k + 1, nc):
                acc += row[p] * b[c0 + p]
            for p in range(nr):
                acc += row[nc + p] * tmp[p]
            b[c0 + k] -= acc


# ---------------------------------------------------------------- a large front's rows on threads
# assemble_front and store_front split by rows of the front (:func:`solver.fem.multifrontal.
# _threaded_assemble`): every entry of the front gets the same additions in the same order (zero,
# the matrix's column, then the children's update matrices from the top of the stack down), so the
# front is the same to the bit; each call writes only its own rows.


@jit
def front_positions(sn_start, row_ptr, rows, s, relpos):
    """Positions in the front of supernode s of its columns and rows (in ``relpos``)."""
    c0, c1 = sn_start[s], sn_start[s + 1]
    nc = c1 - c0
    for k in range(nc):
        relpos[c0 + k] = k
    for k in range(row_ptr[s + 1] - row_ptr[s]):
        relpos[rows[row_ptr[s] + k]] = nc + k


@jit
def _first_at_least(cr, relpos, r):
    """The first a with relpos[cr[a]] >= r (relpos increases along a child's sorted rows)."""
    lo, hi = 0, len(cr)
    while lo < hi:
        mid = (lo + hi) // 2
        if relpos[cr[mid]] < r:
            lo = mid + 1
        else:
            hi = mid
    return lo


@jit
def assemble_rows(colptr, rowind, values, sn_start, row_ptr, rows, sn_parent, s, t, work, r0, r1):
    """Rows r0..r1-1 of the front t of supernode s (not a root): zeroed, the matrix's columns
    added, then the children's update matrices on the stack (not popped: :func:`pop_children`);
    ``front_positions`` first."""
    stack, buf, relpos, st_sn, st_off, state = work
    c0 = sn_start[s]
    nc = sn_start[s + 1] - c0
    for j in range(r0, r1):
        t[j, j:] = 0.0
    for j in range(r0, min(r1, nc)):
        for p in range(colptr[c0 + j], colptr[c0 + j + 1]):
            t[j, relpos[rowind[p]]] += values[p]
    depth = state[0]
    while depth > 0 and sn_parent[st_sn[depth - 1]] == s:
        c = st_sn[depth - 1]
        at = st_off[depth - 1]
        cr = rows[row_ptr[c]:row_ptr[c + 1]]
        w = len(cr)
        for a in range(_first_at_least(cr, relpos, r0), _first_at_least(cr, relpos, r1)):
            pa = relpos[cr[a]]
            for b in range(a, w):
                t[pa, relpos[cr[b]]] += stack[at + a * w + b]
        depth -= 1


@jit
def pop_children(sn_parent, s, work):
    """Pop the update matrices of supernode s's children off the stack (after assemble_rows)."""
    stack, buf, relpos, st_sn, st_off, state = work
    depth = state[0]
    while depth > 0 and sn_parent[st_sn[depth - 1]] == s:
        depth -= 1
    state[0] = depth


@jit
def store_rows(sn_start, row_ptr, factor_ptr, s, t, segment, base, work, k0, k1, a0, a1, copy):
    """Pivot rows k0..k1-1 of the factored front t of supernode s into its factor block (their
    entries left of the diagonal zeroed; with ``copy`` false the block is t's own first rows,
    only zeroed) and rows a0..a1-1 of its update matrix onto the stack at its top (not pushed:
    :func:`push_update`)."""
    stack, buf, relpos, st_sn, st_off, state = work
    nc = sn_start[s + 1] - sn_start[s]
    nr = row_ptr[s + 1] - row_ptr[s]
    f = nc + nr
    off = factor_ptr[s] - base
    for k in range(k0, k1):
        for i in range(k):
            segment[off + k * f + i] = 0.0
        if copy:
            for i in range(k, f):
                segment[off + k * f + i] = t[k, i]
    at = st_off[state[0]]
    for a in range(a0, a1):
        for b in range(a, nr):
            stack[at + a * nr + b] = t[nc + a, nc + b]


@jit
def push_update(sn_start, row_ptr, sn_parent, s, work):
    """Push supernode s's update matrix (written by store_rows) on the stack."""
    stack, buf, relpos, st_sn, st_off, state = work
    nr = row_ptr[s + 1] - row_ptr[s]
    depth = state[0]
    if nr > 0 and sn_parent[s] != -1:
        st_sn[depth] = s
        st_off[depth + 1] = st_off[depth] + nr * nr
        state[0] = depth + 1
