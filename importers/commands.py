"""``ibfem import``, ``ibfem verify`` and ``ibfem info``.

Each handler imports its heavy dependencies when it runs and returns an exit code; errors
(bad URL, HTTP failures, unreadable responses) are printed as one clear message on stderr
with exit code 2 (1 for a verification that fails its tolerances).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def register(sub: "argparse._SubParsersAction") -> None:
    p = sub.add_parser("import", help="fetch an Onshape part studio (or part), or read a STEP/IGES file, and cache it",
                       description="Fetch tessellated faces, tessellated edges and body details of an Onshape "
                       "Part Studio (or one part) into DIR, keyed by microversion. API keys: ONSHAPE_ACCESS_KEY "
                       "and ONSHAPE_SECRET_KEY. A .step/.stp/.iges/.igs file is read with OpenCascade (the 'step' "
                       "extra) and its parsed part (exact surfaces, curves, loops, tessellation) cached in DIR.")
    p.add_argument("url", help="document URL https://<host>/documents/<did>/<w|v|m>/<id>/e/<eid>[?configuration=...], "
                   "or a .step/.stp/.iges/.igs file")
    p.add_argument("--out", required=True, help="directory for the cached responses (or the parsed STEP/IGES part)")
    p.add_argument("--part", default=None, help="part id: import one part instead of the whole Part Studio")
    p.add_argument("--auth", choices=("hmac", "basic"), default="hmac", help="request signing (default) or HTTP Basic")
    p.add_argument("--chord-tolerance", type=float, default=None,
                   help="tessellation chord tolerance (m); STEP/IGES: default 1e-3 of the part's box diagonal")
    p.add_argument("--angle-tolerance", type=float, default=None,
                   help="tessellation angle tolerance (rad, < pi/2); STEP/IGES: default 0.25")
    p.add_argument("--max-facet-width", type=float, default=None, help="largest facet side (m)")
    p.add_argument("--timeout", type=float, default=60.0, help="read timeout per request (s)")
    p.add_argument("--retries", type=int, default=4, help="retries on 429 / 5xx / network errors")
    p.add_argument("--api-version", default="v10", help="API version segment ('' for unversioned /api)")
    p.add_argument("--force", action="store_true", help="fetch even if DIR holds this microversion")
    p.set_defaults(handler=_import)

    p = sub.add_parser("verify", help="check projection onto the exact faces of an imported part",
                       description="Offset every tessellated vertex along its exact outward normal, project it back "
                       "and report per face the largest position and normal error. Tolerances are relative: in "
                       "position 1e4 x the float precision x the part's size for closed-form surfaces, 1e-9 of "
                       "the part's size for B-spline and swept surfaces; in normal, the angle the position "
                       "tolerance subtends at the offset. Vertices at singular points (a cone's apex, a collapsed "
                       "B-spline side) are only checked to lie on the surface. Exit 1 with the reason on stderr "
                       "when a face fails.")
    p.add_argument("directory", help="cached import (ibfem import --out DIR, or fixtures/onshape/<studio>), "
                   "or a .step/.stp/.iges/.igs file")
    p.add_argument("--json", action="store_true",
                   help='print the report as JSON: {"faces": [{"id", "type", "vertices", "max_error", '
                   '"max_normal_error", "exact"}], "max_error", "max_normal_error", "verdict", "reason"}; '
                   'tessellation-only faces have "exact": false and null errors; verdict "pass" or "fail"')
    p.add_argument("--details", action="store_true",
                   help="with --json: add per-face vertex distance / CAD vertex-normal deviation and per-type maxima")
    p.add_argument("--offset", type=float, default=None,
                   help="offset distance along the normal (m); default 1e-3 of the part's size, at most 1e-4 m, "
                   "and at most a fifth of each face's smallest radius of curvature")
    p.set_defaults(handler=_verify)

    p = sub.add_parser("info", help="summarise an imported part: bodies, faces by surface type, edges by curve type")
    p.add_argument("directory", help="cached import directory, a .step/.stp/.iges/.igs file, or an .stl/.obj mesh file")
    p.add_argument("--faces", action="store_true",
                   help="list every face of every solid body: id, surface type, area, centroid, outward normal "
                   "(flat faces) or axis and radius, the values a scene's face selector matches")
    p.set_defaults(handler=_info)


def _fail(command: str, message: str) -> int:
    print(f"ibfem {command}: {message}", file=sys.stderr)
    return 2


STEP_SUFFIXES = (".step", ".stp", ".iges", ".igs")


def _is_step(path: str) -> bool:
    """A STEP/IGES file name, or a directory holding a parsed STEP/IGES part."""
    p = Path(path)
    if p.suffix.lower() in STEP_SUFFIXES:
        return True
    if p.is_dir():
        from ibfem.importers.step.cache import is_cache

        return is_cache(p)
    return False


def _load(path: str):
    p = Path(path)
    if p.is_file() and p.suffix.lower() in (".stl", ".obj", ".ply", ".off"):
        from ibfem.importers.mesh import load_mesh_part

        return load_mesh_part(p)
    if _is_step(path):
        from ibfem.importers.step import load_part as load_step

        return load_step(p)
    from ibfem.importers.onshape import load_part

    return load_part(p)


def _import_step(args: argparse.Namespace) -> int:
    from ibfem.importers.step import load_part, write_cache

    try:
        part = load_part(args.url, tolerance=args.chord_tolerance, angular_tolerance=args.angle_tolerance)
        out = write_cache(part, args.out)
    except (ValueError, OSError) as exc:
        return _fail("import", str(exc))
    counts = ", ".join(f"{n} {t}" for t, n in sorted(part.faces_by_type().items()))
    timing = part.metadata.get("timing", {})
    print(f"imported {len(part.bodies)} bodies, {len(part.faces)} faces ({counts}) from {args.url} into {out} "
          f"in {sum(timing.values()):.2f} s")
    for w in part.warnings:
        print(f"warning: {w}", file=sys.stderr)
    return 0


def _import(args: argparse.Namespace) -> int:
    if _is_step(args.url):
        return _import_step(args)
    from ibfem.importers import OnshapeError
    from ibfem.importers.onshape import OnshapeClient, load_part

    try:
        client = OnshapeClient(auth=args.auth, api_version=args.api_version or None,
                               timeout=(10.0, args.timeout), max_retries=args.retries,
                               chord_tolerance=args.chord_tolerance, angle_tolerance=args.angle_tolerance,
                               max_facet_width=args.max_facet_width)
        out = client.fetch(args.url, args.out, part_id=args.part, force=args.force)
        part = load_part(out)
    except (OnshapeError, ValueError, OSError) as exc:
        return _fail("import", str(exc))
    counts = ", ".join(f"{n} {t}" for t, n in sorted(part.faces_by_type().items()))
    print(f"imported {len(part.bodies)} bodies, {len(part.faces)} faces ({counts}) into {out}")
    for w in part.warnings:
        print(f"warning: {w}", file=sys.stderr)
    return 0


def _verify(args: argparse.Namespace) -> int:
    from ibfem.geometry.verify import verify_projection

    try:
        part = _load(args.directory)
        report = verify_projection(part, args.offset)
    except (ValueError, OSError) as exc:
        return _fail("verify", str(exc))
    ok = report["verdict"] == "pass"
    if args.json:
        print(json.dumps(report if args.details else spec_report(report), indent=2))
    else:
        print(format_verify_report(report, args.directory))
        for w in part.warnings:
            print(f"warning: {w}")
        print("OK" if ok else "FAILED")
    if not ok:
        print(f"ibfem verify: {args.directory}: FAILED: {report['reason']}", file=sys.stderr)
    return 0 if ok else 1


FACE_KEYS = ("id", "type", "vertices", "max_error", "max_normal_error", "exact")
VERDICT_KEYS = ("max_error", "max_normal_error", "verdict", "reason")


def spec_report(report: dict) -> dict:
    """The JSON report: per face id, type, vertices, max_error, max_normal_error (plus
    ``exact``, false for tessellation-only faces whose errors are null), and the part's largest
    errors, ``verdict`` ("pass" / "fail") and ``reason``."""
    return {"faces": [{k: f[k] for k in FACE_KEYS} for f in report["faces"]],
            **{k: report[k] for k in VERDICT_KEYS}}


def format_verify_report(report: dict, title: str = "") -> str:
    lines = [f"projection check of {title} (offset {report['offset']:g} m along the exact outward normal)", ""]
    lines.append(f"{'face':<10} {'type':<10} {'vertices':>8} {'max error (m)':>15} {'normal error (rad)':>19}")
    for f in report["faces"]:
        if f["exact"] and f["max_error"] is not None:
            lines.append(f"{f['id']:<10} {f['type']:<10} {f['vertices']:>8} {f['max_error']:>15.3e} "
                         f"{f['max_normal_error']:>19.3e}")
        else:
            lines.append(f"{f['id']:<10} {f['type']:<10} {f['vertices']:>8} {'tessellation-only':>35}"
                         if f["exact"] is False else f"{f['id']:<10} {f['type']:<10} {0:>8} {'no tessellation':>35}")
    lines += ["", f"{'surface type':<14} {'faces':>5} {'vertices':>8} {'max error (m)':>15} {'normal error (rad)':>19}"]
    for t, e in sorted(report["by_type"].items()):
        if e["max_error"] is None:
            lines.append(f"{t:<14} {e['faces']:>5} {e['vertices']:>8} {'tessellation-only':>35}")
        else:
            lines.append(f"{t:<14} {e['faces']:>5} {e['vertices']:>8} {e['max_error']:>15.3e} "
                         f"{e['max_normal_error']:>19.3e}")
    lines.append(f"\nlargest position error {report['max_error']:.3e} m, normal error "
                 f"{report['max_normal_error']:.3e} rad over {report['exact_faces']} exact faces; "
                 f"{report['tessellation_only_faces']} tessellation-only")
    return "\n".join(lines)


def _info(args: argparse.Namespace) -> int:
    try:
        part = _load(args.directory)
    except (ValueError, OSError) as exc:
        return _fail("info", str(exc))
    print(format_info(part, args.directory))
    if getattr(args, "faces", False):
        print("")
        print(format_faces(part))
    return 0


def format_faces(part) -> str:
    """Every face of every solid body with its geometry (geometry.solids.face_summary); a body
    whose faces cannot make a solid (no tessellation) is named with the reason."""
    import numpy as np

    from ibfem.geometry.solids.face_summary import face_summary
    from ibfem.geometry.solids.part_solid import PartSolid

    def vec(v) -> str:
        if v is None:
            return "-"
        a = np.asarray(v, dtype=float)
        a = np.where(np.abs(a) > 1e-12 * (1.0 + np.abs(a).max()), a, 0.0)
        return "[" + ", ".join(f"{x:.4g}" for x in a) + "]"

    lines = [f"{'body':<8} {'face':<10} {'type':<11} {'area (m^2)':>11}  {'centroid (m)':<30} "
             f"{'normal / axis':<24} {'radius (m)':>10}"]
    for b in part.bodies.values():
        try:
            solid = PartSolid(part, b.id)
        except ValueError as exc:
            lines.append(f"{b.id:<8} (no solid: {exc})")
            continue
        for name, face in solid.faces.items():
            f = face_summary(name, face)
            direction = vec(f.get("normal")) if f["type"] == "plane" else vec(f.get("axis"))
            radius = f"{f['radius']:.6g}" if isinstance(f.get("radius"), float) else "-"
            lines.append(f"{b.id:<8} {name:<10} {f['type']:<11} {f['area']:>11.5g}  {vec(f.get('centroid')):<30} "
                         f"{direction:<24} {radius:>10}")
    return "\n".join(lines)


def format_info(part, title: str = "") -> str:
    src = part.metadata.get("source") or {}
    lines = [f"{title}"]
    if src.get("url"):
        lines.append(f"source: {src['url']}  microversion {src.get('microversion')}")
    wf = part.metadata.get("wire_format")
    if wf:
        lines.append("wire format: " + ", ".join(f"{k} {v}" for k, v in wf.items()))
    lines += ["", f"{'body':<8} {'name':<24} {'type':<8} {'faces':>5} {'edges':>5} {'triangles':>9}"]
    for b in part.bodies.values():
        tris = sum(len(part.faces[f].mesh.faces) for f in b.face_ids if part.faces[f].mesh is not None)
        lines.append(f"{b.id:<8} {b.name[:24]:<24} {b.body_type:<8} {len(b.face_ids):>5} {len(b.edge_ids):>5} {tris:>9}")
    lines += ["", f"{'surface type':<14} {'faces':>5}  exact"]
    for t, n in sorted(part.faces_by_type().items()):
        exact = any(f.surface is not None for f in part.faces.values() if f.surface_type == t)
        lines.append(f"{t:<14} {n:>5}  {'yes' if exact else 'no (tessellation-only)'}")
    lines += ["", f"{'curve type':<14} {'edges':>5}  exact"]
    for t, n in sorted(part.edges_by_type().items()):
        exact = any(e.curve is not None for e in part.edges.values() if e.curve_type == t)
        lines.append(f"{t:<14} {n:>5}  {'yes' if exact else 'no (tessellation-only)'}")
    if part.warnings:
        lines.append("")
        lines += [f"warning: {w}" for w in part.warnings]
    return "\n".join(lines)
