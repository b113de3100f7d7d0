"""Result files of a run (SPEC section 4): ``summary.json``, one VTU file per body and PNG
plots. Everything here relies only on the :class:`solver.problem.Solution` protocol.

``pyvista`` and ``matplotlib`` are imported only when their files are written.
"""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

from solver import problem as pb

__all__ = [
    "von_mises",
    "sample_points",
    "line_points",
    "build_summary",
    "json_safe",
    "write_summary",
    "write_vtu",
    "write_plots",
    "write_results",
]


def von_mises(stress: np.ndarray, model: str, poissons_ratio: float | np.ndarray) -> np.ndarray:
    """Von Mises stress of in-plane stresses (..., 3) = [sxx, syy, sxy]; plane strain adds
    szz = nu (sxx + syy), plane stress has szz = 0."""
    s = np.asarray(stress, dtype=float)
    sxx, syy, sxy = s[..., 0], s[..., 1], s[..., 2]
    szz = np.asarray(poissons_ratio) * (sxx + syy) if model == "plane_strain" else np.zeros_like(sxx)
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxy**2)


def sample_points(problem: pb.Problem, solution: pb.Solution, points: Any) -> dict[str, np.ndarray]:
    """Displacement, stress and von Mises at points, each sampled in the body containing it
    (``solution.body_at``); NaN (null in JSON) where no body contains the point."""
    x = np.asarray(points, dtype=float).reshape(-1, 2)
    n = len(x)
    which = np.asarray(solution.body_at(x), dtype=int).reshape(n)
    disp = np.full((n, 2), np.nan)
    stress = np.full((n, 3), np.nan)
    vm = np.full(n, np.nan)
    for k, body in enumerate(problem.bodies):  # a handful of bodies; each call is vectorised
        sel = which == k
        if not sel.any():
            continue
        disp[sel] = np.asarray(solution.displacement(x[sel], body=body.name), dtype=float).reshape(-1, 2)
        stress[sel] = np.asarray(solution.stress(x[sel], body=body.name), dtype=float).reshape(-1, 3)
        vm[sel] = np.asarray(solution.von_mises(x[sel], body=body.name), dtype=float).reshape(-1)
    names = [b.name for b in problem.bodies]
    body = np.array([names[k] if 0 <= k < len(names) else None for k in which], dtype=object)
    return {"points": x, "body": body, "displacement": disp, "stress": stress, "von_mises": vm}


def line_points(start: Any, end: Any, n: int) -> tuple[np.ndarray, np.ndarray]:
    """n equally spaced points from start to end (both included) and their distance s from start."""
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    t = np.linspace(0.0, 1.0, int(n))
    return a + t[:, None] * (b - a), t * float(np.linalg.norm(b - a))


def _field(obj: Any, key: str) -> Any:
    return obj[key] if isinstance(obj, Mapping) else getattr(obj, key)


def build_summary(
    problem: pb.Problem,
    solution: pb.Solution,
    probes: Iterable[Any] = (),
    lines: Iterable[Any] = (),
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The ``summary.json`` document of SPEC section 4 (plain Python, NaN kept as float NaN;
    :func:`json_safe` turns it into JSON). ``lines`` items have name, start, end, n (objects
    or dicts). Extensions: probes carry ``body``, lines carry ``s`` (distance from start) and
    ``body``; ``timings`` keeps the solver's own entries beside ``total_s``; ``extra`` keys
    are added at the top level."""
    info = solution.body_info
    bodies = {}
    for b in problem.bodies:
        d = dict(info.get(b.name, {}))
        entry = {
            "elements": int(d.pop("elements", 0)),
            "dofs": int(d.pop("dofs", 0)),
            "element_size": float(d.pop("element_size", b.element_size)),
            "min_element_size": float(d.pop("min_element_size", b.element_size)),
        }
        entry.update(d)
        bodies[b.name] = entry

    probe_points = np.asarray([list(p) for p in probes], dtype=float).reshape(-1, 2)
    probe_list = []
    if len(probe_points):
        s = sample_points(problem, solution, probe_points)
        for i in range(len(probe_points)):
            probe_list.append(
                {
                    "point": s["points"][i].tolist(),
                    "body": s["body"][i],
                    "displacement": s["displacement"][i].tolist(),
                    "stress": s["stress"][i].tolist(),
                    "von_mises": float(s["von_mises"][i]),
                }
            )

    line_dict = {}
    for line in lines:
        pts, dist = line_points(_field(line, "start"), _field(line, "end"), _field(line, "n"))
        s = sample_points(problem, solution, pts)
        line_dict[str(_field(line, "name"))] = {
            "points": pts.tolist(),
            "s": dist.tolist(),
            "body": s["body"].tolist(),
            "displacement": s["displacement"].tolist(),
            "stress": s["stress"].tolist(),
            "von_mises": s["von_mises"].tolist(),
        }

    iterations = dict(solution.iterations)
    per_step = [int(k) for k in iterations.get("per_step", [])]
    iterations["per_step"] = per_step
    iterations["total"] = int(iterations.get("total", sum(per_step)))
    iterations = {"total": iterations.pop("total"), "per_step": iterations.pop("per_step"), **iterations}

    timings = {k: float(v) for k, v in dict(solution.timings).items()}
    if total_s is not None:
        if "total_s" in timings:
            timings["solver_total_s"] = timings["total_s"]
        timings["total_s"] = float(total_s)
    timings.setdefault("total_s", float("nan"))
    timings = {"total_s": timings.pop("total_s"), **timings}

    out: dict[str, Any] = {
        "name": problem.name,
        "converged": bool(solution.converged),
        "model": problem.model,
        "bodies": bodies,
        "reactions": {k: np.asarray(v, dtype=float).reshape(2).tolist() for k, v in solution.reactions.items()},
        "contacts": [_contact_block(problem, k, c) for k, c in enumerate(solution.contacts)],
        "probes": probe_list,
        "lines": line_dict,
        "iterations": iterations,
        "timings": timings,
    }
    if extra:
        out.update(extra)
    return out


_CONTACT_KEYS = (
    "bodies", "type", "friction", "point", "normal", "tangent", "half_width", "stick_half_width",
    "normal_force", "tangential_force", "pressure", "shear",
)


def _contact_block(problem: pb.Problem, k: int, block: Mapping[str, Any]) -> dict[str, Any]:
    """A contact block with every SPEC key, in SPEC order: what the scene defines (bodies,
    type, friction) is filled in from the problem, ``tangent`` from its definition
    (-n_y, n_x), and a missing result is null (an empty profile for pressure and shear);
    further keys the solver adds follow."""
    block = dict(block)
    model = problem.contacts[k] if k < len(problem.contacts) else None
    if model is not None:
        block.setdefault("bodies", list(model.bodies))
        block.setdefault("type", model.type)
        block.setdefault("friction", model.friction)
    if block.get("tangent") is None and block.get("normal") is not None:
        n = np.asarray(block["normal"], dtype=float).reshape(2)
        block["tangent"] = [-n[1], n[0]]
    for key in ("pressure", "shear"):
        if block.get(key) is None:
            block[key] = {"s": [], "value": []}
    out = {key: block.pop(key, None) for key in _CONTACT_KEYS}
    out.update(block)
    return out


def json_safe(obj: Any) -> Any:
    """Plain JSON values: numpy arrays and scalars converted, NaN and infinities -> None."""
    if isinstance(obj, Mapping):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, np.ndarray):
        return json_safe(obj.tolist())
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        return x if math.isfinite(x) else None
    if obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"summary value of type {type(obj).__name__} is not JSON-serialisable: {obj!r}")


def write_summary(path: str | Path, summary: Mapping[str, Any]) -> Path:
    """Write JSON (NaN -> null) atomically: a reader never sees a half-written file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(json_safe(summary), indent=1, allow_nan=False)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(text + "\n", encoding="utf-8")
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def _file_stem(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "body"


def _body_mesh(problem: pb.Problem, solution: pb.Solution, body: pb.BodyModel) -> dict[str, np.ndarray]:
    m = solution.mesh(body.name)
    nodes = np.asarray(m["nodes"], dtype=float).reshape(-1, 2)
    cells = np.asarray(m["cells"], dtype=np.int64).reshape(-1, 4)
    disp = np.asarray(m["displacement"], dtype=float).reshape(-1, 2)
    stress = np.asarray(m["cell_stress"], dtype=float).reshape(-1, 3)
    fraction = np.asarray(m.get("cell_inside_fraction", np.ones(len(cells))), dtype=float).reshape(-1)
    vm = von_mises(stress, problem.model, body.material.poissons_ratio)
    return {"nodes": nodes, "cells": cells, "displacement": disp, "stress": stress, "fraction": fraction, "von_mises": vm}


def write_vtu(out_dir: str | Path, problem: pb.Problem, solution: pb.Solution) -> list[Path]:
    """One ``<body>.vtu`` per body: quadrilateral cells (z = 0) with point data
    ``displacement`` (3 components, z = 0, so viewers can warp by it) and cell data
    ``stress`` [sxx, syy, sxy], ``sxx``, ``syy``, ``sxy``, ``von_mises`` and
    ``inside_fraction`` (the part of a cut cell inside the body)."""
    import pyvista as pv

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for body in problem.bodies:
        m = _body_mesh(problem, solution, body)
        points = np.column_stack([m["nodes"], np.zeros(len(m["nodes"]))])
        cells = np.column_stack([np.full(len(m["cells"]), 4, dtype=np.int64), m["cells"]]).ravel()
        types = np.full(len(m["cells"]), pv.CellType.QUAD, dtype=np.uint8)
        grid = pv.UnstructuredGrid(cells, types, points)
        grid.point_data["displacement"] = np.column_stack([m["displacement"], np.zeros(len(points))])
        grid.cell_data["stress"] = m["stress"]
        for k, name in enumerate(("sxx", "syy", "sxy")):
            grid.cell_data[name] = m["stress"][:, k]
        grid.cell_data["von_mises"] = m["von_mises"]
        grid.cell_data["inside_fraction"] = m["fraction"]
        path = out_dir / f"{_file_stem(body.name)}.vtu"
        grid.save(str(path))
        written.append(path)
    return written


def _outline_path(body: pb.BodyModel) -> Any:
    """The body's boundary (outer loop and holes) as a matplotlib compound path, or None."""
    tessellate = getattr(body.profile, "tessellate", None)
    if tessellate is None:
        return None
    from matplotlib.path import Path as MplPath

    verts, codes = [], []
    for points, _ in tessellate(1e-3 * body.element_size):  # sagitta: smooth to the eye
        pts = np.asarray(points, dtype=float)
        verts.append(np.vstack([pts, pts[:1]]))
        c = np.full(len(pts) + 1, MplPath.LINETO, dtype=np.uint8)
        c[0], c[-1] = MplPath.MOVETO, MplPath.CLOSEPOLY
        codes.append(c)
    return MplPath(np.concatenate(verts), np.concatenate(codes)) if verts else None


def write_plots(
    out_dir: str | Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any]
) -> list[Path]:
    """PNG pictures: ``fields.png`` (von Mises and displacement magnitude over every body),
    ``contact_<k>_fields.png`` (the same close to each contact point), ``line_<name>.png`` per
    output line, ``contact_<k>.png`` (pressure and shear) per contact."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.patches import PathPatch

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    summary = json_safe(summary)  # plain lists; None where a value is missing
    written = []

    def save(fig: Any, name: str) -> None:
        path = out_dir / name
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)

    def save_line_plot(fig: Any, ax: Any, xlabel: str, ylabel: str, title: str, name: str) -> None:
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.legend()
        ax.grid(alpha=0.3)
        save(fig, name)

    meshes = [_body_mesh(problem, solution, b) for b in problem.bodies]
    outlines = [_outline_path(b) for b in problem.bodies]

    def field_figure(title: str, window: tuple[float, float, float, float] | None) -> Any:
        """von Mises and displacement magnitude side by side; colour scales from the cells
        in ``window`` (x0, x1, y0, y1), the whole scene when None."""
        fig, axes = plt.subplots(1, 2, figsize=(12, 5), constrained_layout=True)
        allnodes = np.concatenate([m["nodes"] for m in meshes])
        x0, x1, y0, y1 = window or (allnodes[:, 0].min(), allnodes[:, 0].max(), allnodes[:, 1].min(), allnodes[:, 1].max())
        for ax, key, label in (
            (axes[0], "von_mises", "von Mises stress [Pa]"),
            (axes[1], "displacement", "displacement magnitude [m]"),
        ):
            values, shown = [], []
            for m in meshes:
                if key == "von_mises":
                    v = m["von_mises"]
                else:  # node magnitudes averaged onto the cells
                    v = np.linalg.norm(m["displacement"], axis=1)[m["cells"]].mean(axis=1)
                values.append(v)
                lo, hi = m["nodes"][m["cells"]].min(axis=1), m["nodes"][m["cells"]].max(axis=1)
                seen = (hi[:, 0] >= x0) & (lo[:, 0] <= x1) & (hi[:, 1] >= y0) & (lo[:, 1] <= y1)
                shown.append(v[seen & (m["fraction"] > 0)])
            finite = np.concatenate(shown)
            finite = finite[np.isfinite(finite)]
            vmin, vmax = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
            if vmax <= vmin:
                vmax = vmin + max(abs(vmin), 1.0) * 1e-12 + 1e-300
            for m, v, outline in zip(meshes, values, outlines):
                poly = PolyCollection(m["nodes"][m["cells"]], array=v, cmap="viridis", edgecolors="none")
                poly.set_clim(vmin, vmax)
                ax.add_collection(poly)
                if outline is not None:  # cut cells drawn only inside the exact boundary
                    patch = PathPatch(outline, facecolor="none", edgecolor="k", lw=0.6)
                    ax.add_patch(patch)
                    poly.set_clip_path(patch)
            ax.set_xlim(x0, x1)
            ax.set_ylim(y0, y1)
            fig.colorbar(poly, ax=ax, shrink=0.8)
            ax.set_aspect("equal")
            ax.locator_params(nbins=5)
            ax.set_title(f"{title}: {label}", fontsize=10)
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
        return fig

    if meshes:
        save(field_figure(problem.name, None), "fields.png")
        # a close-up of each contact: 4 half-widths (at least 8 of the finest cells) around it
        finest = min(float(d.get("min_element_size") or b.element_size)
                     for b, d in zip(problem.bodies, (summary["bodies"].get(b.name, {}) for b in problem.bodies)))
        for k, c in enumerate(summary.get("contacts", [])):
            if c.get("point") is None or None in c["point"]:
                continue
            half = max(4.0 * float(c.get("half_width") or 0.0), 8.0 * finest)
            px, py = c["point"]
            fig = field_figure(f"{problem.name}, contact {k}", (px - half, px + half, py - half, py + half))
            save(fig, f"contact_{k}_fields.png")

    for name, line in summary.get("lines", {}).items():
        s = np.asarray(line.get("s") or np.linalg.norm(np.subtract(line["points"], line["points"][0]), axis=1), dtype=float)
        stress = np.asarray(line["stress"], dtype=float).reshape(-1, 3)
        vm = np.asarray(line["von_mises"], dtype=float)
        fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
        for k, lab in enumerate(("sxx", "syy", "sxy")):
            ax.plot(s, stress[:, k], label=lab)
        ax.plot(s, vm, "k", lw=2, label="von Mises")
        save_line_plot(
            fig, ax, "distance along the line [m]", "stress [Pa]", f"{problem.name}: line {name}", f"line_{_file_stem(name)}.png"
        )

    for k, c in enumerate(summary.get("contacts", [])):
        pressure, shear = c.get("pressure") or {}, c.get("shear") or {}
        if not (pressure.get("s") or shear.get("s")):
            continue
        fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
        if pressure.get("s"):
            ax.plot(np.asarray(pressure["s"], float), np.asarray(pressure["value"], float), label="pressure")
        if shear.get("s"):
            ax.plot(np.asarray(shear["s"], float), np.asarray(shear["value"], float), label="shear")
        title = f"{problem.name}: contact {' / '.join(c.get('bodies', []))}"
        save_line_plot(fig, ax, "s along the contact curve [m]", "traction [Pa]", title, f"contact_{k}.png")
    return written


def write_results(
    out_dir: str | Path,
    problem: pb.Problem,
    solution: pb.Solution,
    probes: Iterable[Any] = (),
    lines: Iterable[Any] = (),
    vtk: bool = True,
    plots: bool = False,
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """Write every requested file into ``out_dir``; returns the summary written. The summary
    lists the other files under ``files`` (names relative to ``out_dir``)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    summary = build_summary(problem, solution, probes, lines, total_s=total_s, extra=extra)
    files: list[Path] = []
    missing: list[str] = []
    # a missing optional library costs its files, not the summary
    if vtk:
        try:
            files += write_vtu(out_dir, problem, solution)
        except ImportError as err:
            missing.append(f"VTU files not written: pyvista is not installed ({err}); pip install 'ibfem[pictures]'")
    if plots:
        try:
            files += write_plots(out_dir, problem, solution, summary)
        except ImportError as err:
            missing.append(f"plots not written: matplotlib is not installed ({err}); pip install 'ibfem[pictures]'")
    if missing:
        summary["warnings"] = list(summary.get("warnings", [])) + missing
    summary["files"] = sorted(str(p.relative_to(out_dir)) for p in files)
    write_summary(out_dir / "summary.json", summary)
    return summary


def write_scene_results(
    out_dir: str | Path,
    scene: Any,
    solution: pb.Solution,
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """:func:`write_results` with the probes, lines and file choices of a loaded
    :class:`solver.scene.Scene`'s ``[output]`` table."""
    output = scene.output
    return write_results(
        out_dir,
        scene.problem,
        solution,
        probes=output.probes,
        lines=output.lines,
        vtk=output.vtk,
        plots=output.plots,
        total_s=total_s,
        extra=extra,
    )
