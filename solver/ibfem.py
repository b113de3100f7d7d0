"""Immersed-boundary finite elements on structured grids: ``solve(problem) -> Solution``.

Each body gets its own quadtree grid (solver.grid), bilinear cells with the exact square
stiffness inside and moment-exact cut cells on the boundary (solver.integration), essential
conditions by the thin-band step boundary method (solver.step_boundary), natural conditions and
body forces on the exact boundary and cut cells. Dofs of all bodies live in one global vector
(body after body); per-body assembly, point operators and boundary terms are kept separate so
the contact band of the next issues can couple two grids with the same machinery.
See docs/formulation.md for the equations.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .grid import CUT, Boundary, Grid, RefinementZone, assign_to_material_side, build_grid
from .integration import (
    Polyline,
    body_force_vectors,
    cell_stiffness,
    curve_gauss,
    full_cell_moments,
    monomial_stiffness,
    shape_functions,
    strain_matrix,
)
from .recovery import nodal_stress
from .problem import BodyForce, Displacement, Fixed, Pressure, Sliding, Traction
from .step_boundary import (
    DEFAULT_BAND_FRACTION,
    DEFAULT_CONSISTENCY,
    BoundaryPoints,
    projector,
    thin_band_terms,
    thin_band_traction,
)

__all__ = [
    "Settings",
    "BodyDiscretisation",
    "discretise_body",
    "exact_boundary",
    "tessellated_boundary",
    "IBFEMSolution",
    "EssentialTerm",
    "essential_condition",
    "rigid_modes_check",
    "boundary_terms",
    "essential_reactions",
    "LinearSystem",
    "discretise",
    "number_dofs",
    "assemble",
    "body_info",
    "linear_solve",
    "solve",
    "von_mises",
    "nested_dissection",
]


@dataclass(frozen=True)
class Settings:
    """Numerical choices (defaults documented and measured in docs/formulation.md)."""

    band_fraction: float = DEFAULT_BAND_FRACTION  # delta = band_fraction * local cell size
    consistency: float = DEFAULT_CONSISTENCY  # 1 symmetric Nitsche (default), 1/2 thesis band limit
    fictitious_stiffness: float = 1e-9  # cut cells get alpha * full-cell stiffness (conditioning)
    boundary_order: int = 5  # Gauss points per boundary piece for boundary conditions
    curve_order: int = 8  # Gauss points per boundary piece for cut-cell moments
    chord_fraction: float = 0.1  # exact_geometry false: chord tolerance / element_size
    grid_offset: tuple[float, float] = (0.0, 0.0)  # grid origin shift (fraction of element_size)

    chord_tolerance: float | None = None  # exact_geometry false: absolute chord (m), overrides chord_fraction

    @classmethod
    def from_options(cls, options) -> "Settings":
        """Settings with the numerical choices a scene's ``[solver]`` table made
        (``band_fraction``, ``consistency``, ``chord_tolerance``); the rest default."""
        chosen = {
            name: getattr(options, name)
            for name in ("band_fraction", "consistency", "chord_tolerance")
            if getattr(options, name, None) is not None
        }
        return cls(**chosen)

    def __post_init__(self):
        if self.chord_tolerance is not None and not self.chord_tolerance > 0:
            raise ValueError(f"solver.chord_tolerance must be positive, got {self.chord_tolerance!r}")
        if not self.band_fraction > 0:
            raise ValueError(f"band_fraction must be positive, got {self.band_fraction!r}")
        if self.consistency < 0:
            raise ValueError(f"consistency must be >= 0, got {self.consistency!r}")
        if not self.fictitious_stiffness >= 0:
            raise ValueError(f"fictitious_stiffness must be >= 0, got {self.fictitious_stiffness!r}")
        for name in ("boundary_order", "curve_order"):
            v = getattr(self, name)
            if int(v) != v or v < 1:
                raise ValueError(f"{name} must be a positive integer, got {v!r}")
        if not self.chord_fraction > 0:
            raise ValueError(f"chord_fraction must be positive, got {self.chord_fraction!r}")


# ---------------------------------------------------------------------------------- boundaries


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
    def n_dofs(self) -> int:
        return 2 * len(self.grid.free_nodes)

    @property
    def node_dof_map(self) -> sp.csr_matrix:
        """(2 N_nodes, n_total): nodal displacements [x0, y0, x1, ...] from the global vector."""
        if getattr(self, "_dof_map", None) is None:
            t = sp.kron(self.grid.constraint, sp.identity(2), format="coo")
            self._dof_map = sp.csr_matrix(
                (t.data, (t.row, t.col + self.dof_offset)), shape=(t.shape[0], self.n_total)
            )
        return self._dof_map

    def cell_dofs(self, cells: np.ndarray) -> np.ndarray:
        """(m, 8) node-dof indices (before constraints) of cells."""
        nodes = self.grid.cells[cells]
        return (2 * nodes[:, :, None] + np.arange(2)).reshape(-1, 8)

    def shape(self, points: np.ndarray, cells: np.ndarray):
        """N (q, 4) and grad N (q, 4, 2) in physical units at points in their cells."""
        loc = self.grid.local_coordinates(points, cells)
        n, dn = shape_functions(loc[:, 0], loc[:, 1])
        return n, dn * (2.0 / self.grid.size[cells])[:, None, None]

    def _point_matrix(self, values: np.ndarray, cells: np.ndarray) -> sp.csr_matrix:
        """Sparse (rows, n_total) from per-point blocks values (q, r, 8) over cell dofs."""
        q, r, _ = values.shape
        rows = np.broadcast_to(np.arange(q * r).reshape(q, r, 1), values.shape)
        cols = np.broadcast_to(self.cell_dofs(cells)[:, None, :], values.shape)
        m = sp.csr_matrix((values.ravel(), (rows.ravel(), cols.ravel())), shape=(q * r, 2 * len(self.grid.nodes)))
        return (m @ self.node_dof_map).tocsr()

    def displacement_operator(self, points, cells) -> sp.csr_matrix:
        n, _ = self.shape(points, cells)
        v = np.zeros((len(points), 2, 8))
        v[:, 0, 0::2] = n
        v[:, 1, 1::2] = n
        return self._point_matrix(v, cells)

    def stress_operator(self, points, cells) -> sp.csr_matrix:
        """(3q, n_total): [sxx, syy, sxy] at the points."""
        _, g = self.shape(points, cells)
        return self._point_matrix(self.elasticity @ strain_matrix(g), cells)

    def traction_operator(self, points, cells, normals) -> sp.csr_matrix:
        """(2q, n_total): sigma(u_h) n at the points."""
        _, g = self.shape(points, cells)
        s = self.elasticity @ strain_matrix(g)  # (q, 3, 8)
        nx, ny = normals[:, 0, None], normals[:, 1, None]
        t = np.stack([nx * s[:, 0] + ny * s[:, 2], nx * s[:, 2] + ny * s[:, 1]], axis=1)
        return self._point_matrix(t, cells)

    def stiffness(self, alpha: float) -> sp.csr_matrix:
        """Volume stiffness (n_dofs, n_dofs) of the body's free dofs (COO over all cells)."""
        g = self.grid
        km = monomial_stiffness(self.elasticity)
        k_full = cell_stiffness(full_cell_moments(), km)
        cut = np.nonzero(g.status == CUT)[0]
        inner = np.nonzero(g.status != CUT)[0]
        k_cut = cell_stiffness(g.moments[cut], km) + alpha * k_full
        cells = np.concatenate([inner, cut])
        k_cells = np.concatenate([np.broadcast_to(k_full, (len(inner), 8, 8)), k_cut])
        k = assemble_blocks(g.cells[cells], k_cells, len(g.nodes))
        if g.n_hanging:
            t = sp.kron(g.constraint, sp.identity(2), format="csr")
            k = (t.T @ k @ t).tocsr()
        return k

    def body_force(self, value) -> np.ndarray:
        """Consistent load (n_total,) of a uniform body force over the inside parts of cells."""
        g = self.grid
        f = body_force_vectors(g.moments, g.size, np.asarray(value, dtype=float))
        nodal = np.bincount(self.cell_dofs(np.arange(len(g.level))).ravel(), f.ravel(), minlength=2 * len(g.nodes))
        return self.node_dof_map.T @ nodal

    def edge_points(self, edge: str, order: int) -> BoundaryPoints:
        """Gauss points on every piece of an edge (exact curve, or polyline when tessellated)."""
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
            displacement=self.displacement_operator(pts, cells),
            traction=self.traction_operator(pts, cells, nrm),
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
            displacement=self.displacement_operator(points, cells),
            traction=self.traction_operator(points, cells, normals),
        )

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Inside or on the boundary (to round-off of the element size)."""
        phi = self.boundary.signed_distance(points)
        tol = 1e-9 * self.element_size
        if self.boundary.exact:
            return phi >= -tol
        return self.boundary.inside(points, phi) | (np.abs(phi) <= tol)


def assemble_blocks(cell_nodes: np.ndarray, k_cells: np.ndarray, n_nodes: int) -> sp.csr_matrix:
    """Sum cell matrices (m, 8, 8) over node dofs [x0, y0, x1, ...] into a sparse matrix.

    Works on 2x2 node blocks (16 per cell instead of 64 scalar triplets): the node-node pattern
    is the sparse product of the node-cell incidence with its transpose, each cell's 16 node
    pairs are found in it by one binary search, and four bincounts sum the blocks into a BSR
    matrix. Hand-written because scipy's COO -> CSR conversion sorts all 64 scalar triplets
    per cell, 2 to 3 times slower here.
    """
    m = len(cell_nodes)
    inc = sp.csr_matrix((np.ones(4 * m), (cell_nodes.ravel(), np.repeat(np.arange(m), 4))), shape=(n_nodes, m))
    pattern = (inc @ inc.T).tocsr()
    pattern.sort_indices()
    rows = np.repeat(np.arange(n_nodes, dtype=np.int64), np.diff(pattern.indptr))
    keys = rows * n_nodes + pattern.indices
    nodes = cell_nodes.astype(np.int64)
    position = np.searchsorted(keys, (nodes[:, :, None] * n_nodes + nodes[:, None, :]).ravel())
    blocks = np.ascontiguousarray(k_cells.reshape(m, 4, 2, 4, 2).transpose(0, 1, 3, 2, 4)).reshape(-1, 4)
    summed = np.empty((len(keys), 4))
    for j in range(4):
        summed[:, j] = np.bincount(position, blocks[:, j], minlength=len(keys))
    return sp.bsr_matrix(
        (summed.reshape(-1, 2, 2), pattern.indices, pattern.indptr), shape=(2 * n_nodes, 2 * n_nodes)
    ).tocsr()


# 2^12 = 4096 times finer than the background grid is far beyond any use.
MAX_REFINEMENT_LEVELS = 12


def _zones(body, h0) -> tuple[RefinementZone, ...]:
    zones = []
    for k, r in enumerate(body.refinements):
        if r.center is None:
            raise ValueError(
                f"bodies[{body.name}].refinement[{k}].around is 'contact' but no contact point was resolved"
            )
        if int(r.levels) != r.levels or not 0 <= r.levels <= MAX_REFINEMENT_LEVELS:
            raise ValueError(f"bodies[{body.name}].refinement[{k}].levels must be an integer in [0, {MAX_REFINEMENT_LEVELS}], got {r.levels!r}")
        if not (r.radius > 0):
            raise ValueError(f"bodies[{body.name}].refinement[{k}].radius must be positive, got {r.radius!r}")
        zones.append(RefinementZone(int(r.levels), float(r.radius), np.asarray(r.center, dtype=float)))
    return tuple(zones)


def discretise_body(body, index: int, model: str, exact_geometry: bool, settings: Settings) -> BodyDiscretisation:
    """Grid, classification and cut-cell moments of one body."""
    h0 = float(body.element_size)
    if not (h0 > 0 and math.isfinite(h0)):
        raise ValueError(f"bodies[{body.name}].element_size must be positive, got {body.element_size!r}")
    E, nu = body.material.youngs_modulus, body.material.poissons_ratio
    if not E > 0:
        raise ValueError(f"materials[{body.material.name}].youngs_modulus must be positive, got {E!r}")
    if not (-1.0 < nu < 0.5):
        raise ValueError(f"materials[{body.material.name}].poissons_ratio must be in (-1, 0.5), got {nu!r}")
    if exact_geometry:
        boundary = exact_boundary(body.profile)
    else:
        chord = settings.chord_tolerance if settings.chord_tolerance is not None else settings.chord_fraction * h0
        boundary = tessellated_boundary(body.profile, chord)
    grid = build_grid(boundary, h0, _zones(body, h0), settings.grid_offset, settings.curve_order)
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
        poissons_ratio=nu,
        element_size=h0,
    )


# ---------------------------------------------------------------------------------- results


def von_mises(stress: np.ndarray, model: str, poissons_ratio: float) -> np.ndarray:
    """von Mises of [sxx, syy, sxy] (n, 3); plane strain adds szz = nu (sxx + syy)."""
    sxx, syy, sxy = stress[:, 0], stress[:, 1], stress[:, 2]
    szz = poissons_ratio * (sxx + syy) if model == "plane_strain" else np.zeros_like(sxx)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxy**2)


@dataclass
class IBFEMSolution:
    """The solved problem: fields are evaluated lazily at the points asked for."""

    problem: object
    bodies: list[BodyDiscretisation]
    u: np.ndarray
    converged: bool
    body_info: dict[str, dict[str, float]]
    reactions: dict[str, np.ndarray]
    iterations: dict
    timings: dict[str, float]
    contacts: list[dict] = field(default_factory=list)
    settings: Settings = field(default_factory=Settings)
    boundary_tractions: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=dict)

    def _body(self, body: str | None) -> list[BodyDiscretisation]:
        if body is None:
            return self.bodies
        for b in self.bodies:
            if b.name == body:
                return [b]
        raise ValueError(f"no body named {body!r}; bodies: {', '.join(b.name for b in self.bodies)}")

    @staticmethod
    def _points(points) -> np.ndarray:
        p = np.asarray(points, dtype=float)
        if p.ndim == 1 and p.shape == (2,):
            p = p[None]
        if p.ndim != 2 or p.shape[1] != 2:
            raise ValueError(f"points must be an (n, 2) array, got shape {p.shape}")
        return p

    def body_at(self, points: np.ndarray) -> np.ndarray:
        p = self._points(points)
        out = np.full(len(p), -1, dtype=np.int64)
        for b in self.bodies:
            todo = out < 0
            if todo.any():
                hit = b.contains(p[todo]) & (b.grid.locate(p[todo]) >= 0)
                out[np.nonzero(todo)[0][hit]] = b.index
        return out

    def cell_centroids(self, body: str) -> np.ndarray:
        """(m, 2) centroids of the inside parts of the cells."""
        (b,) = self._body(body)
        g = b.grid
        m = g.moments
        with np.errstate(invalid="ignore", divide="ignore"):
            loc = np.stack([m[:, 1, 0] / m[:, 0, 0], m[:, 0, 1] / m[:, 0, 0]], axis=1)
        return g.center + 0.5 * g.size[:, None] * np.clip(np.nan_to_num(loc), -1.0, 1.0)

    def centroid_stress(self, body: str) -> np.ndarray:
        """(m, 3) stress of the discrete field at the centroid of each cell's inside part (the
        superconvergent point of a bilinear square for interior cells); computed once."""
        (b,) = self._body(body)
        cache = self.__dict__.setdefault("_centroid_stress", {})
        if b.name not in cache:
            cells = np.arange(len(b.grid.level))
            cache[b.name] = (b.stress_operator(self.cell_centroids(b.name), cells) @ self.u).reshape(-1, 3)
        return cache[b.name]

    def nodal_stress(self, body: str) -> np.ndarray:
        """(N, 3) recovered nodal stresses (solver.recovery); computed once."""
        (b,) = self._body(body)
        cache = self.__dict__.setdefault("_nodal_stress", {})
        if b.name not in cache:
            cache[b.name] = nodal_stress(b.grid, self.cell_centroids(b.name), self.centroid_stress(b.name))
        return cache[b.name]

    def _evaluate(self, points, body, kind: str, width: int) -> np.ndarray:
        p = self._points(points)
        out = np.full((len(p), width), np.nan)
        owner = self.body_at(p) if body is None else None
        for b in self._body(body):
            if owner is None:
                sel = np.nonzero(b.contains(p))[0]
            else:
                sel = np.nonzero(owner == b.index)[0]
            if len(sel) == 0:
                continue
            cells = b.grid.locate(p[sel])
            ok = cells >= 0
            sel, cells = sel[ok], cells[ok]
            if kind == "displacement":
                out[sel] = (b.displacement_operator(p[sel], cells) @ self.u).reshape(-1, 2)
            elif kind == "stress":
                out[sel] = (b.stress_operator(p[sel], cells) @ self.u).reshape(-1, 3)
            else:  # recovered stress: bilinear interpolation of the nodal stresses
                n, _ = b.shape(p[sel], cells)
                out[sel] = np.einsum("qa,qak->qk", n, self.nodal_stress(b.name)[b.grid.cells[cells]])
        return out

    def displacement(self, points: np.ndarray, body: str | None = None) -> np.ndarray:
        return self._evaluate(points, body, "displacement", 2)

    def stress(self, points: np.ndarray, body: str | None = None, recovered: bool = True) -> np.ndarray:
        """[sxx, syy, sxy] (n, 3). By default the recovered field (solver.recovery: nodal values
        from the cell-centroid stresses, interpolated bilinearly; O(h^2) inside);
        ``recovered=False`` gives the stress of the discrete field itself, C B u (O(h))."""
        return self._evaluate(points, body, "recovered" if recovered else "stress", 3)

    def von_mises(self, points: np.ndarray, body: str | None = None, recovered: bool = True) -> np.ndarray:
        p = self._points(points)
        s = self.stress(p, body, recovered)
        out = np.full(len(p), np.nan)
        owner = self.body_at(p) if body is None else None
        for b in self._body(body):
            sel = np.nonzero(owner == b.index)[0] if owner is not None else np.arange(len(p))
            out[sel] = von_mises(s[sel], b.model, b.poissons_ratio)
        return out

    def mesh(self, body: str) -> dict[str, np.ndarray]:
        (b,) = self._body(body)
        g = b.grid
        disp = (b.node_dof_map @ self.u).reshape(-1, 2)
        stress = self.centroid_stress(b.name)
        return {
            "nodes": g.nodes.copy(),
            "cells": g.cells.copy(),
            "displacement": disp,
            "cell_stress": stress,
            "cell_inside_fraction": g.inside_fraction.copy(),
        }


# ---------------------------------------------------------------------------------- solve


def essential_condition(bc, names):
    """(kind, free, target) of an essential condition, or None for natural ones."""
    if isinstance(bc, Fixed):
        return "fixed", (False, False), lambda n: np.zeros_like(n)
    if isinstance(bc, Displacement):
        if len(bc.value) != 2:
            raise ValueError(f"boundary condition {bc.body}/{bc.edge}: value must have 2 components, got {bc.value!r}")
        free = tuple(v is None for v in bc.value)
        if all(free):
            raise ValueError(f"boundary condition {bc.body}/{bc.edge}: both displacement components are free")
        a = np.array([0.0 if v is None else float(v) for v in bc.value])
        return "displacement", free, lambda n: np.broadcast_to(a, n.shape).copy()
    if isinstance(bc, Sliding):
        an = float(bc.normal_displacement)
        return "sliding", (False, False), lambda n: an * n
    return None


def _finite_vector(value, where: str) -> np.ndarray:
    v = np.asarray(value, dtype=float).ravel()
    if v.shape != (2,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{where} must be two finite numbers, got {value!r}")
    return v


def rigid_modes_check(k: sp.csr_matrix, bodies: list[BodyDiscretisation]) -> None:
    """Raise ValueError when a body can move rigidly (R^T K R singular for its rigid modes)."""
    diag = np.abs(k.diagonal())
    for b in bodies:
        g = b.grid
        nodes = g.nodes[g.free_nodes]
        c = nodes.mean(axis=0)
        r = np.zeros((b.n_total, 3))
        sl = slice(b.dof_offset, b.dof_offset + b.n_dofs)
        r[sl, 0] = np.tile([1.0, 0.0], len(nodes))
        r[sl, 1] = np.tile([0.0, 1.0], len(nodes))
        rot = np.stack([-(nodes[:, 1] - c[1]), nodes[:, 0] - c[0]], axis=1)
        r[sl, 2] = rot.ravel() / max(np.abs(rot).max(), 1e-300)
        m = r.T @ (k @ r)
        m = 0.5 * (m + m.T)
        scale = diag[sl].mean() * len(nodes)
        ev, vec = np.linalg.eigh(m)
        small = np.abs(ev) < 1e-10 * scale
        if small.any():
            v = vec[:, np.argmin(np.abs(ev))]
            what = ["x translation", "y translation", "rotation"]
            motion = " + ".join(f"{x:.2g} {w}" for x, w in zip(v, what) if abs(x) > 1e-3)
            raise ValueError(
                f"body {b.name!r} is not held against rigid-body motion ({motion}); add essential boundary conditions"
            )


@dataclass
class EssentialTerm:
    """One essential condition's thin-band terms, kept to recover its reaction."""

    key: str  # "body/edge"
    body: BodyDiscretisation
    points: BoundaryPoints
    projector: np.ndarray
    target: np.ndarray

    def traction(self, u: np.ndarray, settings: Settings, load_factor: float = 1.0) -> np.ndarray:
        """Traction along the edge with the prescribed values scaled by ``load_factor``."""
        b = self.body
        target = self.target if load_factor == 1.0 else load_factor * self.target
        return thin_band_traction(
            self.points, self.projector, target, b.lam, b.mu, u, settings.band_fraction, settings.consistency
        )


def essential_reactions(
    essentials: list[EssentialTerm], u: np.ndarray, settings: Settings, load_factor: float = 1.0
) -> tuple[dict[str, np.ndarray], dict]:
    """Force (2,) each essential condition exerts on its body (summed over terms with the same
    "body/edge" key), and the (points, weights, traction) along it."""
    reactions: dict[str, np.ndarray] = {}
    tractions = {}
    for e in essentials:
        tr = e.traction(u, settings, load_factor)
        reactions[e.key] = reactions.get(e.key, np.zeros(2)) + (tr * e.points.weights[:, None]).sum(axis=0)
        tractions[e.key] = (e.points.points, e.points.weights, tr)
    return reactions, tractions


@dataclass
class LinearSystem:
    """K u = F of a problem without contact: the stiffness and loads of all bodies (block by
    block) and their boundary conditions. Contact terms are added on top of it."""

    bodies: list[BodyDiscretisation]
    stiffness: sp.csr_matrix
    load: np.ndarray
    essentials: list[EssentialTerm]
    settings: Settings

    @property
    def n_dofs(self) -> int:
        return len(self.load)

    def reactions(self, u: np.ndarray) -> tuple[dict[str, np.ndarray], dict]:
        """Force (2,) each essential condition exerts on its body, and the tractions along it."""
        return essential_reactions(self.essentials, u, self.settings)


def discretise(problem, settings: Settings, progress=None) -> list[BodyDiscretisation]:
    """Grids of all bodies, with their blocks of the global dof vector."""
    report = progress or (lambda *a, **k: None)
    if problem.model not in ("plane_strain", "plane_stress"):
        raise ValueError(f"model must be 'plane_strain' or 'plane_stress', got {problem.model!r}")
    if not problem.bodies:
        raise ValueError("the problem has no bodies")
    bodies = []
    for i, body in enumerate(problem.bodies):
        report(f"grid {body.name}", 0.4 * i / len(problem.bodies))
        bodies.append(discretise_body(body, i, problem.model, problem.options.exact_geometry, settings))
    number_dofs(bodies)
    return bodies


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


def assemble(problem, bodies: list[BodyDiscretisation], settings: Settings) -> LinearSystem:
    """Volume stiffness of every body, essential conditions (thin band), tractions, pressures
    and body forces."""
    k = sp.block_diag([b.stiffness(settings.fictitious_stiffness) for b in bodies], format="csr")
    k, f, essentials = boundary_terms(problem, bodies, settings, k)
    return LinearSystem(bodies, k, f, essentials, settings)


def boundary_terms(
    problem, bodies: list[BodyDiscretisation], settings: Settings, stiffness: sp.spmatrix
) -> tuple[sp.csr_matrix, np.ndarray, list[EssentialTerm]]:
    """``stiffness`` plus the thin-band terms of the essential conditions, the load vector
    (their band loads, tractions, pressures, body forces) and the essential terms kept for
    the reactions."""
    n = bodies[0].n_total if bodies else 0
    k = stiffness
    f = np.zeros(n)
    by_name = {b.name: b for b in bodies}
    names = list(by_name)
    essentials = []
    for j, bc in enumerate(problem.boundary_conditions):
        if bc.body not in by_name:
            raise ValueError(f"boundary_conditions[{j}].body: unknown body {bc.body!r}; bodies: {', '.join(names)}")
        b = by_name[bc.body]
        if isinstance(bc, BodyForce):
            f += b.body_force(_finite_vector(bc.value, f"boundary_conditions[{j}].value"))
            continue
        bp = b.edge_points(bc.edge, settings.boundary_order)
        ess = essential_condition(bc, names)
        if ess is not None:
            ekind, free, target_of = ess
            proj = projector(ekind, bp.normals, free)
            target = target_of(bp.normals)
            kb, fa = thin_band_terms(bp, proj, target, b.lam, b.mu, settings.band_fraction, settings.consistency)
            k = k + kb
            f += fa
            essentials.append(EssentialTerm(f"{bc.body}/{bc.edge}", b, bp, proj, target))
        elif isinstance(bc, Traction):
            tr = np.broadcast_to(_finite_vector(bc.value, f"boundary_conditions[{j}].value"), bp.normals.shape)
            f += bp.displacement.T @ (tr * bp.weights[:, None]).ravel()
        elif isinstance(bc, Pressure):
            if not np.isfinite(bc.value):
                raise ValueError(f"boundary_conditions[{j}].value: pressure must be finite, got {bc.value!r}")
            tr = -float(bc.value) * bp.normals
            f += bp.displacement.T @ (tr * bp.weights[:, None]).ravel()
        else:
            raise ValueError(f"boundary_conditions[{j}]: unsupported condition type {type(bc).__name__}")
    return k.tocsr(), f, essentials


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


def solve(problem, progress: Callable[..., None] | None = None, settings: Settings | None = None) -> IBFEMSolution:
    """Solve a linear elastic :class:`solver.problem.Problem` with IBFEM.

    Problems with contacts go to :func:`solver.contact_solver.solve_contact` (``settings``
    there is a ``ContactSettings``). ``progress(stage, fraction)`` is called between stages.
    """
    if problem.contacts:
        from solver.contact_solver import solve_contact

        return solve_contact(problem, progress=progress, settings=settings)
    settings = settings or Settings.from_options(problem.options)
    t_start = time.perf_counter()
    report = progress or (lambda *a, **k: None)
    timings: dict[str, float] = {}
    t = time.perf_counter()
    bodies = discretise(problem, settings, report)
    timings["grid_s"] = time.perf_counter() - t

    report("assembly", 0.4)
    t = time.perf_counter()
    system = assemble(problem, bodies, settings)
    timings["assembly_s"] = time.perf_counter() - t

    rigid_modes_check(system.stiffness, bodies)
    report("solve", 0.6)
    t = time.perf_counter()
    u = linear_solve(system.stiffness, system.load, bodies)
    timings["solve_s"] = time.perf_counter() - t
    k, f = system.stiffness, system.load
    residual = float(np.linalg.norm(k @ u - f) / max(np.linalg.norm(f), 1e-300))

    reactions, tractions = system.reactions(u)
    timings["total_s"] = time.perf_counter() - t_start
    report("done", 1.0)
    return IBFEMSolution(
        problem=problem,
        bodies=bodies,
        u=u,
        converged=bool(np.isfinite(u).all() and residual < 1e-6),
        body_info=body_info(bodies),
        reactions=reactions,
        iterations={"total": 1, "per_step": [1], "linear_residual": residual},
        timings=timings,
        contacts=[],
        settings=settings,
        boundary_tractions=tractions,
    )


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


def linear_solve(k: sp.csr_matrix, f: np.ndarray, bodies: list[BodyDiscretisation] | None = None) -> np.ndarray:
    """Sparse direct solve with SuperLU (CHOLMOD is not available). The matrix is symmetric:
    symmetric mode, no pivoting across the diagonal. Small systems use SuperLU's minimum
    degree on A + A^T; large ones a geometric nested-dissection order of each body's nodes."""
    n = k.shape[0]
    if bodies is None or n < NESTED_DISSECTION_DOFS:
        lu = spla.splu(k.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        return lu.solve(f)
    perm = []
    for b in bodies:
        nodes = nested_dissection(b.grid.nodes[b.grid.free_nodes])
        perm.append(b.dof_offset + (2 * nodes[:, None] + np.arange(2)).ravel())
    perm = np.concatenate(perm)
    kp = k[perm][:, perm].tocsc()
    lu = spla.splu(kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    u = np.empty(n)
    u[perm] = lu.solve(f[perm])
    return u
