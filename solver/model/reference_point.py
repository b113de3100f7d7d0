"""A rigid reference point coupled to a face (an edge in 2D), or to the part of it inside a box or
a sphere (a rectangle or a circle in 2D): the way a load is brought into a body at a point, as
with a coupling constraint or a remote point in commercial finite element codes.

Two couplings:

- ``kinematic``: the coupled part of the face moves rigidly with the point, u(x) = U + theta x
  (x - x0) (in 2D theta e_z x (x - x0)), for a prescribed displacement U and rotation theta of the
  point; the reaction force and moment at the point are the coupled traction's resultant.
- ``distributing``: a force F and a moment M at the point are spread over the coupled part as the
  traction t(x) = F / A + omega x (x - c), c the part's centroid, A its area and omega the
  solution of J omega = M + (x0 - c) x F with J the part's polar tensor of area; its resultant is F
  and its moment about x0 is M. The face is otherwise free to deform.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

__all__ = ["Box", "Ball", "ReferencePoint"]


@dataclass(frozen=True)
class Box:
    """The axis-aligned box min <= x <= max (a rectangle in 2D)."""

    min: tuple[float, ...]
    max: tuple[float, ...]

    def contains(self, points: np.ndarray) -> np.ndarray:
        p = np.asarray(points, dtype=float)
        return np.all((p >= np.asarray(self.min)) & (p <= np.asarray(self.max)), axis=1)


@dataclass(frozen=True)
class Ball:
    """The points within ``radius`` of ``center`` (a disc in 2D)."""

    center: tuple[float, ...]
    radius: float

    def contains(self, points: np.ndarray) -> np.ndarray:
        p = np.asarray(points, dtype=float)
        return np.linalg.norm(p - np.asarray(self.center), axis=1) <= self.radius


@dataclass(frozen=True)
class ReferencePoint:
    """A reference point at ``point`` coupled to the face (2D: edge) ``edge`` of ``body``, or to
    its part inside ``region``. Kinematic: ``displacement`` and ``rotation`` (3 components in 3D,
    one in 2D, radians) of the point are prescribed. Distributing: ``force`` and ``moment`` (3
    in 3D, one in 2D) act at the point."""

    body: str
    edge: str
    point: tuple[float, ...]
    coupling: Literal["kinematic", "distributing"] = "kinematic"
    region: Box | Ball | None = None
    displacement: tuple[float, ...] = ()
    rotation: tuple[float, ...] = ()
    force: tuple[float, ...] = ()
    moment: tuple[float, ...] = ()

    @property
    def kinematic(self) -> bool:
        return self.coupling == "kinematic"

    def mask(self, points: np.ndarray) -> np.ndarray:
        """(q,) True at the face's points that are coupled."""
        if self.region is None:
            return np.ones(len(points), dtype=bool)
        return self.region.contains(points)
