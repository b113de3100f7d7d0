"""pydantic models of the Onshape responses the importer reads, covering both wire formats
the Onshape REST API sends:

* format A ("BT"): objects with ``btType`` discriminators, vectors ``{"x", "y", "z"}``,
  UPPERCASE enums, tessellation responses as objects holding ``bodies``;
* format B (legacy): tessellation responses as top-level arrays of bodies, vectors
  ``[x, y, z]``, lowercase type strings (``revolved`` = SPUN, ``extruded`` = SWEEP).

Only the fields the importer uses are modelled; everything else is ignored. Numbers,
strings and booleans are checked strictly (no silent coercion of ``"1.5"`` or ``"true"``)
so a wrong value is reported with its JSON path (see :func:`format_validation_error`).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Optional

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, StrictBool, StrictStr, ValidationError

__all__ = [
    "Vec3", "Number", "Facet", "TessFace", "TessBody", "TessFacesResponse", "TessEdge", "TessEdgeBody",
    "TessEdgesResponse", "SurfaceDesc", "CurveDesc", "Coedge", "Loop", "ModelFace", "EdgeGeometry",
    "ModelEdge", "ModelVertex", "ModelBody", "BodiesResponse", "format_validation_error", "describe",
    "BODY_TYPES",
]

BODY_TYPES = ("SOLID", "SHEET", "WIRE", "POINT", "MATE_CONNECTOR", "COMPOSITE", "UNKNOWN")


def describe(value: Any) -> str:
    """A short repr of an offending JSON value for error messages."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


#: no number in an Onshape response (SI units: metres) is larger: a part 1e12 m across is a
#: damaged file, and squares of larger numbers overflow (1e308 did, in the mesh welding)
MAX_MAGNITUDE = 1e12


def _number(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"expected a number, got {describe(value)}")
    try:
        x = float(value)
    except OverflowError:  # an integer beyond floating point
        raise ValueError(f"expected a number below {MAX_MAGNITUDE:g} in magnitude, got a {len(str(value))}-digit "
                         "integer") from None
    if not math.isfinite(x):
        raise ValueError(f"expected a finite number, got {describe(value)}")
    if abs(x) > MAX_MAGNITUDE:
        raise ValueError(f"expected a number below {MAX_MAGNITUDE:g} in magnitude (metres), got {describe(value)}")
    return x


def _int(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"expected an integer, got {describe(value)}")
    return value


def _vec3(value: Any) -> tuple[float, float, float]:
    """``[x, y, z]`` (format B) or ``{"x", "y", "z"}`` (format A, ``btType`` ignored)."""
    # fast path for the tens of thousands of well-formed tessellation vectors
    if type(value) is dict and len(value) <= 4:
        x, y, z = value.get("x"), value.get("y"), value.get("z")
    elif type(value) is list and len(value) == 3:
        x, y, z = value
    else:
        x = y = z = None
    if type(x) is float and type(y) is float and type(z) is float and abs(x) + abs(y) + abs(z) <= MAX_MAGNITUDE:
        return (x, y, z)
    if isinstance(value, dict):
        missing = [k for k in "xyz" if k not in value]
        if missing:
            raise ValueError(f"expected a vector {{x, y, z}}, missing {', '.join(missing)} in {describe(value)}")
        items = [value["x"], value["y"], value["z"]]
    elif isinstance(value, (list, tuple)):
        if len(value) != 3:
            raise ValueError(f"expected a vector of 3 numbers, got {len(value)} items: {describe(value)}")
        items = list(value)
    else:
        raise ValueError(f"expected a vector ([x, y, z] or {{x, y, z}}), got {describe(value)}")
    return tuple(_number(v) for v in items)  # type: ignore[return-value]


def _enum(value: Any) -> str:
    if not isinstance(value, str):
        raise ValueError(f"expected a type name (string), got {describe(value)}")
    return value.strip().upper()


Number = Annotated[float, BeforeValidator(_number)]
Int = Annotated[int, BeforeValidator(_int)]
Vec3 = Annotated[tuple[float, float, float], BeforeValidator(_vec3)]
EnumStr = Annotated[str, BeforeValidator(_enum)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="ignore", frozen=True)


# ---------------------------------------------------------------------------------------
# tessellatedfaces
# ---------------------------------------------------------------------------------------


class Facet(_Model):
    vertices: list[Vec3] = Field(default_factory=list)
    normal: Optional[Vec3] = None
    normals: list[Vec3] = Field(default_factory=list)  # format A per-vertex normals
    vertexNormals: list[Vec3] = Field(default_factory=list)  # format B per-vertex normals
    indices: list[Int] = Field(default_factory=list)

    @property
    def vertex_normals(self) -> list[tuple[float, float, float]]:
        return self.normals or self.vertexNormals


class TessFace(_Model):
    id: StrictStr
    facets: list[Facet] = Field(default_factory=list)
    errorMessage: Optional[StrictStr] = None


class TessBody(_Model):
    id: StrictStr
    name: Optional[StrictStr] = None
    bodyType: Optional[EnumStr] = None
    facetPoints: list[Vec3] = Field(default_factory=list)
    faces: list[TessFace] = Field(default_factory=list)


class TessFacesResponse(_Model):
    bodies: list[TessBody]
    facetPoints: list[Vec3] = Field(default_factory=list)
    errorEnum: Optional[StrictStr] = None


# ---------------------------------------------------------------------------------------
# tessellatededges
# ---------------------------------------------------------------------------------------


class TessEdge(_Model):
    id: StrictStr
    vertices: list[Vec3] = Field(default_factory=list)


class TessEdgeBody(_Model):
    id: StrictStr
    name: Optional[StrictStr] = None
    edges: list[TessEdge] = Field(default_factory=list)


class TessEdgesResponse(_Model):
    bodies: list[TessEdgeBody]
    errorEnum: Optional[StrictStr] = None


# ---------------------------------------------------------------------------------------
# bodydetails
# ---------------------------------------------------------------------------------------


class CurveDesc(_Model):
    """Any curve description (LINE, CIRCLE, ELLIPSE, BCURVE, ICURVE, OTHER, ...)."""

    type: EnumStr
    origin: Optional[Vec3] = None
    direction: Optional[Vec3] = None
    normal: Optional[Vec3] = None
    radius: Optional[Number] = None
    majorAxis: Optional[Vec3] = None
    majorRadius: Optional[Number] = None
    minorRadius: Optional[Number] = None
    degree: Optional[Int] = None
    knots: Optional[list[Number]] = None
    controlPoints: Optional[list[Any]] = None  # layouts: see parser.bcurve_control_points
    weights: Optional[list[Number]] = None
    isRational: StrictBool = False
    isPeriodic: StrictBool = False


class SurfaceDesc(_Model):
    """Any surface description (PLANE, CYLINDER, CONE, SPHERE, TORUS, SWEEP, SPUN, ...)."""

    type: EnumStr
    origin: Optional[Vec3] = None
    normal: Optional[Vec3] = None
    axis: Optional[Vec3] = None
    direction: Optional[Vec3] = None
    radius: Optional[Number] = None
    halfAngle: Optional[Number] = None
    majorRadius: Optional[Number] = None
    minorRadius: Optional[Number] = None
    isOrientedWithFace: Optional[StrictBool] = None
    profile: Optional[CurveDesc] = None


class Coedge(_Model):
    edgeId: StrictStr
    orientation: StrictBool = True


class Loop(_Model):
    isOuter: Optional[StrictBool] = None
    isInner: Optional[StrictBool] = None
    type: Optional[EnumStr] = None  # format B: "outer" / "inner"
    coedges: list[Coedge] = Field(default_factory=list)

    @property
    def outer(self) -> bool:
        if self.isOuter is not None:
            return self.isOuter
        if self.isInner is not None:
            return not self.isInner
        return self.type in (None, "OUTER")


class BoundingBox(_Model):
    minCorner: Optional[Vec3] = None
    maxCorner: Optional[Vec3] = None


class ModelFace(_Model):
    id: StrictStr
    surface: SurfaceDesc
    orientation: StrictBool = True
    area: Optional[Number] = None
    box: Optional[BoundingBox] = None
    loops: list[Loop] = Field(default_factory=list)


class EdgeGeometry(_Model):
    startPoint: Optional[Vec3] = None
    endPoint: Optional[Vec3] = None
    midPoint: Optional[Vec3] = None
    quarterPoint: Optional[Vec3] = None
    startVector: Optional[Vec3] = None
    endVector: Optional[Vec3] = None
    length: Optional[Number] = None
    arcSweep: Optional[Number] = None
    arcIsClockwise: Optional[StrictBool] = None


class ModelEdge(_Model):
    id: StrictStr
    curve: Optional[CurveDesc] = None
    geometry: Optional[EdgeGeometry] = None
    vertices: list[StrictStr] = Field(default_factory=list)


class ModelVertex(_Model):
    id: StrictStr
    point: Vec3


class BodyProperties(_Model):
    name: Optional[StrictStr] = None


class ModelBody(_Model):
    id: StrictStr
    type: Optional[EnumStr] = None
    properties: Optional[BodyProperties] = None
    faces: list[ModelFace] = Field(default_factory=list)
    edges: list[ModelEdge] = Field(default_factory=list)
    vertices: list[ModelVertex] = Field(default_factory=list)


class MicroversionId(_Model):
    theId: Optional[StrictStr] = None


class BodiesResponse(_Model):
    bodies: list[ModelBody]
    microversionId: Optional[MicroversionId] = None
    errorEnum: Optional[StrictStr] = None


# ---------------------------------------------------------------------------------------
# error messages
# ---------------------------------------------------------------------------------------

_PLAIN = {
    "missing": "missing field",
    "string_type": "expected a string",
    "bool_type": "expected true or false",
    "list_type": "expected a list",
    "model_type": "expected an object",
    "model_attributes_type": "expected an object",
    "dict_type": "expected an object",
    "int_type": "expected an integer",
    "float_type": "expected a number",
}


def json_path(loc: tuple) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def format_validation_error(filename: str, error: ValidationError, prefix: tuple = ()) -> str:
    """``file: json.path: message`` for the first (up to three) problems."""
    lines = []
    errors = error.errors(include_url=False)
    for e in errors[:3]:
        path = json_path(tuple(prefix) + tuple(e["loc"]))
        if e["type"] == "value_error":
            msg = str(e["ctx"]["error"]) if "ctx" in e and "error" in e["ctx"] else e["msg"]
        else:
            msg = _PLAIN.get(e["type"], e["msg"])
            if e["type"] != "missing":
                msg += f", got {describe(e.get('input'))}"
        lines.append(f"{filename}: {path}: {msg}")
    if len(errors) > 3:
        lines.append(f"{filename}: ... and {len(errors) - 3} more problems")
    return "\n".join(lines)
