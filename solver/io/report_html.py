"""``report.html``: one self-contained page per run (it opens offline, the pictures embedded):
the scene, the main numbers with their units (contacts, reactions, probes, size and time of the
run, the checks) and every PNG the run wrote."""

from __future__ import annotations

import base64
import html
import json
from pathlib import Path
from typing import Any, Mapping

from .result_line import contact_line

__all__ = ["write_report"]

_STYLE = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
          "table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #ccc;padding:3px 8px;"
          "text-align:left;font-size:90%}img{max-width:100%;border:1px solid #ddd;margin:0.5em 0}"
          "pre{background:#f6f6f6;padding:0.8em;overflow-x:auto;font-size:85%}")


def _table(rows: list[tuple[str, str]]) -> str:
    return "<table>" + "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in rows) + "</table>"


def _vector(v: Any, unit: str) -> str:
    if isinstance(v, list):
        return "[" + ", ".join("n/a" if x is None else f"{float(x):.6g}" for x in v) + f"] {unit}"
    return "n/a" if v is None else f"{float(v):.6g} {unit}"


def _check(key: str, value: Any, force: str) -> str:
    """A check's value with its unit: gaps and brackets in m, pressures in Pa, the force on the
    first body in the force unit; counts, flags and ratios as they are."""
    unit = ("m" if "gap" in key or key.endswith("bracket") else "Pa" if "pressure" in key
            else force if key == "force_on_first" else None)
    if unit is None or not (isinstance(value, (int, float, list)) and not isinstance(value, bool)):
        return json.dumps(value)
    return _vector(value, unit)


def _numbers(summary: Mapping[str, Any]) -> str:
    units = summary.get("units") or {}
    force = units.get("force", "N")
    parts = [_table([("converged", str(summary.get("converged"))), ("model", str(summary.get("model"))),
                     ("iterations", str((summary.get("iterations") or {}).get("total"))),
                     ("run time", _vector((summary.get("timings") or {}).get("total_s"), "s")),
                     ("ibfem", str(summary.get("ibfem_version"))), ("created", str(summary.get("created")))])]
    for k, c in enumerate(summary.get("contacts") or []):
        parts.append(f"<h3>contact {k}: {html.escape(' / '.join(c.get('bodies') or []))} ({html.escape(str(c.get('type')))})</h3>")
        parts.append(f"<p>{html.escape(contact_line(c))}</p>")
        checks = c.get("checks") or {}
        if checks:
            parts.append(_table([(key, _check(key, value, force)) for key, value in checks.items()]))
    rows = [(name, _vector(v, force)) for name, v in (summary.get("reactions") or {}).items()]
    if rows:
        parts.append("<h3>reactions</h3>" + _table(rows))
    rows = [(_vector(p.get("point"), "m"), f"{p.get('body')}: stress {_vector(p.get('stress'), 'Pa')}, "
             f"von Mises {_vector(p.get('von_mises'), 'Pa')}") for p in summary.get("probes") or []]
    if rows:
        parts.append("<h3>probes</h3>" + _table(rows))
    rows = [(name, f"{b.get('dofs')} dofs, {b.get('elements')} cells, h = {b.get('element_size')} m "
             f"(finest {b.get('min_element_size')} m)") for name, b in (summary.get("bodies") or {}).items()]
    parts.append("<h3>bodies</h3>" + _table(rows))
    return "".join(parts)


def write_report(out_dir: str | Path, summary: Mapping[str, Any], pictures: list[Path], scene_text: str | None) -> Path:
    """Write ``report.html`` into ``out_dir``; ``summary`` JSON-safe, ``pictures`` the PNG files."""
    out_dir = Path(out_dir)
    images = "".join(f"<h3>{html.escape(p.name)}</h3><img alt=\"{html.escape(p.name)}\" src=\"data:image/png;base64,"
                     f"{base64.b64encode(p.read_bytes()).decode('ascii')}\">" for p in pictures)
    scene = f"<h2>scene</h2><pre>{html.escape(scene_text)}</pre>" if scene_text else ""
    title = html.escape(str(summary.get("name") or "ibfem run"))
    text = (f"<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{title}</title><style>{_STYLE}</style></head>"
            f"<body><h1>{title}</h1><h2>results</h2>{_numbers(summary)}{scene}<h2>pictures</h2>{images}</body></html>\n")
    path = out_dir / "report.html"
    path.write_text(text, encoding="utf-8")
    return path
