"""The 3D peak-pressure reading of an elliptic region (solver.contact.ellipse_report.peak_reading)
against Hertz's pressure p0 sqrt(1 - x^2 / a^2 - y^2 / b^2) sampled like the band traction: 2 x 2
Gauss points per square cell of a grid cut by the region, weights the points' areas."""

from __future__ import annotations

import numpy as np
import pytest

from ibfem.solver.contact.ellipse_report import HERTZ_LIKE_MISFIT, fit_profile, peak_reading
from ibfem.solver.model.accuracy import HERTZ_SHAPE_PEAK_SIZE_SHARE, peak_size_share, relative_errors

GAUSS = np.array([-1.0, 1.0]) / np.sqrt(3.0)


def sampled(a: float, b: float, h: float, offset=(0.3, 0.7)):
    """Gauss points (x, y), their weights and their cells' local coordinates (xi, eta) inside the
    ellipse of semi-axes a, b on a grid of cells h wide shifted by ``offset`` cells."""
    n = int(np.ceil(max(a, b) / h)) + 2
    cx, cy = ((np.arange(-n, n) + o) * h for o in offset)
    xi, eta = (g.ravel() for g in np.meshgrid(GAUSS, GAUSS))
    shape = (len(cx), len(cy), len(xi))
    x = np.broadcast_to(cx[:, None, None] + 0.5 * h * (1.0 + xi), shape).ravel()
    y = np.broadcast_to(cy[None, :, None] + 0.5 * h * (1.0 + eta), shape).ravel()
    xi_q, eta_q = (np.broadcast_to(g, shape).ravel() for g in (xi, eta))
    inside = (x / a) ** 2 + (y / b) ** 2 < 1.0
    return x[inside], y[inside], np.full(inside.sum(), 0.25 * h * h), xi_q[inside], eta_q[inside]


def hertz(x, y, a, b, p0=2.0e9):
    return p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None))


@pytest.mark.parametrize("ratio", [1.0, 0.45])
def test_hertz_pressure_with_cell_scatter_reads_its_peak(ratio):
    # the traction's cell-to-cell scatter: a linear field of zero mean in each cell, 15 % of p0
    a, b, p0 = 0.045, 0.045 * ratio, 2.0e9
    x, y, w, xi, eta = sampled(a, b, b / 12.0)
    p = hertz(x, y, a, b, p0) + 0.15 * p0 * (xi - 0.5 * eta)
    out = peak_reading(x / a, y / b, w, p)
    assert out["reading"] == "hertz_shape_inner" and out["misfit"] < 0.005
    assert out["coefficients"][0] == pytest.approx(p0, rel=2e-3)


def test_the_edge_cells_do_not_move_the_peak():
    # the cells holding the edge interpolate the root-like fall of the pressure badly: an error of
    # 10 % of p0 in the outer ring X^2 + Y^2 > 0.7 leaves the reading at Hertz's p0, where the
    # whole-region fit's centre value moves
    a, p0 = 0.045, 2.0e9
    x, y, w, _, _ = sampled(a, a, a / 12.0)
    X, Y = x / a, y / a
    p = hertz(x, y, a, a, p0) + 0.1 * p0 * ((X**2 + Y**2) > 0.7)
    out = peak_reading(X, Y, w, p)
    assert out["reading"] == "hertz_shape_inner"
    assert out["coefficients"][0] == pytest.approx(p0, rel=1e-9)
    assert abs(fit_profile(X, Y, w, p)[0] / p0 - 1.0) > 0.01


@pytest.mark.parametrize("shape", ["uniform", "flat punch", "hollow", "tilted"])
def test_a_pressure_unlike_hertz_keeps_the_whole_region_fit(shape):
    a = 0.045
    x, y, w, _, _ = sampled(a, a, a / 12.0)
    X, Y = x / a, y / a
    r2 = X**2 + Y**2
    p = {"uniform": np.ones_like(X), "flat punch": 1.0 / np.sqrt(1.0 - 0.99 * r2),
         "hollow": np.sqrt(1.0 - r2) * (0.5 + r2), "tilted": np.sqrt(1.0 - r2) * (1.0 + 0.15 * X)}[shape]
    out = peak_reading(X, Y, w, 1.0e9 * p)
    assert out["reading"] == "whole_region_fit" and out["misfit"] > HERTZ_LIKE_MISFIT
    assert np.allclose(out["coefficients"], fit_profile(X, Y, w, 1.0e9 * p))


def test_too_few_inner_points_keep_the_whole_region_fit():
    a = 0.045
    x, y, w, _, _ = sampled(a, a, a)
    out = peak_reading(x / a, y / a, w, hertz(x, y, a, a))
    assert out["reading"] == "whole_region_fit" and out["misfit"] is None


def test_the_profile_centre_is_the_peak_and_the_rest_is_fitted():
    # the constant term is the inner reading; the other terms fit what remains over the whole
    # region: a pressure sqrt(1 - R^2) (1 + 0.02 X^2) is reproduced but for the constant's shift
    a, p0 = 0.045, 2.0e9
    x, y, w, _, _ = sampled(a, a, a / 16.0)
    X, Y = x / a, y / a
    p = p0 * np.sqrt(1.0 - X**2 - Y**2) * (1.0 + 0.02 * X**2)
    coef = peak_reading(X, Y, w, p)["coefficients"]
    assert coef[0] == pytest.approx(p0, rel=0.01)
    assert coef[3] == pytest.approx(0.02 * p0 + (p0 - coef[0]), rel=0.2)
    assert np.allclose(coef[[1, 2, 4]], 0.0, atol=1e-6 * p0)


def test_the_size_share_covers_the_reading_s_sensitivity_to_the_semi_axes():
    # Hertz's pressure on the true region read with both semi-axes e too small: the reading moves
    # by about -0.47 e (least squares over X^2 + Y^2 < 0.64); the estimate's floor, the share times
    # the semi-axes' summed error, is at least that
    a, p0, e = 0.045, 2.0e9, -0.01
    x, y, w, _, _ = sampled(a, a, a / 24.0)
    computed = a * (1.0 + e)
    kept = (x / computed) ** 2 + (y / computed) ** 2 < 1.0
    out = peak_reading(x[kept] / computed, y[kept] / computed, w[kept], hertz(x[kept], y[kept], a, a, p0))
    moved = out["coefficients"][0] / p0 - 1.0
    assert moved == pytest.approx(-0.47 * e, rel=0.1)
    block = {"profile_recovery": {"peak": {"reading": out["reading"]}}}
    assert peak_size_share(block) == HERTZ_SHAPE_PEAK_SIZE_SHARE
    fine = {"semi_axes": [computed, computed], "max_pressure": out["coefficients"][0]}
    coarse = {"semi_axes": [a * (1.0 + 2.0**1.5 * e)] * 2, "max_pressure": out["coefficients"][0]}
    errors = relative_errors(fine, coarse, {"semi_axes": 1.5, "max_pressure": 1.5}, size_share=peak_size_share(block))
    assert errors["max_pressure"] >= abs(moved)
    assert peak_size_share({"profile_recovery": {"peak": {"reading": "whole_region_fit"}}}) == 1.0
    assert peak_size_share({}) == 1.0


def test_the_inner_reading_converges_with_the_interior():
    # order 2 for a peak read clear of the edge (its edge share is the size floor), 3/2 for the
    # whole-region fit's centre value, which converges with the region's edge
    from ibfem.solver.model.accuracy import ORDERS, SOLID_PEAK_PRESSURE_ORDER, orders_for
    inner = {"semi_axes": [0.04, 0.04], "profile_recovery": {"peak": {"reading": "hertz_shape_inner"}}}
    whole = {"semi_axes": [0.04, 0.04], "profile_recovery": {"peak": {"reading": "whole_region_fit"}}}
    assert orders_for(inner)["max_pressure"] == ORDERS["max_pressure"] == 2.0
    assert orders_for(whole)["max_pressure"] == SOLID_PEAK_PRESSURE_ORDER == 1.5


def test_a_coarser_grid_s_peak_is_read_as_on_the_finer_grid():
    # Richardson's difference compares one reading on two grids: where the finer grid's peak is
    # Hertz's shape over the inner part, the coarser grid's inner reading is taken where its own
    # region passed the Hertz-like test; where it failed (its profile kept the whole-region fit)
    # the coarser grid has no comparable peak (None)
    from ibfem.solver.model.accuracy import contact_quantities

    def block(reading, profile_peak, shape):
        return {"type": "frictionless", "semi_axes": [0.04, 0.04], "normal_force": 1.0e6,
                "pressure": {"axis0": {"s": [0.0], "value": [profile_peak]}},
                "profile_recovery": {"peak": {"reading": reading, "hertz_shape": shape}}}

    fine = block("hertz_shape_inner", 3.00e9, 3.00e9)
    assert contact_quantities(block("hertz_shape_inner", 3.06e9, 3.05e9), like=fine)["max_pressure"] == 3.05e9
    coarse = block("whole_region_fit", 2.90e9, 3.05e9)
    assert contact_quantities(coarse, like=fine)["max_pressure"] is None
    assert contact_quantities(coarse)["max_pressure"] == 2.90e9
    assert contact_quantities(coarse, like=block("whole_region_fit", 3.0e9, 3.1e9))["max_pressure"] == 2.90e9


def test_an_unresolved_coarser_peak_leaves_the_size_share_alone():
    # the semi-axes converge at order 3/2 (q_h = q + C h^1.5, so their two-grid estimate is their
    # exact error, e); a coarser grid whose inner pressure failed the Hertz-like test gives p0 no
    # two-grid difference: its estimate is the semi-axes' mean error, whatever the coarser grid's
    # own (unresolved) reading
    from ibfem.solver.model.accuracy import ORDERS, contact_quantities

    a, c, h = 0.045, -2.0, 0.0078
    fine_a, coarse_a = a * (1.0 + c * h**1.5), a * (1.0 + c * (2.0 * h) ** 1.5)
    e = abs(fine_a - a) / fine_a  # relative to the grid's value, as the estimate is

    def block(size, reading, p0):
        return {"type": "frictionless", "semi_axes": [size, size], "normal_force": 1.0e6,
                "pressure": {"axis0": {"s": [0.0], "value": [p0]}},
                "profile_recovery": {"peak": {"reading": reading, "hertz_shape": p0}}}

    fine = block(fine_a, "hertz_shape_inner", 3.0e9)
    orders = {**ORDERS, "semi_axes": 1.5}
    for coarse_p0 in (2.5e9, 3.2e9, 4.0e9):
        coarse = contact_quantities(block(coarse_a, "whole_region_fit", coarse_p0), like=fine)
        errors = relative_errors(contact_quantities(fine), coarse, orders, size_share=peak_size_share(fine))
        assert errors["semi_axes"] == pytest.approx([e, e], rel=1e-9)
        assert errors["max_pressure"] == pytest.approx(e, rel=1e-9)
    # a resolved coarser reading keeps its own estimate where it is the larger
    resolved = contact_quantities(block(coarse_a, "hertz_shape_inner", 3.3e9), like=fine)
    errors = relative_errors(contact_quantities(fine), resolved, orders, size_share=peak_size_share(fine))
    assert errors["max_pressure"] == pytest.approx(0.3 / (3.0 * 3.0), rel=1e-9)
