"""Memory of a 3D run with load paths (a frictional contact keeping its history): what the run
holds from one load step to the next does not grow with the steps beyond each step's record (its
displacement field and a few numbers), and the friction history's regions hold no more per
quadrature point than ``ibfem run --check`` counts for them (solver.model.estimate.history_bytes).
Measured with tracemalloc and the objects' sizes (not with timings) on a small ball on a flat, the
normal and the tangential loads cycled together over four steps."""

from __future__ import annotations

import gc
import tomllib
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from ibfem.solver.contact import driver as drv
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model import estimate
from ibfem.solver.solving import solve

SCENE = Path(__file__).resolve().parent.parent / "examples" / "fretting" / "sphere_on_flat_varying_normal.toml"


def _small_scene():
    """The example at 3 refinement levels, one cycle of 4 steps after the normal load's ramp."""
    data = tomllib.loads(SCENE.read_text())
    data["output"] = {"vtk": False, "plots": False}
    for body in data["bodies"]:
        body["refinement"].update(levels=3, radius=0.25)
    data["paths"][0]["points"] = [[0, 0], [1, 1], [2, 1]]
    for path in data["paths"][1:]:
        path["cycle"].update(cycles=1, points_per_cycle=4)
    return load_scene(data, label=SCENE.name, base_dir=SCENE.parent).problem


def _nbytes(obj, seen: set) -> int:
    """Bytes of the numpy arrays and sparse matrices reachable through tuples, lists, dicts and
    plain objects (each array counted once)."""
    if id(obj) in seen:
        return 0
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        return obj.nbytes
    if sp.issparse(obj):
        return sum(_nbytes(getattr(obj, k), seen) for k in ("data", "indices", "indptr", "row", "col") if hasattr(obj, k))
    if isinstance(obj, dict):
        return sum(_nbytes(v, seen) for v in obj.values())
    if isinstance(obj, (tuple, list)):
        return sum(_nbytes(v, seen) for v in obj)
    if hasattr(obj, "__dict__"):
        return sum(_nbytes(v, seen) for v in vars(obj).values())
    return 0


@pytest.fixture(scope="module")
def measured(request):
    held, regions = [], []
    original = drv.ContactDriver._load_step

    def load_step(self, step):
        original(self, step)
        gc.collect()
        held.append(tracemalloc.get_traced_memory()[0])
        c = self.contacts[0]
        for reg in c.regions.values():
            regions.append((len(reg.info[0].s), _nbytes((reg.info, reg.neighbours), set())))

    problem = _small_scene()
    drv.ContactDriver._load_step = load_step
    tracemalloc.start()
    try:
        solution = solve(problem)
    finally:
        tracemalloc.stop()
        drv.ContactDriver._load_step = original
    return problem, solution, held, regions


def test_what_a_run_holds_does_not_grow_with_its_load_steps(measured):
    """Steps 3 and 5 end at the same loads (the cycle's mean normal load, no tangential one), so
    with regions of the same size: between them the run may add only the two steps' records (the
    field, 8 bytes per dof, and 64 KB of numbers and axis profiles each)."""
    problem, solution, held, regions = measured
    assert solution.converged and len(held) == 5
    dofs = sum(float(b["dofs"]) for b in solution.body_info.values())
    per_step = 8.0 * dofs + 64e3
    assert held[4] - held[2] <= 2 * per_step, (held, per_step)


def test_the_check_counts_what_a_history_region_holds_per_point(measured):
    """Each region the friction history holds (its operators, points and neighbour matrix) takes
    no more bytes per quadrature point than the estimate counts for it."""
    from ibfem.solver.contact.friction_history3d import KEEP_REGIONS

    problem, _, _, regions = measured
    assert estimate.HISTORY_REGIONS == KEEP_REGIONS
    counted = estimate.REGION_OPERATOR_BYTES_PER_POINT + estimate.REGION_NEIGHBOUR_BYTES_PER_POINT
    for points, nbytes in regions:
        assert nbytes / points <= counted, (points, nbytes / points, counted)
    assert estimate.history_bytes(problem) > 0.0
