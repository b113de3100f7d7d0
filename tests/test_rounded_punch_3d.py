"""The axisymmetric flat punch with a rounded edge: the closed form (solver/reference/
rounded_punch_3d.py) against its limits (Hertz's sphere for b = 0, Boussinesq's flat punch as the
edge radius vanishes), equilibrium, and an adaptive quadrature of the same integral; the 3D solver
on examples/contact3d/rounded_punch.toml against the closed form (slow)."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import quad

from ibfem.solver.reference.rounded_punch_3d import (rounded_punch_3d_approach, rounded_punch_3d_load,
                                                     rounded_punch_3d_pressure, rounded_punch_3d_radius)

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "contact3d" / "rounded_punch.toml"


def test_without_a_flat_it_is_hertz_sphere():
    """b = 0: P = 4 E* a^3 / (3 R), p = (2 E* / (pi R)) sqrt(a^2 - r^2), d = a^2 / R (Johnson
    eqs. 4.22-4.23 with 1 / R the relative curvature)."""
    a, radius, e_star = 0.02, 0.5, 1.1e11
    assert rounded_punch_3d_load(a, 0.0, radius, e_star) == pytest.approx(4 * e_star * a**3 / (3 * radius), rel=1e-12)
    assert rounded_punch_3d_approach(a, 0.0, radius) == pytest.approx(a * a / radius, rel=1e-12)
    r = np.linspace(0.0, 0.999 * a, 40)
    hertz = 2 * e_star / (math.pi * radius) * np.sqrt(a * a - r * r)
    np.testing.assert_allclose(rounded_punch_3d_pressure(r, a, 0.0, radius, e_star), hertz, rtol=1e-9)


def test_pressure_balances_the_load_and_matches_an_adaptive_quadrature():
    """2 pi int p r dr = P (the load from its own closed form), and p(r) against scipy's adaptive
    quadrature of the same integral, on both sides of the flat's edge r = b."""
    a, b, radius, e_star = 0.06, 0.04, 0.25, 1.6e11
    load = rounded_punch_3d_load(a, b, radius, e_star)
    v, w = np.polynomial.legendre.leggauss(200)
    total = 0.0
    for lo, hi in ((0.0, b), (b, a)):  # points clustered at both ends of each piece (p' is singular at b)
        r = lo + 0.5 * (hi - lo) * (1.0 - np.cos(0.5 * math.pi * (v + 1.0)))
        jac = 0.25 * (hi - lo) * math.pi * np.sin(0.5 * math.pi * (v + 1.0))
        total += 2 * math.pi * float(np.sum(w * jac * r * rounded_punch_3d_pressure(r, a, b, radius, e_star)))
    assert total == pytest.approx(load, rel=1e-6)

    def adaptive(ri):
        kernel = lambda t: (2 * math.sqrt(t * t - b * b) - b * math.acos(b / t)) / math.sqrt(t * t - ri * ri)
        return e_star / (math.pi * radius) * quad(kernel, max(ri, b), a, limit=200)[0]

    for ri in (0.0, 0.02, 0.039, 0.04, 0.045, 0.059):
        assert rounded_punch_3d_pressure(np.array([ri]), a, b, radius, e_star)[0] == pytest.approx(adaptive(ri), rel=1e-8)
    assert rounded_punch_3d_pressure(np.array([a, 1.1 * a]), a, b, radius, e_star).tolist() == [0.0, 0.0]


def test_small_edge_radius_tends_to_the_sharp_flat_punch():
    """R -> 0: a -> b and p -> P / (2 pi b sqrt(b^2 - r^2)), the rigid flat punch (Boussinesq; Johnson
    eq. 3.36), whose approach is d = P / (2 E* b)."""
    b, radius, e_star, load = 0.04, 1e-5, 1.6e11, 4e7
    a = rounded_punch_3d_radius(load, b, radius, e_star)
    assert rounded_punch_3d_load(a, b, radius, e_star) == pytest.approx(load, rel=1e-10)
    assert a == pytest.approx(b, rel=2e-3)
    r = np.array([0.0, 0.2, 0.5, 0.8]) * b
    sharp = load / (2 * math.pi * b * np.sqrt(b * b - r * r))
    np.testing.assert_allclose(rounded_punch_3d_pressure(r, a, b, radius, e_star), sharp, rtol=5e-3)
    assert rounded_punch_3d_approach(a, b, radius) == pytest.approx(load / (2 * e_star * b), rel=5e-3)


def test_bad_input_is_refused_with_the_values():
    with pytest.raises(ValueError, match="0 <= b <= a"):
        rounded_punch_3d_load(0.01, 0.02, 0.1, 1e11)
    with pytest.raises(ValueError, match="load must be positive"):
        rounded_punch_3d_radius(-1.0, 0.02, 0.1, 1e11)


def test_flat_surfaces_take_the_region_of_general_shape():
    """Both relative curvatures 0 at the contact point (a flat punch on a flat) is a flat contact,
    which the star-shaped region takes with equal scales; a slight curvature is not."""
    from ibfem.solver.contact.ellipse import is_flat_contact, is_line_contact

    flat = SimpleNamespace(curvatures=np.array([1e-9, 3e-9]))
    assert is_flat_contact(flat, 0.07) and not is_line_contact(flat)
    assert not is_flat_contact(SimpleNamespace(curvatures=np.array([0.0, 0.1])), 0.07)
    assert not is_flat_contact(SimpleNamespace(curvatures=np.array([0.5, 1.0])), 0.07)


E_STAR = 1.0 / ((1 - 0.24**2) / 6.2e11 + (1 - 0.3**2) / 2.0e11)  # carbide on steel
FLAT, EDGE = 0.04, 0.25


def _cell_means_of(pressure, s: np.ndarray, cell: float, radius: float) -> np.ndarray:
    """The mean of a pressure p(r) over the part r < radius of each square [k cell, (k + 1) cell)
    holding the points s (12 x 12 points per square)."""
    key = np.floor(s / cell + 1e-6)
    u = (np.arange(12) + 0.5) / 12
    sub = (key[:, None, None, :] + np.stack(np.meshgrid(u, u, indexing="ij"), -1)[None]) * cell
    r = np.hypot(sub[..., 0], sub[..., 1]).reshape(len(s), -1)
    inside = r < radius
    return np.where(inside, pressure(r.ravel()).reshape(r.shape), 0.0).sum(axis=1) / np.maximum(inside.sum(axis=1), 1)


def _group_means_of(pressure, merged: list, cell: float, radius: float) -> np.ndarray:
    """The mean of a pressure p(r) over the part r < radius of each group of squares (the map's
    merged squares; 12 x 12 points per square)."""
    out = []
    u = (np.arange(12) + 0.5) / 12
    sub = np.stack(np.meshgrid(u, u, indexing="ij"), -1).reshape(-1, 2)
    for keys in merged:
        pts = ((np.asarray(keys, dtype=float)[:, None, :] + sub[None]) * cell).reshape(-1, 2)
        r = np.hypot(pts[:, 0], pts[:, 1])
        inside = r < radius
        out.append(float(pressure(r[inside]).mean()) if inside.any() else 0.0)
    return np.array(out)


@pytest.mark.slow
def test_rounded_punch_against_the_closed_form():
    """The example (6.25 mm cells): the contact radius within 1 % of the closed form's at the
    computed force (both principal extents and the area's equivalent radius), the region round
    (its knots' rho within 1 % of their mean: the punch is axisymmetric), the pressure's cell
    mean at the centre within 1 % of the closed form's mean over the same square, and the whole
    map (its merged squares) within 3 % of the closed form's peak (RMS weighted by the region's
    area in each group) of the closed form's means over the same squares' parts in the region."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    sol = solve(load_scene(EXAMPLE).problem)
    assert sol.converged, sol.iterations["messages"]
    c = sol.contacts[0]
    assert c["region_shape"] == "star-shaped (flat contact)"
    load = 4.0 * c["normal_force"]  # the quarter model's share
    a = rounded_punch_3d_radius(load, FLAT, EDGE, E_STAR)
    for extent in c["extents"]:
        assert extent == pytest.approx(a, rel=0.01)
    assert math.sqrt(4.0 * c["area"] / math.pi) == pytest.approx(a, rel=0.01)
    rho = np.array(c["knots"]["rho"])[np.array(c["knots"]["inside"])]
    assert float(np.abs(rho / rho.mean() - 1.0).max()) < 0.01
    m = c["pressure_map"]
    s, value = np.array(m["s"]), np.array(m["value"])
    centre = int(np.argmin(np.hypot(s[:, 0], s[:, 1])))
    ref = _cell_means_of(lambda r: rounded_punch_3d_pressure(r, a, FLAT, EDGE, E_STAR), s[centre:centre + 1],
                         m["cell"], float(np.mean(c["semi_axes"])))
    assert value[centre] == pytest.approx(ref[0], rel=0.01)
    pressure = lambda r: rounded_punch_3d_pressure(r, a, FLAT, EDGE, E_STAR)
    ref = _group_means_of(pressure, m["merged"], m["cell"], float(np.mean(c["semi_axes"])))
    area = np.array(m["area"])
    peak = float(pressure(np.linspace(0.0, a, 2001)).max())
    rms = math.sqrt(float(area @ (value - ref) ** 2 / area.sum())) / peak
    print(f"radius {a:.5f} m: extents {[f'{100 * (e / a - 1):+.2f} %' for e in c['extents']]}, area's equivalent "
          f"{100 * (math.sqrt(4.0 * c['area'] / math.pi) / a - 1):+.2f} %; knots' rho within "
          f"{100 * float(np.abs(rho / rho.mean() - 1.0).max()):.2f} %; centre {value[centre] / 1e9:.4f} GPa; largest "
          f"{value.max() / 1e9:.3f} GPa; pressure RMS over the closed form's peak: {100 * rms:.2f} %")
    assert rms < 0.03


@pytest.mark.slow
def test_turned_rounded_punch_gives_the_same_region():
    """A rigid turn changes nothing physical: the example turned by 41 degrees about (2, 1, -3)
    (the grid stays axis-aligned, so the punch lies obliquely on it) against the upright one: both
    principal extents, the area and the force within 0.5 % (measured with the weighted flux of the
    carbide punch on steel: +0.40 % and +0.40 %, -0.11 %, -0.11 %)."""
    import tomllib

    from _turned_scene import turned_scene
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.solving import solve

    upright = solve(scene_from_dict(tomllib.loads(EXAMPLE.read_text()), label="rounded_punch.toml").problem)
    sol = solve(scene_from_dict(turned_scene(tomllib.loads(EXAMPLE.read_text()), [2.0, 1.0, -3.0], 41.0),
                                label="turned.toml").problem)
    assert upright.converged and sol.converged, sol.iterations["messages"]
    u, c = upright.contacts[0], sol.contacts[0]
    print(f"turned against upright: extents {np.array(sorted(c['extents'])) / np.array(sorted(u['extents'])) - 1}, "
          f"area {c['area'] / u['area'] - 1:+.2e}, force {c['normal_force'] / u['normal_force'] - 1:+.2e}")
    np.testing.assert_allclose(sorted(c["extents"]), sorted(u["extents"]), rtol=5e-3)
    assert c["area"] == pytest.approx(u["area"], rel=5e-3)
    assert c["normal_force"] == pytest.approx(u["normal_force"], rel=5e-3)
