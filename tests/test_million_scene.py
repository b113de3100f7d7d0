"""The million-dof 3D contact scene of benchmarks/million_dofs.py (benchmarks/scenes/
ball_on_plate_million.toml) is what its comments say: the shipped full ball on a block's ball and
finest contact cells, on a wider plate of the block's thickness with a four times finer far field,
and about a million dofs (counted from the plate's uniform grid alone, independently of the
solver's size estimate)."""

from __future__ import annotations

from pathlib import Path

from ibfem.solver.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "benchmarks" / "scenes" / "ball_on_plate_million.toml"
SHIPPED = ROOT / "examples" / "solid" / "full" / "ball_on_block.toml"


def _finest(body) -> float:
    return body.element_size / 2.0 ** max(r.levels for r in body.refinements if r.around_contact)


def test_million_scene_keeps_the_shipped_contact_cells_and_holds_a_million_dofs():
    scene, shipped = load_scene(SCENE).problem, load_scene(SHIPPED).problem
    ball, plate = (scene.body(n) for n in ("ball", "plate"))
    for mine, theirs in ((ball, shipped.body("ball")), (plate, shipped.body("block"))):
        assert _finest(mine) == _finest(theirs) == 0.00625  # the same finest cells at the contact
        assert mine.element_size == theirs.element_size / 4  # a four times finer far field
    # the plate alone: a uniform grid of 2.7 / h + 1 nodes each way in x and y, 0.5 / h + 1 in z,
    # three dofs a node (its base fixed: one layer of nodes fewer), before the ball and the refinement
    h = plate.element_size
    nodes = round(2.7 / h + 1) ** 2 * round(0.5 / h)
    assert 3 * nodes >= 0.7e6
