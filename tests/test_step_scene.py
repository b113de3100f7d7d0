"""The `make demo` geometry read from STEP (examples/step): the same 2D profiles as the
Onshape fixture (fixtures/onshape/half_cylinder_on_block) and the same contact result in a run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

from ibfem.solver.io.scene import load_scene  # noqa: E402
from ibfem.solver.solving import solve  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
STEP_SCENE = ROOT / "examples" / "step" / "half_cylinder_on_block.toml"
ONSHAPE_SCENE = ROOT / "examples" / "onshape" / "half_cylinder_on_block.toml"


def test_same_profiles_and_contact_as_the_onshape_part():
    step, onshape = load_scene(STEP_SCENE), load_scene(ONSHAPE_SCENE)
    for a, b in zip(step.problem.bodies, onshape.problem.bodies):
        assert a.profile.area == pytest.approx(b.profile.area, rel=1e-12)
        np.testing.assert_allclose(np.asarray(a.profile.bounds), np.asarray(b.profile.bounds), atol=1e-15)
        assert len(a.profile.edge_names) == len(b.profile.edge_names)
    cs, co = solve(step.problem).contacts[0], solve(onshape.problem).contacts[0]
    assert cs["half_width"] == pytest.approx(co["half_width"], rel=1e-6)
    assert cs["normal_force"] == pytest.approx(co["normal_force"], rel=1e-6)
