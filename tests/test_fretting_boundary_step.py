"""The 2D friction history's stick/slip boundary steps on extreme tries: a boundary pushed out to
where the pressure vanishes has an edge coefficient that grows without bound (measured up to
1.5e307 on a pin in a bore under a turning load); the step stays finite, at most half a cell, and
no floating-point warning is raised."""

import types
import warnings

import numpy as np
import pytest

from ibfem.solver.contact.friction_history import HistoryBandContact, _rising_slope


def test_a_step_from_overflowing_tries_is_finite_and_silent():
    contact = types.SimpleNamespace(h=0.0078125, slopes=[], edge_slope=24.1)
    tries = [(np.float64(0.4947706903127384), 73.16458134123708), (np.float64(0.49525886727688795), 8.723421073680235e306),
             (np.float64(0.4986769403127384), 1.4762621263476424e307), (np.float64(0.49916511727688795), 1.4520909208804288e307)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        step = HistoryBandContact._boundary_step(contact, tries, -1.0)
    assert np.isfinite(step) and abs(step) <= 0.5 * contact.h


def test_a_secant_rises_only_over_a_real_run():
    assert _rising_slope([0.0, 1e-3], [0.0, 2.0], 1e-9) == pytest.approx(2000.0)
    assert _rising_slope([0.0, 1e-3], [0.0, -2.0], 1e-9) is None
    assert _rising_slope([1e-3, 0.0], [2.0, 0.0], 1e-9) == pytest.approx(2000.0)  # falling u and v: rising
    assert _rising_slope([0.0, 1e-12], [0.0, 2.0], 1e-9) is None  # closer than the run allowed
    assert _rising_slope([0.0, 1e-3], [1.0, 1.0], 1e-9) is None  # flat
