"""STL / OBJ (and other trimesh-readable) meshes -> a tessellation-only :class:`geometry.Part`.

A mesh file carries triangles only, no exact surfaces: every face of the Part has
``surface=None`` and ``surface_type="MESH"``. Each mesh object of the file (an OBJ may hold
several) becomes one body with one face; the face keeps the triangles as read (vertices
merged by trimesh) so projection falls back to the tessellation.
"""

from __future__ import annotations

from pathlib import Path

from ibfem.geometry import Body, Face, Part

__all__ = ["load_mesh_part", "MESH_SURFACE_TYPE"]

MESH_SURFACE_TYPE = "MESH"


def load_mesh_part(path: str | Path, units_scale: float = 1.0) -> Part:
    """Read ``path`` with trimesh; ``units_scale`` multiplies coordinates (e.g. 1e-3 for a
    file in millimetres, since STL has no units and the toolkit works in metres)."""
    import trimesh  # lazy

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such mesh file")
    if not (isinstance(units_scale, (int, float)) and units_scale > 0):
        raise ValueError(f"units_scale must be a positive number, got {units_scale!r}")
    try:
        loaded = trimesh.load(str(path), force=None, process=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise ValueError(f"{path}: cannot read the mesh: {exc}") from None
    if isinstance(loaded, trimesh.Scene):
        meshes = [(name, g) for name, g in loaded.geometry.items() if isinstance(g, trimesh.Trimesh)]
    elif isinstance(loaded, trimesh.Trimesh):
        meshes = [(path.stem, loaded)]
    else:
        meshes = []
    meshes = [(n, m) for n, m in meshes if len(m.faces)]
    if not meshes:
        raise ValueError(f"{path}: no triangles found")
    part = Part(metadata={"source": {"file": str(path), "format": path.suffix.lower().lstrip("."),
                                     "units_scale": float(units_scale)}})
    for k, (name, mesh) in enumerate(meshes):
        mesh = mesh.copy()
        if units_scale != 1.0:
            mesh.apply_scale(units_scale)
        bid, fid = f"B{k}", f"B{k}F0"
        notes = () if mesh.is_watertight else ("mesh is not watertight",)
        part.faces[fid] = Face(id=fid, surface_type=MESH_SURFACE_TYPE, surface=None, orientation=1, mesh=mesh,
                               body_id=bid, notes=notes)
        part.bodies[bid] = Body(id=bid, name=str(name), body_type="SOLID", face_ids=(fid,))
        if notes:
            part.warnings.append(f"body {bid} ({name}): mesh is not watertight")
    part.warnings.append(f"{path.name}: a mesh has no exact surfaces: {len(part.faces)} tessellation-only faces")
    return part
