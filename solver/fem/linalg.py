"""Linear algebra of the solver, behind small functions the drivers call: the sparse direct
solve of the whole system (SuperLU, geometric nested dissection for large grids), the condensed
factorisation of the contact drivers (factor once with the contact dofs last, read the Schur
complement off the factors), dense blocks embedded into sparse ones, and a guard that runs dense
linear algebra on one BLAS thread."""

from __future__ import annotations

import contextlib
import ctypes

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = [
    "NESTED_DISSECTION_DOFS",
    "nested_dissection",
    "linear_solve",
    "single_threaded_blas",
    "condensed_factor",
    "dof_order",
    "metis_order",
    "condensed_apply",
    "SmallSystem",
    "PermutedLU",
    "embed",
    "scatter",
]


# Above this many dofs the solver orders the unknowns by geometric nested dissection itself.
NESTED_DISSECTION_DOFS = 40_000


def nested_dissection(points: np.ndarray, leaf: int = 64) -> np.ndarray:
    """Order of grid nodes (n, 2) by geometric nested dissection: split the node set at the
    median grid line of its longer side, order both halves recursively, the line's nodes
    (the separator) last. Hand-written because scipy has no nested-dissection ordering and
    SuperLU's minimum-degree orderings give about twice the fill on grids. Any order is
    correct; a line crossing a coarse cell only makes a worse separator."""
    out = []

    def rec(idx):
        if len(idx) <= leaf:
            out.append(idx)
            return
        p = points[idx]
        axis = int(np.argmax(np.ptp(p, axis=0)))
        vals = np.unique(p[:, axis])
        if len(vals) < 3:
            out.append(idx)
            return
        split = vals[len(vals) // 2]
        rec(idx[p[:, axis] < split])
        rec(idx[p[:, axis] > split])
        out.append(idx[p[:, axis] == split])

    rec(np.arange(len(points)))
    return np.concatenate(out)


def linear_solve(k: sp.csr_matrix, f: np.ndarray, bodies: list | None = None) -> np.ndarray:
    """Sparse direct solve with SuperLU (CHOLMOD is not available). The matrix is symmetric:
    symmetric mode, no pivoting across the diagonal. Small systems use SuperLU's minimum
    degree on A + A^T; large ones a geometric nested-dissection order of each body's nodes."""
    n = k.shape[0]
    if bodies is None or n < NESTED_DISSECTION_DOFS:
        lu = spla.splu(k.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        return lu.solve(f)
    perm = dof_order(bodies, k)
    kp = k[perm][:, perm].tocsc()
    lu = spla.splu(kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    u = np.empty(n)
    u[perm] = lu.solve(f[perm])
    return u


@contextlib.contextmanager
def single_threaded_blas():
    """Run dense linear algebra on one OpenBLAS thread, restoring the previous count.

    The width iterations factor dense matrices of a few hundred rows: threads gain nothing
    there, and on a loaded machine OpenBLAS's spinning threads made a 536 x 536 Cholesky
    25 times slower (0.4 s against 15 ms, measured). threadpoolctl is not a dependency, so
    the OpenBLAS libraries numpy and scipy loaded are driven through ctypes; without them
    this does nothing."""
    handles = []
    try:
        paths = {ln.split()[-1] for ln in open("/proc/self/maps") if "openblas" in ln.lower()}
    except OSError:
        paths = set()
    for path in sorted(paths):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for prefix, suffix in (("scipy_", ""), ("scipy_", "64_"), ("", ""), ("", "64_")):
            get = getattr(lib, f"{prefix}openblas_get_num_threads{suffix}", None)
            put = getattr(lib, f"{prefix}openblas_set_num_threads{suffix}", None)
            if get is not None and put is not None:
                handles.append((put, int(get())))
                put(1)
                break
    try:
        yield
    finally:
        for put, n in handles:
            put(n)


def embed(dense: np.ndarray, dofs: np.ndarray, n: int) -> sp.csr_matrix:
    """A dense block on the dofs ``dofs`` as an (n, n) sparse matrix."""
    r, c = np.nonzero(dense)
    return sp.csr_matrix((dense[r, c], (dofs[r], dofs[c])), shape=(n, n))


def scatter(n, dofs, values):
    out = np.zeros(n)
    out[dofs] = values
    return out


class SmallSystem:
    """A dense m x m system factored once: Cholesky when symmetric positive definite (the
    contact block of the symmetric Nitsche terms), LU otherwise (friction tractions)."""

    def __init__(self, matrix: np.ndarray, symmetric: bool):
        self.cholesky = None
        if symmetric:
            try:
                self.cholesky = sla.cho_factor(matrix, check_finite=False)
            except np.linalg.LinAlgError:
                pass
        if self.cholesky is None:
            self.lu = sla.lu_factor(matrix, check_finite=False)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        if self.cholesky is not None:
            return sla.cho_solve(self.cholesky, rhs, check_finite=False)
        return sla.lu_solve(self.lu, rhs, check_finite=False)


def condensed_apply(lu, small: SmallSystem, schur, dofs, kc, r):
    """(K0 + B^T Kc B)^-1 r by static condensation: (S + Kc) x = S B K0^-1 r (``small`` holds
    S + Kc factored), then U = K0^-1 (r - B^T Kc x)."""
    z = lu.solve(r)
    x = small.solve(schur @ z[dofs])
    return lu.solve(r - scatter(len(r), dofs, kc @ x))


class PermutedLU:
    """Sparse LU of K0 with the contact dofs ordered last; ``solve`` in the original numbering."""

    def __init__(self, lu, order):
        self.lu, self.order = lu, order

    def solve(self, f):
        out = np.empty_like(f)
        out[self.order] = self.lu.solve(np.ascontiguousarray(f[self.order]))
        return out


def condensed_factor(k0: sp.csr_matrix, dofs: np.ndarray, order: np.ndarray | None = None):
    """Factor K0 once with the contact dofs last and read the Schur complement
    S = K_cc - K_ci K_ii^-1 K_ic off the trailing block of the factors: S = L_cc U_cc. Then
    G = B K0^-1 B^T = S^-1 without m solves (scipy's SuperLU solves many right-hand sides one
    by one, ~20 ms each here).

    ``order``: a fill-reducing order of all dofs (:func:`dof_order`, geometric nested
    dissection); the interior dofs keep it, the contact dofs go last; SuperLU then factors in
    that order with diagonal pivots. Without it, SuperLU's minimum degree orders the interior
    (one more factorisation, of the interior block, only to find the order)."""
    n = k0.shape[0]
    m = len(dofs)
    contact = np.zeros(n, dtype=bool)
    contact[dofs] = True
    if order is None:
        interior = np.flatnonzero(~contact)
        kii = k0[interior][:, interior].tocsc()
        lu_i = spla.splu(kii, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        interior = interior[np.argsort(lu_i.perm_c)]
        del lu_i, kii
    else:
        interior = order[~contact[order]]
    order = np.concatenate([interior, dofs])
    kp = _permuted(k0, order)
    lu = spla.splu(kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    del kp
    if (lu.perm_r != np.arange(n)).any() or (lu.perm_c != np.arange(n)).any():
        raise RuntimeError("the condensed factorisation pivoted off the diagonal")
    lcc = _trailing_block(lu.L, m)
    ucc = _trailing_block(lu.U, m)
    schur = lcc @ ucc
    return PermutedLU(lu, order), 0.5 * (schur + schur.T)


def _permuted(k: sp.csr_matrix, order: np.ndarray) -> sp.csc_matrix:
    """P K P^T in CSC for the permutation ``order`` (new index i holds old index order[i])."""
    n = k.shape[0]
    where = np.empty(n, dtype=np.int64)
    where[order] = np.arange(n)
    coo = k.tocoo()
    return sp.csc_matrix((coo.data, (where[coo.row], where[coo.col])), shape=k.shape)


def _trailing_block(factor: sp.csc_matrix, m: int) -> np.ndarray:
    """The last m x m block of a CSC factor, dense (only its last m columns are read)."""
    n = factor.shape[0]
    start = factor.indptr[n - m]
    rows = factor.indices[start:]
    cols = np.repeat(np.arange(m), np.diff(factor.indptr[n - m :]))
    keep = rows >= n - m
    out = np.zeros((m, m))
    out[rows[keep] - (n - m), cols[keep]] = factor.data[start:][keep]
    return out


def dof_order(bodies, k: sp.spmatrix | None = None) -> np.ndarray:
    """A fill-reducing order of the global dofs, the dofs of a node together: METIS's multilevel
    nested dissection of the node graph of ``k`` when pymetis is installed (the ``fast`` extra;
    measured on the 68k-dof peer problem: 15 % less fill than SuperLU's minimum degree, 40 %
    less than the geometric dissection), else geometric nested dissection of each body's free
    nodes (:func:`nested_dissection`)."""
    if k is not None:
        order = metis_order(k, bodies[0].dim if bodies else 2)
        if order is not None:
            return order
    perm = []
    for b in bodies:
        nodes = nested_dissection(b.grid.nodes[b.grid.free_nodes])
        perm.append(b.dof_offset + (b.dim * nodes[:, None] + np.arange(b.dim)).ravel())
    return np.concatenate(perm)


def metis_order(k: sp.spmatrix, block: int) -> np.ndarray | None:
    """METIS nested dissection of the graph of ``block`` x ``block`` node blocks of k (the dofs
    of a node numbered together); None without pymetis."""
    try:
        import pymetis
    except ImportError:
        return None
    n = k.shape[0]
    if n % block:
        return None
    coo = k.tocoo()
    rows, cols = coo.row // block, coo.col // block
    off = rows != cols
    nodes = n // block
    graph = sp.csr_matrix((np.ones(int(off.sum()), dtype=np.int8), (rows[off], cols[off])), shape=(nodes, nodes))
    graph.sum_duplicates()
    graph.sort_indices()
    perm, _ = pymetis.nested_dissection(pymetis.CSRAdjacency(graph.indptr, graph.indices))
    perm = np.asarray(perm, dtype=np.int64)
    return (block * perm[:, None] + np.arange(block)).ravel()
