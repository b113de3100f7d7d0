"""A supernodal multifrontal sparse Cholesky factorisation K = L L^T of a symmetric positive
definite matrix, with the Schur complement of a trailing set of dofs (compiled by numba).

The contact drivers condense the elastic system onto the contact dofs (:func:`solver.fem.linalg.
condensed_factor`). Here the elimination order (a fill-reducing permutation of all dofs, the m
contact dofs last) is factored as follows:

* symbolic: the elimination tree (Liu's path compression), with the last m columns forced into
  one chain and every other column whose parent lies in it hung below its first column; a
  postorder of that forest (an equivalent order: same fill); the column counts of L (the
  Gilbert-Ng-Peyton skeleton algorithm); fundamental supernodes, then relaxed amalgamation of a
  child into its parent when few explicit zeros are added (CHOLMOD's default limits); the
  supernodes' row structures; the factor offsets, the largest front and the depth of the
  update-matrix stack, all before any number is computed;
* numeric: one compiled loop over the supernodes in postorder: assemble the front (the matrix's
  columns and the children's update matrices, popped off a preallocated stack), factor its
  pivot columns (compiled panels of 48 columns, BLAS products for the trailing update), push
  the update matrix. The last m dofs form the root supernode: its assembled front is the Schur
  complement S = K_cc - K_ci K_ii^-1 K_ic, copied before it is factored as the last supernode;
  its Cholesky factor then gives G = S^-1 by LAPACK's potri. With several threads, each front of
  THREADED_FRONT_ROWS rows or more is factored on all of them (:func:`_threaded_ldlt`: the update
  below each outer block of pivots split into row ranges of equal work), the same operations;
* solve: forward and back substitution over the supernodes (compiled), in the original numbering;
  a factor of ON_DISK_BYTES or more below its root is written to a temporary file chunk by chunk
  as the numeric phase computes it (:func:`condensed_cholesky`: the whole factor is never in
  memory, only the root block S and G are read from), and its solves read it back in chunks.

Only L is stored (one flat float64 array, an (columns x front rows) block per supernode): about
half of SuperLU's L and U. A non-positive pivot raises :class:`NotPositiveDefinite` naming the
dof, so a caller can fall back to a pivoting factorisation.

The kernels live in :mod:`solver.fem._multifrontal_kernels`, imported (with numba) on the first
factorisation only; :func:`available` says whether they can be (numba importable,
``IBFEM_NO_JIT`` unset)."""

from __future__ import annotations

import contextlib
import mmap
import os
import tempfile

import numpy as np
import scipy.sparse as sp

from .dense import symmetric_from_lower

__all__ = ["CholeskyFactor", "NotPositiveDefinite", "available", "condensed_cholesky", "factor_flops"]

#: relaxed amalgamation: a merged supernode of at most RELAX_COLUMNS[i] columns is accepted when
#: its fraction of explicit zeros is below RELAX_ZEROS[i] (any size: below RELAX_ZEROS[2])
RELAX_COLUMNS = (4, 16, 48)
RELAX_ZEROS = (0.8, 0.1, 0.05)
#: :func:`condensed_cholesky` writes a factor's blocks below the root supernode to disk as they
#: are computed (``CholeskyFactor(on_disk=None)``) when they take at least this many bytes
ON_DISK_BYTES = 1 << 30
#: a factor held on disk is written and read this many bytes (at least one supernode) at a time;
#: two such ranges are in memory while it is written (one computed, one written)
DISK_CHUNK_BYTES = 1 << 27
#: with several threads, a front of at least this many rows is factored on all of them: after each
#: outer block of pivots, the update of the rows below it is split into row ranges of about equal
#: work, one per thread (94-95 % of the flops of the full ball on a block's bodies are in fronts of
#: 2,000 rows or more)
THREADED_FRONT_ROWS = 1000


class NotPositiveDefinite(np.linalg.LinAlgError):
    """A pivot of the Cholesky factorisation was not positive: the matrix is not positive
    definite (or too ill-conditioned for Cholesky). ``dof`` is the matrix row of the pivot."""

    def __init__(self, dof: int, n: int, definite: bool = True):
        self.dof = dof
        what = "not positive; the matrix is not positive definite" if definite else "zero or not finite"
        super().__init__(f"sparse Cholesky factorisation: the pivot of dof {dof} (of {n}) is {what}")


def available() -> bool:
    """Whether the compiled kernels can be used: numba importable and ``IBFEM_NO_JIT`` unset."""
    if os.environ.get("IBFEM_NO_JIT", "") not in ("", "0"):
        return False
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _kernels():
    from . import _multifrontal_kernels

    return _multifrontal_kernels


def _lower(k: sp.spmatrix, where: np.ndarray, fmt: str):
    """The lower triangle of P (K + K^T)/2 P^T (``where[old] = new``) as int64-indexed CSC or CSR.

    Assembled stiffness matrices are symmetric only to round-off: a coupling that cancels to
    3.7e-9 on one side may be absent on the other. The symbolic phase reads the lower triangle
    in one numbering and the numeric phase in another (the postorder), so both must see one
    structurally symmetric matrix: every entry is folded onto the lower triangle with half its
    weight (the diagonal whole), which factors K's symmetric part."""
    coo = k.tocoo()
    r, c = where[coo.row], where[coo.col]
    data = np.where(r == c, coo.data, 0.5 * coo.data)
    r, c = np.maximum(r, c), np.minimum(r, c)
    shape = k.shape
    out = (sp.csr_matrix if fmt == "csr" else sp.csc_matrix)((data, (r, c)), shape=shape)
    out.sum_duplicates()
    return out.indptr.astype(np.int64), out.indices.astype(np.int64), out.data.astype(np.float64)


class CholeskyFactor:
    """P K P^T = L D L^T (unit L, no pivoting; the Cholesky factor is L D^1/2) in the elimination
    order ``order`` (new index i is dof ``order[i]``), the last ``m`` dofs of the order one root
    supernode whose assembled front (the Schur complement of those dofs) is kept in ``schur``.
    ``definite``: a non-positive pivot raises :class:`NotPositiveDefinite`; else only a zero or
    non-finite one does. ``solve(f)`` for f of shape (n,) or (n, k) in the original numbering.

    Accounting: ``nnz`` (stored entries of L, explicit zeros of the amalgamated supernodes
    included), ``factor_bytes``, ``n_supernodes``, ``largest_front``, and the work space of
    the numeric phase: ``stack_bytes`` (update matrices), ``front_bytes`` (the largest front
    that is not a root; roots are assembled in their factor blocks).

    ``keep_schur=False``: S is not copied out of the root front (an m x m array less);
    :meth:`schur_operator` applies it from the factor's root block instead.

    ``on_disk``: the blocks below the root supernode are written to an unlinked temporary file
    DISK_CHUNK_BYTES at a time as the numeric phase computes them (None: when they take
    ON_DISK_BYTES or more), so the whole factor is never in memory; the root block, which
    products with S and G read, stays. :meth:`to_disk` moves them there afterwards. ``solve``
    then reads them back DISK_CHUNK_BYTES at a time.

    ``threads``: the numeric phase factors each front of THREADED_FRONT_ROWS rows or more on that
    many threads (the compiled kernels hold no lock; the same operations as on one thread).
    ``numeric_bytes``: what the numeric phase allocates, known from the symbolic phase."""

    _disk = None  # the temporary file of the blocks below the root (None: all in memory)
    threaded_solve = True  # solves of several factors may run on threads at once (compiled, no GIL)
    _base = 0  # offset in the factor of ``factor[0]`` (the root block's when on disk)
    _pool = None  # the helper threads of the large fronts during the numeric phase (None: one thread)

    def __init__(self, k: sp.spmatrix, order: np.ndarray, m: int = 0, definite: bool = True,
                 keep_schur: bool = True, on_disk: bool | None = False, threads: int = 1):
        if not sp.issparse(k):
            k = sp.csr_matrix(np.asarray(k, dtype=np.float64))
        n = k.shape[0]
        if k.ndim != 2 or k.shape[1] != n:
            raise ValueError(f"the Cholesky factorisation needs a square matrix, got shape {k.shape}")
        order = np.asarray(order, dtype=np.int64)
        if order.shape != (n,) or not np.array_equal(np.sort(order), np.arange(n)):
            raise ValueError(f"the elimination order must be a permutation of the {n} dofs")
        if not 0 <= m <= n:
            raise ValueError(f"the root supernode must hold between 0 and {n} dofs, got {m}")
        self.n, self.m, self.definite = n, int(m), bool(definite)
        kern = _kernels()
        self.order = self._postordered(k, order, kern)
        self._symbolic(k, kern)
        below_root = self.factor_bytes - 8 * self.m * self.m
        streamed = bool(self.m and self.n_supernodes > 1
                        and (on_disk or (on_disk is None and below_root >= ON_DISK_BYTES)))
        self.numeric_bytes = self._numeric_bytes(streamed, keep_schur)
        with _front_pool(threads, self.largest_front) as self._pool:
            self.schur = np.zeros((self.m, self.m) if keep_schur else (0, 0))
            if streamed:
                self._numeric_to_disk(kern)
            else:
                self._numeric(kern)
        del self._pool

    def _numeric_bytes(self, streamed: bool, keep_schur: bool) -> int:
        """What the numeric phase allocates: the update-matrix stack, the largest front below
        the root, the factor (streamed: its root block and the two range arrays of blocks below it
        that are in memory at once) and the copy of S."""
        held = self.factor_bytes
        if streamed:  # two range arrays (one computed, one written); larger blocks in the front buffer
            ptr = self.factor_ptr
            largest = max((int(ptr[s1] - ptr[s0]) for s0, s1 in self._chunk_bounds() if not self._in_front(s0, s1)),
                          default=0)
            held = 8 * (self.m * self.m + 2 * largest)
        return int(self.stack_bytes + self.front_bytes + held + (8 * self.m * self.m if keep_schur else 0))

    def _postordered(self, k, order, kern) -> np.ndarray:
        """The elimination tree of ``order`` (the root chain forced), its postorder composed
        with ``order``; keeps the tree in the new numbering (whose postorder is the identity)."""
        n, m = self.n, self.m
        where = np.empty(n, dtype=np.int64)
        where[order] = np.arange(n)
        rowptr, colind, _ = _lower(k, where, "csr")
        parent = kern.elimination_tree(rowptr, colind, n)
        del rowptr, colind
        top = n - m
        if m:
            parent[top:-1] = np.arange(top + 1, n)
            parent[n - 1] = -1
            parent[:top][parent[:top] >= top] = top
        post = kern.postorder(parent)
        inverse = np.empty(n, dtype=np.int64)
        inverse[post] = np.arange(n)
        self._parent = np.where(parent[post] >= 0, inverse[np.maximum(parent[post], 0)], -1)
        return order[post]

    def _symbolic(self, k, kern) -> None:
        """Supernodes, their row structures, the factor offsets, the largest front and the
        stack of update matrices (sized by a dry run of the numeric phase's pushes and pops)."""
        n = self.n
        where = np.empty(n, dtype=np.int64)
        where[self.order] = np.arange(n)
        self._colptr, self._rowind, self._values = _lower(k, where, "csc")
        counts = kern.column_counts(self._colptr, self._rowind, self._parent, np.arange(n), self.m)
        start, below = kern.supernodes(self._parent, counts, self.m, np.array(RELAX_COLUMNS, np.int64),
                                       np.array(RELAX_ZEROS, np.float64))
        row_ptr, rows, sn_parent = kern.row_structure(self._colptr, self._rowind, start, below, self._parent)
        if len(sn_parent) != len(below) or (self.m and start[-2] != n - self.m):
            raise RuntimeError("multifrontal symbolic factorisation: row structures disagree with the column counts")
        del self._parent
        ncol = np.diff(start)
        front = ncol + below
        self.sn_start, self.row_ptr, self.rows, self.sn_parent = start, row_ptr, rows, sn_parent
        self.factor_ptr = np.concatenate([[0], np.cumsum(ncol * front)]).astype(np.int64)
        self.n_supernodes = len(below)
        self.largest_front = int(front.max()) if len(front) else 0
        self.stack_size = _stack_size(sn_parent, below)
        self._buffer = int(front[below > 0].max(initial=0))
        self.nnz = int(self.factor_ptr[-1] - np.sum(ncol * (ncol - 1) // 2))
        self.factor_bytes = 8 * int(self.factor_ptr[-1])
        self.stack_bytes = 8 * self.stack_size
        self.front_bytes = 8 * self._buffer ** 2

    def _numeric(self, kern) -> None:
        factor = np.empty(int(self.factor_ptr[-1]))
        work = kern.numeric_work(self.n, self.n_supernodes, self.stack_size, self._buffer)
        bad = self._factor_range(kern, 0, self.n_supernodes, factor, 0, work)
        del self._colptr, self._rowind, self._values, work
        if bad >= 0:
            raise NotPositiveDefinite(int(self.order[bad]), self.n, self.definite)
        self.factor = factor

    def _factor_range(self, kern, s0: int, s1: int, segment: np.ndarray, base: int, work: tuple) -> int:
        """The numeric phase over supernodes s0..s1-1 (blocks into ``segment`` from factor offset
        ``base``, continuing with the work space ``work``): runs of small fronts in one compiled
        call; with a thread pool, each front of THREADED_FRONT_ROWS rows or more assembled and
        stored by compiled calls and factored on the pool's threads (:func:`_threaded_ldlt`).
        Returns the failed column or -1."""
        args = (self._colptr, self._rowind, self._values, self.sn_start, self.row_ptr, self.rows, self.sn_parent,
                self.factor_ptr)
        large = np.empty(0, dtype=np.int64)
        if self._pool is not None:
            front = np.diff(self.sn_start) + np.diff(self.row_ptr)
            large = np.flatnonzero(front[s0:s1] >= THREADED_FRONT_ROWS) + s0
        start = s0
        for s in [*large.tolist(), s1]:
            if s > start:
                bad = kern.multifrontal_range(*args, start, s, segment, base, work, self.schur, self.definite,
                                              kern.DGEMM)
                if bad >= 0:
                    return bad
            if s == s1:
                break
            rowwise = self.row_ptr[s + 1] > self.row_ptr[s]  # not a root (assembled in its factor block)
            if rowwise:
                t = _threaded_assemble(kern, args, s, work, self._pool)
            else:
                t = kern.assemble_front(*args, s, segment, base, work, self.schur)
            bad = _threaded_ldlt(kern, t, int(self.sn_start[s + 1] - self.sn_start[s]), self.definite, self._pool)
            if bad >= 0:
                return int(self.sn_start[s]) + bad
            if rowwise:
                _threaded_store(kern, self, s, t, segment, base, work, self._pool)
            else:
                kern.store_front(self.sn_start, self.row_ptr, self.sn_parent, self.factor_ptr, s, t, segment, base,
                                 work)
            start = s + 1
        return -1

    def _numeric_to_disk(self, kern) -> None:
        """The numeric phase with the blocks below the root written to an unlinked temporary
        file as they are computed, DISK_CHUNK_BYTES (at least one supernode) at a time: only
        the ranges being computed and written and the root block are ever in memory, never the
        whole factor. A range is written on a background thread while the next is computed in
        the other of two range arrays; a supernode whose block alone exceeds DISK_CHUNK_BYTES
        (the large separators near the top of the tree) is written from the front buffer it
        was factored in, so the range arrays need not hold it. Where the file cannot be written
        the ranges are kept in memory instead."""
        ns, m = self.n_supernodes, self.m
        st_off = np.zeros(ns + 1, dtype=np.int64)
        work = [np.empty(self.stack_size), np.empty(self._buffer ** 2), np.empty(self.n, dtype=np.int64),
                np.empty(ns, dtype=np.int64), st_off, np.zeros(1, dtype=np.int64)]
        chunks, ptr = self._chunk_bounds(), self.factor_ptr
        in_front = [self._in_front(s0, s1) for s0, s1 in chunks]
        largest = max((int(ptr[s1] - ptr[s0]) for (s0, s1), f in zip(chunks, in_front) if not f), default=0)
        with _BackgroundWriter(largest) as writer:
            for (s0, s1), front in zip(chunks, in_front):
                size = int(ptr[s1] - ptr[s0])
                segment = work[1][:size] if front else writer.next_buffer(size)
                bad = self._factor_range(kern, s0, s1, segment, int(ptr[s0]), tuple(work))
                if bad >= 0:
                    raise NotPositiveDefinite(int(self.order[bad]), self.n, self.definite)
                writer.append(segment, wait=front)  # the front buffer is reused by the next range
            handle, kept = writer.finish()
        work[1] = np.empty(0)  # the front buffer: the root is assembled in its own block
        root = np.empty(m * m)
        bad = self._factor_range(kern, ns - 1, ns, root, int(ptr[ns - 1]), tuple(work))
        del work, self._colptr, self._rowind, self._values
        if bad >= 0:
            raise NotPositiveDefinite(int(self.order[bad]), self.n, self.definite)
        if handle is None:  # no file: the factor in memory after all
            self.factor = np.concatenate(kept + [root])
            return
        self.factor, self._base, self._disk, self._chunks = root, int(self.factor_ptr[ns - 1]), handle, chunks

    def _in_front(self, s0: int, s1: int) -> bool:
        """Whether the range s0..s1-1 is one supernode larger than DISK_CHUNK_BYTES factored in
        the front buffer (not a root of its own tree, which is assembled in its factor block):
        its block is then the buffer's first rows, written from there."""
        return (s1 == s0 + 1 and 8 * int(self.factor_ptr[s1] - self.factor_ptr[s0]) > DISK_CHUNK_BYTES
                and self.row_ptr[s0 + 1] > self.row_ptr[s0])

    def _chunk_bounds(self) -> list[tuple[int, int]]:
        """Ranges of supernodes below the root of about DISK_CHUNK_BYTES each (at least one)."""
        ptr = self.factor_ptr[:self.n_supernodes]  # the root is the last supernode
        chunk = max(DISK_CHUNK_BYTES // 8, 1)
        bounds, s0 = [], 0
        while s0 < self.n_supernodes - 1:
            s1 = int(np.searchsorted(ptr, ptr[s0] + chunk, side="right")) - 1
            s1 = min(max(s1, s0 + 1), self.n_supernodes - 1)
            bounds.append((s0, s1))
            s0 = s1
        return bounds

    def solve(self, f: np.ndarray) -> np.ndarray:
        """K^-1 f for f of shape (n,) or (n, k), in the original numbering."""
        f = np.asarray(f, dtype=np.float64)
        if f.shape[:1] != (self.n,) or f.ndim > 2:
            raise ValueError(f"the right-hand side must have shape ({self.n},) or ({self.n}, k), got {f.shape}")
        b = np.ascontiguousarray(f[self.order].reshape(self.n, -1))
        if self._disk is None:
            _kernels().solve(self.factor, self.factor_ptr, self.sn_start, self.row_ptr, self.rows, b)
        else:
            b = self._solve_from_disk(np.ascontiguousarray(b.T)).T
        out = np.empty_like(b)
        out[self.order] = b
        return out.reshape(f.shape)

    def to_disk(self, directory: str | None = None) -> None:
        """Move the factor's blocks below the root supernode to an unlinked temporary file (in
        ``directory``, else the system's temporary directory; removed when the factor is):
        their memory is freed, and each solve reads them back in chunks. Where the file cannot
        be written (no writable temporary directory, a full disk) the factor stays in memory."""
        if self._disk is not None or self.m == 0:
            return
        split = int(self.factor_ptr[-1]) - self.m * self.m  # the root block's offset
        try:
            handle = tempfile.TemporaryFile(dir=directory)
            self.factor[:split].tofile(handle)
            handle.flush()
        except OSError:  # no writable temporary directory, or the disk is full: stay in memory
            with contextlib.suppress(NameError, OSError):
                handle.close()
            return
        self.factor, self._base, self._disk = self.factor[split:].copy(), split, handle
        self._chunks = self._chunk_bounds()

    def _sweep(self, kernel, s0: int, s1: int, bt: np.ndarray) -> None:
        """``kernel`` (forward_range or backward_range) over supernodes s0..s1-1 for each row of bt,
        their blocks mapped from the file into memory: the pages the system holds are used in
        place, no copy into a new array (benchmarks/factor_on_disk.py: a solve a third to two thirds
        of the CPU time of reading them), and unmapped afterwards. Read into an array where the file
        cannot be mapped."""
        lo, hi = int(self.factor_ptr[s0]), int(self.factor_ptr[s1])
        args = (s0, s1, self.factor_ptr, self.sn_start, self.row_ptr, self.rows)
        start = (8 * lo) // mmap.ALLOCATIONGRANULARITY * mmap.ALLOCATIONGRANULARITY  # mapped from a page
        try:
            view = mmap.mmap(self._disk.fileno(), 8 * hi - start, offset=start, access=mmap.ACCESS_READ)
            segment = np.frombuffer(view, dtype=np.float64, count=hi - lo, offset=8 * lo - start)
        except (OSError, ValueError, AttributeError):
            view = None
            self._disk.seek(8 * lo)
            segment = np.fromfile(self._disk, dtype=np.float64, count=hi - lo)
        for b in bt:
            kernel(segment, lo, *args, b)
        del segment  # before the view is closed
        if view is not None:
            view.close()

    def _solve_from_disk(self, bt: np.ndarray) -> np.ndarray:
        """Overwrite bt (k, n), right-hand sides in the factor's numbering, with K^-1 of them:
        forward over the chunks read from disk then the root, backward the other way."""
        kern = _kernels()
        args = (self.factor_ptr, self.sn_start, self.row_ptr, self.rows)
        root = (self.n_supernodes - 1, self.n_supernodes)
        for s0, s1 in self._chunks:
            self._sweep(kern.forward_range, s0, s1, bt)
        for b in bt:
            kern.forward_range(self.factor, self._base, *root, *args, b)
            kern.backward_range(self.factor, self._base, *root, *args, b)
        for s0, s1 in reversed(self._chunks):
            self._sweep(kern.backward_range, s0, s1, bt)
        return bt

    def _root_block(self) -> np.ndarray:
        """The root supernode's m x m block of the factor (row k: D_k, then column k of L)."""
        m = self.m
        start = int(self.factor_ptr[-1]) - m * m - self._base
        return self.factor[start:].reshape(m, m)

    def schur_operator(self) -> "RootSchur":
        """S = L_cc D_c L_cc^T of the root block as an operator (no m x m copy)."""
        return RootSchur(self._root_block())

    def root_factor(self) -> np.ndarray:
        """The Cholesky factor W = L sqrt(D) of the Schur complement (lower triangular, m x m,
        Fortran order) from the root block; NotPositiveDefinite when a pivot of D is not positive."""
        m = self.m
        block = self._root_block()
        d = np.diag(block).copy()
        if m and not d.min() > 0.0:
            bad = int(np.flatnonzero(~(d > 0.0))[0])
            raise NotPositiveDefinite(int(self.order[self.n - m + bad]), self.n)
        root = np.sqrt(d)
        w = block * root[:, None]
        w[np.diag_indices(m)] = root
        return w.T  # Fortran order


class RootSchur:
    """The Schur complement S = L D L^T held by a root block of the factor (``block[k, k]`` = D_k,
    ``block[k, i]`` = L_ik below the diagonal): products S x by two triangular products
    (2 m^2 flops, nothing m x m allocated); :meth:`toarray` forms it (the rare dense use)."""

    def __init__(self, block: np.ndarray):
        self.lower = block.T  # Fortran order: unit lower triangular L with D on its diagonal
        self.d = np.diag(block).copy()
        self.shape = block.shape
        self.ndim = 2

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        from scipy.linalg import blas

        x = np.asarray(x, dtype=np.float64)
        if x.ndim == 1:
            y = blas.dtrmv(self.lower, x, trans=1, lower=1, diag=1) * self.d
            return blas.dtrmv(self.lower, y, trans=0, lower=1, diag=1, overwrite_x=1)
        y = blas.dtrmm(1.0, self.lower, x, side=0, lower=1, trans_a=1, diag=1) * self.d[:, None]
        return blas.dtrmm(1.0, self.lower, y, side=0, lower=1, trans_a=0, diag=1, overwrite_b=1)

    def toarray(self) -> np.ndarray:
        from scipy.linalg import blas

        w = np.tril(self.lower, -1) + np.eye(len(self.d))
        w *= np.sqrt(np.abs(self.d))[None, :]
        if np.all(self.d > 0.0):
            return symmetric_from_lower(blas.dsyrk(1.0, np.asfortranarray(w), lower=1))
        return (w * np.sign(self.d)[None, :]) @ w.T

    def __array__(self, dtype=None, copy=None):
        a = self.toarray()
        return a if dtype is None else a.astype(dtype)

    def __getitem__(self, key):
        return self.toarray()[key]


class RootInverse:
    """G = S^-1 of a root block (S = L D L^T) without forming all of it.

    Products G x are solves with the block's factors (2 m^2 flops). Entries of G are read from
    the trailing p x p block of G, formed once: L is lower triangular, so L^-1's trailing block is
    the inverse of L's, and the trailing block of G = L^-T D^-1 L^-1 is (L_TT D_T L_TT^T)^-1,
    LAPACK's potri on the trailing block of S's Cholesky factor ((2/3) p^3 flops and p^2 entries
    instead of (2/3) m^3 and m^2). Entries outside it come from Y = L_QQ^-1 E (the trailing
    block Q from the first index asked): G_uv = Y_u^T D^-1 Y_v. The contact drivers order the
    condensed dofs nearest the contact point last, so a trial region's dofs fall in the trailing
    block."""

    def __init__(self, block: np.ndarray, trailing: int):
        from scipy.linalg import lapack

        m = len(block)
        self.lower = block.T  # Fortran order: unit lower triangular L with D on its diagonal
        self.d = np.diag(block).copy()
        self.shape, self.ndim = block.shape, 2
        self.start = m - int(min(max(trailing, 0), m))
        w = np.tril(self.lower[self.start:, self.start:], -1)
        w[np.diag_indices_from(w)] = 1.0
        w *= np.sqrt(self.d[self.start:])[None, :]
        inverse, info = lapack.dpotri(np.asfortranarray(w), lower=1, overwrite_c=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"the trailing block of the Schur complement is singular (LAPACK info {info})")
        self.trailing = symmetric_from_lower(inverse)

    def __matmul__(self, x: np.ndarray) -> np.ndarray:
        from scipy.linalg import blas

        x = np.asarray(x, dtype=np.float64)
        if x.ndim == 1:
            y = blas.dtrsv(self.lower, x, lower=1, trans=0, diag=1) / self.d
            return blas.dtrsv(self.lower, y, lower=1, trans=1, diag=1, overwrite_x=1)
        y = blas.dtrsm(1.0, self.lower, x, side=0, lower=1, trans_a=0, diag=1) / self.d[:, None]
        return blas.dtrsm(1.0, self.lower, y, side=0, lower=1, trans_a=1, diag=1, overwrite_b=1)

    def take(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """The dense sub-matrix G[rows][:, cols]."""
        from scipy.linalg import blas

        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        if not len(rows) or not len(cols):
            return np.zeros((len(rows), len(cols)))
        q = int(min(rows.min(), cols.min()))
        if q >= self.start:
            return self.trailing[np.ix_(rows - self.start, cols - self.start)]
        both, inverse = np.unique(np.concatenate([rows, cols]), return_inverse=True)
        e = np.zeros((len(self.d) - q, len(both)), order="F")
        e[both - q, np.arange(len(both))] = 1.0
        y = blas.dtrsm(1.0, self.lower[q:, q:], e, side=0, lower=1, trans_a=0, diag=1, overwrite_b=1)
        g = y.T @ (y / self.d[q:, None])
        return g[np.ix_(inverse[:len(rows)], inverse[len(rows):])]

    def toarray(self) -> np.ndarray:
        every = np.arange(len(self.d))
        return self.take(every, every)

    def __array__(self, dtype=None, copy=None):
        a = self.toarray()
        return a if dtype is None else a.astype(dtype)


def _temporary_file():
    """An unlinked temporary file for a factor's blocks, or None where none can be made."""
    try:
        return tempfile.TemporaryFile()
    except OSError:
        return None


def _write_or_keep(handle, segment: np.ndarray, written: int, kept: list):
    """Append ``segment`` to the file ``handle``, which holds ``written`` entries; where that
    fails (a full disk) or there is no file, keep a copy of every segment in ``kept`` (those
    already written are read back; the caller reuses the segment's memory) and return None."""
    if handle is not None:
        try:
            handle.write(segment.data)  # the array's own buffer, not a copy
            handle.flush()
            return handle
        except OSError:
            handle.seek(0)
            kept.append(np.fromfile(handle, dtype=np.float64, count=written))
            handle.close()
    kept.append(segment.copy())
    return None


class _BackgroundWriter:
    """Appends a factor's ranges to an unlinked temporary file (:func:`_temporary_file`, through
    :func:`_write_or_keep`: kept in memory where the file fails) on one background thread, in the
    order given, while the caller computes the next range in the other of two range arrays of
    ``size`` entries (:meth:`next_buffer` waits for that array's write). The write is system time
    that otherwise holds up the factorisation (about 2 s per GB here)."""

    def __init__(self, size: int):
        from concurrent.futures import ThreadPoolExecutor

        self._size, self._arrays, self._pending, self._turn = size, [None, None], [None, None], 0
        self._thread = ThreadPoolExecutor(1)
        self.handle, self.kept, self.written = _temporary_file(), [], 0

    def next_buffer(self, size: int) -> np.ndarray:
        """The first ``size`` entries of the range array whose write has finished longest ago."""
        self._turn = 1 - self._turn
        if self._pending[self._turn] is not None:
            self._pending[self._turn].result()
        if self._arrays[self._turn] is None:
            self._arrays[self._turn] = np.empty(self._size)
        return self._arrays[self._turn][:size]

    def append(self, segment: np.ndarray, wait: bool) -> None:
        """Queue ``segment`` (the last :meth:`next_buffer`'s, or with ``wait`` any other array,
        written before this returns) after those queued before."""
        job = self._thread.submit(self._write, segment, self.written)
        self.written += segment.size
        if wait:
            job.result()
        else:
            self._pending[self._turn] = job

    def _write(self, segment: np.ndarray, written: int) -> None:
        self.handle = _write_or_keep(self.handle, segment, written, self.kept)

    def finish(self):
        """(the file or None, the ranges kept in memory) once every write is done; the range
        arrays freed."""
        self._thread.shutdown(wait=True)
        for job in self._pending:
            if job is not None:
                job.result()  # an error of a write that was not waited for
        self._arrays = self._pending = None
        return self.handle, self.kept

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._thread.shutdown(wait=True)
        self._arrays = self._pending = None
        if exc[0] is not None and self.handle is not None:
            self.handle.close()  # a failed factorisation: the partial file removed
        return False


@contextlib.contextmanager
def _front_pool(threads: int, largest_front: int):
    """threads - 1 helper threads for the large fronts (:func:`_threaded_ldlt`; the caller's
    thread is the other), or None with one thread or no front of THREADED_FRONT_ROWS rows."""
    if threads < 2 or largest_front < THREADED_FRONT_ROWS:
        yield None
        return
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(threads - 1) as pool:
        pool.parts = threads
        yield pool


#: a panel's compiled loops take about this many times BLAS's time per multiply-add (the split of
#: a front's update gives the caller's thread, which factors the next outer block meanwhile, less)
PANEL_COST = 2.0


def _row_bounds(b1: int, f: int, block: int, parts: int, lead: int = 0) -> list[int]:
    """Bounds b1 = r_0 < r_1 < ... < f of row ranges that share the update of the front's rows
    b1..f-1 in about equal work (row j costs f - j entries: the rows from r on cost (f - r)^2 / 2),
    the first range less the work of factoring the next ``lead`` pivots (about PANEL_COST lead
    (f - b1) / 2 in those units), which its thread does next. Each bound is on the grid of BLAS
    blocks from b1, so that every product is the one the serial update makes (the same sums)."""
    whole = (f - b1) ** 2 / 2.0
    panel = PANEL_COST * lead * (f - b1) / 2.0
    bounds = [b1]
    for i in range(1, parts):
        done = i * (whole + panel) / parts - panel  # work of the rows before r_i
        r = (f - np.sqrt(max((f - b1) ** 2 - 2.0 * max(done, 0.0), 0.0)) - b1) / block
        # the grid point above b1 whose rows' work is nearest (the first range keeps the next block)
        r = min((b1 + max(int(k), 1) * block for k in (np.floor(r), np.ceil(r))),
                key=lambda x: abs(whole - min(f - x, f - b1) ** 2 / 2.0 - done))
        if bounds[-1] < r < f:
            bounds.append(r)
    return bounds + [f]


def _threaded_ldlt(kern, t: np.ndarray, nc: int, definite: bool, pool) -> int:
    """The kernels' L D L^T of the first nc columns of the front t (f x f) with the update of the
    rows below each outer block of pivots shared by the pool's threads and the caller's (compiled,
    no lock held; disjoint row ranges). The caller's range comes first and holds the next outer
    block's rows, so the caller factors that block's panels while the others finish their ranges
    (the block's rows have had every update by then, and the panels touch no other row). Every
    entry gets the operations of the one-thread kernel in the same order. Returns the failed
    column or -1."""
    f = t.shape[0]
    bad = kern.outer_block(kern.DGEMM, t, 0, min(kern.OUTER, nc), f, definite)
    for b0 in range(0, nc, kern.OUTER):
        if bad >= 0:
            return bad
        b1 = min(b0 + kern.OUTER, nc)
        b2 = min(b1 + kern.OUTER, nc)  # the next outer block (none when b2 == b1)
        bounds = _row_bounds(b1, f, kern.BLOCK, pool.parts, b2 - b1)
        jobs = [pool.submit(kern.trailing_rows, kern.DGEMM, t, b0, b1, lo, hi, f)
                for lo, hi in zip(bounds[1:-1], bounds[2:])]
        kern.trailing_rows(kern.DGEMM, t, b0, b1, bounds[0], bounds[1], f)
        ahead = b2 > b1 and bounds[1] >= b2
        if ahead:
            bad = kern.outer_block(kern.DGEMM, t, b1, b2, f, definite)
        for job in jobs:
            job.result()
        kern.scale_rows(t, b0, b1, f)
        if b2 > b1 and not ahead:
            bad = kern.outer_block(kern.DGEMM, t, b1, b2, f, definite)
    return bad


def _triangle_bounds(lo: int, hi: int, parts: int) -> list[int]:
    """Bounds lo = r_0 <= ... <= r_parts = hi of row ranges of a triangle whose row j holds
    hi - j entries, each range about the same number of entries."""
    n = hi - lo
    return [lo] + [lo + int(round(n - n * np.sqrt(1.0 - i / parts))) for i in range(1, parts)] + [hi]


def _on_threads(pool, calls) -> None:
    """Run the calls, the first on this thread and the others on the pool's, and wait for all."""
    jobs = [pool.submit(call) for call in calls[1:]]
    calls[0]()
    for job in jobs:
        job.result()


def _threaded_assemble(kern, args: tuple, s: int, work: tuple, pool) -> np.ndarray:
    """:func:`_multifrontal_kernels.assemble_front` of a front that is not a root, its rows shared
    by the pool's threads and the caller's (the same additions in the same order for every
    entry; each thread writes its own rows)."""
    colptr, rowind, values, sn_start, row_ptr, rows, sn_parent, _ = args
    nc = int(sn_start[s + 1] - sn_start[s])
    f = nc + int(row_ptr[s + 1] - row_ptr[s])
    kern.front_positions(sn_start, row_ptr, rows, s, work[2])
    t = work[1][:f * f].reshape(f, f)
    bounds = _triangle_bounds(0, f, pool.parts)
    _on_threads(pool, [lambda lo=lo, hi=hi: kern.assemble_rows(colptr, rowind, values, sn_start, row_ptr, rows,
                                                                 sn_parent, s, t, work, lo, hi)
                       for lo, hi in zip(bounds[:-1], bounds[1:])])
    kern.pop_children(sn_parent, s, work)
    return t


def _threaded_store(kern, factor: "CholeskyFactor", s: int, t: np.ndarray, segment: np.ndarray, base: int,
                    work: tuple, pool) -> None:
    """:func:`_multifrontal_kernels.store_front` of a front that is not a root, its pivot rows and
    update rows shared by the pool's threads and the caller's. A block written from the front
    buffer itself (``segment`` is the buffer: :meth:`CholeskyFactor._numeric_to_disk`) is not
    copied onto itself, only its entries left of the diagonal zeroed."""
    nc = int(factor.sn_start[s + 1] - factor.sn_start[s])
    nr = int(factor.row_ptr[s + 1] - factor.row_ptr[s])
    off = int(factor.factor_ptr[s]) - base
    copy = not (segment.ctypes.data + 8 * off == t.ctypes.data)
    pivots = _triangle_bounds(0, nc, pool.parts)
    update = _triangle_bounds(0, nr if factor.sn_parent[s] != -1 else 0, pool.parts)
    _on_threads(pool, [lambda i=i: kern.store_rows(factor.sn_start, factor.row_ptr, factor.factor_ptr, s, t, segment,
                                                     base, work, pivots[i], pivots[i + 1], update[i], update[i + 1],
                                                     copy)
                       for i in range(pool.parts)])
    kern.push_update(factor.sn_start, factor.row_ptr, factor.sn_parent, s, work)


def factor_flops(k: sp.spmatrix, order: np.ndarray, m: int = 0) -> float:
    """The multiply-adds of the L D L^T factorisation of K in ``order`` (the last m dofs one
    root), sum over the columns of L of the square of their count of entries below the
    diagonal: the elimination tree and the column counts only (no supernodes, no row
    structures, nothing numeric), to compare elimination orders before factoring in one."""
    kern = _kernels()
    f = CholeskyFactor.__new__(CholeskyFactor)
    f.n, f.m = k.shape[0], int(m)
    post = f._postordered(k, np.asarray(order, dtype=np.int64), kern)
    where = np.empty(f.n, dtype=np.int64)
    where[post] = np.arange(f.n)
    colptr, rowind, _ = _lower(k, where, "csc")
    counts = kern.column_counts(colptr, rowind, f._parent, np.arange(f.n), f.m).astype(np.float64)
    return float(np.sum((counts - 1.0) ** 2))


def _stack_size(sn_parent: np.ndarray, below: np.ndarray) -> int:
    """Entries of the update-matrix stack at its deepest: each supernode pushes its (rows x rows)
    update matrix after popping its children's (which are on top, in postorder)."""
    size = below.astype(np.int64) ** 2
    size[sn_parent < 0] = 0
    children = np.zeros(len(below), dtype=np.int64)
    np.add.at(children, sn_parent[sn_parent >= 0], size[sn_parent >= 0])
    depth = np.cumsum(size - children)  # after each supernode's pops and push
    return int(max(depth.max(initial=0), 0))


def condensed_cholesky(k0: sp.spmatrix, order: np.ndarray, m: int, definite: bool = False, guard=None,
                       trailing: int | None = None, on_disk: bool | None = None, threads: int = 1):
    """(factor, S, G) of K0 in the order ``order`` whose last m dofs are the condensed ones:
    S their Schur complement (a :class:`RootSchur` on the factor's root block: no m x m copy),
    G = S^-1 (LAPACK potri on S's Cholesky factor, the root block).
    ``definite=False`` (the condensed contact systems): K0's interior pivots may be negative
    (Nitsche and cut-cell terms make some 3D stiffness matrices indefinite), as in SuperLU's
    factorisation without pivoting; S itself must be positive definite. ``guard``: a context
    manager factory the factorisation runs in (the caller's one-BLAS-thread guard: its many
    mid-size products gain nothing from threads), not potri (one large product). ``trailing``: G
    as a :class:`RootInverse` holding only its trailing ``trailing`` x ``trailing`` block (None:
    all of G, dense). ``on_disk``: the factor's blocks below the root are written to a temporary
    file as they are computed (None: when they take ON_DISK_BYTES or more), so that a caller
    factoring several bodies in turn holds only their root blocks in memory, and the body being
    factored one chunk of its factor besides its work space. ``threads``: as for
    :class:`CholeskyFactor` (its large fronts factored on that many threads)."""
    from scipy.linalg import lapack

    with guard() if guard is not None else contextlib.nullcontext():
        factor = CholeskyFactor(k0, order, m, definite, keep_schur=False, on_disk=on_disk, threads=threads)
    if m == 0:
        return factor, np.zeros((0, 0)), np.zeros((0, 0))
    schur = factor.schur_operator()
    if trailing is not None and trailing < m:
        if not np.all(schur.d > 0.0):
            factor.root_factor()  # raises NotPositiveDefinite naming the dof
        return factor, schur, RootInverse(factor._root_block(), trailing)
    inverse, info = lapack.dpotri(factor.root_factor(), lower=1, overwrite_c=1)
    if info != 0:
        raise NotPositiveDefinite(int(order[len(order) - m + max(info - 1, 0)]), len(order))
    return factor, schur, symmetric_from_lower(inverse)
