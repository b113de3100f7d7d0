"""The contact of two solids: an ellipse where the surfaces curve apart along both principal
directions (solver.contact.ellipse, Hertzian: the fast path), a region of general shape ending at
body 1's free edges where one relative curvature vanishes (a line contact), both do (a flat
contact, such as a punch with rounded edges), or one is small against the other and body 1 ends
along it within the candidate region (a roller with a crowned profile, whose gap along the line
is not quadratic out to its ends: solver.contact.star_region)."""

from __future__ import annotations

from .ellipse import EllipseContact
from .ellipse import build as build_ellipse
from .star_region import StarRegionContact, configure_star_region, reaches_free_end

__all__ = ["build"]


def build(problem, model, b1, b2, options) -> EllipseContact:
    """The formulation of a contact between two discretised solids, chosen by the relative
    curvatures at its point."""
    return build_ellipse(problem, model, b1, b2, options, general=(StarRegionContact, configure_star_region, reaches_free_end))
