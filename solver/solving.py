"""``solve(problem) -> Solution``: the one entry of the numerics. Resolves what the problem leaves
implicit (contact points, refinement centres), then runs the linear solve (no contacts) or the
contact load-step driver. The only module that imports both."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Callable

import numpy as np

from .contact.driver import solve_contact
from .fem.assembly import assemble, essential_reactions, rigid_modes_check
from .fem.linalg import linear_solve
from .fem.path_loads import path_loads
from .fem.bodies import discretise
from .fem.space import body_info
from .model.resolve import resolve_problem
from .solution import IBFEMSolution

if TYPE_CHECKING:
    from .model.problem import Problem

__all__ = ["solve"]


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
