"""The step function, its band integrals, and the thin-band boundary operators."""

import numpy as np
import scipy.sparse as sp

from ibfem.solver.fem.integration import gauss_legendre
from ibfem.solver.fem.step_boundary import (
    BoundaryPoints,
    acoustic_tensor,
    band_integrals,
    projector,
    step_derivative,
    step_function,
    thin_band_terms,
    thin_band_traction,
)


def test_step_function_shape():
    d = 0.3
    phi = np.array([-1.0, 0.0, 0.1, 0.3, 2.0])
    h = step_function(phi, d)
    assert np.allclose(h, [0.0, 0.0, (1 / 3) * (2 - 1 / 3), 1.0, 1.0])
    # derivative by finite differences inside the band, zero slope where it meets 1
    x = np.linspace(0.01, 0.29, 15)
    fd = (step_function(x + 1e-7, d) - step_function(x - 1e-7, d)) / 2e-7
    assert np.allclose(step_derivative(x, d), fd, rtol=1e-6)
    assert step_derivative(np.array([d]), d)[0] == 0.0


def test_band_integrals_against_quadrature():
    # the closed forms behind the thin-band limit, checked by Gauss quadrature across the band
    d = 0.37
    x, w = gauss_legendre(6)
    phi, wt = 0.5 * d * (x + 1), 0.5 * d * w
    H, dH = step_function(phi, d), step_derivative(phi, d)
    ref = band_integrals(d)
    assert np.isclose(np.sum(wt * H * H), ref["H2"])
    assert np.isclose(np.sum(wt * H * dH), ref["HdH"])
    assert np.isclose(np.sum(wt * dH * dH), ref["dH2"])


def test_band_energy_of_a_bar_equals_its_thin_band_form():
    # 1D bar, u = H u_h + (1 - H) a with u_h linear: the exact band energy across [0, delta]
    # equals C [8 delta/15 e^2 + e w + 4/(3 delta) w^2] with e = u_h' and w = u_h - a taken
    # constant across the band (the thin-band assumption)
    C, d, e, w = 2.5, 1e-3, 0.7, 0.2
    x, wt = gauss_legendre(8)
    phi, wt = 0.5 * d * (x + 1), 0.5 * d * wt
    H, dH = step_function(phi, d), step_derivative(phi, d)
    strain = H * e + dH * w  # d/dphi of H (u_h - a) + a, with u_h - a = w + e phi ~ w
    exact = np.sum(wt * C * strain**2)
    thin = C * (8 * d / 15 * e**2 + e * w + 4 / (3 * d) * w**2)
    assert np.isclose(exact, thin, rtol=1e-12)


def _points(q, normals):
    # one dof per point component: displacement operator = identity, traction operator given
    rng = np.random.default_rng(4)
    eu = sp.identity(2 * q, format="csr")
    et = sp.csr_matrix(rng.normal(size=(2 * q, 2 * q)))
    return BoundaryPoints(
        points=np.zeros((q, 2)), weights=rng.uniform(0.5, 1.0, q), normals=normals,
        cell_size=np.full(q, 0.1), displacement_matrix=eu, traction_matrix=et,
    )


def test_sliding_terms_act_on_the_normal_component_only():
    q = 6
    ang = np.linspace(0, 2, q)
    n = np.column_stack([np.cos(ang), np.sin(ang)])
    bp = _points(q, n)
    lam, mu = 3.0, 1.0
    proj = projector("sliding", n)
    k, f = thin_band_terms(bp, proj, 0.01 * n, lam, mu, 0.25, consistency=1.0)
    assert abs(k - k.T).max() < 1e-12  # symmetric Nitsche form
    tangential = np.column_stack([-n[:, 1], n[:, 0]]).ravel()
    # with the consistency terms off only the layer is left: no stiffness against tangential
    # motion, (4/(3 delta)) (lambda + 2 mu) w against normal motion
    k0, _ = thin_band_terms(bp, proj, 0.01 * n, lam, mu, 0.25, consistency=0.0)
    assert abs(tangential @ (k0 @ tangential)) < 1e-12
    normal = n.ravel()
    assert np.isclose(normal @ (k0 @ normal), (4 / 3) / 0.025 * (lam + 2 * mu) * bp.weights.sum())
    # layer traction of a pure normal gap g: -(4/(3 delta)) (lambda + 2 mu) g n, consistency off
    u = (0.01 * n).ravel() + 0.003 * n.ravel()
    tr = thin_band_traction(bp, proj, 0.01 * n, lam, mu, u, 0.25, consistency=0.0)
    assert np.allclose(tr, -(4 / 3) / 0.025 * (lam + 2 * mu) * 0.003 * n)


def test_acoustic_tensor():
    n = np.array([[0.6, 0.8]])
    a = acoustic_tensor(n, 2.0, 0.5)[0]
    t = np.array([-0.8, 0.6])
    assert np.isclose(n[0] @ a @ n[0], 2.0 + 2 * 0.5)
    assert np.isclose(t @ a @ t, 0.5) and np.isclose(t @ a @ n[0], 0.0)


def test_points_on_a_body_give_the_same_operators_as_its_edge_quadrature():
    from ibfem.geometry.shapes import profile_from_shape
    from ibfem.solver.fem.bodies import discretise
    from ibfem.solver.model.options import SolverOptions as Settings
    from ibfem.solver.model.problem import BodyModel, Material, Problem

    prof = profile_from_shape({"type": "disk", "center": [0, 0], "radius": 1.0})
    prob = Problem("d", "plane_strain", 1.0, (BodyModel("d", prof, Material("s", 1.0, 0.3), 0.2),))
    (body,) = discretise(prob, Settings())
    edge = body.edge_points("boundary", 3)
    again = body.points_on(edge.points, edge.weights, edge.normals)
    u = np.random.default_rng(0).normal(size=body.n_total)
    assert np.allclose(edge.displacement @ u, again.displacement @ u)
    assert np.allclose(edge.traction @ u, again.traction @ u)
    # an edge on a grid line: points go to the cells on the material side, as the edge's own
    sq = profile_from_shape({"type": "rectangle", "min": [0, 0], "max": [1, 1]})
    (plate,) = discretise(Problem("s", "plane_strain", 1.0, (BodyModel("p", sq, Material("s", 1.0, 0.3), 0.25),)), Settings())
    u = np.random.default_rng(1).normal(size=plate.n_total)
    for name in ("bottom", "right", "top", "left"):
        edge = plate.edge_points(name, 2)
        again = plate.points_on(edge.points, edge.weights, edge.normals)
        assert np.allclose(edge.traction @ u, again.traction @ u)
