"""The sweep file: pydantic models, and :func:`load_sweep` which reads it with
its base scene.

```toml
[sweep]
name = "friction and load"
scene = "cylinder_on_flat_partial_slip.toml"     # relative to this file
mode = "grid"                                    # "grid" (product), "zip" (side by side), "list"
set = { "output.vtk" = false }                   # optional: the same change in every case

[sweep.parameters]
"contacts.0.friction" = [0.1, 0.2, 0.3]
"boundary_conditions.cylinder/flat.value.1" = { start = -1e-3, stop = -4e-3, num = 4 }

[sweep.outputs]
columns = ["converged", "contacts.0.half_width"]
```

``mode = "list"`` takes ``[[sweep.cases]]`` tables instead of parameters, each a table of
path = value. A linspace is ``{ start, stop, num }`` (both ends included; ``scale = "log"``
spaces the values geometrically).
"""

from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .paths import PathError, set_path, split_path


class SweepError(ValueError):
    """An invalid sweep file: one line per problem, each naming the file, key path and value."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


class Linspace(BaseModel):
    model_config = ConfigDict(extra="forbid")
    start: float
    stop: float
    num: int = Field(ge=1, le=100_000)
    scale: Literal["linear", "log"] = "linear"

    def values(self) -> list[float]:
        import numpy as np

        if self.scale == "log":
            if self.start <= 0 or self.stop <= 0:
                raise ValueError("a log scale needs start and stop > 0")
            return [float(v) for v in np.geomspace(self.start, self.stop, self.num)]
        return [float(v) for v in np.linspace(self.start, self.stop, self.num)]


class Outputs(BaseModel):
    model_config = ConfigDict(extra="forbid")
    columns: list[str] = Field(default_factory=lambda: ["converged"])


class SweepSection(BaseModel):
    model_config = ConfigDict(extra="forbid")
    name: str = ""
    scene: str
    mode: Literal["grid", "zip", "list"] = "grid"
    parameters: dict[str, list[Any] | Linspace] = Field(default_factory=dict)
    cases: list[dict[str, Any]] = Field(default_factory=list)
    set: dict[str, Any] = Field(default_factory=dict)
    outputs: Outputs = Field(default_factory=Outputs)

    @field_validator("parameters")
    @classmethod
    def _non_empty_lists(cls, value: dict) -> dict:
        for key, v in value.items():
            if isinstance(v, list) and not v:
                raise ValueError(f"parameter {key!r} has no values")
        return value


class SweepFile(BaseModel):
    model_config = ConfigDict(extra="forbid")
    sweep: SweepSection


@dataclass
class Sweep:
    """A validated sweep: its base scene data, the parameter values per path, the columns."""

    label: str                      # the sweep file's name in messages
    path: Path | None
    name: str
    mode: str
    scene_path: Path
    base: dict                      # the base scene data with ``set`` applied
    parameters: dict[str, list[Any]]  # grid / zip: path -> values
    cases: list[dict[str, Any]]     # list mode: the cases as given
    columns: list[str]

    @property
    def base_dir(self) -> Path:
        return self.scene_path.parent


def _show(value: Any) -> str:
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _pydantic_lines(label: str, err: ValidationError, data: Any) -> list[str]:
    lines = []
    for e in err.errors():
        loc = ".".join(f'"{x}"' if isinstance(x, str) and "." in x else str(x) for x in e["loc"]
                       if not (isinstance(x, str) and x in ("list[any]", "Linspace")))
        shown = "" if e["type"] == "missing" else f" = {_show(e.get('input'))}"
        lines.append(f"{label}: {loc}{shown}: {e['msg']}")
    return list(dict.fromkeys(lines))


def _read_toml(path: Path, label: str) -> dict:
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise SweepError([f"{path}: cannot read ({err.strerror or err})"]) from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise SweepError([f"{label}: not valid TOML: {err}"]) from None


def _read_scene_data(path: Path, label: str) -> dict:
    if not path.is_file():
        raise SweepError([f"{label}: sweep.scene = {_show(str(path))}: no such scene file"])
    if path.suffix.lower() == ".json":
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as err:
            raise SweepError([f"{label}: sweep.scene = {_show(str(path))}: cannot read JSON: {err}"]) from None
    return _read_toml(path, str(path))


def _parameter_values(section: SweepSection, label: str) -> tuple[dict[str, list[Any]], list[str]]:
    values, problems = {}, []
    for key, spec in section.parameters.items():
        try:
            values[key] = spec.values() if isinstance(spec, Linspace) else list(spec)
        except ValueError as err:
            problems.append(f'{label}: sweep.parameters."{key}" = {_show(spec.model_dump())}: {err}')
    if section.mode in ("grid", "zip") and not section.parameters:
        problems.append(f"{label}: sweep.parameters: mode = {section.mode!r} needs at least one parameter")
    if section.mode == "zip" and len({len(v) for v in values.values()}) > 1:
        sizes = ", ".join(f'"{k}": {len(v)}' for k, v in values.items())
        problems.append(f"{label}: sweep.parameters: mode = 'zip' needs lists of one length, got {sizes}")
    if section.mode == "list":
        if section.parameters:
            problems.append(f"{label}: sweep.parameters: mode = 'list' takes [[sweep.cases]] instead")
        if not section.cases:
            problems.append(f"{label}: sweep.cases: mode = 'list' needs at least one [[sweep.cases]] table")
    elif section.cases:
        problems.append(f"{label}: sweep.cases: only for mode = 'list' (mode is {section.mode!r})")
    return values, problems


def _check_paths(base: dict, section: SweepSection, values: dict, label: str) -> list[str]:
    """Every parameter path must lead somewhere in the base scene (values are checked per case)."""
    problems = []
    keys = [("sweep.parameters", k, v[0] if v else None) for k, v in values.items()]
    keys += [(f"sweep.cases.{i}", k, v) for i, case in enumerate(section.cases) for k, v in case.items()]
    for where, key, value in keys:
        trial = json.loads(json.dumps(base))
        try:
            set_path(trial, key, value)
        except PathError as err:
            problems.append(f'{label}: {where}."{key}": {err}')
    for column in section.outputs.columns:
        try:
            split_path(column)
        except PathError as err:
            problems.append(f"{label}: sweep.outputs.columns: {err}")
    return problems


def sweep_from_dict(data: Any, label: str = "sweep", base_dir: str | Path = ".", path: Path | None = None) -> Sweep:
    """Validate sweep data (the parsed file); relative scene paths are taken from ``base_dir``."""
    try:
        section = SweepFile.model_validate(data).sweep
    except ValidationError as err:
        raise SweepError(_pydantic_lines(label, err, data)) from None
    scene_path = Path(section.scene)
    scene_path = scene_path if scene_path.is_absolute() else Path(base_dir) / scene_path
    base = _read_scene_data(scene_path, label)
    problems = []
    for key, value in section.set.items():
        try:
            set_path(base, key, value)
        except PathError as err:
            problems.append(f'{label}: sweep.set."{key}": {err}')
    values, more = _parameter_values(section, label)
    problems += more
    if not problems:
        problems += _check_paths(base, section, values, label)
    if problems:
        raise SweepError(problems)
    return Sweep(label=label, path=path, name=section.name or (path.stem if path else label), mode=section.mode,
                 scene_path=scene_path, base=base, parameters=values, cases=[dict(c) for c in section.cases],
                 columns=list(section.outputs.columns))


def load_sweep(path: str | Path) -> Sweep:
    """Read and validate a sweep file (TOML) and its base scene."""
    path = Path(path)
    label = path.name
    return sweep_from_dict(_read_toml(path, label), label=label, base_dir=path.parent, path=path)
