"""The 2D size estimate of ``--check`` against the grids the run builds: the part of each
refinement zone the body holds is counted (a wedge's face and a concave seat cut the zone's
disc), and overlapping zones split their common cells once."""

import tomllib
from pathlib import Path

import pytest

from ibfem.solver.fem.bodies import discretise
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model.estimate import estimate_size

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _cells_built(scene) -> int:
    return sum(len(b.grid.level) for b in discretise(scene.problem, scene.problem.options))


@pytest.mark.parametrize("name", ["cylinder_on_wedge_frictionless", "cylinder_in_concave_partial_slip"])
def test_cells_within_ten_percent_of_the_built_grids(name):
    scene = load_scene(EXAMPLES / f"{name}.toml")
    built = _cells_built(scene)
    assert abs(estimate_size(scene.problem).cells / built - 1.0) < 0.1


def test_overlapping_zones_are_counted_once():
    data = tomllib.loads((EXAMPLES / "cylinder_on_cylinder_frictionless.toml").read_text())
    zone = data["bodies"][0]["refinement"][-1]
    radius = float(zone["radius"])
    for k in range(1, 5):  # four more zones as deep, each shifted by a quarter of the radius along x
        centre = [k * 0.25 * radius, 0.0]
        data["bodies"][0]["refinement"].append({"levels": zone["levels"], "around": centre, "radius": radius})
    scene = load_scene(data, label="s.toml", base_dir=EXAMPLES)
    built = _cells_built(scene)
    assert abs(estimate_size(scene.problem).cells / built - 1.0) < 0.1
