"""Linear algebra of the solver, behind small functions the drivers call: the sparse direct
solve of the whole system (SuperLU, geometric nested dissection for large grids), the condensed
factorisation of the contact drivers (factor once with the contact dofs last, read the Schur
complement off the factors: the multifrontal Cholesky of :mod:`solver.fem.multifrontal` for
large systems when numba is installed, else SuperLU; ``IBFEM_CONDENSED_FACTOR`` forces one;
uncoupled bodies one after the other, each on all the threads inside its large fronts),
dense blocks embedded into sparse ones, and a guard that runs dense linear algebra on one BLAS
thread."""

from __future__ import annotations

import contextlib
import ctypes
import os

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..model.estimate import factor_threads
from .block_diagonal import BlockDiagonal, BlockFactor, uncoupled_groups
from .dense import symmetric_from_lower

__all__ = [
    "NESTED_DISSECTION_DOFS",
    "nested_dissection",
    "linear_solve",
    "direct_solve",
    "amg_cg_solve",
    "rigid_body_modes",
    "LINEAR_SOLVERS",
    "LinearSolveError",
    "single_threaded_blas",
    "blas_threads",
    "free_threads",
    "condensed_factor",
    "factor_threads",
    "contact_nearness",
    "CONDENSED_FACTORS",
    "CHOLESKY_NONZEROS",
    "DENSE_ROWS_FACTOR",
    "dof_order",
    "metis_order",
    "contact_last_order",
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


LINEAR_SOLVERS = ("auto", "direct", "iterative")
#: "auto" solves systems with at least this many dofs iteratively (pyamg installed), by dimension:
#: measured crossovers (benchmarks/linear_solvers.py in 2D; the Lame sphere octant in 3D: 58k
#: dofs direct 21 s, iterative 3.8 s)
ITERATIVE_DOFS = {2: 400_000, 3: 20_000}


class LinearSolveError(RuntimeError):
    """An iterative solve that did not reach its tolerance (with its residual history)."""


def linear_solve(k: sp.csr_matrix, f: np.ndarray, bodies: list | None = None, method: str = "auto",
                 tolerance: float = 1e-10) -> np.ndarray:
    """Solve the symmetric system K u = f. ``method``: "direct" (SuperLU, below), "iterative"
    (:func:`amg_cg_solve`: conjugate gradients preconditioned by pyamg's smoothed aggregation
    with the bodies' rigid-body modes), or "auto" (iterative from ITERATIVE_DOFS[dim] dofs on
    when pyamg is installed, direct otherwise). ``tolerance`` is the relative residual of the
    iterative solve."""
    n = k.shape[0]
    if method not in LINEAR_SOLVERS:
        raise ValueError(f"linear solver must be one of {', '.join(LINEAR_SOLVERS)}, got {method!r}")
    if method == "auto":
        dim = bodies[0].dim if bodies else 2
        method = "iterative" if bodies is not None and n >= ITERATIVE_DOFS[dim] and _has_pyamg() else "direct"
    if method == "iterative":
        if bodies is None:
            raise ValueError("the iterative solver needs the bodies (their rigid-body modes)")
        return amg_cg_solve(k, f, bodies, tolerance)
    return direct_solve(k, f, bodies)


def _has_pyamg() -> bool:
    try:
        import pyamg  # noqa: F401
    except ImportError:
        return False
    return True


def direct_solve(k: sp.csr_matrix, f: np.ndarray, bodies: list | None = None) -> np.ndarray:
    """Sparse direct solve of the symmetric system. Small systems: SuperLU with its minimum
    degree on A + A^T, symmetric mode, no pivoting across the diagonal. Large ones (the bodies
    given, NESTED_DISSECTION_DOFS dofs or more) in a fill-reducing order of the bodies' nodes
    (:func:`dof_order`): the multifrontal L D L^T (:mod:`solver.fem.multifrontal`, only L stored)
    when ``IBFEM_CONDENSED_FACTOR`` (default "auto": from CHOLESKY_NONZEROS stored entries with
    numba) picks it, falling back to SuperLU on a zero pivot; else SuperLU in that order."""
    n = k.shape[0]
    if bodies is None or n < NESTED_DISSECTION_DOFS:
        lu = spla.splu(k.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        return lu.solve(f)
    perm = dof_order(bodies)

    def cholesky():
        from .multifrontal import CholeskyFactor

        with single_threaded_blas():
            return CholeskyFactor(k, perm, 0, definite=False, threads=factor_threads()).solve(f)

    u = _cholesky_or_none(_condensed_choice(k.nnz), cholesky)
    if u is not None:
        return u
    kp = _permuted(k, perm)
    lu = spla.splu(kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    u = np.empty(n)
    u[perm] = lu.solve(f[perm])
    return u


def rigid_body_modes(bodies, n: int) -> np.ndarray:
    """(n, k per body) the rigid motions of each body's free nodes (the near-null space of its
    stiffness): d translations and d (d - 1) / 2 rotations (3 in 2D, 6 in 3D), each rotation
    column scaled to unit maximum."""
    columns = []
    for b in bodies:
        d = b.dim
        nodes = b.grid.nodes[b.grid.free_nodes]
        rel = nodes - nodes.mean(axis=0)
        sl = slice(b.dof_offset, b.dof_offset + b.n_dofs)
        for k in range(d):
            col = np.zeros(n)
            col[sl] = np.tile(np.eye(d)[k], len(nodes))
            columns.append(col)
        for i in range(d):
            for j in range(i + 1, d):
                rot = np.zeros((len(nodes), d))
                rot[:, i], rot[:, j] = -rel[:, j], rel[:, i]
                col = np.zeros(n)
                col[sl] = rot.ravel() / max(np.abs(rot).max(), 1e-300)
                columns.append(col)
    return np.stack(columns, axis=1)


def contact_nearness(bodies, dofs: np.ndarray, points) -> np.ndarray:
    """Minus the distance of each dof's node to the nearest of ``points`` (the contact points):
    the order of the condensed dofs, nearest last (:func:`condensed_factor`)."""
    where = np.zeros((len(dofs), bodies[0].dim))
    for b in bodies:
        sel = (dofs >= b.dof_offset) & (dofs < b.dof_offset + b.n_dofs)
        where[sel] = b.grid.nodes[b.grid.free_nodes][(dofs[sel] - b.dof_offset) // b.dim]
    points = np.asarray(points, dtype=float).reshape(-1, where.shape[1])
    return -np.min(np.linalg.norm(where[:, None, :] - points[None], axis=2), axis=1)


def amg_cg_solve(k: sp.csr_matrix, f: np.ndarray, bodies, tolerance: float = 1e-10,
                 max_iterations: int = 2000) -> np.ndarray:
    """Conjugate gradients preconditioned by smoothed-aggregation AMG (pyamg), the rigid-body
    modes as near-null space. Raises LinearSolveError with the residual history when the
    relative residual does not reach ``tolerance``."""
    try:
        import pyamg
    except ImportError:
        raise ImportError("the iterative linear solver needs pyamg: pip install 'ibfem[fast]'") from None
    a = k.tocsr()
    scale = 1.0 / np.sqrt(np.abs(a.diagonal()))  # Jacobi scaling: cut cells' tiny diagonals
    d = sp.diags(scale)
    a = (d @ a @ d).tocsr()
    # prolongation smoothed with row-sum (local) weights: no spectral radius estimate, which took
    # half the setup (Lanczos on D^-1 A at every level); measured on the Lame octant (146k dofs):
    # setup 10.8 -> 3.5 s, CG 16 -> 23 iterations, 17 -> 12 s in all (machine loaded)
    ml = pyamg.smoothed_aggregation_solver(
        a, B=rigid_body_modes(bodies, a.shape[0]) / scale[:, None], symmetry="symmetric", max_coarse=500,
        strength=("symmetric", {"theta": 0.0}), smooth=("jacobi", {"omega": 4.0 / 3.0, "weighting": "local"}),
    )
    residuals: list[float] = []
    x = ml.solve(scale * f, tol=tolerance, accel="cg", maxiter=max_iterations, residuals=residuals)
    b_norm = max(float(np.linalg.norm(scale * f)), 1e-300)
    if not residuals or residuals[-1] > tolerance * b_norm * 10.0:
        history = ", ".join(f"{r / b_norm:.2e}" for r in residuals[:: max(1, len(residuals) // 8)])
        raise LinearSolveError(
            f"the iterative solver (CG + smoothed aggregation, {a.shape[0]} dofs) did not reach the relative residual "
            f"{tolerance:g} in {len(residuals) - 1} iterations; residual history: {history}; "
            "use [solver] linear_solver = \"direct\""
        )
    return scale * x


@contextlib.contextmanager
def single_threaded_blas():
    """Run dense linear algebra on one OpenBLAS thread, restoring the previous count.

    The width iterations factor dense matrices of a few hundred rows: threads gain nothing
    there, and on a loaded machine OpenBLAS's spinning threads made a 536 x 536 Cholesky
    25 times slower (0.4 s against 15 ms, measured). threadpoolctl is not a dependency, so
    the OpenBLAS libraries numpy and scipy loaded are driven through ctypes; without them
    this does nothing."""
    with blas_threads(1):
        yield


@contextlib.contextmanager
def blas_threads(count: int):
    """Run dense linear algebra on ``count`` OpenBLAS threads (of the libraries numpy and scipy
    loaded, driven through ctypes), restoring the previous count; without them this does nothing."""
    handles = []
    try:
        with open("/proc/self/maps") as maps:
            paths = {ln.split()[-1] for ln in maps if "openblas" in ln.lower()}
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
                put(int(count))
                break
    try:
        yield
    finally:
        for put, n in handles:
            put(n)


def free_threads(sample: list | None = None) -> int:
    """:func:`factor_threads` where the machine has had a core idle besides this process's one
    since the last call with the same ``sample`` (a one-item list holding /proc/stat's counts at
    that call: each caller keeps its own; by default the trials' small systems') (the system's
    idle time in /proc/stat over that interval: at least half a core; on the first call, or
    without /proc/stat, the 1-minute load average below the cores less a half), else 1. OpenBLAS's threads wait for each other by spinning: on a busy machine
    an LU of 3,400 rows took 1.3 s on two threads against 0.9 s on one (load 5.5 on 2 cores),
    where a free core halves it."""
    threads = factor_threads()
    idle = _idle_cores() if sample is None else _idle_cores(sample)
    if threads < 2:
        return 1
    if idle is not None:
        return threads if idle >= 0.5 else 1
    try:
        load = os.getloadavg()[0]
    except OSError:
        return 1
    return threads if load < (os.cpu_count() or 1) - 0.5 else 1


_IDLE_SAMPLE: list = [None]  # (idle, total) jiffies of /proc/stat at the last look


def _idle_cores(sample: list | None = None) -> float | None:
    """Cores the machine left idle on average since the last call with ``sample`` (by default
    this module's; None on the first call, over less than a tenth of a second, or without
    /proc/stat)."""
    sample = _IDLE_SAMPLE if sample is None else sample
    try:
        with open("/proc/stat") as stat:
            fields = [int(v) for v in stat.readline().split()[1:9]]
    except (OSError, ValueError):
        return None
    now = (fields[3] + fields[4], sum(fields))  # idle + iowait, all
    last, sample[0] = sample[0], now
    cores = os.cpu_count() or 1
    if last is None or now[1] - last[1] < 10 * cores:  # jiffies of 10 ms
        return None
    return cores * (now[0] - last[0]) / (now[1] - last[1])


def embed(block, dofs: np.ndarray, n: int) -> sp.csr_matrix:
    """A block (dense or sparse) on the dofs ``dofs`` as an (n, n) sparse matrix."""
    if sp.issparse(block):
        coo = block.tocoo()
        r, c, v = coo.row, coo.col, coo.data
    else:
        r, c = np.nonzero(block)
        v = block[r, c]
    return sp.csr_matrix((v, (dofs[r], dofs[c])), shape=(n, n))


def scatter(n, dofs, values):
    out = np.zeros(n)
    out[dofs] = values
    return out


class SmallSystem:
    """The condensed contact system (S + Kc) x = r, factored once per contact state.

    Kc acts only on the active dofs A of the state (those its region's quadrature points touch),
    often a third of the m condensed dofs. With G = S^-1 (computed once per run) the system is
    (I + G Kc) x = G r, whose A-rows are (I + G_AA Kc_AA) x_A = (G r)_A and whose other rows give
    x = G r - G_:A Kc_AA x_A: an LU of I + G_AA Kc_AA (2/3 |A|^3) instead of a factorisation of
    the m x m system. (The symmetric alternative, a Cholesky of G_AA^-1 + Kc_AA, needs G_AA's
    inverse first: measured at the 30k-dof 3D sphere rung, |A| = 1704 of m = 2568, 0.22-0.29 s
    against the LU's 0.12-0.14 s, the solutions equal to 1e-14.) Without G, or when A is most of
    the dofs, S + Kc itself is factored (Cholesky; LU when non-symmetric)."""

    #: the active set is used when it holds at most this fraction of the dofs
    ACTIVE_FRACTION = 0.7
    #: an active set of at least this many dofs is multiplied and factored on :func:`free_threads`
    #: threads (smaller ones on one: their LU gains nothing from more)
    THREADED_ACTIVE = 1500
    #: an active set of at least this many dofs is factored in single precision (an LU at about
    #: 0.6 of the double one's time) and solved to double precision by iterative refinement
    SINGLE_PRECISION_ACTIVE = 1000
    #: refinement ends when a correction is below this fraction of the solution (largest entries):
    #: the error left is that correction times the steps' contraction, cond(M) times single
    #: precision's 6e-8 (about 2e-4 at cond(M) = 3e3), so about 1e-15 of the solution
    REFINED_TOLERANCE = 1e-11
    #: at most this many refinement steps before M is factored in double precision instead
    REFINEMENT_STEPS = 6

    def __init__(self, schur: np.ndarray, kc, symmetric: bool, g_inverse: np.ndarray | None = None):
        """``kc``: the contact stiffness on the m condensed dofs, sparse (or dense)."""
        kc = sp.csr_matrix(kc)
        coo = kc.tocoo()
        nonzero = coo.data != 0.0  # explicit zeros touch nothing (the caller's matrix is not edited)
        touched = np.unique(np.concatenate([coo.row[nonzero], coo.col[nonzero]]))
        self.g = g_inverse
        self.cholesky = self.lu = self.lu32 = None
        if g_inverse is not None and len(touched) <= self.ACTIVE_FRACTION * kc.shape[0]:
            self.active, self.kc_aa = touched, kc[touched][:, touched].tocsr()  # sparse: kept per state
            self._factor_active()
        else:
            self.active = None
            self._factor(schur, coo, symmetric)

    @staticmethod
    def _assembled(schur, kc: sp.coo_matrix) -> np.ndarray:
        """S + Kc as one new dense array (Kc's entries added in place: no dense copy of Kc)."""
        matrix = np.array(_dense(schur), dtype=float, order="F", copy=True)
        np.add.at(matrix, (kc.row, kc.col), kc.data)
        return matrix

    def _factor(self, schur, kc: sp.coo_matrix, symmetric: bool) -> None:
        """Factor S + Kc in place: one m x m array at a time (Cholesky; LU when not positive
        definite or not symmetric, on S + Kc assembled again since the failed Cholesky overwrote it)."""
        if symmetric:
            try:
                self.cholesky = sla.cho_factor(self._assembled(schur, kc), overwrite_a=True, check_finite=False)
                return
            except np.linalg.LinAlgError:
                pass
        self.lu = sla.lu_factor(self._assembled(schur, kc), overwrite_a=True, check_finite=False)

    def _factor_active(self) -> None:
        a = self.active
        threads = free_threads() if len(a) >= self.THREADED_ACTIVE else 1
        single = len(a) >= self.SINGLE_PRECISION_ACTIVE
        self._threads = threads
        m = self._active_matrix(threads, np.float32 if single else np.float64)
        with blas_threads(threads) if threads > 1 else contextlib.nullcontext():  # the caller's guard holds
            # on `threads` BLAS threads where a core is free, else on the caller's (one, under its guard);
            # a large set factored in single precision, solved to double by iterative refinement (_refined)
            if single:
                self.lu32 = sla.lu_factor(m, overwrite_a=True, check_finite=False)
            else:
                self.lu = sla.lu_factor(m, overwrite_a=True, check_finite=False)

    def _active_matrix(self, threads: int, dtype) -> np.ndarray:
        """M = I + G_AA Kc_AA in column order, in ``dtype`` (single precision: no double |A| x |A|
        array is formed)."""
        # G_AA Kc_AA = (Kc_AA^T G_AA)^T (G symmetric): G_AA read in its own (row) order, not copied
        # into a transposed one, and the product comes out in the column order LAPACK factors in place
        if isinstance(self.g, BlockDiagonal):
            m = self._block_product(self.active, threads, dtype).T
        else:
            a = self.active
            g_aa = self.g[np.ix_(a, a)] if isinstance(self.g, np.ndarray) else self.g.take(a, a)
            m = (self.kc_aa.T @ g_aa).T.astype(dtype, order="F", copy=False)
            del g_aa
        m[np.diag_indices_from(m)] += 1.0
        return m

    def _active_product(self, x_a: np.ndarray) -> np.ndarray:
        """M x_A = x_A + G_AA Kc_AA x_A in double precision, from G and Kc_AA (M is not kept)."""
        y = scatter(self.g.shape[0], self.active, self.kc_aa @ x_a)
        return x_a + (self.g @ y)[self.active]

    def _refined(self, rhs: np.ndarray) -> np.ndarray:
        """M^-1 rhs (M = I + G_AA Kc_AA) from M's single-precision LU: x_0 = LU^-1 rhs, then
        x_(k+1) = x_k + LU^-1 (rhs - M x_k) with the residual in double precision (M x from G and
        Kc_AA, M itself not kept beside its factor), until a correction is below
        REFINED_TOLERANCE of x. Each step gains the digits of single precision less log10 cond(M)
        (cond(M) 2e3-3e3 on the trials of the turned ball on a block measured: two steps reach
        1e-14 of the double LU's solution); where the corrections stop shrinking first (M too
        ill-conditioned for single precision), M is formed and factored in double precision
        instead."""
        def step(r):
            return sla.lu_solve(self.lu32, r.astype(np.float32), check_finite=False).astype(float)

        x = step(rhs)
        last = np.inf
        for _ in range(self.REFINEMENT_STEPS):
            dx = step(rhs - self._active_product(x))
            x += dx
            size, scale = float(np.abs(dx).max(initial=0.0)), float(np.abs(x).max(initial=0.0))
            if size <= self.REFINED_TOLERANCE * scale:
                return x
            if size > 0.5 * last:
                break
            last = size
        self.lu32 = None
        m = self._active_matrix(self._threads, np.float64)
        with blas_threads(self._threads) if self._threads > 1 else contextlib.nullcontext():
            self.lu = sla.lu_factor(m, overwrite_a=True, check_finite=False)
        return sla.lu_solve(self.lu, rhs, check_finite=False)

    #: columns of a block's product formed at a time: the slab of G's block and the product's
    #: columns stay in the cache while Kc_AA^T's entries sweep them (a 3,000 x 1,500 product,
    #: Kc_AA^T with 300 entries a column: 0.15 s CPU in slabs against 0.41 s in one product)
    SLAB = 256

    def _block_product(self, a: np.ndarray, threads: int = 1, dtype=np.float64) -> np.ndarray:
        """Kc_AA^T G_AA for a block-diagonal G, one block at a time: the columns of a block's dofs
        are Kc_AA^T's columns there times the block's own part of G_AA, the zeros between the
        blocks neither formed nor multiplied (half the work for two bodies; the same sums). A
        block's columns are a contiguous run of A (each body's dofs are numbered together) and are
        written as a slice: ten times faster than through the index array (a 4000 x 2000 block:
        0.02 s against 0.2 s), SLAB columns at a time. With ``threads`` > 1 the blocks are read and
        multiplied on that many threads (NumPy's indexing and SciPy's sparse products release
        Python's lock). In single precision (``dtype``: for a single-precision factor, which the
        iterative refinement corrects with the residual in double precision) the products are
        formed in single precision (0.08 s against 0.15 s above)."""
        kc_t = self.kc_aa.T.tocsc().astype(dtype, copy=False)
        out = np.empty((len(a), len(a)), dtype=dtype)

        def one(k: int) -> None:
            cols = self.g.block_positions(a, k)
            if not len(cols):
                return
            g_block = self.g.block_take(a, cols, k)
            first = int(cols[0])
            contiguous = cols[-1] - first == len(cols) - 1  # sorted positions: written as slices
            rows = kc_t[:, slice(first, first + len(cols)) if contiguous else cols]
            for j in range(0, len(cols), self.SLAB):
                end = min(j + self.SLAB, len(cols))
                out[:, slice(first + j, first + end) if contiguous else cols[j:end]] = (
                    rows @ g_block[:, j:end].astype(dtype, copy=False))

        blocks = range(len(self.g.blocks))
        if threads > 1 and len(blocks) > 1:
            from concurrent.futures import ThreadPoolExecutor

            with ThreadPoolExecutor(min(threads, len(blocks))) as pool:
                list(pool.map(one, blocks))
        else:
            for k in blocks:
                one(k)
        return out

    def _solve_factored(self, rhs: np.ndarray) -> np.ndarray:
        if self.lu32 is not None:
            return self._refined(rhs)
        if self.cholesky is not None:
            return sla.cho_solve(self.cholesky, rhs, check_finite=False)
        return sla.lu_solve(self.lu, rhs, check_finite=False)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        if self.active is None:
            return self._solve_factored(rhs)
        a = self.active
        g_r = self.g @ rhs
        x_a = self._solve_factored(g_r[a])  # (I + G_AA Kc_AA) x_A = (G r)_A
        y = self.kc_aa @ x_a
        if isinstance(self.g, np.ndarray):
            return g_r - self.g[:, a] @ y
        return g_r - self.g @ scatter(len(rhs), a, y)


def _dense(matrix) -> np.ndarray:
    """A dense array of a matrix held as an array or as an operator with ``toarray``."""
    return matrix if isinstance(matrix, np.ndarray) else matrix.toarray()


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


#: the factorisations of :func:`condensed_factor` (environment variable IBFEM_CONDENSED_FACTOR)
CONDENSED_FACTORS = ("auto", "superlu", "cholesky")
#: "auto" uses the multifrontal Cholesky for a K0 with at least this many stored entries (numba
#: installed). The Cholesky costs ~0.25 s and ~100 MB once per process (numba and LLVM loaded).
#: Measured (benchmarks/cholesky.py, docs/linear-algebra.md), whole runs: the 3D 12k-dof sphere
#: rung (0.71 M entries) even (5.21 / 5.07 s, 522 / 524 MB), so SuperLU; the 2D 68k-dof peer
#: scene (0.89 M) 1.77 s and 340 MB instead of 1.93 s and 456 MB; the 3D 32k-dof rung (1.8 M)
#: 13.0 s and 1302 MB instead of 16.4 s and 1723 MB
CHOLESKY_NONZEROS = 800_000
#: the condensed factorisation of a K0 whose rows hold DENSE_ROWS entries or more on average (a 3D
#: grid's: trilinear cells couple up to 81 dofs a row, bilinear squares 18) takes the Cholesky from
#: this many times CHOLESKY_NONZEROS: SuperLU keeps only L there (:class:`SymmetricFactor`). Measured
#: (sphere_on_flat rungs, whole runs, each factorisation forced, a loaded machine): 11.1k dofs,
#: 0.80 M entries: CPU 3.19 s against the Cholesky's 3.21, peak 244 MB against 334; 30.1k dofs,
#: 1.72 M entries: CPU 9.0 s against 6.6, 641 MB against 668
DENSE_ROWS_FACTOR = 1.5
DENSE_ROWS = 40


#: a body's condensed block of at least this many dofs keeps only the trailing TRAILING_FRACTION of
#: G = S^-1 (solver.fem.multifrontal.RootInverse) when the dofs are ordered by nearness
TRAILING_INVERSE_DOFS = 4000
TRAILING_FRACTION = 0.5


def condensed_factor(k0: sp.csr_matrix, dofs: np.ndarray, order: np.ndarray | None = None,
                     nearness: np.ndarray | None = None):
    """Factor K0 once with the contact dofs last and read the Schur complement
    S = K_cc - K_ci K_ii^-1 K_ic off the factorisation; G = B K0^-1 B^T = S^-1 from S's
    Cholesky factor without m solves. Returns (a factor with ``solve(f)`` in the original
    numbering, S, G).

    ``order``: a fill-reducing order of all dofs (:func:`dof_order`); the interior dofs keep
    it, the contact dofs go last. Without it, SuperLU's minimum degree orders the interior (one
    more factorisation, of the interior block, only to find the order).

    Two factorisations, chosen by the environment variable ``IBFEM_CONDENSED_FACTOR``:
    "cholesky" (:func:`solver.fem.multifrontal.condensed_cholesky`: a supernodal multifrontal
    L D L^T, only L stored, the contact dofs its root front), "superlu" (SuperLU in the same
    order with diagonal pivots, S from the trailing blocks of L and U), or "auto" (the default:
    the Cholesky from CHOLESKY_NONZEROS stored entries of K0 on (DENSE_ROWS_FACTOR times that for a 3D
    grid's dense rows) when numba is available, else SuperLU; a zero pivot
    or a Schur complement that is not positive definite falls back to SuperLU, whose general
    path handles what can be handled). A forced "cholesky" raises instead of falling back.

    When K0 couples no two bodies that hold contact dofs (the usual case: the bodies meet only
    through the contact), each such body is factored on its own with its contact dofs last, and
    S and G are :class:`~solver.fem.block_diagonal.BlockDiagonal`: two blocks of (m/2)^2 entries
    instead of m^2, a quarter of the dense work.

    ``nearness`` (m,): the contact dofs are ordered by it in each block, the nearest (largest)
    last. A Cholesky block of TRAILING_INVERSE_DOFS dofs or more then keeps only the trailing
    TRAILING_FRACTION of G (the dofs a trial region touches: nearest the contact point), an
    eighth of the work of G and a quarter of its memory; other entries are computed when asked."""
    groups = uncoupled_groups(k0, dofs)
    if groups is None and nearness is None:
        return _condensed_one(k0, dofs, order, _condensed_choice(k0.nnz, k0.shape[0]), threads=factor_threads())
    if groups is None:
        groups = np.zeros(k0.shape[0], dtype=np.int64)
    return _condensed_blocks(k0, dofs, order, groups, nearness)


def _condensed_blocks(k0: sp.csr_matrix, dofs: np.ndarray, order: np.ndarray | None, groups: np.ndarray,
                      nearness: np.ndarray | None = None):
    """:func:`condensed_factor` of each uncoupled group of dofs on its own, one after the other,
    each factorisation on :func:`factor_threads` threads (its large fronts shared between them:
    :class:`solver.fem.multifrontal.CholeskyFactor`), so that only one group's work space is in
    memory at a time."""
    choice = _condensed_choice(k0.nnz, k0.shape[0])
    k0 = k0.tocsr()
    threads = factor_threads()

    def one(g: int):
        idx = np.flatnonzero(groups == g)
        local = np.full(k0.shape[0], -1, dtype=np.int64)
        local[idx] = np.arange(len(idx))
        pos = np.flatnonzero(groups[dofs] == g)
        trailing = None
        if nearness is not None:
            pos = pos[np.argsort(nearness[pos], kind="stable")]
            if len(pos) >= TRAILING_INVERSE_DOFS:
                trailing = int(np.ceil(TRAILING_FRACTION * len(pos)))
        sub_order = None if order is None else local[order[groups[order] == g]]
        block = k0 if len(idx) == k0.shape[0] else k0[idx][:, idx]
        if sub_order is not None and choice != "superlu" and len(idx) >= ORDER_CHOICE_DOFS:
            sub_order = _cheaper_order(block, local[dofs[pos]], sub_order)
        return idx, pos, _condensed_one(block, local[dofs[pos]], sub_order, choice, trailing, threads)

    done = [one(g) for g in range(int(groups.max()) + 1)]
    parts, positions = [d[0] for d in done], [d[1] for d in done]
    factors, schurs, inverses = ([d[2][i] for d in done] for i in range(3))
    return BlockFactor(parts, factors), BlockDiagonal(schurs, positions), BlockDiagonal(inverses, positions)


#: a block of at least this many dofs compares its given order with :func:`contact_last_order` by
#: their factorisations' flops (counted on the elimination tree) and is factored in the cheaper
ORDER_CHOICE_DOFS = 40_000


def _cheaper_order(k: sp.csr_matrix, dofs: np.ndarray, order: np.ndarray) -> np.ndarray:
    """``order`` or :func:`contact_last_order`, whichever factors K with ``dofs`` last in fewer
    flops (the given order unchanged without pymetis or the compiled kernels)."""
    from .multifrontal import available, factor_flops

    block = 3
    contact = np.zeros(k.shape[0], dtype=bool)
    contact[dofs] = True
    given = np.concatenate([order[~contact[order]], dofs])
    if not (available() and _node_blocked(given, block)):
        return given
    nodes = _node_graph(k, block, np.arange(k.shape[0] // block))
    other = contact_last_order(k, dofs, block, nodes)
    if other is None:
        return given
    # compared on the node graph (a ninth of the entries): both orders keep a node's dofs together
    nodes = (nodes + sp.identity(nodes.shape[0], dtype=np.int8, format="csr")).tocsr()
    m = len(dofs) // block
    cheaper = factor_flops(nodes, other[::block] // block, m) < factor_flops(nodes, given[::block] // block, m)
    return other if cheaper else given


def _node_blocked(order: np.ndarray, block: int) -> bool:
    """Whether ``order`` numbers the ``block`` dofs of every node together, in their order."""
    if len(order) % block:
        return False
    runs = order.reshape(-1, block)
    return bool(np.all(runs[:, 0] % block == 0) and np.all(runs - runs[:, :1] == np.arange(block)))


def _condensed_one(k0: sp.csr_matrix, dofs: np.ndarray, order: np.ndarray | None, choice: str,
                   trailing: int | None = None, threads: int = 1):
    """:func:`condensed_factor` of one block (factored as a whole; ``trailing``: the Cholesky
    keeps that trailing block of G only; ``threads``: the Cholesky's large fronts factored on
    that many threads)."""
    n = k0.shape[0]
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

    def cholesky():
        from .multifrontal import condensed_cholesky

        # the factorisation's many mid-size products on one BLAS thread (measured x20 slower with BLAS's
        # threads); its own threads share the large fronts instead
        return condensed_cholesky(k0, order, len(dofs), guard=single_threaded_blas, trailing=trailing,
                                  threads=threads)

    factored = _cholesky_or_none(choice, cholesky)
    return factored if factored is not None else _superlu_condensed(k0, order, len(dofs))


def _condensed_choice(nonzeros: int, rows: int | None = None) -> str:
    """"cholesky", "superlu" or "auto" (the Cholesky worth trying) for a matrix of that many entries
    (``rows``: its rows, for a condensed factorisation: DENSE_ROWS_FACTOR where they are dense)."""
    choice = os.environ.get("IBFEM_CONDENSED_FACTOR", "").strip().lower() or "auto"
    if choice not in CONDENSED_FACTORS:
        raise ValueError(f"environment variable IBFEM_CONDENSED_FACTOR must be one of "
                         f"{', '.join(CONDENSED_FACTORS)}, got {choice!r}")
    if choice == "superlu":
        return choice
    from .multifrontal import available

    if choice == "cholesky" and not available():
        raise ValueError("IBFEM_CONDENSED_FACTOR=cholesky needs numba (pip install 'ibfem[fast]') "
                         "and IBFEM_NO_JIT unset")
    threshold = CHOLESKY_NONZEROS
    if rows and nonzeros >= DENSE_ROWS * rows:
        threshold *= DENSE_ROWS_FACTOR
    return choice if choice == "cholesky" or (nonzeros >= threshold and available()) else "superlu"


def _cholesky_or_none(choice: str, factorise):
    """``factorise()`` (a multifrontal factorisation) unless ``choice`` is "superlu"; None when it
    is not taken or meets a zero pivot under "auto" (the caller then uses SuperLU); a forced
    "cholesky" raises instead."""
    if choice == "superlu":
        return None
    from .multifrontal import NotPositiveDefinite

    try:
        return factorise()
    except NotPositiveDefinite:
        if choice == "cholesky":
            raise
        return None


def _superlu_condensed(k0: sp.spmatrix, order: np.ndarray, m: int):
    """(PermutedLU, S, G) by SuperLU in ``order`` (the m condensed dofs last) without pivoting."""
    n = k0.shape[0]
    kp = _permuted(k0, order)
    lu = spla.splu(kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    del kp
    if (lu.perm_r != np.arange(n)).any() or (lu.perm_c != np.arange(n)).any():
        raise RuntimeError("the condensed factorisation pivoted off the diagonal")
    lower, upper = lu.L, lu.U
    del lu  # SuperLU's own copy of both factors: only L and diag(U) are kept
    schur, g_inverse = _schur_and_inverse(lower, upper, m)
    return PermutedLU(SymmetricFactor(lower, upper.diagonal()), order), schur, g_inverse


class SymmetricFactor:
    """K = L D L^T of a symmetric K that SuperLU factored as L U without pivoting (U = D L^T):
    L (unit lower triangular, CSC) and D kept, solved by two sparse triangular solves. SuperLU's
    object holds both factors in its own storage; K0's two bodies at the 7.4k-dof
    sphere_on_flat rung: the run's peak 222 -> 180 MB; a solve of one body's block 1.5 ms
    against SuperLU's 2.0 (through scipy's spsolve_triangular, whose checks and copies of L on
    every call make it 3.1 ms, where SuperLU's triangular solve is not at hand); the solution the
    same to round-off (a, N of that rung 4e-13 and 4e-14 relative)."""

    def __init__(self, lower: sp.csc_matrix, d: np.ndarray):
        self.lower, self.d = sp.csc_matrix(lower), np.asarray(d, dtype=float)
        self.lower.sort_indices()
        self.lower.indices = self.lower.indices.astype(np.intc, copy=False)
        self.lower.indptr = self.lower.indptr.astype(np.intc, copy=False)

    def solve(self, f: np.ndarray) -> np.ndarray:
        y = self._triangular(np.array(f, dtype=float), "N")  # L y = f
        y /= self.d if y.ndim == 1 else self.d[:, None]
        return self._triangular(y, "T")  # L^T x = y

    def _triangular(self, b: np.ndarray, trans: str) -> np.ndarray:
        """L x = b ("N") or L^T x = b ("T"), b overwritten: SuperLU's triangular solve (the one
        scipy's spsolve_triangular calls, without its checks), else spsolve_triangular."""
        low, n = self.lower, self.lower.shape[0]
        gstrs = _superlu_triangular_solve()
        if gstrs is not None:
            none = np.zeros(n + 1, dtype=np.intc)
            try:
                x, info = gstrs(trans, n, low.nnz, low.data, low.indices, low.indptr, n, 0, np.zeros(0), none[:0],
                                none, b)
            except TypeError:  # another signature: the public route
                gstrs = None
            else:
                if info:
                    raise np.linalg.LinAlgError("the factor L is singular")
                return x
        return spla.spsolve_triangular(low if trans == "N" else low.T, b, lower=trans == "N", overwrite_A=True,
                                       overwrite_b=True, unit_diagonal=True)


def _superlu_triangular_solve():
    """SuperLU's triangular solve of scipy's SuperLU module (gstrs: L and U given in CSC), None
    where this scipy has none."""
    try:
        from scipy.sparse.linalg._dsolve import _superlu
    except ImportError:
        return None
    return getattr(_superlu, "gstrs", None)


def _symmetric_from_upper(c: np.ndarray) -> np.ndarray:
    """The symmetric matrix whose upper triangle LAPACK wrote into ``c``, in place."""
    return symmetric_from_lower(c.T).T


def _schur_and_inverse(lower: sp.csc_matrix, upper: sp.csc_matrix, m: int) -> tuple[np.ndarray, np.ndarray]:
    """S = L_cc U_cc from the trailing blocks of the factors L and U (CSC), and G = S^-1.

    K0 is symmetric and factored without pivoting, so L U = L D L^T with D = diag(U): with
    W = D^-1/2 U_cc (upper triangular), S = W^T W, i.e. W is S's Cholesky factor. Then S by one
    symmetric rank-k product (m^3 flops, half a general product) and G from W by LAPACK's
    potri (m^3 / 3 flops) instead of m solves with a fresh Cholesky (68k-dof peer scene, m =
    1352: 0.33 -> 0.1 s). Where a pivot is not positive (K0 not positive definite), the general
    product and a Cholesky of S (which then fails with its own error)."""
    from scipy.linalg import blas, lapack

    ucc = _trailing_block(upper, m)
    pivots = np.diag(ucc).copy()
    if np.all(pivots > 0.0):
        w = np.asfortranarray(ucc / np.sqrt(pivots)[:, None])
        schur = _symmetric_from_upper(blas.dsyrk(1.0, w, trans=1, lower=0))
        inverse, info = lapack.dpotri(w, lower=0)
        if info == 0:
            return schur, _symmetric_from_upper(inverse)
    lcc = _trailing_block(lower, m)
    schur = lcc @ ucc
    schur = 0.5 * (schur + schur.T)
    return schur, sla.cho_solve(sla.cho_factor(schur), np.eye(m))


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
    nested dissection of the node graph of ``k`` when ``k`` is given and pymetis is installed,
    else geometric nested dissection of each body's free nodes (:func:`nested_dissection`).

    Measured (SuperLU, natural order after the permutation): on the locally refined two-body
    peer problem (68k dofs) METIS's fill is 15 % below SuperLU's minimum degree and 40 % below
    the geometric dissection; on a uniform one-body grid (159k and 322k dofs) the geometric
    dissection factors as fast (10 % more fill) and orders 4x faster. So the contact
    condensation passes ``k``, the linear solve does not."""
    if k is not None:
        order = metis_order(k, bodies[0].dim if bodies else 2)
        if order is not None:
            return order
    perm = []
    for b in bodies:
        nodes = nested_dissection(b.grid.nodes[b.grid.free_nodes])
        perm.append(b.dof_offset + (b.dim * nodes[:, None] + np.arange(b.dim)).ravel())
    return np.concatenate(perm)


def _pymetis_nodes(k: sp.spmatrix, block: int):
    """(pymetis, k's node count) when pymetis is installed and k's dofs are whole nodes of
    ``block`` dofs; None otherwise."""
    try:
        import pymetis
    except ImportError:
        return None
    if k.shape[0] % block:
        return None
    return pymetis, k.shape[0] // block


def metis_order(k: sp.spmatrix, block: int) -> np.ndarray | None:
    """METIS nested dissection of the graph of ``block`` x ``block`` node blocks of k (the dofs
    of a node numbered together); None without pymetis."""
    found = _pymetis_nodes(k, block)
    if found is None:
        return None
    pymetis, node_count = found
    perm = _dissection(pymetis, _node_graph(k, block, np.arange(node_count)))
    return (block * perm[:, None] + np.arange(block)).ravel()


def contact_last_order(k: sp.spmatrix, dofs: np.ndarray, block: int, graph: sp.csr_matrix | None = None
                       ) -> np.ndarray | None:
    """A fill-reducing order of k's dofs for a factorisation that keeps ``dofs`` (whole nodes of
    ``block`` dofs) as its root, the last of the order: METIS's nested dissection, three
    separators tried at every level, of the node graph in which the nodes of ``dofs`` are
    contracted into one vertex. Every front whose rows reach the root carries rows of those
    dofs, so a graph that holds them apart lets the dissection cut across them as if they
    were eliminated early; contracted, they are one vertex that the separators treat as one.
    ``graph``: k's node graph (:func:`_node_graph`) when the caller has it. None without
    pymetis or when ``dofs`` are not whole nodes."""
    found = _pymetis_nodes(k, block)
    if found is None:
        return None
    pymetis, node_count = found
    hits = np.bincount(np.asarray(dofs) // block, minlength=node_count)
    if np.any((hits != 0) & (hits != block)):
        return None
    label = np.cumsum(hits == 0) - 1
    contracted = int(np.count_nonzero(hits == 0))
    label[hits != 0] = contracted
    if graph is None:
        graph = _node_graph(k, block, np.arange(node_count))
    perm = _dissection(pymetis, _relabelled(graph, label), nseps=3)
    nodes = np.flatnonzero(hits == 0)[perm[perm < contracted]]
    order = (block * nodes[:, None] + np.arange(block)).ravel()
    return np.concatenate([order, np.asarray(dofs, dtype=np.int64)])


def _node_graph(k: sp.spmatrix, block: int, label: np.ndarray) -> sp.csr_matrix:
    """The adjacency of the vertices ``label[node]`` of k's ``block`` x ``block`` node blocks (no loops)."""
    k = k.tocsr()
    rows = np.repeat(np.arange(k.shape[0]) // block, np.diff(k.indptr))
    return _relabelled(None, label, label[rows], label[k.indices // block])


def _relabelled(graph: sp.csr_matrix | None, label: np.ndarray, rows=None, cols=None) -> sp.csr_matrix:
    """The graph with vertex v renamed ``label[v]`` (vertices of one name contracted; no loops)."""
    if graph is not None:
        coo = graph.tocoo()
        rows, cols = label[coo.row], label[coo.col]
    off = rows != cols
    size = int(label.max()) + 1 if len(label) else 0
    out = sp.csr_matrix((np.ones(int(off.sum()), dtype=np.int8), (rows[off], cols[off])), shape=(size, size))
    out.sum_duplicates()
    out.sort_indices()
    return out


def _dissection(pymetis, graph: sp.csr_matrix, **options) -> np.ndarray:
    opts = pymetis.Options(**options) if options else None
    perm, _ = pymetis.nested_dissection(pymetis.CSRAdjacency(graph.indptr, graph.indices), options=opts)
    return np.asarray(perm, dtype=np.int64)
