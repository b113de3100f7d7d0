"""The command line: exit 1 always comes with summary.json; an
exception the program did not expect exits 5 with one line saying it is a bug and how to see the
traceback; a failure inside numpy / scipy is never reported as a scene error (exit 2), and the
issue's numpy reproducers are caught by the scene check with their key path."""

from __future__ import annotations

import copy
import json
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.cli import INTERNAL_ERROR, main
from ibfem.solver.commands import error_origin
from ibfem.solver.io.scene import SceneError, load_scene

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "cylinder_on_cylinder_frictionless.toml"
LAME = ROOT / "examples" / "single_body" / "lame_quarter_annulus.toml"


def _numpy_failure(problem, progress=None):
    # what the issue saw: np.interp on arrays of different lengths, deep in the solver
    np.interp(0.5, np.arange(3.0), np.arange(4.0))


def _key_failure(problem, progress=None):
    raise ValueError("contacts[0]: the contact region reaches the end of edge 'arc'")


# --- class 3: exit codes --------------------------------------------------------------------------


@pytest.mark.parametrize("crash", [KeyError("JQX"), ZeroDivisionError("float division by zero"),
                                   RecursionError("maximum recursion depth exceeded")])
def test_class3_unexpected_errors_exit_5_with_one_line(tmp_path, capsys, monkeypatch, crash):
    import ibfem.solver.solving
    from ibfem import solver

    def fail(problem, progress=None):
        raise crash

    monkeypatch.setattr(solver.solving, "solve", fail)
    code = main(["run", str(LAME), "--quiet", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == INTERNAL_ERROR == 5
    assert err.count("\n") == 1 and "bug" in err and "--traceback" in err
    assert not (tmp_path / "o").exists()  # no summary: not exit 1


def test_class3_traceback_option_shows_it(monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    monkeypatch.setattr(solver.solving, "solve", _numpy_failure)
    with pytest.raises(ValueError, match="fp and xp"):
        main(["run", str(LAME), "--quiet", "--traceback"])


def test_class3_exit_1_always_has_its_summary(tmp_path):
    """A real non-converged run (solver.tolerance = 1e-300: the residual work of no state is
    below it): exit 1 and summary.json with converged false, through the console script."""
    data = tomllib.loads(EXAMPLE.read_text())
    data["solver"].update(tolerance=1e-300)
    data["output"] = {"vtk": False, "plots": False}
    scene = tmp_path / "s.json"
    scene.write_text(json.dumps(data))
    r = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(scene), "--quiet", "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["converged"] is False
    assert "Traceback" not in r.stderr and "not converged" in r.stderr


# --- class 4: numpy / scipy internals are never scene errors ---------------------------------------


def test_class4_a_numpy_failure_is_an_internal_error_naming_the_solver_function(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    monkeypatch.setattr(solver.solving, "solve", _numpy_failure)
    assert main(["run", str(LAME), "--quiet", "--out", str(tmp_path / "o")]) == 5
    err = capsys.readouterr().err
    assert "numpy reported" in err and "fp and xp" in err and "bug" in err and err.count("\n") == 1


def test_class4_the_solvers_own_value_errors_stay_scene_errors(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    monkeypatch.setattr(solver.solving, "solve", _key_failure)
    assert main(["run", str(LAME), "--quiet"]) == 2
    assert "contacts[0]" in capsys.readouterr().err


def test_class4_error_origin():
    try:
        _numpy_failure(None)
    except ValueError as err:
        library, where = error_origin(err)
    assert library == "numpy" and where == "the solver"  # this test module is not the project's code
    try:
        _key_failure(None)
    except ValueError as err:
        assert error_origin(err)[0] is None
    from ibfem.solver.model.resolve import finest_size_at

    try:  # a project function whose numpy call fails: the library and the function are named
        finest_size_at(None, np.zeros(2))
    except AttributeError as err:
        assert error_origin(err) == (None, "ibfem.solver.model.resolve.finest_size_at")


@pytest.mark.parametrize("mutate, key", [
    # "fp and xp are not of the same length": a contact point not on the first body
    (lambda d: d["contacts"][0].update(point=[0.0, 0.5]), "contacts[0].point"),
    # "zero-size array to reduction operation minimum": element_size 1e-300
    (lambda d: d["bodies"][0].update(element_size=1e-300), "element_size"),
    # "array must not contain infs or NaNs": a displacement of 1e300
    (lambda d: d["boundary_conditions"][0].update(value=[0.0, 1e300]), "boundary_conditions[0].value[1]"),
    # variants: a traction and a body force of 1e300
    (lambda d: d["boundary_conditions"].append({"type": "traction", "body": "upper", "edge": "arc",
                                                "value": [0.0, 1e300]}), "boundary_conditions[2].value[1]"),
    (lambda d: d["boundary_conditions"].append({"type": "body_force", "body": "upper", "value": [0.0, -1e300]}),
     "boundary_conditions[2].value[1]"),
])
def test_class4_the_issues_numpy_reproducers_are_scene_errors_with_their_key(mutate, key):
    data = copy.deepcopy(tomllib.loads(EXAMPLE.read_text()))
    mutate(data)
    with pytest.raises(SceneError) as err:
        load_scene(data, label="s.toml", base_dir=EXAMPLE.parent)
    assert key in str(err.value)
    for internal in ("fp and xp", "zero-size array", "infs or NaNs"):
        assert internal not in str(err.value)


def test_class3_every_command_takes_traceback():
    """The internal-error line tells the user to rerun with --traceback: every command takes it."""
    from ibfem.solver.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name, command in sub.choices.items():
        assert any("--traceback" in a.option_strings for a in command._actions), name
