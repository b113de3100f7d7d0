"""The thin band's cell matrices both ways (matrix products over each cell's points, and
batched sums of per-point matrices) against the same terms built from the sparse point
operators (d q x ndof matrices and their products): independent implementations of one
bilinear form, so each agrees with it to round-off."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.fem import step_boundary
from ibfem.solver.fem.bodies import discretise
from ibfem.solver.fem.step_boundary import BoundaryPoints, projector, thin_band_terms
from ibfem.solver.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("per_cell", [0, 10**9])
@pytest.mark.parametrize("scene, h, face, kind", [
    ("examples/solid/sphere_on_flat.toml", 0.25, "z_min", "fixed"),
    ("examples/cylinder_on_flat_partial_slip.toml", 0.02, None, "fixed"),
])
def test_band_cell_matrices_both_ways_equal_operator_products(monkeypatch, per_cell, scene, h, face, kind):
    monkeypatch.setattr(step_boundary, "_CELL_PRODUCTS", per_cell)  # 0: products always; 1e9: never
    data = tomllib.loads((ROOT / scene).read_text())
    for b in data["bodies"]:
        b["element_size"] = h
        zones = b.get("refinement") or []
        for z in [zones] if isinstance(zones, dict) else zones:
            z["levels"] = min(z.get("levels", 1), 2)
    data["output"] = {"vtk": False, "plots": False}
    problem = load_scene(data, label=scene, base_dir=(ROOT / scene).parent).problem
    b = discretise(problem, problem.options)[-1 if face else 0]
    face = face or next(bc.edge for bc in problem.boundary_conditions if bc.body == b.name)
    bp = b.edge_points(face, 2)
    rng = np.random.default_rng(5)
    proj = projector(kind, bp.normals)
    target = rng.normal(size=bp.normals.shape)
    k_blocks, f_blocks = thin_band_terms(bp, proj, target, b.lam, b.mu, consistency=0.7)
    sparse_route = BoundaryPoints(bp.points, bp.weights, bp.normals, bp.cell_size,
                                  bp.blocks.matrix(bp.blocks.displacement), bp.blocks.matrix(bp.blocks.traction))
    k_matrix, f_matrix = thin_band_terms(sparse_route, proj, target, b.lam, b.mu, consistency=0.7)
    assert abs(k_blocks - k_matrix).max() <= 1e-12 * abs(k_matrix).max()
    assert np.max(np.abs(f_blocks - f_matrix)) <= 1e-12 * np.max(np.abs(f_matrix))
