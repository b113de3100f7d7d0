"""Cell aggregation for the cut cells of the quadtree (2D) and the octree (3D), after Badia,
Verdugo and Martin, "The aggregated unfitted finite element method for elliptic problems", CMAME
336 (2018) 533-553. One implementation for both: the dimension comes from the grid's nodes (d
coordinates), the cell type from its cell table (2^d corners), and the shape functions are the
multilinear ones of that corner order (those of :mod:`solver.fem.elements`: the bilinear square,
the trilinear cube; evaluated here from the corner signs, since the quadtree aggregates its cells
with this module and :mod:`solver.fem.elements` imports the grids). A "cube" below is the square
cell in 2D, a "face" an edge.

A cut cell whose inside part is a tiny share of the cube (a sliver left where a face lies a
hair inside a grid plane, a corner clipped by a curved face) gives its nodes almost no stiffness;
a node all of whose cells are like that is ill supported: the stiffness is nearly singular there,
and the boundary terms of a face in such a cell (sized by the sliver's thickness) can outweigh
it and make the matrix indefinite. Aggregation removes those nodes' unknowns:

- a cell is *well supported* when its inside volume is at least ``threshold`` of its cube;
- every other cell joins the *aggregate* of a well-supported *root* cell, grown layer by layer
  through cells that share an unknown; cells wholly outside (kept near the surface) receive a
  root but pass none on, so the aggregates follow the material and do not jump a gap that no
  cell with material bridges;
- a free node is kept when a well-supported cell depends on it (through the hanging-node
  constraints too); the others are *extended*: their displacement is the root cell's trilinear
  field (bilinear in 2D) evaluated (extrapolated) at the node, u_f = sum_a N_a^root(x_f) u_a.

The extension is exact for linear fields (a multilinear cell reproduces them everywhere), so the
patch test is kept, and it composes with the hanging-node constraint T (nodes x free nodes) of
:mod:`solver.fem.grid` / :mod:`solver.fem.octree` as T' = T E, with E (free nodes x kept
nodes). A node whose cells reach no well-supported cell at all (a piece of the body thinner
than ``threshold`` of a cell everywhere) keeps its unknown.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["AGGREGATION_THRESHOLD", "Aggregation", "ExtendableNodes", "aggregate", "aggregate_thickness"]

#: inside volume share of its cube below which a cell joins an aggregate (see docs/solids.md,
#: "Ill-supported cut cells: aggregation", and docs/formulation.md, "Aggregated cut cells", for
#: the measurements behind it)
AGGREGATION_THRESHOLD = 0.05


class ExtendableNodes:
    """What the quadtree (solver.fem.grid.Grid) and the octree (solver.fem.octree.Octree) share
    for their unknowns: ``nodes``, the ``free_nodes`` that carry one and the ``constraint`` T
    (nodes x free nodes: hanging nodes from their parents), extended by an aggregation."""

    #: (m,) root cell of each cell's aggregate once :meth:`aggregate_cells` ran (None: not aggregated)
    root: np.ndarray | None = None

    def aggregate_cells(self, fraction: np.ndarray, threshold: float = AGGREGATION_THRESHOLD) -> None:
        """Aggregate the cells whose inside part is less than ``threshold`` of their cube
        (``fraction`` (m,)): the ill-supported nodes' unknowns given up (:meth:`extend`), the
        aggregates' roots kept in ``root``. Called while the grid is built, never after."""
        aggregation = aggregate(self, fraction, threshold)
        self.extend(aggregation.extension, aggregation.kept)
        self.root = aggregation.root

    @property
    def cell_roots(self) -> np.ndarray:
        """(m,) ``root``, or -1 for every cell when the cells were not aggregated."""
        return self.root if self.root is not None else np.full(len(self.size), -1)

    @property
    def n_hanging(self) -> int:
        """Nodes without an unknown of their own (hanging, or extended by an aggregation)."""
        return len(self.nodes) - len(self.free_nodes)

    def extend(self, extension: sp.csr_matrix, kept: np.ndarray) -> None:
        """Give up the unknowns of some free nodes: u_free = E u_kept with ``extension`` E (free
        nodes x kept) and ``kept`` the positions of the kept ones among the free nodes; the
        constraint becomes T E, so hanging nodes whose parents are extended follow them. Called
        while the grid is built, never after."""
        self.constraint = (self.constraint @ extension).tocsr()
        self.free_nodes = self.free_nodes[np.asarray(kept)]


@dataclass(frozen=True)
class Aggregation:
    """The aggregates of a grid's cells and the extension of the ill-supported nodes."""

    #: (m,) root cell of each cell (itself when well supported; -1 when it reaches none)
    root: np.ndarray
    #: (free nodes, kept nodes): free-node displacements from the kept ones
    extension: sp.csr_matrix
    #: (kept,) positions of the kept nodes among the free nodes
    kept: np.ndarray

    @property
    def n_extended(self) -> int:
        return self.extension.shape[0] - len(self.kept)


def aggregate(tree, fraction: np.ndarray, threshold: float = AGGREGATION_THRESHOLD) -> Aggregation:
    """Aggregates of the leaves of ``tree`` (a :class:`solver.fem.grid.Grid` or an
    :class:`solver.fem.octree.Octree`) from each cell's inside volume ``fraction`` (m,) of its
    cube (area of its square in 2D)."""
    if not 0.0 <= threshold < 1.0:
        raise ValueError(f"aggregation threshold must lie in [0, 1), got {threshold!r}")
    fraction = np.asarray(fraction, dtype=float)
    well = fraction >= threshold
    support = _cell_support(tree)  # (m, free nodes) pattern
    material = fraction > 0.0
    root = _roots(tree, well, material, support)
    supported = np.asarray(support[well].sum(axis=0)).ravel() > 0
    ill = np.flatnonzero(~supported)
    node_root = _node_roots(tree, ill, root, material, support)
    extended = ill[node_root >= 0]
    n_free = support.shape[1]
    kept = np.setdiff1d(np.arange(n_free), extended)
    return Aggregation(root, _extension(tree, extended, node_root[node_root >= 0], kept), kept)


def aggregate_thickness(root: np.ndarray, size: np.ndarray, volume: np.ndarray, area: np.ndarray) -> np.ndarray:
    """(m,) local size of each cell for a boundary band: min(h, 2 V / A) of its aggregate (the
    sums of the inside volumes V and boundary areas A, in 2D areas and boundary lengths, over the
    cells with the same root, h the root's size), and never more than the cell's own size; a cell
    without root keeps its own."""
    m = len(size)
    own = root < 0
    key = np.where(own, np.arange(m), root)
    v = np.bincount(key, volume, minlength=m)
    a = np.bincount(key, area, minlength=m)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(a > 0, 2.0 * v / a, np.inf)
    return np.minimum(size, np.minimum(size[key], t[key]))


def _cell_support(tree) -> sp.csr_matrix:
    """(m, free nodes) 0/1: the free nodes each cell's field depends on (hanging nodes through
    their parents)."""
    m, k = tree.cells.shape
    incidence = sp.csr_matrix((np.ones(k * m), (np.repeat(np.arange(m), k), tree.cells.ravel())),
                              shape=(m, len(tree.nodes)))
    pattern = tree.constraint.copy()
    pattern.data = np.ones_like(pattern.data)
    s = (incidence @ pattern).tocsr()
    s.data = np.ones_like(s.data)
    return s


def _roots(tree, well: np.ndarray, material: np.ndarray, support: sp.csr_matrix) -> np.ndarray:
    """Root cell of each cell: the well-supported cells are their own; the others take, layer
    after layer, the root nearest to their centre among the cells they share a free node with.
    Only cells with material pass a root on (cells wholly outside receive one but do not bridge a
    gap), unless nothing else is left."""
    root = np.where(well, np.arange(len(well)), -1)
    centre = tree.center
    while True:
        open_cells = np.flatnonzero(root < 0)
        if not len(open_cells):
            break
        touch = (support[open_cells] @ support.T).tocoo()
        source = root[touch.col] >= 0
        through = source & material[touch.col]
        source = through if through.any() else source
        rows, cols = open_cells[touch.row[source]], touch.col[source]
        if not len(rows):
            break
        candidate = root[cols]
        distance = np.linalg.norm(centre[rows] - centre[candidate], axis=1)
        best = _first_per_group(rows, distance, candidate)
        root[rows[best]] = candidate[best]
    return root


def _node_roots(tree, ill: np.ndarray, root: np.ndarray, material: np.ndarray, support: sp.csr_matrix) -> np.ndarray:
    """Root cell of each ill-supported free node (-1: none): among the roots of the cells with
    material that depend on it (of any cell when none has material), the one whose centre is
    nearest the node."""
    out = np.full(len(ill), -1)
    if not len(ill):
        return out
    touch = support[:, ill].tocoo()  # rows: cells, cols: position in ill
    ok = root[touch.row] >= 0
    inside = ok & material[touch.row]
    has_inside = np.bincount(touch.col[inside], minlength=len(ill)) > 0
    ok &= inside | ~has_inside[touch.col]
    node, candidate = touch.col[ok], root[touch.row[ok]]
    x = tree.nodes[tree.free_nodes[ill[node]]]
    distance = np.linalg.norm(x - tree.center[candidate], axis=1)
    best = _first_per_group(node, distance, candidate)
    out[node[best]] = candidate[best]
    return out


def _first_per_group(group: np.ndarray, distance: np.ndarray, tie: np.ndarray) -> np.ndarray:
    """Index of the smallest distance in each group (ties to the smallest ``tie``)."""
    order = np.lexsort((tie, distance, group))
    first = np.ones(len(order), dtype=bool)
    first[1:] = group[order][1:] != group[order][:-1]
    return order[first]


def _extension(tree, extended: np.ndarray, roots: np.ndarray, kept: np.ndarray) -> sp.csr_matrix:
    """E (free nodes, kept): identity on the kept nodes, the root cells' multilinear fields
    evaluated at the extended nodes (through the constraint of the roots' own nodes)."""
    n_free = len(tree.free_nodes)
    column = np.full(n_free, -1)
    column[kept] = np.arange(len(kept))
    x = tree.nodes[tree.free_nodes[extended]]
    local = tree.local_coordinates(x, roots)
    n = _multilinear(local, _reference_corners(tree))  # (e, 2^d), extrapolated outside [-1, 1]^d
    entry = np.repeat(np.arange(len(extended)), n.shape[1])
    weights = sp.csr_matrix((n.ravel(), (entry, tree.cells[roots].ravel())), shape=(len(extended), len(tree.nodes)))
    rows = (weights @ tree.constraint).tocoo()  # (e, free nodes), only kept columns by construction
    if (column[rows.col] < 0).any():  # pragma: no cover - a root's nodes are kept by definition
        raise RuntimeError("aggregation: a root cell depends on an extended node")
    r = np.concatenate([kept, extended[rows.row]])
    c = np.concatenate([np.arange(len(kept)), column[rows.col]])
    v = np.concatenate([np.ones(len(kept)), rows.data])
    return sp.csr_matrix((v, (r, c)), shape=(n_free, len(kept)))


def _reference_corners(tree) -> np.ndarray:
    """(2^d, d) the corners of the cells in reference coordinates (-1 or 1), in the order of the
    grid's cell table (read off its first cell)."""
    first = np.zeros(tree.cells.shape[1], dtype=int)
    return np.sign(tree.local_coordinates(tree.nodes[tree.cells[0]], first))


def _multilinear(local: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(q, 2^d) multilinear shape functions N_a = prod_k (1 + c_ak xi_k) / 2 of the cell whose
    reference corners are ``corners`` at local coordinates (q, d) (any, inside the cell or not)."""
    return np.prod(0.5 * (1.0 + local[:, None, :] * corners[None, :, :]), axis=2)
