"""Every body of a problem on its background grid: quadtrees over profiles in 2D
(solver.fem.space), octrees over solids in 3D (solver.fem.solid_space), numbered into one dof
vector."""

from __future__ import annotations

from ..model.elasticity import MODELS
from ..model.options import SolverOptions
from .solid_space import discretise_solid_body
from .space import BodyDiscretisation, discretise_body, number_dofs

__all__ = ["discretise"]


def discretise(problem, settings: SolverOptions, progress=None) -> list[BodyDiscretisation]:
    """Grids of all bodies, with their blocks of the global dof vector."""
    report = progress or (lambda *a, **k: None)
    if problem.model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}, got {problem.model!r}")
    discretise_one = discretise_solid_body if problem.model == "solid" else discretise_body
    if not problem.bodies:
        raise ValueError("the problem has no bodies")
    bodies = []
    for i, body in enumerate(problem.bodies):
        report(f"grid {body.name}", 0.4 * i / len(problem.bodies))
        bodies.append(discretise_one(body, i, problem.model, problem.options.exact_geometry, settings))
        _keep_condition_faces(bodies[-1], problem)
    number_dofs(bodies)
    return bodies


def _keep_condition_faces(body: BodyDiscretisation, problem) -> None:
    """Keep the quadrature of a solid's faces that a boundary condition names; the others served
    only the cells' boundary areas (already summed). A curved contact face refined about the
    contact holds most of the points: the ball's dome on the 7.4k-dof sphere_on_flat rung, 142,011
    points and 8.7 MB for the whole run. A face asked for later (``edge_points``) has its rule
    computed again. Under load paths every rule is kept (their conditions are read per step)."""
    rules = getattr(body, "face_rules", None)
    if not rules or problem.history is not None:
        return
    named = {getattr(bc, "edge", None) for bc in problem.boundary_conditions if bc.body == body.name}
    body.face_rules = {face: rule for face, rule in rules.items() if face in named}
