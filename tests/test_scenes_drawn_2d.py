"""2D scenes of the kinds a user writes that once failed (found by benchmarks/scene_sweep_2d.py),
each written here and checked against a fact that does not come from the solver."""

from __future__ import annotations

import json
import math

from ibfem.solver.cli import main

STEEL = {"name": "steel", "youngs_modulus": 2.0e11, "poissons_ratio": 0.3}


def _run(tmp_path, scene: dict, *extra: str) -> tuple[int, dict | None]:
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "out"
    code = main(["run", str(path), "--out", str(out), "--quiet", *extra])
    summary = out / "summary.json"
    return code, json.loads(summary.read_text()) if summary.exists() else None


def _hertz_half_width(N: float, R: float, E: float, nu: float) -> float:
    """Two bodies of one material, plane strain: a = sqrt(4 N R / (pi E*)), E* = E / (2 (1 - nu^2))."""
    return math.sqrt(4.0 * N * R / (math.pi * E / (2.0 * (1.0 - nu * nu))))


def cornered_punch_on_cylinder() -> dict:
    """A small flat punch with rounded corners (flat 1.6 mm, corner radius 0.3 mm, 1.6 mm tall) on
    a cylinder of 7 mm: the refinement radius reaches past the punch's top corners, so the
    candidate region ends at a top corner, the farthest point of the punch from the contact."""
    b, r, w, top = 8.0e-4, 3.0e-4, 1.1e-3, 1.6e-3
    edges = [
        {"name": "flat", "type": "line", "start": [-b, 0.0], "end": [b, 0.0]},
        {"name": "corner_right", "type": "arc", "center": [b, r], "radius": r, "start_angle": -90.0, "end_angle": 0.0},
        {"name": "flank_right", "type": "line", "start": [w, r], "end": [w, top]},
        {"name": "top", "type": "line", "start": [w, top], "end": [-w, top]},
        {"name": "flank_left", "type": "line", "start": [-w, top], "end": [-w, r]},
        {"name": "corner_left", "type": "arc", "center": [-b, r], "radius": r, "start_angle": -180.0, "end_angle": -90.0},
    ]
    return {
        "name": "cornered punch on a cylinder", "model": "plane_strain", "output": {"vtk": False},
        "solver": {"load_steps": 1}, "materials": [STEEL],
        "bodies": [
            {"name": "punch", "material": "steel", "element_size": 2.0e-4,
             "refinement": {"levels": 3, "around": "contact", "radius": 3.0e-3},
             "shape": {"type": "profile", "edges": edges}},
            {"name": "cylinder", "material": "steel", "element_size": 1.0e-3,
             "refinement": {"levels": 5, "around": "contact", "radius": 3.0e-3},
             "shape": {"type": "half_disk", "center": [0.0, -7.0e-3], "radius": 7.0e-3, "side": "above"}},
        ],
        "boundary_conditions": [
            {"type": "fixed", "body": "cylinder", "edge": "flat"},
            {"type": "displacement", "body": "punch", "edge": "top", "value": [0.0, -4.0e-6]},
        ],
        "contacts": [{"bodies": ["punch", "cylinder"], "type": "frictionless", "point": [0.0, 0.0]}],
    }


def test_a_region_bounded_by_the_punchs_farthest_corner_solves(tmp_path):
    """The candidate region's end at a corner that is also the farthest point of body 1 from the
    contact point was beyond every sample of the chord walk, and the run stopped with "cannot
    convert float NaN to integer" (exit 2). The flat on the cylinder is Hertz's contact of a
    cylinder of 7 mm on a flat (a = 0.12 mm, well inside the punch's flat)."""
    code, s = _run(tmp_path, cornered_punch_on_cylinder(), "--no-estimate")
    assert code == 0
    c = s["contacts"][0]
    assert abs(c["half_width"] / _hertz_half_width(c["normal_force"], 7.0e-3, 2.0e11, 0.3) - 1.0) < 0.03
    # the fixed edge holds the cylinder up with the contact force (the reaction acts on the body)
    assert abs(s["reactions"]["cylinder/flat"][1] - c["normal_force"]) < 1e-6 * c["normal_force"]
