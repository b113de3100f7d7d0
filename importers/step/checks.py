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

from dataclasses import dataclass

__all__ = ["Failure", "failed_checks", "split_failures", "describe"]

# OpenCascade class prefixes of the entities a B-rep is built from
_GEOMETRY_FAMILIES = ("StepGeom_", "StepShape_", "IGESGeom_", "IGESSolid_")
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


def _family(type_name: str) -> tuple[str, str]:
    head, sep, tail = type_name.partition("_")
    return (head + sep, tail) if sep else ("", type_name)


def failed_checks(reader, kind: str, text=None) -> list[Failure]:
    """Every entity whose check failed after the reader loaded the file (general failures, not
    tied to an entity, are labelled ``file``); ``text``: the file's :class:`~.step_text.StepText`
    (STEP), which gives the ``#n`` labels."""
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
    out = []
    for number, name, messages in raw:
        family, short = _family(name)
        if number <= 0:
            label = "file"
        elif kind == "step":
            n = text.label(number) if text is not None else None
            label = f"#{n}" if n is not None else f"entity {number} (in file order)"
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
