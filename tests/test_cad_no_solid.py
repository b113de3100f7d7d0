"""A part with no closed solid (a file of loose faces, as the FreeCAD bevel gear of the real-CAD
files: 53 faces, each its own sheet body) asked for as a solid body: the error says that none of
its bodies bounds a volume, and names the file, instead of asking to choose among them."""

from __future__ import annotations

import pytest

from ibfem.geometry.part import Body, Part
from ibfem.geometry.solids import PartSolid, solid_from_dict


def _loose_faces(n: int) -> Part:
    return Part(bodies={f"B{k}": Body(id=f"B{k}", body_type="SHEET", face_ids=(f"F{k}",)) for k in range(1, n + 1)})


def test_a_part_of_loose_faces_is_no_solid():
    with pytest.raises(ValueError, match="no closed solid: its 3 bodies are all sheet bodies .*bound no volume"):
        PartSolid(_loose_faces(3))


def test_the_scene_error_names_the_file_and_the_key():
    shape = {"type": "step", "path": "gear.step"}
    with pytest.raises(ValueError, match=r"bodies\[0\]\.shape\.body: gear\.step: the part has no closed solid"):
        solid_from_dict(shape, "bodies[0].shape", load_part=lambda d: _loose_faces(53))


def test_a_sheet_body_chosen_by_id_is_still_named():
    with pytest.raises(ValueError, match="body 'B2' .*is a sheet body"):
        PartSolid(_loose_faces(3), "B2")
