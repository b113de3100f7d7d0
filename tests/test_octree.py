"""The 3D background grid (solver.fem.octree) and trilinear hexahedra (solver.fem.hexahedra),
checked against independent facts: 2:1 balance, conformity of the hanging-node constraints
(linear fields reproduced), the cube stiffness's rigid-body null space and strain energy, and
the patch test (a linear displacement field is reproduced exactly on a graded octree)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ibfem.solver.fem.assembly_blocks import assemble_blocks
from ibfem.solver.fem.grid import RefinementZone
from ibfem.solver.fem.hexahedra import cube_body_force, cube_stiffness, shape_functions, strain_matrix
from ibfem.solver.fem.octree import build_octree, level_jumps
from ibfem.solver.model.elasticity import elasticity_matrix, lame_parameters

C = elasticity_matrix(*lame_parameters(2.0e11, 0.3, "solid"), 3)


def unit_box_tree(levels=2, centre=(0.0, 0.0, 0.0), radius=0.15, h=0.25):
    keep = lambda lower, size: np.all(lower < 1.0 - 1e-12, axis=1)  # noqa: E731  (cells inside [0, 1]^3)
    zones = (RefinementZone(levels, radius, np.asarray(centre, float)),) if levels else ()
    return build_octree(([0, 0, 0], [1, 1, 1]), h, zones, keep)


@pytest.mark.parametrize("seed", range(4))
def test_graded_octree_is_balanced_and_conforming(seed):
    rng = np.random.default_rng(seed)
    tree = unit_box_tree(levels=int(rng.integers(1, 4)), centre=rng.uniform(0, 1, 3), radius=rng.uniform(0.02, 0.3))
    assert level_jumps(tree) <= 1
    assert tree.n_hanging > 0
    # every linear field is continuous across the hanging nodes: T f(free) == f(all nodes)
    a, b = rng.normal(size=3), rng.normal()
    f = tree.nodes @ a + b
    np.testing.assert_allclose(tree.constraint @ f[tree.free_nodes], f, atol=1e-12)
    # the leaves tile the box exactly once
    assert np.isclose((tree.size**3).sum(), 1.0)


def test_locate_finds_the_cell_holding_each_point():
    tree = unit_box_tree(levels=2)
    pts = np.random.default_rng(0).uniform(0, 1, (500, 3))
    cell = tree.locate(pts)
    assert (cell >= 0).all()
    lo, size = tree.lower[cell], tree.size[cell][:, None]
    assert np.all((pts >= lo - 1e-12) & (pts <= lo + size + 1e-12))


def test_locate_agrees_with_a_search_of_every_leaf():
    # brute force: the leaf whose half-open box [lower, lower + size) holds the point (points on
    # shared faces, edges and corners of cells of several levels, and points outside the grid)
    tree = unit_box_tree(levels=3)
    lattice = np.linspace(-0.0625, 1.0625, 37)  # steps of 1/32: the finest cells' planes and between
    pts = np.stack(np.meshgrid(lattice, lattice, lattice, indexing="ij"), axis=-1).reshape(-1, 3)
    lo, size = tree.lower, tree.size
    inside = np.all((pts[:, None, :] >= lo[None]) & (pts[:, None, :] < lo[None] + size[None, :, None]), axis=2)
    expected = np.where(inside.any(axis=1), np.argmax(inside, axis=1), -1)
    assert inside.sum(axis=1).max() == 1 and (expected >= 0).any() and (expected < 0).any()
    np.testing.assert_array_equal(tree.locate(pts), expected)


def test_shape_functions_partition_unity_and_reproduce_linear_fields():
    x = np.random.default_rng(1).uniform(-1, 1, (50, 3))
    n, dn = shape_functions(x)
    np.testing.assert_allclose(n.sum(axis=1), 1.0, atol=1e-14)
    np.testing.assert_allclose(dn.sum(axis=1), 0.0, atol=1e-14)
    corners = 2.0 * np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]) - 1
    np.testing.assert_allclose(n @ corners, x, atol=1e-14)
    assert strain_matrix(dn).shape == (50, 6, 24)


def test_cube_stiffness_null_space_and_strain_energy():
    h = 0.3
    k = cube_stiffness(C, h)
    np.testing.assert_allclose(k, k.T, atol=1e-6 * np.abs(k).max())
    ev = np.linalg.eigvalsh(k)
    assert np.sum(np.abs(ev) < 1e-9 * ev.max()) == 6 and ev.min() > -1e-9 * ev.max()
    # a uniform strain: energy 1/2 eps.C.eps times the volume, exactly
    eps = np.array([1e-3, -2e-4, 5e-4, 3e-4, -1e-4, 2e-4])  # Voigt, engineering shears
    grad = np.array([[eps[0], eps[5] / 2, eps[4] / 2], [eps[5] / 2, eps[1], eps[3] / 2], [eps[4] / 2, eps[3] / 2, eps[2]]])
    corners = h * np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
    u = (corners @ grad.T).ravel()
    np.testing.assert_allclose(0.5 * u @ k @ u, 0.5 * eps @ C @ eps * h**3, rtol=1e-12)
    np.testing.assert_allclose(cube_body_force([0, 0, -9.81], h).reshape(8, 3).sum(axis=0), [0, 0, -9.81 * h**3])


def test_patch_test_on_a_graded_octree():
    """Displacements of a linear field on the boundary of [0, 1]^3, meshed with two levels of
    refinement at a corner (hanging nodes on faces and edges): the interior reproduces the field
    to round-off."""
    tree = unit_box_tree(levels=2, centre=(0.9, 0.1, 0.5), radius=0.2)
    k_cells = np.stack([cube_stiffness(C, s) for s in tree.size])
    k = assemble_blocks(tree.cells, k_cells, len(tree.nodes))
    t = sp.kron(tree.constraint, np.eye(3), format="csr")
    kf = (t.T @ k @ t).tocsr()
    grad = np.array([[1e-3, 2e-4, -1e-4], [3e-4, -5e-4, 2e-4], [0.0, 1e-4, 4e-4]])
    exact = (tree.nodes @ grad.T + np.array([1e-3, -2e-3, 5e-4])).ravel()
    free_xyz = tree.nodes[tree.free_nodes]
    on_boundary = np.any((free_xyz < 1e-12) | (free_xyz > 1 - 1e-12), axis=1)
    fixed = np.repeat(on_boundary, 3)
    target = exact.reshape(-1, 3)[tree.free_nodes].ravel()
    u = np.zeros(len(target))
    u[fixed] = target[fixed]
    inner = ~fixed
    u[inner] = spla.spsolve(kf[inner][:, inner].tocsc(), -kf[inner][:, fixed] @ u[fixed])
    assert inner.sum() > 30 and tree.n_hanging > 0
    np.testing.assert_allclose(u, target, rtol=0, atol=1e-10 * np.abs(target).max())


def test_step_boundary_terms_are_written_once_for_both_dimensions():
    """The band's acoustic tensor and projectors in 3D: A_n n = (lambda + 2 mu) n, A_n t = mu t
    for a tangent t; the sliding projector is n n^T, the fixed one the identity."""
    from ibfem.solver.fem.step_boundary import acoustic_tensor, block_diagonal, projector

    rng = np.random.default_rng(3)
    n = rng.normal(size=(5, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    t = np.cross(n, rng.normal(size=(5, 3)))
    t /= np.linalg.norm(t, axis=1)[:, None]
    lam, mu = lame_parameters(2.0e11, 0.3, "solid")
    a = acoustic_tensor(n, lam, mu)
    np.testing.assert_allclose(np.einsum("qij,qj->qi", a, n), (lam + 2 * mu) * n, rtol=1e-12)
    np.testing.assert_allclose(np.einsum("qij,qj->qi", a, t), mu * t, rtol=1e-12, atol=1e-3)
    np.testing.assert_allclose(projector("sliding", n) @ t[:, :, None], 0.0, atol=1e-15)
    np.testing.assert_allclose(projector("fixed", n), np.broadcast_to(np.eye(3), (5, 3, 3)))
    free_z = projector("displacement", n, (False, False, True))
    assert free_z[0, 2, 2] == 0.0 and free_z[0, 0, 0] == 1.0
    assert block_diagonal(a).shape == (15, 15)


def test_point_operators_of_a_3d_body_reproduce_a_linear_field():
    """The function space's displacement, stress and traction operators on an octree with hanging
    nodes: for u = G x + c they give u, C eps(G) and (C eps(G)) n exactly at any points."""
    from ibfem.solver.fem.space import BodyDiscretisation, number_dofs

    tree = unit_box_tree(levels=2, centre=(0.3, 0.6, 0.2), radius=0.2)
    lam, mu = lame_parameters(2.0e11, 0.3, "solid")
    body = BodyDiscretisation(name="box", index=0, grid=tree, boundary=None, profile=None, lam=lam, mu=mu,
                              elasticity=C, model="solid", poissons_ratio=0.3)
    number_dofs([body])
    grad = np.array([[1e-3, 2e-4, -1e-4], [3e-4, -5e-4, 2e-4], [0.0, 1e-4, 4e-4]])
    u = (tree.nodes[tree.free_nodes] @ grad.T + np.array([1e-3, -2e-3, 5e-4])).ravel()
    pts = np.random.default_rng(5).uniform(0.0, 0.999, (40, 3))
    cells = tree.locate(pts)
    np.testing.assert_allclose((body.displacement_operator(pts, cells) @ u).reshape(-1, 3),
                               pts @ grad.T + np.array([1e-3, -2e-3, 5e-4]), rtol=1e-12, atol=1e-15)
    eps = 0.5 * (grad + grad.T)
    voigt = np.array([eps[0, 0], eps[1, 1], eps[2, 2], 2 * eps[1, 2], 2 * eps[0, 2], 2 * eps[0, 1]])
    sigma = C @ voigt
    np.testing.assert_allclose((body.stress_operator(pts, cells) @ u).reshape(-1, 6), np.tile(sigma, (40, 1)),
                               rtol=1e-9, atol=1e-6 * np.abs(sigma).max())
    n = np.random.default_rng(6).normal(size=(40, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    s = np.array([[sigma[0], sigma[5], sigma[4]], [sigma[5], sigma[1], sigma[3]], [sigma[4], sigma[3], sigma[2]]])
    np.testing.assert_allclose((body.traction_operator(pts, cells, n) @ u).reshape(-1, 3), n @ s.T,
                               rtol=1e-9, atol=1e-6 * np.abs(sigma).max())


def test_monomial_stiffness_reproduces_the_cube_stiffness():
    from ibfem.solver.fem.hexahedra import box_moments, cell_stiffness, full_cube_moments, monomial_stiffness

    km = monomial_stiffness(C)
    for h in (1.0, 0.3):
        k = cube_stiffness(C, h)
        np.testing.assert_allclose(cell_stiffness(full_cube_moments(), h, km), k, atol=1e-13 * np.abs(k).max())
    np.testing.assert_allclose(box_moments(-np.ones(3), np.ones(3)), full_cube_moments(), atol=1e-15)
    # half a cube: the stiffness of the part x < 0 is that of a box, half the volume
    m = box_moments(np.array([-1.0, -1, -1]), np.array([0.0, 1, 1]))
    assert np.isclose(m[0], 4.0)


def test_cut_moments_exact_for_a_face_parallel_plane_and_spectral_on_a_sphere():
    from ibfem.solver.fem.cut_cells3d import CUT, INSIDE, classify_cells, inside_moments
    from ibfem.solver.fem.hexahedra import box_moments, full_cube_moments

    # the half-space z < 0.3 cuts cells of a unit grid; every cut cell's moments are exact
    lower = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, -0.5]])
    size = np.array([1.0, 1.0, 1.0])
    plane = lambda p: 0.3 - p[:, 2]  # noqa: E731
    m = inside_moments(lower, size, plane, depth=2)
    zeta_top = 2.0 * (0.3 - lower[:, 2]) / size - 1.0
    exact = box_moments(np.full((3, 3), -1.0), np.stack([np.ones(3), np.ones(3), np.minimum(zeta_top, 1.0)], axis=1))
    np.testing.assert_allclose(m, exact, atol=1e-14)
    # a sphere: the dimension-reducing rule on the cut cells is spectral on smooth surfaces
    centre = np.array([0.05, -0.03, 0.02])
    sphere = lambda p: 1.0 - np.linalg.norm(p - centre, axis=1)  # noqa: E731
    volume, izz = _volume_and_izz(sphere, centre, depth=1)
    assert volume == pytest.approx(4 / 3 * np.pi, rel=1e-10)
    assert izz == pytest.approx(4 * np.pi / 15, rel=1e-10)


def _volume_and_izz(phi, centre, depth):
    """Volume and int (z - centre_z)^2 dV of the region phi > 0 from the cut-cell moments on a
    uniform grid of h = 0.25 (cells classified by the distance at their centres)."""
    from ibfem.solver.fem.cut_cells3d import CUT, INSIDE, classify_cells, inside_moments
    from ibfem.solver.fem.hexahedra import full_cube_moments

    tree = build_octree(([-1.5] * 3, [1.5] * 3), 0.25, (), lambda lo, s: phi(lo + 0.5 * s[:, None]) > -0.87 * s)
    status = classify_cells(tree.lower, tree.size, phi)
    mom = np.zeros((len(tree.size), 27))
    mom[status == INSIDE] = full_cube_moments()
    cut = status == CUT
    mom[cut] = inside_moments(tree.lower[cut], tree.size[cut], phi, depth)
    half = tree.size / 2
    cz = tree.center[:, 2] - centre[2]
    # z = c_z + half zeta: moments of 1, zeta (index 1) and zeta^2 (index 2)
    izz = (half**3 * (cz**2 * mom[:, 0] + 2 * cz * half * mom[:, 1] + half**2 * mom[:, 2])).sum()
    return (half**3 * mom[:, 0]).sum(), izz


def test_cut_moments_of_a_torus_converge_to_round_off(monkeypatch):
    # volume and second moments of a sphere and a torus exact to 1e-10 (the torus's
    # tube, radius 0.35 against cells of 0.25, needs two levels and six points per piece)
    import ibfem.solver.fem.cut_cells3d as cc

    monkeypatch.setattr(cc, "LINE_POINTS", 6)
    centre = np.array([0.05, -0.03, 0.02])
    big, small = 1.0, 0.35
    torus = lambda p: small - np.hypot(np.hypot(*(p - centre)[:, :2].T) - big, (p - centre)[:, 2])  # noqa: E731
    volume, izz = _volume_and_izz(torus, centre, depth=2)
    assert volume == pytest.approx(2 * np.pi**2 * big * small**2, rel=1e-12)
    assert izz == pytest.approx(np.pi**2 * big * small**4 / 2, rel=1e-10)
