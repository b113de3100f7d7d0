"""The solver's input, independent of any file format: plain frozen dataclasses holding
numpy arrays and ``geometry`` profiles. ``solver.scene`` builds a :class:`Problem` from a
validated scene file; ``solver.ibfem.solve`` turns it into a :class:`Solution`.

Units are SI. In 2D every force is per unit thickness (N/m) and every traction a stress (Pa).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Literal, Protocol

import numpy as np

from ibfem.geometry.profile import Profile

from .elasticity import Model, dimension, dundurs_beta, elasticity_matrix, lame_parameters
from .options import ContactOptions, SolverOptions


__all__ = [
    "Model",
    "Material",
    "Refinement",
    "MAX_REFINEMENT_LEVELS",
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
    "ContactOptions",
    "Problem",
    "Solution",
]


@dataclass(frozen=True)
class Material:
    """Linear elastic, isotropic material (SI: Pa). The law itself is in :mod:`solver.model.elasticity`."""

    name: str
    youngs_modulus: float
    poissons_ratio: float

    def lame(self, model: Model) -> tuple[float, float]:
        """(lambda, mu) of the constitutive law for ``model`` (see :func:`elasticity.lame_parameters`)."""
        return lame_parameters(self.youngs_modulus, self.poissons_ratio, model)

    def elasticity_matrix(self, model: Model) -> np.ndarray:
        """C in Voigt form for ``model`` (see :func:`elasticity.elasticity_matrix`)."""
        lam, mu = self.lame(model)
        return elasticity_matrix(lam, mu, dimension(model))


#: refinement deeper than this (cells 2**12 = 4096 times finer) is almost surely a typo
MAX_REFINEMENT_LEVELS = 12


@dataclass(frozen=True)
class Refinement:
    """Cells within ``radius`` of ``center`` are made 2**levels times finer (graded outside).
    ``around_contact``: the zone follows the body's contact points (``around = "contact"``);
    ``center`` is None until :func:`solver.model.resolve.resolve_problem` fills it in (one
    zone per contact point of the body). A zone made with ``center`` None is around_contact."""

    levels: int
    radius: float
    center: np.ndarray | None = None
    around_contact: bool = False

    def __post_init__(self):
        if self.center is None and not self.around_contact:
            object.__setattr__(self, "around_contact", True)
        if isinstance(self.levels, bool) or int(self.levels) != self.levels or not 0 <= self.levels <= MAX_REFINEMENT_LEVELS:
            raise ValueError(f"refinement.levels must be an integer in [0, {MAX_REFINEMENT_LEVELS}], got {self.levels!r}")
        if not (self.radius > 0 and math.isfinite(self.radius)):
            raise ValueError(f"refinement.radius must be positive, got {self.radius!r}")


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
    """Two-body contact. ``point`` None: found as the closest points of the two exact
    boundaries (:mod:`solver.model.resolve`); ``point_given`` records whether the scene gave it.
    ``options``: the numerical choices of this contact's formulation."""

    bodies: tuple[str, str]
    type: Literal["tied", "frictionless", "frictional"]
    friction: float = 0.0
    point: np.ndarray | None = None
    options: ContactOptions = field(default_factory=ContactOptions)
    point_given: bool | None = None
    #: the point as given or found, when it lay at a convex corner of body 1 and ``point`` was moved
    #: off it into the facing edge (solver.model.resolve.point_off_corner)
    moved_from: np.ndarray | None = None

    def __post_init__(self):
        if self.point_given is None:
            object.__setattr__(self, "point_given", self.point is not None)


@dataclass(frozen=True)
class Problem:
    name: str
    model: Model
    thickness: float
    bodies: tuple[BodyModel, ...]
    boundary_conditions: tuple[BoundaryCondition, ...] = ()
    contacts: tuple[ContactModel, ...] = ()
    options: SolverOptions = field(default_factory=SolverOptions)
    #: load paths (solver.model.load_paths.LoadHistory); None: proportional loading to the values
    history: object | None = None

    def body(self, name: str) -> BodyModel:
        for b in self.bodies:
            if b.name == name:
                return b
        raise KeyError(name)

    def candidate_extent(self, contact: "ContactModel", fraction: float) -> float:
        """The radius of a contact's candidate region: ``fraction`` of the smallest
        ``around = "contact"`` refinement radius of its bodies (10 element sizes without one)."""
        radii = [r.radius for n in contact.bodies for r in self.body(n).refinements if r.around_contact]
        if radii:
            return fraction * min(radii)
        return 10.0 * min(self.body(n).element_size for n in contact.bodies)

    @property
    def dim(self) -> int:
        """Spatial dimension of the model (2 for plane strain / plane stress)."""
        return dimension(self.model)

    def with_options(self, **changes) -> "Problem":
        """A copy with ``[solver]`` options changed (checked as in a scene)."""
        return dataclasses.replace(self, options=dataclasses.replace(self.options, **changes))

    def dundurs_beta(self, contact: "ContactModel") -> float:
        """Dundurs' beta of a contact's two bodies, its first body first
        (:func:`elasticity.dundurs_beta`)."""
        first, second = (self.body(name).material.lame(self.model) for name in contact.bodies)
        return dundurs_beta(first, second)

    def with_contact_options(self, **changes) -> "Problem":
        """A copy with the same contact options changed on every contact."""
        contacts = tuple(
            dataclasses.replace(c, options=dataclasses.replace(c.options, **changes)) for c in self.contacts
        )
        return dataclasses.replace(self, contacts=contacts)


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
    contacts: list[dict]  # the contact blocks of summary.json

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


CONTACT_TYPES = ("tied", "frictionless", "frictional")


def check_problem(problem: Problem) -> None:
    """Consistency of a problem built by hand (a scene is checked with key paths before it gets
    here): known, distinct contact bodies, contact types and friction. Raises ValueError."""
    names = [b.name for b in problem.bodies]
    if not names:
        raise ValueError("the problem has no bodies")
    for i, cm in enumerate(problem.contacts):
        for nm in cm.bodies:
            if nm not in names:
                raise ValueError(f"contacts[{i}].bodies: unknown body {nm!r}; bodies: {', '.join(names)}")
        if cm.bodies[0] == cm.bodies[1]:
            raise ValueError(f"contacts[{i}].bodies: a contact needs two different bodies, got {list(cm.bodies)}")
        if cm.type not in CONTACT_TYPES:
            raise ValueError(f"contacts[{i}].type must be one of {', '.join(CONTACT_TYPES)}, got {cm.type!r}")
        mu = cm.friction
        if cm.type == "frictional" and not (isinstance(mu, (int, float)) and math.isfinite(mu) and mu > 0):
            raise ValueError(f"contacts[{i}].friction must be a positive number for frictional contact, got {mu!r}")
