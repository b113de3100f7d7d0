"""The ``type = "reference_point"`` boundary condition of a scene file (2D and 3D): a rigid
reference point coupled to a face (an edge in 2D) or to its part inside a box or a sphere, with a
prescribed displacement and rotation (``coupling = "kinematic"``) or a force and moment
(``coupling = "distributing"``) at the point. The mechanics: :mod:`solver.model.reference_point`.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, Optional

from pydantic import BeforeValidator, Field, model_validator
from pydantic_core import PydanticCustomError

from ibfem.solver.model.reference_point import Ball, Box, ReferencePoint

from .strict_model import StrictTable, number

__all__ = ["RegionSpec2", "RegionSpec3", "ReferencePoint2Spec", "ReferencePoint3Spec", "reference_point"]

Num = Annotated[float, BeforeValidator(number)]


class _Region(StrictTable):
    """A box (``min`` and ``max``) or a sphere (``center`` and ``radius``)."""

    radius: Optional[Num] = Field(None, gt=0)

    @model_validator(mode="after")
    def _box_or_sphere(self):
        box = (self.min is not None, self.max is not None)
        sphere = (self.center is not None, self.radius is not None)
        if all(box) and not any(sphere):
            if any(lo >= hi for lo, hi in zip(self.min, self.max)):
                raise PydanticCustomError("region", "every component of min must be below max's")
            return self
        if all(sphere) and not any(box):
            return self
        raise PydanticCustomError("region", "give either min and max (a box) or center and radius (a sphere)")

    def region(self) -> Box | Ball:
        if self.min is not None:
            return Box(tuple(self.min), tuple(self.max))
        return Ball(tuple(self.center), float(self.radius))


class RegionSpec2(_Region):
    min: Optional[tuple[Num, Num]] = None
    max: Optional[tuple[Num, Num]] = None
    center: Optional[tuple[Num, Num]] = None


class RegionSpec3(_Region):
    min: Optional[tuple[Num, Num, Num]] = None
    max: Optional[tuple[Num, Num, Num]] = None
    center: Optional[tuple[Num, Num, Num]] = None


class _ReferencePointBase(StrictTable):
    type: Literal["reference_point"]
    body: str
    coupling: Literal["kinematic", "distributing"] = "kinematic"

    @model_validator(mode="after")
    def _loads_fit_coupling(self):
        if self.coupling == "kinematic":
            if self.force is not None or self.moment is not None:
                raise PydanticCustomError(
                    "coupling", 'force and moment need coupling = "distributing" (a kinematic coupling '
                    "prescribes the point's displacement and rotation)")
            if self.displacement is None:
                raise PydanticCustomError("coupling", "a kinematic coupling needs the point's displacement")
        else:
            if self.displacement is not None or self.rotation is not None:
                raise PydanticCustomError(
                    "coupling", 'displacement and rotation need coupling = "kinematic" (a distributing '
                    "coupling carries a force and a moment)")
            if self.force is None and self.moment is None:
                raise PydanticCustomError("coupling", "a distributing coupling needs a force or a moment")
        return self


class ReferencePoint2Spec(_ReferencePointBase):
    """2D: an edge, the point [x, y], rotation and moment about e_z (scalars)."""

    edge: str
    point: tuple[Num, Num]
    region: Optional[RegionSpec2] = None
    displacement: Optional[tuple[Num, Num]] = None
    rotation: Optional[Num] = None
    force: Optional[tuple[Num, Num]] = None
    moment: Optional[Num] = None


class ReferencePoint3Spec(_ReferencePointBase):
    """3D: a face (its name or a selector, checked by the scene), the point [x, y, z]."""

    face: Any
    point: tuple[Num, Num, Num]
    region: Optional[RegionSpec3] = None
    displacement: Optional[tuple[Num, Num, Num]] = None
    rotation: Optional[tuple[Num, Num, Num]] = None
    force: Optional[tuple[Num, Num, Num]] = None
    moment: Optional[tuple[Num, Num, Num]] = None


def _vector(v, n: int) -> tuple[float, ...]:
    if v is None:
        return (0.0,) * n
    return tuple(float(c) for c in (v if isinstance(v, tuple) else (v,)))


def reference_point(spec: ReferencePoint2Spec | ReferencePoint3Spec) -> ReferencePoint:
    """The solver's reference point of a validated scene table."""
    dim = len(spec.point)
    n_rot = 1 if dim == 2 else 3
    kinematic = spec.coupling == "kinematic"
    return ReferencePoint(
        body=spec.body,
        edge=spec.edge if dim == 2 else spec.face,
        point=tuple(float(c) for c in spec.point),
        coupling=spec.coupling,
        region=None if spec.region is None else spec.region.region(),
        displacement=_vector(spec.displacement, dim) if kinematic else (),
        rotation=_vector(spec.rotation, n_rot) if kinematic else (),
        force=() if kinematic else _vector(spec.force, dim),
        moment=() if kinematic else _vector(spec.moment, n_rot),
    )
