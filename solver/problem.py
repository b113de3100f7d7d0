"""The solver's input, independent of any file format: plain frozen dataclasses holding
numpy arrays and ``geometry`` profiles. ``solver.scene`` builds a :class:`Problem` from a
validated scene file; ``solver.ibfem.solve`` turns it into a :class:`Solution`.

Units are SI. In 2D every force is per unit thickness (N/m) and every traction a stress (Pa).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, Protocol

import numpy as np

from geometry.profile import Profile

Model = Literal["plane_strain", "plane_stress"]

__all__ = [
    "Model",
    "Material",
    "Refinement",
    "BodyModel",
    "Fixed",
    "Displacement",
    "Sliding",
    "Traction",
    "Pressure",
    "BodyForce",
    "BoundaryCondition",
    "ContactModel",
    "SolverOptions",
    "Problem",
    "Solution",
]


@dataclass(frozen=True)
class Material:
    name: str
    youngs_modulus: float
    poissons_ratio: float

    def lame(self, model: Model) -> tuple[float, float]:
        """(lambda, mu) of the 2D constitutive law: plane strain uses the 3D Lame constants,
        plane stress the reduced lambda* = 2 lambda mu / (lambda + 2 mu)."""
        E, nu = self.youngs_modulus, self.poissons_ratio
        mu = E / (2.0 * (1.0 + nu))
        lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
        if model == "plane_stress":
            lam = 2.0 * lam * mu / (lam + 2.0 * mu)
        return lam, mu

    def elasticity_matrix(self, model: Model) -> np.ndarray:
        """C in Voigt form acting on [exx, eyy, 2 exy] -> [sxx, syy, sxy]."""
        lam, mu = self.lame(model)
        return np.array([[lam + 2 * mu, lam, 0.0], [lam, lam + 2 * mu, 0.0], [0.0, 0.0, mu]])


@dataclass(frozen=True)
class Refinement:
    """Cells within ``radius`` of ``center`` are made 2**levels times finer (graded outside).
    ``center`` None means "around the contact points" and is resolved before solving."""

    levels: int
    radius: float
    center: np.ndarray | None = None


@dataclass(frozen=True)
class BodyModel:
    name: str
    profile: Profile
    material: Material
    element_size: float
    refinements: tuple[Refinement, ...] = ()


@dataclass(frozen=True)
class Fixed:
    body: str
    edge: str


@dataclass(frozen=True)
class Displacement:
    """Prescribed displacement; a component None is free."""

    body: str
    edge: str
    value: tuple[float | None, float | None]


@dataclass(frozen=True)
class Sliding:
    """Normal displacement prescribed along the exact local normal, tangential free."""

    body: str
    edge: str
    normal_displacement: float = 0.0


@dataclass(frozen=True)
class Traction:
    body: str
    edge: str
    value: tuple[float, float]  # Pa, global axes


@dataclass(frozen=True)
class Pressure:
    body: str
    edge: str
    value: float  # Pa, positive pushes into the body


@dataclass(frozen=True)
class BodyForce:
    body: str
    value: tuple[float, float]  # N/m^3


BoundaryCondition = Fixed | Displacement | Sliding | Traction | Pressure | BodyForce


@dataclass(frozen=True)
class ContactModel:
    """Two-body contact (issues 5 and 6). ``point`` None: found as the closest points."""

    bodies: tuple[str, str]
    type: Literal["tied", "frictionless", "frictional"]
    friction: float = 0.0
    point: np.ndarray | None = None


@dataclass(frozen=True)
class SolverOptions:
    load_steps: int = 10
    tolerance: float = 1e-10
    max_iterations: int = 100
    exact_geometry: bool = True
    # Extensions (README "Extensions to the contracts"); None keeps the documented default.
    band_fraction: float | None = None  # step-function band delta / local cell size
    consistency: float | None = None  # 1 symmetric Nitsche (default), 0.5 the thesis's band limit
    chord_tolerance: float | None = None  # m; exact_geometry = false: tessellation chord (default 0.1 h)


@dataclass(frozen=True)
class Problem:
    name: str
    model: Model
    thickness: float
    bodies: tuple[BodyModel, ...]
    boundary_conditions: tuple[BoundaryCondition, ...] = ()
    contacts: tuple[ContactModel, ...] = ()
    options: SolverOptions = field(default_factory=SolverOptions)

    def body(self, name: str) -> BodyModel:
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)


class Solution(Protocol):
    """What ``solve`` returns; results writers rely only on this."""

    converged: bool
    # per body: {"elements", "dofs", "element_size", "min_element_size"}
    body_info: dict[str, dict[str, float]]
    # "body/edge" -> force (2,) the essential condition exerts on its body
    reactions: dict[str, np.ndarray]
    # {"total": int, "per_step": list[int]} and any history worth keeping
    iterations: dict
    timings: dict[str, float]
    contacts: list[dict]  # SPEC section 4 contact blocks (issue 5)

    def body_at(self, points: np.ndarray) -> np.ndarray:
        """Index of the body containing each point (n,), -1 outside all bodies."""

    def displacement(self, points: np.ndarray, body: str | None = None) -> np.ndarray:
        """(n, 2); NaN for points outside the body (or all bodies when body is None)."""

    def stress(self, points: np.ndarray, body: str | None = None) -> np.ndarray:
        """(n, 3) [sxx, syy, sxy]; NaN outside."""

    def von_mises(self, points: np.ndarray, body: str | None = None) -> np.ndarray:
        """(n,) von Mises stress (plane strain includes szz = nu (sxx + syy))."""

    def mesh(self, body: str) -> dict[str, np.ndarray]:
        """Active cells of a body for output: {"nodes" (N, 2), "cells" (M, 4) node indices
        counter-clockwise, "displacement" (N, 2) at the nodes, "cell_stress" (M, 3) at the
        centres of the parts of cells inside the body, "cell_inside_fraction" (M,)}."""
