"""The profiles of a 3D contact with friction history along its principal axes
(solver.contact.friction_history_profiles): a bin's mean reproduces a linear field at its
sample (the points lie symmetrically about each sample), vectors are split along and across the
loop's direction, the zone carries the slip's sign, and a sample without points is not inside."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ibfem.solver.contact.friction_history_profiles import PROFILE_SAMPLES, STRIP_CELLS, axis_profiles

REACH, CELL = 0.05, 0.01


def _points(radius: float):
    """Points on a square lattice of a quarter of the samples' spacing, offset by half a lattice
    step from every sample and axis line (so symmetric about each), within ``radius``."""
    spacing = REACH / PROFILE_SAMPLES
    d = spacing / 4.0
    k = np.arange(-int(REACH / d) - 2, int(REACH / d) + 2) + 0.5
    x, y = np.meshgrid(k * d, k * d, indexing="ij")
    local = np.column_stack([x.ravel(), y.ravel()])
    return local[np.hypot(local[:, 0], local[:, 1]) <= radius], d * d


def _frame(angle: float):
    c, s = np.cos(angle), np.sin(angle)
    axes = np.array([[c, s, 0.0], [-s, c, 0.0]])
    return SimpleNamespace(point=np.array([1.0, 2.0, 3.0]), normal=np.array([0.0, 0.0, 1.0]), axes=axes)


def test_linear_fields_are_read_exactly_along_both_axes():
    local, area = _points(0.8 * REACH)
    frame = _frame(0.4)
    q = len(local)
    on_plane = frame.point + local @ frame.axes
    pressure = 2.0 + 3.0 * local[:, 0] - 5.0 * local[:, 1]
    shear = (1.0 + 7.0 * local[:, 0])[:, None] * frame.axes[0] + (4.0 * local[:, 1])[:, None] * frame.axes[1]
    slip = local[:, 0] > 0.6 * REACH
    direction = np.where(slip[:, None], -frame.axes[0], frame.axes[0])
    state = {"pressure": pressure, "shear": shear, "slip_increment": 0.5 * shear, "tangential_jump": 2.0 * shear,
             "slip": slip, "direction": direction, "accumulated_slip": np.abs(local[:, 1]), "points": on_plane}
    out = axis_profiles(local, np.full(q, area), REACH, CELL, frame, np.zeros(2), state)
    n = 2 * PROFILE_SAMPLES + 1
    assert out["s"].shape == (2 * n,) and np.array_equal(out["axis"], np.repeat([0, 1], n))
    inside = out["inside"]
    assert inside.any() and not inside.all()
    assert np.all(np.abs(out["s"][inside]) <= 0.8 * REACH + REACH / PROFILE_SAMPLES)
    x = np.where(out["axis"] == 0, out["s"], 0.0)
    y = np.where(out["axis"] == 1, out["s"], 0.0)
    assert np.allclose(out["pressure"][inside], (2.0 + 3.0 * x - 5.0 * y)[inside], rtol=0, atol=1e-12)
    assert np.allclose(out["shear"][inside], (1.0 + 7.0 * x)[inside], rtol=0, atol=1e-12)
    assert np.allclose(out["shear_across"][inside], (4.0 * y)[inside], rtol=0, atol=1e-12)
    assert np.allclose(out["tangential_jump"][inside], 2.0 * out["shear"][inside], rtol=0, atol=1e-12)
    assert np.allclose(out["slip_increment_across"][inside], 0.5 * out["shear_across"][inside], rtol=0, atol=1e-12)
    # the strip across the axis line: |y| <= STRIP_CELLS cell on axis 0, so |y| averages to at most that
    assert np.all(out["accumulated_slip"][inside & (out["axis"] == 0)] <= STRIP_CELLS * CELL)
    # the points of a sample lie on the axis line through the centre (the lattice is symmetric)
    line = frame.point + x[:, None] * frame.axes[0] + y[:, None] * frame.axes[1]
    assert np.allclose(out["points"], line, rtol=0, atol=1e-12)
    # zone: 0 where all stick, -1 where the slip runs along -axes[0]; nothing outside
    far = (out["axis"] == 0) & (out["s"] > 0.65 * REACH) & inside
    assert far.any() and np.allclose(out["zone"][far], -1.0)
    assert np.allclose(out["zone"][inside & (np.abs(x) < 0.5 * REACH)], 0.0)
    assert np.all(out["pressure"][~inside] == 0.0) and np.all(out["zone"][~inside] == 0.0)


def test_a_half_model_has_one_side_of_its_second_axis():
    local, area = _points(0.8 * REACH)
    half = local[:, 1] > 0.0
    local = local[half]
    frame = _frame(0.0)
    q = len(local)
    zeros = np.zeros((q, 3))
    state = {"pressure": np.ones(q), "shear": zeros, "slip_increment": zeros, "tangential_jump": zeros,
             "slip": np.zeros(q, dtype=bool), "direction": zeros, "accumulated_slip": np.zeros(q),
             "points": frame.point + local @ frame.axes}
    out = axis_profiles(local, np.full(q, area), REACH, CELL, frame, np.zeros(2), state)
    second = out["axis"] == 1
    assert not np.any(out["inside"][second & (out["s"] < 0.0)])
    assert np.all(out["inside"][second & (out["s"] > 0.0) & (out["s"] < 0.7 * REACH)])
    assert np.allclose(out["pressure"][out["inside"]], 1.0)


def test_damage_along_the_axes_of_a_slip_to_and_fro():
    """Fretting damage between solids from given profiles: a tangential jump moving to and fro
    along a line at an angle to the axes with amplitude A has slip amplitude A; under a uniform
    stress sigma the surface stress along the loop's direction t is t . sigma t (here a uniaxial
    stress S along x and t at angle theta: S cos^2 theta); Ruiz's parameter is its positive part
    times the largest |q| times the slip amplitude."""
    import dataclasses

    from ibfem.solver.io.fretting_outputs import _damage

    theta, amplitude, stress = 0.3, 2.0e-5, 4.0e8

    @dataclasses.dataclass
    class Uniform:
        u: float = 0.0

        def stress(self, points, body, recovered=True):
            return np.tile([stress, 0.0, 0.0, 0.0, 0.0, 0.0], (len(points), 1))

    frame = _frame(theta)
    n = 5
    s = np.linspace(-0.02, 0.02, n)
    steps = []
    for k, phase in enumerate(np.sin(0.5 * np.pi * np.arange(5))):  # 0, 1, 0, -1, 0
        jump = phase * amplitude * np.array([np.cos(0.7), np.sin(0.7)])  # along a line at 0.7 rad to axis 0
        prof = {"s": s, "axis": np.zeros(n, dtype=int), "inside": np.array([False, True, True, True, True]),
                "points": np.column_stack([s, np.zeros(n), np.zeros(n)]), "normal": np.tile([0.0, 0.0, 1.0], (n, 1)),
                "tangential_jump": np.full(n, jump[0]), "tangential_jump_across": np.full(n, jump[1]),
                "shear": np.full(n, 3.0e7 * phase), "shear_across": np.full(n, 4.0e7 * phase)}
        steps.append({"contacts": [{"axis_profile": prof}], "field": float(k)})
    block = {"axes": frame.axes.tolist(), "bodies": ["ball", "block"]}
    out = _damage(None, Uniform(), steps, 0, block, None)
    inside = np.array([False, True, True, True, True])
    assert np.allclose(out["slip_amplitude"][inside], amplitude, rtol=1e-12)
    assert np.all(out["slip_amplitude"][~inside] == 0.0)
    assert np.allclose(out["max_shear"], 5.0e7, rtol=1e-12)
    sigma_t = stress * np.cos(theta) ** 2
    assert np.allclose(out["max_surface_stress"][inside], sigma_t, rtol=1e-12)
    assert np.allclose(out["ruiz"][inside], sigma_t * 5.0e7 * amplitude, rtol=1e-12)
    assert np.array_equal(out["axis"], np.zeros(n, dtype=int))
