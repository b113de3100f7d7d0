"""What a run's output costs and whether it shows the bodies as they are, per scene:

    python benchmarks/output_cost.py examples/solid/sphere_on_flat.toml [more scenes] [--out DIR]

Each scene is loaded, solved and written with its VTU files (and the plots it asks for); the
summary's ``timings`` give the share of the run the output took (summary sampling, VTU files,
plots). The VTU files are then read back with pyvista (the ``pictures`` extra) and checked
against the exact solids: every cell's centroid inside the body (signed distance <= 0, negative
inside), the cells' volume against the solid's (the divergence theorem on its faces'
quadrature), and the stress read from the file at each probe against summary.json's."""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def _solid_volume(solid, resolution: float) -> float:
    total = 0.0
    for face in solid.faces.values():
        points, weights, normals = face.quadrature(resolution)
        total += float(np.sum(weights * np.einsum("ij,ij->i", points, normals))) / 3.0
    return total


def _check_body(pv, out: Path, body) -> str:
    grid = pv.read(out / f"{body.name}.vtu")
    centroids = np.asarray(grid.cell_centers().points)
    phi = body.profile.signed_distance
    outside = -np.concatenate([np.asarray(phi(centroids[k:k + 20000])) for k in range(0, len(centroids), 20000)])
    volume = float(np.sum(np.abs(grid.compute_cell_sizes(length=False, area=False, volume=True)["Volume"])))
    exact = _solid_volume(body.profile, body.element_size / 4)
    return (f"  {body.name}: {grid.n_cells} cells, largest centroid signed distance {outside.max():.2e} m, "
            f"volume {volume / exact - 1:+.2e} of the solid's; point data stress "
            f"{np.asarray(grid.point_data['stress']).shape[1]} components, von_mises {'von_mises' in grid.point_data}")


def _check_probe(pv, out: Path, probe: dict) -> str:
    grid = pv.read(out / f"{probe['body']}.vtu")
    sample = pv.PolyData(np.asarray([probe["point"]], dtype=float)).sample(grid)
    got = np.asarray(sample.point_data["stress"])[0]
    want = np.asarray(probe["stress"], dtype=float)[[0, 1, 2, 5, 3, 4]]  # VTK's tensor order
    return f"  probe {probe['point']}: |file - summary| / |stress| = {np.abs(got - want).max() / np.abs(want).max():.1e}"


def run(scene_path: str, out: Path) -> None:
    import pyvista as pv

    from ibfem.solver.io.output import write_results
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    t0 = time.perf_counter()
    scene = load_scene(scene_path)
    solution = solve(scene.problem)
    o = scene.output
    summary = write_results(out, scene.problem, solution, probes=o.probes, lines=o.lines, vtk=True, plots=o.plots,
                            total_s=time.perf_counter() - t0, extra={"scene": scene_path})
    t = summary["timings"]
    print(f"{scene_path}: run {t['total_s']:.2f} s, output {t['output_s']:.2f} s = "
          f"{100 * t['output_s'] / t['total_s']:.1f} % (summary {t['summary_s']:.2f}, VTU {t.get('vtk_s', 0.0):.2f}, "
          f"plots {t.get('plots_s', 0.0):.2f} s)")
    if scene.problem.dim == 3:
        for body in scene.problem.bodies:
            print(_check_body(pv, out, body))
    for probe in summary.get("probes", []):
        if probe["body"] is not None and len(probe["stress"]) == 6:
            print(_check_probe(pv, out, probe))


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--out", default=None, help="output folder (default: a temporary one)")
    args = ap.parse_args(argv)
    root = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="ibfem-output-"))
    for path in args.scenes:
        run(path, root / Path(path).stem)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
