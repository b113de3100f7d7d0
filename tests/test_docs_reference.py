"""The scene-file reference (docs/scene-reference.md) is complete: every key the scene loader
accepts, every shape type with its keys and edge or face names, every choice of a numerical option
and every exit code of ``ibfem run`` appears on the page. The sets come from the code (the pydantic
models of the file, the shape builders, the options' allowed values), so a key added to the code
without its documentation fails here."""

from __future__ import annotations

import re
import typing
from pathlib import Path

import pytest
from pydantic import BaseModel

from ibfem.geometry import shapes as shapes2d
from ibfem.geometry.solids import build as solids3d
from ibfem.importers.part_profile import SHAPE_KEYS as CAD_SHAPE_KEYS
from ibfem.solver.io.scene import SceneSpec
from ibfem.solver.io.scene_solid import SolidSceneSpec
from ibfem.solver.model import options

PAGE = Path(__file__).resolve().parents[1] / "docs" / "scene-reference.md"


@pytest.fixture(scope="module")
def documented() -> set[str]:
    """Every `code span` of the page's text, outside its example blocks (and each word inside
    a span, for spans like `min = [x, y]`)."""
    text = re.sub(r"^```.*?^```", "", PAGE.read_text(), flags=re.M | re.S)
    spans = re.findall(r"`([^`\n]+)`", text)
    words = {w for s in spans for w in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", s)}
    return set(spans) | words


def _models(annotation) -> list[type[BaseModel]]:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [m for arg in typing.get_args(annotation) for m in _models(arg)]


def _keys(model: type[BaseModel], seen: set) -> set[str]:
    if model in seen:
        return set()
    seen.add(model)
    keys = set()
    for name, field in model.model_fields.items():
        keys.add(name)
        for sub in _models(field.annotation):
            keys |= _keys(sub, seen)
    return keys


@pytest.mark.parametrize("spec", [SceneSpec, SolidSceneSpec], ids=["2D", "3D"])
def test_every_scene_key_is_documented(spec, documented):
    missing = sorted(_keys(spec, set()) - documented)
    assert not missing, f"keys of {spec.__name__} missing from {PAGE.name}: {missing}"


def test_every_shape_type_and_key_is_documented(documented):
    kinds = set(shapes2d.SHAPE_TYPES) | set(solids3d.SOLID_TYPES) | set(solids3d.IMPORTED)
    keys = set().union(*shapes2d._KEYS.values(), shapes2d._COMMON, solids3d._COMMON, CAD_SHAPE_KEYS)
    for required, optional in solids3d._KEYS.values():
        keys |= required | optional
    missing = sorted((kinds | keys) - documented)
    assert not missing, f"shape types or keys missing from {PAGE.name}: {missing}"


def test_every_edge_and_face_name_is_documented(documented):
    profiles = [
        {"type": "rectangle", "min": [0, 0], "max": [1, 1]},
        {"type": "disk", "center": [0, 0], "radius": 1},
        {"type": "half_disk", "center": [0, 0], "radius": 1, "side": "below"},
        {"type": "half_ellipse", "center": [0, 0], "semi_axes": [1, 2], "side": "above"},
    ]
    names = {name for d in profiles for name in shapes2d.profile_from_shape(d).edge_names}
    solids = [
        {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]},
        {"type": "sphere", "center": [0, 0, 0], "radius": 1},
        {"type": "half_sphere", "center": [0, 0, 0], "radius": 1},
        {"type": "ellipsoid", "center": [0, 0, 0], "semi_axes": [1, 2, 3]},
        {"type": "half_ellipsoid", "center": [0, 0, 0], "semi_axes": [1, 2, 3]},
        {"type": "cylinder", "center": [0, 0, 0], "axis": [0, 0, 1], "radius": 1, "length": 2},
        {"type": "half_cylinder", "center": [0, 0, 0], "axis": [1, 0, 0], "radius": 1, "length": 2},
    ]
    names |= {face for d in solids for face in solids3d.solid_from_dict(d).faces}
    missing = sorted(names - documented)
    assert not missing, f"edge or face names missing from {PAGE.name}: {missing}"


def test_every_option_choice_is_documented(documented):
    choices = (set(options.WIDTH_UPDATES) | set(options.FLUXES) | set(options.CONTACT_NORMALS)
               | set(options.REGION_CENTRES) | set(options.LINEAR_SOLVERS) | set(options.FORMULATION_NAMES))
    missing = sorted(f'"{c}"' for c in choices if f'"{c}"' not in documented)
    assert not missing, f"option values missing from {PAGE.name}: {missing}"


def test_every_exit_code_is_documented():
    from ibfem.solver import cli, commands

    rows = set(re.findall(r"^\| (\d+) \|", PAGE.read_text(), flags=re.M))
    source = Path(commands.__file__).read_text() + Path(cli.__file__).read_text()
    codes = set(re.findall(r"return (\d+)\b", source)) | {str(cli.INTERNAL_ERROR), str(cli.OUT_OF_MEMORY)}
    assert codes <= rows, f"exit codes missing from {PAGE.name}: {sorted(codes - rows)}"
