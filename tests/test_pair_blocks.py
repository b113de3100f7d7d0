"""The contact band's terms summed per cell pair (solver.fem.pair_blocks) against the same terms
formed as sparse products of the bodies' own point operators (the jump and flux matrices of
solver.contact.ellipse.contact_operators, solver.fem.step_boundary.thin_band_terms), with a
slip zone's Coulomb block; and an invariant of the band: a translation common to both bodies has
no jump and no flux, so the contact stiffness annihilates it. A ball on a block, two levels of
refinement about the contact (hanging nodes in the band's cells)."""

import gc
import weakref

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.contact import ellipse
from ibfem.solver.contact.driver import ContactDriver
from ibfem.solver.fem.step_boundary import BoundaryPoints, thin_band_terms
from ibfem.solver.model import problem as pb
from ibfem.solver.model.resolve import resolve_problem

from _solids3d import HalfBall
from _turned_box import TurnedBox

E, NU = 2.0e11, 0.3


@pytest.fixture(scope="module")
def contact():
    ball = HalfBall([0, 0, 1.0], 1.0)
    block = TurnedBox([2, 2, 1], shift=(-1, -1, -1))
    steel = pb.Material("steel", E, NU)
    zone = (pb.Refinement(2, 0.3),)
    bodies = (pb.BodyModel("ball", ball, steel, 0.25, zone), pb.BodyModel("block", block, steel, 0.25, zone))
    bcs = (pb.Displacement("ball", "flat", (2e-4, 0.0, -0.002)), pb.Fixed("block", "z0"))
    model = pb.ContactModel(("ball", "block"), "frictional", friction=0.3, point=np.zeros(3))
    driver = ContactDriver(resolve_problem(pb.Problem("pair_blocks", "solid", 1.0, bodies, bcs, (model,))))
    driver._discretise()
    driver._assemble()
    c = driver.contacts[0]
    c.stick_ratio, c.slip_direction = 0.7, np.array([1.0, 0.0, 0.0])
    return c


def _sparse_terms(c, a):
    """The band's stiffness and load by sparse products of (3q x m) operators, Coulomb's block on
    the slip zone included."""
    pts = c.region_quadrature(a)
    jump, flux, size = ellipse.contact_operators(c, pts)
    bp = BoundaryPoints(pts.x1, pts.weights, pts.normal, size, jump, flux)
    proj = ellipse._projector(c, pts, a)
    k, f = thin_band_terms(bp, proj, -pts.delta, c.b1.lam, c.b1.mu, c.band_fraction, 1.0, jump=jump)
    r, b = ellipse.pressure_rows(c, (pts, bp, proj, jump, flux, size, a))
    g = ellipse.point_blocks(np.broadcast_to(-c.friction * c.slip_direction, pts.x1.shape)) @ jump
    wq = np.where(ellipse._slip_mask(c, pts, a), pts.weights, 0.0)
    assert wq.any()
    return (k - g.T @ sp.csr_matrix(r.multiply(wq[:, None]))).tocsr(), f + g.T @ (wq * b), (jump, flux)


def test_pair_sums_equal_the_sparse_products(contact):
    a = 0.06
    kc, fc, info = contact.terms(a)
    k_ref, f_ref, (jump, flux) = _sparse_terms(contact, a)
    assert abs(kc - k_ref).max() <= 1e-12 * abs(k_ref).max()
    np.testing.assert_allclose(fc, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
    x = np.random.default_rng(3).standard_normal(kc.shape[0])
    for op, ref in ((info[3], jump), (info[4], flux)):
        np.testing.assert_allclose(op @ x, ref @ x, rtol=0, atol=1e-12 * np.abs(ref @ x).max())
        assert abs(op.tocsr() - ref).max() <= 1e-12 * abs(ref).max()


def test_a_common_translation_has_no_contact_stiffness(contact):
    kc, _, _ = contact.terms(0.06)
    scale = abs(kc).max() * np.sqrt(kc.shape[0])
    for k in range(3):
        t = (contact.dofs % 3 == k).astype(float)  # every node of both bodies moved along axis k
        assert np.abs(kc @ t).max() <= 1e-10 * scale


def test_a_region_kept_across_a_stick_update_gives_the_terms_built_anew(contact):
    # the quadrature and blocks of a region do not depend on the stick zone: the search after a
    # stick-ratio update reuses them, and the terms equal those built from nothing
    c, a = contact, 0.05
    _, _, first = c.terms(a)
    c.stick_ratio = 0.5
    try:
        k_kept, f_kept, kept = c.terms(a)
        assert kept[0] is first[0]  # the same points: reused
        c._recent_regions = None
        k_new, f_new, new = c.terms(a)
        assert new[0] is not first[0]
        assert abs(k_kept - k_new).max() == 0.0 and np.array_equal(f_kept, f_new)
    finally:
        c.stick_ratio = 0.7


def test_the_blocks_are_freed_without_a_garbage_collection(contact):
    # the blocks hold no reference to their operators: nothing but a collection would free a
    # cycle, and the trials of a large contact would pile up their arrays until one ran
    gc.disable()
    try:
        contact._recent_regions = None
        _, _, info = contact.terms(0.05)
        ref = weakref.ref(info[3].blocks)
        del info
        contact._recent_regions = None
        assert ref() is None
    finally:
        gc.enable()


def test_pressure_rows_of_a_trial_state(contact):
    # the pressure's affine rows (read by the friction history) from a trial's operators equal the
    # pressure the trial's traction gives
    a = 0.05
    _, _, info = contact.terms(a)
    r, b = ellipse.pressure_rows(contact, info)
    x = np.random.default_rng(5).standard_normal(r.shape[1]) * 1e-4
    saved, contact.slip_direction = contact.slip_direction, None  # the normal traction alone
    try:
        p = np.einsum("qi,qi->q", contact.quadrature_traction(info, x), info[0].normal)
    finally:
        contact.slip_direction = saved
    np.testing.assert_allclose(r @ x + b, p, rtol=0, atol=1e-10 * np.abs(p).max())


def _assert_terms_equal_the_sparse_products(contact, a: float) -> None:
    contact._recent_regions = None
    kc, fc, _ = contact.terms(a)
    k_ref, f_ref, _ = _sparse_terms(contact, a)
    assert abs(kc - k_ref).max() <= 1e-12 * abs(k_ref).max()
    np.testing.assert_allclose(fc, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())


def test_pair_sums_on_two_threads_equal_the_sparse_products(contact, monkeypatch):
    # the pairs split into two ranges summed side by side (as where a core is free)
    from ibfem.solver.fem import linalg, pair_blocks

    monkeypatch.setattr(pair_blocks, "THREADED_POINTS", 0)
    monkeypatch.setattr(pair_blocks, "compiled", lambda: True)
    monkeypatch.setattr(linalg, "free_threads", lambda sample=None: 2)
    _assert_terms_equal_the_sparse_products(contact, 0.06)


@pytest.mark.parametrize("with_kernels", [True, False])
def test_both_routes_equal_the_sparse_products(contact, monkeypatch, with_kernels):
    # the compiled kernels (runs that loaded numba) and the NumPy route (small runs on SuperLU)
    from ibfem.solver.fem import pair_blocks

    if with_kernels:
        import numba  # noqa: F401  (the kernels are used where numba is loaded)
    monkeypatch.setattr(pair_blocks, "compiled", lambda: with_kernels)
    _assert_terms_equal_the_sparse_products(contact, 0.06)


@pytest.mark.parametrize("chunk", [1, 40])
def test_the_numpy_route_in_short_passes_equals_the_sparse_products(contact, monkeypatch, chunk):
    # the NumPy route sums a few pairs per pass (1: every pair alone, each longer than a pass) and
    # gathers the flux blocks a few points at a time
    from ibfem.solver.fem import pair_blocks

    monkeypatch.setattr(pair_blocks, "compiled", lambda: False)
    monkeypatch.setattr(pair_blocks, "BAND_CHUNK_POINTS", chunk)
    monkeypatch.setattr(pair_blocks, "GATHER_POINTS", 7)
    contact._recent_regions = None
    _assert_terms_equal_the_sparse_products(contact, 0.06)


def test_runs_cover_every_pair_once():
    from ibfem.solver.fem.pair_blocks import _runs

    bounds = np.array([0, 3, 4, 10, 11, 12, 30])
    for points in (1, 2, 5, 8, 100):
        runs = list(_runs(bounds, points))
        assert runs[0][0] == 0 and runs[-1][1] == len(bounds) - 1
        assert all(b[0] == a[1] and a[1] > a[0] for a, b in zip(runs, runs[1:]))
        # each pass holds at most ``points`` points unless it is one pair
        assert all(last - first == 1 or bounds[last] - bounds[first] <= points for first, last in runs)


def test_an_older_region_releases_its_flux_blocks_and_builds_the_same_again(contact):
    # only a contact's latest region keeps its flux blocks (most of a trial's memory); an older
    # region asked for its flux builds them again: the same numbers
    contact._recent_regions = None
    _, _, first = contact.terms(0.05)
    x = np.random.default_rng(4).standard_normal(len(contact.dofs))
    flux = first[4] @ x
    traction = first[4].blocks.traction.copy()
    _, _, second = contact.terms(0.06)
    assert first[4].blocks._traction is None and second[4].blocks._traction is not None
    np.testing.assert_array_equal(first[4] @ x, flux)
    np.testing.assert_array_equal(first[4].blocks.traction, traction)
    assert second[4].blocks._traction is None  # the older one is the latest user now
    contact._recent_regions = None
