"""The step boundary method (thesis chapter 3) in its thin-band limit.

Trial and test fields u = H u_h + (I - H) a, v = H v_h with the approximate step H(phi) of
eq. 3-4 over a band of width delta. Integrating the band energy across its thickness and letting
delta -> 0 (docs/formulation.md) leaves boundary integrals on the exact edge:

    a(v, u) + sum_q w_q [ (P v).A_n (P w) 4/(3 delta)  - theta ((sigma(v) n).P w + (sigma(u) n).P v) ]

with w = u_h - a, A_n = (lambda + 2 mu) n n^T + mu (I - n n^T) the acoustic tensor of the exact
normal n, P the projector on the constrained components (I fixed, e_x e_x^T for a prescribed x
only, n n^T sliding) and theta = 1/2 (the band's value; theta = 1 is symmetric Nitsche). The
terms with a go to the right-hand side: the F_a load of eq. 3-30.

Everything here acts on sparse *point operators*: a displacement operator E_u (2q x ndof) and
a traction operator E_t (2q x ndof) giving u_h and sigma(u_h) n at q quadrature points. For one
body they come from its own grid; for the contact band of the next issues E_u is the jump
between two grids, so the same functions couple two bodies.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = [
    "step_function",
    "step_derivative",
    "band_integrals",
    "PENALTY_FACTOR",
    "THESIS_CONSISTENCY",
    "NITSCHE_CONSISTENCY",
    "DEFAULT_BAND_FRACTION",
    "DEFAULT_CONSISTENCY",
    "acoustic_tensor",
    "projector",
    "BoundaryPoints",
    "CellBlocks",
    "point_matrix",
    "block_diagonal",
    "thin_band_terms",
    "band_tensors",
    "thin_band_traction",
]

# int_0^delta H'^2 dphi = 4 / (3 delta): the layer stiffness factor.
PENALTY_FACTOR = 4.0 / 3.0
# int_0^delta H H' dphi = 1/2: weight of the consistency terms the band gives.
THESIS_CONSISTENCY = 0.5
NITSCHE_CONSISTENCY = 1.0
# delta = DEFAULT_BAND_FRACTION * local size (measured: docs/formulation.md, "Choosing delta").
DEFAULT_BAND_FRACTION = 0.25
# The solver's default weight: the fully consistent one (patch test exact, O(h^2) displacements);
# THESIS_CONSISTENCY is kept as an option (its O(delta) inconsistency is measured in the docs).
DEFAULT_CONSISTENCY = NITSCHE_CONSISTENCY


def step_function(phi: np.ndarray, delta: float) -> np.ndarray:
    """H(phi) of eq. 3-4: 0 outside, (phi/delta)(2 - phi/delta) in the band, 1 beyond it."""
    s = np.clip(np.asarray(phi, dtype=float) / delta, 0.0, 1.0)
    return s * (2.0 - s)


def step_derivative(phi: np.ndarray, delta: float) -> np.ndarray:
    """dH/dphi = (2/delta)(1 - phi/delta) in the band, 0 elsewhere."""
    phi = np.asarray(phi, dtype=float)
    inside = (phi >= 0.0) & (phi <= delta)
    return np.where(inside, 2.0 / delta * (1.0 - phi / delta), 0.0)


def band_integrals(delta: float) -> dict[str, float]:
    """Closed forms of the band integrals across its thickness used by the thin-band limit."""
    return {"H2": 8.0 * delta / 15.0, "HdH": 0.5, "dH2": 4.0 / (3.0 * delta)}


def acoustic_tensor(normals: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """A_n (q, d, d) = sym(n x .) : C : sym(n x .) = (lambda + 2 mu) n n^T + mu (I - n n^T)."""
    nn = normals[:, :, None] * normals[:, None, :]
    return (lam + mu) * nn + mu * np.eye(normals.shape[1])[None]


def projector(kind: str, normals: np.ndarray, free: tuple[bool, ...] | None = None) -> np.ndarray:
    """P (q, d, d) on the constrained components: "fixed"/"displacement" in global axes (a
    component with free[i] True is not constrained), "sliding" along the exact local normal."""
    q, dim = normals.shape
    if kind == "sliding":
        return normals[:, :, None] * normals[:, None, :]
    if kind in ("fixed", "displacement"):
        d = np.array([0.0 if f else 1.0 for f in (free or (False,) * dim)])
        return np.broadcast_to(np.diag(d), (q, dim, dim)).copy()
    raise ValueError(f"unknown essential condition kind {kind!r}")


def point_matrix(blocks: np.ndarray, cell_dofs: np.ndarray, dof_map: sp.csr_matrix) -> sp.csr_matrix:
    """Sparse (q r, columns of ``dof_map``) operator of per-point blocks (q, r, cell dofs) over
    the node dofs ``cell_dofs`` (q, cell dofs) of each point's cell, mapped by ``dof_map``
    (node dofs -> global or restricted dofs). Every row holds its cell's dofs: CSR directly."""
    q, r, c = blocks.shape
    cols = np.broadcast_to(cell_dofs[:, None, :], blocks.shape).ravel().astype(np.int64)
    m = sp.csr_matrix((blocks.ravel(), cols, np.arange(0, q * r * c + 1, c, dtype=np.int64)),
                      shape=(q * r, dof_map.shape[0]))
    return (m @ dof_map).tocsr()


#: points per batch of the cell-block band terms: (batch, p d, p d) temporaries of ~9 MB in 3D
_BAND_BATCH = 2048
#: from this many points per cell on average the band's cell matrices are formed as matrix
#: products over each cell's points (one Python step per cell), below it as batched sums of
#: per-point matrices
_CELL_PRODUCTS = 8


@dataclass
class CellBlocks:
    """Point operators kept as one block per point over the dofs of the point's cell (before
    the hanging-node constraints): u_h(x_q) = N_q u_c and sigma(u_h) n (x_q) = T_q u_c with
    u_c the cell's node dofs of D u (D the body's node-dof map). The band terms of a
    single-body condition are summed over each cell's points into cell matrices and assembled
    once, as the volume stiffness is, instead of through sparse products of (d q, ndof)
    operators (3D problems reach a million dofs)."""

    cells: np.ndarray  # (q,) cell holding each point
    cell_nodes: np.ndarray  # (q, p) the nodes of that cell
    displacement: np.ndarray  # (q, d, p d) N_q
    traction: np.ndarray | None  # (q, d, p d) T_q (None: loads only)
    node_dof_map: sp.csr_matrix  # (d N_nodes, ndof)

    @property
    def dim(self) -> int:
        return self.displacement.shape[1]

    @functools.cached_property
    def cell_dofs(self) -> np.ndarray:
        """(q, p d) node-dof indices of each point's cell, [x0, y0, (z0,) x1, ...]."""
        d = self.dim
        return (d * self.cell_nodes.astype(np.int64)[:, :, None] + np.arange(d)).reshape(len(self.cells), -1)

    def values(self, blocks: np.ndarray, u: np.ndarray) -> np.ndarray:
        """(q, d): ``blocks`` (N or T) applied to the global vector u."""
        nodal = self.node_dof_map @ np.asarray(u, dtype=float)
        return np.einsum("qdc,qc->qd", blocks, nodal[self.cell_dofs])

    def matrix(self, blocks: np.ndarray) -> sp.csr_matrix:
        """(d q, ndof) sparse operator of ``blocks``."""
        return point_matrix(blocks, self.cell_dofs, self.node_dof_map)

    def _to_dofs(self, per_dof: np.ndarray) -> np.ndarray:
        """(ndof,) of per-point values (q, p d) on the cells' node dofs, summed and mapped by D^T."""
        nodal = np.bincount(self.cell_dofs.ravel(), per_dof.ravel(), minlength=self.node_dof_map.shape[0])
        return np.asarray(self.node_dof_map.T @ nodal).ravel()

    def load(self, vectors: np.ndarray) -> np.ndarray:
        """(ndof,): sum_q N_q^T vectors_q (vectors (q, d), weights included)."""
        return self._to_dofs(np.einsum("qdc,qd->qc", self.displacement, vectors))

    def band_terms(self, pen: np.ndarray, wp: np.ndarray, target: np.ndarray,
                   consistency: float) -> tuple[sp.csr_matrix, np.ndarray]:
        """Stiffness and load of the thin band with per-point layer ``pen`` (q, d, d) and
        consistency weights ``wp`` (q, d, d): sum_q N^T pen N - theta (T^T wp N + N^T wp T),
        summed per cell, assembled on the cells' nodes, mapped by D^T (.) D."""
        from .assembly_blocks import assemble_blocks

        n_blocks, t_blocks = self.displacement, self.traction
        q, d, c = n_blocks.shape
        order = np.argsort(self.cells, kind="stable")
        cells_sorted = self.cells[order]
        first = np.flatnonzero(np.r_[True, cells_sorted[1:] != cells_sorted[:-1]])
        if q >= _CELL_PRODUCTS * len(first):
            k_cells = _cell_products(n_blocks, t_blocks, pen, wp, consistency, order, first)
        else:
            k_cells = _point_sums(n_blocks, t_blocks, pen, wp, consistency, order, first, cells_sorted)
        a = np.asarray(target, dtype=float).reshape(len(self.cells), -1)
        vectors = np.einsum("qij,qj->qi", pen, a)
        per_dof = np.einsum("qdc,qd->qc", n_blocks, vectors) - consistency * np.einsum(
            "qdc,qd->qc", t_blocks, np.einsum("qij,qj->qi", wp, a))
        d_map = self.node_dof_map
        k_nodes = assemble_blocks(self.cell_nodes[order[first]], k_cells, d_map.shape[0] // self.dim)
        return (d_map.T @ k_nodes @ d_map).tocsr(), self._to_dofs(per_dof)


def _cell_products(n_blocks, t_blocks, pen, wp, consistency, order, first) -> np.ndarray:
    """(cells, p d, p d) band stiffness of each cell from matrix products over its points
    (``order`` sorts the points by cell, ``first`` is where each cell's run starts in that order).
    N_q is shape_q (x) I_d, so N^T pen N = sum_q (s s^T)_q (x) pen_q: one product of the points'
    (s s^T) (p^2 columns) with their pen (d^2), and T^T wp N = sum_q (T^T wp)_q (x) s_q: one product
    of the points' T^T wp (p d x d) with their s (p); some 3.5 times fewer operations in 3D than
    N^T (pen N) and T^T (wp N) over the cells' stacked rows. Whole cells of about _BAND_BATCH
    points at a time."""
    q, d, c = n_blocks.shape
    p = c // d
    k_cells = np.empty((len(first), c, c))
    bounds = np.r_[first, q]
    cell = 0
    while cell < len(first):
        last = min(max(int(np.searchsorted(bounds, bounds[cell] + _BAND_BATCH, side="right")) - 1, cell + 1),
                   len(first))
        rows = order[bounds[cell]:bounds[last]]
        shape = n_blocks[rows, 0, ::d]  # (n, p): N_q is shape (x) I_d
        ss = (shape[:, :, None] * shape[:, None, :]).reshape(len(rows), p * p)
        tw = np.matmul(t_blocks[rows].transpose(0, 2, 1), wp[rows]).reshape(len(rows), c * d)  # T^T wp
        pen_rows = pen[rows].reshape(len(rows), d * d)
        runs = bounds[cell:last + 1] - bounds[cell]
        for k, (lo, hi) in enumerate(zip(runs[:-1], runs[1:])):
            nn = (ss[lo:hi].T @ pen_rows[lo:hi]).reshape(p, p, d, d).transpose(0, 2, 1, 3).reshape(c, c)
            cross = (tw[lo:hi].T @ shape[lo:hi]).reshape(c, d, p).transpose(0, 2, 1).reshape(c, c)
            k_cells[cell + k] = nn - consistency * (cross + cross.T)
        cell = last
    return k_cells


def _point_sums(n_blocks, t_blocks, pen, wp, consistency, order, first, cells_sorted) -> np.ndarray:
    """The same as :func:`_cell_products` as sums of per-point (p d, p d) matrices, batch by
    batch (fewer Python steps where cells hold few points each)."""
    q, d, c = n_blocks.shape
    shape = n_blocks[:, 0, ::d]  # (q, p): N_q is shape (x) I_d
    k_cells = np.zeros((len(first), c * c))
    for lo in range(0, q, _BAND_BATCH):
        idx = order[lo:lo + _BAND_BATCH]
        n_q = shape[idx]
        # N^T pen N = (n n^T) (x) pen
        k_q = (n_q[:, :, None, None, None] * n_q[:, None, None, :, None]
               * pen[idx][:, None, :, None, :]).reshape(len(idx), c, c)
        wn = (wp[idx][:, :, None, :] * n_q[:, None, :, None]).reshape(len(idx), d, c)  # wp N
        cross = np.swapaxes(t_blocks[idx], 1, 2) @ wn
        k_q -= consistency * (cross + np.swapaxes(cross, 1, 2))
        # the batch's runs of equal cells: their sums go to the run's cell (unique in a batch)
        run = cells_sorted[lo:lo + len(idx)]
        starts = np.flatnonzero(np.r_[True, run[1:] != run[:-1]])
        k_cells[np.searchsorted(first, lo + starts, side="right") - 1] += np.add.reduceat(
            k_q.reshape(len(idx), -1), starts, axis=0)
    return k_cells.reshape(-1, c, c)


@dataclass
class BoundaryPoints:
    """Quadrature points on an edge (a face in 3D) with their operators onto the global dof
    vector: sparse matrices, or per-point cell blocks (:class:`CellBlocks`) from which the
    matrices are built only when asked for."""

    points: np.ndarray  # (q, d)
    weights: np.ndarray  # (q,) ds (dA in 3D)
    normals: np.ndarray  # (q, d) exact outward normals of the body
    cell_size: np.ndarray  # (q,) local size setting delta (cell size, or less in a sliver)
    displacement_matrix: sp.csr_matrix | None = None  # (d q, ndof): u_h at the points, rows [x0, y0, (z0,) x1, ...]
    traction_matrix: sp.csr_matrix | None = None  # (d q, ndof): sigma(u_h) n at the points
    blocks: CellBlocks | None = None

    def __post_init__(self) -> None:
        if self.blocks is None and (self.displacement_matrix is None or self.traction_matrix is None):
            raise ValueError("BoundaryPoints needs its operators: sparse matrices or cell blocks")

    @property
    def displacement(self) -> sp.csr_matrix:
        """(d q, ndof) sparse operator of u_h at the points (built from the blocks on first use)."""
        if self.displacement_matrix is None:
            self.displacement_matrix = self.blocks.matrix(self.blocks.displacement)
        return self.displacement_matrix

    @property
    def traction(self) -> sp.csr_matrix:
        """(d q, ndof) sparse operator of sigma(u_h) n at the points."""
        if self.traction_matrix is None:
            self.traction_matrix = self.blocks.matrix(self._traction_blocks())
        return self.traction_matrix

    def _traction_blocks(self) -> np.ndarray:
        if self.blocks.traction is None:
            raise ValueError("these boundary points were made for loads only (no traction operator)")
        return self.blocks.traction

    def displacement_at(self, u: np.ndarray) -> np.ndarray:
        """(q, d) u_h at the points."""
        if self.blocks is not None:
            return self.blocks.values(self.blocks.displacement, u)
        return (self.displacement_matrix @ u).reshape(len(self.points), -1)

    def traction_at(self, u: np.ndarray) -> np.ndarray:
        """(q, d) sigma(u_h) n at the points."""
        if self.blocks is not None:
            return self.blocks.values(self._traction_blocks(), u)
        return (self.traction_matrix @ u).reshape(len(self.points), -1)

    def load(self, vectors: np.ndarray) -> np.ndarray:
        """(ndof,) consistent load sum_q N_q^T vectors_q of point forces (q, d)."""
        if self.blocks is not None:
            return self.blocks.load(vectors)
        return np.asarray(self.displacement_matrix.T @ np.asarray(vectors, dtype=float).ravel()).ravel()


def block_diagonal(blocks: np.ndarray) -> sp.csr_matrix:
    """Sparse block-diagonal matrix of q (d, d) blocks."""
    q, d = blocks.shape[:2]
    return sp.bsr_matrix((np.ascontiguousarray(blocks), np.arange(q), np.arange(q + 1)), shape=(d * q, d * q)).tocsr()


def band_tensors(bp: BoundaryPoints, proj: np.ndarray, lam: float, mu: float,
                 band_fraction: float = DEFAULT_BAND_FRACTION) -> tuple[np.ndarray, np.ndarray]:
    """The band's per-point tensors (q, d, d), quadrature weights included: the layer
    w 4/(3 delta) P A_n P (delta = band_fraction times the local size) and the consistency
    weight w P."""
    delta = band_fraction * bp.cell_size
    pen = (PENALTY_FACTOR / delta * bp.weights)[:, None, None] * (proj @ acoustic_tensor(bp.normals, lam, mu) @ proj)
    return pen, bp.weights[:, None, None] * proj


def thin_band_terms(
    bp: BoundaryPoints,
    proj: np.ndarray,
    target: np.ndarray,
    lam: float,
    mu: float,
    band_fraction: float = DEFAULT_BAND_FRACTION,
    consistency: float = DEFAULT_CONSISTENCY,
    jump: sp.csr_matrix | None = None,
) -> tuple[sp.csr_matrix, np.ndarray]:
    """Stiffness (ndof, ndof) and F_a load (ndof,) of the thin-band step boundary terms.

    ``target`` (q, d) is the prescribed displacement a at each point (only P a matters);
    ``jump`` replaces the displacement operator (contact: u_h1 - u_h2), default bp.displacement.
    """
    pen, wp = band_tensors(bp, proj, lam, mu, band_fraction)
    if jump is None and bp.blocks is not None:
        return bp.blocks.band_terms(pen, wp, target, consistency)
    eu = bp.displacement if jump is None else jump
    et = bp.traction
    k_pen = block_diagonal(pen)
    k_con = block_diagonal(wp)
    cross = et.T @ k_con @ eu
    k = eu.T @ k_pen @ eu - consistency * (cross + cross.T)
    a = np.asarray(target, dtype=float).reshape(-1)
    f = eu.T @ (k_pen @ a) - consistency * (et.T @ (k_con @ a))
    return k.tocsr(), np.asarray(f).ravel()


def thin_band_traction(
    bp: BoundaryPoints,
    proj: np.ndarray,
    target: np.ndarray,
    lam: float,
    mu: float,
    u: np.ndarray,
    band_fraction: float = DEFAULT_BAND_FRACTION,
    consistency: float = DEFAULT_CONSISTENCY,
    jump: sp.csr_matrix | None = None,
) -> np.ndarray:
    """Traction (q, 2) the condition exerts on the body at each point: the layer's
    -4/(3 delta) P A_n P (u_h - a) plus the consistency part theta P sigma(u_h) n. Integrated
    with bp.weights it is the reaction; by the translation invariance of the bulk form the
    reactions and the applied loads balance exactly."""
    d = bp.normals.shape[1]
    uh = bp.displacement_at(u) if jump is None else (jump @ u).reshape(-1, d)
    w = uh - np.asarray(target, dtype=float).reshape(-1, d)
    tn = bp.traction_at(u)
    delta = band_fraction * bp.cell_size
    layer = (PENALTY_FACTOR / delta)[:, None, None] * (proj @ acoustic_tensor(bp.normals, lam, mu) @ proj)
    return -np.einsum("qij,qj->qi", layer, w) + consistency * np.einsum("qij,qj->qi", proj, tn)
