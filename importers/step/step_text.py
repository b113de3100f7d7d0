"""The data section of a STEP file read as text: each entity's ``#n`` label, type and parameters,
the names the file gives them decoded, and the product a solid belongs to.

OpenCascade's reader keeps neither the ``#n`` labels nor the bytes of names (a name outside ASCII
comes back mangled), so they are read from the file here.

Names. STEP strings are ISO 8859-1 with escapes (ISO 10303-21, section 6.4.3): ``''`` is a quote,
``\\\\`` a backslash, ``\\S\\c`` the character ``c`` + 128, ``\\X\\hh`` one byte in hex, ``\\X2\\...\\X0\\``
UTF-16 code units (4 hex digits each), ``\\X4\\...\\X0\\`` code points (8 hex digits each);
``\\P?\\`` page directives are dropped. Several exporters write the system's code page instead
of escapes: bytes that are valid UTF-8 are read as UTF-8; otherwise, when every byte above 127
is a Cyrillic letter of Windows-1251 (0xC0 to 0xFF, and 0xA8 / 0xB8 for Yo / yo) and they form
words of two or more letters, as Windows-1251; else as ISO 8859-1. The name ``NONE`` (SolidWorks'
word for no name) is no name.

Products. A solid (``MANIFOLD_SOLID_BREP``, ``BREP_WITH_VOIDS``) without a name of its own is
named by its product: the representation that lists it as an item, the
``SHAPE_DEFINITION_REPRESENTATION`` of that representation (directly or through a
``SHAPE_REPRESENTATION_RELATIONSHIP``), then ``PRODUCT_DEFINITION_SHAPE`` ->
``PRODUCT_DEFINITION`` -> ``PRODUCT_DEFINITION_FORMATION`` -> ``PRODUCT``'s name.
"""

from __future__ import annotations

import re
from functools import cached_property
from pathlib import Path

__all__ = ["StepText", "decode_step_string"]

_STATEMENT_END = re.compile(rb"'(?:[^']|'')*'|/\*.*?\*/|;", re.S)
_HEAD = re.compile(rb"\s*#(\d+)\s*=\s*(.*)", re.S)
_TYPE = re.compile(rb"([A-Z_][A-Z0-9_]*)\s*\(")
_STRING = re.compile(rb"'((?:[^']|'')*)'")
_REF = re.compile(rb"#(\d+)")
_ESCAPE = re.compile(r"\\X2\\((?:[0-9A-Fa-f]{4})*)\\X0\\|\\X4\\((?:[0-9A-Fa-f]{8})*)\\X0\\|\\X\\([0-9A-Fa-f]{2})"
                     r"|\\S\\(.)|\\P[A-I]\\|\\\\", re.S)
_CYRILLIC_1251 = set(range(0xC0, 0x100)) | {0xA8, 0xB8}
_SOLIDS = (b"MANIFOLD_SOLID_BREP", b"BREP_WITH_VOIDS")
_NO_NAME = "NONE"  # what SolidWorks writes for an item without a name


def _raw_text(raw: bytes) -> str:
    """Bytes of a STEP string (escapes still in) -> text, guessing the code page of unescaped bytes."""
    if all(b < 128 for b in raw):
        return raw.decode("ascii")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        pass
    high = [b for b in raw if b >= 128]
    words = re.findall(rb"[\xc0-\xff\xa8\xb8]{2,}", raw)
    if set(high) <= _CYRILLIC_1251 and sum(len(w) for w in words) == len(high):
        return raw.decode("cp1251")
    return raw.decode("latin-1")


def _unescape(m: re.Match) -> str:
    two, four, byte, shifted = m.groups()
    if two is not None:
        units = bytes.fromhex(two)
        return units.decode("utf-16-be", "replace")
    if four is not None:
        return "".join(chr(int(four[i:i + 8], 16)) for i in range(0, len(four), 8))
    if byte is not None:
        return bytes.fromhex(byte).decode("latin-1")
    if shifted is not None:
        return chr(ord(shifted) + 128)
    return "\\" if m.group(0) == "\\\\" else ""


def decode_step_string(raw: bytes) -> str:
    """The text of a STEP string's bytes (between the quotes), see the module docstring."""
    return _ESCAPE.sub(_unescape, _raw_text(raw.replace(b"''", b"'")))


class StepText:
    """The entities of a STEP file's data section, parsed once (lazily)."""

    def __init__(self, path: str | Path):
        self.path = Path(path)

    @cached_property
    def _entities(self) -> tuple[list[int], dict[int, bytes]]:
        data = self.path.read_bytes()
        start = data.find(b"DATA;")
        order, body = [], {}
        if start < 0:
            return order, body
        last = start + len(b"DATA;")
        for m in _STATEMENT_END.finditer(data, last):
            if m.group(0) != b";":
                continue
            head = _HEAD.match(data, last, m.start())
            last = m.end()
            if head:
                n = int(head.group(1))
                order.append(n)
                body[n] = head.group(2)
        return order, body

    def labels(self) -> list[str]:
        """``#n`` labels in file order (OpenCascade numbers entities 1, 2, ... in this order)."""
        return [f"#{n}" for n in self._entities[0]]

    def label(self, number: int) -> int | None:
        """The ``n`` of ``#n`` of OpenCascade's entity ``number`` (1-based, file order)."""
        order = self._entities[0]
        return order[number - 1] if 0 < number <= len(order) else None

    def kind(self, n: int) -> str:
        m = _TYPE.match(self._entities[1].get(n, b""))
        return m.group(1).decode() if m else ""

    def name(self, n: int) -> str:
        """The first string parameter of entity ``#n`` (its name for representation items), decoded;
        '' for ``NONE``."""
        m = _STRING.search(self._entities[1].get(n, b""))
        name = decode_step_string(m.group(1)).strip() if m else ""
        return "" if name == _NO_NAME else name

    def _refs(self, n: int) -> list[int]:
        return [int(r) for r in _REF.findall(self._entities[1].get(n, b""))]

    @cached_property
    def _referrers(self) -> dict[int, list[int]]:
        out: dict[int, list[int]] = {}
        for n in self._entities[0]:
            for r in self._refs(n):
                out.setdefault(r, []).append(n)
        return out

    def _users(self, n: int, kind: str) -> list[int]:
        return [u for u in self._referrers.get(n, []) if kind in self.kind(u)]

    def product_name(self, n: int) -> str:
        """The name of the PRODUCT whose shape holds the solid ``#n`` ('' when none is found)."""
        for rep in self._referrers.get(n, []):
            name = self.representation_product(rep)
            if name:
                return name
        return ""

    def representation_product(self, rep: int) -> str:
        """The name of the PRODUCT a shape representation ``#rep`` defines ('' when none)."""
        if "REPRESENTATION" not in self.kind(rep) or "RELATIONSHIP" in self.kind(rep):
            return ""
        reps = [rep] + [r for rel in self._users(rep, "SHAPE_REPRESENTATION_RELATIONSHIP")
                        for r in self._refs(rel) if r != rep]
        for r in reps:
            for sdr in self._users(r, "SHAPE_DEFINITION_REPRESENTATION"):
                name = self._product_of_definition_shape(self._refs(sdr)[0])
                if name:
                    return name
        return ""

    def _product_of_definition_shape(self, pds: int) -> str:
        if not self.kind(pds).startswith("PRODUCT_DEFINITION_SHAPE"):
            return ""
        refs = self._refs(pds)
        return self._product_of_definition(refs[0]) if refs else ""

    def _product_of_definition(self, pd: int) -> str:
        chain = [("PRODUCT_DEFINITION", 0), ("PRODUCT_DEFINITION_FORMATION", 0), ("PRODUCT", None)]
        n = pd
        for kind, ref in chain:
            if not self.kind(n).startswith(kind):
                return ""
            if ref is None:
                strings = _STRING.findall(self._entities[1][n])
                return decode_step_string(strings[1]).strip() if len(strings) > 1 else self.name(n)
            refs = self._refs(n)
            if not refs:
                return ""
            n = refs[ref]
        return ""

    def names_tell_apart(self, kind: str) -> bool:
        """Whether the names of the entities of type ``kind`` tell some apart: some entity has a
        name, and not every one the same (CATIA writes the body's name on every face)."""
        target = kind.encode()
        names = [self.name(n) for n, b in self._entities[1].items() if b.startswith(target)
                 and b[len(target):].lstrip().startswith(b"(")]
        named = [n for n in names if n]
        return bool(named) and not (len(named) == len(names) and len(set(named)) == 1)

    def occurrence_name(self, n: int) -> str:
        """The product placed by the assembly occurrence ``#n`` (NEXT_ASSEMBLY_USAGE_OCCURRENCE), else
        the occurrence's own name."""
        refs = self._refs(n)
        product = self._product_of_definition(refs[1]) if len(refs) > 1 else ""
        strings = _STRING.findall(self._entities[1].get(n, b""))
        return product or (decode_step_string(strings[1]).strip() if len(strings) > 1 else "")

    def solid_name(self, n: int) -> str:
        """A solid's own name, else its product's (for a shape representation: its product's)."""
        own = self.name(n)
        if "SHAPE_REPRESENTATION" in self.kind(n):
            return self.representation_product(n) or own
        if own or not self.kind(n).startswith(tuple(k.decode() for k in _SOLIDS)):
            return own
        return self.product_name(n)
