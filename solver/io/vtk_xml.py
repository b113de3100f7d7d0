"""VTK's XML file formats written directly (no VTK or pyvista needed): unstructured grids
(``.vtu``), polygonal data (``.vtp``) and the multiblock index (``.vtm``) that opens every
file of a run at once. Arrays are stored as raw little-endian binary in the file's appended
section, each behind a 64-bit byte count (``header_type="UInt64"``), as ParaView, VTK and
pyvista read them."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

__all__ = ["write_unstructured_grid", "write_polydata", "write_multiblock", "TENSOR_COMPONENTS"]

#: component names of a symmetric tensor in VTK's order (ParaView's tensor filters expect it)
TENSOR_COMPONENTS = ("XX", "YY", "ZZ", "XY", "YZ", "XZ")
_TYPES = {np.dtype("float64"): "Float64", np.dtype("float32"): "Float32", np.dtype("int64"): "Int64",
          np.dtype("int32"): "Int32", np.dtype("uint8"): "UInt8", np.dtype("int8"): "Int8"}
_HEADER = '<?xml version="1.0"?>\n<VTKFile type="{kind}" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n'


class _Appended:
    """The arrays of one file: XML elements pointing into the raw appended section."""

    def __init__(self):
        self.chunks: list[bytes] = []
        self.offset = 0

    def array(self, name: str, values: np.ndarray, components: Sequence[str] = ()) -> str:
        from xml.sax.saxutils import quoteattr  # here: it imports urllib, a run without VTK output needs none

        values = np.ascontiguousarray(values)
        if values.dtype not in _TYPES:
            values = values.astype(np.float64 if values.dtype.kind == "f" else np.int64)
        kind = _TYPES[values.dtype]
        raw = values.astype(values.dtype.newbyteorder("<"), copy=False).tobytes()
        n_comp = 1 if values.ndim == 1 else int(values.shape[1])
        names = "".join(f' ComponentName{k}="{c}"' for k, c in enumerate(components))
        element = (f'<DataArray type="{kind}" Name={quoteattr(name)} NumberOfComponents="{n_comp}"{names} '
                   f'format="appended" offset="{self.offset}"/>\n')
        self.chunks += [np.uint64(len(raw)).astype("<u8").tobytes(), raw]
        self.offset += 8 + len(raw)
        return element

    def fields(self, tag: str, fields: Mapping[str, np.ndarray], components: Mapping[str, Sequence[str]]) -> str:
        if not fields:
            return f"<{tag}/>\n"
        arrays = "".join(self.array(name, np.asarray(v), components.get(name, ())) for name, v in fields.items())
        return f"<{tag}>\n{arrays}</{tag}>\n"

    def document(self, xml: str) -> bytes:
        return (xml + '<AppendedData encoding="raw">\n_').encode("ascii") + b"".join(self.chunks) + \
            b"\n</AppendedData>\n</VTKFile>\n"


def _write(path: Path, data: bytes) -> Path:
    """Atomically: a viewer never opens a half-written file."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_bytes(data)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def _index_type(n: int):
    return np.int32 if n < 2**31 - 1 else np.int64


def _points3(points: np.ndarray) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    return np.column_stack([p, np.zeros((len(p), 3 - p.shape[1]))]) if p.shape[1] < 3 else p


def write_unstructured_grid(path: str | Path, points: np.ndarray, connectivity: np.ndarray, offsets: np.ndarray,
                            types: np.ndarray, point_data: Mapping[str, np.ndarray] | None = None,
                            cell_data: Mapping[str, np.ndarray] | None = None,
                            components: Mapping[str, Sequence[str]] | None = None) -> Path:
    """A ``.vtu`` file: points (n, 2 or 3; z = 0 added in 2D), cells as VTK's flat
    connectivity, end offsets and type numbers; arrays per point and per cell."""
    components = components or {}
    p = _points3(points)
    data = _Appended()
    index = _index_type(max(len(p), int(np.max(offsets, initial=0))))
    xml = (_HEADER.format(kind="UnstructuredGrid") + "<UnstructuredGrid>\n"
           + f'<Piece NumberOfPoints="{len(p)}" NumberOfCells="{len(types)}">\n'
           + data.fields("PointData", point_data or {}, components) + data.fields("CellData", cell_data or {}, components)
           + "<Points>\n" + data.array("Points", p) + "</Points>\n<Cells>\n"
           + data.array("connectivity", np.asarray(connectivity).astype(index))
           + data.array("offsets", np.asarray(offsets).astype(index))
           + data.array("types", np.asarray(types, dtype=np.uint8))
           + "</Cells>\n</Piece>\n</UnstructuredGrid>\n")
    return _write(Path(path), data.document(xml))


def write_polydata(path: str | Path, points: np.ndarray, polys: np.ndarray | None = None, lines: np.ndarray | None = None,
                   point_data: Mapping[str, np.ndarray] | None = None,
                   components: Mapping[str, Sequence[str]] | None = None) -> Path:
    """A ``.vtp`` file: points with triangles ``polys`` (k, 3) or one polyline ``lines`` (its
    point indices in order), and arrays per point."""
    p = _points3(points)
    data = _Appended()
    blocks, counts = "", {"Verts": 0, "Lines": 0, "Strips": 0, "Polys": 0}
    for tag, cells in (("Lines", None if lines is None else np.asarray(lines, dtype=np.int64).reshape(1, -1)),
                       ("Polys", None if polys is None else np.asarray(polys, dtype=np.int64))):
        if cells is None or not cells.size:
            continue
        counts[tag] = len(cells)
        offsets = np.cumsum(np.full(len(cells), cells.shape[1]))
        blocks += f"<{tag}>\n" + data.array("connectivity", cells.ravel()) + data.array("offsets", offsets) + f"</{tag}>\n"
    xml = (_HEADER.format(kind="PolyData") + "<PolyData>\n"
           + f'<Piece NumberOfPoints="{len(p)}" ' + " ".join(f'NumberOf{k}="{v}"' for k, v in counts.items()) + ">\n"
           + data.fields("PointData", point_data or {}, components or {})
           + "<Points>\n" + data.array("Points", p) + "</Points>\n" + blocks + "</Piece>\n</PolyData>\n")
    return _write(Path(path), data.document(xml))


def write_multiblock(path: str | Path, blocks: Sequence[tuple[str, str]]) -> Path:
    """A ``.vtm`` index: one named block per (name, file relative to the index's folder)."""
    from xml.sax.saxutils import quoteattr

    rows = "".join(f'<DataSet index="{k}" name={quoteattr(name)} file={quoteattr(file)}/>\n'
                   for k, (name, file) in enumerate(blocks))
    text = _HEADER.format(kind="vtkMultiBlockDataSet") + f"<vtkMultiBlockDataSet>\n{rows}</vtkMultiBlockDataSet>\n</VTKFile>\n"
    return _write(Path(path), text.encode("ascii"))
