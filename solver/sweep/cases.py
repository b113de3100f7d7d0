"""The cases of a sweep: expansion (grid / zip / list), the hash that keys each case's record,
each case's scene data, and its validation by the scene loader before anything runs."""

from __future__ import annotations

import hashlib
import itertools
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .paths import PathError, set_path
from .spec import Sweep

#: a case's files travel with it up to this size (a remote worker cannot read the driver's disk)
MAX_SENT_BYTES = 64 * 2**20


@dataclass
class Case:
    index: int
    params: dict[str, Any]
    hash: str
    scene: dict = field(default_factory=dict)
    status: str = ""            # "" (to run) or "invalid"
    message: str = ""

    @property
    def label(self) -> str:
        return f"case {self.index} ({self.hash})"


def canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), default=str)


def case_hash(params: dict[str, Any]) -> str:
    """The key of a case's record: a hash of its parameters (paths and values)."""
    return hashlib.sha256(canonical(params).encode()).hexdigest()[:16]


def scene_digest(base: dict) -> str:
    """A hash of the base scene (with the sweep's ``set``): records of another base are not reused."""
    return hashlib.sha256(canonical(base).encode()).hexdigest()[:16]


def expand(sweep: Sweep) -> list[dict[str, Any]]:
    """The parameter sets, in order: grid = product (the last parameter varying fastest),
    zip = the lists side by side, list = the ``[[sweep.cases]]`` tables."""
    if sweep.mode == "list":
        return [dict(c) for c in sweep.cases]
    keys = list(sweep.parameters)
    columns = [sweep.parameters[k] for k in keys]
    rows = itertools.product(*columns) if sweep.mode == "grid" else zip(*columns)
    return [dict(zip(keys, row)) for row in rows]


def case_scene(base: dict, params: dict[str, Any]) -> dict:
    data = json.loads(json.dumps(base))
    for key, value in params.items():
        set_path(data, key, value)
    return data


def build_cases(sweep: Sweep, validate: bool = True) -> list[Case]:
    """Every case with its scene data; with ``validate`` each scene goes through the scene
    loader and a case that fails is marked ``invalid`` with the loader's message."""
    from ibfem.solver.io.scene import SceneError, scene_from_dict

    cases, seen = [], {}
    for i, params in enumerate(expand(sweep)):
        h = case_hash(params)
        if h in seen:
            case = Case(i, params, h, status="invalid", message=f"the same parameters as case {seen[h]}")
            cases.append(case)
            continue
        seen[h] = i
        case = Case(i, params, h)
        try:
            case.scene = case_scene(sweep.base, params)
        except PathError as err:
            case.status, case.message = "invalid", f"{sweep.label}: {err}"
        if validate and not case.status:
            label = f"{sweep.label} case {i}"
            try:
                scene_from_dict(json.loads(json.dumps(case.scene)), label=label, base_dir=sweep.base_dir)
            except SceneError as err:
                case.status, case.message = "invalid", str(err).replace("\n", "; ")
        cases.append(case)
    return cases


def referenced_files(scene: dict) -> list[tuple[dict, str]]:
    """(shape dict, path) for every shape that reads a file (``onshape`` / ``step`` parts)."""
    found = []
    for body in scene.get("bodies", []) if isinstance(scene.get("bodies"), list) else []:
        shape = body.get("shape") if isinstance(body, dict) else None
        if isinstance(shape, dict) and isinstance(shape.get("path"), str):
            found.append((shape, shape["path"]))
    return found


def _pack_one(src: Path, ref: str, files: dict[str, bytes], name: str, base_dir: Path) -> str:
    if src.is_file():
        files[f"{ref}/{src.name}"] = src.read_bytes()
        return f"{ref}/{src.name}"
    members = sorted(p for p in src.rglob("*") if p.is_file()) if src.is_dir() else []
    if not members:
        raise FileNotFoundError(f"shape.path = {name!r}: no such file or directory under {base_dir}")
    for p in members:
        files[f"{ref}/{p.relative_to(src).as_posix()}"] = p.read_bytes()
    return ref


def pack_files(scene: dict, base_dir: Path) -> dict[str, bytes]:
    """Put the files the scene reads into the case (relative names ``ref<k>/...``) and point
    the scene at them; the worker writes them out and loads the scene from there."""
    files: dict[str, bytes] = {}
    sent: dict[Path, str] = {}  # a file or directory read by several shapes travels once
    for shape, name in referenced_files(scene):
        src = (Path(name) if Path(name).is_absolute() else base_dir / name).resolve()
        if src not in sent:
            sent[src] = _pack_one(src, f"ref{len(sent)}", files, name, base_dir)
        shape["path"] = sent[src]
    total = sum(len(b) for b in files.values())
    if total > MAX_SENT_BYTES:
        raise ValueError(f"the scene's files are {total / 2**20:.0f} MB, more than the {MAX_SENT_BYTES // 2**20} MB "
                         "a case may carry to a remote worker; put them on a disk the workers share and "
                         "pass --shared-files")
    return files
