"""The energy per cycle that benchmarks/fretting_stick_compliance.py draws from a measured tangent
compliance, against two invariants of a loop: a compliance added uniformly (linear in Q) adds no
area, and the part of the compliance that grows as the stick circle shrinks, 1 / (8 G* c) -
1 / (8 G* a), scaled by 1 + k scales the area by 1 + k."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from ibfem.solver.reference.fretting_sphere import effective_shear_modulus, hertz_radius

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "fretting_stick_compliance.py"
E, NU, R, N, MU = 2.0e11, 0.3, 1.0, 1.377e7, 0.3
G_STAR = effective_shear_modulus(E, NU, E, NU)
A = hertz_radius(N, R, E / (2.0 * (1.0 - NU * NU)))


def _module():
    spec = importlib.util.spec_from_file_location("fretting_stick_compliance", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("x", [0.15, 0.3, 0.6])
def test_linear_compliance_adds_no_area(x):
    energy = _module().implied_energy
    assert energy(x, lambda c: 0.0 * c, N, MU, A, G_STAR) == pytest.approx(0.0, abs=1e-6)
    assert energy(x, lambda c: 0.0 * c + 0.05 / (8.0 * G_STAR * A), N, MU, A, G_STAR) == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize("x, k", [(0.3, 0.1), (0.6, -0.05)])
def test_growing_part_scales_the_area(x, k):
    energy = _module().implied_energy
    excess = lambda c: k * (1.0 / c - 1.0) / (8.0 * G_STAR * A)  # noqa: E731
    assert energy(x, excess, N, MU, A, G_STAR) == pytest.approx(k, abs=2e-4)


@pytest.mark.slow
def test_stick_circle_tangent_compliance_is_mindlins():
    """On the fretting example's grid (about 10 s, 0.65 GB): with stick circles of c = 0.94 a and
    0.888 a imposed (the annulus at Coulomb's traction), the rise of the tangential compliance over
    the full stick's is Mindlin's (1 / c - 1 / a) / (8 G*) within 0.2 % of 1 / (8 G* c) (measured:
    0.03 % and 0.07 %; docs/load-paths.md, "The stick circle's compliance and the ties' layer")."""
    mod = _module()
    from ibfem.solver.reports.validate_fretting_sphere import amplitude_for

    r = mod.measure([1.0, 0.94, 0.888], amplitude_for(0.3), False)
    assert r["converged"]
    g = effective_shear_modulus(r["E"], r["nu"], r["E"], r["nu"])
    full = r["radii"][0]["compliance"]
    for v in r["radii"][1:]:
        assert v["stick_ratio"] == pytest.approx(v["c"], abs=2e-3)
        rise = v["compliance"] - full
        mindlin = (1.0 / v["c"] - 1.0) / (8.0 * g * r["a"])
        assert abs(rise - mindlin) * 8.0 * g * r["a"] * v["c"] < 2e-3


def test_the_loading_curve_sag_holds_no_linear_part():
    """Mindlin's own states (with any linear compliance added to the rig's displacement) read a sag
    of Mindlin's, to round-off; a displacement 1 % larger at the mid radius reads a smaller sag."""
    mod = _module()
    unit = 3.0 * MU * N / (16.0 * A * G_STAR)

    def states(linear, bump=0.0):
        radii = []
        for c in (1.0, 0.94, 0.888, 0.7):
            q = MU * N * (1.0 - c ** 3)
            d = unit * (1.0 - c ** 2) + linear * q + (bump * unit if c == 0.94 else 0.0)
            radii.append({"c": c, "compliance": 1.0, "offset": q - d})  # Q = (delta - delta_0) / 1 through (d, q)
        return {"radii": radii, "mu": MU, "N": N, "a": A}

    for linear in (0.0, 3e-11):
        for line in mod.loading_curve_sags(states(linear), G_STAR):
            assert line.endswith("(+0.00%)") or line.endswith("(-0.00%)")
    bumped = mod.loading_curve_sags(states(0.0, 0.01), G_STAR)
    assert bumped[0].startswith("c/a 0.940 on the chord to 0.888") and "(-" in bumped[0]
