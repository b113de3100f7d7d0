"""The condensed factorisation of the contact drivers: SuperLU against the
multifrontal Cholesky of solver.fem.multifrontal, on whole runs and on the bare factorisation.

Whole runs: each scene solved by ``ibfem run --quiet`` in its own process with
``IBFEM_CONDENSED_FACTOR=superlu`` or ``=cholesky``, the two alternating, ``--repeat`` times
each; wall time and peak RSS by ``/usr/bin/time``, the driver's factor time and a, N from
summary.json (a and N of the two must agree to 1e-9 relative).

Bare factorisation (``--bare``): K0, the contact dofs and the order are captured once from a run
(the driver's call to condensed_factor, patched in a child process), then every backend times
``condensed_factor`` alone in a fresh process (numba's load included for the Cholesky: it is
paid once per run), reporting its peak RSS above the process's start.

Scenes: the 68k-dof 2D peer scene (benchmarks/scenes/peer_half_disc.toml) and the 3D
sphere_on_flat example at element_size 0.2 with 5 levels (12k dofs; ``--large``: the example's
0.25 / 6 levels, 32k dofs), vtk, plots, probes and lines off.

Scaling (``--grid NX``): the symbolic and numeric phases alone on a 2D grid Laplacian kron I_2
of 2 NX^2 dofs in METIS order, a grid line of nodes as the root (NX 708: 1M dofs).

    python benchmarks/cholesky.py [--repeat 3] [--large] [--bare] [--grid 708]

Writes benchmarks/results/cholesky.json."""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BACKENDS = ("superlu", "cholesky")

CAPTURE = """
import sys, numpy as np, scipy.sparse as sp
import ibfem.solver.contact.driver as driver
original = driver.condensed_factor
def capture(k0, dofs, order=None, nearness=None):
    sp.save_npz(sys.argv[2] + "/k0.npz", k0.tocsr())
    np.savez(sys.argv[2] + "/dofs.npz", dofs=dofs, order=order)
    raise SystemExit(0)
driver.condensed_factor = capture
from ibfem.solver.cli import main
main(["run", sys.argv[1], "--quiet", "--out", sys.argv[2] + "/out"])
"""

BARE = """
import resource, sys, time, numpy as np, scipy.sparse as sp
def rss():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3
k0 = sp.load_npz(sys.argv[1] + "/k0.npz")
z = np.load(sys.argv[1] + "/dofs.npz", allow_pickle=True)
from ibfem.solver.fem.linalg import condensed_factor
before = rss()
t0 = time.perf_counter()
factor, schur, g = condensed_factor(k0, z["dofs"], z["order"])
t1 = time.perf_counter()
f = np.random.default_rng(0).standard_normal(k0.shape[0])
x = factor.solve(f)
t2 = time.perf_counter()
x = factor.solve(f)
t3 = time.perf_counter()
out = dict(n=k0.shape[0], m=len(z["dofs"]), nnz_k0=k0.nnz, factor_s=t1 - t0, first_solve_s=t2 - t1, solve_s=t3 - t2,
           rss_before_mb=before, peak_rss_mb=rss(), residual=float(np.abs(k0 @ x - f).max() / np.abs(f).max()),
           g_trace=float(np.trace(g)), type=type(factor).__name__)
for key in ("nnz", "factor_bytes", "n_supernodes", "largest_front", "stack_bytes", "front_bytes"):
    if hasattr(factor, key):
        out[key] = int(getattr(factor, key))
print("RESULT " + __import__("json").dumps(out))
"""


GRID = """
import resource, sys, time, numpy as np, scipy.sparse as sp
from ibfem.solver.fem import multifrontal as mf, linalg
from ibfem.solver.fem.linalg import single_threaded_blas
def rss():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3
kern = mf._kernels()
kern.postorder(np.array([-1], np.int64))
nx = int(sys.argv[1])
lap = sp.diags([-np.ones(nx - 1), 2 * np.ones(nx), -np.ones(nx - 1)], [-1, 0, 1])
grid = sp.kron(lap, sp.eye(nx)) + sp.kron(sp.eye(nx), lap)
k = (sp.kron(grid, np.array([[1.0, 0.3], [0.3, 1.0]])) + 1e-6 * sp.eye(2 * nx * nx)).tocsr()
n, m = k.shape[0], 2 * nx
order = linalg.metis_order(k, 2)
dofs = np.arange(2 * nx * (nx // 2), 2 * nx * (nx // 2) + m)
order = np.concatenate([order[~np.isin(order, dofs)], dofs])
start = rss()
f = mf.CholeskyFactor.__new__(mf.CholeskyFactor)
f.n, f.m, f.definite = n, m, True
t0 = time.perf_counter()
f.order = f._postordered(k, order, kern)
t1 = time.perf_counter()
f._symbolic(k, kern)
t2 = time.perf_counter()
symbolic_peak = rss()
f.schur = np.zeros((m, m))
with single_threaded_blas():
    f._numeric(kern)
t3 = time.perf_counter()
x = f.solve(np.ones(n))
t4 = time.perf_counter()
out = dict(n=n, nnz_k=k.nnz, m=m, tree_counts_s=t1 - t0, supernodes_rows_s=t2 - t1, numeric_s=t3 - t2, solve_s=t4 - t3,
           nnz_l=f.nnz, factor_mb=f.factor_bytes / 1e6, n_supernodes=f.n_supernodes, largest_front=f.largest_front,
           rss_start_mb=start, rss_after_symbolic_mb=symbolic_peak, peak_rss_mb=rss(),
           residual=float(np.abs(k @ x - 1.0).max()))
print("RESULT " + __import__("json").dumps(out))
"""


def grid_scaling(nx: int) -> dict:
    done = subprocess.run([sys.executable, "-c", GRID, str(nx)], cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(next(ln for ln in done.stdout.splitlines() if ln.startswith("RESULT "))[len("RESULT "):])


def sphere_scene(tmp: Path, element_size: float, levels: int) -> Path:
    """The sphere_on_flat example with the given element size and levels, outputs off."""
    text = (ROOT / "examples/solid/sphere_on_flat.toml").read_text()
    text = text.replace("element_size = 0.25", f"element_size = {element_size}")
    text = text.replace("levels = 6", f"levels = {levels}")
    text = re.sub(r"^vtk = true", "vtk = false", text, flags=re.M)
    text = re.sub(r"^plots = true", "plots = false", text, flags=re.M)
    text = re.sub(r"^(probes|lines) = .*\n", "", text, flags=re.M)
    path = tmp / f"sphere_on_flat_{element_size}_{levels}.toml"
    path.write_text(text)
    return path


def run_scene(scene: Path, backend: str, out: Path) -> dict:
    env = dict(os.environ, IBFEM_CONDENSED_FACTOR=backend, MPLBACKEND="Agg")
    cmd = ["/usr/bin/time", "-f", "TIME %e %M", sys.executable, "-m", "ibfem.solver.cli", "run", str(scene), "--quiet",
           "--out", str(out)]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        raise SystemExit(f"{scene.name} with {backend} failed: {done.stderr.strip()[-2000:]}")
    wall, kb = done.stderr.strip().splitlines()[-1].split()[1:]
    summary = json.loads((out / "summary.json").read_text())
    contact = summary["contacts"][0]
    a = contact["semi_axes"][0] if "semi_axes" in contact else contact["half_width"]
    return dict(backend=backend, wall_s=float(wall), peak_rss_mb=int(kb) / 1e3, a=a, N=contact["normal_force"],
                factor_s=summary["timings"].get("factor_s"), solver_s=summary["timings"].get("solver_total_s"),
                dofs=sum(b["dofs"] for b in summary["bodies"].values()))


def bare(scene: Path, tmp: Path) -> dict:
    work = tmp / (scene.stem + "_k0")
    work.mkdir(exist_ok=True)
    subprocess.run([sys.executable, "-c", CAPTURE, str(scene), str(work)], cwd=ROOT, check=True,
                   env=dict(os.environ, MPLBACKEND="Agg"))
    out = {}
    for backend in BACKENDS:
        env = dict(os.environ, IBFEM_CONDENSED_FACTOR=backend)
        done = subprocess.run([sys.executable, "-c", BARE, str(work)], cwd=ROOT, capture_output=True, text=True,
                              env=env, check=True)
        line = next(ln for ln in done.stdout.splitlines() if ln.startswith("RESULT "))
        out[backend] = json.loads(line[len("RESULT "):])
    return out


def relative(x: float, y: float) -> float:
    return abs(x - y) / max(abs(y), 1e-300)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--large", action="store_true", help="also the 32k-dof sphere rung (15-20 s a run)")
    parser.add_argument("--bare", action="store_true", help="also the bare factorisation of each scene's K0")
    parser.add_argument("--grid", type=int, default=0, help="only the scaling check on a 2D grid of 2 GRID^2 dofs")
    args = parser.parse_args()
    results: dict = {"runs": {}, "bare": {}}
    if args.grid:
        r = grid_scaling(args.grid)
        print(json.dumps(r, indent=1))
        (HERE / "results").mkdir(exist_ok=True)
        (HERE / "results/cholesky_grid.json").write_text(json.dumps(r, indent=1))
        return
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir)
        scenes = [HERE / "scenes/peer_half_disc.toml", sphere_scene(tmp, 0.2, 5)]
        if args.large:
            scenes.append(sphere_scene(tmp, 0.25, 6))
        for scene in scenes:
            runs = []
            for i in range(args.repeat):
                for backend in BACKENDS if i % 2 == 0 else BACKENDS[::-1]:
                    runs.append(run_scene(scene, backend, tmp / f"out_{backend}"))
                    r = runs[-1]
                    print(f"{scene.stem:34s} {backend:8s} wall {r['wall_s']:6.2f} s  peak {r['peak_rss_mb']:7.0f} MB  "
                          f"factor {r['factor_s']:.3f} s  a {r['a']:.10g}  N {r['N']:.10g}", flush=True)
            results["runs"][scene.stem] = runs
            if args.bare:
                results["bare"][scene.stem] = bare(scene, tmp)
    print()
    print(f"{'scene':34s} {'backend':8s} {'dofs':>7s} {'wall s (median)':>16s} {'peak MB':>8s} {'factor s':>9s}")
    for name, runs in results["runs"].items():
        ref = next(r for r in runs if r["backend"] == "superlu")
        for backend in BACKENDS:
            mine = [r for r in runs if r["backend"] == backend]
            print(f"{name:34s} {backend:8s} {mine[0]['dofs']:7d} {statistics.median(r['wall_s'] for r in mine):16.2f} "
                  f"{statistics.median(r['peak_rss_mb'] for r in mine):8.0f} "
                  f"{statistics.median(r['factor_s'] for r in mine):9.3f}")
        worst = max(max(relative(r["a"], ref["a"]), relative(r["N"], ref["N"])) for r in runs)
        print(f"{'':34s} a and N agree to {worst:.1e} relative" + ("" if worst <= 1e-9 else "  ** MORE THAN 1e-9 **"))
    for name, both in results["bare"].items():
        for backend, r in both.items():
            print(f"bare {name:29s} {backend:8s} n {r['n']} m {r['m']}: factor {r['factor_s']:.3f} s, solve "
                  f"{r['solve_s'] * 1e3:.1f} ms, peak {r['peak_rss_mb']:.0f} MB (start {r['rss_before_mb']:.0f}), "
                  f"residual {r['residual']:.1e}" + (f", L {r['factor_bytes'] / 1e6:.0f} MB in {r['n_supernodes']} "
                                                     f"supernodes, largest front {r['largest_front']}"
                                                     if "factor_bytes" in r else ""))
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results/cholesky.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
