"""The problem, independent of files and grids: materials and the constitutive law, bodies,
boundary conditions, contacts, every solver option, and the resolution of contact points and
refinement centres. Imports only ``geometry``.

Public API: the types of :mod:`.problem` (``Problem``, ``BodyModel``, ``Material``,
``Refinement``, ``Fixed``, ``Displacement``, ``Sliding``, ``Traction``, ``Pressure``,
``BodyForce``, ``ContactModel``, ``Solution``), the options (``SolverOptions``,
``ContactOptions``), ``resolve_problem`` and ``rigid_body_modes``.
"""

from .options import ContactOptions, OptionError, SolverOptions
from .problem import (
    BodyForce,
    BodyModel,
    BoundaryCondition,
    ContactModel,
    Displacement,
    Fixed,
    Material,
    Pressure,
    Problem,
    Refinement,
    Sliding,
    Solution,
    Traction,
)
from .resolve import resolve_problem
from .rigid import rigid_body_modes

__all__ = [
    "BodyForce",
    "BodyModel",
    "BoundaryCondition",
    "ContactModel",
    "ContactOptions",
    "Displacement",
    "Fixed",
    "Material",
    "OptionError",
    "Pressure",
    "Problem",
    "Refinement",
    "Sliding",
    "Solution",
    "SolverOptions",
    "Traction",
    "resolve_problem",
    "rigid_body_modes",
]
