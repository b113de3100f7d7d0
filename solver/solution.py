"""The solved problem: the discrete displacement of every body, and the fields derived from it
(displacement, raw and recovered stress, von Mises) evaluated lazily at the points asked for;
forces, iteration history and timings as the solver reported them."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .fem.cut_cells3d import CUT as CUT3
from .fem.recovery import nodal_stress, patch_recovery, sliding_symmetry
from .fem.space import BodyDiscretisation
from .model.elasticity import von_mises
from .model.options import SolverOptions
from .model.problem import Sliding

__all__ = ["IBFEMSolution"]


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
    settings: SolverOptions = field(default_factory=SolverOptions)
    boundary_tractions: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=dict)
    #: with load paths: one record per solved load step (summary.json "steps")
    steps: list = field(default_factory=list)

    def _body(self, body: str | None) -> list[BodyDiscretisation]:
        if body is None:
            return self.bodies
        for b in self.bodies:
            if b.name == body:
                return [b]
        raise ValueError(f"no body named {body!r}; bodies: {', '.join(b.name for b in self.bodies)}")

    @property
    def dim(self) -> int:
        """Spatial dimension (2 or 3)."""
        return self.bodies[0].dim if self.bodies else 2

    @property
    def voigt(self) -> int:
        """Stress components: [sxx, syy, sxy] in 2D, [sxx, syy, szz, syz, sxz, sxy] in 3D."""
        return self.dim * (self.dim + 1) // 2

    def _points(self, points) -> np.ndarray:
        p = np.asarray(points, dtype=float)
        d = self.dim
        if p.ndim == 1 and p.shape == (d,):
            p = p[None]
        if p.ndim != 2 or p.shape[1] != d:
            raise ValueError(f"points must be an (n, {d}) array, got shape {p.shape}")
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
        """(m, dim) centroids of the inside parts of the cells."""
        (b,) = self._body(body)
        if b.dim == 3:
            return b.cell_centroids()
        g = b.grid
        m = g.moments
        with np.errstate(invalid="ignore", divide="ignore"):
            loc = np.stack([m[:, 1, 0] / m[:, 0, 0], m[:, 0, 1] / m[:, 0, 0]], axis=1)
        return g.center + 0.5 * g.size[:, None] * np.clip(np.nan_to_num(loc), -1.0, 1.0)

    def centroid_stress(self, body: str, fields: np.ndarray | None = None) -> np.ndarray:
        """(m, 3) stress of the discrete field at the centroid of each cell's inside part (the
        superconvergent point of a bilinear square for interior cells); computed once.
        ``fields`` (dofs, k): other displacement fields instead, their stresses side by side
        (m, 3 k), not cached."""
        (b,) = self._body(body)
        cache = {} if fields is not None else self.__dict__.setdefault("_centroid_stress", {})
        if b.name not in cache:
            cells = np.arange(len(b.grid.level))
            op = b.stress_operator(self.cell_centroids(b.name), cells)
            if fields is not None:
                values = np.asarray(op @ fields).reshape(len(cells), self.voigt, -1)
                return values.transpose(0, 2, 1).reshape(len(cells), -1)
            cache[b.name] = (op @ self.u).reshape(-1, self.voigt)
        return cache[b.name]

    def nodal_stress(self, body: str, centroid_stress: np.ndarray | None = None) -> np.ndarray:
        """(N, 3) or (N, 6) recovered nodal stresses (solver.fem.recovery); computed once.
        ``centroid_stress`` (m, k): other values at the body's cell centroids to recover the same
        way instead (several fields side by side, e.g. the load steps'), not cached."""
        (b,) = self._body(body)
        cache = {} if centroid_stress is not None else self.__dict__.setdefault("_nodal_stress", {})
        if b.name not in cache:
            # flat sliding faces (straight sliding edges) are planes of symmetry: the patches
            # there are completed by their mirror images (solver.fem.recovery.sliding_symmetry)
            sliding = [bc.edge for bc in getattr(self.problem, "boundary_conditions", ())
                       if isinstance(bc, Sliding) and bc.body == b.name]
            values = self.centroid_stress(b.name) if centroid_stress is None else centroid_stress
            if b.dim == 3:
                g, centroids = b.grid, self.cell_centroids(b.name)
                planes, cut = sliding_symmetry(b.boundary, sliding, g, b.status == CUT3, b.inside_volume, centroids)
                cache[b.name] = patch_recovery(g.cells, g.nodes, g.size, b.inside_volume, cut, centroids,
                                               values, planes)
            else:
                cache[b.name] = nodal_stress(b.grid, self.cell_centroids(b.name), values, b.boundary, sliding)
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
                out[sel] = (b.displacement_operator(p[sel], cells) @ self.u).reshape(-1, self.dim)
            elif kind == "stress":
                out[sel] = (b.stress_operator(p[sel], cells) @ self.u).reshape(-1, self.voigt)
            else:  # recovered stress: bilinear interpolation of the nodal stresses
                n, _ = b.shape(p[sel], cells)
                out[sel] = np.einsum("qa,qak->qk", n, self.nodal_stress(b.name)[b.grid.cells[cells]])
        return out

    def displacement(self, points: np.ndarray, body: str | None = None) -> np.ndarray:
        return self._evaluate(points, body, "displacement", self.dim)

    def stress(self, points: np.ndarray, body: str | None = None, recovered: bool = True) -> np.ndarray:
        """[sxx, syy, sxy] (n, 3) in 2D, [sxx, syy, szz, syz, sxz, sxy] (n, 6) in 3D. By default the recovered field (solver.fem.recovery: nodal values
        from the cell-centroid stresses, interpolated bilinearly; O(h^2) inside);
        ``recovered=False`` gives the stress of the discrete field itself, C B u (O(h))."""
        return self._evaluate(points, body, "recovered" if recovered else "stress", self.voigt)

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
        disp = (b.node_dof_map @ self.u).reshape(-1, b.dim)
        stress = self.centroid_stress(b.name)
        fraction = b.moments[:, 0] / 8.0 if b.dim == 3 else g.inside_fraction.copy()
        return {
            "nodes": g.nodes.copy(),
            "cells": g.cells.copy(),
            "displacement": disp,
            "cell_stress": stress,
            "cell_inside_fraction": fraction,
        }


