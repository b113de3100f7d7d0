"""``ibfem run``: exit codes, one-line scene errors without tracebacks, the summary kept on
non-convergence, the progress display, and one end-to-end run of the Lame scene checked
against the closed form."""

import io
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from _scene_standins import FieldBody, FieldSolution
from ibfem.solver.cli import main
from ibfem.solver.io.progress import ProgressReporter

ROOT = Path(__file__).resolve().parents[1]
LAME = ROOT / "examples" / "single_body" / "lame_quarter_annulus.toml"

PLATE = """
name = "plate"
[[materials]]
name = "steel"
youngs_modulus = 2.0e11
poissons_ratio = 0.3
[[bodies]]
name = "plate"
material = "{material}"
element_size = 0.1
shape = {{ type = "rectangle", min = [0.0, 0.0], max = [1.0, 1.0] }}
[[boundary_conditions]]
body = "plate"
edge = "bottom"
type = "fixed"
[output]
vtk = false
probes = [[0.5, 0.5]]
"""


def write_plate(tmp_path, material="steel"):
    path = tmp_path / "plate.toml"
    path.write_text(PLATE.format(material=material))
    return path


def test_scene_error_is_one_line_per_problem_and_exit_code_2(tmp_path, capsys):
    path = write_plate(tmp_path, material="stel")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ['ibfem run: plate.toml: bodies[0].material = "stel": unknown material (known: steel)']
    assert not (tmp_path / "out").exists()


def test_scene_error_through_the_console_script_has_no_traceback(tmp_path):
    path = write_plate(tmp_path, material="stel")
    r = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(path)], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 2
    assert "Traceback" not in r.stderr and r.stderr.count("\n") == 1 and "bodies[0].material" in r.stderr


def test_missing_file(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.toml")]) == 2
    assert "cannot read scene file" in capsys.readouterr().err


def test_check_only(tmp_path, capsys):
    assert main(["run", str(write_plate(tmp_path)), "--check"]) == 0
    assert "valid scene 'plate'" in capsys.readouterr().out


def fake_solution(converged):
    body = FieldBody("plate", (0.0, 0.0), (1.0, 1.0), a=1e-4, b=0.0)
    history = {"total": 7, "per_step": [3, 4], "residual": [1.0, 1e-3, 2e-5]}
    return FieldSolution(bodies=[body], converged=converged, iterations=history,
                         reactions={"plate/bottom": np.array([0.0, -5.0])})


def test_non_convergence_keeps_the_history_and_fails(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    calls = []

    def fake_solve(problem, progress=None):
        calls.append(problem)
        progress("load step", 0.5)
        return fake_solution(converged=False)

    monkeypatch.setattr(solver.solving, "solve", fake_solve)
    out = tmp_path / "out"
    assert main(["run", str(write_plate(tmp_path)), "--out", str(out), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "not converged after 7 iterations" in err and "Traceback" not in err
    data = json.loads((out / "summary.json").read_text())
    assert data["converged"] is False
    assert data["iterations"] == {"total": 7, "per_step": [3, 4], "residual": [1.0, 1e-3, 2e-5]}
    assert data["reactions"] == {"plate/bottom": [0.0, -5.0]}
    # the probe is the stand-in's closed-form field at (0.5, 0.5)
    assert data["probes"][0]["displacement"] == pytest.approx([1e-4 * 0.25, 0.0])
    assert calls[0].name == "plate" and data["scene"].endswith("plate.toml")


def test_non_convergence_prints_the_solvers_diagnosis(tmp_path, capsys, monkeypatch):
    """A non-converged run says why on stderr when the solver diagnosed it, not only in summary.json."""
    import ibfem.solver.solving
    from ibfem import solver

    diagnosis = "contact a/b: the contact is smaller than the grid resolves: refine it"

    def fake_solve(problem, progress=None):
        solution = fake_solution(converged=False)
        solution.iterations["messages"] = [diagnosis]
        return solution

    monkeypatch.setattr(solver.solving, "solve", fake_solve)
    assert main(["run", str(write_plate(tmp_path)), "--out", str(tmp_path / "out"), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "not converged after 7 iterations" in err
    assert f"plate.toml: {diagnosis}" in err


def test_converged_run_with_default_output_directory(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    def solved(problem, progress=None):
        sol = fake_solution(converged=True)
        sol.contacts = [{"bodies": ["plate", "pin"], "half_width": 0.0125, "normal_force": 2.5e6}]
        return sol

    monkeypatch.setattr(solver.solving, "solve", solved)
    path = write_plate(tmp_path)
    monkeypatch.chdir(tmp_path)
    assert main(["run", str(path), "--quiet", "--no-estimate"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("plate: converged in 7 iterations")
    assert out[1] == ("  contact plate / pin: half_width = 0.0125 m, stick_half_width = n/a, "
                      "normal_force = 2.5e+06 N/m, tangential_force = n/a")
    assert json.loads((tmp_path / "out" / "plate" / "summary.json").read_text())["converged"] is True


def test_solver_value_error_is_a_one_line_scene_error(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    def refuse(problem, progress=None):
        raise ValueError("body 'plate' is not held against rigid-body motion")

    monkeypatch.setattr(solver.solving, "solve", refuse)
    assert main(["run", str(write_plate(tmp_path)), "--quiet"]) == 2
    assert capsys.readouterr().err == "ibfem run: plate.toml: body 'plate' is not held against rigid-body motion\n"


def test_missing_solver_core(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ibfem.solver.solving", None)
    assert main(["run", str(write_plate(tmp_path)), "--quiet"]) == 3
    assert "solver core" in capsys.readouterr().err


class FakeClock:
    def __init__(self):
        self.t = 0.0

    def __call__(self):
        return self.t


def test_progress_is_quiet_on_short_runs_and_throttled_on_long_ones():
    clock, stream = FakeClock(), io.StringIO()
    rep = ProgressReporter(stream=stream, delay=1.0, interval=5.0, clock=clock)
    rep("grid", 0.1)
    clock.t = 0.5
    rep("assembly", 0.3)
    assert stream.getvalue() == ""  # nothing during the first second
    clock.t = 1.5
    rep("solve", 0.6)
    clock.t = 2.0
    rep("stress", 0.8)  # within the interval: held back
    assert stream.getvalue() == "[    1.5 s] solve (60 %)\n"
    clock.t = 7.0
    rep("load step", fraction=0.9, step=3)
    assert stream.getvalue().splitlines()[-1] == "[    7.0 s] load step step=3 (90 %)"
    clock.t = 7.5
    rep("done", 1.0)
    rep.close()  # the last message is shown at the end
    assert stream.getvalue().splitlines()[-1] == "[    7.5 s] done (100 %)"
    short = io.StringIO()
    quick = ProgressReporter(stream=short, delay=1.0, clock=FakeClock())
    quick("done", 1.0)
    quick.close()
    assert short.getvalue() == ""


def test_a_contact_solve_reports_each_region_trial():
    """The contact driver reports every trial of its region search (a long 3D search is a
    minute of trials), in order, within its load step's share of the run."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    messages = []
    solution = solve(load_scene(ROOT / "examples" / "cylinder_on_cylinder_frictionless.toml").problem,
                     progress=lambda text, fraction=None: messages.append((text, fraction)))
    trials = [(text, f) for text, f in messages if "region trial" in text]
    assert solution.converged and len(trials) == solution.iterations["total"] >= 2
    assert [int(re.search(r"region trial (\d+)", text)[1]) for text, _ in trials] == list(range(1, len(trials) + 1))
    fractions = [f for _, f in messages if f is not None]
    assert fractions == sorted(fractions) and all(0.3 <= f < 1.0 for _, f in trials)


def test_a_part_of_a_run_reports_within_its_share():
    """``share`` maps a part's own fractions into its share of the run and names the part."""
    from ibfem.solver.io.progress import share

    seen = []
    part = share(lambda *a, **k: seen.append((a, k)), 0.9, 1.0, "error estimate: ")
    part("assembly", 0.2)
    part("load step", fraction=0.5, step=3)
    part("grids")
    assert seen[0] == (("error estimate: assembly", pytest.approx(0.92)), {})
    assert seen[1] == (("error estimate: load step",), {"fraction": pytest.approx(0.95), "step": 3})
    assert seen[2] == (("error estimate: grids",), {})


def test_the_run_shows_its_error_estimate_after_its_solve_in_order(monkeypatch):
    """A contact run solves twice (the second, coarser solve is the error estimate): the progress
    goes on rising through both, the estimate's stages named as such, never back to 0 %."""
    from ibfem.solver.commands import _solve_scene
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    messages = []
    problem = load_scene(ROOT / "examples" / "cylinder_on_cylinder_frictionless.toml").problem
    solution, _ = _solve_scene(problem, solve, lambda text, fraction=None, **k: messages.append((text, fraction)),
                               estimate=True)
    assert solution.contacts[0]["estimated_error"]
    fractions = [f for _, f in messages if f is not None]
    assert fractions == sorted(fractions) and fractions[-1] == pytest.approx(1.0)
    estimate = [text for text, _ in messages if text.startswith("error estimate: ")]
    assert estimate and any("region trial" in text for text in estimate)
    first = [f for text, f in messages if f is not None and not text.startswith("error estimate")]
    assert max(first) == pytest.approx(0.9)


def lame(r, p=1e8, a=1.0, b=2.0, E=2e11, nu=0.3):
    """Thick cylinder under internal pressure, plane strain (Timoshenko & Goodier)."""
    k = p * a * a / (b * b - a * a)
    return (k * (1 - b * b / r**2), k * (1 + b * b / r**2),
            k * (1 + nu) / E * ((1 - 2 * nu) * r + b * b / r))


def test_end_to_end_lame_quarter_annulus(tmp_path):
    """The example scene on a coarser grid (0.04) through the console entry point; compared
    with the closed form. Tolerances sized for h = 0.04; the 0.02 acceptance run is the
    solver's validation."""
    pytest.importorskip("pyvista")
    scene = LAME.read_text().replace("element_size = 0.02", "element_size = 0.04").replace("plots = true", "plots = false")
    path = tmp_path / "lame.toml"
    path.write_text(scene)
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(path), "--out", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    data = json.loads((out / "summary.json").read_text())
    assert data["converged"] is True and data["model"] == "plane_strain"
    assert data["bodies"]["ring"]["element_size"] == 0.04 and data["bodies"]["ring"]["dofs"] > 0
    # each symmetry edge carries p * a = 1e8 N/m, normal to it
    assert np.allclose(data["reactions"]["ring/x_symmetry"], [0.0, -1e8], atol=0.02e8)
    assert np.allclose(data["reactions"]["ring/y_symmetry"], [-1e8, 0.0], atol=0.02e8)
    (probe,) = data["probes"]
    x = np.array(probe["point"])
    r_, th = np.hypot(*x), math.atan2(x[1], x[0])
    sr, st, ur = lame(r_)
    c, s = math.cos(th), math.sin(th)
    exact = [sr * c * c + st * s * s, sr * s * s + st * c * c, (sr - st) * s * c]
    assert np.allclose(probe["stress"], exact, atol=0.05 * 1e8)
    assert np.dot(probe["displacement"], [c, s]) == pytest.approx(ur, rel=0.01)
    line = data["lines"]["radial_45"]
    pts = np.array(line["points"])
    radius = np.hypot(pts[:, 0], pts[:, 1])
    u_r = np.einsum("ij,ij->i", np.array(line["displacement"]), pts / radius[:, None])
    assert np.allclose(u_r, lame(radius)[2], rtol=0.01)
    assert (out / "ring.vtu").stat().st_size > 1000 and data["files"] == ["result.vtm", "ring.vtu"]


def test_unwritable_output_directory(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    monkeypatch.setattr(solver.solving, "solve", lambda problem, progress=None: fake_solution(converged=True))
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert main(["run", str(write_plate(tmp_path)), "--quiet", "--out", str(blocker / "out")]) == 4
    err = capsys.readouterr().err
    assert err.startswith("ibfem run: cannot write results to") and err.count("\n") == 1


def test_vtu_files_are_written_without_pyvista(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    monkeypatch.setattr(solver.solving, "solve", lambda problem, progress=None: fake_solution(converged=True))
    monkeypatch.setitem(sys.modules, "pyvista", None)
    monkeypatch.setitem(sys.modules, "vtk", None)
    path = tmp_path / "plate.toml"
    path.write_text(PLATE.format(material="steel").replace("vtk = false", "vtk = true"))
    assert main(["run", str(path), "--quiet", "--out", str(tmp_path / "out")]) == 0
    assert "warning" not in capsys.readouterr().err
    data = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert data["files"] == ["plate.vtu", "result.vtm"] and "warnings" not in data
    head = (tmp_path / "out" / "plate.vtu").read_bytes()[:200]
    assert b'<VTKFile type="UnstructuredGrid"' in head


def test_progress_on_a_terminal_rewrites_one_line():
    class Tty(io.StringIO):
        def isatty(self):
            return True

    clock, stream = FakeClock(), Tty()
    rep = ProgressReporter(stream=stream, delay=1.0, clock=clock)
    clock.t = 2.0
    rep("assembly of a long name", 0.25)
    clock.t = 3.0
    rep("solve", 0.5)
    rep.close()
    text = stream.getvalue()
    assert text.count("\n") == 1 and text.endswith("\n")
    last = text.split("\r")[-1].rstrip("\n")
    assert last.startswith("[    3.0 s] solve (50 %)")
    assert len(last) == len("[    2.0 s] assembly of a long name (25 %)")  # padded over the longer line


def test_an_unexpected_error_is_one_line_with_its_own_exit_code(tmp_path, capsys, monkeypatch):
    # exit 1 means "not converged, summary written"; a bug gets 5 and one line
    import ibfem.solver.solving
    from ibfem import solver

    def crash(problem, progress=None):
        raise IndexError("index 7 is out of bounds for axis 0 with size 3")

    monkeypatch.setattr(solver.solving, "solve", crash)
    assert main(["run", str(write_plate(tmp_path)), "--quiet", "--out", str(tmp_path / "o")]) == 5
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "internal error (IndexError" in err and "--traceback" in err
    assert not (tmp_path / "o" / "summary.json").exists()
    with pytest.raises(IndexError):  # --traceback shows it
        main(["run", str(write_plate(tmp_path)), "--quiet", "--traceback"])


def test_running_out_of_memory_is_reported_as_such(tmp_path, capsys, monkeypatch):
    import ibfem.solver.solving
    from ibfem import solver

    def starve(problem, progress=None):
        raise MemoryError()

    monkeypatch.setattr(solver.solving, "solve", starve)
    assert main(["run", str(write_plate(tmp_path)), "--quiet"]) == 6
    assert "out of memory" in capsys.readouterr().err
