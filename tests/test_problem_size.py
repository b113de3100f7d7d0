"""The grids' size is estimated before anything is built; --check reports the
estimate and refuses what cannot fit in the machine's memory (element_size 1e-300, twelve
refinement levels), naming what to coarsen. The estimate is checked against built grids."""

import tomllib
from pathlib import Path

import pytest

from ibfem.solver.io.scene import SceneError, load_scene
from ibfem.solver.model.estimate import estimate_size

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _scene(**changes):
    data = tomllib.loads((EXAMPLES / "cylinder_on_cylinder_frictionless.toml").read_text())
    for key, value in changes.items():
        if key == "element_size":
            data["bodies"][0]["element_size"] = value
        if key == "levels":
            data["bodies"][0]["refinement"][-1]["levels"] = value
    return data


@pytest.mark.parametrize("changes", [{"element_size": 1e-300}, {"element_size": 1e-4}, {"levels": 12}])
def test_grids_that_cannot_fit_are_refused(changes):
    with pytest.raises(SceneError) as err:
        load_scene(_scene(**changes), label="s.toml", base_dir=EXAMPLES)
    assert "the grids would need" in str(err.value) and "coarsen" in str(err.value)


def test_estimate_against_the_built_grids():
    from ibfem.solver.fem.bodies import discretise

    scene = load_scene(_scene(), label="s.toml", base_dir=EXAMPLES)
    size = estimate_size(scene.problem)
    bodies = discretise(scene.problem, scene.problem.options)
    cells = sum(len(b.grid.level) for b in bodies)
    assert 0.5 * cells <= size.cells <= 2.0 * cells


@pytest.mark.parametrize("value", [1e300, 1e10, -5.0])
def test_displacements_beyond_the_body_size_are_refused(value):
    # a displacement of 1e300 ended in "array must not contain infs or NaNs";
    # beyond the largest magnitude a scene may hold the number itself is refused first
    data = _scene()
    disp = next(bc for bc in data["boundary_conditions"] if bc["type"] == "displacement")
    disp["value"] = [0.0, value]
    with pytest.raises(SceneError) as err:
        load_scene(data, label="s.toml", base_dir=EXAMPLES)
    message = str(err.value)
    assert "boundary_conditions[" in message and message.startswith("s.toml")
    if abs(value) < 1e20:
        assert "exceeds the size of body" in message
    else:
        assert "beyond the largest number a scene may hold" in message
