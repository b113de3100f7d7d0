"""A body's function space on its background grid: the grid (solver.fem.grid) over the exact
(or tessellated) boundary, bilinear cells, the body's block of the global dof vector, and the
point operators (displacement, stress, traction at any points) every term is assembled from.

Dimension: the number of displacement components per node is ``dim`` (from the grid's nodes),
the nodes per cell and the Voigt size come from the cell table and the elasticity matrix; the
shape functions and the grid are the quadtree's (solver.fem.integration, solver.fem.grid).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..model.options import SolverOptions
from .grid import (
    CUT,
    QUADTREE_AGGREGATION_THRESHOLD,
    Boundary,
    Grid,
    RefinementZone,
    assign_to_material_side,
    build_grid,
)
from .integration import (
    REFERENCE_NODES,
    Polyline,
    body_force_vectors,
    cell_stiffness,
    curve_gauss,
    full_cell_moments,
    monomial_stiffness,
)
from .assembly_blocks import assemble_blocks
from .fictitious import nonlinear_part
from .step_boundary import BoundaryPoints, CellBlocks, point_matrix
from .elasticity_ops import traction_of_voigt
from .elements import element_for

__all__ = [
    "BodyDiscretisation",
    "exact_boundary",
    "tessellated_boundary",
    "discretise_body",
    "number_dofs",
    "body_info",
    "body_zones",
]


def exact_boundary(profile) -> Boundary:
    """The profile's exact curves and signed distance."""
    return Boundary(dict(profile.edges), profile.signed_distance, profile.bounds, 0.0, None)


def tessellated_boundary(profile, chord_tolerance: float) -> Boundary:
    """The thesis's boundary: every edge replaced by its tessellation (polyline), polygon
    inside tests; volume and boundary integrals then see only the polygon."""
    curves = {}
    loops = []
    for lp in profile.loops:
        verts = []
        for c in lp:
            pts, _ = c.tessellate(chord_tolerance)
            pts = np.asarray(pts, dtype=float).copy()
            pts[0], pts[-1] = c.start, c.end
            curves[c.name] = Polyline(c.name, pts)
            verts.append(pts[:-1])
        loops.append(np.concatenate(verts))
    return Boundary(curves, profile.signed_distance, profile.bounds, float(chord_tolerance), loops)


# ---------------------------------------------------------------------------------- one body


@dataclass
class BodyDiscretisation:
    """One body on its grid, with its block of the global dof vector."""

    name: str
    index: int
    grid: Grid
    boundary: Boundary
    profile: object
    lam: float
    mu: float
    elasticity: np.ndarray
    model: str
    poissons_ratio: float
    dof_offset: int = 0
    n_total: int = 0  # size of the global dof vector
    element_size: float = 0.0

    @property
    def dim(self) -> int:
        """Displacement components per node (the grid's spatial dimension)."""
        return self.grid.nodes.shape[1]

    @property
    def n_dofs(self) -> int:
        return self.dim * len(self.grid.free_nodes)

    @property
    def node_dof_map(self) -> sp.csr_matrix:
        """(dim N_nodes, n_total): nodal displacements [x0, y0, x1, ...] from the global vector."""
        if getattr(self, "_dof_map", None) is None:
            t = sp.kron(self.grid.constraint, sp.identity(self.dim), format="coo")
            self._dof_map = sp.csr_matrix(
                (t.data, (t.row, t.col + self.dof_offset)), shape=(t.shape[0], self.n_total)
            )
        return self._dof_map

    def cell_dofs(self, cells: np.ndarray) -> np.ndarray:
        """(m, dim x nodes per cell) node-dof indices (before constraints) of cells."""
        nodes = self.grid.cells[cells]
        d = self.dim
        return (d * nodes[:, :, None] + np.arange(d)).reshape(len(nodes), -1)

    def shape(self, points: np.ndarray, cells: np.ndarray):
        """N (q, nodes per cell) and grad N (q, nodes per cell, dim) in physical units at points
        in their cells."""
        loc = self.grid.local_coordinates(points, cells)
        n, dn = element_for(self.dim).shape_functions(loc)
        return n, dn * (2.0 / self.grid.size[cells])[:, None, None]

    def _point_matrix(self, values: np.ndarray, cells: np.ndarray, dof_map: sp.csr_matrix | None = None) -> sp.csr_matrix:
        """Sparse (rows, n_total) from per-point blocks values (q, r, cell dofs) over cell dofs;
        (rows, m) with a restricted ``dof_map`` (:meth:`restricted_dof_map`)."""
        return point_matrix(values, self.cell_dofs(cells), self.node_dof_map if dof_map is None else dof_map)

    def restricted_dof_map(self, dofs: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
        """The node-dof map restricted to the global dofs ``dofs`` (sorted): (dim N_nodes, m), and
        per grid node whether every dof its displacement depends on is among them (operators
        built with the map are exact only at points whose cells' nodes all are)."""
        full = self.node_dof_map
        inside = np.zeros(self.n_total, dtype=bool)
        inside[dofs] = True
        row_ok = np.ones(full.shape[0], dtype=bool)
        bad_rows = np.repeat(np.arange(full.shape[0]), np.diff(full.indptr))[~inside[full.indices]]
        row_ok[bad_rows] = False
        node_ok = row_ok.reshape(-1, self.dim).all(axis=1)
        return full[:, dofs].tocsr(), node_ok

    def _displacement_blocks(self, n: np.ndarray) -> np.ndarray:
        """(q, d, cell dofs) of shape values n (q, nodes per cell)."""
        d = self.dim
        v = np.zeros((len(n), d, d * n.shape[1]))
        for k in range(d):
            v[:, k, k::d] = n
        return v

    def _traction_blocks(self, g: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """(q, d, cell dofs) sigma(.) n of shape gradients g (q, nodes per cell, d)."""
        if self.dim == 3 and g.shape[1] == 8 and self.elasticity.shape == (6, 6):
            from .hexahedra import traction_blocks  # B's non-zeros only: 3x faster than forming it

            return traction_blocks(g, np.broadcast_to(normals, (len(g), 3)), self.elasticity)
        b = element_for(self.dim).strain_matrix(g)  # (q, nv, cell dofs)
        q, nv, c = b.shape
        # one matrix product over every point (a (nv, nv) matmul broadcast over q is much slower)
        s = (self.elasticity @ np.moveaxis(b, 1, 0).reshape(nv, -1)).reshape(nv, q, c)
        return traction_of_voigt(np.moveaxis(s, 0, 1), normals)

    def cell_blocks(self, points, cells, normals, traction: bool = True) -> CellBlocks:
        """The displacement and (unless ``traction`` is False: loads only) traction operators at
        points as per-point cell blocks."""
        from . import pair_blocks

        if self.dim == 3 and traction and self.elasticity.shape == (6, 6) and pair_blocks.compiled():
            # trilinear cells: shape values and traction blocks in one compiled pass (where numba
            # is loaded already)
            from ._point_kernels import hexahedron_blocks
            from .hexahedra import REFERENCE_CORNERS

            loc = self.grid.local_coordinates(points, cells)
            n, t = hexahedron_blocks(loc, 2.0 / self.grid.size[cells], REFERENCE_CORNERS, self.elasticity,
                                     np.broadcast_to(normals, loc.shape))
            return CellBlocks(cells, self.grid.cells[cells], self._displacement_blocks(n), t, self.node_dof_map)
        n, g = self.shape(points, cells)
        return CellBlocks(cells, self.grid.cells[cells], self._displacement_blocks(n),
                          self._traction_blocks(g, normals) if traction else None, self.node_dof_map)

    def displacement_operator(self, points, cells, dof_map=None) -> sp.csr_matrix:
        n, _ = self.shape(points, cells)
        return self._point_matrix(self._displacement_blocks(n), cells, dof_map)

    def stress_operator(self, points, cells, dof_map=None) -> sp.csr_matrix:
        """(nv q, n_total): the Voigt stress ([sxx, syy, sxy] in 2D) at the points."""
        _, g = self.shape(points, cells)
        return self._point_matrix(self.elasticity @ element_for(self.dim).strain_matrix(g), cells, dof_map)

    def traction_operator(self, points, cells, normals, dof_map=None) -> sp.csr_matrix:
        """(dim q, n_total): sigma(u_h) n at the points."""
        _, g = self.shape(points, cells)
        return self._point_matrix(self._traction_blocks(g, normals), cells, dof_map)

    def stiffness(self, alpha: float) -> sp.csr_matrix:
        """Volume stiffness (n_dofs, n_dofs) of the body's free dofs (COO over all cells)."""
        g = self.grid
        km = monomial_stiffness(self.elasticity)
        k_full = cell_stiffness(full_cell_moments(), km)
        cut = np.nonzero(g.status == CUT)[0]
        inner = np.nonzero(g.status != CUT)[0]
        # the fictitious stiffness on the cut cells' non-linear modes only (solver.fem.fictitious)
        k_cut = cell_stiffness(g.moments[cut], km) + alpha * nonlinear_part(k_full, REFERENCE_NODES)
        cells = np.concatenate([inner, cut])
        k_cells = np.concatenate([np.broadcast_to(k_full, (len(inner),) + k_full.shape), k_cut])
        k = assemble_blocks(g.cells[cells], k_cells, len(g.nodes))
        if g.n_hanging:
            t = sp.kron(g.constraint, sp.identity(self.dim), format="csr")
            k = (t.T @ k @ t).tocsr()
        return k

    def body_force(self, value) -> np.ndarray:
        """Consistent load (n_total,) of a uniform body force over the inside parts of cells."""
        g = self.grid
        f = body_force_vectors(g.moments, g.size, np.asarray(value, dtype=float))
        nodal = np.bincount(self.cell_dofs(np.arange(len(g.level))).ravel(), f.ravel(), minlength=self.dim * len(g.nodes))
        return self.node_dof_map.T @ nodal

    def edge_points(self, edge: str, order: int, traction: bool = True) -> BoundaryPoints:
        """Gauss points on every piece of an edge (exact curve, or polyline when tessellated);
        without the traction operator when ``traction`` is False (loads on the edge)."""
        pc = self.grid.pieces
        if edge not in pc.curve_names:
            raise ValueError(f"body {self.name!r} has no edge {edge!r}; edges: {', '.join(pc.curve_names)}")
        sel = pc.of(edge)
        curve = self.boundary.curves[edge]
        pts, w, nrm, _ = curve_gauss(curve, pc.t0[sel], pc.t1[sel], order)
        cells = np.repeat(pc.cell[sel], order)
        pts, w, nrm = pts.reshape(-1, 2), w.ravel(), nrm.reshape(-1, 2)
        return BoundaryPoints(
            points=pts,
            weights=w,
            normals=nrm,
            cell_size=np.maximum(self.grid.material_thickness[cells], 1e-6 * self.grid.size[cells]),
            blocks=self.cell_blocks(pts, cells, nrm, traction),
        )

    def points_on(self, points: np.ndarray, weights: np.ndarray, normals: np.ndarray) -> BoundaryPoints:
        """BoundaryPoints at boundary points of this body (e.g. matched contact points), with
        the operators of the cells holding them (a point on a cell side goes to the cell on
        the material side of ``normals``); points in no cell raise ValueError."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        normals = np.asarray(normals, dtype=float).reshape(-1, 2)
        cells = assign_to_material_side(self.grid, points, -normals)
        if (cells < 0).any():
            bad = points[cells < 0][0]
            raise ValueError(f"point {bad.tolist()} lies outside the grid of body {self.name!r}")
        return BoundaryPoints(
            points=points,
            weights=np.asarray(weights, dtype=float).ravel(),
            normals=normals,
            cell_size=np.maximum(self.grid.material_thickness[cells], 1e-6 * self.grid.size[cells]),
            displacement_matrix=self.displacement_operator(points, cells),
            traction_matrix=self.traction_operator(points, cells, normals),
        )

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Inside or on the boundary (to round-off of the element size)."""
        phi = self.boundary.signed_distance(points)
        tol = 1e-9 * self.element_size
        if self.boundary.exact:
            return phi >= -tol
        return self.boundary.inside(points, phi) | (np.abs(phi) <= tol)


def body_zones(body) -> tuple[RefinementZone, ...]:
    """The body's refinement zones (centres resolved: :func:`solver.model.resolve_problem`)."""
    zones = []
    for k, r in enumerate(body.refinements):
        if r.center is None:
            raise ValueError(
                f"bodies[{body.name}].refinement[{k}].around is 'contact' but no contact point was resolved"
            )
        zones.append(RefinementZone(int(r.levels), float(r.radius), np.asarray(r.center, dtype=float)))
    return tuple(zones)


def discretise_body(body, index: int, model: str, exact_geometry: bool, settings: SolverOptions,
                    aggregation_threshold: float | None = QUADTREE_AGGREGATION_THRESHOLD) -> BodyDiscretisation:
    """Grid, classification and cut-cell moments of one body, the cells whose inside part is
    less than ``aggregation_threshold`` of the square aggregated to well-supported ones
    (solver.fem.aggregation; None: not at all)."""
    h0 = float(body.element_size)
    if exact_geometry:
        boundary = exact_boundary(body.profile)
    else:
        chord = settings.chord_tolerance if settings.chord_tolerance is not None else settings.chord_fraction * h0
        boundary = tessellated_boundary(body.profile, chord)
    if len(settings.grid_offset) != 2:
        raise ValueError(f"solver.grid_offset = {list(settings.grid_offset)}: a 2D grid takes two fractions [fx, fy]")
    grid = build_grid(boundary, h0, body_zones(body), tuple(settings.grid_offset), settings.curve_order,
                      aggregation_threshold)
    lam, mu = body.material.lame(model)
    return BodyDiscretisation(
        name=body.name,
        index=index,
        grid=grid,
        boundary=boundary,
        profile=body.profile,
        lam=lam,
        mu=mu,
        elasticity=body.material.elasticity_matrix(model),
        model=model,
        poissons_ratio=body.material.poissons_ratio,
        element_size=h0,
    )


def number_dofs(bodies: list[BodyDiscretisation]) -> int:
    """Give each body its block of the global dof vector (in order); the total number of dofs."""
    offset = 0
    for b in bodies:
        b.dof_offset = offset
        offset += b.n_dofs
    for b in bodies:
        b.n_total = offset
        b._dof_map = None
    return offset


def body_info(bodies: list[BodyDiscretisation]) -> dict[str, dict[str, float]]:
    return {
        b.name: {
            "elements": int(len(b.grid.level)),
            "dofs": int(b.n_dofs),
            "element_size": float(b.element_size),
            "min_element_size": float(b.grid.min_size),
        }
        for b in bodies
    }


