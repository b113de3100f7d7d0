"""What a run's output costs and whether it shows the bodies as they are, per scene:

    python benchmarks/output_cost.py examples/solid/sphere_on_flat.toml [more scenes] [--out DIR] [--vtk]

Each scene is loaded, solved and written as ``ibfem run`` does it: the files its ``[output]``
table asks for (``--vtk``: the VTU files too), the pictures rendered in other processes beside
the VTU files when the machine has idle cores (``--serial``: after them, in this process, for
comparison). The
summary's ``timings`` give the share of the run the output took (summary sampling, VTU files,
plots: these two overlap). The VTU files are then read back with pyvista (the ``pictures`` extra) and checked
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


def run(scene_path: str, out: Path, force_vtk: bool, serial: bool = False) -> None:
    from ibfem.solver.io.output import write_results
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    t0 = time.perf_counter()
    scene = load_scene(scene_path)
    o = scene.output
    solution = solve(scene.problem)
    vtk = o.vtk or force_vtk
    summary = write_results(out, scene.problem, solution, probes=o.probes, lines=o.lines, vtk=vtk, plots=o.plots,
                            total_s=time.perf_counter() - t0, extra={"scene": scene_path}, parallel=not serial)
    t = summary["timings"]
    print(f"{scene_path}{' (serial)' if serial else ''}: run {t['total_s']:.2f} s, output {t['output_s']:.2f} s = "
          f"{100 * t['output_s'] / t['total_s']:.1f} % (summary {t['summary_s']:.2f}, VTU {t.get('vtk_s', 0.0):.2f}, "
          f"plots {t.get('plots_s', 0.0):.2f} s; VTU {'written' if vtk else 'not asked'}, "
          f"plots {'written' if o.plots else 'not asked'}; solver {t.get('solver_total_s', 0.0):.2f} s)")
    if not vtk:
        return
    import pyvista as pv

    if scene.problem.dim == 3:
        for body in scene.problem.bodies:
            print(_check_body(pv, out, body))
    for probe in summary.get("probes", []):
        if probe["body"] is not None and len(probe["stress"]) == 6:
            print(_check_probe(pv, out, probe))


def _alternate(path: str, out: Path, force_vtk: bool, pairs: int) -> None:
    """Serial and parallel runs alternating, each in a fresh interpreter; prints each run's line and the ratios of their output and run times."""
    import subprocess

    shares = {True: [], False: []}
    for _ in range(pairs):
        for serial in (True, False):
            cmd = [sys.executable, __file__, path, "--out", str(out)] + ["--vtk"] * force_vtk + ["--serial"] * serial
            line = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.splitlines()[0]
            print(line)
            run_s, output_s = (float(line.split(key)[1].split()[0]) for key in ("run ", "output "))
            shares[serial].append((run_s, output_s))
    for k in range(pairs):
        (r0, o0), (r1, o1) = shares[True][k], shares[False][k]
        print(f"  pair {k + 1}: output parallel / serial = {o1 / o0:.2f}, run parallel / serial = {r1 / r0:.2f}")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--out", default=None, help="output folder (default: a temporary one)")
    ap.add_argument("--vtk", action="store_true", help="write (and check) the VTU files even where the scene does not ask")
    ap.add_argument("--serial", action="store_true",
                    help="the pictures after the VTU files, in this process (for comparison)")
    ap.add_argument("--alternate", type=int, default=0, metavar="N",
                    help="N pairs of runs of each scene, serial and parallel alternating (timing ratios on a loaded machine)")
    args = ap.parse_args(argv)
    root = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="ibfem-output-"))
    for path in args.scenes:
        if args.alternate:
            _alternate(path, root / Path(path).stem, args.vtk, args.alternate)
        else:
            run(path, root / Path(path).stem, args.vtk, args.serial)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
