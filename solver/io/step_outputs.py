"""The outputs of a run with load paths: the ``steps`` block of ``summary.json``, a VTU series
over the steps (``steps.pvd`` for ParaView, one folder of VTU files per step, with the contact
tractions of each frictional contact with memory as a polyline ``contact_k.vtp``) and
``steps.csv`` (t, forces, half-width, stick half-width of every contact per step; between solids the
tangential force along the contact's first axis and the first semi-axes of the region and of the
stick zone)."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

__all__ = ["steps_block", "write_step_files", "write_pvd"]

#: per-step keys that are arrays for the files, not for summary.json
_ARRAY_KEYS = ("field", "profile", "axis_profile")


def steps_block(steps: list[dict]) -> list[dict]:
    """The steps as written to summary.json (the fields and profiles left out)."""
    out = []
    for st in steps:
        entry = {k: v for k, v in st.items() if k not in _ARRAY_KEYS}
        entry["contacts"] = [{k: v for k, v in c.items() if k not in _ARRAY_KEYS} for c in st.get("contacts", [])]
        out.append(entry)
    return out


def write_pvd(path: Path, entries: list[tuple[float, int, str]]) -> Path:
    """A ParaView collection: (time, part, file relative to the .pvd) per dataset."""
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    lines += [f'    <DataSet timestep="{t:.10g}" group="" part="{part}" file={quoteattr(name)}/>'
              for t, part, name in entries]
    lines += ["  </Collection>", "</VTKFile>", ""]
    path.write_text("\n".join(lines), encoding="utf-8")
    return path


#: the per-point arrays of a contact profile written to the step's polyline
_PROFILE_FIELDS = ("pressure", "shear", "zone", "slip_increment", "accumulated_slip", "tangential_jump")


def _write_contact_profiles(folder: Path, st: dict) -> list[Path]:
    """One polyline per contact with a profile (friction with memory): the sample points of the
    region on the second body's surface with the pressure, the shear on the first body along the
    contact's tangent, the zone (0 stick, +-1 slipping), the step's slip, the accumulated slip and
    the tangential jump."""
    from .vtk_xml import write_polydata

    out = []
    for k, c in enumerate(st.get("contacts", [])):
        prof = c.get("profile")
        if prof is None or not np.any(prof["inside"]):
            continue
        inside = np.asarray(prof["inside"], dtype=bool)
        points = np.asarray(prof["points"], dtype=float)[inside]
        data = {name: np.asarray(prof[name], dtype=float)[inside] for name in _PROFILE_FIELDS}
        data["normal"] = np.asarray(prof["normal"], dtype=float)[inside]
        out.append(write_polydata(folder / f"contact_{k}.vtp", points, lines=np.arange(len(points)), point_data=data))
    return out


def _write_series(out_dir: Path, problem, solution, write_vtu) -> list[Path]:
    files, entries = [], []
    for k, st in enumerate(solution.steps, start=1):
        folder = out_dir / "steps" / f"step_{k:04d}"
        written = write_vtu(folder, problem, dataclasses.replace(solution, u=st["field"]))
        written += _write_contact_profiles(folder, st)
        files += written
        entries += [(st["t"], part, str(p.relative_to(out_dir))) for part, p in enumerate(written)]
    files.append(write_pvd(out_dir / "steps.pvd", entries))
    return files


def _write_csv(out_dir: Path, steps: list[dict]) -> Path:
    head = ["t"]
    n_contacts = len(steps[0]["contacts"]) if steps else 0
    for k in range(n_contacts):
        head += [f"c{k}_normal_force", f"c{k}_tangential_force", f"c{k}_half_width", f"c{k}_stick_half_width"]
    rows = []
    for st in steps:
        row = [st["t"]]
        for c in st["contacts"]:
            if "semi_axes" in c:  # between solids: the tangential force along the first axis, the semi-axes a
                row += [c["normal_force"], c["tangential_force"][0], c["semi_axes"][0], c["stick_semi_axes"][0]]
            else:
                row += [c["normal_force"], c["tangential_force"], c["half_width"], c["stick_half_width"]]
        rows.append(row)
    path = out_dir / "steps.csv"
    np.savetxt(path, np.asarray(rows, dtype=float).reshape(len(rows), -1), delimiter=",", header=",".join(head),
               comments="", fmt="%.10g")
    return path


def write_step_files(out_dir: Path, problem, solution, summary: dict, write_vtu=None, plots: bool = False,
                     missing: list[str] | None = None) -> list[Path]:
    """Every file of a run with paths; ``write_vtu(folder, problem, solution)`` writes one step's
    VTU files (None: no series); a missing optional library is noted in ``missing``."""
    out_dir = Path(out_dir)
    files = [_write_csv(out_dir, solution.steps)]
    if write_vtu is not None:
        try:
            files += _write_series(out_dir, problem, solution, write_vtu)
        except ImportError as err:
            if missing is not None:
                missing.append(f"the VTU step series was not written: pyvista is not installed ({err})")
    from .fretting_outputs import write_fretting_files

    files += write_fretting_files(out_dir, problem, solution, summary, plots=plots, missing=missing)
    return files
