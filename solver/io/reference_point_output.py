"""The ``reference_points`` block of the results: for each reference point condition, the point's
force and moment and its displacement and rotation. A kinematic coupling prescribes the motion
and reacts with the coupled traction's resultant about the point; a distributing coupling applies
the given force and moment, and the point moves with the rigid motion closest (weighted least
squares) to the coupled points' displacement."""

from __future__ import annotations

from typing import Any

import numpy as np

from ibfem.solver.fem.reference_point import resultant, rigid_fit
from ibfem.solver.model.reference_point import ReferencePoint

__all__ = ["reference_point_blocks"]


def _motion(solution: Any, bc: ReferencePoint) -> tuple[np.ndarray, np.ndarray]:
    body = next(b for b in solution.bodies if b.name == bc.body)
    bp = body.edge_points(bc.edge, solution.settings.boundary_order, traction=False)
    weights = np.where(bc.mask(bp.points), bp.weights, 0.0)
    u = np.asarray(solution.displacement(bp.points, bc.body), dtype=float)
    return rigid_fit(bp.points, weights, u, np.asarray(bc.point, dtype=float))


def _block(solution: Any, bc: ReferencePoint) -> dict[str, Any]:
    point = np.asarray(bc.point, dtype=float)
    if bc.kinematic:
        points, weights, traction = solution.boundary_tractions[f"{bc.body}/{bc.edge}"]
        force, moment = resultant(points, weights, traction, point)
        displacement, rotation = np.asarray(bc.displacement), np.asarray(bc.rotation)
    else:
        force, moment = np.asarray(bc.force), np.asarray(bc.moment)
        displacement, rotation = _motion(solution, bc)
    return {"body": bc.body, "face": bc.edge, "point": point.tolist(), "coupling": bc.coupling,
            "force": np.asarray(force, float).tolist(), "moment": np.asarray(moment, float).tolist(),
            "displacement": np.asarray(displacement, float).tolist(),
            "rotation": np.asarray(rotation, float).tolist()}


def reference_point_blocks(problem: Any, solution: Any) -> list[dict[str, Any]]:
    """One block per reference point condition of ``problem`` (none: an empty list). Force and
    moment are those the point exerts on the body (for a kinematic coupling, the reaction that
    imposes the prescribed motion), the moment about the point."""
    return [_block(solution, bc) for bc in problem.boundary_conditions if isinstance(bc, ReferencePoint)]
