"""Elimination orders for the condensed factorisation: the flop count of an order read off its
elimination tree (solver.fem.multifrontal.factor_flops) against closed forms, and the order with
the contact nodes contracted into one vertex (solver.fem.linalg.contact_last_order), which the
condensed factorisation compares with the given one: any order gives the same Schur complement
(checked against the dense formula), the contact dofs last, a node's dofs together."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.fem import linalg

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)
pytest.importorskip("pymetis")


def squares(k: int) -> float:
    """sum_{i < k} i^2."""
    return (k - 1) * k * (2 * k - 1) / 6.0


def test_flops_of_a_path_a_dense_matrix_and_a_star():
    n = 30
    path = sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tocsr()
    natural = np.arange(n)
    assert mf.factor_flops(path, natural) == n - 1  # one entry below every pivot but the last
    assert mf.factor_flops(path, natural, 5) == (n - 5) + squares(5)  # the last 5 dofs one dense root
    dense = sp.csr_matrix(np.eye(n) * n + 1.0)
    assert mf.factor_flops(dense, np.random.default_rng(0).permutation(n)) == squares(n)
    star = sp.lil_matrix(np.eye(n) * n)
    star[0, 1:] = star[1:, 0] = 1.0
    star = star.tocsr()
    assert mf.factor_flops(star, natural) == squares(n)  # the hub first fills everything in
    assert mf.factor_flops(star, natural[::-1]) == n - 1  # the hub last: no fill


def grid3d(shape, seed: int) -> sp.csr_matrix:
    """SPD: a 3D grid Laplacian coupled across a node's 3 dofs, randomly scaled per dof."""
    lap = [sp.diags([-np.ones(k - 1), 2 * np.ones(k), -np.ones(k - 1)], [-1, 0, 1]) for k in shape]
    eye = [sp.eye(k) for k in shape]
    grid = (sp.kron(sp.kron(lap[0], eye[1]), eye[2]) + sp.kron(sp.kron(eye[0], lap[1]), eye[2])
            + sp.kron(sp.kron(eye[0], eye[1]), lap[2]))
    k = sp.kron(grid, np.eye(3) + 0.4 * (np.ones((3, 3)) - np.eye(3))) + 1e-3 * sp.eye(3 * grid.shape[0])
    scale = sp.diags(np.random.default_rng(seed).uniform(0.5, 2.0, k.shape[0]))
    return (scale @ k @ scale).tocsr()


def face_dofs(shape, radius: float) -> np.ndarray:
    """The dofs of the nodes of the face z = 0 within ``radius`` of its centre (a contact patch)."""
    i, j, kk = np.meshgrid(*(np.arange(s) for s in shape), indexing="ij")
    centre = (np.array(shape[:2]) - 1) / 2.0
    near = (kk.ravel() == 0) & (np.hypot(i.ravel() - centre[0], j.ravel() - centre[1]) <= radius)
    return (3 * np.flatnonzero(near)[:, None] + np.arange(3)).ravel()


def dense_schur(k: np.ndarray, contact: np.ndarray) -> np.ndarray:
    interior = np.setdiff1d(np.arange(len(k)), contact)
    kii = k[np.ix_(interior, interior)]
    return k[np.ix_(contact, contact)] - k[np.ix_(contact, interior)] @ np.linalg.solve(kii, k[np.ix_(interior, contact)])


def test_contracted_order_keeps_nodes_together_and_gives_the_schur_complement():
    shape = (9, 8, 7)
    k = grid3d(shape, seed=1)
    dofs = face_dofs(shape, 2.5)
    order = linalg.contact_last_order(k, dofs, 3)
    assert np.array_equal(np.sort(order), np.arange(k.shape[0]))
    np.testing.assert_array_equal(order[-len(dofs):], dofs)
    assert linalg._node_blocked(order, 3)
    factor, schur, g = mf.condensed_cholesky(k, order, len(dofs))
    truth = dense_schur(k.toarray(), dofs)
    np.testing.assert_allclose(np.asarray(schur), truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    np.testing.assert_allclose(g @ truth, np.eye(len(dofs)), rtol=0, atol=1e-9)


def test_partial_nodes_have_no_contracted_order():
    k = grid3d((4, 4, 4), seed=2)
    assert linalg.contact_last_order(k, np.array([0, 1, 5]), 3) is None


def test_the_cheaper_order_is_taken_by_its_flops():
    shape = (10, 9, 8)
    k = grid3d(shape, seed=3)
    dofs = face_dofs(shape, 3.0)
    contact = np.zeros(k.shape[0], dtype=bool)
    contact[dofs] = True
    # a poor order: the dofs by increasing z, so the face's neighbours are eliminated first
    poor = np.arange(k.shape[0]).reshape(shape + (3,)).transpose(2, 0, 1, 3).ravel()
    chosen = linalg._cheaper_order(k, dofs, poor)
    np.testing.assert_array_equal(chosen[-len(dofs):], dofs)
    contracted = linalg.contact_last_order(k, dofs, 3)
    given = np.concatenate([poor[~contact[poor]], dofs])
    flops = {name: mf.factor_flops(k, o, len(dofs)) for name, o in (("given", given), ("contracted", contracted),
                                                                      ("chosen", chosen))}
    assert flops["chosen"] == min(flops["given"], flops["contracted"])
    # an order that splits a node's dofs is not compared on the node graph: kept as given
    split = np.concatenate([poor[1:], poor[:1]])
    kept = linalg._cheaper_order(k, dofs, split)
    np.testing.assert_array_equal(kept, np.concatenate([split[~contact[split]], dofs]))


def test_condensed_factor_with_the_order_choice_gives_the_same_schur_complement(monkeypatch):
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    monkeypatch.setattr(linalg, "ORDER_CHOICE_DOFS", 0)
    compared = []
    cheaper = linalg._cheaper_order
    monkeypatch.setattr(linalg, "_cheaper_order", lambda *args: compared.append(1) or cheaper(*args))
    shapes = ((7, 6, 5), (6, 6, 6))
    k = sp.block_diag([grid3d(s, seed=4 + i) for i, s in enumerate(shapes)], format="csr")
    n1 = 3 * int(np.prod(shapes[0]))
    dofs = np.concatenate([face_dofs(shapes[0], 2.0), n1 + face_dofs(shapes[1], 2.0)])
    nearness = -np.arange(len(dofs), dtype=float)
    factor, schur, g = linalg.condensed_factor(k, dofs, linalg.metis_order(k, 3), nearness)
    kd = k.toarray()
    truth = dense_schur(kd, dofs)
    np.testing.assert_allclose(np.asarray(schur), truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    f = np.random.default_rng(5).standard_normal(k.shape[0])
    x = factor.solve(f)
    assert np.abs(kd @ x - f).max() <= 1e-12 * np.abs(kd).max() * np.abs(x).max()
    assert len(compared) == 2  # each body's order chosen
