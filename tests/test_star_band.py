"""Where the refinement that follows a line contact's region refines one level more
(solver.contact.region_band and solver.contact.follow): the stretches along the line where the
region's smooth edge runs at more than TURNING_SLOPE to it. Checked on regions whose edge is known
in closed form (a quarter of a superellipse |x / a|^4 + |y / b|^4 = 1, whose slope
dy/dx = -(b / a) (x / a)^3 (1 - (x / a)^4)^(-3/4) gives where the threshold is crossed, found here
by bisection), on a straight-sided region ending at a free edge (none), and on the coarse pass's
retry one level finer, with stand-in solutions (nothing is solved)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.optimize import brentq

from ibfem.solver.contact import follow
from ibfem.solver.contact.star_region import EDGE_WINDOW_CELLS
from ibfem.solver.contact.region_band import TURNING_SLOPE, band_balls, side_balls, turning_balls, turning_stretches
from ibfem.solver.io.scene import scene_from_dict

A, B, MARGIN = 0.08, 0.024, 0.0125


def _quarter_block(edge: np.ndarray, free: np.ndarray | None = None) -> dict:
    """A quarter model's contact block: the boundary from the contact point along the edge
    (x >= 0, y >= 0, from the tip on the line to mid-length) and back, frame = global axes."""
    pts = np.vstack([[0.0, 0.0], edge])
    flags = np.concatenate([[False], free if free is not None else np.zeros(len(edge), bool)])
    return {"point": [0.0, 0.0, 0.0], "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            "boundary": {"points": np.column_stack([pts, np.zeros(len(pts))]).tolist(),
                         "free_edge": flags.tolist()}}


def _superellipse(n: int = 400) -> np.ndarray:
    t = np.linspace(0.0, 0.5 * math.pi, n)
    c, s = np.cos(t), np.sin(t)
    return np.column_stack([A * np.sign(c) * np.abs(c) ** 0.5, B * np.abs(s) ** 0.5])


def test_the_turning_stretch_of_a_superellipse_starts_where_its_slope_reaches_the_threshold():
    block = _quarter_block(_superellipse())

    def slope(x):
        u = x / A
        return (B / A) * u**3 * (1.0 - u**4) ** -0.75 - TURNING_SLOPE

    start = brentq(slope, 1e-6, A * (1 - 1e-12))
    (a, b, width), = turning_stretches(block, MARGIN)
    assert a == pytest.approx(start - MARGIN, abs=5e-4)  # the polyline's pieces are about 0.2 mm
    assert b == pytest.approx(A + MARGIN, abs=1e-9)  # the tip runs across the line
    assert width == pytest.approx(B * (1.0 - ((start - MARGIN) / A) ** 4) ** 0.25, abs=5e-4)
    (centres, radius), = turning_balls(block, MARGIN, 0.01)
    assert radius == pytest.approx(MARGIN + 0.01)
    np.testing.assert_allclose((centres[:, 0] / A) ** 4 + (centres[:, 1] / B) ** 4, 1.0, atol=1e-9)  # on the edge
    edge = _superellipse(4000)
    edge = edge[(edge[:, 0] >= a) & (edge[:, 0] <= b)]
    gap = np.hypot(*(edge[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)).min(axis=1)
    assert gap.max() <= 0.5 * radius + 5e-4  # the edge's stretch within half a radius of a centre


def test_the_band_covers_the_whole_region():
    block = _quarter_block(_superellipse())
    centres, radius = band_balls(block, MARGIN)
    assert radius == pytest.approx(B + MARGIN, abs=1e-9)
    assert centres[0] == pytest.approx(0.0) and centres[-1] == pytest.approx(A)
    assert np.diff(centres).max() <= radius + 1e-12


def test_a_straight_side_ending_at_a_free_edge_is_not_refined_further():
    """A straight roller's region: straight sides, ended by the end face (complete contact) where
    the edge turns across the line within a cell of the free edge."""
    end = np.column_stack([np.full(12, 0.1), np.linspace(0.0, 0.022, 12)])
    corner = np.array([[0.0995, 0.0232], [0.098, 0.0238]])  # the edge bends into the corner
    side = np.column_stack([np.linspace(0.09, 0.0, 30), np.full(30, 0.024)])
    edge = np.vstack([end, corner, side])
    free = np.concatenate([np.ones(12, bool), np.zeros(len(corner) + len(side), bool)])
    assert turning_stretches(_quarter_block(edge, free), MARGIN) == []
    # the same region without the free edge: its end turns across the line and is refined
    (a, b, _), = turning_stretches(_quarter_block(edge), MARGIN)
    assert a == pytest.approx(0.098 - MARGIN) and b == pytest.approx(0.1 + MARGIN)


def test_the_sides_balls_cover_the_smooth_edge_outside_the_turning_stretches():
    """On the superellipse's quarter the side balls lie on the edge from mid-length to where the
    turning stretch starts, covering it to half their radius; on a straight roller's region they
    keep a margin from the free edge."""
    block = _quarter_block(_superellipse())
    (a, _, _), = turning_stretches(block, MARGIN)
    centres, radius = side_balls(block, MARGIN, 0.01)
    assert radius == 0.01 and len(centres)
    np.testing.assert_allclose((centres[:, 0] / A) ** 4 + (centres[:, 1] / B) ** 4, 1.0, atol=1e-9)
    assert centres[:, 0].max() < a
    edge = _superellipse(4000)
    edge = edge[edge[:, 0] < a - 0.5e-3]
    gap = np.hypot(*(edge[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)).min(axis=1)
    assert gap.max() <= 0.5 * radius + 5e-4
    end = np.column_stack([np.full(12, 0.1), np.linspace(0.0, 0.022, 12)])
    side = np.column_stack([np.linspace(0.098, 0.0, 60), np.full(60, 0.024)])
    free = np.concatenate([np.ones(12, bool), np.zeros(len(side), bool)])
    centres, _ = side_balls(_quarter_block(np.vstack([end, side]), free), MARGIN, 0.01)
    assert np.allclose(centres[:, 1], 0.024) and centres[:, 0].max() < 0.1 - MARGIN
    assert centres[:, 0].min() <= 0.005


def _stand_in(converged: bool, cells: float):
    block = _quarter_block(_superellipse())
    block["cells_per_semi_axis"] = [cells * A / B, cells]
    return SimpleNamespace(converged=converged, contacts=[block], iterations={"total": 1})


def test_an_unresolved_coarse_pass_is_repeated_one_level_finer(monkeypatch):
    levels = []
    monkeypatch.setattr(follow, "coarse_problem", lambda p, lines, fewer=2: levels.append(fewer) or p)
    answers = iter([_stand_in(False, 0.9), _stand_in(True, 1.9)])
    coarse, fewer, tried = follow.coarse_pass(SimpleNamespace(), [0], lambda p: next(answers))
    assert levels == [2, 1] and fewer == 1 and coarse.converged
    assert [t["converged"] for t in tried] == [False, True]


def test_a_resolved_coarse_pass_is_kept_and_the_finest_keeps_a_level_to_spare(monkeypatch):
    levels = []
    monkeypatch.setattr(follow, "coarse_problem", lambda p, lines, fewer=2: levels.append(fewer) or p)
    _, fewer, _ = follow.coarse_pass(SimpleNamespace(), [0], lambda p: _stand_in(True, 1.8))
    assert levels == [2] and fewer == 2
    levels.clear()
    _, fewer, tried = follow.coarse_pass(SimpleNamespace(), [0], lambda p: _stand_in(False, 0.5))
    assert levels == [2, 1] and fewer == 1 and len(tried) == 2  # never the scene's own levels


SCENES = Path(__file__).resolve().parent / "scenes"


def _with_contact_ball(path: Path, levels: int):
    """A scene with its refinements replaced by one contact ball of ``levels`` levels."""
    data = tomllib.loads(path.read_text())
    for body in data["bodies"]:
        body["refinement"] = {"levels": levels, "around": "contact", "radius": 0.13}
    return scene_from_dict(data, label=path.name).problem


def test_an_elongated_contact_reaching_a_free_end_is_followed_and_its_turning_edge_refined():
    """Lundberg's roller (relative curvatures 0.21 and 2 1/m, the roller ending along the line)
    is followed as a line contact is; its fine pass has the contact ball at the coarse levels,
    the band at the scene's and balls one level finer on the coarse edge where it turns."""
    problem = _with_contact_ball(SCENES / "lundberg_roller.toml", 4)
    assert follow.line_contacts(problem) == [0]
    block = _quarter_block(_superellipse())
    fine, record = follow.band_problem(problem, [0], [block], 1)
    for body in fine.bodies:
        levels = sorted({z.levels for z in body.refinements})
        assert levels == [3, 4, 5]  # the coarse ball, the band, the turning edge
        finer = np.array([z.center[:2] for z in body.refinements if z.levels == 5])
        np.testing.assert_allclose((finer[:, 0] / A) ** 4 + (finer[:, 1] / B) ** 4, 1.0, atol=1e-9)
    assert record["roller"]["finer"][0]["levels"] == 5
    # the finer balls reach TURNING_REACH_CELLS coarse cells beyond the coarse edge (where the
    # edge may lie) plus the edge condition's window of the finer cells
    coarse = follow.finest_contact_cell(follow.coarse_problem(problem, [0], 1), ["roller", "block"])
    fine = follow.finest_contact_cell(problem, ["roller", "block"])
    window = EDGE_WINDOW_CELLS * 0.5 * fine
    assert record["roller"]["finer"][0]["radius"] == pytest.approx(follow.TURNING_REACH_CELLS * coarse + window, rel=1e-12)
    assert record["roller"]["radius"] == pytest.approx(B + coarse, rel=1e-9)  # the band: a whole cell
    # the band's cells resolve the half-width with fewer than SIDE_MIN_CELLS: its straight sides
    # get thinner balls one level finer (SIDE_REACH_CELLS coarse cells beyond the edge, plus
    # SIDE_WINDOW_CELLS of the finer cells), none where the half-width spans more band cells
    if follow.SIDE_REACH_CELLS is not None:
        assert B < follow.SIDE_MIN_CELLS * fine
        side = record["roller"]["finer"][-1]
        assert side["radius"] == pytest.approx(follow.SIDE_REACH_CELLS * coarse + follow.SIDE_WINDOW_CELLS * 0.5 * fine)
        assert max(x for x, _, _ in side["centres"]) < turning_stretches(block, coarse)[0][0]
        wide = _quarter_block(_superellipse() * np.array([1.0, follow.SIDE_MIN_CELLS * fine / B * 1.01]))
        _, wide_record = follow.band_problem(problem, [0], [wide], 1)
        assert len(wide_record["roller"]["finer"]) == len(turning_balls(wide, coarse, window))
