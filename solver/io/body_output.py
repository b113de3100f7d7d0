"""A body's output mesh and its fields: the background cells clipped by the exact surface
(solver.io.clipped_cells), the displacement and the recovered stress at its points, the raw
stress of the background cell each output cell comes from.

Point values are the solution's own at each point: the grid's nodes keep their nodal values
(displacement and recovered stress), the points made by the clipping are evaluated in the body
(``Solution.displacement`` / ``Solution.stress``). Inside a whole cell the output interpolates
exactly as the solution does (trilinear / bilinear), so a probe there reads the same stress from
the file as from ``summary.json``; in a clipped cell the values are exact at the points and
linear between them."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from ibfem.solver.model import problem as pb
from ibfem.solver.model.elasticity import von_mises

from .clipped_cells import VTK_TYPES, clip_cells, unique_rows

__all__ = ["BodyOutput", "body_output", "full_stress", "principal_stresses", "clip_tolerance"]

#: the leaves' linearity tolerance as a fraction of the body's volume over its boundary area (area
#: over perimeter in 2D), per dimension: the chords of a curved surface lose about 0.3 x tolerance
#: x area / volume of a ball's volume, 0.5 x tolerance x perimeter / area of a disc's area; with
#: the area over-estimated by the cut cells' faces the loss stays under 1e-3 (2D cells are cheap)
VOLUME_TOLERANCE = {2: 5e-4, 3: 2.5e-3}
#: deepest split of a cut cell (16 sub-cubes along each side)
MAX_DEPTH = 4
#: leaves on the solid's edges (where the distance is never linear) stop at this fraction of the
#: grid's finest cells
EDGE_RESOLUTION = 0.5


@dataclass
class BodyOutput:
    """Points (n, dim), VTK cells (flat connectivity, end offsets, types), the background cell
    of each output cell, and the fields: ``point_data`` and ``cell_data`` by name."""

    points: np.ndarray
    connectivity: np.ndarray
    offsets: np.ndarray
    types: np.ndarray
    parent: np.ndarray
    point_data: dict
    cell_data: dict

    def cell_measures(self) -> np.ndarray:
        """Volume (area in 2D) of every output cell (boxes axis-aligned, simplices by determinant)."""
        dim = self.points.shape[1]
        starts = np.concatenate([[0], self.offsets[:-1]])
        sizes = self.offsets - starts
        out = np.zeros(len(sizes))
        for n in np.unique(sizes):
            rows = np.nonzero(sizes == n)[0]
            v = self.points[self.connectivity[starts[rows, None] + np.arange(n)]]
            if n == dim + 1:
                out[rows] = np.abs(np.linalg.det(v[:, 1:] - v[:, :1])) / (2.0 if dim == 2 else 6.0)
            else:
                out[rows] = np.prod(v.max(axis=1) - v.min(axis=1), axis=1)
        return out

    def cell_centroids(self) -> np.ndarray:
        starts = np.concatenate([[0], self.offsets[:-1]])
        sizes = self.offsets - starts
        out = np.zeros((len(sizes), self.points.shape[1]))
        for n in np.unique(sizes):
            rows = np.nonzero(sizes == n)[0]
            out[rows] = self.points[self.connectivity[starts[rows, None] + np.arange(n)]].mean(axis=1)
        return out


def clip_tolerance(fraction: np.ndarray, size: np.ndarray, cut: np.ndarray, dim: int) -> float:
    """Linearity tolerance of the leaves: VOLUME_TOLERANCE x volume / boundary area, both from the
    grid (the area over-estimated by the cut cells' faces, which only tightens it)."""
    volume = float(np.sum(fraction * size**dim))
    area = float(np.sum(size[cut] ** (dim - 1))) or float(np.max(size) ** (dim - 1))
    return VOLUME_TOLERANCE[dim] * volume / area


def full_stress(stress: np.ndarray, model: str, poissons_ratio: float) -> np.ndarray:
    """(n, 6) stresses in VTK's tensor order [xx, yy, zz, xy, yz, xz] from the project's Voigt
    order ([sxx, syy, sxy] in 2D with szz = nu (sxx + syy) in plane strain and 0 in plane
    stress; [sxx, syy, szz, syz, sxz, sxy] in 3D)."""
    s = np.asarray(stress, dtype=float)
    out = np.zeros((len(s), 6))
    if s.shape[1] == 6:
        out[:, [0, 1, 2, 3, 4, 5]] = s[:, [0, 1, 2, 5, 3, 4]]
    else:
        out[:, 0], out[:, 1], out[:, 3] = s[:, 0], s[:, 1], s[:, 2]
        if model == "plane_strain":
            out[:, 2] = poissons_ratio * (s[:, 0] + s[:, 1])
    return out


def principal_stresses(tensor: np.ndarray) -> np.ndarray:
    """(n, 3) principal stresses s1 >= s2 >= s3 of tensors in VTK order (NaN rows stay NaN)."""
    t = np.asarray(tensor, dtype=float)
    m = np.zeros((len(t), 3, 3))
    for k, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        m[:, i, j] = m[:, j, i] = t[:, k]
    ok = np.all(np.isfinite(t), axis=1)
    out = np.full((len(t), 3), np.nan)
    out[ok] = np.linalg.eigvalsh(m[ok])[:, ::-1]
    return out


def _signed_distance(body: pb.BodyModel):
    return getattr(body.profile, "signed_distance", None)


def _merge(points: np.ndarray, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the distinct points (first occurrence kept) and each point's distinct one."""
    return unique_rows(np.round(points / scale).astype(np.int64))


#: the clipped cells of the last few grids (a load-step series writes the same bodies once per
#: step: the cells are clipped once, the fields sampled per step)
_CLIPPED: dict = {}
_CLIPPED_KEPT = 4


def body_output(problem: pb.Problem, solution: pb.Solution, body: pb.BodyModel, probes=()) -> BodyOutput:
    """The body's cells as they are with every field (see the module's description).
    ``probes``: points whose values the output must hold (the run's probes): the cut cells are
    split around each until it lies in an output cell, however close to the surface."""
    dim = problem.dim
    m = solution.mesh(body.name)
    nodes = np.asarray(m["nodes"], dtype=float).reshape(-1, dim)
    cells = np.asarray(m["cells"], dtype=np.int64).reshape(-1, 2**dim)
    fraction = np.asarray(m.get("cell_inside_fraction", np.ones(len(cells))), dtype=float).reshape(-1)
    lower = nodes[cells].min(axis=1)
    size = (nodes[cells].max(axis=1) - lower)[:, 0]
    held = np.asarray([list(p) for p in probes], dtype=float).reshape(-1, dim)
    geometry, used, origin = _clipped(body, dim, nodes, cells, fraction, lower, size, held)
    out = BodyOutput(**geometry, point_data={}, cell_data={})
    _point_fields(out, problem, solution, body, m, used, origin, lower, size)
    _cell_fields(out, problem, body, m, fraction)
    return out


def _clipped(body: pb.BodyModel, dim: int, nodes, cells, fraction, lower, size, held):
    """The output cells of a grid (points, connectivity, offsets, types, parent), the grid nodes
    used and each point's origin (-1: a grid node, else the background cell of a new point);
    kept for the last few grids, told apart by their nodes, cells, inside fractions, the points
    held and the body."""
    key = (id(body.profile), hashlib.sha1(b"".join(np.ascontiguousarray(a).tobytes()
                                                    for a in (nodes, cells, fraction, held))).hexdigest())
    if key not in _CLIPPED:
        while len(_CLIPPED) >= _CLIPPED_KEPT:
            _CLIPPED.pop(next(iter(_CLIPPED)))
        _CLIPPED[key] = (body.profile, _clip(body, dim, nodes, cells, fraction, lower, size, held))
    return _CLIPPED[key][1]


def _clip(body: pb.BodyModel, dim: int, nodes, cells, fraction, lower, size, held):
    whole = fraction >= 1.0 - 1e-12
    phi = _signed_distance(body)
    if phi is None:  # nothing to clip with: the cells as they are
        whole[:] = True
    tolerance = clip_tolerance(fraction, size, ~whole, dim)
    kept, (box_pts, box_parent, simplex_pts, simplex_parent, _) = clip_cells(
        lower, size, whole, phi, tolerance, EDGE_RESOLUTION * float(size.min()), MAX_DEPTH, held)
    # points: the whole cells' nodes first (their nodal values win when merged), then the new ones
    used = np.unique(cells[kept])
    new_points = np.concatenate([box_pts.reshape(-1, dim), simplex_pts.reshape(-1, dim)])
    new_parent = np.concatenate([np.repeat(box_parent, 2**dim), np.repeat(simplex_parent, dim + 1)])
    all_points = np.concatenate([nodes[used], new_points])
    first, index = _merge(all_points, 1e-9 * float(size.min()))
    local = np.full(len(nodes), -1, dtype=np.int64)
    local[used] = np.arange(len(used))
    n_box, n_simplex = len(box_pts), len(simplex_pts)
    conn = [index[local[cells[kept]]].ravel(),
            index[len(used) + np.arange(n_box * 2**dim)],
            index[len(used) + n_box * 2**dim + np.arange(n_simplex * (dim + 1))]]
    counts = np.concatenate([np.full(len(kept) + n_box, 2**dim), np.full(n_simplex, dim + 1)])
    box_type, simplex_type = VTK_TYPES[dim]
    geometry = {"points": all_points[first], "connectivity": np.concatenate(conn), "offsets": np.cumsum(counts),
                "types": np.concatenate([np.full(len(kept) + n_box, box_type),
                                         np.full(n_simplex, simplex_type)]).astype(np.uint8),
                "parent": np.concatenate([kept, box_parent, simplex_parent])}
    origin = np.concatenate([np.full(len(used), -1), new_parent])[first]
    return geometry, used, origin


def _point_fields(out: BodyOutput, problem, solution, body, m, used, origin, lower, size) -> None:
    """Displacement and recovered stress at the output points: nodal values at the grid's nodes,
    the solution evaluated in the body at the others (nudged towards their background cell's
    centre when the point sits on a side no active cell holds)."""
    dim, n_used = problem.dim, len(used)
    voigt = dim * (dim + 1) // 2
    disp = np.full((len(out.points), dim), np.nan)
    stress = np.full((len(out.points), voigt), np.nan)
    grid_rows = np.nonzero(origin < 0)[0]
    disp[grid_rows] = np.asarray(m["displacement"], dtype=float).reshape(-1, dim)[used[grid_rows]]
    nodal = getattr(solution, "nodal_stress", None)
    if nodal is not None:
        stress[grid_rows] = np.asarray(nodal(body.name), dtype=float)[used[grid_rows]]
    todo = np.nonzero(np.isnan(stress[:, 0]))[0]
    for attempt in range(3):
        if not len(todo):
            break
        p = out.points[todo]
        if attempt:  # towards the background cell's centre (grid nodes: none to move towards)
            parent = origin[todo]
            centre = np.where(parent[:, None] >= 0, lower[parent] + 0.5 * size[parent, None], p)
            p = p + 1e-9 * attempt * (centre - p)
        d = np.asarray(solution.displacement(p, body=body.name), dtype=float).reshape(-1, dim)
        s = np.asarray(solution.stress(p, body=body.name), dtype=float).reshape(-1, voigt)
        fill = np.isnan(disp[todo, 0])
        disp[todo[fill]] = d[fill]
        stress[todo] = s
        todo = todo[np.isnan(stress[todo, 0])]
    nu = body.material.poissons_ratio
    tensor = full_stress(stress, problem.model, nu)
    out.point_data["displacement"] = np.column_stack([disp, np.zeros((len(disp), 3 - dim))]) if dim < 3 else disp
    out.point_data["stress"] = tensor
    out.point_data["von_mises"] = von_mises(stress, problem.model, nu)
    out.point_data["principal_stress"] = principal_stresses(tensor)


def _cell_fields(out: BodyOutput, problem, body, m, fraction) -> None:
    """The raw stress (the discrete field's C B u at the inside part's centroid) of each output
    cell's background cell, its von Mises stress, inside fraction and index."""
    dim = problem.dim
    raw = np.asarray(m["cell_stress"], dtype=float).reshape(-1, dim * (dim + 1) // 2)[out.parent]
    nu = body.material.poissons_ratio
    out.cell_data["cell_stress"] = full_stress(raw, problem.model, nu)
    out.cell_data["cell_von_mises"] = von_mises(raw, problem.model, nu)
    out.cell_data["inside_fraction"] = fraction[out.parent]
    out.cell_data["background_cell"] = out.parent.astype(np.int32)
