"""Packaging invariants: the layers import in the allowed direction only."""

import subprocess
import sys
import time


def test_import_geometry_is_light_and_isolated():
    code = (
        "import sys, time; t = time.perf_counter(); import geometry; dt = time.perf_counter() - t\n"
        "bad = [m for m in ('solver', 'importers', 'pyvista', 'matplotlib', 'requests', 'trimesh') if m in sys.modules]\n"
        "print(dt); print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split("\n")
    assert out[1] == "", f"import geometry pulled in {out[1]}"
    # generous bound in a test; the 0.5 s target is measured in benchmarks/import_time.py
    assert float(out[0]) < 2.0


def test_cli_help_runs():
    r = subprocess.run([sys.executable, "-m", "solver.cli", "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "run" in r.stdout
