"""A 3D body's function space: the octree over a solid with exact cut cells, trilinear
cubes, and boundary points on the solid's faces for the step-boundary terms and loads.

The solid is anything with ``signed_distance(points (n, 3)) -> (n,)`` (positive inside),
``bounds -> (min (3,), max (3,))`` and ``faces`` (name -> face), each face with
``quadrature(resolution) -> (points (q, 3), weights (q,), normals (q, 3))``: Gauss points on the
exact trimmed face, every panel of the rule at most ``resolution`` across, outward normals. The
points are the face's own (never a tessellation's); a point is assigned to the leaf that holds
it (nudged into the material along the normal).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .aggregation import AGGREGATION_THRESHOLD, aggregate_thickness
from .assembly_blocks import assemble_blocks
from .cut_cells3d import CUT, INSIDE, classify_cells, inside_moments
from .grid import RefinementZone
from .fictitious import nonlinear_part
from .hexahedra import REFERENCE_CORNERS, cell_stiffness, full_cube_moments, monomial_stiffness

MULTILINEAR = np.array([(p, q, r) for p in range(2) for q in range(2) for r in range(2)])
from .octree import CORNERS, build_octree
from .space import BodyDiscretisation, body_zones
from .step_boundary import BoundaryPoints
from .surface_quadrature import cell_split_quadrature, polygon_split_quadrature

__all__ = ["SolidDiscretisation", "discretise_solid", "discretise_solid_body"]

#: subdivision levels of the cut cells' moments (volume error ~ 4^-depth of the cut cells' share)
CUT_DEPTH = 0
#: boundary quadrature panels per cell width
PANELS_PER_CELL = 2
#: collapsed Gauss order on the faces' pieces (2: 4 points per triangle, exact to degree 3: a
#: trilinear field on any planar piece, so the loads and consistency terms of a linear field
#: (the patch test); the band's products of two trilinear fields to fourth order in the piece.
#: Order 3 (9 points) changed the Lame errors by less than 1e-3 of themselves at 2.2x the points)
FACE_ORDER = 2
#: on curved faces the integrands are not polynomial: order 3 (9 points per triangle) keeps a
#: pressure's resultant on the Lame octant's inner sphere to 1e-12 of p pi a^2 / 4 (order 2: 3e-9)
CURVED_FACE_ORDER = 3


@dataclass
class SolidDiscretisation(BodyDiscretisation):
    """A solid on its octree: the cells' status (INSIDE / CUT) and the local moments (m, 27) of
    their inside parts; the rest as in 2D (dof block, point operators)."""

    status: np.ndarray = field(default=None, repr=False)
    moments: np.ndarray = field(default=None, repr=False)
    #: (m,) boundary area of the solid inside each cell (from the faces' quadrature)
    boundary_area: np.ndarray = field(default=None, repr=False)
    #: per face: (points, weights, normals, cells) of its quadrature on this octree (computed
    #: once, for the areas and for the conditions on the face)
    face_rules: dict = field(default=None, repr=False)

    @property
    def material_thickness(self) -> np.ndarray:
        """Local size available to a boundary band: min(h, 2 V / A) with V the inside volume and
        A the boundary area (h for a cell cut in half by a plane, the sliver's thickness for a
        sliver), as in 2D (solver.fem.grid.Grid.material_thickness), taken over the cell's
        aggregate when the cells are aggregated (a sliver's points then see its root cell's
        field: their band is sized by the aggregate, not by the sliver)."""
        return aggregate_thickness(self.grid.cell_roots, self.grid.size, self.inside_volume, self.boundary_area)

    def stiffness(self, alpha: float) -> sp.csr_matrix:
        """Volume stiffness of the free dofs: moment-fitted cube parts, cut cells plus ``alpha``
        times the full cube's stiffness on their non-linear modes (conditioning of tiny cut parts;
        solver.fem.fictitious)."""
        g = self.grid
        km = monomial_stiffness(self.elasticity)
        k_cells = cell_stiffness(self.moments, g.size, km)
        cut = np.nonzero(self.status == CUT)[0]
        if alpha > 0.0 and len(cut):  # on the cut cells' non-linear modes only (solver.fem.fictitious)
            k_f = nonlinear_part(cell_stiffness(full_cube_moments(), 1.0, km), REFERENCE_CORNERS)
            k_cells[cut] += (alpha * g.size[cut])[:, None, None] * k_f
        k = assemble_blocks(g.cells, k_cells, len(g.nodes))
        if g.n_hanging:
            t = sp.kron(g.constraint, sp.identity(3), format="csr")
            k = (t.T @ k @ t).tocsr()
        return k

    def edge_points(self, face: str, order: int = 2, traction: bool = True) -> BoundaryPoints:
        """Quadrature points on a face of the solid with their operators (the name follows the
        2D edge_points: boundary conditions call it for their ``edge``, a face name in 3D);
        without the traction operator when ``traction`` is False (loads on the face)."""
        faces = self.boundary.faces
        if face not in faces:
            raise ValueError(f"body {self.name!r} has no face {face!r}; faces: {', '.join(faces)}")
        points, weights, normals, cells = (self.face_rules or {}).get(face) or located_face_rule(faces[face], self.grid)
        return self._boundary_points(points, weights, normals, cells, traction)

    def edge_point_passes(self, face: str, order: int = 2, traction: bool = True, points: int = 4096):
        """:meth:`edge_points` of the face as consecutive runs of about ``points`` points (their
        operators, some 1.2 kB a point, then exist for one run at a time: a condition's reaction
        after the solve reads each point on its own)."""
        rule = (self.face_rules or {}).get(face)
        if rule is None:
            yield self.edge_points(face, order, traction)
            return
        for start in range(0, max(len(rule[1]), 1), points):
            yield self._boundary_points(*(a[start:start + points] for a in rule), traction)

    def _boundary_points(self, points, weights, normals, cells, traction: bool) -> BoundaryPoints:
        return BoundaryPoints(
            points=points,
            weights=weights,
            normals=normals,
            cell_size=np.maximum(self.material_thickness[cells], 1e-6 * self.grid.size[cells]),
            blocks=self.cell_blocks(points, cells, normals, traction),
        )

    def contains(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(self.boundary.signed_distance(points), dtype=float) >= -1e-9 * self.element_size

    @property
    def inside_volume(self) -> np.ndarray:
        """(m,) volume of each cell's inside part."""
        return self.moments[:, 0] * (0.5 * self.grid.size) ** 3

    def cell_centroids(self) -> np.ndarray:
        """(m, 3) centroids of the cells' inside parts (from their first moments)."""
        m = self.moments
        with np.errstate(invalid="ignore", divide="ignore"):
            local = m[:, [9, 3, 1]] / m[:, [0]]  # moments of xi, eta, zeta over the volume
        return self.grid.center + 0.5 * self.grid.size[:, None] * np.clip(np.nan_to_num(local), -1.0, 1.0)

    def body_force(self, value) -> np.ndarray:
        """Consistent load (n_total,) of a uniform body force (3,) over the inside parts: the
        integral of each trilinear N_a = (1/8) sum_e s_a^e xi^e from the moments of the part."""
        g = self.grid
        force = np.asarray(value, dtype=float).reshape(3)
        signs = 2.0 * CORNERS - 1.0  # (8, 3)
        powers = np.prod(signs[:, None, :] ** MULTILINEAR[None, :, :], axis=2)  # (8 corners, 8 e)
        m_e = self.moments[:, MULTILINEAR @ np.array([9, 3, 1])]  # (m, 8) moments of xi^e
        shape_integrals = (m_e @ powers.T) / 8.0 * (0.5 * g.size[:, None]) ** 3  # (m, 8)
        f = shape_integrals[:, :, None] * force[None, None, :]
        nodal = np.bincount(self.cell_dofs(np.arange(len(g.level))).ravel(), f.ravel(), minlength=3 * len(g.nodes))
        return self.node_dof_map.T @ nodal


def face_rule(face, tree, order: int = FACE_ORDER) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points, weights and outward normals on a face: split at the octree's planes when the face
    offers its parameter panels (solver.fem.surface_quadrature: exact for trilinear integrands on
    planar faces), else the face's own rule with panels of PANELS_PER_CELL per finest cell."""
    polygon = face.polygon() if hasattr(face, "polygon") else None
    if polygon is not None:  # a planar region with straight edges: cut exactly at the cells' planes
        return polygon_split_quadrature(polygon, face.normal, tree.h0, tree.origin, tree.h0 / 2.0**tree.max_level,
                                        order, cell_size=lambda points, normals: _cell_size(tree, points, normals))
    if hasattr(face, "panels") and hasattr(face, "evaluate"):
        spacing = tree.h0 / 2.0**tree.max_level
        if order == FACE_ORDER and not _planar(face):
            order = CURVED_FACE_ORDER
        return cell_split_quadrature(face, tree.h0, tree.origin, spacing, order,
                                     cell_size=lambda points, normals: _cell_size(tree, points, normals))
    if hasattr(face, "graded_quadrature"):  # points as fine as the cells they fall in
        # (a wrapped CAD face without a graded rule of its own never calls these: it has no normal)
        def cell_size(points):
            return _cell_size(tree, points, np.asarray(face.normal, dtype=float))

        # strips of half a cell across the lines; along them, one segment per cell crossed
        return face.graded_quadrature(tree.h0 / PANELS_PER_CELL, lambda p: cell_size(p) / PANELS_PER_CELL,
                                      split=lambda a, b: _cell_plane_cuts(tree.origin, a, b, cell_size(0.5 * (a + b))))
    if getattr(face, "graded_panels", False):  # CAD faces: triangles no larger than the cells they lie in
        return face.quadrature(tree.min_size / PANELS_PER_CELL,
                               panel_size=lambda points, normals: _cell_size(tree, points, normals))
    return face.quadrature(tree.min_size / PANELS_PER_CELL)


def _face_cells(tree, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Leaf of each face point, looked up a hair inside the solid (-1: none)."""
    return tree.locate(points - 1e-9 * tree.min_size * normals)


def _cell_size(tree, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Size of the cell holding each face point (the finest size where none does)."""
    cells = _face_cells(tree, points, normals)
    return np.where(cells >= 0, tree.size[np.maximum(cells, 0)], tree.min_size)


def _cell_plane_cuts(origin: np.ndarray, a: np.ndarray, b: np.ndarray, spacing: np.ndarray) -> np.ndarray:
    """(n, k) fractions of the segments a -> b where they cross the planes origin + j spacing
    (the faces of the cells of that size; 1 where there is no crossing)."""
    cuts = []
    for k in range(3):
        lo, hi = np.minimum(a[:, k], b[:, k]), np.maximum(a[:, k], b[:, k])
        first = np.floor((lo - origin[k]) / spacing) + 1.0
        last = np.ceil((hi - origin[k]) / spacing) - 1.0
        span = np.where(hi > lo, b[:, k] - a[:, k], 1.0)
        for m in range(int(max(0.0, (last - first).max(initial=-1.0) + 1.0))):
            plane = origin[k] + (first + m) * spacing
            cuts.append(np.where((first + m <= last) & (hi > lo), (plane - a[:, k]) / span, 1.0))
    return np.column_stack(cuts) if cuts else np.ones((len(a), 1))


def _planar(face) -> bool:
    """Whether a parametric face is flat (its normals at a grid of parameters agree)."""
    if not hasattr(face, "u0"):
        return False
    uu, vv = np.meshgrid(np.linspace(face.u0, face.u1, 5), np.linspace(face.v0, face.v1, 5), indexing="ij")
    _, normals, _ = face.evaluate(np.column_stack([uu.ravel(), vv.ravel()]))
    normals = np.asarray(normals, dtype=float)
    return bool(np.all(np.abs(normals - normals[0]).max(axis=1) < 1e-12))


def located_face_rule(face, tree, order: int = FACE_ORDER):
    """:func:`face_rule` with the cell of each point (points in no cell dropped)."""
    points, weights, normals = face_rule(face, tree, order)
    cells = _face_cells(tree, points, normals)
    keep = cells >= 0
    return points[keep], weights[keep], normals[keep], cells[keep]


#: the moments of the cut cells already integrated, per solid, by cell (its lower corner, size and
#: the subdivision depth): a line contact's coarse passes, the run's own grid and its error
#: estimate's share every cell away from the contact, whose moments are the same numbers
_CUT_MOMENTS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def cut_cell_moments(solid, lower: np.ndarray, size: np.ndarray, depth: int = CUT_DEPTH) -> np.ndarray:
    """:func:`solver.fem.cut_cells3d.inside_moments` of the cells (lower corners (m, 3), sizes
    (m,)) of ``solid`` by its signed distance, each cell integrated once per solid (a solid that
    takes no weak reference: every time)."""
    lower, size = np.asarray(lower, float).reshape(-1, 3), np.asarray(size, float).reshape(-1)
    try:
        memo = _CUT_MOMENTS.setdefault(solid, {})
    except TypeError:
        memo = {}
    keys = [bytes(row) + bytes([depth]) for row in np.ascontiguousarray(np.column_stack([lower, size]))]
    new = [i for i, k in enumerate(keys) if k not in memo]
    if new:
        values = inside_moments(lower[new], size[new], solid.signed_distance, depth)
        memo.update(zip((keys[i] for i in new), values))
    return np.array([memo[k] for k in keys], dtype=float).reshape(-1, 27)


def discretise_solid(name: str, solid, material_lame: tuple[float, float], elasticity: np.ndarray,
                     poissons_ratio: float, element_size: float, zones: tuple[RefinementZone, ...] = (),
                     index: int = 0, offset=(0.0, 0.0, 0.0), depth: int = CUT_DEPTH,
                     aggregation_threshold: float | None = AGGREGATION_THRESHOLD) -> SolidDiscretisation:
    """The octree over ``solid`` (cells farther outside than their half diagonal dropped), the
    status and inside moments of its cells, the cells whose inside part is less than
    ``aggregation_threshold`` of the cube aggregated to well-supported ones (None: not at all)."""
    phi = solid.signed_distance
    reach = 0.5 * np.sqrt(3.0) * (1.0 + 1e-9)

    def keep(lower, size):
        return np.asarray(phi(lower + 0.5 * size[:, None]), dtype=float) > -reach * size

    tree = build_octree(solid.bounds, element_size, zones, keep, offset)
    status = classify_cells(tree.lower, tree.size, phi)
    moments = np.zeros((len(tree.size), 27))
    moments[status == INSIDE] = full_cube_moments()
    cut = status == CUT
    moments[cut] = cut_cell_moments(solid, tree.lower[cut], tree.size[cut], depth)
    if aggregation_threshold is not None:
        tree.aggregate_cells(moments[:, 0] / 8.0, aggregation_threshold)
    lam, mu = material_lame
    area = np.zeros(len(tree.size))
    rules = {}
    for face_name, face in solid.faces.items():
        rules[face_name] = located_face_rule(face, tree)
        _, weights, _, cells = rules[face_name]
        area += np.bincount(cells, weights, minlength=len(area))
    return SolidDiscretisation(
        name=name, index=index, grid=tree, boundary=solid, profile=solid, lam=lam, mu=mu, elasticity=elasticity,
        model="solid", poissons_ratio=poissons_ratio, element_size=float(element_size), status=status,
        moments=moments, boundary_area=area, face_rules=rules,
    )


def discretise_solid_body(body, index: int, model: str, exact_geometry: bool, settings) -> SolidDiscretisation:
    """One body of a 3D problem (``body.profile`` is its solid) on its octree."""
    if not exact_geometry:
        raise ValueError("solver.exact_geometry = false: 3D solids are integrated on their exact surfaces only")
    offset = tuple(settings.grid_offset) + (0.0,) * (3 - len(settings.grid_offset))
    lam, mu = body.material.lame(model)
    return discretise_solid(
        body.name, body.profile, (lam, mu), body.material.elasticity_matrix(model), body.material.poissons_ratio,
        float(body.element_size), body_zones(body), index=index, offset=offset,
    )
