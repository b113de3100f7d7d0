"""The balls one level finer about a pressure peak next to where a line contact's edge turns
(solver.contact.region_band.peak_balls): checked on a quarter model's region whose edge is a
superellipse |x / a|^4 + |y / b|^4 = 1 and whose pressure map holds the square means of a closed
form, with a sharp peak on the line before the end narrows (as a crowned roller's end peak), or
falling monotonically from mid-length (a plateau, as Lundberg's roller: no peak by the end).
Nothing is solved."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.contact import follow
from ibfem.solver.contact.region_band import peak_balls, symmetry_maps, turning_balls, turning_stretches
from ibfem.solver.io.scene import scene_from_dict

A, B, MARGIN, CELL = 0.08, 0.024, 0.0125, 0.0125
RADIUS = MARGIN + 0.0094  # a turning ball's: a coarse cell plus three of the finer cells
SCENES = Path(__file__).resolve().parent / "scenes"


def _edge(n: int = 400) -> np.ndarray:
    t = np.linspace(0.0, 0.5 * math.pi, n)
    return np.column_stack([A * np.cos(t) ** 0.5, B * np.sin(t) ** 0.5])


def _block(pressure) -> dict:
    """A quarter model's contact block (boundary from the contact point along the line to the
    tip, round the superellipse's quarter and back along the other axis) with the pressure map
    of ``pressure(x, y)``: the means over CELL squares of the region, on 20 x 20 points each."""
    pts = np.vstack([[0.0, 0.0], _edge()])
    k = (np.arange(20) + 0.5) / 20.0
    centres, values, areas, keys = [], [], [], []
    for i in range(int(A / CELL) + 1):
        for j in range(int(B / CELL) + 1):
            x, y = np.meshgrid((i + k) * CELL, (j + k) * CELL, indexing="ij")
            inside = (x / A) ** 4 + (y / B) ** 4 < 1.0
            if inside.sum() < 4:
                continue
            centres.append([x[inside].mean(), y[inside].mean()])
            values.append(float(pressure(x[inside], y[inside]).mean()))
            areas.append(CELL**2 * inside.mean())
            keys.append([i, j])
    return {"point": [0.0, 0.0, 0.0], "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            "model_share": 0.25,
            "boundary": {"points": np.column_stack([pts, np.zeros(len(pts))]).tolist(),
                         "free_edge": [False] * len(pts)},
            "pressure_map": {"cell": CELL, "s": centres, "value": values, "area": areas, "square": keys}}


def _halfwidth(x):
    return B * np.clip(1.0 - (np.abs(x) / A) ** 4, 0.0, None) ** 0.25


def _end_peak(x, y, at: float = 0.055, width: float = 0.008):
    """Hertzian across the line, along it a base with a sharp bump at ``at`` (a crowned end's peak)."""
    across = np.sqrt(np.clip(1.0 - (y / np.maximum(_halfwidth(x), 1e-12)) ** 2, 0.0, None))
    return 2e9 * (1.0 + 0.6 * np.exp(-(((x - at) / width) ** 2))) * across


def test_the_symmetry_maps_of_a_quarter_model_are_its_mirror_images():
    maps = symmetry_maps(_block(_end_peak))
    assert len(maps) == 4
    assert {tuple(np.round(np.diag(m))) for m in maps} == {(1, 1), (1, -1), (-1, 1), (-1, -1)}


def test_a_peak_next_to_the_turning_end_gets_a_ball_on_the_line_at_its_place():
    """The peak of the closed form lies on the line (y = 0, a symmetry plane) at x = 55 mm, by the
    turning stretch (which starts a coarse cell before the superellipse's slope reaches 0.25):
    one ball, on the line, within half a square of the peak; a peak placed elsewhere along the
    stretch is followed."""
    for at in (0.050, 0.055, 0.062):
        block = _block(lambda x, y: _end_peak(x, y, at))
        (a, b, _), = turning_stretches(block, MARGIN)
        assert a - RADIUS <= at <= b
        centres = peak_balls(block, MARGIN, RADIUS)
        assert centres.shape == (1, 2)
        assert centres[0, 1] == pytest.approx(0.0, abs=1e-12)  # the mirror images put it on the line
        assert abs(centres[0, 0] - at) <= 0.5 * CELL


def test_a_pressure_falling_from_mid_length_gets_no_peak_ball():
    """Lundberg's plateau: the pressure falls monotonically from mid-length, so the largest square
    by the turning stretch is the rise towards the middle, not a peak."""
    block = _block(lambda x, y: 2e9 * (1.0 - (x / A) ** 8) * np.sqrt(np.clip(1.0 - (y / _halfwidth(x)) ** 2, 0.0, None)))
    assert turning_stretches(block, MARGIN)
    assert peak_balls(block, MARGIN, RADIUS).shape == (0, 2)


def test_no_map_no_peak_ball():
    block = _block(_end_peak)
    del block["pressure_map"]
    assert peak_balls(block, MARGIN, RADIUS).shape == (0, 2)


def test_the_fine_pass_refines_about_the_peak_one_level_finer():
    """In the fine pass (follow.band_problem) the peak's ball comes with the turning balls, at their
    level and radius; with follow.PEAK_BALLS False it is left out."""
    import tomllib

    data = tomllib.loads((SCENES / "lundberg_roller.toml").read_text())
    for body in data["bodies"]:
        body["refinement"] = {"levels": 4, "around": "contact", "radius": 0.13}
    problem = scene_from_dict(data, label="lundberg_roller.toml").problem
    block = _block(_end_peak)
    fine, record = follow.band_problem(problem, [0], [block], 1)
    finer = record["roller"]["finer"]
    turning = turning_balls(block, MARGIN, follow.EDGE_WINDOW_CELLS * 0.5 * follow.finest_contact_cell(problem, ["roller", "block"]),
                            follow.TURNING_REACH_CELLS * MARGIN)
    peak = finer[len(turning)]  # after the turning balls
    assert peak["levels"] == finer[0]["levels"] == 5 and peak["radius"] == pytest.approx(turning[0][1])
    assert len(peak["centres"]) == 1 and peak["centres"][0][1] == pytest.approx(0.0, abs=1e-12)
    assert abs(peak["centres"][0][0] - 0.055) <= 0.5 * CELL
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(follow, "PEAK_BALLS", False)
        _, without = follow.band_problem(problem, [0], [block], 1)
    assert len(without["roller"]["finer"]) == len(finer) - 1
