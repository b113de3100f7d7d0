"""3D contact at scale: the full-model scenes of examples/solid/full (a ball on a block with
friction, the same pair turned with an aluminium ball, crossed cylinders), each solved in its own
process: wall and CPU time, peak memory (``/usr/bin/time``), dofs, contact dofs, the driver's
stage times, and the answer against theory: the semi-axes a, b against Hertz for the computed
normal force (Johnson 1985 sections 4.2 and 4.2.2, solver.reference.theory) and the stick ratio
c/a against Mindlin's (1 - Q / (mu N))^(1/3) (Johnson section 7.2).

``--levels L`` solves every scene with L refinement levels instead of the scene's own (a smaller
rung of the same scene: the acceptance targets are for the scenes as written). ``--scene-disc``
skips the coarse pass that sizes a large contact's candidate disc (solver.contact.sizing), for
comparison. ``--threads N`` runs the children with ``IBFEM_THREADS=N`` (the threads of each
body's large fronts and of the bodies' solves; 1: one thread); each row records the machine's load average (1 minute) before and after its run, since wall times on a
shared machine follow it.

    python benchmarks/full_3d.py [--scenes ball_on_block crossed_cylinders ...] [--levels 3] [--scene-disc]
                                 [--threads 1]

Prints a table, the same rows as the markdown table of docs/scale-3d.md ("Against the
targets"), and writes benchmarks/results/full_3d.json (or --out).

Measured (2026-11-28, each body's large fronts on two threads, the bodies one after the other; a
machine shared with four other sessions at load 2-6, so wall times follow the load): the ball on
a block 125.9-161.7 s wall, 90.9-92.9 s CPU, 2.93-2.95 GB (bodies side by side, alternated with
those runs: 121.5-185.9 s wall, 93.2-98.5 s CPU, 3.77-3.92 GB; one thread 93.2 s, 91.0 s CPU,
2.94 GB as the load fell to 2); the crossed cylinders 109.3 s, 86.9 s CPU, 2.24 GB; the turned
pair 240.0 s, 116.1 s CPU, 2.53 GB; a, b and c/a as before (docs/scale-3d.md). With the factor's
ranges written on a second thread, the large fronts' rows and the trials' small system on threads
(load 0.8-1.5, ``--threads 2``): the crossed cylinders 48 s wall (67 s CPU), 2.25 GB; the ball on
a block 50 s (71 s), 2.64 GB; the turned pair 62 s (88 s), 2.45 GB. With the trials' terms in
compiled passes and their LU in single precision (load 1.4-1.7): the turned pair 59-61 s (84-85 s
CPU), 2.44-2.46 GB; the crossed cylinders 44 s (64 s), 2.26 GB; the ball on a block 48 s (69 s),
2.65 GB. With the load steps starting where the last ended and the coarse pass in one step (quiet
machine, load 0.6-1.6): the turned pair 48-52 s (69-74 s CPU), 2.46 GB, 31 trials; the crossed
cylinders 44 s, 2.27 GB; the ball on a block 44 s, 2.65 GB, 37 trials."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SCENES = ("ball_on_block", "ball_on_block_turned", "crossed_cylinders")

CHILD = r"""
import json, math, sys, time, tomllib
import numpy as np
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model.estimate import estimate_size
from ibfem.solver.solving import solve
from ibfem.solver.reference import theory
path, levels = sys.argv[1], int(sys.argv[2])
if "scene-disc" in sys.argv[3:]:  # no coarse pass: the candidate disc as the scene gives it
    from ibfem.solver.contact import sizing
    sizing.MIN_CONTACT_DOFS = math.inf
if "given-order" in sys.argv[3:]:  # each body factored in the driver's order, no other order compared
    from ibfem.solver.fem import linalg
    linalg.ORDER_CHOICE_DOFS = math.inf
d = tomllib.load(open(path, "rb"))
d["output"] = {"vtk": False, "plots": False}
if levels >= 0:
    for b in d["bodies"]:
        for zone in b.get("refinement", []):
            zone["levels"] = levels
scene = load_scene(d, label=path, base_dir=str(__import__("pathlib").Path(path).parent))
problem = scene.problem
estimate = estimate_size(problem)
t, c = time.perf_counter(), time.process_time()
sol = solve(problem)
wall, cpu = time.perf_counter() - t, time.process_time() - c
block = sol.contacts[0]
n = float(block["normal_force"])
a, b = (float(v) for v in block["semi_axes"])
mats = {m["name"]: m for m in d["materials"]}
e = [(mats[x["material"]]["youngs_modulus"], mats[x["material"]]["poissons_ratio"]) for x in d["bodies"]]
e_star = theory.effective_modulus(e[0][0], e[0][1], e[1][0], e[1][1])
shapes = [x["shape"] for x in d["bodies"]]
if shapes[0]["type"] == "half_cylinder":
    radii = sorted(s["radius"] for s in shapes)
    a_h, b_h, _ = theory.hertz_elliptic_contact(n, (1.0 / radii[1], 1.0 / radii[0]), e_star)
else:
    a_h = b_h = theory.hertz_sphere_radius(n, shapes[0]["radius"], e_star)
row = dict(scene=path, levels=levels, dofs=int(sum(v["dofs"] for v in sol.body_info.values())),
           estimated_dofs=float(estimate.dofs), estimated_memory_gb=float(estimate.memory) / 2**30,
           contact_dofs=int(sol.iterations["contact_dofs"]), converged=bool(sol.converged),
           iterations=int(sol.iterations["total"]), wall_s=wall, cpu_s=cpu, timings=sol.timings,
           candidate_region=sol.iterations.get("candidate_region"),
           normal_force=n, a=a, b=b, hertz_a=a_h, hertz_b=b_h, a_error=a / a_h - 1.0, b_error=b / b_h - 1.0)
friction = d["contacts"][0].get("friction")
if friction:
    q = float(np.linalg.norm(block["tangential_force"]))
    stick = block.get("stick_semi_axes") or [0.0, 0.0]
    row.update(tangential_force=q, stick_ratio=float(stick[0]) / a,
               mindlin_stick_ratio=float(theory.mindlin_sphere_stick_ratio(q, n, friction)))
print("RESULT " + json.dumps(row))
"""


def timed_child(child: str, args: list[str], env: dict | None = None) -> tuple[dict, float, float, float] | None:
    """Run ``python -c child ARGS`` under /usr/bin/time (``env``: variables added to the
    environment): (its ``RESULT`` row, the process's wall and CPU seconds, its peak resident
    memory in GB), or None when it failed (its stderr echoed)."""
    cmd = ["/usr/bin/time", "-f", "TIME %e %U %S %M", sys.executable, "-c", child, *args]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env={**os.environ, **(env or {})})
    lines = (done.stdout + done.stderr).splitlines()
    result = next((ln for ln in lines if ln.startswith("RESULT ")), None)
    if done.returncode != 0 or result is None:
        sys.stderr.write(done.stderr[-3000:])
        return None
    wall, user, system, peak_kb = next(ln for ln in lines if ln.startswith("TIME ")).split()[1:]
    return json.loads(result[len("RESULT "):]), float(wall), float(user) + float(system), float(peak_kb) / 2**20


def run(scene: Path, levels: int, scene_disc: bool = False, given_order: bool = False, env: dict | None = None) -> dict:
    flags = (["scene-disc"] if scene_disc else []) + (["given-order"] if given_order else [])
    load_before = os.getloadavg()[0]
    timed = timed_child(CHILD, [str(scene), str(levels)] + flags, env)
    if timed is None:
        return {"scene": str(scene), "levels": levels, "failed": True}
    row, wall, cpu, peak_gb = timed
    row.update(process_wall_s=wall, process_cpu_s=cpu, peak_gb=peak_gb, environment=env or {},
               load_average=[load_before, os.getloadavg()[0]])
    return row


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    ap.add_argument("--levels", type=int, default=-1, help="refinement levels of every zone (default: the scene's)")
    ap.add_argument("--scene-disc", action="store_true",
                    help="no coarse pass: the contacts' candidate disc as the scene gives it (for comparison)")
    ap.add_argument("--given-order", action="store_true",
                    help="every body factored in the driver's order (the fill-reducing order of the whole "
                         "system), not the cheaper of it and the order with the contact nodes contracted (for comparison)")
    ap.add_argument("--threads", type=int, default=None,
                    help="IBFEM_THREADS of the runs (1: every factorisation and solve on one thread)")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "full_3d.json")
    args = ap.parse_args(argv)
    env = {}
    if args.threads is not None:
        env["IBFEM_THREADS"] = str(args.threads)
    rows = []
    print(f"{'scene':22} {'dofs':>8} {'est':>8} {'m':>6} {'wall s':>7} {'cpu s':>7} {'GB':>5} {'est GB':>6} "
          f"{'a err':>7} {'b err':>7} {'c/a':>6} {'Mindlin':>7}")
    for name in args.scenes:
        row = run(ROOT / "examples" / "solid" / "full" / f"{name}.toml", args.levels, args.scene_disc, args.given_order,
                  env)
        rows.append(row)
        if row.get("failed"):
            print(f"{name:22} failed")
            continue
        stick = f"{row['stick_ratio']:6.3f} {row['mindlin_stick_ratio']:7.3f}" if "stick_ratio" in row else f"{'-':>6} {'-':>7}"
        print(f"{name:22} {row['dofs']:8d} {row['estimated_dofs']:8.0f} {row['contact_dofs']:6d} {row['process_wall_s']:7.1f} "
              f"{row['process_cpu_s']:7.1f} {row['peak_gb']:5.2f} {row['estimated_memory_gb']:6.2f} "
              f"{100 * row['a_error']:6.2f}% {100 * row['b_error']:6.2f}% {stick}"
              + ("" if row["converged"] else "  NOT CONVERGED"), flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=1))
    print()
    print(markdown(rows))
    return 0


def markdown(rows: list[dict]) -> str:
    """The rows as the table of docs/scale-3d.md ("Against the targets")."""
    out = ["| scene | dofs | m | peak | CPU / wall | coarse pass / factorisation / trials / final field (wall) | a vs Hertz "
           "| b vs Hertz | c/a, Mindlin |", "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        name = Path(row["scene"]).stem
        if row.get("failed"):
            out.append(f"| {name} | failed | | | | | | | |")
            continue
        t = row["timings"]
        coarse = f"{t['coarse_pass_s']:.0f}" if "coarse_pass_s" in t else "-"
        stages = (f"{coarse} / {t.get('factor_s', 0):.0f} / {t.get('iterations_s', 0):.0f} / {t.get('results_s', 0):.0f} s, "
                  f"{row['iterations']} trials")
        stick = f"{row['stick_ratio']:.4f}, {row['mindlin_stick_ratio']:.4f}" if "stick_ratio" in row else "-"
        load = "-".join(f"{v:.1f}" for v in row.get("load_average", []))
        out.append(f"| {name} | {row['dofs']:,} | {row['contact_dofs']:,} | {row['peak_gb']:.2f} GB | "
                   f"{row['process_cpu_s']:.0f} s / {row['process_wall_s']:.0f} s (load {load}) | {stages} | "
                   f"{100 * row['a_error']:+.2f} % | "
                   f"{100 * row['b_error']:+.2f} % | {stick} |" + ("" if row["converged"] else " not converged"))
    return "\n".join(out)


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
