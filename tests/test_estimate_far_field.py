"""The far field's share of a 3D normal force estimate (solver.model.accuracy): the energy density
of known stresses and the force error an energy error causes."""

import math

import numpy as np
import pytest

from ibfem.solver.model.accuracy import complementary_energy_density, far_field_force_error

E, NU = 2.0e11, 0.3


def test_energy_density_of_uniaxial_stress_shear_and_pressure():
    s = 1.0e8
    uniaxial = np.array([[s, 0, 0, 0, 0, 0], [0, 0, s, 0, 0, 0]], dtype=float)
    assert complementary_energy_density(uniaxial, E, NU) == pytest.approx(s ** 2 / E, rel=1e-14)
    shear = np.array([[0, 0, 0, s, 0, 0], [0, 0, 0, 0, 0, s]], dtype=float)
    assert complementary_energy_density(shear, E, NU) == pytest.approx(s ** 2 / (E / (2 * (1 + NU))), rel=1e-14)
    pressure = np.array([[-s, -s, -s, 0, 0, 0]], dtype=float)  # bulk modulus K = E / (3 (1 - 2 nu))
    assert complementary_energy_density(pressure, E, NU) == pytest.approx(s ** 2 / (E / (3 * (1 - 2 * NU))), rel=1e-14)
    # invariant under a rotation of the axes
    rng = np.random.default_rng(3)
    a = rng.normal(size=(3, 3))
    sym = a + a.T
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    turned = q @ sym @ q.T
    voigt = lambda m: np.array([[m[0, 0], m[1, 1], m[2, 2], m[1, 2], m[0, 2], m[0, 1]]])
    assert complementary_energy_density(voigt(turned), E, NU) == pytest.approx(
        complementary_energy_density(voigt(sym), E, NU), rel=1e-12)


@pytest.mark.parametrize("m", [1.0, 1.5])
def test_force_error_of_a_uniformly_stiffer_response(m):
    # N = k delta^m and the discrete response stiffer by (1 + eps): U = k delta^(m+1) / (m + 1),
    # U_h - U = eps U = ||e||^2 / 2, and the force's relative error is (N_h - N) / N_h = eps / (1 + eps)
    k, delta, eps = 3.0e9, 2.0e-3, 0.0123
    energy = k * delta ** (m + 1) / (m + 1)
    got = far_field_force_error(2.0 * eps * energy, (1.0 + eps) * energy)
    assert got == pytest.approx(eps / (1.0 + eps), rel=1e-12)
    assert math.isnan(far_field_force_error(1.0, 0.0))


def test_far_field_energy_of_a_constant_stress_patch():
    # a turned box under a uniform stress (sliding faces through one corner, tractions sigma n on
    # the others): the recovered stress equals the discrete one (no error energy) and the strain
    # energy is (sigma : C^-1 : sigma) V / 2, with V the box's volume
    from _turned_box import uniform_stress_box

    from ibfem.solver.solving import far_field_energy, solve

    rng = np.random.default_rng(5)
    h = 0.25
    problem, box, sigma = uniform_stress_box(rng, E, NU, h)
    sol = solve(problem.with_options(grid_offset=tuple(rng.uniform(0, h, 3))))
    voigt = sigma[[0, 1, 2, 1, 0, 0], [0, 1, 2, 2, 2, 1]][None, :]
    exact = 0.5 * complementary_energy_density(voigt, E, NU)[0] * 0.48
    error, energy = far_field_energy(sol, box.to_world(np.zeros(3)), 0.0)
    assert error <= 1e-12 * energy
    assert energy == pytest.approx(exact, rel=1e-10)  # measured 3e-15
