"""``[solver] accuracy`` against hand-chosen grids: for each scene and target, one ``ibfem run``
with the target (its own process, wall time of the whole process), and the scene's own grid
scaled by 2^-k (every element size, k in ``--scales``; each its own process, ``--no-estimate``).
The true error of the contact's size against Hertz's theory for the computed force (2D: half
width; 3D: the circular contact's radius) decides which hand-chosen grids reach the target; the
table gives the accuracy run's time over the cheapest of them, in CPU time (user + system of the
process: less disturbed by other jobs on a shared machine) and wall time (docs/accuracy.md).

    python benchmarks/accuracy_target.py examples/mesh_convergence.toml --targets 0.01 0.002
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import peers  # noqa: E402

from ibfem.solver.io.scene import scene_from_dict  # noqa: E402
from ibfem.solver.reference import theory  # noqa: E402
from ibfem.solver.reports.validate import effective_properties  # noqa: E402


def true_size_error(data: dict, base: Path, summary: dict) -> float:
    """Relative error of a (2D) or the mean semi-axis (3D) against Hertz for the computed force."""
    scene = scene_from_dict(data, label="hertz", base_dir=base)
    c = summary["contacts"][0]
    if "semi_axes" in c:
        mats = [scene.problem.body(n).material for n in c["bodies"]]
        e_star = 1.0 / sum((1 - m.poissons_ratio ** 2) / m.youngs_modulus for m in mats)
        n_full = c["normal_force"] / c.get("model_share", 1.0)
        a = theory.hertz_sphere_radius(n_full, 1.0 / c["relative_curvatures"][0], e_star)
        return abs(sum(c["semi_axes"]) / 2 / a - 1.0)
    r_eff, e_eff = effective_properties(scene.problem, c)
    return abs(c["half_width"] / theory.hertz_half_width(c["normal_force"], r_eff, e_eff) - 1.0)


def run(data: dict, base: Path, tmp: Path, tag: str, estimate: bool) -> dict:
    data = json.loads(json.dumps(data))
    data["output"] = {"vtk": False, "plots": False}
    scene = tmp / f"{tag}.json"
    scene.write_text(json.dumps(data))
    ibfem = Path(sys.executable).with_name("ibfem")
    cmd = [str(ibfem), "run", str(scene), "--out", str(tmp / tag), "--quiet"] + ([] if estimate else ["--no-estimate"])
    code, out, err, wall, peak, cpu = peers.run_child(cmd)
    if code != 0:
        return {"tag": tag, "error": (err.strip().splitlines() or [f"exit {code}"])[-1], "wall_s": wall}
    summary = json.loads((tmp / tag / "summary.json").read_text())
    row = {"tag": tag, "wall_s": wall, "cpu_s": cpu, "peak_mb": peak,
           "dofs": sum(b["dofs"] for b in summary["bodies"].values()),
           "true_error": true_size_error(data, base, summary)}
    if "accuracy" in summary:
        row["ladder"] = [(r["dofs"], r["largest_error"]) for r in summary["accuracy"]["rungs"]]
        row["reached"] = summary["accuracy"]["reached"]
    return row


def scaled(data: dict, k: int) -> dict:
    out = json.loads(json.dumps(data))
    for body in out["bodies"]:
        body["element_size"] = body["element_size"] * 2.0 ** -k
    return out


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", type=Path)
    ap.add_argument("--targets", type=float, nargs="+", default=[0.01, 0.002])
    ap.add_argument("--scales", type=int, nargs="+", default=[-1, 0, 1, 2], help="hand grids: element sizes x 2^-k")
    args = ap.parse_args(argv)
    table = []
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        for path in args.scenes:
            data = tomllib.loads(path.read_text())
            data.pop("probes", None), data.pop("lines", None)
            base = path.resolve().parent
            hand = [dict(run(scaled(data, k), base, tmp, f"{path.stem}_k{k}", False), k=k) for k in args.scales]
            for r in hand:
                print(json.dumps(r), flush=True)
            for target in args.targets:
                d = json.loads(json.dumps(data))
                d.setdefault("solver", {})["accuracy"] = target
                r = run(d, base, tmp, f"{path.stem}_acc{target}", True)
                print(json.dumps(r), flush=True)
                ok = [h for h in hand if "true_error" in h and h["true_error"] <= target]
                best = min(ok, key=lambda h: h["wall_s"]) if ok else None
                table.append((path.stem, target, r, best))
    print("\n| example | target | rungs (dofs: estimated error) | true error | CPU (s) | wall (s) | cheapest hand grid "
          "reaching the target | its true error | its CPU (s) | its wall (s) | ratio, CPU | ratio, wall |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, target, r, best in table:
        ladder = "; ".join(f"{d}: {100 * e:.2g} %" for d, e in r.get("ladder", []))
        hand = f"sizes x 2^{-best['k']}, {best['dofs']} dofs" if best else "none of the scales"
        nan = float("nan")
        ratio_cpu = f"{r['cpu_s'] / best['cpu_s']:.2f}" if best and "cpu_s" in r else "n/a"
        ratio_wall = f"{r['wall_s'] / best['wall_s']:.2f}" if best and "wall_s" in r else "n/a"
        print(f"| {name} | {target:g} | {ladder or r.get('error')} | {100 * r.get('true_error', nan):.3g} % | "
              f"{r.get('cpu_s', nan):.2f} | {r['wall_s']:.1f} | {hand} | {100 * best['true_error'] if best else nan:.3g} % | "
              f"{best['cpu_s'] if best else nan:.2f} | {best['wall_s'] if best else nan:.1f} | {ratio_cpu} | {ratio_wall} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
