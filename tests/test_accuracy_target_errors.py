"""The true errors the accuracy-target benchmark (benchmarks/accuracy_target.py) judges its grids
by, against hand-computed Hertz values: a summary carrying Hertz's own a, p0 and largest von
Mises stress for its force has no error, and one 1 % off has 1 %."""

from __future__ import annotations

import importlib.util
import math
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _load(name: str):
    if str(ROOT / "benchmarks") not in sys.path:
        sys.path.insert(0, str(ROOT / "benchmarks"))
    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


target = _load("accuracy_target")


def _sphere_summary(scale_a: float = 1.0, scale_p: float = 1.0, scale_vm: float = 1.0) -> dict:
    # steel on steel, R = 1: E* = E / (2 (1 - nu^2)); the quarter model carries N / 4
    n_full, e_star = 1.36e7, 2.0e11 / (2.0 * (1.0 - 0.09))
    a = (3.0 * n_full * 1.0 / (4.0 * e_star)) ** (1.0 / 3.0)
    p0 = 3.0 * n_full / (2.0 * math.pi * a * a)
    # Hertz's largest von Mises stress on the axis of a sphere's contact, nu = 0.3: 0.62 p0 at
    # 0.48 a (Johnson, Contact Mechanics, 1985, fig. 4.3), here from the axis stresses (eq. 3.45)
    return {"contacts": [{"bodies": ["ball", "block"], "type": "frictionless", "friction": 0.0,
                          "semi_axes": [a * scale_a, a], "normal_force": n_full / 4.0, "model_share": 0.25,
                          "relative_curvatures": [1.0, 1.0], "max_von_mises": 0.6200 * p0 * scale_vm,
                          "pressure": {"axis0": {"s": [0.0], "value": [p0 * scale_p]}}}]}


def test_a_summary_with_hertz_s_values_has_no_error_and_one_off_by_one_percent_has_one():
    data = tomllib.loads((ROOT / "examples" / "solid" / "sphere_on_flat.toml").read_text())
    exact = target.true_errors(data, ROOT / "examples" / "solid", _sphere_summary(), force_reference=1.36e7)
    assert exact["a"] == pytest.approx(0.0, abs=1e-12) and exact["p0"] == pytest.approx(0.0, abs=1e-12)
    assert exact["N"] == pytest.approx(0.0, abs=1e-12)
    assert exact["von_mises"] < 1e-3  # 0.62 p0 is Johnson's rounded value
    off = target.true_errors(data, ROOT / "examples" / "solid", _sphere_summary(1.01, 1.01, 1.01))
    assert off["a"] == pytest.approx(0.01, rel=1e-9) and off["p0"] == pytest.approx(0.01, rel=1e-9)
    assert off["von_mises"] == pytest.approx(0.01, abs=1.1e-3) and off["N"] is None and off["stick"] is None
