"""``solve(problem) -> Solution``: the one entry of the numerics. Resolves what the problem leaves
implicit (contact points, refinement centres), then runs the linear solve (no contacts) or the
contact load-step driver. The only module that imports both. ``estimate_errors`` adds the
estimated error of each contact's results from a second solve on a grid twice as coarse (in 2D
a third on one 4 times as coarse for the sizes)."""

from __future__ import annotations

import dataclasses
import math
import time
from functools import partial
from typing import TYPE_CHECKING, Callable

import numpy as np

from .contact.driver import solve_contact
from .fem.assembly import assemble, essential_reactions, rigid_modes_check
from .fem.linalg import linear_solve
from .fem.path_loads import path_loads
from .fem.bodies import discretise
from .fem.space import body_info
from .model.accuracy import (COMPLETE_END_ORDER_RANGE, SIZE_ORDER_RANGE, complementary_energy_density, contact_quantities,
                             far_field_force_error, has_complete_end,
                             largest_error, orders_for, peak_size_share, refinement_ratio, relative_errors,
                             size_orders)
from .model.estimate import available_memory, estimate_size
from .model.problem import MAX_REFINEMENT_LEVELS, Refinement
from .model.resolve import resolve_problem
from .solution import IBFEMSolution

if TYPE_CHECKING:
    from .model.problem import Problem

__all__ = ["solve", "estimate_errors", "solve_to_accuracy", "coarser", "refined_around_contacts", "max_von_mises"]


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
    (a quarter or half model's symmetry planes: the line moved off them by 1e-6 a into the model).
    The largest sample is then refined between its neighbours by ``samples`` points along each
    direction sampled: the depths alone, 21 of them from 0.05 a to 2 a, are 1.2 times apart, and
    Hertz's sphere's stress sampled there misses its peak (0.620 p0 at 0.48 a) by 0.10 %."""
    if block.get("point") is None or block.get("normal") is None:
        return math.nan
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
        axes = [along, depth]
        lines = lambda t, d: [point + t[:, None, None] * tangent + d[None, :, None] * normal]  # noqa: E731
    else:
        frame = np.asarray(block.get("axes"), dtype=float).reshape(2, 3)
        axes = [depth]
        lines = lambda d: [point + d[:, None] * normal + 1e-6 * a * (i * frame[0] + j * frame[1])  # noqa: E731
                           for i in (1, -1) for j in (1, -1)]
    best, where = _largest_von_mises(solution, lines(*axes))
    if where is None:
        return best
    finer = [np.linspace(x[max(k - 1, 0)], x[min(k + 1, len(x) - 1)], samples) for x, k in zip(axes, where)]
    return max(best, _largest_von_mises(solution, lines(*finer))[0])


def _largest_von_mises(solution, candidates: list) -> tuple[float, tuple | None]:
    """The largest von Mises stress at the points of ``candidates`` (arrays of points, the last
    axis the coordinates) inside a body, and the index (without the last axis) of where it lies in
    its array; (nan, None) where none is inside."""
    best, where = math.nan, None
    for grid in candidates:
        pts = grid.reshape(-1, grid.shape[-1])
        inside = np.asarray(solution.body_at(pts)) >= 0
        if not inside.any():
            continue
        vm = np.full(len(pts), -np.inf)
        vm[inside] = np.asarray(solution.von_mises(pts[inside]), dtype=float)
        vm[~np.isfinite(vm)] = -np.inf
        k = int(np.argmax(vm))
        if np.isfinite(vm[k]) and not vm[k] <= best:
            best, where = float(vm[k]), np.unravel_index(k, grid.shape[:-1])
    return best, where


def _add_estimates(fine: IBFEMSolution, coarse: IBFEMSolution | None, dim: int, note: str | None,
                   coarsest: IBFEMSolution | None = None, ratios: tuple[float, float] = (2.0, 2.0)) -> list[dict]:
    """Each contact block of ``fine`` gets ``max_pressure``, ``max_von_mises`` and
    ``estimated_error`` against ``coarse`` (a solution on a grid twice as coarse, or ``ratios[0]``
    times), or a null estimate and ``estimate_note``. ``coarsest``, a third grid twice (or
    ``ratios[1]`` times) as coarse again, gives the regions' sizes the three-grid estimate
    (solver.model.accuracy.three_grid_error). Returns each contact's sizes' observed orders on
    the three grids (solver.model.accuracy.size_orders; empty without a third grid)."""
    observed: list[dict] = []
    for block in fine.contacts:
        block["max_pressure"] = contact_quantities(block).get("max_pressure")
        block["max_von_mises"] = max_von_mises(fine, block, dim)
    for k, block in enumerate(fine.contacts):
        other = coarse.contacts[k] if coarse is not None and k < len(coarse.contacts) else None
        if note is None and other is not None:
            if other.get("max_von_mises") is None:  # a partner not yet sampled (a rung's is)
                other = dict(other, max_von_mises=max_von_mises(coarse, other, dim))
            third = coarsest.contacts[k] if coarsest is not None and k < len(coarsest.contacts) else None
            span = COMPLETE_END_ORDER_RANGE if has_complete_end(block) else SIZE_ORDER_RANGE
            grids = [contact_quantities(block), contact_quantities(other, like=block),
                     contact_quantities(third) if third is not None else None]
            block["estimated_error"] = relative_errors(*grids[:2], orders_for(block), coarsest=grids[2],
                                                       order_range=span, size_share=peak_size_share(block),
                                                       ratios=ratios)
            block.pop("estimate_note", None)
            observed.append(size_orders(*grids, span, ratios) if grids[2] is not None else {})
        else:
            block["estimated_error"] = None
            block["estimate_note"] = note or "the coarser grid found no such contact"
            observed.append({})
    if dim == 3:
        _add_far_field(fine)
    return observed


#: Gauss points per axis of each cell for the energy error (2: exact for the trilinear field)
_GAUSS = np.array([-1.0, 1.0]) / math.sqrt(3.0)


def far_field_energy(solution: IBFEMSolution, centre, radius: float) -> tuple[float, float]:
    """(error energy beyond ``radius`` from ``centre``, strain energy U_h) of a 3D solution: the
    Zienkiewicz-Zhu estimate of ||u - u_h||^2 in the energy norm (the recovered stress against
    the discrete field's, O. C. Zienkiewicz and J. Z. Zhu, A simple error estimator and adaptive
    procedure for practical engineering analysis, Int. J. Numer. Methods Eng. 24, 337-357, 1987)
    summed over the cells whose centres lie beyond ``radius``, and the strain energy of the
    whole solution, both by 2 x 2 x 2 Gauss points per cell weighted by the cell's inside
    volume (the points outside the body dropped; a cut cell with none inside takes its inside
    part's centroid)."""
    local = np.array(np.meshgrid(_GAUSS, _GAUSS, _GAUSS, indexing="ij")).reshape(3, -1).T
    centre = np.asarray(centre, dtype=float)
    error, energy = 0.0, 0.0
    for body in solution.bodies:
        grid, material = body.grid, solution.problem.body(body.name).material
        corners = grid.nodes[grid.cells]
        low, high = corners.min(axis=1), corners.max(axis=1)
        middle = 0.5 * (low + high)
        points = (middle[:, None, :] + 0.5 * (high - low)[:, None, :] * local[None]).reshape(-1, 3)
        cells = np.repeat(np.arange(len(middle)), len(local))
        keep = body.contains(points)
        points, cells = points[keep], cells[keep]
        # a cut cell none of whose Gauss points lies inside keeps its volume at its inside centroid
        empty = np.nonzero((np.bincount(cells, minlength=len(middle)) == 0) & (body.inside_volume > 0.0))[0]
        points = np.concatenate([points, body.cell_centroids()[empty]])
        cells = np.concatenate([cells, empty])
        discrete = np.asarray(body.stress_operator(points, cells) @ solution.u).reshape(-1, 6)
        shape, _ = body.shape(points, cells)
        recovered = np.einsum("qa,qak->qk", shape, solution.nodal_stress(body.name)[grid.cells[cells]])
        weight = (body.inside_volume / np.maximum(np.bincount(cells, minlength=len(middle)), 1))[cells]
        far = np.linalg.norm(middle - centre, axis=1)[cells] > radius
        density = partial(complementary_energy_density, youngs_modulus=material.youngs_modulus,
                          poissons_ratio=material.poissons_ratio)
        error += float(np.sum((weight * density(recovered - discrete))[far]))
        energy += 0.5 * float(np.sum(weight * density(discrete)))
    return error, energy


def _add_far_field(solution: IBFEMSolution) -> None:
    """In 3D, each contact's normal force estimate plus the far field's share
    (:func:`far_field_energy`, solver.model.accuracy.far_field_force_error): the two-grid
    difference misses the error of a far field too coarse to be in its asymptotic range (on the
    sphere on a flat with cells of 0.25 m beyond 0.07 m of the contact, 0.14 % where N erred by
    1.04 %)."""
    for block in solution.contacts:
        errors, extent = block.get("estimated_error"), _region_extent(block)
        if not errors or errors.get("normal_force") is None or extent is None:
            continue
        # the far field: beyond the zone a rung around the contact refines (REGION_MARGIN times the
        # region's extent); nearer, the pressure's square-root edge and the contact band defeat
        # the recovery, and the two-grid difference carries the error
        error, energy = far_field_energy(solution, block["point"], REGION_MARGIN * extent)
        share = far_field_force_error(error, energy)
        if math.isfinite(share):
            errors["normal_force"] += share
            block["far_field_force_error"] = share


def _solve_quietly(problem: Problem, progress: Callable[..., None] | None = None) -> tuple[IBFEMSolution | None, str | None]:
    """(solution, None), or (None or the solution, why it cannot serve as an estimate's partner)."""
    try:
        solution = solve(problem, progress=progress)
    except (ValueError, MemoryError) as err:
        return None, f"the solve on the grid with element sizes {_sizes(problem)} failed: {err}"
    if not solution.converged:
        return solution, f"the solve on the grid with element sizes {_sizes(problem)} did not converge"
    return solution, None


def _sizes(problem: Problem) -> str:
    return ", ".join(f"{b.name} {b.element_size:.4g} m" for b in problem.bodies)


def estimate_errors(problem: Problem, solution: IBFEMSolution, factor: float = 2.0,
                    progress: Callable[..., None] | None = None) -> None:
    """Adds to each contact block of ``solution`` its ``max_pressure``, ``max_von_mises`` and
    ``estimated_error`` (relative, per quantity: solver.model.accuracy) from a second solve of
    ``problem`` on a grid ``factor`` times coarser, and in 2D a third on a grid ``factor`` times
    coarser again for the sizes (:func:`_coarsest`); ``estimate_s`` to the timings. A coarse
    problem that cannot be solved or does not converge leaves ``estimated_error`` null and
    says why in ``estimate_note``. ``progress``: told the second solve's stages, as :func:`solve`."""
    t = time.perf_counter()
    coarse, note = _solve_quietly(coarser(problem, factor), progress)
    _add_estimates(solution, coarse, problem.dim, note, coarsest=_coarsest(problem, factor, note))
    solution.timings["estimate_s"] = time.perf_counter() - t


def _coarsest(problem: Problem, factor: float, note: str | None) -> IBFEMSolution | None:
    """In 2D, the solution on the grid ``factor``^2 times coarser than ``problem``'s (a sixteenth of
    its dofs), where the coarse solve succeeded and this one converges; else None, and the sizes
    keep the two-grid estimate (3D: an eighth of an eighth would leave the region a few cells
    across). A grid that coarse may not carry the problem at all (a singular system): that too
    only drops the third grid."""
    if problem.dim != 2 or note is not None:
        return None
    try:
        solution, why = _solve_quietly(coarser(problem, factor * factor))
    except (RuntimeError, np.linalg.LinAlgError):
        return None
    return solution if why is None else None


#: a rung refined around the contacts makes its new zone this many times the region's largest
#: extent (half width, semi-axis, or the farthest point of a star region's boundary) in radius,
#: plus REGION_MARGIN_CELLS of the new finest cell: the region's edge and the subsurface stress
#: peak (about 0.5 a deep) both lie well inside it
REGION_MARGIN = 1.5
REGION_MARGIN_CELLS = 4.0
#: quantities whose error the far field carries: a rung refined only around the contacts does not
#: shrink it, so its estimate is carried over from the rung before
_FAR_FIELD = ("normal_force",)


def _region_extent(block: dict) -> float | None:
    """The largest distance from a contact block's point to its region's edge, or None."""
    point = block.get("point")
    if point is None:
        return None
    sizes = []
    for key in ("half_width", "semi_axes"):
        value = block.get(key)
        sizes += [float(v) for v in (value if isinstance(value, (list, tuple)) else [value]) if v is not None]
    region = block.get("region")
    if isinstance(region, (list, tuple)) and len(region) == 2 and not isinstance(region[0], (list, tuple)):
        sizes += [abs(float(r)) for r in region]
    boundary = (block.get("boundary") or {}).get("points") if isinstance(block.get("boundary"), dict) else None
    if boundary:
        sizes.append(float(np.linalg.norm(np.asarray(boundary, float) - np.asarray(point, float), axis=1).max()))
    sizes = [s for s in sizes if math.isfinite(s) and s > 0.0]
    return max(sizes) if sizes else None


def refined_around_contacts(problem: Problem, solution: IBFEMSolution) -> Problem | None:
    """``problem`` with one more level of refinement around each contact region ``solution``
    found: for each body in contact a zone one level deeper than its deepest zone, centred on the
    contact point, of radius REGION_MARGIN times the region's extent plus REGION_MARGIN_CELLS new
    finest cells. The rest of the grid is kept. None when a contact has no region to refine
    around (then the ladder refines every cell instead). The zone is a contact zone, as the
    scene's ``around = "contact"`` ones: the passes that find a region on a grid a few levels
    shallower (solver.contact.sizing, .follow, .grow) take it shallower too. As a zone of its own
    (it was) the sphere on a flat's third rung on the 0.2 % ladder solved its region-sizing pass
    with the new level kept, as fine as the rung: 247 of the rung's 509 s."""
    zones: dict[str, list] = {}
    for contact, block in zip(problem.contacts, solution.contacts):
        extent = _region_extent(block)
        if extent is None:
            return None
        for name in contact.bodies:
            body = problem.body(name)
            levels = max([int(r.levels) for r in body.refinements], default=0) + 1
            if levels > MAX_REFINEMENT_LEVELS:
                return None
            radius = REGION_MARGIN * extent + REGION_MARGIN_CELLS * body.element_size / 2.0 ** levels
            zones.setdefault(name, []).append(Refinement(levels=levels, radius=radius, around_contact=True,
                                                         center=np.asarray(block["point"], dtype=float)))
    return _with_zones(problem, zones)


def graded_around_contacts(problem: Problem, solution: IBFEMSolution) -> Problem | None:
    """``problem`` with its far field graded about each contact region ``solution`` found: for
    each body in contact, beyond its deepest zone (radius r0, at least REGION_MARGIN times the
    region's extent), zones one level coarser at every doubling of the radius, 2 r0, 4 r0, ...,
    until one covers the body's bounding box, so that the cells grow in proportion to the distance
    from the contact (the displacement of a concentrated load falls like 1 / r). None when a
    contact has no region or the grading adds nothing (the grid is graded already)."""
    zones: dict[str, list] = {}
    for contact, block in zip(problem.contacts, solution.contacts):
        extent = _region_extent(block)
        if extent is None:
            return None
        centre = np.asarray(block["point"], dtype=float)
        for name in contact.bodies:
            body = problem.body(name)
            lo, hi = (np.asarray(v, dtype=float) for v in body.profile.bounds)
            reach = float(np.linalg.norm(np.maximum(np.abs(lo - centre), np.abs(hi - centre))))
            levels = max([int(r.levels) for r in body.refinements], default=0)
            deepest = [r.radius for r in body.refinements if int(r.levels) == levels]
            radius = max(deepest + [REGION_MARGIN * extent])
            while levels > 1 and radius < reach:
                levels, radius = levels - 1, 2.0 * radius
                if not any(int(r.levels) >= levels and r.radius >= radius for r in body.refinements):
                    zones.setdefault(name, []).append(Refinement(levels=levels, radius=radius, center=centre))
    return _with_zones(problem, zones) if zones else None


def _with_zones(problem: Problem, zones: dict[str, list]) -> Problem:
    """``problem`` with the refinement zones ``zones`` (by body name) added to its bodies'."""
    bodies = tuple(dataclasses.replace(b, refinements=b.refinements + tuple(zones[b.name])) if b.name in zones else b
                   for b in problem.bodies)
    return dataclasses.replace(problem, bodies=bodies)


def rung_ratio(solution: IBFEMSolution, target: float, observed: list[dict] | None = None) -> float:
    """How many times smaller a rung's cells must be than ``solution``'s for every contact's
    estimated errors to fall below ``target`` with a margin (solver.model.accuracy.
    refinement_ratio), each quantity at the order its estimate took, the sizes at their order
    ``observed`` on three grids where given (:func:`_add_estimates`); the largest over the
    contacts; 2 (one level) where no contact has an estimate."""
    observed = observed or [{}] * len(solution.contacts)
    ratios = [refinement_ratio(block["estimated_error"], {**orders_for(block), **seen}, target)
              for block, seen in zip(solution.contacts, observed) if block.get("estimated_error")]
    return max(ratios, default=2.0)


def _cheaper(first: Problem, second: Problem) -> bool:
    """Whether ``first`` is estimated to need no more memory than ``second`` (solver.model.
    estimate: in 2D the dofs, in 3D also the condensed contact block and the factorisation's work
    space about the finest zone, which set a 3D contact solve's time as well as its memory). The
    work space of graded bodies' balanced cuts is left out: on the sphere on a flat's 0.2 % ladder
    it rates the contact zone one level deeper (285k dofs) 20 % cheaper than every cell 1.7 times
    smaller (447k dofs), while the runs took 110 and 95 s of CPU and peaked at 3.10 and 3.03 GB."""
    return (estimate_size(first, balanced_cuts=False).memory
            <= estimate_size(second, balanced_cuts=False).memory)


def _next_rung(problem: Problem, solution: IBFEMSolution, worst: str | None,
               target: float | None = None, observed: list[dict] | None = None) -> tuple[Problem, str, float]:
    """The next rung of the accuracy ladder, how it was refined and by what ratio (how many times
    smaller its refined cells are). When the largest estimated error is the normal force, whose
    error the far field carries too, the far field graded about the contacts
    (:func:`graded_around_contacts`) if it is not yet. Otherwise every cell made smaller by the
    ratio the estimates ask for (:func:`rung_ratio` against ``target``; 2 without one), or, when
    the largest error is a quantity the region's cells govern (its sizes, the peak pressure, the
    subsurface stress), the contact zone one level deeper around the contacts
    (:func:`refined_around_contacts`) where that is estimated to cost no more (in 2D the added
    zone is a small part of the grid; in 3D halving the contact's cells quadruples the dense
    condensed block, and a smaller ratio everywhere can be cheaper)."""
    if worst in _FAR_FIELD:
        graded = graded_around_contacts(problem, solution)
        if graded is not None:
            return graded, "far field", 2.0
        local = None
    else:
        local = refined_around_contacts(problem, solution)
    ratio = 2.0 if target is None else rung_ratio(solution, target, observed)
    everywhere = coarser(problem, 1.0 / ratio)
    if local is not None and (ratio >= 2.0 or _cheaper(local, everywhere)):
        return local, "contact", 2.0
    return everywhere, "everywhere", ratio


#: under an accuracy target the stick zone's iteration stops within this share of the target in c/a
#: (the default, 1e-3 of c/a, left the stick half width of a partial-slip cylinder 0.25 % from
#: Cattaneo-Mindlin's where its width was 0.15 % off, on a ladder asked for 0.2 %)
STICK_TOLERANCE_SHARE = 0.1


def _tightened(problem: Problem, target: float) -> Problem:
    """``problem`` with each contact's stick-zone tolerance at most STICK_TOLERANCE_SHARE of
    ``target``: an iteration error below the discretisation error the target asks for."""
    contacts = tuple(dataclasses.replace(c, options=dataclasses.replace(
        c.options, stick_tolerance=min(c.options.stick_tolerance, STICK_TOLERANCE_SHARE * target)))
        for c in problem.contacts)
    return dataclasses.replace(problem, contacts=contacts)


def _carry_far_field(solution: IBFEMSolution, previous: IBFEMSolution, far: bool = True) -> None:
    """After a rung refined around the contacts only: each far-field quantity's estimate is at
    least the previous rung's (the cells it depends on were not refined), except where the rung's
    own estimate already holds the far field's share (3D: :func:`_add_far_field`; carried, rung
    2's estimate of N on the sphere on a flat, 0.42 % of which 0.27 % was the difference of two
    rungs whose far fields differed, kept a rung at 0.175 % from the converged N above a target
    of 0.2 % and asked for a fourth rung); with ``far`` false,
    after a rung that graded only the far field, each of the other quantities' (sizes, peak
    pressure, subsurface stress: the contact's cells were kept, and the two rungs' difference
    would not see their error)."""
    for block, before in zip(solution.contacts, previous.contacts):
        now, then = block.get("estimated_error"), before.get("estimated_error")
        if not now or not then:
            continue
        if far and math.isfinite(block.get("far_field_force_error", math.nan)):
            continue  # the rung's own estimate holds its far field's share (_add_far_field)
        for key in _FAR_FIELD if far else [k for k in then if k not in _FAR_FIELD]:
            if isinstance(then.get(key), list) and isinstance(now.get(key), list):
                now[key] = [b if a is None else a if b is None else max(a, b) for a, b in zip(now[key], then[key])]
                continue
            if then.get(key) is not None and (now.get(key) is None or now[key] < then[key]):
                now[key] = then[key]


def _rung(problem: Problem, solution: IBFEMSolution, seconds: float, refined: str = "scene",
          ratio: float | None = None) -> dict:
    errors = [largest_error(c.get("estimated_error") or {}) for c in solution.contacts]
    worst = max(errors, key=lambda e: e[1], default=(None, math.nan))
    return {"element_sizes": {b.name: b.element_size for b in problem.bodies},
            "dofs": int(sum(v.get("dofs", 0) for v in solution.body_info.values())),
            "largest_error": worst[1] if worst[0] is not None else None, "quantity": worst[0],
            "converged": bool(solution.converged), "wall_s": seconds, "refined": refined, "ratio": ratio}


def solve_to_accuracy(problem: Problem, progress: Callable[..., None] | None = None,
                      max_rungs: int = 6) -> tuple[IBFEMSolution, dict]:
    """Solve ``problem`` on its own grid and on one twice as coarse, then refine until the
    estimated relative error of every contact quantity is below ``problem.options.accuracy``
    (:func:`_next_rung`): while the largest error is the normal force, the far field graded about
    the contacts (:func:`graded_around_contacts`) once; otherwise every cell made smaller by the
    ratio r the estimates ask for (each estimate scaled by r^-p to a share of the target:
    :func:`rung_ratio`; element sizes divided by r, zones kept), or the contact zone one level
    deeper within 1.5 times each region's extent (:func:`refined_around_contacts`) where the
    largest error is a contact quantity and that is estimated to cost no more. Each new rung's
    estimate takes the previous rung as its coarse partner, with the rung's ratio in
    Richardson's formula, so every rung is solved once; a 2D rung refined around the contacts
    keeps the previous rung's estimate of the normal force where that is larger (its far field
    was not refined). Each contact's stick-zone tolerance is tightened to a tenth of the target.
    Stops, saying why, when a rung does not converge, when the next rung would not fit in memory
    (solver.model.estimate) or after ``max_rungs`` rungs. Returns the last solution (with its
    estimates) and the record of the ladder ({target, reached, rungs, note})."""
    target = float(problem.options.accuracy)
    problem = _tightened(problem, target)
    report = progress or (lambda *a, **k: None)
    t = time.perf_counter()
    coarse, note = _solve_quietly(coarser(problem))
    fine, fine_note = _solve_quietly(problem)
    if fine is None:
        raise ValueError(fine_note)
    observed = _add_estimates(fine, coarse, problem.dim, note, coarsest=_coarsest(problem, 2.0, note))
    partner, ratio = (coarse if note is None else None), 2.0
    rungs = [_rung(problem, fine, time.perf_counter() - t)]
    note = fine_note
    while note is None and not (rungs[-1]["largest_error"] is not None and rungs[-1]["largest_error"] <= target):
        if len(rungs) >= max_rungs:
            note = f"stopped after {max_rungs} rungs"
            break
        finer, refined, step = _next_rung(problem, fine, rungs[-1]["quantity"], target, observed)
        size = estimate_size(finer)
        if size.memory > 0.5 * available_memory():
            note = f"the next grid ({size}) would not fit in half the machine's memory"
            break
        report(f"accuracy rung {len(rungs) + 1}", min(0.9, 0.1 * len(rungs)))
        t = time.perf_counter()
        solution, note = _solve_quietly(finer)
        if solution is None:
            break
        seen = _add_estimates(solution, fine, problem.dim, note, coarsest=partner, ratios=(step, ratio))
        # a rung that graded only the far field kept the contact's cells: its sizes' orders are the last rung's
        observed = observed if refined == "far field" else seen
        if refined in ("contact", "far field"):
            _carry_far_field(solution, fine, far=refined == "contact")
        problem, fine, partner, ratio = finer, solution, fine, step
        # a graded far field has no one ratio (its estimate keeps Richardson's 2, as before)
        rungs.append(_rung(problem, fine, time.perf_counter() - t, refined, None if refined == "far field" else step))
    reached = rungs[-1]["largest_error"] is not None and rungs[-1]["largest_error"] <= target
    return fine, {"target": target, "reached": bool(reached), "rungs": rungs, "note": note}
