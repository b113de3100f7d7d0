"""A contact point given in a scene must lie on both bodies' boundaries; a
mistyped one (inside a body, far away) is refused by the scene check, naming the key, the
distances and the nearest boundary points, instead of a converged zero-force run."""

import tomllib
from pathlib import Path

import pytest

from ibfem.solver.io.scene import SceneError, load_scene

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "cylinder_on_cylinder_frictionless.toml"


@pytest.mark.parametrize("point", [[0.0, 0.5], [1.9, 0.0], [100.0, 100.0], [0.0, -0.3]])
def test_a_point_off_the_boundaries_is_refused(point):
    data = tomllib.loads(EXAMPLE.read_text())
    data["contacts"][0]["point"] = point
    with pytest.raises(SceneError) as err:
        load_scene(data, label="scene.toml", base_dir=EXAMPLE.parent)
    text = str(err.value)
    assert "contacts[0].point" in text and "nearest boundary point" in text


def test_the_point_on_the_boundaries_and_a_missing_one_load():
    data = tomllib.loads(EXAMPLE.read_text())
    data["contacts"][0]["point"] = [0.0, 0.0]
    assert load_scene(data, label="scene.toml", base_dir=EXAMPLE.parent).problem.contacts[0].point_given
    data["contacts"][0].pop("point")
    found = load_scene(data, label="scene.toml", base_dir=EXAMPLE.parent).problem.contacts[0]
    assert not found.point_given and abs(found.point[1]) < 1e-9
