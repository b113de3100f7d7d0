"""``solve(problem) -> Solution``: the one entry of the numerics. Resolves what the problem leaves
implicit (contact points, refinement centres), then runs the linear solve (no contacts) or the
contact load-step driver. The only module that imports both. ``estimate_errors`` adds the
estimated error of each contact's results from a second solve on a grid twice as coarse."""

from __future__ import annotations

import dataclasses
import math
import time
from typing import TYPE_CHECKING, Callable

import numpy as np

from .contact.driver import solve_contact
from .fem.assembly import assemble, essential_reactions, rigid_modes_check
from .fem.linalg import linear_solve
from .fem.path_loads import path_loads
from .fem.bodies import discretise
from .fem.space import body_info
from .model.accuracy import contact_quantities, relative_errors
from .model.resolve import resolve_problem
from .solution import IBFEMSolution

if TYPE_CHECKING:
    from .model.problem import Problem

__all__ = ["solve", "estimate_errors", "coarser", "max_von_mises"]


def solve(problem: Problem, progress: Callable[..., None] | None = None) -> IBFEMSolution:
    """Solve a linear elastic :class:`solver.model.Problem` with IBFEM (every numerical choice is
    in ``problem.options`` and each contact's ``options``). ``progress(stage, fraction)`` is
    called between stages.

    A run that does not converge raises nothing: the returned solution has ``converged`` false
    and keeps its iteration history.

    :raises ValueError: the problem cannot be solved as given (the solver's own checks on its
        input); the message says why.
    :raises MemoryError: the grid does not fit in the machine's memory."""
    problem = resolve_problem(problem)
    if problem.contacts:
        return solve_contact(problem, progress=progress)
    return _solve_linear(problem, progress)


def _solve_linear(problem, progress) -> IBFEMSolution:
    options = problem.options
    t_start = time.perf_counter()
    report = progress or (lambda *a, **k: None)
    timings: dict[str, float] = {}
    t = time.perf_counter()
    bodies = discretise(problem, options, report)
    timings["grid_s"] = time.perf_counter() - t

    report("assembly", 0.4)
    t = time.perf_counter()
    system = assemble(problem, bodies, options)
    timings["assembly_s"] = time.perf_counter() - t

    rigid_modes_check(system.stiffness, bodies)
    report("solve", 0.6)
    t = time.perf_counter()
    steps, factors = [], 1.0
    if problem.history is not None:  # load paths: the state at the end; each step a sum of the columns' fields
        system, steps, factors = _path_steps(problem, bodies, system)
    u = linear_solve(system.stiffness, system.load, bodies, options.linear_solver, tolerance=1e-10)
    timings["solve_s"] = time.perf_counter() - t
    k, f = system.stiffness, system.load
    r = f - k @ u
    residual = float(np.linalg.norm(r) / max(np.linalg.norm(f), 1e-300))
    work = abs(float(u @ r)) / max(abs(float(u @ f)), 1e-300)
    converged = bool(np.isfinite(u).all() and residual < 1e-6 and work <= options.tolerance)
    messages = [] if work <= options.tolerance else [
        f"the residual work of the solution is {work:.3g}, above solver.tolerance = {options.tolerance:g}"
    ]
    reactions, tractions = essential_reactions(system.essentials, u, options, factors)
    timings["total_s"] = time.perf_counter() - t_start
    report("done", 1.0)
    return IBFEMSolution(
        problem=problem,
        bodies=bodies,
        u=u,
        converged=converged,
        body_info=body_info(bodies),
        reactions=reactions,
        iterations={"total": 1, "per_step": [1], "linear_residual": residual, "residual_work": work,
                    "messages": messages},
        timings=timings,
        contacts=[],
        settings=options,
        boundary_tractions=tractions,
        steps=steps,
    )


def _path_steps(problem, bodies, system):
    """Under load paths without contact: the system at the end of the run, the step records
    (t, reactions, field: the columns' fields combined with the factors at t) and the essential
    conditions' factors at the end."""
    import dataclasses

    loads = path_loads(problem, bodies, problem.options)
    fields = np.column_stack([linear_solve(system.stiffness, loads.columns[:, j], bodies, problem.options.linear_solver,
                                           tolerance=1e-10) for j in range(loads.columns.shape[1])])
    times = problem.history.times()
    steps = []
    for t in times:
        u = fields @ loads.weights(t)
        reactions, _ = essential_reactions(system.essentials, u, problem.options, loads.essential_factors(t))
        steps.append({"t": float(t), "reactions": {k: np.asarray(v).tolist() for k, v in reactions.items()},
                      "contacts": [], "field": u})
    end = float(times[-1])
    return dataclasses.replace(system, load=loads.load(end)), steps, loads.essential_factors(end)


def coarser(problem: Problem, factor: float = 2.0) -> Problem:
    """The problem on a grid ``factor`` times coarser everywhere: every body's element size times
    ``factor``, its refinement levels and radii kept (every cell ``factor`` times larger)."""
    bodies = tuple(dataclasses.replace(b, element_size=b.element_size * factor) for b in problem.bodies)
    return dataclasses.replace(problem, bodies=bodies)


def max_von_mises(solution, block: dict, dim: int, samples: int = 21) -> float:
    """The largest von Mises stress below the contact, in both bodies: 2D on a grid of points
    within 1.5 a along the tangent and from 0.05 a to 2 a deep along the normal on either side;
    3D on the normal through the contact point (where Hertz's maximum lies), at the same depths
    (a quarter or half model's symmetry planes: the line moved off them by 1e-6 a into the model)."""
    point = np.asarray(block.get("point"), dtype=float).reshape(dim)
    normal = np.asarray(block.get("normal"), dtype=float).reshape(dim)
    size = block.get("semi_axes") if dim == 3 else block.get("half_width")
    a = max(size) if isinstance(size, (list, tuple)) else size
    if a is None or not a > 0.0:
        return math.nan
    depth = np.concatenate([-np.geomspace(2.0, 0.05, samples), np.geomspace(0.05, 2.0, samples)]) * a
    if dim == 2:
        tangent = np.array([-normal[1], normal[0]])
        along = np.linspace(-1.5, 1.5, samples) * a
        pts = (point + along[:, None, None] * tangent + depth[None, :, None] * normal).reshape(-1, 2)
        candidates = [pts]
    else:
        axes = np.asarray(block.get("axes"), dtype=float).reshape(2, 3)
        line = point + depth[:, None] * normal
        candidates = [line + 1e-6 * a * (i * axes[0] + j * axes[1]) for i in (1, -1) for j in (1, -1)]
    best = math.nan
    for pts in candidates:
        inside = np.asarray(solution.body_at(pts)) >= 0
        if inside.any():
            vm = np.asarray(solution.von_mises(pts[inside]), dtype=float)
            vm = vm[np.isfinite(vm)]
            if len(vm):
                best = float(vm.max()) if not best == best else max(best, float(vm.max()))
    return best


def estimate_errors(problem: Problem, solution: IBFEMSolution, factor: float = 2.0) -> None:
    """Adds to each contact block of ``solution`` its ``max_pressure``, ``max_von_mises`` and
    ``estimated_error`` (relative, per quantity: solver.model.accuracy) from a second solve of
    ``problem`` on a grid ``factor`` times coarser; ``estimate_s`` to the timings. A coarse
    problem that cannot be solved or does not converge leaves ``estimated_error`` null and
    says why in ``estimate_note``."""
    t = time.perf_counter()
    dim = problem.dim
    for block in solution.contacts:
        block["max_pressure"] = contact_quantities(block).get("max_pressure")
        block["max_von_mises"] = max_von_mises(solution, block, dim)
    try:
        coarse = solve(coarser(problem, factor))
        note = None if coarse.converged else "the solve on the coarser grid did not converge"
    except (ValueError, MemoryError) as err:
        coarse, note = None, f"the solve on the coarser grid failed: {err}"
    for k, block in enumerate(solution.contacts):
        other = coarse.contacts[k] if coarse is not None and k < len(coarse.contacts) else None
        if note is None and other is not None:
            other = dict(other, max_von_mises=max_von_mises(coarse, other, dim))
            block["estimated_error"] = relative_errors(contact_quantities(block), contact_quantities(other))
        else:
            block["estimated_error"] = None
            block["estimate_note"] = note or "the coarser grid found no such contact"
    solution.timings["estimate_s"] = time.perf_counter() - t
