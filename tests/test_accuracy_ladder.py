"""Convergence of the 2D contact to the continuum problem (slow): the half disc R = 1 on a block
(benchmarks/scenes/peer_half_disc.toml, steel, plane strain, frictionless) on a ladder of grids,
every cell halved per rung, against the converged solution of the same problem by another code
(NGSolve P3 on curved fitted meshes, pairs on the undeformed geometry: N = 5.09163e8 N/m to
+-0.006 %, a between 0.07664 and 0.07673 m depending on how the edge is read from its penalty
solution); and the error estimate of a region with a complete end against Johnson's closed form
of a rigid tilted flat punch on a half-plane (Contact Mechanics, 1985, sec. 2.8)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.io.scene import load_scene, scene_from_dict
from ibfem.solver.solving import estimate_errors, solve

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "benchmarks" / "scenes" / "peer_half_disc.toml"
REFERENCE_N = 5.09163e8
REFERENCE_A = (0.07664, 0.07673)

pytestmark = pytest.mark.slow


def _rung(element_size: float, levels: int = 3) -> tuple[float, float]:
    data = tomllib.loads(SCENE.read_text())
    for body in data["bodies"]:
        body["element_size"] = element_size
        body["refinement"][0]["levels"] = levels
    data["output"] = {"vtk": False, "plots": False}
    block = solve(scene_from_dict(data, label="ladder test", base_dir=ROOT).problem).contacts[0]
    return float(block["half_width"]), float(block["normal_force"])


@pytest.fixture(scope="module")
def ladder():
    # 6.4k to 351k dofs (the finest cell 0.0125 to 0.0016 m)
    return np.array([_rung(h) for h in (0.1, 0.05, 0.025, 0.0125)])


def test_width_converges_monotonically(ladder):
    a = ladder[:, 0]
    d = np.diff(a)
    assert (d > 0).all()
    # the differences shrink at every rung, at an observed order of at least 1
    orders = np.log2(d[:-1] / d[1:])
    assert (orders >= 1.0).all(), orders
    # Richardson's limit from the last three rungs lies in the reference's interval
    limit = a[-1] + d[-1] / (2.0 ** orders[-1] - 1.0)
    assert REFERENCE_A[0] <= limit <= REFERENCE_A[1], limit


def test_normal_force_error_falls_at_every_rung(ladder):
    error = np.abs(ladder[:, 1] / REFERENCE_N - 1.0)
    assert (np.diff(error) < 0).all(), error
    assert error[-1] < 1e-4


def test_complete_end_estimate_within_a_factor_two():
    # the tilted flat punch (a region from a corner of the punch to a free end): the estimate of
    # its half length against its error from Johnson's P = pi E* eps a / 2 for the computed force
    path = ROOT / "examples" / "contact2d" / "tilted_punch.toml"
    scene = load_scene(path)
    solution = solve(scene.problem)
    estimate_errors(scene.problem, solution)
    c = solution.contacts[0]
    data = scene.spec.model_dump(mode="json")
    eps = -math.radians(data["bodies"][0]["shape"]["rotate_deg"])
    moduli = {m["name"]: (m["youngs_modulus"], m["poissons_ratio"]) for m in data["materials"]}
    e_star = 1.0 / sum((1.0 - nu * nu) / e for e, nu in (moduli[b["material"]] for b in data["bodies"]))
    true = abs(c["half_width"] / (2.0 * c["normal_force"] / (math.pi * e_star * eps)) - 1.0)
    estimated = c["estimated_error"]["half_width"]
    assert 0.5 * true <= estimated <= 2.0 * true, (estimated, true)
    assert c["estimated_error"]["max_pressure"] is None  # the corner's singular value
