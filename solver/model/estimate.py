"""Size of a problem before anything is built: cells, dofs and memory from the bodies' boxes,
element sizes and refinement zones, so ``--check`` can refuse a grid that cannot fit in the
machine and say how much it would need.

Cells in 2D: the box's area over h0^2 filled by the body's share of it, plus per zone and level
the disc of the level's reach over that level's cell size (the grids refine every cell of level
l closer than R_l = radius + 2 sum of the finer sizes to the centre: solver.fem.grid.
refinement_radii). Cells in 3D: the octree keeps only cells whose centre lies within their half
diagonal of the part, whatever its orientation, so the estimate asks the part's signed distance
the same question: at every level-0 centre of the box (or a sample of them), then per zone and
level at SAMPLES points of the ball in which cells are split (the kept children less the split
parents); in 2D the same sampling, with a disc, counts the part of each zone the body holds
(the box-and-disc count stands in where a body has no signed distance or is too large to
sample). Overlapping zones are counted once (each sample weighted by one over the zones that
hold it). Dofs: DOFS_PER_CELL per cell. Memory: in 2D the process's resident memory when the
estimate is made (the scene loaded, a CAD kernel included) plus SOLVER_BYTES_2D plus
BYTES_PER_DOF[2] per dof, fitted on the peaks of the shipped 2D examples; in 3D what the loaded
scene holds beyond an analytic one (a CAD kernel), measured bytes per dof for the sparse part,
and for a 3D contact the dense arrays of its condensed dofs (the cell faces of the part of the
candidate disc that the bodies hold, each part at the cell size its refinement zones give it,
times CONTACT_DOFS_PER_FACET per body; each body's block held twice and formed once more), then
the larger of the factorisation's work space and the region trials' contact blocks (per point of
the region: the area a coarse pass found, else a share of the candidate disc). A 3D frictional
contact under load paths keeps a friction history on its region's quadrature points: the regions
it holds through a load step are counted per point of a region as large as the candidate disc
(:func:`history_bytes`)."""

from __future__ import annotations

import math
import os

import numpy as np

__all__ = ["ProblemSize", "estimate_size", "REGION_FILL", "POINT_REGION_FILL", "history_bytes", "estimate_contact_dofs", "contact_dofs_per_body", "available_memory",
           "resident_memory", "loaded_scene_bytes", "factor_threads", "trial_bytes"]

#: bytes per dof measured: 2D (fitted, with SOLVER_BYTES_2D, on the peaks of the shipped 2D
#: examples, 1e4-1.8e5 dofs), 3D without contact (AMG-CG solves, rounded up)
BYTES_PER_DOF = {2: 3_200, 3: 6_000}
#: 2D: what a run adds to the process that loaded its scene besides the per-dof part (the
#: solver's imports and fixed arrays)
SOLVER_BYTES_2D = 25e6
#: the resident memory of a process that has loaded a scene, where it cannot be read
RESIDENT_BYTES = 80e6
#: numba and the geometry's compiled kernels, once loaded (measured: a process that loaded the
#: Onshape ball of examples/solid, which compiles them and has no CAD kernel, 0.13 GB above RESIDENT_BYTES)
JIT_BYTES = 130e6
#: 3D contact, the sparse part: the direct factor of K0 with the contact dofs last and K0 itself
#: (measured on the full crossed cylinders, 236k dofs: the bodies' factors 14 KB per dof without
#: their dense roots); the dense arrays are counted from the contact dofs
BYTES_PER_DOF_3D_CONTACT = 14_000
#: a body's sparse factor of this many bytes or more is written to disk while it is computed
#: (solver.fem.multifrontal.ON_DISK_BYTES): it is never whole in memory
ON_DISK_BYTES = 2**30
#: 3D contact, a body whose factor goes to disk: K0 and the factorisation's sparse arrays per dof,
#: plus one chunk of the factor (DISK_CHUNK_BYTES, solver.fem.multifrontal) in memory at a time
#: (calibrated on the full crossed cylinders, 236k dofs: 3.40 GB measured)
STREAMED_BYTES_PER_DOF = 2_000
#: a body's factor below its root (the contact dofs' block), in entries: FACTOR_FILL n^(4/3) for
#: the nested dissection of an octree of n dofs, plus ROOT_REACH_FILL m_b^2 for the rows into the
#: body's m_b contact dofs that the fronts beside the contact hold. It decides, as the solver does
#: with the real factor, whether a body's factor goes to disk (ON_DISK_BYTES). Fitted on symbolic
#: phases (benchmarks/factor_profile_3d.py): the graded quarter sphere on a flat at 264k and 695k
#: dofs 20.1-20.5 n^(4/3) (their m_b^2 terms are small), the million-dof plate 21.1, the full
#: crossed cylinders 20 n^(4/3) + 0.87-0.92 m_b^2 (m_b about 9,000)
FACTOR_FILL = 20.0
ROOT_REACH_FILL = 0.9
DISK_CHUNK_BYTES = 2**28
#: 3D contact, what does not grow with the grid: the interpreter, numpy, scipy, numba's compiled
#: kernels (an idle process with them loaded holds 137 MB; set against the peaks of the 12 shipped
#: 3D contact scenes of benchmarks/check_estimate_3d.py, 0.34-2.2 GB, which the estimate then reads
#: within -22 to +20 %: 300 MB read the smallest runs' peaks 16-33 % high)
BASE_BYTES_3D_CONTACT = 250e6
#: free dofs per cell (3D: hanging and aggregated nodes carry none; measured 2.4-2.8 on octrees)
DOFS_PER_CELL = {3: 2.7}
#: a 3D contact's condensed dofs per body and finest cell face in its candidate disc widened by
#: CONTACT_DISC_MARGIN finest cells (fitted on the full ball on a block at 2 and 4 levels, 816 and
#: 9045 dofs per body; within 5 % at 4 and 5 levels of the quarter sphere on a flat)
CONTACT_DOFS_PER_FACET = 7.1
CONTACT_DISC_MARGIN = 1.4
#: a 3D contact's factorisation work space (its update-matrix stack and largest front) is set by the
#: separators of the finely refined region about the contact, whatever disc the solve condenses
#: on: WORK_SPACE_FACTOR m_z^2 entries per body, m_z the contact dofs of a section through the
#: refinement (a disc of ZONE_SECTION_FRACTION of its radius), or 3 m_b^2 where the condensed
#: block is the larger (fitted on the peaks of the three full models' runs, 2.5-3.0 GiB, with the
#: candidate disc sized by a coarse pass to 0.4-0.6 of the section's dofs; the factorisation's
#: profile of the crossed cylinders gives 1.3 GB of stack and largest front per body on that disc,
#: 1.6 GB on the section's)
WORK_SPACE_FACTOR = 2.5
ZONE_SECTION_FRACTION = 0.8
#: a large body's own separators: nested dissection first cuts the body's background grid across
#: its longest side, a plane of 3 (n_1 + 1)(n_2 + 1) dofs (n_1, n_2 the cells along the two shorter
#: sides, times the share of the box's section the body fills), and the factorisation's update-
#: matrix stack and largest front then hold about FAR_WORK_FACTOR times its square in entries
#: (fitted on the symbolic factorisations of a plate of 2.7 x 2.7 x 0.5 m at 25 mm cells, 852k dofs:
#: 3.96 GB of stack and front against 6,900 separator dofs; the same rule reads 4.8 GB for a plate
#: 3 x 3 x 0.5 m, measured 5.0 GB, and 8.3 GB for a block 2 x 2 x 1 m, measured 7.2 GB; at 50 mm
#: cells 0.27 GB against 0.35 GB measured)
FAR_WORK_FACTOR = 10.4
#: a body graded about its contact through its whole depth (zones nested out to the far field):
#: its cells gather at the contact, so nested dissection's balanced cuts cross the zones at their
#: fine cell sizes, and the factorisation's update-matrix stack and largest front hold about
#: CONTACT_PLANE_WORK_FACTOR times the square of the dofs of the axis plane that halves the body's
#: cells (3 per cell crossing it; the smallest of the three planes; the larger body's counts).
#: Fitted on the symbolic factorisations of the graded quarter sphere on a flat
#: (benchmarks/accuracy_ladder.py, zones of 6 to 2 levels within 0.07-1.2 m): the block's stack and
#: front are 2.7 and 1.9 times its plane's square at 264k and 695k dofs, the ball's 5.3 and 4.8
#: times its smaller plane's; the million-dof plate's 5.3 (there the background rule, larger, holds)
CONTACT_PLANE_WORK_FACTOR = 2.5
#: a 3D contact's region quadrature points per finest cell face of body 1's surface (the region's
#: panels split at both grids' cell lines, REGION_ORDER^2 points each: measured 193-201 on the half
#: sphere on a flat at 5 levels, 10 456-10 870 points over regions of 52-56 finest faces)
REGION_POINTS_PER_FACET = 200.0
#: a friction history under load paths (solver.contact.friction_history3d) holds up to this many
#: regions through a load step (its KEEP_REGIONS), where the proportional solve holds the
#: operators of the driver's last KEPT_TRIALS trials
HISTORY_REGIONS = 3
KEPT_TRIALS = 2
#: bytes per region point: the jump and flux operators and the points (2.24 KB, over 1308 condensed
#: dofs, measured with the objects' sizes on the half sphere on a flat at 5 levels) and the
#: same-zone mean's bins (solver.contact.disc_means.DiscBins: the point's plane coordinates, weight
#: and bin, 40 bytes whatever the points per disc)
REGION_OPERATOR_BYTES_PER_POINT = 2_300
REGION_NEIGHBOUR_BYTES_PER_POINT = 40
#: a 3D contact's region trials, per quadrature point of the region (REGION_POINTS_PER_FACET per
#: finest cell face of it): the contact blocks of the trials the driver keeps (KEPT_TRIALS), the
#: arrays that build them and the factored small system, which live after the factorisation's
#: work space is freed (measured with tracemalloc on the roller on a flat: 0.66 GB over a
#: region of 48,700 points, 13.5 KB per point; rounded up to the process's resident growth, which
#: the allocator's pages add to: the roller's peak 1.72 GB against 1.58 GB estimated)
TRIAL_BYTES_PER_POINT = 16_000
#: the fraction of its candidate disc's faces a contact's region is taken to cover where no coarse
#: pass has measured it (the disc bounds the region's growth; a region half the disc's radius): a
#: line contact's or a flat punch's, which grow along the disc
REGION_FILL = 0.25
#: the same for a point contact (an ellipse): a region a quarter of the disc's radius (the shipped
#: point contacts' regions fill 0.04-0.06 of their discs: a / h of 3 in a quarter disc of 130-200
#: finest faces)
POINT_REGION_FILL = 1.0 / 16.0
#: points of the signed distance per level and body when counting a 3D body's kept cells
SAMPLES = 2000
#: bodies estimated above this many cells are not sampled (the box's fill by volume is used)
SAMPLED_CELLS = 5e6
#: the grading reach of a refinement level in cells (solver.fem.grid.GRADING_CELLS)
GRADING_CELLS = 2


class ProblemSize:
    def __init__(self, cells: float, dofs: float, memory: float):
        # nan (inf x 0 of absurd sizes) counts as beyond every machine
        self.cells, self.dofs, self.memory = (v if v == v else math.inf for v in (cells, dofs, memory))

    def __str__(self) -> str:
        return f"about {self.cells:.3g} cells, {self.dofs:.3g} dofs, {self.memory / 2**30:.2g} GB"


def _zone_cells(radius: float, levels: int, h0: float, dim: int, centre, lo, hi) -> float:
    """New cells of a refinement zone, level by level, its disc (ball) clipped to the body's box
    axis by axis."""
    h = h0 / 2.0 ** np.arange(levels + 1)
    total = 0.0
    centre = np.zeros(dim) if centre is None else np.asarray(centre, dtype=float)
    for lv in range(levels):
        reach = _reach(radius, h, lv)
        measure = math.pi * reach**2 if dim == 2 else 4.0 / 3.0 * math.pi * reach**3
        overlap = np.clip(np.minimum(centre + reach, hi) - np.maximum(centre - reach, lo), 0.0, None) / (2 * reach)
        total += float(np.prod(overlap)) * measure / h[lv + 1] ** dim * (1.0 - 0.5**dim) if measure else 0.0
    return total


def _reach(radius: float, h: np.ndarray, lv: int) -> float:
    """Distance from a zone's centre within which cells of level lv are split (their centres)."""
    return radius + GRADING_CELLS * h[lv + 1:-1].sum() + h[lv]


def _kept(phi, points: np.ndarray, size: float) -> np.ndarray:
    """The grids' rule: a cell is kept unless its centre lies farther outside the body than its
    half diagonal."""
    return np.asarray(phi(points), dtype=float) > -0.5 * math.sqrt(points.shape[1]) * size


def _sampled_body_cells(body, centres: list, lo: np.ndarray, hi: np.ndarray, rng) -> tuple[np.ndarray, np.ndarray]:
    """Cells of a body's quadtree (2D) or octree (3D) from its signed distance, as sampled cell
    centres and the cells each stands for (their sum the body's cells): the kept cells of level 0
    (every centre tested, or SAMPLES of them), then per refinement zone and level the kept
    children less their kept parents, from SAMPLES points uniform in each zone's disc (ball) of
    that level, each weighted by one over the zones whose discs hold it (overlapping zones split a
    cell once): only the part of the zones the body holds is counted."""
    phi = body.profile.signed_distance
    dim = len(lo)
    h0 = float(body.element_size)
    shape = np.floor((hi - lo) / h0).astype(np.int64) + 1
    total = float(np.prod(shape))
    if total <= SAMPLES:
        axes = [lo[k] + h0 * (np.arange(shape[k]) + 0.5) for k in range(dim)]
        pts = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
        weights = [_kept(phi, pts, h0).astype(float)]
    else:
        pts = lo + rng.random((SAMPLES, dim)) * shape * h0
        weights = [_kept(phi, pts, h0) * (total / SAMPLES)]
    points = [pts]
    corners = np.stack(np.meshgrid(*[(-1.0, 1.0)] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    unit_ball = math.pi if dim == 2 else 4.0 / 3.0 * math.pi
    zones = list(zip(body.refinements, (np.asarray(c, dtype=float) for c in centres)))
    for lv in range(max([int(z.levels) for z, _ in zones], default=0)):
        h = h0 / 2.0**lv
        balls = _level_balls(zones, h0, lv, dim)
        for centre, _, reach in balls:
            pts = _in_ball(rng, centre, reach, dim)
            split, covering = _split_and_covering(balls, pts, h)
            split &= np.all((pts >= lo) & (pts <= hi + h0), axis=1) & _kept(phi, pts, h)
            # two of each split cell's 2^dim children, at random corners
            corner = corners[rng.integers(0, len(corners), (int(split.sum()), 2))]
            children = (pts[split][:, None, :] + 0.25 * h * corner).reshape(-1, dim)
            kept = _kept(phi, children, 0.5 * h).reshape(-1, 2).sum(axis=1)
            points.append(pts[split])
            weights.append((len(corners) / 2.0 * kept - 1.0) / covering[split] * (unit_ball * reach**dim / h**dim / SAMPLES))
    return np.vstack(points), np.concatenate(weights)


def _level_balls(zones, h0: float, lv: int, dim: int) -> list:
    """The zones splitting the cells of level ``lv``: per zone (centre, split radius of the cells'
    boxes, reach of their centres), the grids' grading included (solver.fem.grid)."""
    h = h0 / 2.0**lv
    balls = []
    for zone, centre in zones:
        if int(zone.levels) > lv:
            sizes = h0 / 2.0 ** np.arange(int(zone.levels) + 1)
            split_radius = float(zone.radius) + GRADING_CELLS * sizes[lv + 1:-1].sum()
            balls.append((centre, split_radius, split_radius + 0.5 * math.sqrt(dim) * h))
    return balls


def _split_and_covering(balls, pts: np.ndarray, h: float):
    """Which of ``pts`` (centres of level cells of size h) the zones split, and how many zones'
    reaches hold each (overlapping zones split a cell once)."""
    split, covering = np.zeros(len(pts), dtype=bool), np.zeros(len(pts))
    for other, radius, other_reach in balls:
        gap = np.maximum(np.abs(pts - other) - 0.5 * h, 0.0)
        split |= np.sqrt((gap * gap).sum(axis=1)) < radius
        covering += np.linalg.norm(pts - other, axis=1) <= other_reach
    return split, covering


def _median_plane_dofs(body, centres, points: np.ndarray, weights: np.ndarray, rng) -> float:
    """3 x the cells of a 3D body's octree crossing the axis plane that halves its cells (the
    weighted median of its sampled cell centres along the axis), the smallest of the three: the
    balanced cut nested dissection makes first. On a body graded about a contact the cells
    gather at the contact, and so do these planes."""
    lo, hi = (np.asarray(v, dtype=float) for v in body.profile.bounds)
    zones = list(zip(body.refinements, (np.asarray(c, dtype=float) for c in centres)))
    counts = []
    for axis in range(3):
        order = np.argsort(points[:, axis])
        cumulative = np.cumsum(np.maximum(weights[order], 0.0))
        median = float(points[order[min(np.searchsorted(cumulative, 0.5 * cumulative[-1]), len(order) - 1)], axis])
        counts.append(_plane_cells(body.profile.signed_distance, zones, float(body.element_size), lo, hi, axis,
                                   median, rng))
    return 3.0 * min(counts)


def _plane_cells(phi, zones, h0: float, lo: np.ndarray, hi: np.ndarray, axis: int, x0: float, rng) -> float:
    """Cells of a body's octree that the plane x[axis] = x0 crosses: the background layer's kept
    cells (SAMPLES points of the layer's section), then per zone and level the crossing children
    less their split parents, from SAMPLES points of the zone's section (a disc) in the layer of
    that level's cells the plane crosses (a split cell has four children on either side of it)."""
    other = [k for k in range(3) if k != axis]
    shape = np.floor((hi - lo) / h0).astype(np.int64) + 1
    layer = lo[axis] + h0 * (np.clip(np.floor((x0 - lo[axis]) / h0), 0, shape[axis] - 1) + 0.5)
    pts = np.empty((SAMPLES, 3))
    pts[:, axis] = layer
    pts[:, other] = lo[other] + rng.random((SAMPLES, 2)) * shape[other] * h0
    cells = float(np.prod(shape[other])) * float(_kept(phi, pts, h0).mean())
    for lv in range(max([int(z.levels) for z, _ in zones], default=0)):
        h = h0 / 2.0**lv
        balls = _level_balls(zones, h0, lv, 3)
        for centre, _, reach in balls:
            if abs(x0 - centre[axis]) >= reach:
                continue
            disc = math.sqrt(reach**2 - (x0 - centre[axis]) ** 2)
            angle, r = 2.0 * math.pi * rng.random(SAMPLES), disc * np.sqrt(rng.random(SAMPLES))
            pts = np.empty((SAMPLES, 3))
            pts[:, axis] = lo[axis] + h * (math.floor((x0 - lo[axis]) / h) + 0.5)  # the layer of level lv's cells
            pts[:, other[0]], pts[:, other[1]] = centre[other[0]] + r * np.cos(angle), centre[other[1]] + r * np.sin(angle)
            split, covering = _split_and_covering(balls, pts, h)
            split &= np.all((pts >= lo) & (pts <= hi + h0), axis=1) & _kept(phi, pts, h)
            corner = np.empty((int(split.sum()), 2, 3))  # two of the four children the plane crosses
            corner[:, :, axis] = np.where(x0 >= pts[split, axis], 1.0, -1.0)[:, None]
            corner[:, :, other] = rng.choice([-1.0, 1.0], size=(len(corner), 2, 2))
            kept = _kept(phi, (pts[split][:, None, :] + 0.25 * h * corner).reshape(-1, 3), 0.5 * h).reshape(-1, 2).sum(axis=1)
            new = float(np.sum((2.0 * kept - 1.0) / np.maximum(covering[split], 1.0)))
            cells += math.pi * disc**2 / h**2 * new / SAMPLES
    return cells


def _in_ball(rng, centre: np.ndarray, radius: float, dim: int) -> np.ndarray:
    """SAMPLES points uniform in the disc (ball) of ``radius`` about ``centre``."""
    direction = rng.standard_normal((SAMPLES, dim))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    return centre + direction * (radius * rng.random(SAMPLES) ** (1.0 / dim))[:, None]


def _zone_centres(problem, body) -> list:
    """Each refinement zone's centre: its own, else the point of a contact of the body (when the
    scene gives one), else the origin."""
    points = [c.point for c in problem.contacts if body.name in c.bodies and c.point is not None]
    default = np.asarray(points[0], dtype=float) if points else np.zeros(problem.dim)
    return [default if z.center is None else np.asarray(z.center, dtype=float) for z in body.refinements]


def estimate_size(problem, loaded: float | None = None, region_areas=None, region_fills=None,
                  balanced_cuts: bool = True) -> ProblemSize:
    """Estimated cells, dofs and peak memory of ``problem`` (a solver.model.Problem); inf for
    sizes beyond floating point (an element size of 1e-300). ``loaded``: in 3D, the bytes the
    loaded scene holds (:func:`loaded_scene_bytes` when the scene was loaded, before a solve
    grew the process); measured now when not given. ``region_areas``: in 3D, per contact the
    area (m^2, of the model) of its region where a coarse pass has found it, else None: the
    region trials' memory is counted from it (:func:`trial_bytes`); ``region_fills``: per
    contact the share of its candidate disc a region not found yet is taken to cover (REGION_FILL
    for every contact when not given; POINT_REGION_FILL suits a point contact).
    ``balanced_cuts``: False leaves out the work space of graded bodies' balanced cuts
    (CONTACT_PLANE_WORK_FACTOR), which sets the peak of graded grids of several hundred thousand
    dofs but not which of two rungs costs less (see solver.solving's rung choice)."""
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        return _estimate(problem, loaded_scene_bytes() if loaded is None else loaded, region_areas, region_fills,
                         balanced_cuts)


def _estimate(problem, loaded: float, region_areas=None, region_fills=None, balanced_cuts: bool = True) -> ProblemSize:
    dim = problem.dim
    cells = 0.0
    per_body = []
    rng = np.random.default_rng(0)
    separators, planes = [], [0.0]
    plane_rng = np.random.default_rng(3)  # its own stream: the cells' samples stay as they were
    for body in problem.bodies:
        lo, hi = (np.asarray(v, dtype=float) for v in body.profile.bounds)
        h0 = float(body.element_size)
        box = float(np.prod(np.maximum(hi - lo, h0)))
        measure = float(getattr(body.profile, "volume" if dim == 3 else "area", box) or box)
        fill = min(1.0, max(measure / box, 0.05)) if math.isfinite(measure) else 1.0
        per_axis = np.maximum(hi - lo, h0) / h0  # cells along each axis (inf for absurd sizes)
        separators.append(_background_separator_dofs(per_axis, fill))
        body_cells = fill * float(np.prod(per_axis)) + float(np.sum(per_axis + 1.0)) ** (dim - 1)  # inside + cut
        centres = _zone_centres(problem, body)
        for zone, centre in zip(body.refinements, centres):
            body_cells += _zone_cells(float(zone.radius), int(zone.levels), h0, dim, centre, lo, hi)
        if body_cells <= SAMPLED_CELLS and hasattr(body.profile, "signed_distance"):
            points, weights = _sampled_body_cells(body, centres, lo, hi, rng)
            body_cells = float(weights.sum())
            if balanced_cuts and dim == 3 and body.refinements and any(body.name in c.bodies for c in problem.contacts):
                planes.append(_median_plane_dofs(body, centres, points, weights, plane_rng))
        cells += body_cells
        per_body.append(body_cells)
    dofs = DOFS_PER_CELL.get(dim, dim) * cells
    if dim == 3 and problem.contacts:
        body_dofs = DOFS_PER_CELL[3] * np.array(per_body)
        on_disk = _factor_below_root_bytes(body_dofs, _contact_dofs_of_bodies(problem)) >= ON_DISK_BYTES
        streamed = bool(np.any(on_disk))
        rest = BASE_BYTES_3D_CONTACT + loaded + history_bytes(problem)
        far_work = 8.0 * max(FAR_WORK_FACTOR * max(separators) ** 2, CONTACT_PLANE_WORK_FACTOR * max(planes) ** 2)
        memory = (_sparse_contact_bytes(body_dofs, on_disk)
                  + _dense_contact_bytes(problem, streamed, region_areas, region_fills, far_work) + rest)
    elif dim == 2:  # the process as it is (a CAD kernel's import included), the solver, the dofs
        memory = resident_memory() + SOLVER_BYTES_2D + dofs * BYTES_PER_DOF[2]
    else:
        memory = dofs * BYTES_PER_DOF[dim] + 200e6 + loaded
    return ProblemSize(cells, dofs, memory)


def loaded_scene_bytes() -> float:
    """3D: what the process holds beyond one that loaded an analytic scene (RESIDENT_BYTES, the
    size the 3D fits were measured from), less the compiled kernels where loading the scene has
    already loaded them (JIT_BYTES: BASE_BYTES_3D_CONTACT counts them): a STEP import's CAD
    kernel (0.22 GB) stays resident for the whole run."""
    import sys

    jit = JIT_BYTES if "numba" in sys.modules else 0.0
    return max(0.0, resident_memory() - RESIDENT_BYTES - jit)


def resident_memory() -> float:
    """Bytes this process holds in memory now (Linux; elsewhere its peak so far, or
    RESIDENT_BYTES where neither can be read)."""
    try:
        with open("/proc/self/statm") as f:
            return float(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError, AttributeError):
        pass
    try:
        import resource
        import sys

        peak = float(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
        return peak if sys.platform == "darwin" else peak * 1024.0  # bytes on macOS, KB elsewhere
    except (ImportError, OSError, ValueError):
        return RESIDENT_BYTES


def _sparse_contact_bytes(body_dofs: np.ndarray, on_disk: np.ndarray) -> float:
    """The sparse part of a 3D contact: BYTES_PER_DOF_3D_CONTACT per dof of every body whose
    factor stays in memory; a body whose factor takes ON_DISK_BYTES or more (``on_disk``) has it
    written to disk while it is computed, so such bodies count only K0 and the factorisation's
    sparse arrays (STREAMED_BYTES_PER_DOF) and one chunk of the factor (the bodies are factored
    one at a time)."""
    if not len(body_dofs):
        return 0.0
    total = BYTES_PER_DOF_3D_CONTACT * float(body_dofs[~on_disk].sum())
    if on_disk.any():
        total += STREAMED_BYTES_PER_DOF * float(body_dofs[on_disk].sum()) + DISK_CHUNK_BYTES
    return total


def _factor_below_root_bytes(body_dofs: np.ndarray, contact_dofs: np.ndarray) -> np.ndarray:
    """Bytes of each body's factor below its root: FACTOR_FILL n^(4/3) + ROOT_REACH_FILL m_b^2
    entries of 8 bytes, n its dofs and m_b its contact dofs."""
    return 8.0 * (FACTOR_FILL * body_dofs ** (4.0 / 3.0) + ROOT_REACH_FILL * contact_dofs**2)


def _contact_dofs_of_bodies(problem) -> np.ndarray:
    """Each body's contact dofs m_b, summed over its contacts (:func:`contact_dofs_per_body`)."""
    per_body = {b.name: 0.0 for b in problem.bodies}
    for c in problem.contacts:
        _, m_b = contact_dofs_per_body(problem, c)
        for name in c.bodies:
            per_body[name] += m_b
    return np.array([per_body[b.name] for b in problem.bodies])


def factor_threads() -> int:
    """Threads a body's condensed factorisation runs its large fronts on: ``IBFEM_THREADS`` if set (>= 1), else
    the machine's cores (the same setting as the geometry's projections)."""
    from ibfem.geometry._jit import threads

    return threads()


def trial_bytes(problem, region_areas=None, region_fills=None) -> list[float]:
    """Per contact of a 3D problem, the memory of its region trials (:func:`_contact_trial_bytes`);
    ``region_areas``: m^2 per contact where a coarse pass has found the region, else None;
    ``region_fills`` as :func:`estimate_size`'s."""
    if problem.dim != 3:
        return [0.0] * len(problem.contacts)
    return [_contact_trial_bytes(problem, c, contact_dofs_per_body(problem, c)[1],
                                 None if region_areas is None else region_areas[k],
                                 REGION_FILL if region_fills is None else region_fills[k])
            for k, c in enumerate(problem.contacts)]


def _contact_trial_bytes(problem, contact, m_b: float, area: float | None, fill: float = REGION_FILL) -> float:
    """TRIAL_BYTES_PER_POINT per point of the contact's region, REGION_POINTS_PER_FACET points per
    finest cell face: a region of ``area`` (m^2), else ``fill`` of the candidate disc's faces
    (its ``m_b`` contact dofs per body over CONTACT_DOFS_PER_FACET)."""
    if area is None:
        faces = fill * m_b / CONTACT_DOFS_PER_FACET
    else:
        faces = float(area) / _finest_cell_size([b for b in problem.bodies if b.name in contact.bodies]) ** 2
    return TRIAL_BYTES_PER_POINT * REGION_POINTS_PER_FACET * faces


def _background_separator_dofs(per_axis: np.ndarray, fill: float) -> float:
    """The dofs of the plane across a body's background grid that nested dissection cuts first:
    3 (n_1 + 1)(n_2 + 1) for the cells n_1, n_2 along the box's two shorter sides (the cut is
    across the longest), times the share of the box's section the body fills (its volume share
    to the power 2/3). 0 in 2D or for absurd sizes."""
    if len(per_axis) != 3 or not np.all(np.isfinite(per_axis)):
        return 0.0
    n_1, n_2 = np.sort(per_axis)[:2]
    return 3.0 * (n_1 + 1.0) * (n_2 + 1.0) * fill ** (2.0 / 3.0)


def _finest_cell_size(bodies) -> float:
    """The smallest cell of the bodies' grids: each body's element size halved per level of its
    deepest refinement zone."""
    return min(float(b.element_size) / 2.0 ** max([int(z.levels) for z in b.refinements], default=0)
               for b in bodies)


def _dense_contact_bytes(problem, streamed: bool = False, region_areas=None, region_fills=None,
                         far_work: float = 0.0) -> float:
    """The dense arrays of a 3D contact: per body, its contact dofs m_b hold m_b^2 entries in
    the root of the factor and a quarter of that in the kept block of the inverse (all of it
    for blocks below 4000 dofs, where it is small), and while the last body is factored about
    three more m_b^2 are work space (the factorisation's update-matrix stack and largest front:
    measured 1.7 and 1.2 m_b^2 on the crossed cylinders), or WORK_SPACE_FACTOR m_z^2 where the
    condensed disc is smaller than a section through the contact refinement (m_z dofs). ``streamed``: the factors go to disk
    as they are computed; the last body's root block is then allocated only once its front
    buffer is freed, so it is not counted beside the work space. The bodies are factored one at
    a time, so one work space is counted. Then the region trials (:func:`_contact_trial_bytes`,
    ``region_areas`` and ``region_fills`` as :func:`trial_bytes`'), which come after the
    factorisation: the larger of the two counts. ``far_work``: the bytes of the work space a
    large body's own separators need (FAR_WORK_FACTOR), where they exceed the contact's."""
    total = 0.0
    for k, c in enumerate(problem.contacts):
        n_bodies, m_b = contact_dofs_per_body(problem, c)
        m_zone = contact_dofs_per_body(problem, c, ZONE_SECTION_FRACTION)[1]
        work = max(3.0 * m_b**2, WORK_SPACE_FACTOR * m_zone**2, far_work / 8.0)
        later = _contact_trial_bytes(problem, c, m_b, None if region_areas is None else region_areas[k],
                                     REGION_FILL if region_fills is None else region_fills[k])
        total += 8.0 * 1.25 * m_b**2 * (n_bodies - 1 if streamed else n_bodies) + max(8.0 * work, later)
    return total


def history_bytes(problem) -> float:
    """What a 3D run with load paths adds for its frictional contacts' history beyond a
    proportional solve: per contact HISTORY_REGIONS regions (operators and the same-zone mean's bins) less
    the operators of the KEPT_TRIALS trials a proportional solve holds too, per point of a region
    filling the candidate disc (REGION_POINTS_PER_FACET per finest face of it: the disc's faces
    are its contact dofs per body over CONTACT_DOFS_PER_FACET). 0 without paths, in 2D, and for
    frictionless or tied contacts (no history kept)."""
    if problem.dim != 3 or getattr(problem, "history", None) is None:
        return 0.0
    per_point = (HISTORY_REGIONS * (REGION_OPERATOR_BYTES_PER_POINT + REGION_NEIGHBOUR_BYTES_PER_POINT)
                 - KEPT_TRIALS * REGION_OPERATOR_BYTES_PER_POINT)
    total = 0.0
    for c in problem.contacts:
        if getattr(c, "type", None) != "frictional":
            continue
        points = REGION_POINTS_PER_FACET * contact_dofs_per_body(problem, c)[1] / CONTACT_DOFS_PER_FACET
        total += per_point * points
    return total


def estimate_contact_dofs(problem) -> float:
    """Estimated condensed (contact) dofs m of a 3D problem, summed over its contacts and bodies
    (0 for a 2D problem, whose contacts are not condensed on a disc)."""
    if problem.dim != 3:
        return 0.0
    total = 0.0
    for c in problem.contacts:
        n_bodies, m_b = contact_dofs_per_body(problem, c)
        total += n_bodies * m_b
    return total


def contact_dofs_per_body(problem, contact, fraction: float | None = None) -> tuple[int, float]:
    """A contact's bodies and the contact dofs of each: CONTACT_DOFS_PER_FACET per cell face of
    the bodies' grids that the candidate disc, widened by CONTACT_DISC_MARGIN finest cells,
    covers, each part of the disc counted at the cell size its refinement zones give it (a line
    contact's band is fine, the rest of its disc coarser). The disc is the part of a circle of
    the candidate extent around the contact point that the bodies hold: a quarter model (two
    symmetry planes through the point) holds a quarter of it, a full model all of it.
    ``fraction``: a disc of this fraction of the contact refinement radius instead of the
    contact's ``extent_fraction``."""
    bodies = [b for b in problem.bodies if b.name in contact.bodies]
    h_fine = _finest_cell_size(bodies)
    extent = problem.candidate_extent(contact, contact.options.extent_fraction if fraction is None else fraction)
    radius = extent + CONTACT_DISC_MARGIN * h_fine
    faces = math.pi * radius**2 * _mean_inverse_square_size(problem, bodies, contact.point, radius)
    return len(bodies), CONTACT_DOFS_PER_FACET * faces * _held_fraction(bodies, contact.point, extent)


def _mean_inverse_square_size(problem, bodies, point, radius: float) -> float:
    """The mean over the candidate disc of radius ``radius`` about ``point`` of 1 / h^2, h the
    finest cell size the bodies' refinement zones give a point of it (a zone's level l reaches
    as far as the grids split cells of level l - 1, its radius widened by their grading; outside
    every zone a body's element size). The disc lies in the plane through
    the point that holds the zones' centres (the contact's tangent plane: zones that follow a
    contact are centred on it), sampled at SAMPLES points; where all zones are centred at the
    point the plane does not matter."""
    centre = np.zeros(3) if point is None else np.asarray(point, dtype=float)
    zones = []  # (centre, reach, cell size) of every level of every body's zones (the grids' grading)
    for body in bodies:
        for zone, at in zip(body.refinements, _zone_centres(problem, body)):
            sizes = float(body.element_size) / 2.0 ** np.arange(int(zone.levels) + 1)
            zones += [(np.asarray(at, dtype=float), _reach(float(zone.radius), sizes, lv), sizes[lv + 1])
                      for lv in range(int(zone.levels))]
    coarsest = min(float(b.element_size) for b in bodies)
    if point is None or len(centre) != 3 or not zones:
        finest = min([z[2] for z in zones], default=coarsest)
        return 1.0 / finest**2
    offsets = np.array([z[0] - centre for z in zones])
    offsets = offsets[np.linalg.norm(offsets, axis=1) > 1e-9 * radius]
    basis = np.linalg.svd(np.vstack([offsets, np.eye(3) * 1e-12 * radius]))[2][:2] if len(offsets) else np.eye(3)[:2]
    rng = np.random.default_rng(2)
    angle = 2.0 * math.pi * rng.random(SAMPLES)
    r = radius * np.sqrt(rng.random(SAMPLES))
    pts = centre + (r * np.cos(angle))[:, None] * basis[0] + (r * np.sin(angle))[:, None] * basis[1]
    size = np.full(SAMPLES, coarsest)
    for at, reach, h in zones:
        inside = np.linalg.norm(pts - at, axis=1) <= reach
        size[inside] = np.minimum(size[inside], h)
    held = _held_points(bodies, pts, np.cross(basis[0], basis[1]), min(z[2] for z in zones))
    return float(np.mean(1.0 / size[held]**2))


def _held_points(bodies, pts: np.ndarray, normal: np.ndarray, depth: float) -> np.ndarray:
    """Which points of a contact's disc lie on the bodies: a body holds a point of its tangent
    plane where the point, moved ``depth`` to either side of the plane, lies inside it. A symmetric
    model holds part of the disc (a quarter model a quarter), and its refinement zones cover only
    that part: the disc's mean cell density is the held part's. All points where a body has no
    signed distance, or where none is held."""
    if not all(hasattr(b.profile, "signed_distance") for b in bodies):
        return np.ones(len(pts), dtype=bool)
    held = np.zeros(len(pts), dtype=bool)
    for b in bodies:
        for side in (-1.0, 1.0):
            held |= np.asarray(b.profile.signed_distance(pts + side * depth * normal), dtype=float) >= 0.0
    return held if held.any() else np.ones(len(pts), dtype=bool)


def _held_fraction(bodies, point, radius: float) -> float:
    """The fraction of the ball of ``radius`` around ``point`` that lies in one of the bodies
    (their signed distances at SAMPLES points uniform in the ball); 1 without a point or a
    signed distance. Near a contact point the two bodies fill the ball but for the thin gap
    between their surfaces, so this is also the fraction of the contact disc they hold."""
    if point is None or not all(hasattr(b.profile, "signed_distance") for b in bodies):
        return 1.0
    rng = np.random.default_rng(1)
    direction = rng.standard_normal((SAMPLES, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    pts = np.asarray(point, dtype=float) + direction * (radius * rng.random(SAMPLES) ** (1.0 / 3.0))[:, None]
    held = np.zeros(SAMPLES, dtype=bool)
    for b in bodies:
        held |= np.asarray(b.profile.signed_distance(pts), dtype=float) >= 0.0
    return float(held.mean())


def available_memory() -> float:
    """Physical memory of the machine in bytes (inf when unknown)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return math.inf
