"""PNG files of RGB pixel arrays, written with the standard library's zlib.

A rendered plot (large flat areas, smooth colour fields) compresses about as well with every row
filtered as the difference to the row above (PNG filter type 2, "Up") at zlib's fastest level as
an adaptive filter does, in under half of Pillow's time at its own fastest level: measured on a
2D run's field picture (1320 x 550 pixels), 8.6 ms and 234 KB against 20.8 ms and 237 KB. The
file format: W3C, Portable Network Graphics (PNG) Specification, second edition (2003)."""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np

__all__ = ["write_png"]

_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: PNG's "Up" filter: each byte stored as its difference to the byte above it (mod 256)
_UP = 2


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def write_png(path: str | Path, rgb: np.ndarray, dpi: float | None = None) -> None:
    """Write ``rgb`` ((height, width, 3) uint8, rows from the top) as an 8-bit RGB PNG; ``dpi``
    is recorded as the image's physical pixel size (how large a document shows it)."""
    rgb = np.asarray(rgb)
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.dtype != np.uint8:
        raise ValueError(f"write_png: {path}: expected (height, width, 3) uint8 pixels, got {rgb.shape} {rgb.dtype}")
    height, width = rgb.shape[:2]
    rows = rgb.reshape(height, 3 * width)
    filtered = np.empty((height, 3 * width + 1), dtype=np.uint8)
    filtered[:, 0] = _UP
    filtered[0, 1:] = rows[0]
    np.subtract(rows[1:], rows[:-1], out=filtered[1:, 1:])  # uint8 arithmetic wraps mod 256, as PNG's
    parts = [_SIGNATURE, _chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))]
    if dpi:
        per_metre = int(round(dpi / 0.0254))
        parts.append(_chunk(b"pHYs", struct.pack(">IIB", per_metre, per_metre, 1)))
    parts += [_chunk(b"IDAT", zlib.compress(filtered.tobytes(), 1)), _chunk(b"IEND", b"")]
    Path(path).write_bytes(b"".join(parts))
