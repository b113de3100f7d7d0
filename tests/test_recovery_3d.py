"""Stress recovery at planes of symmetry (solver.fem.recovery): a planar sliding face
is a mirror of the solution, so the patches of the nodes on and near it are completed by the
mirror images of the cells' centroid stresses. The truth here is a quadratic stress field with
that symmetry (the components with one index normal to a plane odd across it, the others even):
the quadratic fit of a whole mirrored patch reproduces it exactly on the symmetry planes and on
their intersection (the axis of a quarter model), where one-sided patches could not."""

from types import SimpleNamespace

import numpy as np
import pytest

from ibfem.geometry.solids.shapes import Box
from ibfem.solver.fem.cut_cells3d import CUT
from ibfem.solver.fem.grid import RefinementZone
from ibfem.solver.fem.recovery import MirrorPlane, patch_recovery, reflect_stress, sliding_symmetry
from ibfem.solver.fem.solid_space import discretise_solid
from ibfem.solver.model.problem import Sliding
from ibfem.solver.solution import IBFEMSolution

H0 = 0.1


def _box(offset=(0.0, 0.0, 0.0), refine: bool = True):
    zones = (RefinementZone(1, 0.3, np.array([0.0, 0.0, 0.5])),) if refine else ()
    return discretise_solid("box", Box([0, 0, 0], [1, 1, 1]), (1.0, 1.0), np.eye(6), 0.3, H0, zones, offset=offset)


def _field(p):
    """[sxx, syy, szz, syz, sxz, sxy]: even in x and y except syz (odd in y), sxz (odd in x), sxy
    (odd in both): the symmetry of a solution with sliding faces on x = 0 and y = 0."""
    x, y, z = p.T
    return np.column_stack([1 + x * x + 2 * y * y - z + z * z, 2 - x * x + y * y + 3 * z * z, 0.5 + x * x + y * y - 2 * z,
                            y * (1 + z), x * (2 - z), x * y])


def _recover(body, sliding):
    cent = body.cell_centroids()
    planes, cut = sliding_symmetry(body.boundary, sliding, body.grid, body.status == CUT, body.inside_volume, cent)
    g = body.grid
    return patch_recovery(g.cells, g.nodes, g.size, body.inside_volume, cut, cent, _field(cent), planes), planes


def _away_from_other_faces(nodes):
    """Nodes whose patches (two cells of the coarsest size) stay clear of the faces that are no
    mirrors (x = 1, y = 1, z = 0, z = 1)."""
    reach = 3.01 * H0
    return (nodes[:, 0] <= 1 - reach) & (nodes[:, 1] <= 1 - reach) & (nodes[:, 2] >= reach) & (nodes[:, 2] <= 1 - reach)


@pytest.mark.parametrize("refine", [False, True])
def test_symmetric_quadratic_field_is_recovered_exactly_on_the_symmetry_planes(refine):
    body = _box(refine=refine)
    nodes = body.grid.nodes
    rec, planes = _recover(body, ["x_min", "y_min"])
    assert len(planes) == 2
    clear = _away_from_other_faces(nodes)
    on_planes = clear & ((np.abs(nodes[:, 0]) < 1e-12) | (np.abs(nodes[:, 1]) < 1e-12))
    axis = clear & (np.abs(nodes[:, 0]) < 1e-12) & (np.abs(nodes[:, 1]) < 1e-12)
    assert axis.sum() >= 3 and on_planes.sum() > 20
    assert np.allclose(rec[clear], _field(nodes[clear]), atol=1e-9)
    # without the mirrors the one-sided patches there are off by O(h^2) of the curvature
    g = body.grid
    plain = patch_recovery(g.cells, g.nodes, g.size, body.inside_volume, body.status == CUT, body.cell_centroids(),
                           _field(body.cell_centroids()))
    assert np.abs(plain[axis] - _field(nodes[axis])).max() > 1e-3
    # next to the faces that are no mirrors the linear fits keep their own cells (a mirrored
    # patch's linear fit would average a boundary's peak across the node)
    _, cut = sliding_symmetry(body.boundary, ["x_min", "y_min"], g, body.status == CUT, body.inside_volume,
                              body.cell_centroids())
    at_boundary = np.zeros(len(nodes), bool)
    at_boundary[g.cells[cut].ravel()] = True
    assert at_boundary.sum() > 100
    assert np.allclose(rec[at_boundary], plain[at_boundary], equal_nan=True)


def test_a_curved_or_missing_plane_gives_no_mirror_and_a_misaligned_one_changes_nothing():
    body = _box(refine=False)
    g, cent = body.grid, body.cell_centroids()
    plain = patch_recovery(g.cells, g.nodes, g.size, body.inside_volume, body.status == CUT, cent, _field(cent))
    rec, planes = _recover(body, [])
    assert planes == [] and np.array_equal(rec, plain, equal_nan=True)
    # a grid shifted by fractions of a cell: the planes cut cells, the images share no node with
    # the grid and the recovery is the plain one (cut cells keep their linear fits)
    shifted = _box(offset=(0.3, 0.45, 0.1), refine=False)
    g, cent = shifted.grid, shifted.cell_centroids()
    plain = patch_recovery(g.cells, g.nodes, g.size, shifted.inside_volume, shifted.status == CUT, cent, _field(cent))
    rec, planes = _recover(shifted, ["x_min", "y_min"])
    assert len(planes) == 2 and any(p.cells.any() for p in planes)
    assert np.allclose(rec, plain, equal_nan=True)


def test_reflection_of_stresses():
    rng = np.random.default_rng(3)
    s = rng.normal(size=(5, 6))
    ex = reflect_stress(s, [1.0, 0.0, 0.0])
    # sxz and sxy change sign, the rest stays
    assert np.allclose(ex, s * [1, 1, 1, 1, -1, -1])
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    t = reflect_stress(s, n)
    assert np.allclose(reflect_stress(t, n), s)  # an involution

    def tensor(v):
        return np.array([[v[0], v[5], v[4]], [v[5], v[1], v[3]], [v[4], v[3], v[2]]])

    for a, b in zip(s, t):  # the principal stresses stay
        assert np.allclose(np.linalg.eigvalsh(tensor(a)), np.linalg.eigvalsh(tensor(b)))
    # a uniaxial stress along the normal, or across it, is its own image
    nn = np.outer(n, n)
    v = np.array([[nn[0, 0], nn[1, 1], nn[2, 2], nn[1, 2], nn[0, 2], nn[0, 1]]])
    assert np.allclose(reflect_stress(v, n), v)
    assert np.allclose(reflect_stress(np.array([[1.0, -2.0, 0.5]]), [0.0, 1.0]), [[1.0, -2.0, -0.5]])  # 2D


def test_mirror_planes_complete_a_two_dimensional_patch_too():
    # a uniform 2D grid of squares on [0, 1]^2 with the plane x = 0: the node (0, 0.5) gets the
    # quadratic fit of its whole mirrored patch, exact for a field even in x
    n = 8
    h = 1.0 / n
    ij = np.stack(np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij"), -1).reshape(-1, 2)
    nodes = ij * h
    idx = lambda i, j: i * (n + 1) + j  # noqa: E731
    cells = np.array([[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)] for i in range(n) for j in range(n)])
    cent = nodes[cells].mean(axis=1)
    field = lambda p: np.column_stack([1 + p[:, 0] ** 2 + p[:, 1] ** 2, 3 * p[:, 1] ** 2, p[:, 0] * p[:, 1]])  # noqa: E731
    border = np.isclose(cent, 0.5 * h) | np.isclose(cent, 1 - 0.5 * h)
    cut = border[:, 1] | np.isclose(cent[:, 0], 1 - 0.5 * h)  # every side but x = 0 is a boundary
    plane = MirrorPlane(np.zeros(2), np.array([-1.0, 0.0]), np.ones(len(cells), bool))
    size, w = np.full(len(cells), h), np.full(len(cells), h * h)
    rec = patch_recovery(cells, nodes, size, w, cut, cent, field(cent), [plane])
    on_plane = np.isclose(nodes[:, 0], 0) & (nodes[:, 1] > 2.9 * h) & (nodes[:, 1] < 1 - 2.9 * h)
    assert on_plane.sum() == 3
    assert np.allclose(rec[on_plane], field(nodes[on_plane]), atol=1e-12)


def test_the_solution_recovers_with_its_sliding_faces():
    body = _box(refine=False)
    cent = body.cell_centroids()
    problem = SimpleNamespace(boundary_conditions=[Sliding("box", "x_min"), Sliding("box", "y_min")])
    sol = IBFEMSolution(problem=problem, bodies=[body], u=np.zeros(0), converged=True, body_info={}, reactions={},
                        iterations={}, timings={})
    sol.__dict__["_centroid_stress"] = {"box": _field(cent)}
    nodes = body.grid.nodes
    clear = _away_from_other_faces(nodes)
    assert np.allclose(sol.nodal_stress("box")[clear], _field(nodes[clear]), atol=1e-9)


def test_a_plane_given_with_its_inward_normal_is_turned_outward():
    # a CAD face's surface may be oriented into the body: the mirror is the same plane
    from ibfem.geometry.surfaces import Plane

    body = _box(refine=False)
    faces = dict(body.boundary.faces)
    for name in ("x_min", "y_min"):
        face, plane = faces[name], faces[name].surface
        faces[name] = SimpleNamespace(surface=Plane(origin=plane.origin, normal=tuple(-np.asarray(plane.normal))),
                                      project=face.project)
    cent = body.cell_centroids()
    boundary = SimpleNamespace(faces=faces, signed_distance=body.boundary.signed_distance)
    planes, _ = sliding_symmetry(boundary, ["x_min", "y_min"], body.grid, body.status == CUT, body.inside_volume, cent)
    assert np.allclose(planes[0].normal, [-1, 0, 0]) and np.allclose(planes[1].normal, [0, -1, 0])
    assert all(p.cells.sum() > 0 for p in planes)


def test_a_flat_face_of_a_revolution_is_found_plane_from_its_points():
    # a quarter cylinder turned from the rectangle (r, z) in [0, 1] x [0, 1]: its bottom
    # ("bottom", a turned line) names no plane, its cut ends ("start", "end") do; all three are
    # mirrors, and a field symmetric about the three is recovered exactly on them
    from ibfem.geometry.solids.build import solid_from_dict

    solid = solid_from_dict({"type": "revolution", "axis_origin": [0, 0, 0], "axis": [0, 0, 1], "angle_deg": 90,
                             "profile": {"type": "profile", "edges": [
                                 {"type": "line", "start": [0, 0], "end": [1, 0], "name": "bottom"},
                                 {"type": "line", "start": [1, 0], "end": [1, 1], "name": "side"},
                                 {"type": "line", "start": [1, 1], "end": [0, 1], "name": "top"},
                                 {"type": "line", "start": [0, 1], "end": [0, 0], "name": "axis"}]}})
    body = discretise_solid("quarter", solid, (1.0, 1.0), np.eye(6), 0.3, H0)
    cent = body.cell_centroids()
    planes, cut = sliding_symmetry(body.boundary, ["bottom", "start", "end", "side"], body.grid, body.status == CUT,
                                   body.inside_volume, cent)
    normals = sorted(tuple(np.round(p.normal, 12) + 0.0) for p in planes)
    assert normals == [(-1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)]  # the curved side is none

    def field(p):
        x, y, z = p.T
        return np.column_stack([1 + x * x + y * y + z * z, 2 + x * x - z * z, 3 + y * y + 2 * z * z, y * z, x * z, x * y])

    g = body.grid
    rec = patch_recovery(g.cells, g.nodes, g.size, body.inside_volume, cut, cent, field(cent), planes)
    nodes = g.nodes
    clear = (np.hypot(nodes[:, 0], nodes[:, 1]) <= 1 - 3.01 * H0 - 0.5 * np.sqrt(2) * H0) & (nodes[:, 2] <= 1 - 3.01 * H0)
    edges = clear & (np.sum(np.abs(nodes) < 1e-6, axis=1) >= 2)
    assert edges.sum() >= 3  # on the axis and the edges where two planes meet
    assert np.allclose(rec[clear], field(nodes[clear]), atol=1e-9)


def test_a_straight_sliding_edge_of_a_2d_body_is_a_mirror():
    # a half disk on its diameter (y = 0, on the grid's lines): a field even in y (sxy odd) is
    # recovered exactly on the diameter away from the arc; the arc is no mirror
    from ibfem.geometry.shapes import profile_from_shape
    from ibfem.solver.fem.grid import CUT as CUT2
    from ibfem.solver.fem.grid import build_grid
    from ibfem.solver.fem.recovery import nodal_stress
    from ibfem.solver.fem.space import exact_boundary

    boundary = exact_boundary(profile_from_shape({"type": "half_disk", "center": [0, 0], "radius": 1.0, "side": "above"}))
    grid = build_grid(boundary, 0.1, (RefinementZone(1, 0.3, np.array([0.2, 0.0])),))
    m = grid.moments
    cent = grid.center + 0.5 * grid.size[:, None] * np.column_stack([m[:, 1, 0], m[:, 0, 1]]) / m[:, 0, 0, None]

    def field(p):
        x, y = p.T
        return np.column_stack([1 + x * x + 2 * y * y - 0.5 * x, 3 * y * y - x, x * y + y])

    planes, _ = sliding_symmetry(boundary, ["flat", "arc"], grid, grid.status == CUT2, grid.inside_area, cent)
    assert len(planes) == 1 and np.allclose(planes[0].normal, [0, -1])
    rec = nodal_stress(grid, cent, field(cent), boundary, ["flat", "arc"])
    nodes = grid.nodes
    clear = np.hypot(nodes[:, 0], nodes[:, 1]) <= 1 - 3.01 * 0.1 - 0.15
    diameter = clear & (np.abs(nodes[:, 1]) < 1e-12)
    assert diameter.sum() >= 9
    assert np.allclose(rec[clear], field(nodes[clear]), atol=1e-9)
    plain = nodal_stress(grid, cent, field(cent))
    assert np.abs(plain[diameter] - field(nodes[diameter])).max() > 1e-3


def test_faces_with_quadrature_only_are_mirrors_too():
    # the solid contract asks a face for its quadrature alone: its plane comes from the points
    # and the feet on it are judged by the signed distance
    body = _box(refine=False)
    faces = {name: SimpleNamespace(quadrature=face.quadrature) for name, face in body.boundary.faces.items()}
    boundary = SimpleNamespace(faces=faces, signed_distance=body.boundary.signed_distance)
    cent = body.cell_centroids()
    planes, cut = sliding_symmetry(boundary, ["x_min", "y_min"], body.grid, body.status == CUT, body.inside_volume, cent)
    assert np.allclose(planes[0].normal, [-1, 0, 0]) and np.allclose(planes[1].normal, [0, -1, 0])
    g, nodes = body.grid, body.grid.nodes
    rec = patch_recovery(g.cells, g.nodes, g.size, body.inside_volume, cut, cent, _field(cent), planes)
    clear = _away_from_other_faces(nodes)
    assert np.allclose(rec[clear], _field(nodes[clear]), atol=1e-9)


def _half_face(z0, z1):
    """The part z0 <= z <= z1 of the box's face x = 0: its quadrature and its projection."""
    def quadrature(resolution):
        y, z = np.meshgrid(np.linspace(0.05, 0.95, 10), np.linspace(z0 + 0.025, z1 - 0.025, 10))
        points = np.column_stack([np.zeros(y.size), y.ravel(), z.ravel()])
        return points, np.full(y.size, (z1 - z0) / y.size), np.tile([-1.0, 0.0, 0.0], (y.size, 1))

    def project(points):
        feet = np.column_stack([np.zeros(len(points)), np.clip(points[:, 1], 0, 1), np.clip(points[:, 2], z0, z1)])
        return SimpleNamespace(points=feet)

    return SimpleNamespace(quadrature=quadrature, project=project)


def test_a_face_sharing_its_plane_with_another_mirrors_only_its_own_part():
    # the face x = 0 split at z = 0.5: sliding on the lower half mirrors the cells whose feet lie
    # on it (z <= 0.5), none above; the whole face, alone in its plane, mirrors the whole band
    body = _box(refine=False)
    faces = dict(body.boundary.faces)
    whole = faces.pop("x_min")
    split = dict(faces, low=_half_face(0.0, 0.5), high=_half_face(0.5, 1.0))
    cent = body.cell_centroids()
    args = (body.grid, body.status == CUT, body.inside_volume, cent)
    lower, _ = sliding_symmetry(SimpleNamespace(faces=split, signed_distance=body.boundary.signed_distance), ["low"], *args)
    full, _ = sliding_symmetry(SimpleNamespace(faces=dict(faces, x_min=whole),
                                               signed_distance=body.boundary.signed_distance), ["x_min"], *args)
    low_cells, all_cells = np.nonzero(lower[0].cells)[0], np.nonzero(full[0].cells)[0]
    assert len(all_cells) > 0 and set(low_cells) <= set(all_cells)
    assert cent[low_cells, 2].max() <= 0.5 + 1e-9
    assert set(low_cells) == set(all_cells[cent[all_cells, 2] <= 0.5])
