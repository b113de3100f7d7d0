"""Validation of the 2D contacts CAD makes (slow: `make validate`, pytest -m slow), against
closed forms on the grids of examples/contact2d (finest cell 0.04 / 2^7 = 3.1e-4 m):

- the rounded flat punch (Ciavarella, Hills and Monno 1998; solver.reference.punch) for
  a / b = 1.1, 1.5 and 3, turned by 20 degrees, and as a half model: a within 0.5 %, the
  pressure within 2 % of its peak (RMS over the region);
- the sharp flat punch 100 times stiffer than the block (Sadowsky; one level finer, 1.6e-4 m):
  the pressure within 2 % of P / (2 b) on |x| < 0.9 b, each corner's stress intensity
  P / sqrt(pi b) within 3 %;
- a punch with one sharp and one rounded edge (solver.reference.one_sided): the region length
  within 0.5 %, the corner's stress intensity within 3 %;
- a sharp flat punch tilted by 2 mrad, touching at its corner (Johnson's tilted punch; finest
  cell 1.6e-4 m): the region length within 1 %, the corner's stress intensity within 3 %, converged
  from the corner and from a point beside the other corner;
- a CAD profile with fillets (OpenCascade's 2D fillet, through STEP) against the same geometry
  as an analytic profile: a and N to 1e-6;
- the pin in a bore (Persson's problem, solver.reference.pin): the contact semi-angle within
  0.5 % from 0.18 to 1.31 rad, converged.

The fast tests (tests/test_contact2d.py) run the same scenes on grids 2 to 4 times coarser."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.io.scene import scene_from_dict
from ibfem.solver.reference.punch import (flat_punch_pressure, flat_punch_stress_intensity, rounded_punch_half_width,
                                          rounded_punch_pressure)
from ibfem.solver.solving import solve

from _contact2d_scenes import E_STAR, EDGE_RADIUS, HALF_FLAT, punch_on_block

B, R = HALF_FLAT, EDGE_RADIUS

#: approach of the punch for a / b ~ 1.1, 1.5 and 3 (radius: of the contact refinement)
ROUNDED = {1.1: dict(approach=7e-6, radius=0.02), 1.5: dict(approach=8.5e-5), 3.0: dict(approach=7.8e-4)}


def _rounded(c, factor):
    a_ref = rounded_punch_half_width(factor * c["normal_force"], B, R, E_STAR)
    s, p = np.array(c["pressure"]["s"]), np.array(c["pressure"]["value"])
    inside = np.abs(s) < a_ref
    ref = rounded_punch_pressure(np.abs(s), a_ref, B, R, E_STAR)
    return c["half_width"] / a_ref - 1.0, float(np.sqrt(np.mean((p - ref)[inside] ** 2)) / ref.max())


@pytest.mark.slow
@pytest.mark.parametrize("ratio,turn,half", [(1.1, 0.0, False), (1.5, 0.0, False), (3.0, 0.0, False),
                                             (1.5, 20.0, False), (1.5, 0.0, True)])
def test_rounded_flat_punch(ratio, turn, half):
    sol = solve(scene_from_dict(punch_on_block(levels=7, turn=turn, half=half, **ROUNDED[ratio])).problem)
    c = sol.contacts[0]
    assert sol.converged
    assert c["half_width"] / B == pytest.approx(ratio, rel=0.1)
    error, rms = _rounded(c, 2.0 if half else 1.0)
    assert abs(error) < 0.005 and rms < 0.02


@pytest.mark.slow
def test_sharp_flat_punch():
    sol = solve(scene_from_dict(punch_on_block(2e-4, levels=8, sharp=True, punch_modulus=100 * 2.0e11)).problem)
    c = sol.contacts[0]
    assert sol.converged
    load = c["normal_force"]
    s, p = np.array(c["pressure"]["s"]), np.array(c["pressure"]["value"])
    inner = np.abs(s) < 0.9 * B
    assert np.abs(p - flat_punch_pressure(s, load, B))[inner].max() < 0.02 * load / (2 * B)
    for end in c["ends"]:
        assert end["type"] == "complete"
        assert end["stress_intensity"] == pytest.approx(flat_punch_stress_intensity(load, B), rel=0.03)


#: hub displacements of the pin for contact semi-angles of about 0.18, 0.35, 0.71, 1.0, 1.22 and 1.31 rad
PIN_LOADS = [3e-5, 1e-4, 4e-4, 1e-3, 2.5e-3, 4e-3]


@pytest.mark.slow
def test_pin_in_bore_reference_converges():
    """Persson's load converged in the series' terms and harmonics, monotone in the angle up to
    1.3 rad, and its inverse."""
    from ibfem.solver.reference.pin import _dimensionless_load, pin_in_bore_angle, pin_in_bore_load

    assert _dimensionless_load(1.3) == pytest.approx(_dimensionless_load(1.3, terms=20, harmonics=3000), rel=1e-6)
    loads = [_dimensionless_load(t) for t in np.linspace(0.05, 1.3, 12)]
    assert np.all(np.diff(loads) > 0)
    assert pin_in_bore_angle(pin_in_bore_load(0.89, 5e-4, E_STAR), 5e-4, E_STAR) == pytest.approx(0.89, rel=1e-10)


@pytest.mark.slow
@pytest.mark.parametrize("displacement", PIN_LOADS)
def test_pin_in_bore(displacement):
    """Pin R = 0.5 m in a bore 0.5 mm larger, plate 40 R square, hub R / 12.5, finest cell 7.8e-3 m,
    pairs along their own normals: the contact semi-angle within 0.5 % of Persson's problem's
    solution (solver.reference.pin) for the computed load."""
    from ibfem.solver.reference.pin import pin_in_bore_angle

    from _contact2d_scenes import pin_in_bore

    sol = solve(scene_from_dict(pin_in_bore(displacement, plate=20.0, element_size=0.5, levels=6, hub=0.04)).problem)
    c = sol.contacts[0]
    assert sol.converged
    angle = 2.0 * np.arcsin(c["half_width"] / (2.0 * 0.5))
    assert angle / pin_in_bore_angle(c["normal_force"], 5e-4, E_STAR) - 1.0 == pytest.approx(0.0, abs=0.005)


@pytest.mark.slow
@pytest.mark.parametrize("point", ["corner", "far"])
def test_tilted_flat_punch(point):
    """A sharp flat punch 1000 times stiffer than the block, tilted by eps = 2 mrad, touching at its
    corner and pressed 0.06 mm: Johnson's tilted punch on a half-plane (Contact Mechanics, 1985,
    sec. 2.8): the region of length 2 a from the corner with P = pi E* eps a / 2, the corner's
    stress intensity K = E* eps sqrt(pi a). Measured at this grid: -0.30 % and +1.7 % (both fall
    at least as the cell: -1.97 %, -0.80 %, -0.30 % in the length)."""
    from _contact2d_scenes import NU, tilted_punch

    eps = 0.002
    sol = solve(scene_from_dict(tilted_punch(6e-5, eps, levels=8, point=point)).problem)
    c = sol.contacts[0]
    e_star = 1.0 / ((1 - NU**2) / 2.0e11 + (1 - NU**2) / (1000 * 2.0e11))
    a = 2.0 * c["normal_force"] / (math.pi * e_star * eps)
    corner, = [e for e in c["ends"] if e["type"] == "complete"]
    assert sol.converged
    assert (c["region"][1] - c["region"][0]) / (2 * a) == pytest.approx(1.0, abs=0.01)
    assert corner["stress_intensity"] / (e_star * eps * math.sqrt(math.pi * a)) == pytest.approx(1.0, abs=0.03)


@pytest.mark.slow
@pytest.mark.parametrize("approach", [1e-4, 2e-4])
def test_punch_with_one_sharp_edge(approach):
    """One sharp and one rounded edge (R = 1 m), the punch 100 times stiffer, finest cell 3.1e-4 m:
    the region from the sharp corner onto the rounded edge within 0.5 % of the half-plane
    reference's length (solver.reference.one_sided), the corner's stress intensity within 3 %, the
    recovered pressure within 2 % of the mean pressure (RMS, the 90 % of the region away from the
    corner)."""
    from ibfem.solver.reference.one_sided import one_sided_pressure, one_sided_region, one_sided_stress_intensity

    from _contact2d_scenes import NU

    sol = solve(scene_from_dict(punch_on_block(approach, levels=7, one_sharp=True, punch_modulus=100 * 2.0e11)).problem)
    c = sol.contacts[0]
    e_star = 1.0 / ((1 - NU**2) / 2.0e11 + (1 - NU**2) / (100 * 2.0e11))

    def slope(s):  # the chord s runs from the sharp corner (s = -b) onto the rounded edge (s > b)
        t = np.maximum(np.asarray(s, dtype=float) - B, 0.0)
        return t / np.sqrt(R * R - t * t)

    lo, hi = one_sided_region(c["normal_force"], slope, -B, e_star, complete=-1, longest=0.1)
    assert [e["type"] for e in c["ends"]] == ["complete", "incomplete"]
    assert (c["region"][1] - c["region"][0]) / (hi - lo) == pytest.approx(1.0, abs=0.005)
    k = one_sided_stress_intensity(slope, lo, hi, e_star, complete=-1)
    assert c["ends"][0]["stress_intensity"] == pytest.approx(k, rel=0.03)
    s, p = np.array(c["pressure"]["s"]), np.array(c["pressure"]["value"])
    inner = (s > lo + 0.1 * (hi - lo)) & (s < hi)
    ref = one_sided_pressure(s, slope, lo, hi, e_star, complete=-1)
    assert np.sqrt(np.mean((p - ref)[inner] ** 2)) < 0.02 * c["normal_force"] / (hi - lo)


@pytest.mark.slow
def test_cad_fillets_give_the_analytic_profiles_contact(tmp_path):
    # the rounded punch drawn as CAD draws it (a trapezoid whose lower corners OpenCascade rounds
    # with a 2D fillet), written to STEP and read back through a section: the region crosses the
    # junctions of the flat and the fillets (a / b ~ 1.5) and gives the analytic profile's a and N
    # to 1e-6 (on the grid of the fast tests)
    pytest.importorskip("OCP")
    from ibfem.importers.step import profile_from_shape as step_profile

    from _contact2d_scenes import filleted_punch_step

    path = tmp_path / "filleted_punch.step"
    filleted_punch_step(path)
    analytic = punch_on_block(8.1e-5, levels=6)
    cad = punch_on_block(8.1e-5, levels=6)
    for body, bc, y in zip(cad["bodies"], cad["boundary_conditions"], (0.3, -0.6)):  # top of punch, bottom of block
        body["shape"] = {"type": "step", "path": str(path), "body": body["name"],
                         "section": {"origin": [0.0, 0.0, 0.01], "normal": [0.0, 0.0, 1.0]}}
        edges = dict(step_profile(body["shape"]).edges)
        bc["edge"], = [n for n, e in edges.items()
                       if np.allclose(np.asarray(e.evaluate(np.array([float(e.t_start), float(e.t_end)])))[:, 1], y)]
    fillets = [e for e in dict(step_profile(cad["bodies"][0]["shape"]).edges).values() if hasattr(e, "radius")]
    assert len(fillets) == 2 and all(e.radius == pytest.approx(R, rel=1e-12) for e in fillets)
    a = solve(scene_from_dict(analytic).problem).contacts[0]
    sol = solve(scene_from_dict(cad).problem)
    c = sol.contacts[0]
    assert sol.converged and 1.4 < c["half_width"] / B < 1.7
    assert c["half_width"] == pytest.approx(a["half_width"], rel=1e-6)
    assert c["normal_force"] == pytest.approx(a["normal_force"], rel=1e-6)
