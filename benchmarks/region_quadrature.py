"""The cost of a 3D scene's star-shaped contact regions with their quadrature graded by the cells
it lies in (the code's rule, solver.contact.graded_quadrature) or, with ``--uniform``, spaced by
the finest cell over the whole region (the rule before it): one solve, then the process's CPU
time and peak resident memory, the region builds (points per build, their CPU time) and each
contact's semi-axes. Alternate the two in turn on a shared machine and compare the CPU-time
ratios.

    python benchmarks/region_quadrature.py examples/contact3d/crowned_roller.toml [--uniform]
"""

from __future__ import annotations

import argparse
import json
import resource
import time

import numpy as np

from ibfem.solver.contact import star_region
from ibfem.solver.io.scene import load_scene
from ibfem.solver.solving import solve


def _instrument(uniform: bool) -> list:
    """Record (points, CPU seconds) of every region build; ``uniform``: no cells to follow."""
    builds: list = []
    build = star_region.StarRegionContact.region_quadrature

    def recorded(self, a):
        t0 = time.process_time()
        pts = build(self, a)
        seconds = time.process_time() - t0
        cells = star_region.StarRegionContact.leaf_sizes(self)  # the grids' leaves, whichever the rule
        size = np.minimum(cells[0](pts.x1), cells[1](pts.x2)) if cells else np.full(len(pts.weights), self.h)
        builds.append((len(pts.weights), seconds, float((pts.weights / size**2).sum())))
        return pts

    star_region.StarRegionContact.region_quadrature = recorded
    if uniform:
        star_region.StarRegionContact.region_quadrature = lambda self, a: _uniform(self, a, recorded)
    return builds


def _uniform(contact, a, recorded):
    """The region's quadrature spaced by the finest cell (no cells to follow), recorded."""
    leaf_sizes = star_region.StarRegionContact.leaf_sizes
    contact.leaf_sizes = lambda: None
    try:
        return recorded(contact, a)
    finally:
        del contact.leaf_sizes
        assert star_region.StarRegionContact.leaf_sizes is leaf_sizes


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="a 3D scene file with a line, elongated or flat contact")
    parser.add_argument("--uniform", action="store_true", help="the region's quadrature spaced by the finest cell")
    args = parser.parse_args(argv)
    builds = _instrument(args.uniform)
    scene = load_scene(args.scene)
    t0, c0 = time.perf_counter(), time.process_time()
    result = solve(scene.problem)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    contacts = [{"semi_axes": c.get("semi_axes"), "normal_force": c.get("normal_force")} for c in result.contacts]
    points = [p for p, _, _ in builds]
    print(json.dumps({
        "scene": args.scene, "rule": "uniform" if args.uniform else "graded", "wall_s": round(wall, 1),
        "cpu_s": round(cpu, 1), "peak_rss_gb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6, 3),
        "region_builds": len(builds), "points_last": points[-1] if points else 0, "points_max": max(points, default=0),
        "build_cpu_s": round(sum(t for _, t, _ in builds), 1),
        "points_per_cell_face_last": round(builds[-1][0] / builds[-1][2], 1) if builds else None, "dofs": int(result.u.size),
        "converged": bool(result.converged), "contacts": contacts}, indent=1))


if __name__ == "__main__":
    main()
