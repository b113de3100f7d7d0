"""Point operators of a contact band between two grids, kept as one block per point over the
node dofs of the point's two cells (one in each body's grid), and the band's terms summed over
each pair of cells before anything is mapped onto the contact dofs.

At a point q of the band the jump is J_q = [N1_q, -N2_q] (x) I_3 and the mean flux is
F_q = [T1_q, T2_q] / 2 (T = sigma(N) n, both bodies' tractions on body 1's normal), over the 16
nodes of the two cells, 48 node dofs. The stiffness of the band,

    K = sum_q J_q^T Pen_q J_q - theta (F_q^T W_q J_q + J_q^T W_q^T F_q),

written per point as M_q + M_q^T with M_q[A, (b, j)] = X_q[A, j] n_q[b], where
n_q = (N1_q, -N2_q) and X_q = n_q (x) Pen_q / 2 - theta F_q^T W_q (48 x 3; Pen_q is symmetric):
an outer product of a 144-vector and a 16-vector. The points are stored grouped by cell pair, so
each pair's sum is one small matrix product (points x 144)^T (points x 16); the (48 x 48)
sums are assembled on the cells' nodes and mapped once by the restricted node-dof maps onto the
contact dofs (D^T K D, D the two maps stacked). The sparse route (J^T Pen J and F^T W J as
products of (3q x m) operators) did the same sums on every nonzero of every point's rows, with
the hanging-node constraints already applied: two to three times the work of the pair sums.

Operators applied to a vector of contact dofs (``jump @ x``, ``flux @ x``) read the cells' node
values once; the sparse (3q x m) matrices are built only when asked for (``tocsr``).
"""

from __future__ import annotations

import functools
import sys
import weakref
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .assembly_blocks import assemble_blocks
from .step_boundary import CellBlocks, point_matrix

__all__ = ["PairBlocks", "PairOperator", "RecentRegions"]

#: dofs per node
_D = 3

#: a band of at least this many points sums its pairs on two threads where a core is free
THREADED_POINTS = 4000

#: points per pass of the NumPy route's band sums (whole pairs; about 1.7 kB of products a point)
BAND_CHUNK_POINTS = 1024

#: /proc/stat's idle time at this module's last look (solver.fem.linalg.free_threads)
_IDLE_SAMPLE: list = [None]


def compiled() -> bool:
    """Whether the compiled kernels are used: where numba is already loaded (a run whose K0 is
    factored by the multifrontal Cholesky, every large one). A small run on SuperLU keeps the
    NumPy route: importing numba and LLVM for it would add about 100 MB to its peak."""
    return "numba" in sys.modules


@dataclass
class PairBlocks:
    """Per-point blocks of a band between body 1's and body 2's grids, the points stored grouped
    by cell pair: stored point k is the caller's point ``order[k]``, the points of pair p are
    stored at ``bounds[p]:bounds[p + 1]``. ``pair_nodes`` (pairs, 16) holds each pair's nodes:
    body 1's eight, then body 2's offset by body 1's node count, in one stacked node numbering
    whose dofs ``dof_map`` (3 (N1 + N2), m) maps from the contact dofs.

    Per-point arguments (coefficients, values, tensors) are given in the caller's order; the
    rows of :meth:`rows` are in the stored order, which :meth:`vector` and :meth:`outer` take."""

    order: np.ndarray  # (q,)
    bounds: np.ndarray  # (pairs + 1,)
    pair_nodes: np.ndarray  # (pairs, 16)
    shape: np.ndarray  # (q, 16) N1_q, then -N2_q (stored order)
    _traction: np.ndarray | None  # (q, 3, 48) the mean flux F_q (stored order); None: released
    dof_map: sp.csr_matrix  # (3 (N1 + N2), m)
    #: () -> (t1, t2): both bodies' traction blocks again, in the caller's order (None: kept always)
    _rebuild: object = field(default=None, repr=False)
    _weights: tuple = (0.5, 0.5)
    #: the caller whose latest blocks keep their flux (a contact): :func:`_hold`
    _family: object = field(default=None, repr=False)

    @classmethod
    def between(cls, blocks1: CellBlocks, blocks2: CellBlocks, map1: sp.csr_matrix, map2: sp.csr_matrix,
                n_nodes1: int, flux_weights: tuple[float, float] = (0.5, 0.5), rebuild=None,
                family=None) -> "PairBlocks":
        """The blocks of points whose cells and operators on body 1 and body 2 are ``blocks1`` and
        ``blocks2`` (the same points, tractions on the same normals), mapped by each body's
        restricted node-dof map (3 N_i x m; ``n_nodes1`` = N1); the flux is
        w1 t1 + w2 t2 with ``flux_weights`` (w1, w2).

        ``rebuild`` (() -> (t1, t2), both bodies' traction blocks computed again) and ``family``
        (the caller, a contact): only the latest blocks of a family keep their flux blocks
        (1152 bytes a point, most of a trial region's memory); older ones release them and
        build them again with ``rebuild`` if asked (the same numbers)."""
        key = blocks1.cells.astype(np.int64) * (int(blocks2.cells.max(initial=0)) + 1) + blocks2.cells
        order = np.argsort(key, kind="stable")
        key = key[order]
        first = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
        nodes = np.concatenate([blocks1.cell_nodes[order[first]], blocks2.cell_nodes[order[first]] + n_nodes1],
                               axis=1).astype(np.int64)
        shape = np.concatenate([blocks1.displacement[order, 0, ::_D], -blocks2.displacement[order, 0, ::_D]], axis=1)
        weights = tuple(float(w) for w in flux_weights)
        _release(family, keep=KEPT_FLUX_BLOCKS - 1)  # before these are built: the new blocks are the latest
        traction = _gathered_traction(blocks1.traction, blocks2.traction, weights, order)
        blocks = cls(order, np.r_[first, len(order)], nodes, shape, traction, sp.vstack([map1, map2], format="csr"),
                     rebuild, weights, family)
        _hold(blocks)
        return blocks

    @property
    def traction(self) -> np.ndarray:
        """(q, 3, 48) the mean flux F_q (stored order), built again if it was released."""
        if self._traction is None:
            self._traction = _gathered_traction(*self._rebuild(), self._weights, self.order)
        _hold(self)
        return self._traction

    # ------------------------------------------------------------------ operators

    @property
    def n_points(self) -> int:
        return len(self.order)

    @functools.cached_property
    def point_dofs(self) -> np.ndarray:
        """(q, 48) stacked node-dof indices of each stored point's two cells."""
        nodes = np.repeat(self.pair_nodes, np.diff(self.bounds), axis=0)
        return (_D * nodes[:, :, None] + np.arange(_D)).reshape(len(nodes), -1)

    def _caller(self, stored: np.ndarray) -> np.ndarray:
        out = np.empty_like(stored)
        out[self.order] = stored
        return out

    def node_values(self, x: np.ndarray) -> np.ndarray:
        """(q, 48) the two cells' node dofs at each stored point for contact dof values x."""
        return np.asarray(self.dof_map @ x)[self.point_dofs]

    def jump_at(self, x: np.ndarray) -> np.ndarray:
        """(q, 3) u_h1 - u_h2 at the points (caller's order)."""
        v = self.node_values(x).reshape(self.n_points, -1, _D)
        return self._caller(np.einsum("qa,qai->qi", self.shape, v))

    def flux_at(self, x: np.ndarray) -> np.ndarray:
        """(q, 3) the mean flux at the points (caller's order)."""
        return self._caller(np.einsum("qic,qc->qi", self.traction, self.node_values(x)))

    @property
    def jump(self) -> "PairOperator":
        """The jump as an operator (a new one each time: the blocks keep no reference to their
        operators, so no reference cycle holds their arrays until a garbage collection)."""
        return PairOperator(self, "jump")

    @property
    def flux(self) -> "PairOperator":
        """The mean flux as an operator (a new one each time, as :attr:`jump`)."""
        return PairOperator(self, "flux")

    def rows(self, jump_coefficients: np.ndarray, flux_coefficients: np.ndarray | None = None) -> np.ndarray:
        """(q, 48) per-point rows (stored order) of the functional c_q . J_q + d_q . F_q, the
        coefficients (q, 3) in the caller's order."""
        return self._stored_rows(np.asarray(jump_coefficients)[self.order],
                                 None if flux_coefficients is None else np.asarray(flux_coefficients)[self.order])

    def _stored_rows(self, c: np.ndarray, d: np.ndarray | None) -> np.ndarray:
        out = (self.shape[:, :, None] * c[:, None, :]).reshape(self.n_points, -1)
        if d is not None:
            out += np.einsum("qi,qic->qc", d, self.traction)
        return out

    # ------------------------------------------------------------------ terms on the contact dofs

    def vector(self, rows: np.ndarray, values: np.ndarray | None = None) -> np.ndarray:
        """(m,) sum_q rows_q (times values_q, caller's order) mapped onto the contact dofs."""
        per_dof = rows if values is None else rows * np.asarray(values)[self.order][:, None]
        nodal = np.bincount(self.point_dofs.ravel(), per_dof.ravel(), minlength=self.dof_map.shape[0])
        return np.asarray(self.dof_map.T @ nodal).ravel()

    def outer(self, left: np.ndarray, right: np.ndarray, weights: np.ndarray | None = None) -> sp.csr_matrix:
        """(m, m) sum_q w_q left_q right_q^T of per-point rows (q, 48, stored order), weights w
        (q,) in the caller's order (1 without; points of weight 0 are skipped)."""
        if not compiled():
            if weights is not None:
                left = left * np.asarray(weights)[self.order][:, None]
            return self._assembled(self._pair_sums(left, right))
        from ._pair_kernels import outer_pair_sums

        w = np.ones(self.n_points) if weights is None else np.ascontiguousarray(np.asarray(weights, dtype=float)[self.order])
        out = np.empty((len(self.pair_nodes), left.shape[1], right.shape[1]))
        self._over_pairs(outer_pair_sums, (np.ascontiguousarray(left, dtype=float),
                                           np.ascontiguousarray(right, dtype=float), w), out)
        return self._assembled(out)

    def band_terms(self, pen: np.ndarray, wp: np.ndarray, target: np.ndarray,
                   consistency: float) -> tuple[sp.csr_matrix, np.ndarray]:
        """Stiffness (m, m) and load (m,) of the band with per-point layer ``pen`` and consistency
        weights ``wp`` (q, 3, 3, quadrature weights included) and prescribed jump ``target``
        (q, 3): sum_q J^T pen (J - a) - theta (F^T wp (J - a) + J^T wp^T F)."""
        q, nodes = self.n_points, self.shape.shape[1]
        pen, wp = np.ascontiguousarray(pen, dtype=float), np.ascontiguousarray(wp, dtype=float)
        if compiled():
            from ._pair_kernels import band_pair_sums

            k_pairs = np.empty((len(self.pair_nodes), _D * nodes, _D * nodes))
            self._over_pairs(band_pair_sums, (self.shape, self.traction, pen, wp, self.order, float(consistency)),
                             k_pairs)
            k = self._assembled(k_pairs)
            pen, wp = pen[self.order], wp[self.order]
        else:
            pen, wp = pen[self.order], wp[self.order]
            k = self._assembled(self._band_pair_sums(pen, wp, float(consistency)))
        a = np.asarray(target, dtype=float).reshape(q, _D)[self.order]
        load = self._stored_rows(np.einsum("qij,qj->qi", pen, a), -consistency * np.einsum("qij,qj->qi", wp, a))
        return k, self.vector(load)

    def _band_pair_sums(self, pen: np.ndarray, wp: np.ndarray, consistency: float) -> np.ndarray:
        """(pairs, 48, 48) the band's M_p + M_p^T of each pair (the NumPy route; ``pen``, ``wp`` in
        the stored order), a run of whole pairs of about BAND_CHUNK_POINTS points at a time: the
        per-point products (X_q, some 1.7 kB a point) then never exist for the whole band at
        once, nor leave the processor's cache. Each pair's sum is the same product on the same
        numbers as in one pass."""
        q, nodes = self.n_points, self.shape.shape[1]
        out = np.empty((len(self.pair_nodes), _D * nodes, _D * nodes))
        for first, last in _runs(self.bounds, BAND_CHUNK_POINTS):
            lo, hi = self.bounds[first], self.bounds[last]
            x = 0.5 * self.shape[lo:hi, :, None, None] * pen[lo:hi, None, :, :]  # (n, 16, 3, 3): n (x) pen / 2
            # (n, 48, 3): T^T wp as batched products (einsum's generic loop is some 7x slower here)
            x = x.reshape(hi - lo, -1, _D) - consistency * np.matmul(self.traction[lo:hi].transpose(0, 2, 1), wp[lo:hi])
            m = _run_sums(x.reshape(hi - lo, -1), self.shape[lo:hi], self.bounds[first:last + 1] - lo)
            m = m.reshape(len(m), -1, _D, nodes).transpose(0, 1, 3, 2).reshape(len(m), nodes * _D, nodes * _D)
            np.add(m, m.transpose(0, 2, 1), out=out[first:last])
        return out

    def _pair_sums(self, left: np.ndarray, right: np.ndarray) -> np.ndarray:
        """(pairs, l, r) sum over each pair's points of outer(left_q, right_q) (stored order):
        one matrix product per pair over its run of points (the NumPy route)."""
        return _run_sums(left, right, self.bounds)

    def _over_pairs(self, kernel, args: tuple, out: np.ndarray) -> None:
        """``kernel(*args, bounds, first, last, out)`` over all pairs: on two threads (two ranges
        of about equal points) when the machine has had a core idle since the last look
        (:func:`solver.fem.linalg.free_threads`) and there are points enough, else on this one."""
        from .linalg import free_threads

        pairs = len(self.pair_nodes)
        threads = min(free_threads(_IDLE_SAMPLE), 2) if self.n_points >= THREADED_POINTS else 1
        if threads < 2 or pairs < 2:
            kernel(*args, self.bounds, 0, pairs, out)
            return
        from concurrent.futures import ThreadPoolExecutor

        middle = int(np.clip(np.searchsorted(self.bounds, self.n_points // 2), 1, pairs - 1))
        with ThreadPoolExecutor(2) as pool:
            for job in [pool.submit(kernel, *args, self.bounds, lo, hi, out) for lo, hi in ((0, middle), (middle, pairs))]:
                job.result()

    def _assembled(self, k_pairs: np.ndarray) -> sp.csr_matrix:
        """(m, m) D^T K D of per-pair (48 x 48) matrices over the pairs' stacked node dofs (only
        the nodes the pairs touch are assembled)."""
        used, local = np.unique(self.pair_nodes, return_inverse=True)
        k = assemble_blocks(local.reshape(self.pair_nodes.shape), k_pairs, len(used))
        d = self.dof_map[(_D * used[:, None] + np.arange(_D)).ravel()]
        return (d.T @ k @ d).tocsr()

    def matrix(self, kind: str) -> sp.csr_matrix:
        """(3q, m) sparse operator of the jump or the flux, rows in the caller's order."""
        if kind == "jump":
            blocks = np.zeros((self.n_points, _D, _D * self.shape.shape[1]))
            for k in range(_D):
                blocks[:, k, k::_D] = self.shape
        else:
            blocks = self.traction
        stored = point_matrix(blocks, self.point_dofs, self.dof_map)
        where = np.empty(self.n_points, dtype=np.int64)
        where[self.order] = np.arange(self.n_points)
        return stored[(_D * where[:, None] + np.arange(_D)).ravel()].tocsr()


def _gathered_traction(t1: np.ndarray, t2: np.ndarray, weights: tuple[float, float], order: np.ndarray) -> np.ndarray:
    """(q, 3, 48) [w1 t1, w2 t2] of both bodies' traction blocks (q, 3, 24) in the stored order."""
    t1, t2 = (np.ascontiguousarray(t, dtype=float) for t in (t1, t2))
    w1, w2 = weights
    traction = np.empty((len(order), t1.shape[1], t1.shape[2] + t2.shape[2]))
    if t1.shape == t2.shape and compiled():
        from ._pair_kernels import gather_weighted_traction

        gather_weighted_traction(t1, t2, w1, w2, order, traction)
    else:  # in passes: the gathered copies stay small
        for start in range(0, len(order), GATHER_POINTS):
            rows = order[start:start + GATHER_POINTS]
            traction[start:start + len(rows), :, :t1.shape[2]] = w1 * t1[rows]
            traction[start:start + len(rows), :, t1.shape[2]:] = w2 * t2[rows]
    return traction


#: points per pass of the NumPy route's gathering of the flux blocks
GATHER_POINTS = 4096


#: per family (a contact, by identity; the entry goes with it): its blocks that hold their flux
#: blocks, oldest first (weak references)
_HOLDING: dict = {}
#: blocks of a family that keep their flux blocks: the latest (the region being judged)
KEPT_FLUX_BLOCKS = 1


def _hold(blocks: PairBlocks) -> None:
    """Record ``blocks`` as its family's latest user of its flux blocks and release those of the
    family's older blocks beyond KEPT_FLUX_BLOCKS (blocks without a family or a rebuild keep them)."""
    if blocks._family is None or blocks._rebuild is None:
        return
    key = id(blocks._family)
    if key not in _HOLDING:
        try:
            weakref.finalize(blocks._family, _HOLDING.pop, key, None)
        except TypeError:  # a family that takes no weak reference: nothing is released
            return
        _HOLDING[key] = []
    held = _HOLDING[key]
    held[:] = [r for r in held if r() is not None and r() is not blocks] + [weakref.ref(blocks)]
    _release(blocks._family, KEPT_FLUX_BLOCKS)


def _release(family, keep: int) -> None:
    """Release the flux blocks of all but the latest ``keep`` blocks of ``family`` that hold them."""
    held = _HOLDING.get(id(family)) if family is not None else None
    while held and len(held) > keep:
        older = held.pop(0)()
        if older is not None:
            older._traction = None


def _run_sums(left: np.ndarray, right: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """(runs, l, r) sum over each run of rows bounds[p]:bounds[p + 1] of outer(left_q, right_q):
    one matrix product per run."""
    out = np.empty((len(bounds) - 1, left.shape[1], right.shape[1]))
    for p, (lo, hi) in enumerate(zip(bounds[:-1], bounds[1:])):
        np.matmul(left[lo:hi].T, right[lo:hi], out=out[p])
    return out


def _runs(bounds: np.ndarray, points: int):
    """(first, last) ranges of whole runs (run p holds rows bounds[p]:bounds[p + 1]) of about
    ``points`` rows each (a longer run alone)."""
    first, runs = 0, len(bounds) - 1
    while first < runs:
        last = int(np.searchsorted(bounds, bounds[first] + points, side="right")) - 1
        last = min(max(last, first + 1), runs)
        yield first, last
        first = last


class PairOperator:
    """The jump or the mean flux of :class:`PairBlocks` as an operator on contact dof vectors
    (``op @ x`` -> (3q,), ``op @ X`` for (m, k) arrays); anything else a sparse matrix offers is
    delegated to the sparse (3q, m) matrix, built on first use."""

    def __init__(self, blocks: PairBlocks, kind: str):
        self.blocks, self.kind = blocks, kind

    @property
    def shape(self) -> tuple[int, int]:
        return (_D * self.blocks.n_points, self.blocks.dof_map.shape[1])

    def __matmul__(self, x):
        x = np.asarray(x, dtype=float)
        at = self.blocks.jump_at if self.kind == "jump" else self.blocks.flux_at
        if x.ndim == 1:
            return at(x).ravel()
        return np.stack([at(col).ravel() for col in x.T], axis=1)

    @functools.cached_property
    def _matrix(self) -> sp.csr_matrix:
        return self.blocks.matrix(self.kind)

    def tocsr(self) -> sp.csr_matrix:
        return self._matrix

    def __getattr__(self, name):
        if name.startswith("__") or name in ("blocks", "kind"):
            raise AttributeError(name)
        return getattr(self._matrix, name)


class RecentRegions:
    """What was built for the last ``keep`` contact regions, by a key that fixes the region (its
    quadrature points and their blocks do not depend on the stick zone or the load, so a region
    search that starts where the last one ended finds them here)."""

    def __init__(self, keep: int = 2):
        self.keep, self._items = keep, {}

    def get(self, key, build):
        """The value kept for ``key``, else ``build()`` kept in place of the oldest."""
        value = self._items.pop(key) if key in self._items else build()
        self._items[key] = value
        while len(self._items) > self.keep:
            del self._items[next(iter(self._items))]
        return value
