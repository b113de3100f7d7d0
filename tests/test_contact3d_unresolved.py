"""A 3D point contact smaller than the grid resolves, found without a given contact point, whose
final state overlaps at the region's edge: the run ends "not converged" with the diagnosis (how
small the contact is by Hertz's estimate from the overlap, and what to refine), not only with the
failed edge check. A ball of radius 0.267 m pressed 0.148 mm into a block, finest cells 11 mm:
sqrt(R delta) = 6.3 mm."""

from __future__ import annotations

import json

from ibfem.solver.cli import main


def scene() -> dict:
    r = 0.2666
    materials = [{"name": "steel", "youngs_modulus": 2.0e11, "poissons_ratio": 0.3},
                 {"name": "aluminium", "youngs_modulus": 7.0e10, "poissons_ratio": 0.33}]
    return {
        "name": "small contact", "model": "solid", "solver": {"load_steps": 3},
        "output": {"vtk": False, "plots": False}, "materials": materials,
        "bodies": [
            {"name": "ball", "material": "steel", "element_size": 0.0889,
             "refinement": {"levels": 3, "around": "contact", "radius": 0.0634},
             "shape": {"type": "half_sphere", "center": [0.0, 0.0, r], "radius": r}},
            {"name": "block", "material": "aluminium", "element_size": 0.0889,
             "refinement": {"levels": 3, "around": "contact", "radius": 0.0451},
             "shape": {"type": "box", "min": [-r, -r, -0.3895], "max": [r, r, 0.0]}},
        ],
        "boundary_conditions": [
            {"type": "displacement", "body": "ball", "face": "flat", "value": [0.0, 0.0, -1.482e-4]},
            {"type": "fixed", "body": "block", "face": "z_min"},
        ],
        "contacts": [{"bodies": ["ball", "block"], "type": "frictionless"}],
    }


def test_an_unresolved_contact_is_diagnosed(tmp_path, capsys):
    path = tmp_path / "small.json"
    path.write_text(json.dumps(scene()))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and "smaller than the grid resolves" in err
    assert "Hertz's estimate from the overlap" in err
    assert "inf Pa" not in err and "nan Pa" not in err  # no edge pressure read at a region of size 0


def test_a_region_point_outside_a_body_names_the_body_and_the_cause():
    # a contact region that reaches past a body's material (a ball overhanging a block's edge at
    # the given point): the error says which body and what to check, not "no grid cell"
    from types import SimpleNamespace

    import numpy as np
    import pytest

    from ibfem.solver.contact.band import locate_cells

    body = SimpleNamespace(name="block", grid=SimpleNamespace(locate=lambda x: np.full(len(x), -1), min_size=0.1))
    with pytest.raises(ValueError, match="body 'block'.*outside the body's grid.*bodies meet"):
        locate_cells(body, np.array([[-1.9e-9, 0.0092, 0.0]]), np.array([[0.0, 0.0, 1.0]]))
