"""Scene files: TOML, or JSON with the same structure, validated into
pydantic models and turned into a :class:`solver.model.problem.Problem`.

Validation happens in three stages, all before any assembly, and every error names the
file, the key path and the offending value (``scene.toml: bodies[1].material = "stel":
unknown material (known: steel)``):

1. structure and values (pydantic): unknown keys, types, E > 0, -1 < nu < 0.5, sizes > 0,
   "free" displacement components, refinement levels and radii, friction, output probes/lines;
2. references: unique names, known materials, bodies and edges, one essential condition per
   edge, contacts between two distinct bodies, ``around = "contact"`` only with a contact;
3. geometry: each shape built into an exact profile, the grid not coarser than the body,
   probes inside a body, and no body left with rigid-body motion (:func:`rigid_body_modes`).

The public entry points are :func:`load_scene` (a path) and :func:`scene_from_dict`.
"""

from __future__ import annotations

import dataclasses
import inspect
from importlib import import_module
import json
import math
import re
import tomllib
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    BaseModel,
    BeforeValidator,
    Field,
    ValidationError,
    ValidationInfo,
    create_model,
    field_validator,
)
from pydantic_core import PydanticCustomError

from ibfem.solver.model import problem as pb
from ibfem.solver.model.problem import MAX_REFINEMENT_LEVELS
from ibfem.solver.model.options import ContactOptions, OptionError, SolverOptions
from ibfem.solver.model.resolve import (CONTACT_SEARCH_SPACING, boundary_gap, contact_frame, contact_point,
                                  corner_distance, finest_size_at, resolve_problem)
from ibfem.solver.model.rigid import rigid_body_modes

from .strict_model import StrictTable, integer, number
from .load_paths_spec import PathRef, PathSpec, history_problems, load_history
from .load_axes import AlongAxes, in_global_components
from .scene_reference_point import ReferencePoint2Spec, reference_point

__all__ = [
    "SceneError",
    "SceneSpec",
    "Scene",
    "OutputSpec",
    "LineSpec",
    "load_scene",
    "scene_from_dict",
    "rigid_body_modes",
    "MAX_REFINEMENT_LEVELS",
    "COARSE_GRID_RATIO",
]

#: element_size may be at most this fraction of the body's smallest bounding-box dimension
COARSE_GRID_RATIO = 0.5


#: every character str.splitlines() breaks at -> its escape (a problem is printed as one line)
_LINE_BREAKS = {ord(c): c.encode("unicode_escape").decode() for c in "\n\r\v\f\x1c\x1d\x1e\x85\u2028\u2029"}


class SceneError(ValueError):
    """A scene that cannot be solved. ``str(err)`` is one line per problem found, each
    ``FILE: KEY.PATH = VALUE: what is wrong``."""

    def __init__(self, problems: list[str]):
        # one line per problem, whatever a value or key held (a newline in a key name)
        self.problems = [str(p).translate(_LINE_BREAKS) for p in problems]
        super().__init__("\n".join(self.problems))


# ---------------------------------------------------------------------------------------
# pydantic models of the file
# ---------------------------------------------------------------------------------------


_Strict = StrictTable


def _component(v: Any) -> Any:
    """A displacement component: a number or the string "free" (-> None)."""
    if isinstance(v, str):
        if v.strip().lower() == "free":
            return None
        raise PydanticCustomError("free_or_number", 'must be a number or "free"')
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise PydanticCustomError("free_or_number", 'must be a number or "free"')
    return v


_number = number
_integer = integer


def _boolean(v: Any) -> Any:
    if not isinstance(v, bool):  # "yes", 1, "true" are not true
        raise PydanticCustomError("boolean", "must be true or false")
    return v


Num = Annotated[float, BeforeValidator(_number)]
Int = Annotated[int, BeforeValidator(_integer)]
Bool = Annotated[bool, BeforeValidator(_boolean)]
#: the scene types of the options dataclasses' fields (strict: no strings for numbers, no "yes")
_STRICT_TYPES = {float: Num, int: Int, bool: Bool, float | None: Num | None, int | None: Int | None}
Vec2 = tuple[Num, Num]
Component = Annotated[Union[float, None], BeforeValidator(_component)]


def _fields_of(options: type, base: type[BaseModel], name: str) -> type[BaseModel]:
    """``base`` with a field for every option of the dataclass ``options`` that ``base`` does
    not declare (its type and default): every option the solver has is reachable from a scene,
    and its range is checked once, by the dataclass (see :func:`_options`)."""
    hints = typing.get_type_hints(options)
    extra = {
        f.name: (_STRICT_TYPES.get(hints[f.name], hints[f.name]), f.default)
        for f in dataclasses.fields(options)
        if f.name not in base.model_fields and f.default is not dataclasses.MISSING
    }
    return create_model(name, __base__=base, **extra)


class _SolverBase(_Strict):
    exact_geometry: Bool = True


SolverSpec = _fields_of(SolverOptions, _SolverBase, "SolverSpec")


class MaterialSpec(_Strict):
    name: str = Field(min_length=1)
    youngs_modulus: Num
    poissons_ratio: Num

    @field_validator("youngs_modulus")
    @classmethod
    def _e_positive(cls, v: float) -> float:
        if not v > 0.0:
            raise PydanticCustomError("modulus", "must be positive (Pa)")
        return v

    @field_validator("poissons_ratio")
    @classmethod
    def _nu_range(cls, v: float) -> float:
        if not -1.0 < v < 0.5:
            raise PydanticCustomError(
                "poisson", "must lie in (-1, 0.5): 0.5 is incompressible, outside is not elastic"
            )
        return v


def _around(v: Any) -> Any:
    """``"contact"`` or a point [x, y]."""
    if isinstance(v, str):
        if v == "contact":
            return v
    elif isinstance(v, (list, tuple)) and len(v) == 2 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c) for c in v
    ):
        return (float(v[0]), float(v[1]))
    raise PydanticCustomError("around", 'must be "contact" or a point [x, y]')


class RefinementSpec(_Strict):
    levels: Int = Field(ge=1, le=MAX_REFINEMENT_LEVELS)
    around: Annotated[Union[Literal["contact"], tuple[float, float]], BeforeValidator(_around)]
    radius: Num = Field(gt=0.0)


class BodySpec(_Strict):
    name: str = Field(min_length=1)
    material: str
    element_size: Num = Field(gt=0.0)
    refinement: list[RefinementSpec] = []
    shape: dict[str, Any]

    @field_validator("refinement", mode="before")
    @classmethod
    def _one_or_many(cls, v: Any) -> Any:
        return [v] if isinstance(v, dict) else v

    @field_validator("shape")
    @classmethod
    def _shape_type(cls, v: dict[str, Any]) -> dict[str, Any]:
        if "type" not in v:
            raise PydanticCustomError("shape_type", "missing key 'type'")
        if not isinstance(v["type"], str):
            raise PydanticCustomError("shape_type", "shape.type must be a string (the shape's type name)")
        return v


class FixedSpec(_Strict):
    type: Literal["fixed"]
    body: str
    edge: str


class DisplacementSpec(AlongAxes):
    type: Literal["displacement"]
    body: str
    edge: str
    value: tuple[Component, Component]
    path: PathRef | None = None  # load path name(s): docs/load-paths.md
    axes: tuple[Vec2, Vec2] | None = None  # value and path along these directions

    @field_validator("value")
    @classmethod
    def _not_all_free(cls, v: tuple) -> tuple:
        if v[0] is None and v[1] is None:
            raise PydanticCustomError("all_free", "both components free: nothing is prescribed")
        return v


class SlidingSpec(_Strict):
    type: Literal["sliding"]
    body: str
    edge: str
    normal_displacement: Num = 0.0
    path: PathRef | None = None  # load path name(s): docs/load-paths.md


class TractionSpec(AlongAxes):
    type: Literal["traction"]
    body: str
    edge: str
    value: Vec2
    path: PathRef | None = None  # load path name(s): docs/load-paths.md
    axes: tuple[Vec2, Vec2] | None = None  # value and path along these directions


class PressureSpec(_Strict):
    type: Literal["pressure"]
    body: str
    edge: str
    value: Num
    path: PathRef | None = None  # load path name(s): docs/load-paths.md


class BodyForceSpec(AlongAxes):
    type: Literal["body_force"]
    body: str
    value: Vec2
    path: PathRef | None = None  # load path name(s): docs/load-paths.md
    axes: tuple[Vec2, Vec2] | None = None  # value and path along these directions


BoundaryConditionSpec = Annotated[
    Union[FixedSpec, DisplacementSpec, SlidingSpec, TractionSpec, PressureSpec, BodyForceSpec, ReferencePoint2Spec],
    Field(discriminator="type"),
]
_BC_TYPES = ("fixed", "displacement", "sliding", "traction", "pressure", "body_force", "reference_point")
_ESSENTIAL = (FixedSpec, DisplacementSpec, SlidingSpec)


class _ContactBase(_Strict):
    bodies: tuple[str, str]
    type: Literal["tied", "frictionless", "frictional"]
    friction: Num = Field(0.0, ge=0.0, validate_default=True)
    point: Vec2 | None = None

    @field_validator("friction")
    @classmethod
    def _friction_fits_type(cls, v: float, info: ValidationInfo) -> float:
        kind = info.data.get("type")
        if kind == "frictional" and not v > 0.0:
            raise PydanticCustomError("friction", 'type = "frictional" needs friction > 0')
        if kind in ("tied", "frictionless") and v != 0.0:
            raise PydanticCustomError(
                "friction", 'only used by type = "frictional" (this contact is "{type}")', {"type": kind}
            )
        return v


ContactSpec = _fields_of(ContactOptions, _ContactBase, "ContactSpec")


class LineSpec(_Strict):
    name: str = Field(min_length=1)
    start: Vec2
    end: Vec2
    n: Int = Field(100, ge=2, le=100_000)

    @field_validator("end")
    @classmethod
    def _not_degenerate(cls, v: tuple, info: ValidationInfo) -> tuple:
        if info.data.get("start") == v:
            raise PydanticCustomError("line", "start and end coincide")
        return v


class OutputSpec(_Strict):
    vtk: Bool = True
    plots: Bool = False
    probes: list[Vec2] = []
    lines: list[LineSpec] = []

    @field_validator("lines")
    @classmethod
    def _unique_lines(cls, v: list[LineSpec]) -> list[LineSpec]:
        names = [ln.name for ln in v]
        for name in names:
            if names.count(name) > 1:
                raise PydanticCustomError("duplicate", 'line name "{name}" used twice', {"name": name})
        return v


class SceneSpec(_Strict):
    name: str | None = None
    description: str = ""
    model: Literal["plane_strain", "plane_stress"] = "plane_strain"
    thickness: Num = Field(1.0, gt=0.0)
    solver: SolverSpec = SolverSpec()
    materials: list[MaterialSpec] = Field(min_length=1)
    bodies: list[BodySpec] = Field(min_length=1)
    boundary_conditions: list[BoundaryConditionSpec] = []
    contacts: list[ContactSpec] = []
    output: OutputSpec = OutputSpec()
    paths: list[PathSpec] = []


# ---------------------------------------------------------------------------------------
# the loaded scene
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Scene:
    """A validated scene: the file's models, the solver's :class:`Problem`, and notes
    (suspicious but legal values, e.g. a modulus that looks like GPa)."""

    path: Path | None
    spec: SceneSpec
    problem: pb.Problem
    warnings: tuple[str, ...] = ()

    @property
    def output(self) -> OutputSpec:
        return self.spec.output

    @property
    def name(self) -> str:
        return self.problem.name


#: scene models read by other modules of this layer, which register their loader here when
#: imported: "solid" -> solver.io.scene_solid.solid_scene_from_dict
SCENE_MODELS: dict[str, Any] = {}

#: the module that registers each of those models, imported when a scene first names the model
#: (so that importing this package loads no 3D numerics)
MODEL_MODULES = {"solid": "ibfem.solver.io.scene_solid"}


def _model_loader(model: Any):
    """The registered loader of a scene's ``model`` (its module imported on first use), or None
    for the 2D models this module reads itself."""
    if not isinstance(model, str):
        return None
    if model not in SCENE_MODELS and model in MODEL_MODULES:
        import_module(MODEL_MODULES[model])
    return SCENE_MODELS.get(model)


def load_scene(
    source: str | Path | dict, label: str | None = None, base_dir: str | Path | None = None
) -> Scene:
    """Read and validate a TOML (or JSON, by extension ``.json``) scene file, or a scene given
    as parsed data (a dict: ``label`` names it in errors, relative paths are taken from
    ``base_dir``, default the working directory).

    :raises SceneError: the file cannot be read or parsed, or the scene is invalid; one line
        per problem, each naming the file, the key path and the value."""
    if isinstance(source, dict):
        return scene_from_dict(source, label=label or "scene", base_dir=base_dir or ".")
    path = Path(source)
    label = label or path.name
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise SceneError([f"{path}: cannot read scene file ({err.strerror or err})"]) from None
    data = parse_scene_text(raw, label, json_file=path.suffix.lower() == ".json")
    return scene_from_dict(data, label=label, base_dir=path.parent if base_dir is None else base_dir, path=path)


def parse_scene_text(raw: bytes, label: str, json_file: bool = False) -> Any:
    """The parsed TOML (JSON) of a scene file's bytes; every failure a SceneError naming the
    file: not UTF-8 (a leading byte-order mark is allowed), invalid syntax, numbers with more
    digits than Python converts, nesting too deep for the parser."""
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise SceneError([f"{label}: not a UTF-8 text file (byte 0x{raw[err.start]:02x} at offset {err.start}); "
                          "save it as UTF-8"]) from None
    try:
        return json.loads(text) if json_file else tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SceneError([f"{label}: invalid TOML: {err}"]) from None
    except json.JSONDecodeError as err:
        raise SceneError([f"{label}: invalid JSON: {err.msg} (line {err.lineno}, column {err.colno})"]) from None
    except RecursionError:
        raise SceneError([f"{label}: nested too deeply to read (arrays or tables inside each other "
                          f"more than {MAX_NESTING} levels deep)"]) from None
    except ValueError as err:  # e.g. an integer of more than 4300 digits
        raise SceneError([f"{label}: cannot read a value: {str(err).split(';')[0]}"]) from None


#: a scene nests tables and arrays at most this deep (a profile's edges: 5)
MAX_NESTING = 32
#: numbers in a scene are at most this large in magnitude (SI units; beyond it products of two
#: of them overflow double precision in the solver)
MAX_MAGNITUDE = 1e20


def _input_problems(data: Any, label: str) -> list[str]:
    """Nesting deeper than MAX_NESTING and numbers beyond MAX_MAGNITUDE (or non-finite), with
    their key paths; iterative, so no recursion limit is reached on any input."""
    problems: list[str] = []
    stack: list[tuple[Any, tuple]] = [(data, ())]
    while stack and len(problems) < 10:
        value, loc = stack.pop()
        if len(loc) > MAX_NESTING:
            problems.append(f"{label}: {_key_path(loc[:4])}...: nested more than {MAX_NESTING} levels deep")
            break
        if isinstance(value, dict):
            stack.extend((v, loc + (str(k),)) for k, v in value.items())
        elif isinstance(value, list):
            stack.extend((v, loc + (i,)) for i, v in enumerate(value))
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            problem = _number_problem(value)
            if problem:
                problems.append(f"{label}: {_key_path(loc) or '(top level)'} = {problem}")
    return problems


def _number_problem(value: int | float) -> str | None:
    if isinstance(value, int) and value.bit_length() > 128:  # float(value) may overflow
        return (f"an integer of about {int(value.bit_length() * math.log10(2)) + 1} digits: beyond the largest "
                f"number a scene may hold ({MAX_MAGNITUDE:g})")
    if not math.isfinite(value):
        return f"{_show(value)}: input should be a finite number"
    if abs(value) > MAX_MAGNITUDE:
        return f"{_show(value)}: beyond the largest number a scene may hold ({MAX_MAGNITUDE:g}, SI units)"
    return None


def scene_from_dict(
    data: Any, label: str = "scene", base_dir: str | Path = ".", path: Path | None = None
) -> Scene:
    """Validate a scene given as plain data (the parsed file). ``label`` names the file in
    errors; relative paths in the scene (``onshape`` and ``step`` shapes) are taken from
    ``base_dir``.

    :raises SceneError: the scene is invalid; one line per problem, each naming ``label``, the
        key path and the value."""
    if not isinstance(data, dict):
        raise SceneError([f"{label}: the scene must be a table/object, got {type(data).__name__}"])
    problems = _input_problems(data, label)
    if problems:
        raise SceneError(problems)
    loader = _model_loader(data.get("model"))
    if loader is not None:  # e.g. model = "solid": solver/io/scene_solid.py
        return loader(data, label=label, base_dir=Path(base_dir), path=path)
    try:
        spec = SceneSpec.model_validate(data)
    except ValidationError as err:
        raise SceneError(_format_errors(err, data, label)) from None
    _check_references(spec, label)
    if history_problems(spec.paths, spec.boundary_conditions, label):
        raise SceneError(history_problems(spec.paths, spec.boundary_conditions, label))
    spec = in_global_components(spec, 2)
    profiles = _build_profiles(spec, label, Path(base_dir))
    problem = _problem(spec, profiles, Path(label).stem if path is None else path.stem, label)
    try:
        problem = resolve_problem(problem)
    except ValueError as err:
        raise SceneError([f"{label}: {err}"]) from None
    _check_geometry(spec, problem, label)
    return Scene(path=path, spec=spec, problem=problem, warnings=tuple(_notes(spec, label)))


# ---------------------------------------------------------------------------------------
# error messages
# ---------------------------------------------------------------------------------------


_PLAIN_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")


def _show(value: Any, limit: int = 80) -> str:
    try:
        text = json.dumps(value, default=str, allow_nan=True)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _key_path(loc: tuple) -> str:
    out = ""
    for item in loc:
        if isinstance(item, int):
            out += f"[{item}]"
        elif _PLAIN_KEY.fullmatch(str(item)):
            out += ("." if out else "") + str(item)
        else:  # a key with spaces, newlines or other characters: quoted, on one line
            out += f"[{json.dumps(str(item))}]"
    return out


def _lookup(data: Any, loc: tuple) -> tuple[bool, Any]:
    for item in loc:
        if item == 0 and isinstance(data, dict):  # a single table given where a list is allowed
            continue
        try:
            data = data[item]
        except (KeyError, IndexError, TypeError):
            return False, None
    return True, data


def _clean_loc(loc: tuple) -> tuple:
    """Drop pydantic's union tags (``boundary_conditions[0].fixed.edge`` ->
    ``boundary_conditions[0].edge``) and its internal step names."""
    out: list = []
    for i, item in enumerate(loc):
        if isinstance(item, str) and i >= 2 and loc[i - 2] == "boundary_conditions" and isinstance(loc[i - 1], int):
            if item in _BC_TYPES:
                continue
        if isinstance(item, str) and (item.startswith("function-") or item in ("literal['contact']",)):
            continue
        out.append(item)
    return tuple(out)


def _format_errors(err: ValidationError, data: Any, label: str) -> list[str]:
    problems: list[str] = []
    for e in err.errors(include_url=False):
        loc = _clean_loc(tuple(e["loc"]))
        kind = e["type"]
        ctx = e.get("ctx") or {}
        msg = e["msg"]
        if kind == "unknown_key":
            loc = loc + (ctx["key"],)
            msg = f"unknown key (known: {ctx['known']})"
        elif kind == "missing" and loc and isinstance(loc[-1], int):
            found, value = _lookup(data, loc[:-1])
            problems.append(f"{label}: {_key_path(loc[:-1])} = {_show(value)}: too few components")
            continue
        elif kind == "missing":
            problems.append(f"{label}: {_key_path(loc)}: missing required key")
            continue
        elif kind == "union_tag_invalid":
            loc = loc + ("type",)
            msg = f"unknown type (known: {', '.join(_BC_TYPES)})"
        elif kind == "union_tag_not_found":
            problems.append(f"{label}: {_key_path(loc)}: missing key 'type' (one of: {', '.join(_BC_TYPES)})")
            continue
        elif kind == "literal_error" and loc == ("model",):
            msg = f"input should be {', '.join(repr(m) for m in ('plane_strain', 'plane_stress', *MODEL_MODULES, *(m for m in SCENE_MODELS if m not in MODEL_MODULES)))}"
        elif kind.startswith("value_error") and msg.startswith("Value error, "):
            msg = msg[len("Value error, "):]
        found, value = _lookup(data, loc)
        where = _key_path(loc) or "(top level)"
        if found:
            problems.append(f"{label}: {where} = {_show(value)}: {_lower(msg)}")
        else:
            problems.append(f"{label}: {where}: {_lower(msg)}")
    # a union of "contact" | [x, y] reports both alternatives; keep one line per key path
    seen: set[str] = set()
    unique = []
    for p in problems:
        head = p.split(": ")[1] if ": " in p else p
        if head not in seen:
            seen.add(head)
            unique.append(p)
    return unique


def _lower(msg: str) -> str:
    return msg[:1].lower() + msg[1:] if msg[:2] != msg[:2].upper() else msg


# ---------------------------------------------------------------------------------------
# references between sections
# ---------------------------------------------------------------------------------------


def pair_problems(contacts, label: str) -> list[str]:
    """Two bodies may touch at several places (a pin in a V-groove, a ball between two races'
    shoulders): then each of their contacts needs its own ``point``, and no two the same."""
    problems = []
    seen: dict[frozenset, list[int]] = {}
    for i, c in enumerate(contacts):
        seen.setdefault(frozenset(c.bodies), []).append(i)
    for pair, ids in seen.items():
        if len(ids) < 2:
            continue
        for i in ids:
            if contacts[i].point is None:
                problems.append(f"{label}: contacts[{i}].point: missing; the bodies {_show(list(contacts[i].bodies))} "
                                f"have {len(ids)} contacts (contacts{ids}), and each needs the point where it touches")
        given = [i for i in ids if contacts[i].point is not None]
        for n, i in enumerate(given):
            for j in given[:n]:
                if all(abs(float(a) - float(b)) <= 1e-12 * max(1.0, abs(float(a))) for a, b in zip(contacts[i].point, contacts[j].point)):
                    problems.append(f"{label}: contacts[{i}].point = {_show(list(contacts[i].point))}: the same point "
                                    f"as contacts[{j}] of the same bodies; give each contact of a pair its own point")
    return problems


def _check_references(spec: SceneSpec, label: str) -> None:
    problems: list[str] = []

    def duplicates(items: list[str], where: str) -> None:
        seen: dict[str, int] = {}
        for i, name in enumerate(items):
            if name in seen:
                problems.append(
                    f'{label}: {where}[{i}].name = {_show(name)}: duplicate name (also {where}[{seen[name]}])'
                )
            seen.setdefault(name, i)

    duplicates([m.name for m in spec.materials], "materials")
    duplicates([b.name for b in spec.bodies], "bodies")
    materials = [m.name for m in spec.materials]
    bodies = [b.name for b in spec.bodies]
    for i, b in enumerate(spec.bodies):
        if b.material not in materials:
            problems.append(
                f"{label}: bodies[{i}].material = {_show(b.material)}: unknown material (known: {', '.join(materials)})"
            )
    for i, bc in enumerate(spec.boundary_conditions):
        if bc.body not in bodies:
            problems.append(
                f"{label}: boundary_conditions[{i}].body = {_show(bc.body)}: unknown body (known: {', '.join(bodies)})"
            )
    for i, bc in enumerate(spec.boundary_conditions):
        if isinstance(bc, ReferencePoint2Spec) and spec.paths:
            problems.append(f"{label}: boundary_conditions[{i}]: a reference point does not follow load paths; "
                            "remove [[paths]] or the reference point")
    essential: dict[tuple[str, str], int] = {}
    for i, bc in enumerate(spec.boundary_conditions):
        if isinstance(bc, _ESSENTIAL):
            key = (bc.body, bc.edge)
            if key in essential:
                j = essential[key]
                problems.append(
                    f"{label}: boundary_conditions[{i}].edge = {_show(bc.edge)}: edge {bc.body}/{bc.edge} already has "
                    f"an essential condition (boundary_conditions[{j}]); combine them into one"
                )
            essential.setdefault(key, i)
    problems += pair_problems(spec.contacts, label)
    for i, c in enumerate(spec.contacts):
        for k, name in enumerate(c.bodies):
            if name not in bodies:
                problems.append(
                    f"{label}: contacts[{i}].bodies[{k}] = {_show(name)}: unknown body (known: {', '.join(bodies)})"
                )
        if c.bodies[0] == c.bodies[1]:
            problems.append(f"{label}: contacts[{i}].bodies = {_show(list(c.bodies))}: a contact needs two different bodies")
    in_contact = {name for c in spec.contacts for name in c.bodies}
    for i, b in enumerate(spec.bodies):
        for k, r in enumerate(b.refinement):
            if r.around == "contact" and b.name not in in_contact:
                problems.append(
                    f'{label}: bodies[{i}].refinement[{k}].around = "contact": body "{b.name}" has no contact; '
                    "give a point [x, y] instead"
                )
    if problems:
        raise SceneError(problems)


# ---------------------------------------------------------------------------------------
# geometry
# ---------------------------------------------------------------------------------------


def _build_profiles(spec: SceneSpec, label: str, base_dir: Path) -> dict[str, Any]:
    problems: list[str] = []
    profiles: dict[str, Any] = {}
    for i, b in enumerate(spec.bodies):
        where = f"{label}: bodies[{i}].shape"
        try:
            profiles[b.name] = _profile(dict(b.shape), base_dir, where=f"bodies[{i}].shape")
        except SceneError as err:
            problems.extend(f"{where}: {p}" for p in err.problems)
        except (ValueError, KeyError, TypeError, ArithmeticError) as err:
            text = err.args[0] if isinstance(err, KeyError) and err.args else str(err)
            text = text.replace("shape.type must be one of ", "shape.type must be one of onshape, step, ")
            first, *more = str(text).splitlines() or [type(err).__name__]
            if first.startswith(f"bodies[{i}].shape"):  # the builder named the key path itself
                problems.append(f"{label}: {first}")
            elif first.startswith("shape.") or first.startswith("shape:") or first.startswith("shape "):
                problems.append(f"{label}: bodies[{i}].{first}")
            else:
                problems.append(f"{where} (type {_show(b.shape.get('type'))}): {first}")
            problems += [f"{where}: {line.strip()}" for line in more if line.strip()]  # one line per problem
    if problems:
        raise SceneError(problems)
    return profiles


#: 2D shape types read by an importer (imported only when a scene uses them) -> its module,
#: which provides ``profile_from_shape(shape, where=...)``
IMPORTED_SHAPES = {"onshape": "ibfem.importers.onshape.profile", "step": "ibfem.importers.step.profile"}


def _profile(shape: dict[str, Any], base_dir: Path, where: str = "shape") -> Any:
    """Shape dict -> exact ``geometry`` profile. ``onshape`` and ``step`` shapes are built by
    their importer (imported only then); their ``path`` is relative to the scene file. ``where``
    is the key path the builders put in their error messages."""
    kind = str(shape.get("type", "")).lower()
    if kind in IMPORTED_SHAPES:
        module = IMPORTED_SHAPES[kind]
        try:
            importer = import_module(module)
        except ImportError as err:
            title = {"onshape": "Onshape", "step": "STEP"}.get(kind, kind)
            raise ValueError(f'{where}.type = "{kind}": needs the {title} importer ({module}): {err}') from None
        if "path" in shape:
            p = Path(str(shape["path"]))
            shape["path"] = str(p if p.is_absolute() else (base_dir / p))
        build = getattr(importer, "profile_from_shape", None)
        if build is None:
            raise ValueError(f'{where}.type = "{kind}": {module} has no profile_from_shape')
        if "where" in inspect.signature(build).parameters:
            return build(shape, where=where)
        return build(shape)
    from ibfem.geometry.shapes import profile_from_shape

    return profile_from_shape(shape, where=where)


def _options(kind: type, spec: BaseModel, where: str, label: str) -> Any:
    """The options dataclass ``kind`` from a validated table; its range checks become a
    SceneError naming the key."""
    values = {f.name: getattr(spec, f.name) for f in dataclasses.fields(kind)}
    try:
        return kind(**values)
    except OptionError as err:
        value = values.get(err.key)
        raise SceneError([f"{label}: {where}.{err.key} = {_show(value)}: {str(err)[len(err.key) + 1:]}"]) from None


def _problem(spec: SceneSpec, profiles: dict[str, Any], default_name: str, label: str) -> pb.Problem:
    materials = {
        m.name: pb.Material(name=m.name, youngs_modulus=m.youngs_modulus, poissons_ratio=m.poissons_ratio)
        for m in spec.materials
    }
    bodies = []
    for b in spec.bodies:
        refinements = tuple(
            pb.Refinement(
                levels=r.levels,
                radius=r.radius,
                center=None if r.around == "contact" else _frozen(np.asarray(r.around, dtype=float)),
            )
            for r in b.refinement
        )
        bodies.append(
            pb.BodyModel(
                name=b.name,
                profile=profiles[b.name],
                material=materials[b.material],
                element_size=b.element_size,
                refinements=refinements,
            )
        )
    conditions: list[pb.BoundaryCondition] = []
    for bc in spec.boundary_conditions:
        if isinstance(bc, FixedSpec):
            conditions.append(pb.Fixed(body=bc.body, edge=bc.edge))
        elif isinstance(bc, DisplacementSpec):
            conditions.append(pb.Displacement(body=bc.body, edge=bc.edge, value=(bc.value[0], bc.value[1])))
        elif isinstance(bc, SlidingSpec):
            conditions.append(pb.Sliding(body=bc.body, edge=bc.edge, normal_displacement=bc.normal_displacement))
        elif isinstance(bc, TractionSpec):
            conditions.append(pb.Traction(body=bc.body, edge=bc.edge, value=(bc.value[0], bc.value[1])))
        elif isinstance(bc, PressureSpec):
            conditions.append(pb.Pressure(body=bc.body, edge=bc.edge, value=bc.value))
        elif isinstance(bc, ReferencePoint2Spec):
            conditions.append(reference_point(bc))
        else:
            conditions.append(pb.BodyForce(body=bc.body, value=(bc.value[0], bc.value[1])))
    contacts = tuple(
        pb.ContactModel(
            bodies=(c.bodies[0], c.bodies[1]),
            type=c.type,
            friction=c.friction,
            point=None if c.point is None else _frozen(np.asarray(c.point, dtype=float)),
            options=_options(ContactOptions, c, f"contacts[{i}]", label),
        )
        for i, c in enumerate(spec.contacts)
    )
    options = _options(SolverOptions, spec.solver, "solver", label)
    _plane_option_checks(options, contacts, label, [b.element_size for b in spec.bodies])
    return pb.Problem(
        name=spec.name if spec.name else default_name,
        model=spec.model,
        thickness=spec.thickness,
        bodies=tuple(bodies),
        boundary_conditions=tuple(conditions),
        contacts=contacts,
        options=options,
        history=load_history(spec.paths, spec.boundary_conditions, options.steps_per_unit, options.load_steps),
    )


def _plane_option_checks(options: SolverOptions, contacts: tuple, label: str, sizes: list[float]) -> None:
    """Options valid in 3D only (model = "solid") refused in a plane scene; a tessellation chord
    above the smallest element size (a boundary coarser than the grid)."""
    problems = []
    if options.chord_tolerance is not None and options.chord_tolerance > min(sizes):
        problems.append(f"{label}: solver.chord_tolerance = {_show(options.chord_tolerance)}: above the smallest "
                        f"element size ({min(sizes):.4g}): the tessellated boundary would be coarser than the grid")
    if len(options.grid_offset) != 2:
        problems.append(f"{label}: solver.grid_offset = {_show(list(options.grid_offset))}: a plane scene's grid "
                        "takes two fractions [fx, fy]")
    for k, c in enumerate(contacts):
        if c.options.formulation == "ellipse":
            problems.append(f'{label}: contacts[{k}].formulation = "ellipse": the formulation between solids '
                            '(model = "solid"); plane scenes use "band"')
    if problems:
        raise SceneError(problems)


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def _check_geometry(spec: SceneSpec, problem: pb.Problem, label: str) -> None:
    problems: list[str] = []
    body_index = {b.name: i for i, b in enumerate(spec.bodies)}
    for i, body in enumerate(problem.bodies):
        lo, hi = (np.asarray(v, dtype=float) for v in body.profile.bounds)
        smallest = float(np.min(hi - lo))
        if body.element_size > COARSE_GRID_RATIO * smallest:
            problems.append(
                f"{label}: bodies[{i}].element_size = {_show(body.element_size)}: grid coarser than the body "
                f"(its smallest bounding-box dimension is {smallest:.6g}; element_size must be at most "
                f"{COARSE_GRID_RATIO:g} of it)"
            )
    for i, bc in enumerate(spec.boundary_conditions):
        if isinstance(bc, BodyForceSpec) or bc.body not in body_index:
            continue
        lo, hi = (np.asarray(v, dtype=float) for v in problem.body(bc.body).profile.bounds)
        size = float(np.linalg.norm(hi - lo))
        moves = [v for v in getattr(bc, "value", ()) if v is not None] if isinstance(bc, DisplacementSpec) else []
        moves += [bc.normal_displacement] if isinstance(bc, SlidingSpec) else []
        if moves and max(abs(float(v)) for v in moves) > size:
            problems.append(
                f"{label}: boundary_conditions[{i}]: a prescribed displacement of {max(abs(float(v)) for v in moves):.4g} m "
                f"exceeds the size of body {bc.body!r} ({size:.4g} m): small-strain linear elasticity needs "
                "displacements far below the body's size (a unit typo?)"
            )
        names = list(problem.body(bc.body).profile.edge_names)
        if bc.edge not in names:
            problems.append(
                f'{label}: boundary_conditions[{i}].edge = {_show(bc.edge)}: body "{bc.body}" has no such edge '
                f"(known: {', '.join(names)})"
            )
    if problems:
        raise SceneError(problems)

    if spec.output.probes:
        points = np.asarray(spec.output.probes, dtype=float).reshape(-1, 2)
        inside = np.zeros(len(points), dtype=bool)
        for body in problem.bodies:  # points on a boundary count as inside
            lo, hi = (np.asarray(v, dtype=float) for v in body.profile.bounds)
            tol = 1e-9 * float(np.max(hi - lo))
            inside |= np.asarray(body.profile.signed_distance(points), dtype=float) >= -tol
        for k in np.flatnonzero(~inside):
            problems.append(f"{label}: output.probes[{k}] = {_show(list(spec.output.probes[k]))}: outside every body")

    problems += _contact_point_problems(spec, problem, label)
    problems += size_problems(problem, label)
    if problems:
        raise SceneError(problems)
    contact_frames = [contact_frame(problem, c) for c in problem.contacts]
    modes = rigid_body_modes(problem, contact_frames)
    for name, description in modes.items():
        i = body_index[name]
        problems.append(
            f"{label}: bodies[{i}].name = {_show(name)}: rigid-body motion not prevented ({description}); "
            "add fixed, displacement or sliding conditions, or a contact with a supported body"
        )
    if problems:
        raise SceneError(problems)


def size_problems(problem: pb.Problem, label: str) -> list[str]:
    """The grid must fit in the machine's memory (estimated before anything is built:
    solver.model.estimate); the message says how much it would need."""
    from ibfem.solver.model.estimate import available_memory, estimate_size

    lines = _followed_line_contacts(problem)
    if lines:
        from ibfem.solver.contact.follow import coarse_problem

        problem = coarse_problem(problem, lines)
    size = estimate_size(problem)
    have = available_memory()
    if not size.memory <= have:
        need = size.memory / 2**30
        what = "the coarse pass of its line contacts would need" if lines else "the grids would need"
        return [f"{label}: {what} {need:.3g} GB ({size}) but the machine has {have / 2**30:.3g} GB: "
                "coarsen them (bodies[k].element_size, refinement levels or radii)"]
    return []


def _followed_line_contacts(problem: pb.Problem) -> list[int]:
    """The 3D line contacts whose refinement follows their region: the run builds the scene's
    contact ball two levels shallower (a coarse pass), then a band along the region it finds,
    never the whole ball at the scene's depth. Judging the scene's grid would refuse runs that
    fit; the coarse pass is what is known before a solve (``ibfem run --check`` solves it and
    estimates the band too)."""
    if problem.dim != 3:
        return []
    from ibfem.solver.contact.follow import line_contacts

    try:
        return line_contacts(problem)
    except (ValueError, ArithmeticError):  # a point that is no contact: the solve says why
        return []


#: a given contact point may lie this many of the finer element size off either boundary
CONTACT_POINT_REACH = 2.0
#: ... and the gap at it may exceed the smallest gap between the bodies by this many of the
#: finest cells there (a point where the bodies are not closest finds no contact)
CONTACT_GAP_CELLS = 2.0


def _contact_point_problems(spec: SceneSpec, problem: pb.Problem, label: str) -> list[str]:
    """A ``point`` given for a contact must lie on (or within CONTACT_POINT_REACH cells of) both
    bodies' boundaries, where the bodies are closest (unchecked, a mistyped point inside a body,
    or one off the touching point, gave a converged zero force); given or found, it must not sit
    at a corner of either body (the run needs the boundary to continue smoothly on each side of it),
    unless that corner lies on a symmetry line (a sliding condition on one of its edges)."""
    from ibfem.solver.contact.chain import contact_allowed_at_junction

    problems = []
    for k, (given, c) in enumerate(zip(spec.contacts, problem.contacts)):
        p = np.asarray(c.point, dtype=float)
        if given.point is not None:
            text = _point_distance_problem(problem, c) or _point_gap_problem(problem, c)
            if text:
                problems.append(f"{label}: contacts[{k}].point = {_show(list(given.point))}: {text}")
                continue
        for name in c.bodies:
            body = problem.body(name)
            h = finest_size_at(body, p)
            distance, edge = corner_distance(body.profile, p)
            symmetry = {bc.edge for bc in problem.boundary_conditions if isinstance(bc, pb.Sliding) and bc.body == name}
            if distance < h and not contact_allowed_at_junction(body.profile, p, symmetry):
                where = (f"contacts[{k}].point = {_show(list(given.point))}" if given.point is not None else
                         f"contacts[{k}]: the closest points of the two bodies ({_show([round(float(x), 9) for x in p])})")
                problems.append(f"{label}: {where}: at a corner of body {name!r} ({distance:.3g} from the end of its "
                                f"edge {edge!r}, less than the finest cell there, {h:.3g}); the contact needs a point "
                                "inside one edge of each body, at a tangent junction of two edges, on a symmetry "
                                "line (a corner with a sliding condition on one of its edges), or at a convex corner of "
                                "the first body of contacts.bodies with one edge far flatter against the other body "
                                "than the other edge (a tilted punch; list the body with the corner first)")
                break
    return problems


def _point_distance_problem(problem: pb.Problem, c: pb.ContactModel) -> str | None:
    p = np.asarray(c.point, dtype=float)[None, :]
    reach = CONTACT_POINT_REACH * min(problem.body(n).element_size for n in c.bodies)
    far = []
    for name in c.bodies:
        profile = problem.body(name).profile
        distance = abs(float(np.asarray(profile.signed_distance(p), dtype=float)[0]))
        if not distance <= reach:
            nearest = np.asarray(profile.project(p).points, dtype=float)[0]
            far.append(f"{distance:.4g} from body {name!r} (nearest boundary point "
                       f"[{nearest[0]:.6g}, {nearest[1]:.6g}])")
    if not far:
        return None
    return ("not on the bodies' boundaries: " + "; ".join(far) + f" (allowed: {reach:.4g}, {CONTACT_POINT_REACH:g} "
            "elements); leave the point out to use the closest points of the two boundaries")


def _point_gap_problem(problem: pb.Problem, c: pb.ContactModel) -> str | None:
    first, second = (problem.body(n) for n in c.bodies)
    p = np.asarray(c.point, dtype=float)
    spacing = CONTACT_SEARCH_SPACING * min(first.element_size, second.element_size)
    here = boundary_gap(first.profile, second.profile, p, spacing)
    least = boundary_gap(first.profile, second.profile, None, spacing)
    allowed = CONTACT_GAP_CELLS * min(finest_size_at(first, p), finest_size_at(second, p))
    if here - least <= allowed:
        return None
    found = contact_point(problem, dataclasses.replace(c, point=None))
    return (f"not where the bodies are closest: the gap between them is {here:.4g} there but {least:.4g} at "
            f"[{found[0]:.6g}, {found[1]:.6g}] (allowed difference: {allowed:.3g}, {CONTACT_GAP_CELLS:g} of the "
            "finest cells); give that point or leave the point out")


def _notes(spec: SceneSpec, label: str) -> list[str]:
    notes = []
    for i, m in enumerate(spec.materials):
        if m.youngs_modulus < 1e6:
            notes.append(
                f"{label}: materials[{i}].youngs_modulus = {_show(m.youngs_modulus)}: very small for Pa "
                "(units are SI: steel is 2.0e11)"
            )
        if m.poissons_ratio >= NEARLY_INCOMPRESSIBLE and spec.model != "plane_stress":
            notes.append(
                f"{label}: materials[{i}].poissons_ratio = {_show(m.poissons_ratio)}: nearly incompressible; "
                "the bilinear (2D) and trilinear (3D) cells lock as it nears 0.5 and the results come out too "
                "stiff (two cylinders in contact, plane strain: the contact width -0.4 % from Hertz's at 0.3, "
                "-0.6 % at 0.45, -1.8 % at 0.49, -10 % at 0.499)"
            )
    return notes


#: Poisson's ratio from which a scene is warned of volumetric locking (plane strain and solids)
NEARLY_INCOMPRESSIBLE = 0.45


