"""The reader's failed entity checks, sorted into errors and warnings.

Real exporters write entities OpenCascade's STEP parser does not fully accept, most often outside
the geometry: presentation styles (``POINT_STYLE`` with a marker of another type), units whose
derived ``dimensions`` attribute is written ``*`` (AP242), product-manufacturing annotations. The
shapes OpenCascade transfers do not use them, so a failed check there is a warning. A failed
check on a geometric or topological entity (points, curves, surfaces, edges, faces, shells,
solids) is an error: the shape built from it cannot be trusted. A unit whose check fails on
anything but its derived ``dimensions`` is an error too (lengths or angles would be scaled
wrongly). Every entity is named by its ``#n`` label in the file (its directory entry in IGES).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Failure", "failed_checks", "split_failures", "describe", "step_labels"]

# OpenCascade class prefixes of the entities a B-rep is built from
_GEOMETRY_FAMILIES = ("StepGeom_", "StepShape_", "IGESGeom_", "IGESSolid_")
_STEP_TOKEN = re.compile(r"'(?:[^']|'')*'|/\*.*?\*/|(#\d+)\s*=", re.S)
_LISTED = 8


@dataclass(frozen=True)
class Failure:
    """One entity whose check failed: its label (``#12`` / ``directory entry 7``), its type
    (OpenCascade's class name without the family prefix) and the messages."""

    label: str
    entity_type: str
    family: str
    messages: tuple[str, ...]

    @property
    def is_geometry(self) -> bool:
        return self.family in _GEOMETRY_FAMILIES

    @property
    def is_unit(self) -> bool:
        return self.family == "StepBasic_" and "Unit" in self.entity_type

    @property
    def harmless(self) -> bool:
        """True when the shapes do not depend on the entity (see the module docstring)."""
        if self.is_geometry or self.label == "file":
            return False
        if self.is_unit:
            return all("(dimensions)" in m for m in self.messages)
        return True

    def __str__(self) -> str:
        return f"{self.label} ({self.entity_type}): {'; '.join(self.messages)}"


def step_labels(path: Path) -> list[str]:
    """The ``#n`` labels of a STEP file's data section in file order (OpenCascade numbers the
    entities 1, 2, ... in this order). Strings and comments are skipped."""
    text = Path(path).read_bytes().decode("latin-1")
    start = text.find("DATA;")
    if start < 0:
        return []
    return [m.group(1) for m in _STEP_TOKEN.finditer(text, start) if m.group(1)]


def _family(type_name: str) -> tuple[str, str]:
    head, sep, tail = type_name.partition("_")
    return (head + sep, tail) if sep else ("", type_name)


def failed_checks(reader, kind: str, path: Path) -> list[Failure]:
    """Every entity whose check failed after the reader loaded ``path`` (general failures,
    not tied to an entity, are labelled ``file``)."""
    checks = reader.WS().ModelCheckList()
    checks.Start()
    raw = []
    while checks.More():
        check = checks.Value()
        if check.NbFails():
            entity = check.Entity() if check.HasEntity() else None
            name = entity.DynamicType().Name() if entity is not None else ""
            messages = tuple(check.CFail(i, True) for i in range(1, check.NbFails() + 1))
            raw.append((checks.Number() if entity is not None else 0, name, messages))
        checks.Next()
    labels = step_labels(path) if kind == "step" and any(n > 0 for n, _, _ in raw) else []
    out = []
    for number, name, messages in raw:
        family, short = _family(name)
        if number <= 0:
            label = "file"
        elif kind == "step":
            label = labels[number - 1] if number <= len(labels) else f"entity {number} (in file order)"
        else:
            label = f"directory entry {2 * number - 1}"
        out.append(Failure(label, short or "entity", family, messages))
    return out


def split_failures(failures: list[Failure]) -> tuple[list[Failure], list[Failure]]:
    """(errors, warnings): see the module docstring."""
    errors = [f for f in failures if not f.harmless]
    return errors, [f for f in failures if f.harmless]


def describe(failures: list[Failure]) -> str:
    """The first few failures, then how many more."""
    shown = "; ".join(str(f) for f in failures[:_LISTED])
    more = len(failures) - _LISTED
    return shown + (f" (and {more} more)" if more > 0 else "")
