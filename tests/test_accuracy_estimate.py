"""The error estimate's arithmetic (solver.model.accuracy): Richardson's estimate is exact on a
sequence converging at the assumed order, and the summary's blocks are read as documented."""

from __future__ import annotations

import math

import pytest

from ibfem.solver.io.result_line import contact_line
from ibfem.solver.model.accuracy import ORDERS, contact_quantities, largest_error, relative_errors


@pytest.mark.parametrize("key", sorted(ORDERS))
def test_richardson_exact_at_the_assumed_order(key):
    # q_h = q + C h^p with p the assumed order: the estimate is the true error of q_h
    p, q, c, h = ORDERS[key], 3.7, 0.8, 0.01
    fine, coarse = q + c * h ** p, q + c * (2 * h) ** p
    if key in ("semi_axes", "stick_semi_axes"):
        est = relative_errors({key: [fine, fine]}, {key: [coarse, coarse]})[key]
        assert est == pytest.approx([abs(fine - q) / fine] * 2, rel=1e-9)
    else:
        assert relative_errors({key: fine}, {key: coarse})[key] == pytest.approx(abs(fine - q) / fine, rel=1e-9)


def test_quantities_of_a_block():
    block = {"type": "frictionless", "half_width": 0.03, "stick_half_width": 0.0, "normal_force": 1e8,
             "pressure": {"s": [-0.01, 0.0, 0.01], "value": [1.0e9, 2.0e9, 1.5e9]}, "max_von_mises": 1.1e9}
    q = contact_quantities(block)
    assert q == {"half_width": 0.03, "normal_force": 1e8, "max_pressure": 2.0e9, "max_von_mises": 1.1e9}
    block3d = {"type": "frictional", "semi_axes": [0.04, 0.05], "stick_semi_axes": [0.02, 0.025], "normal_force": 1e6,
               "pressure": {"axis0": {"s": [0.0], "value": [3e9]}, "axis1": {"s": [0.0], "value": [3.1e9]}}}
    q = contact_quantities(block3d)
    assert q["semi_axes"] == [0.04, 0.05] and q["stick_semi_axes"] == [0.02, 0.025] and q["max_pressure"] == 3.1e9


def test_missing_coarse_quantity_and_largest():
    errors = relative_errors({"normal_force": 1.0, "stick_half_width": 0.5}, {"normal_force": 1.03})
    assert errors["stick_half_width"] is None and errors["normal_force"] == pytest.approx(0.01)
    assert largest_error(errors) == ("normal_force", pytest.approx(0.01))
    assert largest_error({"half_width": math.nan}) == (None, 0.0)


def test_result_line_prints_the_estimate():
    line = contact_line({"type": "frictionless", "half_width": 0.03, "normal_force": 1e8,
                         "estimated_error": {"half_width": 0.0042, "normal_force": 0.0003}})
    assert "estimated error half_width 0.42 %, normal_force 0.03 %" in line
