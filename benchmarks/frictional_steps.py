"""Load steps of frictional 3D contact: trials and the stick ratio on variants of the full ball on a block.

Each variant is examples/solid/full/ball_on_block.toml (a half ball R = 0.5 m on a block, steel,
friction 0.2, the ball's flat face moved by (0.3, 0, -4) mm) on a coarser grid (element size 0.1
with three levels unless said) with its own load steps, friction, displacement, materials or
turn, solved by ``ibfem run --no-estimate`` in its own process. Per variant: the trial solves in
all and per load step, and the stick ratio c/a against Mindlin's (1 - Q / (mu N))^(1/3) for the
run's own forces (Johnson 1985, section 7.2). ``--ibfem PATH`` runs another installation's
``ibfem`` (a checkout of an earlier commit) on the same scenes, for a before / after table.

    python benchmarks/frictional_steps.py [--variants NAME ...] [--ibfem PATH]

Measured (2026-11-29, docs/scale-3d.md "Load steps that start where the last one ended"): trials
32, 21, 51, 34, 34, 34 (the variants in the order below) against 32, 24, 57, 34, 37, 39 on the
commit before the load steps' starts; c/a within 0.001 of Mindlin in every run."""

from __future__ import annotations

import argparse
import copy
import json
import math
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BASE = ROOT / "examples" / "solid" / "full" / "ball_on_block.toml"
#: name -> (load steps, friction, the ball's face displacement (m), levels, element size, aluminium ball, turned)
VARIANTS = {
    "five_steps": (5, 0.2, (3e-4, 0.0, -4e-3), 3, 0.1, False, False),
    "three_steps_mu_0.3": (3, 0.3, (3e-4, 0.0, -4e-3), 3, 0.1, False, False),
    "eight_steps_aluminium": (8, 0.2, (3e-4, 0.0, -4e-3), 3, 0.1, True, False),
    "turned_four_steps": (4, 0.2, (3e-4, 0.0, -4e-3), 3, 0.1, False, True),
    "high_q": (5, 0.15, (6e-4, 2e-4, -4e-3), 3, 0.1, False, False),
    "four_levels": (5, 0.2, (3e-4, 0.0, -4e-3), 4, 0.125, False, False),
}
#: the turn of the turned variant: 37 degrees about (1, 2, 3) through the contact point
TURN_AXIS, TURN_DEG = np.array([1.0, 2.0, 3.0]), 37.0


def _turn(v) -> list[float]:
    """v turned by TURN_DEG about TURN_AXIS (Rodrigues)."""
    k = TURN_AXIS / np.linalg.norm(TURN_AXIS)
    t = math.radians(TURN_DEG)
    v = np.asarray(v, dtype=float)
    return (v * math.cos(t) + np.cross(k, v) * math.sin(t) + k * (k @ v) * (1.0 - math.cos(t))).tolist()


def variant_scene(name: str) -> dict:
    """The scene data of variant ``name``."""
    steps, mu, disp, levels, size, aluminium, turned = VARIANTS[name]
    d = copy.deepcopy(tomllib.loads(BASE.read_text(encoding="utf-8")))
    d["name"], d["output"] = name, {"vtk": False, "plots": False}
    d["solver"]["load_steps"] = steps
    d["contacts"][0]["friction"] = mu
    for body in d["bodies"]:
        body["element_size"] = size
        body["refinement"][0]["levels"] = levels
        if turned:
            body["shape"]["rotate"] = {"axis": TURN_AXIS.tolist(), "angle_deg": TURN_DEG}
            body["shape"]["pivot"] = [0.0, 0.0, 0.0]
    d["boundary_conditions"][0]["value"] = _turn(disp) if turned else list(disp)
    if aluminium:
        d["materials"].append({"name": "aluminium", "youngs_modulus": 7.0e10, "poissons_ratio": 0.33})
        d["bodies"][0]["material"] = "aluminium"
    return d


def run(name: str, ibfem: str, work: Path) -> dict:
    """Variant ``name`` solved by ``ibfem``: its trials, per step, and c/a against Mindlin's."""
    from ibfem.solver.reference import theory

    scene, out = work / f"{name}.json", work / name
    data = variant_scene(name)
    scene.write_text(json.dumps(data))
    done = subprocess.run([ibfem, "run", str(scene), "--out", str(out), "--quiet", "--no-estimate"],
                          capture_output=True, text=True)
    if not (out / "summary.json").exists():
        return {"variant": name, "error": (done.stderr.strip().splitlines() or [f"exit {done.returncode}"])[-1]}
    summary = json.loads((out / "summary.json").read_text())
    block, it = summary["contacts"][0], summary["iterations"]
    a, n = float(block["semi_axes"][0]), float(block["normal_force"])
    q = float(np.linalg.norm(block["tangential_force"]))
    mu = data["contacts"][0]["friction"]
    return {"variant": name, "converged": summary["converged"], "trials": it["total"], "per_step": it["per_step"],
            "stick_ratio": float(block["stick_semi_axes"][0]) / a,
            "mindlin": float(theory.mindlin_sphere_stick_ratio(q, n, mu))}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    ap.add_argument("--ibfem", default=str(Path(sys.executable).with_name("ibfem")),
                    help="the ibfem executable to run (default: this environment's)")
    args = ap.parse_args()
    print("| variant | converged | trials (per step) | c/a (Mindlin) |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="frictional_steps_") as tmp:
        for name in args.variants:
            r = run(name, args.ibfem, Path(tmp))
            if "error" in r:
                print(f"| {name} | failed: {r['error']} | | |", flush=True)
                continue
            print(f"| {name} | {r['converged']} | {r['trials']} {r['per_step']} | "
                  f"{r['stick_ratio']:.4f} ({r['mindlin']:.4f}) |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
