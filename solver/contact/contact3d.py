"""The contact of two solids: an ellipse where the surfaces curve apart along both principal
directions (solver.contact.ellipse, Hertzian: the fast path), a region of general shape ending at
body 1's free edges where one relative curvature vanishes (a line contact) or both do (a flat
contact, such as a punch with rounded edges: solver.contact.star_region)."""

from __future__ import annotations

from .ellipse import EllipseContact
from .ellipse import build as build_ellipse
from .star_region import StarRegionContact, configure_star_region

__all__ = ["build"]


def build(problem, model, b1, b2, options) -> EllipseContact:
    """The formulation of a contact between two discretised solids, chosen by the relative
    curvatures at its point."""
    return build_ellipse(problem, model, b1, b2, options, general=(StarRegionContact, configure_star_region))
