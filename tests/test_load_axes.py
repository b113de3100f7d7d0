"""Conditions given along axes of their own (``axes``): the value the solver sees at every load
step against the closed form of the paths (a sine sampled at the cycle's points, a ramp held),
turned by hand; the scene errors for unusable axes."""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.io.scene import SceneError, scene_from_dict

ROOT = Path(__file__).resolve().parents[1]
FRETTING_2D = ROOT / "examples" / "fretting" / "cylinder_on_flat_fretting.toml"
FRETTING_3D = ROOT / "examples" / "fretting" / "sphere_on_flat_fretting.toml"


def _hold(t):  # the examples' "hold": 0 -> 1 over t in [0, 1], then held
    return np.clip(t, 0.0, 1.0)


def _fret(t, points_per_cycle=20, cycles=3):
    """The examples' "fret": 0 until t = 1, then sin(2 pi (t - 1)) sampled at 20 points a cycle,
    linear between samples, held after the last."""
    t = np.asarray(t, dtype=float)
    k = np.clip((t - 1.0) * points_per_cycle, 0.0, cycles * points_per_cycle)
    lo = np.floor(k)
    hi = np.minimum(lo + 1, cycles * points_per_cycle)
    f_lo, f_hi = np.sin(2 * math.pi * lo / points_per_cycle), np.sin(2 * math.pi * hi / points_per_cycle)
    return np.where(t <= 1.0, 0.0, f_lo + (k - lo) * (f_hi - f_lo))


def _value_at(problem, j, t):
    bc = problem.boundary_conditions[j]
    names = problem.history.names_of(j, len(bc.value))
    return np.array([v * float(problem.history.factor(n, t)) for v, n in zip(bc.value, names)])


def _turned_2d(theta_deg, **bc_keys):
    data = tomllib.loads(FRETTING_2D.read_text(encoding="utf-8"))
    c, s = math.cos(math.radians(theta_deg)), math.sin(math.radians(theta_deg))
    data["boundary_conditions"][0]["axes"] = [[c, s], [-s, c]]
    data["boundary_conditions"][0].update(bc_keys)
    return data, np.array([[c, s], [-s, c]])


@pytest.mark.parametrize("theta", [0.0, 30.0, 117.0])
def test_a_turned_tangent_cycled_and_normal_held_at_every_step(theta):
    data, axes = _turned_2d(theta)
    ut, un = data["boundary_conditions"][0]["value"]
    problem = scene_from_dict(data, label="turned.toml", base_dir=FRETTING_2D.parent).problem
    times = problem.history.times()
    assert len(times) == 4 + 3 * 20  # as the example: 4 steps to t = 1, then 20 a cycle (no step added)
    for t in np.concatenate([times, [0.37, 1.013, 2.49]]):
        expected = ut * _fret(t) * axes[0] + un * _hold(t) * axes[1]
        assert np.allclose(_value_at(problem, 0, t), expected, rtol=0, atol=1e-12 * abs(un))


def test_axes_that_are_not_unit_or_orthogonal_are_directions():
    """Axes are scaled to unit length and need not be orthogonal: 2 (1, 0) and (1, 1) mean (1, 0)
    and (1, 1) / sqrt(2)."""
    data, _ = _turned_2d(0.0, axes=[[2.0, 0.0], [1.0, 1.0]], path="hold", value=[1e-4, -1e-3])
    problem = scene_from_dict(data, label="axes.toml", base_dir=FRETTING_2D.parent).problem
    bc = problem.boundary_conditions[0]
    assert np.allclose(bc.value, [1e-4 - 1e-3 / math.sqrt(2), -1e-3 / math.sqrt(2)], rtol=1e-14)
    assert problem.history.names_of(0, 2) == ("hold", "hold")  # one path: the value turned, nothing added


@pytest.mark.parametrize("keys, message", [
    ({"axes": [[0.0, 0.0], [0.0, 1.0]]}, "an axis is the zero vector"),
    ({"axes": [[1.0, 1.0], [-2.0, -2.0]]}, "not independent"),
    ({"value": [1e-4, "free"]}, "value has a free component"),
])
def test_unusable_axes_are_refused_naming_the_file_and_key(keys, message):
    data, _ = _turned_2d(30.0, **keys)
    with pytest.raises(SceneError) as err:
        scene_from_dict(data, label="axes.toml", base_dir=FRETTING_2D.parent)
    assert "axes.toml: boundary_conditions[0]" in str(err.value) and message in str(err.value)


def test_3d_a_displacement_along_a_turned_frame():
    """The 3D example's displacement (tangent cycled, normal held) given along a frame turned by
    40 degrees about z: every step's prescribed vector is the frame's combination of the paths."""
    data = tomllib.loads(FRETTING_3D.read_text(encoding="utf-8"))
    c, s = math.cos(math.radians(40.0)), math.sin(math.radians(40.0))
    axes = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    bc = data["boundary_conditions"][0]
    bc["axes"] = axes.tolist()
    v = np.array(bc["value"], dtype=float)
    problem = scene_from_dict(data, label="turned3d.toml", base_dir=FRETTING_3D.parent).problem
    for t in np.concatenate([problem.history.times(), [0.5, 1.26]]):
        expected = v[0] * _fret(t) * axes[0] + v[1] * _hold(t) * axes[1] + v[2] * _hold(t) * axes[2]
        assert np.allclose(_value_at(problem, 0, t), expected, rtol=0, atol=1e-12 * np.abs(v).max())
