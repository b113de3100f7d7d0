"""The number-making helpers of the 2D peer study (benchmarks/peers.py, steel and aluminium): the
graded rungs' refinement zones, the errors in a and N against the references and the time to an
error in both, each against a hand computation. Nothing here needs NGSolve."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from ibfem.solver.io.scene import scene_from_dict

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"


def _load(name: str):
    if str(BENCHMARKS) not in sys.path:
        sys.path.insert(0, str(BENCHMARKS))
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


peers = _load("peers")


def test_graded_zones_coarsen_one_level_per_doubling():
    zones = peers.graded_zones(4, 0.12)
    assert [z["levels"] for z in zones] == [4, 3, 2, 1]
    assert [z["radius"] for z in zones] == pytest.approx([0.12, 0.24, 0.48, 0.96], rel=1e-15)
    # the cell size h0 / 2^levels over the zone's radius is the same in every zone
    assert {round(z["radius"] * 2.0 ** z["levels"], 12) for z in zones} == {1.92}
    assert all(z["around"] == "contact" for z in zones)


def test_graded_rung_scene_reads_with_its_zones():
    data = peers.scene_data("aluminium", 0.2, 5, 0.12)
    for body in data["bodies"]:
        assert body["element_size"] == 0.2
        assert [z["levels"] for z in body["refinement"]] == [5, 4, 3, 2, 1]
        assert [z["radius"] for z in body["refinement"]] == pytest.approx([0.12, 0.24, 0.48, 0.96, 1.92])
    scene = scene_from_dict(data, label="peer aluminium")     # a scene ibfem accepts
    for body in scene.problem.bodies:
        zones = sorted((int(r.levels), r.radius) for r in body.refinements)
        assert [z[0] for z in zones] == [1, 2, 3, 4, 5]
        assert [z[1] for z in zones] == pytest.approx([1.92, 0.96, 0.48, 0.24, 0.12])
    uniform = peers.scene_data("steel", 0.05, 3)       # the earlier ladder: the base scene's one zone
    assert [(z["levels"], z["radius"]) for z in uniform["bodies"][0]["refinement"]] == [(3, 0.3)]


def test_error_in_a_and_n_is_the_larger_of_the_two():
    spec = peers.PROBLEMS["steel"]
    row = peers.add_errors({"problem": "steel", "code": "NGSolve P2", "a": spec["a"] * 0.998,
                            "a_fit": spec["a"] * 1.0005, "N": spec["N"] * 1.001})
    assert row["a_error"] == pytest.approx(-0.002, abs=1e-12)
    assert row["aN_error"] == pytest.approx(0.002, abs=1e-12)          # a's error leads
    assert row["a_fitN_error"] == pytest.approx(0.001, abs=1e-12)      # N's error leads
    # a lucky a does not reach a target its force misses
    rows = [{"wall_s": 1.0, "cpu_s": 1.0, "peak_mb": 10.0, **peers.add_errors(
                {"problem": "steel", "code": "ibfem", "a": spec["a"], "N": spec["N"] * 1.005})},
            {"wall_s": 2.0, "cpu_s": 2.0, "peak_mb": 20.0, **peers.add_errors(
                {"problem": "steel", "code": "ibfem", "a": spec["a"] * 0.9995, "N": spec["N"] * 1.0008})}]
    assert peers.time_to_error(rows, 0.001, "a_error")["time_s"] == 1.0
    assert peers.time_to_error(rows, 0.001, "aN_error")["time_s"] > 1.0
    cmp = peers.comparisons_2d(rows, ["steel"])
    assert [c["of"] for c in cmp] == ["a and N"] * 6
    assert [c["ngsolve_a"] for c in cmp] == ["gap closing"] * 3 + ["gap opening fit"] * 3
