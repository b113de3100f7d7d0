"""What a run's output costs and whether it shows the bodies as they are, per scene:

    python benchmarks/output_cost.py examples/solid/sphere_on_flat.toml [more scenes] [--markdown FILE]
    python benchmarks/output_cost.py SCENE --vtk    # VTU files forced, read back and checked

By default each scene is run as a user runs it, ``ibfem run SCENE --out DIR --quiet`` in a child
process (the error estimate's second solve included, the files the scene's ``[output]`` asks
for), and one table row is printed: the child's wall time (start, imports and writing
included), the run's own ``total_s``, the solver's and the estimate's seconds, the output's
(``output_s`` from summary.json: summary sampling, VTU files, pictures) and its share of the
wall time, whether the pictures were rendered in other processes, the child's peak memory, the
CPU seconds of the child and every process it started (``wait4``: load-independent, unlike the
wall time), and the one-minute load average after the run. ``--compare-pictures`` runs each
scene with and without its pictures in turn: the difference is what the pictures cost.
``--markdown FILE`` also writes the table there. ``--alternate N`` runs each scene N times in
turn with the others (a loaded machine's noise spreads over all of them). ``--idle-cores N``
starts the pictures' processes as if the machine had N idle cores whatever its load (a shared
machine measured as an idle one would run; the default follows the load average as ``ibfem
run`` does).

``--vtk`` instead loads, solves and writes the scene in this process with the VTU files whatever
the scene asks (``--serial``: the pictures after the VTU files, in this process), then reads
the files back with pyvista (the ``pictures`` extra) and checks them against the exact solids:
every cell's centroid inside the body (signed distance <= 0, negative inside), the cells'
volume against the solid's (the divergence theorem on its faces' quadrature), and the stress
read from the file at each probe against summary.json's (a 3D scene without probes is given
six per contact, on its normal a quarter, one and two of the region's larger semi-axes deep
into each body). ``--final-only``: a run with load
paths writes its final bodies only (the load steps' series, clipped the same way, left out)."""

from __future__ import annotations

import argparse
import copy
import json
import os
import subprocess
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


#: the distance within which VTK's probe may take a cell for the one holding the point, relative to
#: the file's diagonal: its default (a fraction of the diagonal) takes a neighbour of the cells a
#: run splits about a probe (1e-8 m across on a 1 m body) and reads it there
PROBE_TOLERANCE = 1e-12


def _check_probe(pv, out: Path, probe: dict) -> str:
    grid = pv.read(out / f"{probe['body']}.vtu")
    sample = pv.PolyData(np.asarray([probe["point"]], dtype=float)).sample(grid, tolerance=PROBE_TOLERANCE * grid.length)
    got = np.asarray(sample.point_data["stress"])[0]
    want = np.asarray(probe["stress"], dtype=float)[[0, 1, 2, 5, 3, 4]]  # VTK's tensor order
    return f"  probe {probe['point']}: |file - summary| / |stress| = {np.abs(got - want).max() / np.abs(want).max():.1e}"


def _probes_below_contacts(problem, solution) -> list:
    """For a 3D scene without probes: points on each contact's normal, a quarter, one and two of
    the region's larger semi-axes into each body (where the contact's subsurface stress is read)."""
    from ibfem.solver.io.results import build_summary, json_safe

    points = []
    for c in json_safe(build_summary(problem, solution)).get("contacts", []):
        size = max((c.get("semi_axes") or [c.get("half_width") or 0.0]) or [0.0])
        if problem.dim != 3 or not c.get("point") or not c.get("normal") or not size:
            continue
        point, normal = np.asarray(c["point"], float), np.asarray(c["normal"], float)
        points += [_inside(problem, solution, point + side * depth * size * normal, 1e-6 * size).tolist()
                   for side in (1.0, -1.0) for depth in (0.25, 1.0, 2.0)]
    return points


def _inside(problem, solution, point: np.ndarray, step: float) -> np.ndarray:
    """The point, or where it is not strictly inside a body (on a symmetry plane: a rounding
    off the model) the first of it moved by ``step`` along one axis that is."""
    for move in [np.zeros(3)] + [sign * step * e for e in np.eye(3) for sign in (1.0, -1.0)]:
        k = int(np.asarray(solution.body_at((point + move)[None]))[0])
        if k >= 0 and float(np.asarray(problem.bodies[k].profile.signed_distance((point + move)[None]))[0]) > 0.0:
            return point + move
    return point


def run(scene_path: str, out: Path, force_vtk: bool, serial: bool = False, final_only: bool = False) -> None:
    from ibfem.solver.io.output import write_results
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    t0 = time.perf_counter()
    scene = load_scene(scene_path)
    o = scene.output
    solution = solve(scene.problem)
    if final_only and getattr(solution, "steps", None):  # the load steps' series left out
        solution = copy.copy(solution)
        solution.steps = []
    vtk = o.vtk or force_vtk
    probes = o.probes or (_probes_below_contacts(scene.problem, solution) if force_vtk else [])
    summary = write_results(out, scene.problem, solution, probes=probes, lines=o.lines, vtk=vtk, plots=o.plots,
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


_HEADER = ("| example | files | run, wall (s) | solver (s) | estimate (s) | output (s) | output / wall "
           "| summary / VTU / plots (s) | pictures | peak (GB) | CPU (s) | load |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|")


#: ``ibfem run`` as the command line runs it, with the machine's idle cores taken as ``sys.argv[1]``
_CHILD = ("import sys\nfrom ibfem.solver.io import parallel_plots, scene\n"
          "idle, worker, pictures = sys.argv[1].split(',')\n"
          "if idle != 'load':\n    parallel_plots.idle_cores = lambda: int(idle)\n"
          "if worker == 'no' or pictures == 'no':\n"
          "    parallel_plots.PictureWorker.early = classmethod(lambda cls, scene_path: None)\n"
          "if worker == 'no':\n    parallel_plots.PictureWorker.start = classmethod(lambda cls, problem, early=None: None)\n"
          "if pictures == 'no':\n    load = scene.load_scene\n"
          "    def without(*args, **kwargs):\n        loaded = load(*args, **kwargs)\n"
          "        object.__setattr__(loaded.spec.output, 'plots', False)\n        return loaded\n"
          "    scene.load_scene = without\n"
          "from ibfem.solver.cli import main\nraise SystemExit(main(sys.argv[2:]))")


def command_row(path: str, out: Path, idle: str = "load", worker: bool = True, pictures: bool = True) -> tuple[str, float]:
    """(table row, output share of the wall time) of ``ibfem run`` on one scene in a child process;
    ``idle``: the idle cores the pictures' processes are started for ("load": from the load
    average, as ``ibfem run`` does; a number: as if the machine had that many); ``worker``
    false: no picture worker started with the run (the pictures start after the solve);
    ``pictures`` false: the scene run without its pictures."""
    t0 = time.perf_counter()
    flags = f"{idle},{'yes' if worker else 'no'},{'yes' if pictures else 'no'}"
    child = subprocess.Popen([sys.executable, "-c", _CHILD, flags, "run", path, "--out", str(out), "--quiet"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - t0
    name = str(Path(path).with_suffix("")).replace("examples/", "") + ("" if pictures else " (no pictures)")
    if os.waitstatus_to_exitcode(status) not in (0, 1):
        return f"| {name} | failed: {child.stderr.read().decode(errors='replace').strip().splitlines()[-1:]} |", float("nan")
    child.stderr.read()
    summary = json.loads((out / "summary.json").read_text())
    t = summary["timings"]
    files = summary.get("files", [])
    kinds = [k for k, ext in (("VTU", ".vtu"), ("plots", ".png")) if any(f.endswith(ext) for f in files)]
    pictures = ("-" if "plots" not in kinds else
                f"{t.get('plots_processes', 0)} processes" if t.get("plots_processes") else "this process")
    if "plots_warm_up_s" in t:
        pictures += " (worker)"
    share = t["output_s"] / wall
    row = (f"| {name} | {' + '.join(kinds) or 'summary only'} | {wall:.2f} | {t.get('solver_total_s', 0.0):.2f} "
           f"| {t.get('estimate_s', 0.0):.2f} | {t['output_s']:.2f} | {100 * share:.1f} % "
           f"| {t.get('summary_s', 0.0):.2f} / {t.get('vtk_s', 0.0):.2f} / {t.get('plots_s', 0.0):.2f} | {pictures} "
           f"| {usage.ru_maxrss / 2**20:.2f} | {usage.ru_utime + usage.ru_stime:.2f} | {os.getloadavg()[0]:.1f} |")
    return row, share


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--out", default=None, help="output folder (default: a temporary one)")
    ap.add_argument("--vtk", action="store_true",
                    help="in this process, the VTU files written (whatever the scene asks), read back and checked")
    ap.add_argument("--serial", action="store_true",
                    help="with --vtk: the pictures after the VTU files, in this process (for comparison)")
    ap.add_argument("--final-only", action="store_true",
                    help="with --vtk: a run with load paths writes its final bodies only, not every step's")
    ap.add_argument("--alternate", type=int, default=1, metavar="N",
                    help="N runs of each scene, the scenes in turn (a loaded machine's noise spread over all)")
    ap.add_argument("--markdown", type=Path, default=None, help="also write the table to this file")
    ap.add_argument("--compare-worker", action="store_true",
                    help="each run twice in turn, with and without the picture worker started with the run")
    ap.add_argument("--compare-pictures", action="store_true",
                    help="each run twice in turn, with and without its pictures (their cost in wall and CPU time)")
    ap.add_argument("--idle-cores", default="load", metavar="N",
                    help="start the pictures' processes as if the machine had N idle cores (default: from its load "
                         "average, as ibfem run does; on a shared machine, what an idle one would do)")
    args = ap.parse_args(argv)
    root = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="ibfem-output-"))
    if args.vtk:
        for path in args.scenes:
            run(path, root / Path(path).stem, True, args.serial, args.final_only)
        return 0
    print(_HEADER, flush=True)
    rows = []
    for _ in range(args.alternate):
        for path in args.scenes:
            for worker in ((True, False) if args.compare_worker else (True,)):
                for pictures in ((True, False) if args.compare_pictures else (True,)):
                    row, _share = command_row(path, root / Path(path).stem, args.idle_cores, worker, pictures)
                    print(row, flush=True)
                    rows.append(row)
    if args.markdown:
        args.markdown.write_text(_HEADER + "\n" + "\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
