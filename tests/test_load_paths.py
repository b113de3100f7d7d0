"""Load paths: the piecewise-linear factors, the cycle generator, the step times, the scene keys
(their errors name the key), the split of the load by factor (linearity: the columns summed are
the assembled load) and path independence of frictionless contact (a path ending at the same
loads gives the same state as proportional loading)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.io.scene import SceneError, scene_from_dict
from ibfem.solver.model.load_paths import LoadHistory, LoadPath, cycle_points

from _contact_scenes import E, NU, cylinder_on_block


def test_path_interpolates_and_holds():
    p = LoadPath("p", [[0.0, 0.0], [1.0, 2.0], [3.0, -2.0]])
    assert np.allclose(p.factor([0.0, 0.5, 1.0, 2.0, 3.0, 5.0]), [0.0, 1.0, 2.0, 0.0, -2.0, -2.0])
    assert p.end == 3.0
    with pytest.raises(ValueError, match="increase strictly"):
        LoadPath("q", [[0.0, 0.0], [1.0, 1.0], [1.0, 2.0]])


def test_cycle_points_are_a_sampled_sine():
    pts = cycle_points(amplitude=2.0, cycles=2, points_per_cycle=4, mean=0.5, start=1.0)
    # a ramp from 0 at t = 0 to the mean at the start, then the triangle wave of 4 points per cycle
    assert np.allclose(pts[:, 0], [0.0, 1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 2.75, 3.0])
    assert np.allclose(pts[:, 1], [0.0, 0.5, 2.5, 0.5, -1.5, 0.5, 2.5, 0.5, -1.5, 0.5])
    fine = cycle_points(1.0, 1, points_per_cycle=64)
    assert np.allclose(fine[:, 1], np.sin(2 * math.pi * fine[:, 0]), atol=1e-12)


def test_times_hit_every_corner():
    h = LoadHistory(paths={"a": LoadPath("a", [[0, 0], [1, 1], [1.3, 0.5], [2, 0]])}, assignments=(("a",),),
                    steps_per_unit=2)
    t = h.times()
    assert np.allclose(t, [0.5, 1.0, 1.3, 1.5, 2.0])
    assert h.factor("", 1.0) == pytest.approx(0.5)  # a condition without a path: a ramp to the end


def _scene(paths=None, bc_path=None, solver=None):
    data = {
        "name": "paths", "model": "plane_strain",
        "solver": solver or {},
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU}],
        "bodies": [{"name": "plate", "material": "steel", "element_size": 0.25,
                    "shape": {"type": "rectangle", "min": [0, 0], "max": [2, 1]}}],
        "boundary_conditions": [
            {"body": "plate", "edge": "left", "type": "fixed"},
            {"body": "plate", "edge": "right", "type": "traction", "value": [1.0e6, 2.0e5],
             **({} if bc_path is None else {"path": bc_path})},
        ],
    }
    if paths is not None:
        data["paths"] = paths
    return scene_from_dict(data, label="s.toml")


@pytest.mark.parametrize("paths, bc_path, key, words", [
    ([{"name": "a", "points": [[0, 0], [1, 1]]}], "b", "boundary_conditions[1].path", "unknown load path"),
    ([{"name": "a", "points": [[0, 0], [1, 1]]}], ["a", "a", "a"], "boundary_conditions[1].path", "one per component"),
    ([{"name": "a", "points": [[0, 0], [1, 1]]}, {"name": "a", "points": [[0, 0]]}], None, "paths[1].name",
     "duplicate"),
    ([{"name": "a", "points": [[0, 0], [1, 1]], "cycle": {"amplitude": 1, "cycles": 1}}], None, "paths[0]",
     "not both"),
    ([{"name": "a", "points": [[1, 0], [0.5, 1]]}], None, "paths[0]", "increase strictly"),
    ([{"name": "a", "cycle": {"amplitude": 1, "cycles": 0}}], None, "paths[0].cycle.cycles", "greater than 0"),
    ([{"name": "a", "points": [[0, 0]], "ramp": 1}], None, "paths[0].ramp", "unknown key"),
])
def test_scene_errors_name_the_key(paths, bc_path, key, words):
    with pytest.raises(SceneError) as err:
        _scene(paths, bc_path)
    text = str(err.value)
    assert f"s.toml: {key}" in text and words in text, text


def test_steps_per_unit_is_checked():
    with pytest.raises(SceneError, match=r"solver.steps_per_unit = 0"):
        _scene([{"name": "a", "points": [[0, 0], [1, 1]]}], "a", {"steps_per_unit": 0})


def test_load_columns_sum_to_the_assembled_load():
    """Linearity: the columns of each factor, summed with factor 1, are the assembled load."""
    from ibfem.solver.fem.assembly import assemble
    from ibfem.solver.fem.bodies import discretise
    from ibfem.solver.fem.path_loads import path_loads

    problem = _scene([{"name": "x", "points": [[0, 0], [1, 1]]}, {"name": "y", "points": [[0, 0], [2, 1]]}],
                     ["x", "y"]).problem
    bodies = discretise(problem, problem.options)
    loads = path_loads(problem, bodies, problem.options)
    assert set(loads.names) == {"x", "y"}
    full = assemble(problem, bodies, problem.options).load
    assert np.allclose(loads.columns.sum(axis=1), full, rtol=0, atol=1e-9 * np.abs(full).max())
    # at t = 1 path "y" is at half: the load is the x column plus half the y column
    k = loads.names.index("y")
    expected = loads.columns.sum(axis=1) - 0.5 * loads.columns[:, k]
    assert np.allclose(loads.load(1.0), expected, atol=1e-9 * np.abs(full).max())


def test_frictionless_contact_is_path_independent():
    """Frictionless contact under a path that overshoots and comes back ends in the state of
    proportional loading to the same loads (summary steps record every step)."""
    from ibfem.solver.solving import solve



    plain = cylinder_on_block("frictionless", uy=-2.0e-3, load_steps=1)
    from ibfem.solver.model.load_paths import LoadHistory as H

    history = H(paths={"up": LoadPath("up", [[0, 0], [1, 1.5], [2, 1.0]])}, assignments=(("up",), None),
                steps_per_unit=1)
    import dataclasses

    pathed = dataclasses.replace(plain, history=history)
    a = solve(plain)
    b = solve(pathed)
    assert b.converged and len(b.steps) == 2
    assert [st["t"] for st in b.steps] == [1.0, 2.0]
    ca, cb = a.contacts[0], b.contacts[0]
    assert cb["half_width"] == pytest.approx(ca["half_width"], rel=2e-4)
    assert cb["normal_force"] == pytest.approx(ca["normal_force"], rel=2e-4)
    # the overshoot step carries 1.5 times the load: N grows (Hertz: a ~ sqrt(N))
    n1 = b.steps[0]["contacts"][0]["normal_force"]
    assert n1 > 1.3 * cb["normal_force"]


def test_paths_without_contact_scale_each_component():
    """A plate pulled by a traction whose x component follows a cycle and y a ramp: each step's
    reaction at the fixed edge balances the traction's resultant at that t (equilibrium)."""
    from ibfem.solver.solving import solve

    sc = _scene([{"name": "cyc", "cycle": {"amplitude": 1.0, "cycles": 1, "points_per_cycle": 4}},
                 {"name": "ramp", "points": [[0, 0], [1, 1]]}], ["cyc", "ramp"], {"steps_per_unit": 4})
    sol = solve(sc.problem)
    assert sol.converged and [st["t"] for st in sol.steps] == [0.25, 0.5, 0.75, 1.0]
    factors_x = [1.0, 0.0, -1.0, 0.0]
    for st, fx in zip(sol.steps, factors_x):
        applied = np.array([1.0e6 * fx, 2.0e5 * st["t"]]) * 1.0  # traction x the right edge's length (1 m)
        reaction = np.asarray(st["reactions"]["plate/left"])
        assert np.allclose(reaction, -applied, atol=1e-6 * 1.0e6), (st["t"], reaction, applied)


def test_step_files(tmp_path):
    """summary.json steps, steps.csv and a ParaView series with one dataset per step and body."""
    import json

    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.solving import solve

    sc = _scene([{"name": "ramp", "points": [[0, 0], [1, 1], [2, 0.5]]}], "ramp", {"steps_per_unit": 2})
    summary = write_scene_results(tmp_path, sc, solve(sc.problem))
    assert [s["t"] for s in summary["steps"]] == [0.5, 1.0, 1.5, 2.0]
    assert "field" not in summary["steps"][0]
    on_disk = json.loads((tmp_path / "summary.json").read_text())
    assert on_disk["steps"][2]["reactions"]["plate/left"][0] == pytest.approx(-0.75e6, rel=1e-6)
    rows = np.loadtxt(tmp_path / "steps.csv", delimiter=",", skiprows=1, ndmin=2)
    assert rows.shape[0] == 4
    pvd = (tmp_path / "steps.pvd").read_text()
    assert pvd.count("<DataSet ") == 4 and 'timestep="1.5"' in pvd
    for k in range(1, 5):
        assert (tmp_path / "steps" / f"step_{k:04d}" / "plate.vtu").is_file()
