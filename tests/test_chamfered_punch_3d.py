"""The axisymmetric flat punch with a conical chamfer (solver/reference/chamfered_punch_3d.py): its
closed form against the cone (b = 0), equilibrium, an adaptive quadrature of the same integral and
Boussinesq's influence coefficients on the same gap (solver/reference/halfspace.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from ibfem.solver.reference.chamfered_punch_3d import (chamfered_punch_3d_approach, chamfered_punch_3d_load,
                                                       chamfered_punch_3d_pressure, chamfered_punch_3d_radius)


def test_without_a_flat_it_is_the_cone():
    """b = 0: P = pi E* k a^2 / 2, d = pi k a / 2, p = (E* k / 2) arccosh(a / r) (Johnson eq. 5.25
    with cot alpha = k)."""
    a, k, e_star = 0.03, 0.05, 1.2e11
    assert chamfered_punch_3d_load(a, 0.0, k, e_star) == pytest.approx(math.pi * e_star * k * a * a / 2, rel=1e-12)
    assert chamfered_punch_3d_approach(a, 0.0, k) == pytest.approx(math.pi * k * a / 2, rel=1e-12)
    r = np.linspace(0.05, 0.95, 10) * a
    np.testing.assert_allclose(chamfered_punch_3d_pressure(r, a, 0.0, k, e_star), 0.5 * e_star * k * np.arccosh(a / r),
                               rtol=1e-6)


def test_pressure_balances_the_load_and_matches_an_adaptive_quadrature():
    a, b, k, e_star = 0.05, 0.04, 0.08, 1.6e11
    load = chamfered_punch_3d_load(a, b, k, e_star)
    assert chamfered_punch_3d_radius(load, b, k, e_star) == pytest.approx(a, rel=1e-10)

    def adaptive(ri):
        kernel = lambda t: (math.acos(b / t) + b / math.sqrt(t * t - b * b)) / math.sqrt(t * t - ri * ri)
        lo = max(ri, b)
        return e_star * k / math.pi * quad(kernel, lo, a, limit=400, points=[0.5 * (lo + a)])[0]

    for ri in (0.0, 0.02, 0.035, 0.042, 0.048):
        assert chamfered_punch_3d_pressure(np.array([ri]), a, b, k, e_star)[0] == pytest.approx(adaptive(ri), rel=1e-5)
    # 2 pi int p r dr = P: Gauss-Legendre clustered at both ends of each piece (p is infinite at b)
    v, w = np.polynomial.legendre.leggauss(400)
    total = 0.0
    for lo, hi in ((0.0, b), (b, a)):
        r = lo + 0.5 * (hi - lo) * (1.0 - np.cos(0.5 * math.pi * (v + 1.0)))
        jac = 0.25 * (hi - lo) * math.pi * np.sin(0.5 * math.pi * (v + 1.0))
        total += 2 * math.pi * float(np.sum(w * jac * r * chamfered_punch_3d_pressure(r, a, b, k, e_star)))
    assert total == pytest.approx(load, rel=1e-3)


def test_closed_form_against_the_half_space_influence_coefficients():
    """The same gap k max(r - b, 0) on Boussinesq's influence coefficients (0.5 mm squares, the
    quarter): the contact radius within a square and the pressure's means over rings within 3 %
    of the closed form's peak of the rings, away from the edge's logarithmic peak."""
    from ibfem.solver.reference.halfspace import halfspace_contact

    b, k, e_star = 0.01, 0.08, 1.6e11
    a = 0.0125
    load = chamfered_punch_3d_load(a, b, k, e_star)
    dx = 0.0005
    x = np.arange(dx / 2, 0.016, dx)
    ref = halfspace_contact(lambda X, Y: k * np.clip(np.hypot(X, Y) - b, 0.0, None), x, x, e_star, force=load / 4,
                            symmetric=True)
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    edge = r[ref.pressure > 0].max()
    assert edge == pytest.approx(a, abs=1.5 * dx)
    rings = np.arange(0.0, a, 0.001)
    closed = chamfered_punch_3d_pressure(r.ravel(), a, b, k, e_star).reshape(r.shape)
    means = []
    for lo in rings:
        m = (r >= lo) & (r < lo + 0.001) & (np.abs(r - b) > 0.001)
        if m.any():
            means.append((ref.pressure[m].mean(), closed[m].mean()))
    means = np.array(means)
    assert np.abs(means[:, 0] - means[:, 1]).max() < 0.03 * means[:, 1].max()


SCENE = Path(__file__).resolve().parent / "scenes" / "chamfered_punch.toml"
E_STAR = 1.0 / ((1 - 0.24**2) / 6.2e11 + (1 - 0.3**2) / 2.0e11)  # carbide on steel
FLAT, SLOPE = 0.04, 0.08


@pytest.mark.slow
def test_chamfered_punch_across_an_angled_edge():
    """The scene (6.25 mm cells; the region crosses the edge where the flat face meets the chamfer
    at 4.6 degrees) against the closed form at the computed force: converged, the contact radius
    (both principal extents and the area's equivalent radius) within 2 % (measured +1.4 %), and
    the map within 8 % of the closed form's largest mean (RMS over the merged squares against the
    closed form's means over their parts in the region; measured 6 %: the closed form is
    logarithmically infinite at r = b, which a cell's mean cannot follow)."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    sol = solve(load_scene(SCENE).problem)
    assert sol.converged, sol.iterations["messages"]
    c = sol.contacts[0]
    a = chamfered_punch_3d_radius(4.0 * c["normal_force"], FLAT, SLOPE, E_STAR)
    for extent in c["extents"]:
        assert extent == pytest.approx(a, rel=0.02)
    assert math.sqrt(4.0 * c["area"] / math.pi) == pytest.approx(a, rel=0.02)
    m = c["pressure_map"]
    value, area = np.array(m["value"]), np.array(m["area"])
    u = (np.arange(12) + 0.5) / 12
    sub = np.stack(np.meshgrid(u, u, indexing="ij"), -1).reshape(-1, 2)
    radius = float(np.mean(c["semi_axes"]))
    ref = []
    for keys in m["merged"]:
        pts = ((np.asarray(keys, dtype=float)[:, None, :] + sub[None]) * m["cell"]).reshape(-1, 2)
        r = np.hypot(pts[:, 0], pts[:, 1])
        ref.append(float(chamfered_punch_3d_pressure(r[r < radius], a, FLAT, SLOPE, E_STAR).mean()))
    ref = np.array(ref)
    rms = math.sqrt(float(area @ (value - ref) ** 2 / area.sum())) / ref.max()
    print(f"radius {c['extents']} against {a}; map RMS over the largest reference mean {100 * rms:.2f} %")
    assert rms < 0.08
