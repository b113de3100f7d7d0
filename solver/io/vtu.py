"""The VTK files of a run: ``<body>.vtu`` per body (solver.io.body_output: the cells clipped by
the exact surface, point and cell data), ``contact_<k>.vtp`` per contact with a region
(solver.io.contact_output) and ``result.vtm``, the index that opens all of them at once in
ParaView. Written directly in VTK's XML format (solver.io.vtk_xml): no VTK library is needed."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ibfem.solver.model import problem as pb

from .body_output import body_output
from .contact_output import region_polydata, surface_pressure
from .vtk_xml import TENSOR_COMPONENTS, write_multiblock, write_polydata, write_unstructured_grid

__all__ = ["write_vtk_files", "write_step_bodies", "step_contacts", "file_stem", "INDEX_NAME"]

#: the multiblock index of every file of a run
INDEX_NAME = "result.vtm"
_COMPONENTS = {"stress": TENSOR_COMPONENTS, "cell_stress": TENSOR_COMPONENTS,
               "principal_stress": ("s1", "s2", "s3"), "displacement": ("x", "y", "z")}


def file_stem(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "body"


def _on_surface(body: pb.BodyModel, tolerance: float):
    phi = getattr(body.profile, "signed_distance", None)
    if phi is None:
        return lambda p: np.zeros(len(p), dtype=bool)
    return lambda p: np.abs(np.asarray(phi(p), dtype=float)) <= tolerance


def _contact_pressure(problem: pb.Problem, body: pb.BodyModel, points: np.ndarray, contacts) -> np.ndarray:
    """Pressure of every contact the body takes part in at its surface points (0 elsewhere)."""
    out = np.zeros(len(points))
    on_surface = _on_surface(body, 1e-6 * float(body.element_size))
    for c in contacts:
        if body.name in (c.get("bodies") or []):
            out = np.maximum(out, surface_pressure(c, points, on_surface))
    return out


def _probe_points(summary: Mapping[str, Any]) -> list:
    """The points of the summary's probes (the output cells are made to hold them)."""
    return [p["point"] for p in summary.get("probes") or [] if p.get("point") is not None]


def write_vtk_files(out_dir: str | Path, problem: pb.Problem, solution: pb.Solution,
                    summary: Mapping[str, Any], progress=None, outputs: dict | None = None) -> list[Path]:
    """Every body's VTU file, every contact region's VTP file and the index; returns the paths.
    ``summary`` is the run's summary (JSON-safe: lists, None for missing values); ``progress``
    is told each file's name before it is made; ``outputs`` (a dict) receives each body's output
    mesh by name, for the pictures (a mesh already in it is written as it is)."""
    report = progress or (lambda *a, **k: None)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written, blocks = [], []
    contacts = summary.get("contacts") or []
    for body in problem.bodies:
        report(f"results: {file_stem(body.name)}.vtu (cells clipped at the surface)")
        mesh = (outputs or {}).get(body.name) or body_output(problem, solution, body, _probe_points(summary))
        if outputs is not None:
            outputs[body.name] = mesh
        mesh.point_data["contact_pressure"] = _contact_pressure(problem, body, mesh.points, contacts)
        path = write_unstructured_grid(out_dir / f"{file_stem(body.name)}.vtu", mesh.points, mesh.connectivity,
                                       mesh.offsets, mesh.types, mesh.point_data, mesh.cell_data, _COMPONENTS)
        written.append(path)
        blocks.append((body.name, path.name))
    for k, c in enumerate(contacts):
        body1 = problem.body(c["bodies"][0]) if c.get("bodies") else None
        region = region_polydata(c, problem.dim, getattr(getattr(body1, "profile", None), "signed_distance", None))
        if region is None:
            continue
        path = write_polydata(out_dir / f"contact_{k}.vtp", region["points"], polys=region.get("polys"),
                              lines=region.get("lines"), point_data=region["point_data"])
        written.append(path)
        blocks.append((f"contact {k}: {' / '.join(c['bodies'])}", path.name))
    written.append(write_multiblock(out_dir / INDEX_NAME, blocks))
    return written


def step_contacts(final_contacts, step: Mapping[str, Any]) -> list[dict]:
    """The contact blocks of one load step, for its files: each final block's geometry (bodies,
    point, normal, tangent or axes) with the step's region (``half_width``, ``region_centre``,
    ``stick_half_width``) and the step's pressure and shear profiles where the step records them
    (a contact with friction history: ``profile`` with ``s``, ``pressure``, ``shear``); a step
    without a profile gives its contact no pressure."""
    blocks = []
    for final, now in zip(final_contacts or [], step.get("contacts") or []):
        block = {k: final.get(k) for k in ("bodies", "type", "point", "normal", "tangent", "axes")}
        block.update({k: now.get(k) for k in ("half_width", "region_centre", "stick_half_width")})
        profile = now.get("profile") or {}
        s = np.asarray(profile.get("s", []), dtype=float).tolist()
        for key in ("pressure", "shear"):
            block[key] = {"s": s, "value": np.asarray(profile.get(key, []), dtype=float).tolist()} \
                if len(profile.get(key, [])) == len(s) else {"s": [], "value": []}
        blocks.append(block)
    return blocks


def write_step_bodies(folder: str | Path, problem: pb.Problem, solution: pb.Solution,
                      contacts: list[dict], probes: list[dict] | None = None) -> list[Path]:
    """One load step's body files (VTU, clipped at the exact surfaces) with its contact pressure
    (``contacts``: :func:`step_contacts`) as the point data ``contact_pressure``; returns the
    VTU paths. The step's contact regions are in ``summary.json``'s ``steps``. ``probes``: the
    summary's probes, which the output cells hold (the same cells as the final files')."""
    written = write_vtk_files(folder, problem, solution, {"contacts": contacts, "probes": probes or []})
    return [p for p in written if p.suffix == ".vtu"]
