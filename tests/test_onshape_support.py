"""Shared helpers of the Onshape importer tests (no tests here): fixture paths, the fixture
generator module, and which fixtures need primitives that may not be registered yet."""

from __future__ import annotations

import importlib.util
import json
import shutil
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "fixtures" / "onshape"
STUDIOS = sorted(p.name for p in FIXTURES.iterdir() if (p / "bodydetails.json").is_file())


@lru_cache(maxsize=None)
def generator():
    """fixtures/onshape/make_fixtures.py as a module."""
    spec = importlib.util.spec_from_file_location("make_fixtures", FIXTURES / "make_fixtures.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["make_fixtures"] = mod  # dataclasses look their module up there
    spec.loader.exec_module(mod)
    return mod


def registered(name: str) -> bool:
    from ibfem.geometry._base import _REGISTRY

    return name in _REGISTRY


def needs(studio: str) -> list[str]:
    """Primitive types a studio's exact faces/edges need (from its body details)."""
    text = (FIXTURES / studio / "bodydetails.json").read_text()
    out = []
    if '"BCURVE"' in text or '"bcurve"' in text:
        out.append("bspline_curve")
    if '"SWEEP"' in text or '"extruded"' in text:
        out += ["sweep", "bspline_curve"]
    if '"ELLIPSE"' in text or '"ellipse"' in text:
        out.append("ellipse")
    return out


def missing_primitives(studio: str) -> list[str]:
    return [n for n in needs(studio) if not registered(n)]


def copy_studio(studio: str, dest: Path) -> Path:
    target = dest / studio
    shutil.copytree(FIXTURES / studio, target)
    return target


def edit_json(path: Path, fn) -> None:
    data = json.loads(path.read_text())
    fn(data)
    path.write_text(json.dumps(data))


def body_volume(part, body_id: str) -> float:
    """Signed volume enclosed by a body's face meshes (divergence theorem over the
    triangles, each face wound outward): positive when every face points out."""
    total = 0.0
    for fid in part.bodies[body_id].face_ids:
        m = part.faces[fid].mesh
        P = np.asarray(m.vertices)[np.asarray(m.faces)]
        total += float(np.einsum("ij,ij->i", P[:, 0], np.cross(P[:, 1], P[:, 2])).sum()) / 6.0
    return total


@lru_cache(maxsize=None)
def cached_part(studio: str):
    """load_part of a shipped fixture, loaded once per test session (do not mutate it)."""
    from ibfem.importers.onshape import load_part

    return load_part(FIXTURES / studio)
