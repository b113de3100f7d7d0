"""A 2D contact narrower than the grid resolves ends "not converged" with a diagnosis that says so
and what to change, on stderr as well as in summary.json (a new user's scene: a disc of radius
1.9 m pressed 0.66 mm into a block, cells of 0.12 m at the contact: Hertz's half-width for that
overlap is at most sqrt(2 R delta) = 0.05 m, under half a cell)."""

from __future__ import annotations

import json

from ibfem.solver.cli import main


def scene() -> dict:
    material = {"name": "steel", "youngs_modulus": 2.0e11, "poissons_ratio": 0.3}
    zone = {"levels": 2, "around": "contact", "radius": 0.6}
    return {
        "name": "coarse", "model": "plane_strain", "output": {"vtk": False, "plots": False},
        "materials": [material],
        "bodies": [
            {"name": "disk", "material": "steel", "element_size": 0.475, "refinement": zone,
             "shape": {"type": "half_disk", "center": [0.0, 1.9], "radius": 1.9, "side": "below"}},
            {"name": "block", "material": "steel", "element_size": 0.475, "refinement": zone,
             "shape": {"type": "rectangle", "min": [-3.8, -3.8], "max": [3.8, 0.0]}},
        ],
        "boundary_conditions": [
            {"type": "displacement", "body": "disk", "edge": "flat", "value": [0.0, -6.6e-4]},
            {"type": "fixed", "body": "block", "edge": "bottom"},
        ],
        "contacts": [{"bodies": ["disk", "block"], "type": "frictionless"}],
    }


def test_a_contact_smaller_than_a_cell_is_diagnosed(tmp_path, capsys):
    path = tmp_path / "coarse.json"
    path.write_text(json.dumps(scene()))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "not converged" in err and "Traceback" not in err
    assert "smaller than the grid resolves" in err and "refinement levels" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] is False
    assert any("smaller than the grid resolves" in m for m in summary["iterations"]["messages"])
