"""Two-body contact on the IBFEM core: contact geometry (chord matching, quadrature split at
both grids), formulations behind a protocol with a registry (the band / half-width formulation
of thesis chapter 5 is the first), one bracketed root finder for region sizes and stick ratios,
and the load-step driver that knows no formulation.

Public API: ``solve_contact(problem, progress=None)`` (a resolved problem with contacts),
``FORMULATIONS`` and ``formulation(name)``.
"""

from .driver import solve_contact
from .formulation import FORMULATIONS, formulation

__all__ = ["solve_contact", "FORMULATIONS", "formulation"]
