"""3D scenes (``model = "solid"``): the file's pydantic models and the solver's
problem with solids for bodies.

The 2D scene's vocabulary carries over (materials, ``[solver]``, output), with 3-vectors, solid
shapes (built by :func:`geometry.solids.solid_from_dict`) and boundary conditions naming a
``face``. Registered in :data:`solver.io.scene.SCENE_MODELS`, so ``load_scene`` reads both.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import BeforeValidator, Field, ValidationError, field_validator
from pydantic_core import PydanticCustomError

from ibfem.solver.model import problem as pb
from ibfem.solver.model.options import ContactOptions, SolverOptions
from ibfem.solver.model.solid_contact import SolidContactModel
from ibfem.solver.model.resolve import resolve_problem

from .scene import (
    SCENE_MODELS,
    BodySpec,
    RefinementSpec,
    _ContactBase,
    Component,
    MaterialSpec,
    Num,
    Scene,
    SceneError,
    SolverSpec,
    _format_errors,
    _notes,
    _options,
    _show,
    _Strict,
    pair_problems,
    size_problems,
    _fields_of,
    LineSpec,
    OutputSpec,
)
from .load_paths_spec import PathRef, PathSpec, history_problems, load_history
from .load_axes import AlongAxes, in_global_components
from .scene_reference_point import ReferencePoint3Spec, reference_point
from .rigid_3d import rigid_body_problems
from .scene_solid_checks import solid_contact_notes, solid_geometry_problems

__all__ = ["SolidSceneSpec", "solid_scene_from_dict"]

Vec3 = tuple[Num, Num, Num]


def _around3(v: Any) -> Any:
    if v == "contact":
        return v
    if isinstance(v, (list, tuple)) and len(v) == 3 and all(
        isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c) for c in v
    ):
        return tuple(float(c) for c in v)
    raise PydanticCustomError("around", 'must be "contact" or a point [x, y, z]')


class RefinementSpec3(RefinementSpec):
    around: Annotated[Union[Literal["contact"], tuple[float, float, float]], BeforeValidator(_around3)]


class SolidBodySpec(BodySpec):
    """A body of a 3D scene: the 2D body's keys, refinement centres in 3D."""

    refinement: list[RefinementSpec3] = []


class FaceSelector(_Strict):
    """A face picked by its geometry (solver.io.face_selectors): every key given must hold."""

    normal: Optional[Vec3] = None
    nearest: Optional[Vec3] = None
    type: Optional[str] = None
    radius: Optional[float] = Field(None, gt=0)
    axis: Optional[Vec3] = None


class _FaceCondition(_Strict):
    body: str
    face: Union[str, FaceSelector]


class Fixed3(_FaceCondition):
    type: Literal["fixed"]


class Displacement3(_FaceCondition, AlongAxes):
    type: Literal["displacement"]
    value: tuple[Component, Component, Component]
    path: PathRef | None = None  # load path name(s): docs/load-paths.md
    axes: tuple[Vec3, Vec3, Vec3] | None = None  # value and path along these directions

    @field_validator("value")
    @classmethod
    def _not_all_free(cls, v: tuple) -> tuple:
        if all(c is None for c in v):
            raise PydanticCustomError("all_free", "every component free: nothing is prescribed")
        return v


class Sliding3(_FaceCondition):
    type: Literal["sliding"]
    normal_displacement: Num = 0.0
    path: PathRef | None = None


class Traction3(_FaceCondition, AlongAxes):
    type: Literal["traction"]
    value: Vec3
    path: PathRef | None = None
    axes: tuple[Vec3, Vec3, Vec3] | None = None  # value and path along these directions


class Pressure3(_FaceCondition):
    type: Literal["pressure"]
    value: Num
    path: PathRef | None = None


class BodyForce3(AlongAxes):
    type: Literal["body_force"]
    body: str
    value: Vec3
    path: PathRef | None = None
    axes: tuple[Vec3, Vec3, Vec3] | None = None  # value and path along these directions


class ReferencePoint3(ReferencePoint3Spec):
    """A rigid reference point coupled to a face (solver.io.scene_reference_point)."""

    face: Union[str, FaceSelector]


Condition3 = Annotated[
    Union[Fixed3, Displacement3, Sliding3, Traction3, Pressure3, BodyForce3, ReferencePoint3],
    Field(discriminator="type"),
]
_ESSENTIAL = (Fixed3, Displacement3, Sliding3)


def _holds(bc) -> bool:
    """Whether the condition holds its body against rigid-body motion."""
    return isinstance(bc, _ESSENTIAL) or (isinstance(bc, ReferencePoint3) and bc.coupling == "kinematic")


class Line3(LineSpec):
    """An output line of a 3D scene (as a 2D scene's, with 3D points)."""

    start: Vec3
    end: Vec3


class Output3(OutputSpec):
    """The ``[output]`` table of a 3D scene (as a 2D scene's, with 3D probes and lines)."""

    probes: list[Vec3] = []
    lines: list[Line3] = []


class _SolidContactBase(_ContactBase):
    point: Vec3 | None = None
    tangential_direction: Vec3 | None = None


SolidContactSpec = _fields_of(ContactOptions, _SolidContactBase, "SolidContactSpec")


class SolidSceneSpec(_Strict):
    name: str | None = None
    description: str = ""
    model: Literal["solid"]
    solver: SolverSpec = SolverSpec()
    materials: list[MaterialSpec] = Field(min_length=1)
    bodies: list[SolidBodySpec] = Field(min_length=1)
    boundary_conditions: list[Condition3] = []
    contacts: list[SolidContactSpec] = []
    output: Output3 = Output3()
    paths: list[PathSpec] = []


def solid_scene_from_dict(data: dict, label: str, base_dir: Path, path: Path | None = None) -> Scene:
    """Validate a 3D scene given as plain data; errors name the key path and value."""
    if "thickness" in data:
        raise SceneError([f"{label}: thickness = {_show(data['thickness'])}: not used by model = \"solid\" "
                          "(3D forces are in N, not per unit thickness); remove it"])
    try:
        spec = SolidSceneSpec.model_validate(data)
    except ValidationError as err:
        raise SceneError(_format_errors(err, data, label)) from None
    solids = _build_solids(spec, label, base_dir)
    spec = _select_faces(spec, solids, label)
    _check_references(spec, solids, label)
    _check_paths(spec, label)
    spec = in_global_components(spec, 3)
    problem = _problem(spec, solids, Path(label).stem if path is None else path.stem, label)
    wrong = solid_geometry_problems(spec, problem, label)
    if wrong:
        raise SceneError(wrong)
    try:
        problem = resolve_problem(problem)
    except ValueError as err:
        raise SceneError([f"{label}: {err}"]) from None
    too_big = size_problems(problem, label) or rigid_body_problems(problem, label)
    if too_big:
        raise SceneError(too_big)
    notes = _notes(spec, label) + solid_contact_notes(spec, problem, label)
    return Scene(path=path, spec=spec, problem=problem, warnings=tuple(notes))


def _build_solids(spec: SolidSceneSpec, label: str, base_dir: Path) -> dict[str, Any]:
    try:
        from ibfem.geometry.solids import solid_from_dict
    except ImportError as err:  # pragma: no cover - part of the package
        raise SceneError([f"{label}: 3D solids need geometry.solids: {err}"]) from None
    problems, solids = [], {}
    for i, body in enumerate(spec.bodies):
        shape = dict(body.shape)
        if "path" in shape:  # CAD parts: relative to the scene file
            p = Path(str(shape["path"]))
            shape["path"] = str(p if p.is_absolute() else base_dir / p)
        try:
            solids[body.name] = solid_from_dict(shape, where=f"bodies[{i}].shape", load_part=_load_part)
        except (ValueError, KeyError, TypeError) as err:
            text = err.args[0] if isinstance(err, KeyError) and err.args else str(err)
            prefix = "" if text.startswith(f"bodies[{i}]") else f"bodies[{i}].shape: "
            problems.append(f"{label}: {prefix}{text}")
    if problems:
        raise SceneError(problems)
    return solids


#: the importer of each CAD shape type (imported when a scene uses it): module, function
CAD_LOADERS = {"onshape": ("ibfem.importers.onshape", "load_part"), "step": ("ibfem.importers.step", "load_part")}


def _load_part(shape: dict):
    """geometry.Part of an ``onshape`` (cached import directory) or ``step`` shape."""
    from importlib import import_module

    module, name = CAD_LOADERS[shape["type"]]
    try:
        loader = getattr(import_module(module), name)
    except (ImportError, AttributeError) as err:
        raise ValueError(f"type = {shape['type']!r} needs the importer {module}: {err}") from None
    if not isinstance(shape.get("path"), str) or not shape["path"]:
        raise ValueError(f"path: expected a file or directory name (a string), got {shape.get('path')!r}")
    try:
        return loader(shape["path"])
    except OSError as exc:  # a name too long, a directory without permission, ...
        raise ValueError(f"path: cannot read {shape['path']!r}: {exc.strerror or exc}") from None


def _select_faces(spec: SolidSceneSpec, solids: dict[str, Any], label: str) -> SolidSceneSpec:
    """The spec with every face selector replaced by the name of the face it picks."""
    conditions, problems = [], []
    for j, bc in enumerate(spec.boundary_conditions):
        if isinstance(getattr(bc, "face", None), FaceSelector) and bc.body in solids:
            from .face_selectors import select_face

            selector = bc.face.model_dump()
            try:
                bc = bc.model_copy(update={"face": select_face(solids[bc.body], selector)})
            except ValueError as err:
                shown = ", ".join(f"{k} = {_show(v)}" for k, v in selector.items() if v is not None)
                problems.append(f"{label}: boundary_conditions[{j}].face = {{ {shown} }} (body {bc.body!r}): {err}")
        conditions.append(bc)
    if problems:
        raise SceneError(problems)
    return spec.model_copy(update={"boundary_conditions": conditions})


def _check_references(spec: SolidSceneSpec, solids: dict[str, Any], label: str) -> None:
    problems = []
    materials = [m.name for m in spec.materials]
    bodies = [b.name for b in spec.bodies]
    for kind, names in (("materials", materials), ("bodies", bodies)):
        for name in set(names):
            if names.count(name) > 1:
                problems.append(f"{label}: {kind}: name {name!r} used {names.count(name)} times")
    for i, b in enumerate(spec.bodies):
        if b.material not in materials:
            problems.append(f"{label}: bodies[{i}].material = {b.material!r}: no such material "
                            f"(materials: {', '.join(materials)})")
    held = set()
    for j, bc in enumerate(spec.boundary_conditions):
        where = f"{label}: boundary_conditions[{j}]"
        if bc.body not in solids:
            problems.append(f"{where}.body = {bc.body!r}: no such body (bodies: {', '.join(bodies)})")
            continue
        if hasattr(bc, "face") and bc.face not in solids[bc.body].faces:
            problems.append(f"{where}.face = {bc.face!r}: body {bc.body!r} has no such face "
                            f"(faces: {', '.join(solids[bc.body].faces)})")
        if _holds(bc):
            held.add(bc.body)
    for k, c in enumerate(spec.contacts):
        for j, name in enumerate(c.bodies):
            if name not in solids:
                problems.append(f"{label}: contacts[{k}].bodies[{j}] = {name!r}: no such body (bodies: {', '.join(bodies)})")
        if c.bodies[0] == c.bodies[1]:
            problems.append(f"{label}: contacts[{k}].bodies: a body cannot touch itself ({c.bodies[0]!r})")
    problems += pair_problems(spec.contacts, label)
    for name in bodies:
        if name not in held and name in solids:
            problems.append(f"{label}: body {name!r} has no fixed, displacement, sliding or kinematic reference "
                            "point condition: "
                            "it is not held against rigid-body motion")
    if problems:
        raise SceneError(problems)


def _condition(bc) -> pb.BoundaryCondition:
    if isinstance(bc, Fixed3):
        return pb.Fixed(bc.body, bc.face)
    if isinstance(bc, Displacement3):
        return pb.Displacement(bc.body, bc.face, tuple(bc.value))
    if isinstance(bc, Sliding3):
        return pb.Sliding(bc.body, bc.face, float(bc.normal_displacement))
    if isinstance(bc, Traction3):
        return pb.Traction(bc.body, bc.face, tuple(float(v) for v in bc.value))
    if isinstance(bc, Pressure3):
        return pb.Pressure(bc.body, bc.face, float(bc.value))
    if isinstance(bc, ReferencePoint3):
        return reference_point(bc)
    return pb.BodyForce(bc.body, tuple(float(v) for v in bc.value))


def _problem(spec: SolidSceneSpec, solids: dict[str, Any], default_name: str, label: str) -> pb.Problem:  # noqa: C901
    import numpy as np

    materials = {m.name: pb.Material(m.name, float(m.youngs_modulus), float(m.poissons_ratio)) for m in spec.materials}
    bodies = []
    for b in spec.bodies:
        zones = tuple(
            pb.Refinement(int(r.levels), float(r.radius), None if r.around == "contact" else np.array(r.around, float))
            for r in b.refinement
        )
        bodies.append(pb.BodyModel(b.name, solids[b.name], materials[b.material], float(b.element_size), zones))
    options = _options(SolverOptions, spec.solver, "solver", label)
    contacts = tuple(_contact(c, k, solids, bodies, label) for k, c in enumerate(spec.contacts))
    return pb.Problem(
        name=spec.name or default_name,
        model="solid",
        thickness=1.0,
        bodies=tuple(bodies),
        boundary_conditions=tuple(_condition(bc) for bc in spec.boundary_conditions),
        contacts=contacts,
        options=options,
        history=load_history(spec.paths, spec.boundary_conditions, options.steps_per_unit, options.load_steps),
    )


def _check_paths(spec: SolidSceneSpec, label: str) -> None:
    """Load paths as in 2D (names known, one per component or one for all); a reference point
    does not follow them."""
    problems = history_problems(spec.paths, spec.boundary_conditions, label)
    for i, bc in enumerate(spec.boundary_conditions):
        if isinstance(bc, ReferencePoint3) and spec.paths:
            problems.append(f"{label}: boundary_conditions[{i}]: a reference point does not follow load paths; "
                            "remove [[paths]] or the reference point")
    if problems:
        raise SceneError(problems)


def _contact(c, k: int, solids: dict[str, Any], bodies, label: str) -> SolidContactModel:
    """The contact model; without a ``point``, the midpoint of the two solids' closest points
    (solver.contact.touching3d.closest_points_3d from the middle of their nearest bounding-box
    corners)."""
    import numpy as np

    from ibfem.solver.contact.touching3d import closest_points_3d

    options = _options(ContactOptions, c, f"contacts[{k}]", label)
    first, second = solids[c.bodies[0]], solids[c.bodies[1]]
    if c.point is not None:
        point = np.array(c.point, dtype=float)
    else:
        size = min(b.element_size for b in bodies if b.name in c.bodies)
        lo1, hi1 = (np.asarray(v, float) for v in first.bounds)
        lo2, hi2 = (np.asarray(v, float) for v in second.bounds)
        x = 0.5 * (np.clip(0.5 * (lo2 + hi2), lo1, hi1) + np.clip(0.5 * (lo1 + hi1), lo2, hi2))
        point = closest_points_3d(first, second, x, size)
    tangent = None if c.tangential_direction is None else np.array(c.tangential_direction, dtype=float)
    return SolidContactModel(bodies=tuple(c.bodies), type=c.type, friction=float(c.friction), point=point,
                             options=options, point_given=c.point is not None, tangential_direction=tangent)


SCENE_MODELS["solid"] = solid_scene_from_dict
