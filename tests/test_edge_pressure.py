"""The pressure read on agglomerated cells (solver.contact.edge_pressure), against closed forms:
the merged means conserve the pressure's integral, undo a sliver's tension that its neighbour
balances, stay compressive at the edge of Hertz's region and turn tensile at the edge of a
region too large for its approach (the pressure of a rigid sphere pressed to a contact radius c
beyond Hertz's a at the approach a^2 / R: Hertz's pressure for c less a flat punch's for the
missing approach, (2 E* / (pi R)) sqrt(c^2 - r^2) - E* (c^2 - a^2) / (pi R sqrt(c^2 - r^2));
K. L. Johnson, Contact Mechanics, 1985, eqs. 3.34 and 4.4 superposed)."""

from __future__ import annotations

import numpy as np
import pytest

from ibfem.solver.contact.edge_pressure import SLIVER_FRACTION, agglomerated_cells


def _quarter_disc(c: float, n_r: int = 160, n_t: int = 320):
    """Points and exact areas of a midpoint rule in polar coordinates on the quarter disc."""
    r = (np.arange(n_r) + 0.5) / n_r * c
    t = (np.arange(n_t) + 0.5) / n_t * (np.pi / 2)
    R, T = np.meshgrid(r, t, indexing="ij")
    w = (R * (c / n_r) * (np.pi / 2 / n_t)).ravel()
    return np.stack([R.ravel() * np.cos(T.ravel()), R.ravel() * np.sin(T.ravel())], axis=1), w


def _pressed(c: float, a: float, r: np.ndarray) -> np.ndarray:
    """A rigid sphere (R = 1, E* / pi = 1) at the approach a^2 with the contact radius c >= a."""
    return 2.0 * np.sqrt(c**2 - r**2) - (c**2 - a**2) / np.sqrt(c**2 - r**2)


def test_merged_means_conserve_the_integral_and_fill_three_quarters_of_a_cell():
    s, w = _quarter_disc(1.0)
    p = _pressed(1.0, 1.0, np.hypot(*s.T))
    cells = agglomerated_cells(s, w, p, 1.0 / 5.2)
    assert cells.cut.any() and len(cells.means) < len(np.unique(np.floor(s * 5.2 + 1e-6), axis=0))
    assert cells.areas.sum() == pytest.approx(w.sum(), rel=1e-12)
    assert cells.means @ cells.areas == pytest.approx(w @ p, rel=1e-12)
    assert cells.areas.min() >= SLIVER_FRACTION * (1.0 / 5.2) ** 2


def test_a_slivers_tension_balanced_by_its_neighbour_is_read_away():
    """Each sliver (a square the region fills less than three quarters) carries a tension of twice the peak
    whose force the square inward of it carries: the sliver's own mean is tensile, the merged
    means are Hertz's."""
    h = 1.0 / 5.2
    s, w = _quarter_disc(1.0)
    hertz = _pressed(1.0, 1.0, np.hypot(*s.T))
    plain = agglomerated_cells(s, w, hertz, h)
    key = np.floor(s / h + 1e-6).astype(int)
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    area = np.bincount(inverse, weights=w)
    artefact = np.zeros(len(s))
    for k in np.flatnonzero(area < SLIVER_FRACTION * h * h):
        sliver = inverse == k
        partner = plain.point_group == plain.point_group[np.flatnonzero(sliver)[0]]
        neighbour = partner & ~sliver
        artefact[sliver] = -4.0
        artefact[neighbour] = 4.0 * w[sliver].sum() / w[neighbour].sum()
    cells = agglomerated_cells(s, w, hertz + artefact, h)
    np.testing.assert_allclose(cells.means, plain.means, rtol=1e-9, atol=1e-9)
    assert (cells.means[cells.cut] > 0.0).all()
    own = np.bincount(inverse, weights=w * (hertz + artefact)) / area
    assert own.min() < -1.0


@pytest.mark.parametrize("cells_per_radius, too_large", [(5.2, 0.2), (10.0, 0.10), (20.0, 0.05)])
def test_edge_means_are_compressive_for_hertz_and_tensile_for_a_region_too_large(cells_per_radius, too_large):
    h = 1.0 / cells_per_radius
    for c, tensile in ((1.0, False), (1.0 + too_large, True)):
        s, w = _quarter_disc(c)
        p = _pressed(c, 1.0, np.hypot(*s.T))
        cells = agglomerated_cells(s, w, p, h)
        assert (cells.means[cells.cut].min() < 0.0) == tensile
