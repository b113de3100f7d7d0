"""The size estimate of ``ibfem run --check`` against the run: every 3D scene of examples/solid
and examples/contact3d (and, with --full, the full models of examples/solid/full) is estimated and then solved in its
own process (VTU and plots off); the table gives dofs and peak resident memory
(``/usr/bin/time``) estimated and measured, and for contact scenes the condensed contact dofs m.
The aim is both within 30 %.

    python benchmarks/check_estimate_3d.py [--full] [--scenes sphere_on_flat ...]

Prints a table and writes benchmarks/results/check_estimate_3d.json (or --out)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from full_3d import timed_child  # benchmarks/ is the script's folder

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SOLID = ROOT / "examples" / "solid"

CHILD = r"""
import dataclasses, json, sys, tomllib
from pathlib import Path
from ibfem.solver.io.run_size import run_size
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model.estimate import estimate_contact_dofs
from ibfem.solver.solving import solve
path = Path(sys.argv[1])
d = tomllib.load(open(path, "rb"))
d["output"] = {"vtk": False, "plots": False}
problem = load_scene(d, label=str(path), base_dir=str(path.parent)).problem
size, _ = run_size(problem)  # what --check prints (a coarse pass solved where the run solves one)
sol = solve(problem)
discs = ((sol.iterations or {}).get("candidate_region") or {}).get("contacts") or {}
contacts = list(problem.contacts)
for k, disc in discs.items():  # the disc the run condensed on, where a coarse pass sized it
    if disc:
        c = contacts[int(k)]
        fraction = c.options.extent_fraction * disc["extent"] / disc["scene_extent"]
        contacts[int(k)] = dataclasses.replace(c, options=dataclasses.replace(c.options, extent_fraction=fraction))
row = dict(scene=path.stem, dofs=int(sum(v["dofs"] for v in sol.body_info.values())),
           estimated_dofs=float(size.dofs), estimated_gb=float(size.memory) / 2**30,
           estimated_contact_dofs=float(estimate_contact_dofs(dataclasses.replace(problem, contacts=tuple(contacts)))),
           contact_dofs=int(sol.iterations.get("contact_dofs", 0)) if sol.iterations else 0,
           converged=bool(sol.converged))
print("RESULT " + json.dumps(row))
"""


def run(scene: Path) -> dict:
    timed = timed_child(CHILD, [str(scene)])
    if timed is None:
        return {"scene": scene.stem, "failed": True}
    row, wall, cpu, peak_gb = timed
    row.update(wall_s=wall, cpu_s=cpu, peak_gb=peak_gb)
    return row


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--full", action="store_true", help="also the full models (up to 3 GB and minutes each)")
    ap.add_argument("--scenes", nargs="+", help="scene names (default: every 3D scene of examples/solid and examples/contact3d)")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "check_estimate_3d.json")
    args = ap.parse_args(argv)
    paths = sorted(SOLID.glob("*.toml")) + sorted((ROOT / "examples" / "contact3d").glob("*.toml"))
    paths += sorted((SOLID / "full").glob("*.toml")) if args.full else []
    paths = [p for p in paths if 'model = "solid"' in p.read_text()]
    if args.scenes:
        paths = [p for p in paths if p.stem in args.scenes]
    print(f"{'scene':28} {'dofs':>8} {'est':>8} {'err':>6} {'m':>6} {'est m':>7} {'GB':>5} {'est GB':>6} {'err':>6} {'cpu s':>6}")
    rows = []
    for path in paths:
        row = run(path)
        rows.append(row)
        if row.get("failed"):
            print(f"{path.stem:28} failed", flush=True)
            continue
        print(f"{row['scene']:28} {row['dofs']:8d} {row['estimated_dofs']:8.0f} "
              f"{100 * (row['estimated_dofs'] / row['dofs'] - 1):5.0f}% {row['contact_dofs']:6d} "
              f"{row['estimated_contact_dofs']:7.0f} {row['peak_gb']:5.2f} {row['estimated_gb']:6.2f} "
              f"{100 * (row['estimated_gb'] / row['peak_gb'] - 1):5.0f}% {row['cpu_s']:6.1f}", flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
