"""A part imported from CAD: faces and edges that carry both their tessellation and, where
the CAD system told us, their exact primitive; loops of coedges link faces to edges.

This module only holds data; ``trimesh`` is imported lazily by whoever builds the meshes
(the importers), so ``from ibfem import geometry`` stays light.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ._base import Curve, Surface

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

    from .solids.domain_moments import FaceMoments

__all__ = ["Coedge", "Loop", "Face", "Edge", "Body", "Part"]


@dataclass(frozen=True)
class Coedge:
    edge_id: str
    same_sense: bool = True  # runs with the edge's direction


@dataclass(frozen=True)
class Loop:
    coedges: tuple[Coedge, ...]
    is_outer: bool = True


@dataclass(frozen=True)
class Face:
    """One face. ``surface`` is None for tessellation-only faces (``surface_type`` then says
    what the CAD system called it). ``orientation`` is +1 when the outward normal of the
    solid equals the surface's own normal (the convention of every importer), -1 when opposite.
    ``moments``: the face's area and moments about a point of it for the solid's outward normal,
    integrated by the importer over the face's parameter domain (``geometry.solids.domain_moments``),
    or None; a solid whose faces all have them takes its volume from them."""

    id: str
    surface_type: str
    surface: Surface | None
    orientation: int
    mesh: "trimesh.Trimesh | None"
    loops: tuple[Loop, ...] = ()
    body_id: str = ""
    vertex_normals: np.ndarray | None = None  # (n, 3) as sent by the CAD system, if any
    notes: tuple[str, ...] = ()
    moments: "FaceMoments | None" = None

    @property
    def is_exact(self) -> bool:
        return self.surface is not None


@dataclass(frozen=True)
class Edge:
    """One edge: exact curve (None when tessellation-only), its polyline (m, 3) and, when
    known, its end points (the trimmed parameter interval of the unbounded curve)."""

    id: str
    curve_type: str
    curve: Curve | None
    polyline: np.ndarray
    start: np.ndarray | None = None
    end: np.ndarray | None = None
    length: float | None = None
    body_id: str = ""
    notes: tuple[str, ...] = ()

    @property
    def is_exact(self) -> bool:
        return self.curve is not None


@dataclass(frozen=True)
class Body:
    id: str
    name: str = ""
    body_type: str = "SOLID"
    face_ids: tuple[str, ...] = ()
    edge_ids: tuple[str, ...] = ()


@dataclass
class Part:
    """Faces and edges keyed by id, bodies grouping them, and free-form metadata
    (source URL, microversion, tolerances) kept for reports."""

    faces: dict[str, Face] = field(default_factory=dict)
    edges: dict[str, Edge] = field(default_factory=dict)
    bodies: dict[str, Body] = field(default_factory=dict)
    metadata: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)

    def exact_faces(self) -> list[Face]:
        return [f for f in self.faces.values() if f.surface is not None]

    def tessellation_only_faces(self) -> list[Face]:
        return [f for f in self.faces.values() if f.surface is None]

    def faces_by_type(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for f in self.faces.values():
            counts[f.surface_type] = counts.get(f.surface_type, 0) + 1
        return counts

    def edges_by_type(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for e in self.edges.values():
            counts[e.curve_type] = counts.get(e.curve_type, 0) + 1
        return counts
