"""Packaging invariants: one ``ibfem`` namespace, a light ``ibfem.geometry``, the command line
reachable as ``ibfem`` and ``python -m ibfem``, the version from the package metadata."""

import subprocess
import sys
from importlib.metadata import version

import ibfem


def _run(code: str, cwd) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=cwd).stdout


def test_import_geometry_is_light_and_isolated(tmp_path):
    code = (
        "import sys, time; t = time.perf_counter(); from ibfem import geometry; dt = time.perf_counter() - t\n"
        "heavy = ('ibfem.solver', 'ibfem.importers', 'pyvista', 'matplotlib', 'requests', 'trimesh')\n"
        "bad = [m for m in sys.modules if m.startswith(heavy)]\n"
        "print(dt); print(','.join(bad))"
    )
    out = _run(code, tmp_path).split("\n")
    assert out[1] == "", f"from ibfem import geometry pulled in {out[1]}"
    # generous bound in a test; the 0.5 s target is measured in benchmarks/import_time.py
    assert float(out[0]) < 2.0


def test_no_generic_top_level_packages(tmp_path):
    """Outside the source tree, only ``ibfem`` is importable: ``geometry``, ``solver`` and
    ``importers`` are not installed at top level (they would shadow users' own modules)."""
    code = "import importlib.util as u; print([n for n in ('geometry', 'solver', 'importers') if u.find_spec(n)])"
    assert _run(code, tmp_path).strip() == "[]"
    assert _run("import ibfem.geometry, ibfem.solver, ibfem.importers; print('ok')", tmp_path).strip() == "ok"


def test_version_from_metadata(tmp_path):
    assert ibfem.__version__ == version("ibfem")
    for cmd in ([sys.executable, "-m", "ibfem", "--version"], [sys.executable, "-m", "ibfem.solver.cli", "--version"]):
        r = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path)
        assert r.returncode == 0 and r.stdout.strip() == f"ibfem {version('ibfem')}"


def test_cli_help_runs(tmp_path):
    r = subprocess.run([sys.executable, "-m", "ibfem", "--help"], capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0 and "run" in r.stdout and "usage: ibfem" in r.stdout


def test_solve_is_the_function_after_the_cli_ran(tmp_path):
    """The public ``ibfem.solver.solve`` stays the function once the module that defines it has
    been imported (the command line imports it): no submodule shadows a public name."""
    code = ("import ibfem.solver.solving, ibfem.solver.commands\n"
            "from ibfem import solver\nfrom ibfem.solver import solve\n"
            "print(callable(solve) and solve is solver.solve and solve.__module__ == 'ibfem.solver.solving')")
    assert _run(code, tmp_path).strip() == "True"
