"""The number-making helpers of the 3D peer study (benchmarks/peers.py --problem sphere3d): Hertz's
radius, the errors against it, the log-log time-to-error interpolation, the finest-rung
cross-check and the fine zone of the NGSolve mesh, each against a hand computation. Nothing here
needs NGSolve."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import pytest

from ibfem.solver.io.scene import scene_from_dict

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"


def _load(name: str):
    if str(BENCHMARKS) not in sys.path:
        sys.path.insert(0, str(BENCHMARKS))     # peers_ngsolve3d imports its 2D sibling
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


peers = _load("peers")
peers3d = _load("peers_ngsolve3d")


def test_hertz_radius_by_hand():
    # E* = E / (2 (1 - nu^2)) = 3 for E = 5.46, nu = 0.3; quarter force 2 -> N = 8; R = 4:
    # a^3 = 3 * 8 * 4 / (4 * 3) = 8, a = 2
    assert peers.hertz_sphere_radius(2.0, 4.0, 5.46, 0.3, model_share=4) == pytest.approx(2.0, rel=1e-14)
    # docs/validation-solid.md, sphere_on_flat: quarter N 3.42441e6 N, steel -> Hertz a 0.0453854 m
    assert peers.hertz_sphere_radius(3.42441e6, 1.0, 2.0e11, 0.3, 4) == pytest.approx(0.0453854, abs=1e-7)
    with pytest.raises(ValueError, match="positive force"):
        peers.hertz_sphere_radius(-1.0, 1.0, 2.0e11, 0.3)


def test_errors_against_hertz_for_the_rows_own_force():
    row = peers.add_errors({"problem": "sphere3d", "code": "NGSolve P2", "N": 3.42441e6, "a": 0.045, "a_fit": 0.0454})
    a_h = 0.0453854
    assert row["a_hertz"] == pytest.approx(a_h, abs=1e-7)
    assert row["a_error"] == pytest.approx(0.045 / a_h - 1.0, abs=3e-6)
    assert row["a_fit_error"] == pytest.approx(0.0454 / a_h - 1.0, abs=3e-6)
    assert "N_error" not in row                  # no reference force in 3D


def test_time_to_error_interpolates_log_log_on_the_running_best():
    rows = [{"wall_s": 1.0, "a_error": -0.04, "peak_mb": 10.0},
            {"wall_s": 2.0, "a_error": 0.05, "peak_mb": 20.0},      # worse than the best so far: skipped
            {"wall_s": 4.0, "a_error": -0.005, "peak_mb": 40.0}]
    hit = peers.time_to_error(rows, 0.01)
    # f = ln(0.01 / 0.04) / ln(0.005 / 0.04) = 2 / 3, t = exp(2/3 ln 4) = 4^(2/3)
    assert hit["time_s"] == pytest.approx(4.0 ** (2.0 / 3.0), rel=1e-12)
    assert hit["peak_mb"] == 40.0 and not hit["bound"]
    first = peers.time_to_error(rows, 0.05)     # the first rung is already below: an upper bound
    assert first == {"time_s": 1.0, "peak_mb": 10.0, "bound": True}
    assert peers.time_to_error(rows, 0.001) is None


def test_cross_check_of_the_finest_rungs():
    rows = [{"code": "ibfem", "rung": "coarse", "dofs": 10, "a": 0.040, "N": 1.0, "a_error": -0.1},
            {"code": "ibfem", "rung": "fine", "dofs": 100, "a": 0.0450, "N": 3.0e6, "a_error": -0.003},
            {"code": "NGSolve P2", "rung": "h_c 0.008", "dofs": 50, "a_fit": 0.0451, "N": 2.97e6, "a_fit_error": -0.002}]
    c = peers.cross_check(rows)
    assert (c["ibfem"], c["ngsolve"]) == ("fine", "h_c 0.008")
    assert c["a_difference"] == pytest.approx(0.0450 / 0.0451 - 1.0, rel=1e-12)
    assert c["N_difference"] == pytest.approx(3.0 / 2.97 - 1.0, rel=1e-12)
    assert c["a_over_hertz_difference"] == pytest.approx(0.997 / 0.998 - 1.0, rel=1e-12)
    assert peers.cross_check(rows[:2]) is None


def test_ibfem_rung_scene_is_sphere_on_flat_with_the_rungs_grid():
    data = peers.sphere_scene_data(0.2, 5)
    for body in data["bodies"]:
        assert body["element_size"] == 0.2 and body["refinement"]["levels"] == 5
        assert body["refinement"]["radius"] == 0.07          # as shipped
    assert data["output"] == {"vtk": False, "plots": False}
    scene = scene_from_dict(data, label="peer sphere3d")    # a scene ibfem accepts
    assert scene is not None


def test_ngsolve_fine_zone_points():
    hc, zone = 0.01, 0.1
    x, y = peers3d.zone_points(hc, zone)
    assert min(x.min(), y.min()) == 0.0
    assert (x * x + y * y <= zone * zone + 1e-15).all()
    # points every h_c / 2 inside the quarter disc: about its area / (h_c / 2)^2, plus the edge rows
    area = math.pi * zone**2 / 4.0
    assert area / (hc / 2) ** 2 < len(x) < area / (hc / 2) ** 2 + 2 * zone / (hc / 2) + 3
