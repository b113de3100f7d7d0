"""The peak's fit of a region's pressure map (solver.contact.region_report.fitted_peak): a
weighted least-squares quadratic over the squares within two local cells of the peak's place,
checked on maps of closed forms averaged over the squares, where the peak is known.

Independent truth: a quadratic's square means are its values at the centroids raised by its
curvatures times h^2 / 24, so its vertex and value come back exactly; Hertz's ellipse
p0 sqrt(1 - x^2/a^2 - y^2/b^2) peaks at its centre with p0; a flat top along a roller's line has
the value of its closed form at mid-length, which squares alternating by +-0.7 % (the scatter
measured along Lundberg's plateau, where the map's squares are half the grid's cells) must not
move by more than the stated bound."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.contact.region_report import WINDOW_CELLS, fitted_peak, mirror_images, peak_place

H = 0.003125
QUARTER = mirror_images([(0.0, 0.5 * math.pi)])


def _square_means(pressure, kx: np.ndarray, ky: np.ndarray, h: float = H, n: int = 12):
    """(keys, centres, means, areas) of ``pressure(X, Y)`` over the squares of side h with integer
    keys kx x ky (the midpoint rule on n x n points in each)."""
    keys = np.stack(np.meshgrid(kx, ky, indexing="ij"), axis=-1).reshape(-1, 2)
    u = (np.arange(n) + 0.5) / n
    means = np.array([pressure(*np.meshgrid((k[0] + u) * h, (k[1] + u) * h, indexing="ij")).mean() for k in keys])
    return keys, (keys + 0.5) * h, means, np.full(len(keys), h * h)


@pytest.mark.parametrize("cells", [1, 2])
@pytest.mark.parametrize("x0", [0.05625, 0.0571, 0.0599])
def test_a_quadratic_peak_comes_back_exactly(cells, x0):
    """p0 - alpha (x - x0)^2 - beta y^2 over a quarter model's squares (mirror images across its
    symmetry planes, also planes off the axes by the frame's round-off), its squares the cells or
    half of them: the vertex (x0, 0) and p0 to round-off, wherever x0 falls in its square."""
    p0, alpha, beta = 3.5e9, 2.0e12, 5.0e11
    kx, ky = np.meshgrid(np.arange(30), np.arange(8), indexing="ij")
    keys = np.stack([kx.ravel(), ky.ravel()], axis=1)
    centres = (keys + 0.5) * H
    means = p0 - alpha * ((centres[:, 0] - x0) ** 2 + H * H / 12) - beta * (centres[:, 1] ** 2 + H * H / 12)
    area = np.full(len(means), H * H)
    for off in (0.0, 2e-8, 4e-6):
        maps = mirror_images([(off, 0.5 * math.pi + off)])
        at, value = fitted_peak(centres, means, area, keys, H, cells * H, maps)
        assert at == pytest.approx([x0, 0.0], abs=1e-12)
        assert value == pytest.approx(p0, rel=1e-12)


@pytest.mark.parametrize("cells", [1, 2])
def test_a_hertzian_peak_between_squares(cells):
    """Hertz's ellipse (a = 30 mm, b = 20 mm): over a quarter model at its centre exactly; over a
    whole model with the centre anywhere in its square (on a square's edge and corner too)
    within a fifth of a square (measured 0.001 of one), the value within 0.2 % of p0 (measured
    0.01 % on squares that are the cells, 0.1 % on half cells: the window's quadratic against
    the ellipse's root)."""
    a, b, p0 = 0.03, 0.02, 1e9

    def hertz(x0, y0):
        return lambda X, Y: p0 * np.sqrt(np.maximum(1.0 - (X - x0) ** 2 / a**2 - (Y - y0) ** 2 / b**2, 0.0))

    keys, centres, means, area = _square_means(hertz(0.0, 0.0), np.arange(12), np.arange(8))
    at, value = fitted_peak(centres, means, area, keys, H, cells * H, QUARTER)
    assert at == pytest.approx([0.0, 0.0], abs=1e-12)
    assert value == pytest.approx(p0, rel=0.002)
    for x0, y0 in ((0.0, 0.2 * H), (0.3 * H, 0.2 * H), (0.5 * H, 0.5 * H), (0.8 * H, 0.1 * H), (H, 0.0)):
        keys, centres, means, area = _square_means(hertz(x0, y0), np.arange(-12, 12), np.arange(-8, 8))
        at, value = fitted_peak(centres, means, area, keys, H, cells * H)
        assert np.abs(at - [x0, y0]).max() < 0.2 * H
        assert value == pytest.approx(p0, rel=0.002)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_plateau_with_alternating_squares(sign):
    """A flat top along a quarter roller's line, p0 (1 - (x/L)^8) sqrt(1 - (y/b)^2), on squares
    half the grid's cells (as on Lundberg's plateau) alternating by +-0.7 % along the line: the
    peak at mid-length (the plateau's middle, by the mirror image) and its value within 0.4 % of
    p0 (measured -0.28 % and +0.33 %), where the largest square reads the noise (+0.44 %) a
    square and a half from mid-length."""
    p0, length = 3e9, 0.08
    keys, centres, means, area = _square_means(
        lambda X, Y: p0 * (1.0 - (X / length) ** 8) * np.sqrt(np.maximum(1.0 - (Y / 0.025) ** 2, 0.0)),
        np.arange(26), np.arange(9), n=8)
    noisy = means * (1.0 + sign * 0.007 * np.where(keys[:, 0] % 2 == 1, 1.0, -1.0))
    at, value = fitted_peak(centres, noisy, area, keys, H, 2 * H, QUARTER)
    assert at == pytest.approx([0.0, 0.0], abs=1e-12)
    assert value == pytest.approx(p0, rel=0.004)
    if sign > 0:
        assert centres[int(np.argmax(noisy))][0] == pytest.approx(1.5 * H)


def test_a_half_model_falling_from_its_end_keeps_the_place():
    """Without a peak along x (a half model's pressure falling along x from its end x = 0) the fit
    moves the peak only across the line (to y = 0, its vertex there) and keeps the peak's place
    along it; the window is WINDOW_CELLS cells."""
    p0, beta = 3.5e9, 5.0e11
    kx, ky = np.meshgrid(np.arange(12), np.arange(4), indexing="ij")
    keys = np.stack([kx.ravel(), ky.ravel()], axis=1)
    centres = (keys + 0.5) * H
    falling = p0 - 1e10 * centres[:, 0] - beta * centres[:, 1] ** 2
    area = np.full(len(falling), H * H)
    half = mirror_images([(0.0, math.pi)])
    at, _ = fitted_peak(centres, falling, area, keys, H, H, half)
    place = peak_place(centres, falling, area, keys, H, half)
    assert at[0] == pytest.approx(place[0], abs=1e-12) and at[1] == pytest.approx(0.0, abs=1e-12)
    assert WINDOW_CELLS == 2.0


def test_a_window_too_thin_for_a_quadratic_gives_the_place_and_the_largest_mean():
    """A map of one row of squares cannot fix a quadratic across it: the peak's place and the
    largest mean."""
    keys = np.stack([np.arange(5), np.zeros(5, dtype=int)], axis=1)
    centres = (keys + 0.5) * H
    means = np.array([1.0, 2.0, 3.0, 2.5, 1.0]) * 1e9
    area = np.full(5, H * H)
    at, value = fitted_peak(centres, means, area, keys, H, H)
    assert at == pytest.approx(peak_place(centres, means, area, keys, H), abs=1e-15)
    assert value == 3e9
