"""A STEP or IGES file -> an OpenCascade shape in metres.

OpenCascade converts lengths while it reads, from the file's unit into its "cascade unit"
(the static parameter ``xstep.cascade.unit``, millimetres by default). We set that unit to
metres for the read and restore it afterwards, so the shape's coordinates are metres whatever
the file's unit (mm, inch, m, ...).

Errors: the reader's parse messages go to the C++ streams; they are captured (file
descriptors 1 and 2 redirected for the read) and the first one is put in the
:class:`StepFormatError`, with the file name. Failed checks of entities after a successful
parse are sorted by :mod:`.checks`: entities of the geometry are errors, the others (presentation,
annotations, units' derived attributes) warnings; each is named by its ``#12`` label in STEP, its
directory entry in IGES.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

from .checks import describe, failed_checks, split_failures
from .errors import StepFormatError, require_ocp
from .step_text import StepText

__all__ = ["read_shape", "STEP_SUFFIXES", "IGES_SUFFIXES", "CAD_SUFFIXES", "cad_format"]

STEP_SUFFIXES = (".step", ".stp")
IGES_SUFFIXES = (".iges", ".igs")
CAD_SUFFIXES = STEP_SUFFIXES + IGES_SUFFIXES
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def cad_format(path: str | Path) -> str | None:
    """'step', 'iges' or None from the file name's suffix (case-insensitive)."""
    suffix = Path(path).suffix.lower()
    return "step" if suffix in STEP_SUFFIXES else "iges" if suffix in IGES_SUFFIXES else None


def _quiet_messenger() -> None:
    """OpenCascade's default printer writes every info line of a read or write to stdout;
    keep failures only."""
    from OCP.Message import Message, Message_Gravity

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)


@contextmanager
def _captured_output():
    """Redirect the process's stdout and stderr (the C++ streams) into a temporary file for the
    duration; yields a list that receives the captured lines afterwards."""
    lines: list[str] = []
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    with tempfile.TemporaryFile(mode="w+b") as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield lines
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            text = _ANSI.sub("", sink.read().decode("utf-8", "replace"))
            lines += [ln.strip(" *\t") for ln in text.splitlines() if ln.strip(" *\t")]


@contextmanager
def _metres():
    """Read lengths in metres (``xstep.cascade.unit = M``), restoring the previous unit."""
    from OCP.Interface import Interface_Static

    before = Interface_Static.CVal_s("xstep.cascade.unit") or "MM"
    if not Interface_Static.SetCVal_s("xstep.cascade.unit", "M"):
        raise StepFormatError("OpenCascade refused the length unit M (xstep.cascade.unit): cannot convert to metres")
    try:
        yield
    finally:
        Interface_Static.SetCVal_s("xstep.cascade.unit", before)


def _check_path(path: Path) -> str:
    kind = cad_format(path)
    if kind is None:
        raise StepFormatError(f"{path}: not a STEP or IGES file name (expected one of {', '.join(CAD_SUFFIXES)})")
    if not path.exists():
        raise StepFormatError(f"{path}: no such file")
    if not path.is_file():
        raise StepFormatError(f"{path}: not a file")
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise StepFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if size == 0:
        raise StepFormatError(f"{path}: the file is empty")
    return kind


def _reader(kind: str):
    if kind == "step":
        from OCP.STEPControl import STEPControl_Reader

        return STEPControl_Reader()
    from OCP.IGESControl import IGESControl_Reader

    return IGESControl_Reader()


def _unlocated(shape):
    from OCP.TopLoc import TopLoc_Location

    return shape.Located(TopLoc_Location())


def _step_namer(reader, text):
    """name(sub-shape) for a STEP file: the name of the entity OpenCascade made the sub-shape from,
    read from the file (:class:`~.step_text.StepText`: decoded; a solid without a name of its own,
    or placed in an assembly, named by its product). Faces are looked up only when the names of the
    file's ``ADVANCED_FACE`` entities tell faces apart (the look-up is slow on large files)."""
    from OCP.TopAbs import TopAbs_ShapeEnum

    transfer = reader.WS().TransferReader()
    model = reader.StepModel()
    entities = [model.Value(i) for i in range(1, model.NbEntities() + 1)]  # kept alive: ids stay unique
    number = {id(e): i for i, e in enumerate(entities, 1)}
    faces_named = text.names_tell_apart("ADVANCED_FACE")

    def name(shape, _keep=(reader, entities)) -> str:  # the reader owns the transfer results
        if shape.ShapeType() == TopAbs_ShapeEnum.TopAbs_FACE and not faces_named:
            return ""
        entity = None
        tries = ((shape, 1),) if shape.ShapeType() == TopAbs_ShapeEnum.TopAbs_FACE else \
            ((shape, 1), (_unlocated(shape), -1))  # a body as placed, then its prototype
        for key, mode in tries:
            try:
                entity = transfer.EntityFromShapeResult(key, mode)
            except Exception:  # OpenCascade's Standard_OutOfRange: no entity for this shape
                entity = None
            if entity is not None:
                break
        label = text.label(number.get(id(entity), 0)) if entity is not None else None
        if label is None:
            return ""
        if entity.DynamicType().Name() == "StepRepr_NextAssemblyUsageOccurrence":
            return text.occurrence_name(label)
        return text.solid_name(label)

    return name


def _iges_namer(reader):
    """name(sub-shape) for an IGES file: the entity's name, when it has one (its name property,
    else its directory entry's label; OpenCascade appends the label's subscript as ``(n)``, and a
    subscript 0, which numbers nothing, is dropped)."""
    transfer = reader.WS().TransferReader()

    def name(shape, _keep=reader) -> str:  # the reader owns the transfer results: kept alive
        try:
            entity = transfer.EntityFromShapeResult(shape, 1)
            if entity is None or not hasattr(entity, "HasName") or not entity.HasName():
                return ""
            text = entity.NameValue().ToCString().strip()
            return text[:-3].rstrip() if text.endswith("(0)") else text
        except Exception:  # an entity without a readable name: unnamed
            return ""

    return name


def read_shape(path: str | Path):
    """(shape, info) of a STEP/IGES file: the OpenCascade shape of all its roots in metres,
    and ``info`` = {"format", "roots", "warnings", "names"} (``names(sub-shape)``: its name in the file). Raises :class:`StepFormatError` naming the
    file (and the entity) when it cannot be read."""
    require_ocp()
    from OCP.IFSelect import IFSelect_ReturnStatus

    path = Path(path)
    kind = _check_path(path)
    _quiet_messenger()
    reader = _reader(kind)  # creating a reader registers the xstep statics
    with _metres(), _captured_output() as printed:
        status = reader.ReadFile(str(path))
        roots = reader.TransferRoots() if status == IFSelect_ReturnStatus.IFSelect_RetDone else 0
        shape = reader.OneShape() if roots else None
    fmt = kind.upper()
    if status != IFSelect_ReturnStatus.IFSelect_RetDone:
        said = [ln for ln in printed if "ERR" in ln or "rror" in ln or "Incorrect" in ln]
        detail = said[0].replace("ERR ", "") if said else status.name.replace("IFSelect_Ret", "status ")
        raise StepFormatError(f"{path}: not a readable {fmt} file: {detail}")
    text = StepText(path) if kind == "step" else None
    errors, harmless = split_failures(failed_checks(reader, kind, text))
    if kind == "iges" and roots:  # IGES checks are advisory once the roots transfer
        errors, harmless = [], errors + harmless
    if errors:
        raise StepFormatError(f"{path}: {fmt} entity checks failed on the geometry ({len(errors)}): "
                              f"{describe(errors)}")
    if shape is None or shape.IsNull():
        raise StepFormatError(f"{path}: the {fmt} file holds no shape OpenCascade can transfer "
                              f"({reader.NbRootsForTransfer()} roots, none transferred)")
    warnings = []
    if harmless:
        warnings.append(f"{path.name}: {len(harmless)} {fmt} entities that the shapes do not use failed their "
                        f"checks (ignored): {describe(harmless)}")
    names = _step_namer(reader, text) if text is not None else _iges_namer(reader)
    return shape, {"format": kind, "roots": int(roots), "warnings": warnings, "names": names}
