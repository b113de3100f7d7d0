"""The thin-band terms summed per cell from point blocks (CellBlocks) against the same terms
built from the sparse point operators (d q x ndof matrices and their products): the two routes
are independent implementations of one bilinear form, so they agree to round-off; and the
reactions from the blocks balance the applied pressure (equilibrium)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.fem.bodies import discretise
from ibfem.solver.fem.step_boundary import BoundaryPoints, projector, thin_band_terms, thin_band_traction
from ibfem.solver.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def _bodies(path: Path, element_size: float):
    data = tomllib.loads(path.read_text())
    for b in data["bodies"]:
        b["element_size"] = element_size
        zones = b.get("refinement") or []
        for z in [zones] if isinstance(zones, dict) else zones:
            z["levels"] = min(z.get("levels", 1), 2)  # hanging nodes, few cells
    data["output"] = {"vtk": False, "plots": False}
    scene = load_scene(data, label=path.name, base_dir=path.parent)
    return scene.problem, discretise(scene.problem, scene.problem.options)


@pytest.mark.parametrize("scene, h, body, face, kind", [
    ("examples/solid/lame_sphere.toml", 0.25, "shell", "equator", "sliding"),
    ("examples/solid/sphere_on_flat.toml", 0.25, "block", "z_min", "fixed"),
    ("examples/cylinder_on_flat_partial_slip.toml", 0.02, None, None, "fixed"),
])
def test_cell_block_band_terms_equal_sparse_operator_products(scene, h, body, face, kind):
    problem, bodies = _bodies(ROOT / scene, h)
    b = bodies[0] if body is None else next(x for x in bodies if x.name == body)
    if face is None:  # 2D: the condition's edge of the first body
        face = next(bc.edge for bc in problem.boundary_conditions if bc.body == b.name)
    bp = b.edge_points(face, 2)
    assert bp.blocks is not None
    rng = np.random.default_rng(3)
    proj = projector(kind, bp.normals)
    target = rng.normal(size=bp.normals.shape)
    k_blocks, f_blocks = thin_band_terms(bp, proj, target, b.lam, b.mu)
    dense_route = BoundaryPoints(bp.points, bp.weights, bp.normals, bp.cell_size,
                                 bp.blocks.matrix(bp.blocks.displacement), bp.blocks.matrix(bp.blocks.traction))
    k_matrix, f_matrix = thin_band_terms(dense_route, proj, target, b.lam, b.mu)
    scale = abs(k_matrix).max()
    assert abs(k_blocks - k_matrix).max() <= 1e-12 * scale
    assert np.max(np.abs(f_blocks - f_matrix)) <= 1e-12 * np.max(np.abs(f_matrix))
    u = rng.normal(size=b.n_total)
    t1 = thin_band_traction(bp, proj, target, b.lam, b.mu, u)
    t2 = thin_band_traction(dense_route, proj, target, b.lam, b.mu, u)
    assert np.max(np.abs(t1 - t2)) <= 1e-12 * np.max(np.abs(t2))
    loads = rng.normal(size=bp.normals.shape)
    assert np.allclose(bp.load(loads), dense_route.load(loads), rtol=0, atol=1e-12 * np.abs(loads).sum())


def test_a_reaction_read_in_short_passes_equals_the_sparse_operators(monkeypatch):
    # after the solve a condition's traction is read a few points at a time (their operators
    # never exist for the whole face): against the whole face's sparse operators
    from ibfem.solver.fem import assembly, solid_space

    problem, bodies = _bodies(ROOT / "examples/solid/sphere_on_flat.toml", 0.25)
    b = next(x for x in bodies if x.name == "block")
    bp = b.edge_points("z_min", 2)
    proj = projector("fixed", bp.normals)
    rng = np.random.default_rng(8)
    target = rng.normal(size=bp.normals.shape)
    u = rng.normal(size=b.n_total)
    term = assembly.EssentialTerm("block/z_min", b, "z_min", bp.points, bp.weights, proj, target)
    passes = solid_space.SolidDiscretisation.edge_point_passes
    monkeypatch.setattr(solid_space.SolidDiscretisation, "edge_point_passes",
                        lambda self, face, order=2, traction=True: passes(self, face, order, traction, points=7))
    assert len(list(b.edge_point_passes("z_min", 2))) > 1
    dense_route = BoundaryPoints(bp.points, bp.weights, bp.normals, bp.cell_size,
                                 bp.blocks.matrix(bp.blocks.displacement), bp.blocks.matrix(bp.blocks.traction))
    expected = thin_band_traction(dense_route, proj, target, b.lam, b.mu, u, problem.options.band_fraction,
                                  problem.options.consistency)
    got = term.traction(u, problem.options)
    assert got.shape == expected.shape
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))
