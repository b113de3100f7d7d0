"""The half-space reference (solver.reference.halfspace): Boussinesq's rectangle integral against
Love's closed form for the centre of a uniformly loaded square and against a midpoint quadrature,
and the contact of a sphere on a flat against Hertz (Johnson, Contact Mechanics, eqs. 4.22-4.23)."""

import numpy as np
import pytest

from ibfem.solver.reference.halfspace import halfspace_contact, rectangle_integral
from ibfem.solver.reference.theory import hertz_sphere_radius


def test_uniformly_loaded_square_centre_and_corner():
    # int int over [-a, a]^2 of dA / r at the centre: 8 a ln(1 + sqrt 2) (Love 1929; Johnson 3.2:
    # the centre deflection 2.24 p a (1 - nu^2) / E); at a corner: 4 a ln(1 + sqrt 2)
    a = 0.3
    centre = rectangle_integral(np.array(0.0), np.array(0.0), -a, a, -a, a)
    corner = rectangle_integral(np.array(a), np.array(a), -a, a, -a, a)
    assert float(centre) == pytest.approx(8 * a * np.log(1 + np.sqrt(2)), rel=1e-12)
    assert float(corner) == pytest.approx(4 * a * np.log(1 + np.sqrt(2)), rel=1e-12)


def test_rectangle_integral_matches_a_quadrature_away_from_it():
    x, y = np.array([1.3, -0.7]), np.array([0.4, 2.1])
    t = (np.arange(400) + 0.5) / 400
    xs, ys = np.meshgrid(-0.2 + 0.5 * t, 0.1 + 0.3 * t, indexing="ij")
    quad = [(0.5 * 0.3 / 400**2 / np.hypot(xi - xs, yi - ys)).sum() for xi, yi in zip(x, y)]
    np.testing.assert_allclose(rectangle_integral(x, y, -0.2, 0.3, 0.1, 0.4), quad, rtol=1e-6)


def test_sphere_on_flat_against_hertz():
    R, e_star, force = 1.0, 1.0989e11, 1.0e6
    a = hertz_sphere_radius(force, R, e_star)
    x = np.linspace(-1.3 * a, 1.3 * a, 31)
    result = halfspace_contact(lambda X, Y: (X**2 + Y**2) / (2 * R), x, x, e_star, force=force)
    assert result.force == pytest.approx(force, rel=1e-10)
    assert np.sqrt(result.area / np.pi) == pytest.approx(a, rel=0.01)  # measured +0.33 %
    p0 = 3 * force / (2 * np.pi * a**2)
    assert result.pressure.max() == pytest.approx(p0, rel=0.01)  # measured +0.03 %
    assert result.approach == pytest.approx(a**2 / R, rel=0.01)  # Hertz's approach delta = a^2 / R


def test_quarter_grid_with_mirror_images_is_the_full_grid():
    """A gap even in x and y: the quarter x, y > 0 with its three mirror images per rectangle
    gives the full grid's pressures (symmetry), and Hertz's sphere within 3 % on this coarse grid."""
    R, e_star, force = 1.0, 1.0989e11, 1.0e6
    a = hertz_sphere_radius(force, R, e_star)
    x = np.linspace(-1.3 * a, 1.3 * a, 20)  # an even count: no centre on the axes
    gap = lambda X, Y: (X**2 + Y**2) / (2 * R)  # noqa: E731
    full = halfspace_contact(gap, x, x, e_star, force=force)
    quarter = halfspace_contact(gap, x[10:], x[10:], e_star, force=force / 4, symmetric=True)
    np.testing.assert_allclose(quarter.pressure, full.pressure[10:, 10:], rtol=1e-9, atol=1e-9 * full.pressure.max())
    assert quarter.approach == pytest.approx(full.approach, rel=1e-9)
    assert np.sqrt(4 * quarter.area / np.pi) == pytest.approx(a, rel=0.03)


def test_half_grid_with_mirror_images_is_the_full_grid_for_a_tilted_gap():
    """A gap even in y only (a sphere on a plane tilted about the y axis, which moves the contact
    along x): the half y > 0 with each rectangle's image (x, -y) gives the full grid's pressures."""
    R, e_star, force = 1.0, 1.0989e11, 1.0e6
    a = hertz_sphere_radius(force, R, e_star)
    x = np.linspace(-1.3 * a, 1.3 * a, 20)
    gap = lambda X, Y: (X**2 + Y**2) / (2 * R) + 0.2 * a / R * X  # noqa: E731
    full = halfspace_contact(gap, x, x, e_star, force=force)
    half = halfspace_contact(gap, x, x[10:], e_star, force=force / 2, symmetric="y")
    np.testing.assert_allclose(half.pressure, full.pressure[:, 10:], rtol=1e-9, atol=1e-9 * full.pressure.max())
    assert half.approach == pytest.approx(full.approach, rel=1e-9)
    with pytest.raises(ValueError, match="symmetric"):
        halfspace_contact(gap, x, x, e_star, force=force, symmetric="x")
