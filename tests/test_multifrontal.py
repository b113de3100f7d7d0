"""The multifrontal Cholesky (solver.fem.multifrontal) against dense truth: Schur complements of
the trailing dofs, their inverses and solves on elasticity-like grid matrices in random and
nested-dissection orders, forests, the whole matrix as the root, indefinite matrices; then
condensed_factor with either factorisation forced, and a contact scene solved with both."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.fem import linalg

mf = pytest.importorskip("ibfem.solver.fem.multifrontal")
if not mf.available():
    pytest.skip("the compiled kernels (numba) are not available", allow_module_level=True)


def laplacian(k: int) -> sp.csr_matrix:
    return sp.diags([-np.ones(k - 1), 2 * np.ones(k), -np.ones(k - 1)], [-1, 0, 1]).tocsr()


def elasticity_like(shape: tuple[int, ...], seed: int = 0) -> sp.csr_matrix:
    """An SPD grid matrix of FE type: the grid Laplacian coupled across the dim dofs of a node
    (kron with an SPD dim x dim block), randomly scaled per dof, a small mass term, an explicit
    zero stored."""
    dim = len(shape)
    lap = sp.csr_matrix((1, 1))
    for i, k in enumerate(shape):
        term = laplacian(k)
        for j, other in enumerate(shape):
            if j != i:
                term = sp.kron(term, sp.eye(other)) if j > i else sp.kron(sp.eye(other), term)
        lap = term if lap.shape == (1, 1) else lap + term
    block = np.eye(dim) + 0.4 * (np.ones((dim, dim)) - np.eye(dim))
    k = sp.kron(lap, block).tocsr() + 1e-3 * sp.eye(lap.shape[0] * dim)
    scale = sp.diags(np.random.default_rng(seed).uniform(0.5, 2.0, k.shape[0]))
    k = (scale @ k @ scale).tocoo()
    n = k.shape[0]
    rows, cols = np.append(k.row, [0, n - 1]), np.append(k.col, [n - 1, 0])
    return sp.csr_matrix((np.append(k.data, [0.0, 0.0]), (rows, cols)), shape=(n, n))


def dense_schur(k: np.ndarray, interior: np.ndarray, contact: np.ndarray) -> np.ndarray:
    kii = k[np.ix_(interior, interior)]
    return k[np.ix_(contact, contact)] - k[np.ix_(contact, interior)] @ np.linalg.solve(kii, k[np.ix_(interior, contact)])


def random_order(n: int, dofs: np.ndarray, rng) -> np.ndarray:
    rest = np.setdiff1d(np.arange(n), dofs)
    return np.concatenate([rng.permutation(rest), dofs])


def check_condensed(k: sp.csr_matrix, dofs: np.ndarray, order: np.ndarray) -> mf.CholeskyFactor:
    factor, schur, g = mf.condensed_cholesky(k, order, len(dofs))
    kd = k.toarray()
    interior = np.setdiff1d(np.arange(k.shape[0]), dofs)
    truth = dense_schur(kd, interior, dofs)
    np.testing.assert_allclose(schur, truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    np.testing.assert_allclose(g @ schur, np.eye(len(dofs)), rtol=0, atol=1e-9)
    np.testing.assert_array_equal(g, g.T)
    f = np.random.default_rng(1).standard_normal((k.shape[0], 3))
    x = factor.solve(f)
    assert np.abs(kd @ x - f).max() <= 1e-12 * np.abs(kd).max() * np.abs(x).max()
    # one right-hand side takes the vector path (sums reassociated)
    np.testing.assert_allclose(factor.solve(f[:, 1]), x[:, 1], rtol=0, atol=1e-12 * np.abs(x[:, 1]).max())
    return factor


@pytest.mark.parametrize("shape", [(24, 17), (7, 6, 5)])
def test_schur_inverse_and_solves_in_a_random_order(shape):
    k = elasticity_like(shape)
    rng = np.random.default_rng(2)
    dofs = rng.choice(k.shape[0], 40, replace=False)
    factor = check_condensed(k, dofs, random_order(k.shape[0], dofs, rng))
    assert factor.n_supernodes > 1
    assert factor.largest_front >= 40
    assert factor.factor_bytes == 8 * factor.factor_ptr[-1]


def test_nested_dissection_order_with_a_contact_line():
    pytest.importorskip("pymetis")
    k = elasticity_like((40, 30), seed=3)
    order = linalg.metis_order(k, 2)
    dofs = np.arange(2 * 30 * 20, 2 * 30 * 21)  # the dofs of one grid line (a separator-like set)
    interior = order[~np.isin(order, dofs)]
    factor = check_condensed(k, dofs, np.concatenate([interior, dofs]))
    # nested dissection: far less fill than the dense lower triangle
    assert factor.nnz < 0.1 * k.shape[0] ** 2 / 2


def test_nnz_counts_the_lower_triangle_of_every_supernode():
    k = elasticity_like((12, 9))
    factor = mf.CholeskyFactor(k, np.arange(k.shape[0]), 0)
    ncol = np.diff(factor.sn_start)
    front = ncol + np.diff(factor.row_ptr)
    assert factor.nnz == int(np.sum(ncol * front - ncol * (ncol - 1) // 2))
    # the stored factor covers at least the exact fill of L (dense Cholesky of the same order)
    dense = np.linalg.cholesky(k.toarray())
    assert factor.nnz >= np.count_nonzero(np.abs(dense) > 1e-300)


def test_no_condensed_dofs():
    k = elasticity_like((15, 11))
    factor, schur, g = mf.condensed_cholesky(k, np.random.default_rng(4).permutation(k.shape[0]), 0)
    assert schur.shape == g.shape == (0, 0)
    f = np.random.default_rng(5).standard_normal(k.shape[0])
    np.testing.assert_allclose(k @ factor.solve(f), f, rtol=0, atol=1e-11 * np.abs(f).max())


def test_all_dofs_condensed_gives_the_matrix_and_its_inverse():
    k = elasticity_like((6, 5))
    n = k.shape[0]
    dofs = np.random.default_rng(6).permutation(n)
    factor, schur, g = mf.condensed_cholesky(k, dofs, n)
    kd = k.toarray()[np.ix_(dofs, dofs)]
    np.testing.assert_allclose(schur, kd, rtol=0, atol=1e-14 * np.abs(kd).max())
    np.testing.assert_allclose(g, np.linalg.inv(kd), rtol=0, atol=1e-10 * np.abs(g).max())
    assert factor.n_supernodes == 1


def test_two_bodies_make_an_elimination_forest():
    a, b = elasticity_like((10, 8), seed=7), elasticity_like((6, 5, 3), seed=8)
    k = sp.block_diag([a, b]).tocsr()
    rng = np.random.default_rng(9)
    dofs = np.concatenate([rng.choice(a.shape[0], 6, replace=False), a.shape[0] + rng.choice(b.shape[0], 5, replace=False)])
    factor = check_condensed(k, dofs, random_order(k.shape[0], dofs, rng))
    # the Schur complement of two unconnected bodies is block diagonal
    _, schur, _ = mf.condensed_cholesky(k, random_order(k.shape[0], dofs, rng), len(dofs))
    assert np.all(schur[:6, 6:] == 0.0)
    # and a forest without condensed dofs
    free = mf.CholeskyFactor(k, rng.permutation(k.shape[0]), 0)
    f = rng.standard_normal(k.shape[0])
    np.testing.assert_allclose(k @ free.solve(f), f, rtol=0, atol=1e-11 * np.abs(f).max())
    assert factor.n_supernodes > 2


def test_an_indefinite_matrix_raises_naming_the_dof():
    k = elasticity_like((9, 7)).tolil()
    k[20, 20] = -5.0
    k = k.tocsr()
    with pytest.raises(mf.NotPositiveDefinite, match=r"dof \d+ \(of 126\) is not positive") as err:
        mf.CholeskyFactor(k, np.arange(k.shape[0]), 0)
    assert isinstance(err.value, np.linalg.LinAlgError)
    assert err.value.dof == 20  # every other principal submatrix is positive definite


def test_negative_interior_pivots_are_allowed_when_not_definite():
    """An indefinite K0 whose Schur complement is positive definite (as SuperLU without
    pivoting handles it): L D L^T with signed pivots."""
    k = elasticity_like((8, 7)).toarray()
    n = len(k)
    k[0, :], k[:, 0] = 0.0, 0.0
    k[0, 0] = -3.0  # a decoupled negative dof: the interior indefinite, S untouched
    dofs = np.arange(n - 10, n)
    order = np.concatenate([np.random.default_rng(10).permutation(n - 10), dofs])
    factor = check_condensed(sp.csr_matrix(k), dofs, order)
    with pytest.raises(mf.NotPositiveDefinite):
        mf.CholeskyFactor(sp.csr_matrix(k), order, 10, definite=True)
    assert not factor.definite


def test_a_zero_pivot_raises_even_when_not_definite():
    k = elasticity_like((5, 4)).toarray()
    k[3, :], k[:, 3] = 0.0, 0.0
    with pytest.raises(mf.NotPositiveDefinite, match="zero or not finite"):
        mf.condensed_cholesky(sp.csr_matrix(k), np.arange(len(k)), 4)


def test_bad_arguments_are_named():
    k = elasticity_like((4, 3))
    with pytest.raises(ValueError, match="permutation"):
        mf.CholeskyFactor(k, np.zeros(k.shape[0], dtype=int), 0)
    with pytest.raises(ValueError, match="root supernode"):
        mf.CholeskyFactor(k, np.arange(k.shape[0]), k.shape[0] + 1)
    factor = mf.CholeskyFactor(k, np.arange(k.shape[0]), 0)
    with pytest.raises(ValueError, match="right-hand side"):
        factor.solve(np.ones(3))


@pytest.fixture
def grid_system():
    k = elasticity_like((30, 22), seed=11)
    dofs = np.random.default_rng(12).choice(k.shape[0], 60, replace=False)
    return k, dofs, np.random.default_rng(13).permutation(k.shape[0])


def test_condensed_factor_backends_agree(monkeypatch, grid_system):
    k, dofs, order = grid_system
    out = {}
    for name in ("superlu", "cholesky"):
        monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", name)
        out[name] = linalg.condensed_factor(k, dofs, order)
    (lu, s1, g1), (ch, s2, g2) = out["superlu"], out["cholesky"]
    assert isinstance(ch, mf.CholeskyFactor) and isinstance(lu, linalg.PermutedLU)
    np.testing.assert_allclose(s2, s1, rtol=0, atol=1e-12 * np.abs(s1).max())
    np.testing.assert_allclose(g2, g1, rtol=0, atol=1e-10 * np.abs(g1).max())
    f = np.random.default_rng(14).standard_normal(k.shape[0])
    np.testing.assert_allclose(ch.solve(f), lu.solve(f), rtol=0, atol=1e-11 * np.abs(lu.solve(f)).max())


def test_condensed_factor_choice(monkeypatch, grid_system):
    k, dofs, order = grid_system
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "lapack")
    with pytest.raises(ValueError, match="IBFEM_CONDENSED_FACTOR must be one of auto, superlu, cholesky, got 'lapack'"):
        linalg.condensed_factor(k, dofs, order)
    monkeypatch.delenv("IBFEM_CONDENSED_FACTOR")
    assert isinstance(linalg.condensed_factor(k, dofs, order)[0], linalg.PermutedLU)  # small: SuperLU
    monkeypatch.setattr(linalg, "CHOLESKY_NONZEROS", 0)
    assert isinstance(linalg.condensed_factor(k, dofs, order)[0], mf.CholeskyFactor)
    monkeypatch.setenv("IBFEM_NO_JIT", "1")
    assert isinstance(linalg.condensed_factor(k, dofs, order)[0], linalg.PermutedLU)
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    with pytest.raises(ValueError, match="needs numba"):
        linalg.condensed_factor(k, dofs, order)


def test_auto_falls_back_to_superlu_on_a_bad_pivot(monkeypatch):
    k = elasticity_like((6, 5)).toarray()
    k[3, :], k[:, 3] = 0.0, 0.0  # a zero pivot
    k = sp.csr_matrix(k)
    monkeypatch.setattr(linalg, "CHOLESKY_NONZEROS", 0)
    calls = []
    monkeypatch.setattr(linalg, "_superlu_condensed", lambda *a: calls.append(a) or "superlu")
    assert linalg.condensed_factor(k, np.array([0, 1]), np.arange(k.shape[0])) == "superlu"
    assert len(calls) == 1
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    with pytest.raises(mf.NotPositiveDefinite):
        linalg.condensed_factor(k, np.array([0, 1]), np.arange(k.shape[0]))


def quarter_ball_on_block():
    """A small 3D scene: a quarter half-ball on a block, symmetry planes sliding (3 levels, 2k dofs)."""
    from _solids3d import QuarterHalfBall
    from _turned_box import TurnedBox
    from ibfem.solver.model import problem as pb

    steel = pb.Material("steel", 2.0e11, 0.3)
    zone = (pb.Refinement(3, 0.1),)
    bodies = (pb.BodyModel("ball", QuarterHalfBall([0, 0, 1.0], 1.0), steel, 0.25, zone),
              pb.BodyModel("block", TurnedBox([1, 1, 1], shift=(0, 0, -1)), steel, 0.25, zone))
    bcs = (pb.Displacement("ball", "flat", (0.0, 0.0, -0.002)), pb.Sliding("ball", "sym_x"),
           pb.Sliding("ball", "sym_y"), pb.Fixed("block", "z0"), pb.Sliding("block", "x0"), pb.Sliding("block", "y0"))
    contact = pb.ContactModel(("ball", "block"), "frictionless", point=np.zeros(3))
    return pb.Problem("quarter ball", "solid", 1.0, bodies, bcs, (contact,))


def test_a_contact_scene_is_the_same_with_either_factorisation(monkeypatch):
    from _contact_scenes import cylinder_on_block
    from ibfem.solver.solving import solve

    results, calls = {}, []
    original = mf.condensed_cholesky
    monkeypatch.setattr(mf, "condensed_cholesky", lambda *a, **kw: calls.append(a[0].shape) or original(*a, **kw))
    for name in ("superlu", "cholesky"):
        monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", name)
        results[name] = solve(cylinder_on_block("frictionless")).contacts[0]
    # the forced Cholesky factored K0, each body's block on its own (K0 couples no two bodies); the
    # forced SuperLU did not call it
    assert len(calls) == 2
    a, b = results["superlu"], results["cholesky"]
    assert b["half_width"] == pytest.approx(a["half_width"], rel=1e-9)
    assert b["normal_force"] == pytest.approx(a["normal_force"], rel=1e-9)


def test_the_condensed_3d_stiffness_is_the_same_with_either_factorisation(monkeypatch):
    """On the K0 of a 3D contact scene (captured from the driver). The scene's a and N are not
    compared: they move by 4e-5 relative when K0 is multiplied by 1 + 2^-52 (SuperLU alone,
    measured), a round-off sensitivity of the contact iteration, not of the factorisations."""
    import ibfem.solver.contact.driver as driver
    from ibfem.solver.solving import solve

    captured = {}
    original = driver.condensed_factor

    def capture(k0, dofs, order=None, nearness=None):
        captured.update(k0=k0, dofs=dofs, order=order)
        return original(k0, dofs, order, nearness)

    monkeypatch.setattr(driver, "condensed_factor", capture)
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "superlu")
    solve(quarter_ball_on_block())
    k0, dofs, order = captured["k0"], captured["dofs"], captured["order"]
    lu, s1, g1 = linalg.condensed_factor(k0, dofs, order)
    monkeypatch.setenv("IBFEM_CONDENSED_FACTOR", "cholesky")
    ch, s2, g2 = linalg.condensed_factor(k0, dofs, order)
    np.testing.assert_allclose(s2, s1, rtol=0, atol=1e-12 * np.abs(s1).max())
    np.testing.assert_allclose(g2, g1, rtol=0, atol=1e-12 * np.abs(g1).max())
    f = np.random.default_rng(15).standard_normal(k0.shape[0])
    x = ch.solve(f)
    np.testing.assert_allclose(x, lu.solve(f), rtol=0, atol=1e-12 * np.abs(x).max())
    assert np.abs(k0 @ x - f).max() <= 1e-12 * np.abs(f).max()


def grid_structured_system(rng) -> tuple[sp.csr_matrix, np.ndarray]:
    """A random SPD system with the structures the grids make: several bodies (an elimination
    forest), hanging-node and aggregated-cell couplings (a dof tied to a few others beyond the
    grid stencil), condensed dofs drawn from every body, and round-off asymmetry (couplings that
    cancel to about 1e-16 of the diagonal stored on one side only, as assembly leaves them)."""
    blocks, contact = [], []
    offset = 0
    for _ in range(int(rng.integers(1, 4))):
        shape = tuple(int(s) for s in rng.integers(2, 6, size=int(rng.integers(2, 4))))
        k = elasticity_like(shape, seed=int(rng.integers(1 << 30))).tolil()
        n = k.shape[0]
        for i in rng.choice(n, size=max(1, n // 10), replace=False):  # hanging nodes / aggregation
            for j in rng.choice(n, size=int(rng.integers(1, 4)), replace=False):
                if i != j:
                    w = 0.05 * rng.uniform() * min(k[i, i], k[j, j])
                    k[i, j] -= w
                    k[j, i] -= w
                    k[i, i] += w
                    k[j, j] += w
        blocks.append(k.tocsr())
        contact.append(offset + rng.choice(n, size=int(rng.integers(1, max(2, n // 6))), replace=False))
        offset += n
    k = sp.block_diag(blocks, format="coo")
    n = k.shape[0]
    diag = np.abs(k.diagonal()).max()
    r = rng.integers(0, n, size=n // 3)
    c = rng.integers(0, n, size=n // 3)
    keep = r != c  # one-sided round-off entries
    k = sp.csr_matrix((np.append(k.data, 1e-16 * diag * rng.standard_normal(keep.sum())),
                       (np.append(k.row, r[keep]), np.append(k.col, c[keep]))), shape=(n, n))
    return k, np.unique(np.concatenate(contact))


@pytest.mark.parametrize("seed", range(40))
def test_fuzz_grid_structures_with_round_off_asymmetry_against_scipy(seed):
    """The factorisation of the symmetric part against scipy: Schur complement, its inverse and
    solves, for matrices whose structure is symmetric only up to round-off entries (a crossed-
    cylinders full model failed with 'row structures disagree with the column counts')."""
    rng = np.random.default_rng(seed)
    k, dofs = grid_structured_system(rng)
    order = random_order(k.shape[0], dofs, rng)
    factor, schur, g = mf.condensed_cholesky(k, order, len(dofs))
    sym = (0.5 * (k + k.T)).toarray()
    interior = np.setdiff1d(np.arange(k.shape[0]), dofs)
    truth = dense_schur(sym, interior, dofs)
    np.testing.assert_allclose(schur, truth, rtol=0, atol=1e-10 * np.abs(truth).max())
    np.testing.assert_allclose(g @ schur, np.eye(len(dofs)), rtol=0, atol=1e-8)
    f = rng.standard_normal((k.shape[0], 2))
    x = factor.solve(f)
    import scipy.sparse.linalg as spla

    np.testing.assert_allclose(x, spla.splu(sp.csc_matrix(sym)).solve(f), rtol=1e-9, atol=1e-12 * np.abs(x).max())
