"""The memory check when a scene is loaded: a 3D line contact whose refinement follows its
region is solved on a coarse pass and then a band along the region, never on the scene's whole
contact ball at its depth; the check judges the coarse pass (what is known before a solve), so a
scene whose ball alone would not fit is not refused."""

from pathlib import Path

import pytest

from ibfem.solver.contact.follow import coarse_problem, line_contacts
from ibfem.solver.io import scene as scene_module
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model import estimate

ROOT = Path(__file__).resolve().parents[1]
ROLLER = ROOT / "examples" / "contact3d" / "crowned_roller.toml"


def test_a_followed_line_contact_is_judged_by_its_coarse_pass(monkeypatch):
    problem = load_scene(ROLLER).problem
    lines = line_contacts(problem)
    assert lines == [0]
    monkeypatch.setattr(estimate, "loaded_scene_bytes", lambda: 2.0e8)  # the process's own share, fixed
    ball = estimate.estimate_size(problem).memory
    coarse = estimate.estimate_size(coarse_problem(problem, lines)).memory
    assert coarse < ball  # two levels shallower about the contact
    monkeypatch.setattr(estimate, "available_memory", lambda: 0.5 * (coarse + ball))
    assert scene_module.size_problems(problem, "roller.toml") == []
    monkeypatch.setattr(estimate, "available_memory", lambda: 0.5 * coarse)
    (message,) = scene_module.size_problems(problem, "roller.toml")
    assert message.startswith("roller.toml: the coarse pass of its line contacts would need")
    assert f"{coarse / 2**30:.3g} GB" in message


def test_a_point_contact_is_judged_by_its_whole_grid(monkeypatch):
    problem = load_scene(ROOT / "examples" / "solid" / "sphere_on_flat.toml").problem
    assert line_contacts(problem) == []
    monkeypatch.setattr(estimate, "loaded_scene_bytes", lambda: 2.0e8)
    whole = estimate.estimate_size(problem).memory
    monkeypatch.setattr(estimate, "available_memory", lambda: 0.9 * whole)
    (message,) = scene_module.size_problems(problem, "ball.toml")
    assert message.startswith("ball.toml: the grids would need")
