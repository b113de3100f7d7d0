"""``summary.json`` of a run: the document, its probes and lines sampled from the solution,
JSON-safe values and the atomic writer. Everything here relies only on the
:class:`solver.model.problem.Solution` protocol."""

from __future__ import annotations

import functools

import json
import math
import os
import re
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

from ibfem.solver.model import problem as pb
from ibfem.solver.model.elasticity import von_mises
from ibfem.solver.model.reference_point import ReferencePoint

from .reference_point_output import reference_point_blocks

__all__ = [
    "von_mises",
    "sample_points",
    "line_points",
    "build_summary",
    "json_safe",
    "write_summary",
]


def sample_points(problem: pb.Problem, solution: pb.Solution, points: Any) -> dict[str, np.ndarray]:
    """Displacement, stress and von Mises at points, each sampled in the body containing it
    (``solution.body_at``); NaN (null in JSON) where no body contains the point."""
    dim = problem.dim
    voigt = dim * (dim + 1) // 2
    x = np.asarray(points, dtype=float).reshape(-1, dim)
    n = len(x)
    which = np.asarray(solution.body_at(x), dtype=int).reshape(n)
    disp = np.full((n, dim), np.nan)
    stress = np.full((n, voigt), np.nan)
    vm = np.full(n, np.nan)
    for k, body in enumerate(problem.bodies):  # a handful of bodies; each call is vectorised
        sel = which == k
        if not sel.any():
            continue
        disp[sel] = np.asarray(solution.displacement(x[sel], body=body.name), dtype=float).reshape(-1, dim)
        stress[sel] = np.asarray(solution.stress(x[sel], body=body.name), dtype=float).reshape(-1, voigt)
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


def _probe_blocks(problem: pb.Problem, solution: pb.Solution, probes: Iterable[Any]) -> list[dict[str, Any]]:
    probe_points = np.asarray([list(p) for p in probes], dtype=float).reshape(-1, problem.dim)
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
    return probe_list


def _line_blocks(problem: pb.Problem, solution: pb.Solution, lines: Iterable[Any]) -> dict[str, Any]:
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
    return line_dict


def _iterations_block(history: Mapping[str, Any]) -> dict[str, Any]:
    """``iterations``: total and per_step first, the solver's further history after."""
    iterations = dict(history)
    per_step = [int(k) for k in iterations.get("per_step", [])]
    iterations["per_step"] = per_step
    iterations["total"] = int(iterations.get("total", sum(per_step)))
    iterations = {"total": iterations.pop("total"), "per_step": iterations.pop("per_step"), **iterations}
    return iterations


def _timings_block(solver_timings: Mapping[str, float], total_s: float | None) -> dict[str, float]:
    """``timings``: total_s (the whole run when given; the solver's own as solver_total_s) first."""
    timings = {k: float(v) for k, v in dict(solver_timings).items()}
    if total_s is not None:
        if "total_s" in timings:
            timings["solver_total_s"] = timings["total_s"]
        timings["total_s"] = float(total_s)
    timings.setdefault("total_s", float("nan"))
    timings = {"total_s": timings.pop("total_s"), **timings}
    return timings


@functools.cache
def _version() -> str:
    try:
        return metadata.version("ibfem")
    except metadata.PackageNotFoundError:  # a source tree that was never installed
        return "unknown"


def units(dim: int) -> dict[str, str]:
    """The units of the summary's numbers: SI throughout; in 2D forces are per unit thickness."""
    return {"length": "m", "displacement": "m", "stress": "Pa", "pressure": "Pa", "traction": "Pa",
            "force": "N" if dim == 3 else "N/m", "area": "m^2" if dim == 3 else "m", "time": "s"}


def build_summary(
    problem: pb.Problem,
    solution: pb.Solution,
    probes: Iterable[Any] = (),
    lines: Iterable[Any] = (),
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
    earlier: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The ``summary.json`` document (plain Python, NaN kept as float NaN;
    :func:`json_safe` turns it into JSON). ``lines`` items have name, start, end, n (objects
    or dicts). Extensions: probes carry ``body``, lines carry ``s`` (distance from start) and
    ``body``; ``timings`` keeps the solver's own entries beside ``total_s``; ``extra`` keys
    are added at the top level. ``earlier``: a summary built before of the same solution field
    (the pictures' summary, built before the error estimate added its numbers to the contacts):
    its probes and lines, sampled from that field, are taken as they are."""
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

    if earlier is not None and "probes" in earlier and "lines" in earlier:
        probe_list, line_dict = earlier["probes"], earlier["lines"]
    else:
        probe_list = _probe_blocks(problem, solution, probes)
        line_dict = _line_blocks(problem, solution, lines)
    iterations = _iterations_block(solution.iterations)
    timings = _timings_block(solution.timings, total_s)

    out: dict[str, Any] = {
        "name": problem.name,
        "converged": bool(solution.converged),
        "model": problem.model,
        "ibfem_version": _version(),
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "units": units(problem.dim),
        "bodies": bodies,
        "reactions": {k: np.asarray(v, dtype=float).reshape(problem.dim).tolist() for k, v in solution.reactions.items()},
        "contacts": [_contact_block(problem, k, c) for k, c in enumerate(solution.contacts)],
        "probes": probe_list,
        "lines": line_dict,
        "iterations": iterations,
        "timings": timings,
    }
    if any(isinstance(bc, ReferencePoint) for bc in problem.boundary_conditions):
        out["reference_points"] = reference_point_blocks(problem, solution)
    if getattr(solution, "steps", None):  # load paths: one record per step (solver.io.step_outputs)
        from .step_outputs import steps_block

        out["steps"] = steps_block(solution.steps)
    if extra:
        out.update(extra)
    return out


_CONTACT_KEYS = (
    "bodies", "type", "friction", "point", "normal", "tangent", "half_width", "stick_half_width",
    "normal_force", "tangential_force", "pressure", "shear",
)


_CONTACT_KEYS_3D = (
    "bodies", "type", "friction", "point", "normal", "axes", "semi_axes", "stick_semi_axes",
    "normal_force", "tangential_force", "pressure", "shear",
)


#: the solver's verdicts renamed to say what they count or compare
CHECK_NAMES = {
    "penetration": "penetration_found",
    "tension": "tension_at_region_edges",
    "edge_penetration": "penetration_at_region_edges",
    "edge_gap": "gap_beyond_region_edges",
    "edge_pressure": "pressure_inside_region_edges",
    "penetration_points": "overlapping_samples_outside_region",
    "tension_points": "tensile_samples_inside_region",
    "min_gap": "smallest_gap_outside_region",
    "min_pressure": "smallest_pressure_inside_region",
}


def _contact_block(problem: pb.Problem, k: int, block: Mapping[str, Any]) -> dict[str, Any]:
    """A contact block with every documented key, in order (2D: half widths; 3D: semi-axes;
    every type has them all: the stick size of a tied contact is its size, of a frictionless one
    zero, and a frictionless contact's tangential force and shear are the computed ones, the
    check that none passes): what the scene defines (bodies, type, friction) is filled in from the
    problem, ``tangent`` from its definition (-n_y, n_x), and a missing result is null (an empty
    profile for pressure and shear); further keys the solver adds follow, its ``checks`` renamed
    (CHECK_NAMES); a symmetric model's block has ``full_contact``."""
    block = dict(block)
    model = problem.contacts[k] if k < len(problem.contacts) else None
    if model is not None:
        block.setdefault("bodies", list(model.bodies))
        block.setdefault("type", model.type)
        block.setdefault("friction", model.friction)
        block.setdefault("dundurs_beta", problem.dundurs_beta(model))
    if problem.dim == 2 and block.get("tangent") is None and block.get("normal") is not None:
        n = np.asarray(block["normal"], dtype=float).reshape(2)
        block["tangent"] = [-n[1], n[0]]
    empty = {f"axis{j}": {"s": [], "value": []} for j in (0, 1)} if problem.dim == 3 else {"s": [], "value": []}
    for key in ("pressure", "shear"):
        if block.get(key) is None:
            block[key] = empty
    order = _CONTACT_KEYS_3D if problem.dim == 3 else _CONTACT_KEYS
    out = {key: block.pop(key, None) for key in order}
    if isinstance(block.get("checks"), Mapping):
        block["checks"] = {CHECK_NAMES.get(name, name): value for name, value in block["checks"].items()}
    out.update(block)
    share = out.get("model_share")
    if isinstance(share, (int, float)) and 0.0 < share < 1.0 - 1e-6 and isinstance(out.get("normal_force"), (int, float)):
        out["full_contact"] = {"model_share": float(share), "normal_force": float(out["normal_force"]) / float(share)}
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
