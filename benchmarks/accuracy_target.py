"""``[solver] accuracy`` against hand-chosen grids: for each scene and target, one ``ibfem run``
with the target (its own process, wall time of the whole process), and the scene's own grid
scaled by 2^-k (every element size, k in ``--scales``) and with its deepest contact zone m levels
deeper (m in ``--levels-added``, radius kept); each its own process, ``--no-estimate``.
The true errors of the contact's size (2D: half width; 3D: the circular contact's radius) and of
its peak pressure against Hertz's theory for the computed force, and of a 2D stick half width
against Cattaneo-Mindlin's, decide which hand-chosen grids reach the target; the
table gives the accuracy run's time over the cheapest of them, in CPU time (user + system of the
process: less disturbed by other jobs on a shared machine) and wall time (docs/accuracy.md).

    python benchmarks/accuracy_target.py examples/mesh_convergence.toml --targets 0.01 0.002
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import peers  # noqa: E402

from ibfem.solver.io.scene import scene_from_dict  # noqa: E402
from ibfem.solver.model.accuracy import contact_quantities  # noqa: E402
from ibfem.solver.reference import theory  # noqa: E402
from ibfem.solver.reports.validate import effective_properties  # noqa: E402


def true_errors(data: dict, base: Path, summary: dict) -> tuple[float, float, float | None]:
    """Relative errors of a (2D) or the mean semi-axis (3D) and of the peak pressure against
    Hertz for the computed force, and of a 2D stick half width against Cattaneo-Mindlin's for the
    computed forces, c = a sqrt(1 - |Q| / (mu N)) (None without one)."""
    scene = scene_from_dict(data, label="hertz", base_dir=base)
    c = summary["contacts"][0]
    p_max = contact_quantities(c)["max_pressure"]
    if "semi_axes" in c:
        mats = [scene.problem.body(n).material for n in c["bodies"]]
        e_star = 1.0 / sum((1 - m.poissons_ratio ** 2) / m.youngs_modulus for m in mats)
        n_full = c["normal_force"] / c.get("model_share", 1.0)
        a = theory.hertz_sphere_radius(n_full, 1.0 / c["relative_curvatures"][0], e_star)
        p0 = 3.0 * n_full / (2.0 * math.pi * a * a)
        return abs(sum(c["semi_axes"]) / 2 / a - 1.0), abs(p_max / p0 - 1.0), None
    r_eff, e_eff = effective_properties(scene.problem, c)
    a = theory.hertz_half_width(c["normal_force"], r_eff, e_eff)
    stick = None
    if c.get("stick_half_width") and c.get("friction"):
        c_cm = a * math.sqrt(1.0 - abs(c["tangential_force"]) / (c["friction"] * c["normal_force"]))
        stick = abs(c["stick_half_width"] / c_cm - 1.0)
    return abs(c["half_width"] / a - 1.0), abs(p_max / (2.0 * c["normal_force"] / (math.pi * a)) - 1.0), stick


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
           **dict(zip(("true_error", "true_p0_error", "true_stick_error"), true_errors(data, base, summary)))}
    if "accuracy" in summary:
        row["ladder"] = [(r["dofs"], r["largest_error"], r.get("refined")) for r in summary["accuracy"]["rungs"]]
        row["reached"] = summary["accuracy"]["reached"]
    return row


def scaled(data: dict, k: int) -> dict:
    out = json.loads(json.dumps(data))
    for body in out["bodies"]:
        body["element_size"] = body["element_size"] * 2.0 ** -k
    return out


def _worst(row: dict) -> float:
    return max(v for v in (row["true_error"], row["true_p0_error"], row.get("true_stick_error")) if v is not None)


def _pair(row: dict) -> str:
    """The true errors of a, p0 and (2D partial slip) c, in per cent."""
    keys = ("true_error", "true_p0_error") + (("true_stick_error",) if row.get("true_stick_error") is not None else ())
    return " / ".join(f"{100 * row.get(k, float('nan')):.3g}" for k in keys) + " %"


def deeper(data: dict, m: int) -> dict:
    """The scene with each body's deepest ``around = "contact"`` zone ``m`` levels deeper."""
    out = json.loads(json.dumps(data))
    for body in out["bodies"]:
        zones = body.get("refinement") or []
        zones = [zones] if isinstance(zones, dict) else zones
        contact = [z for z in zones if z.get("around") == "contact"]
        if contact:
            max(contact, key=lambda z: z["levels"])["levels"] += m
        body["refinement"] = zones
    return out


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", type=Path)
    ap.add_argument("--targets", type=float, nargs="+", default=[0.01, 0.002])
    ap.add_argument("--scales", type=int, nargs="+", default=[-1, 0, 1, 2], help="hand grids: element sizes x 2^-k")
    ap.add_argument("--levels-added", type=int, nargs="*", default=[1, 2],
                    help="hand grids: the deepest contact zone m levels deeper")
    args = ap.parse_args(argv)
    table = []
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        for path in args.scenes:
            data = tomllib.loads(path.read_text())
            data.pop("probes", None), data.pop("lines", None)
            base = path.resolve().parent
            hand = [dict(run(scaled(data, k), base, tmp, f"{path.stem}_k{k}", False), grid=f"sizes x 2^{-k}")
                    for k in args.scales]
            hand += [dict(run(deeper(data, m), base, tmp, f"{path.stem}_m{m}", False), grid=f"contact levels + {m}")
                     for m in args.levels_added]
            for r in hand:
                print(json.dumps(r), flush=True)
            for target in args.targets:
                d = json.loads(json.dumps(data))
                d.setdefault("solver", {})["accuracy"] = target
                r = run(d, base, tmp, f"{path.stem}_acc{target}", True)
                print(json.dumps(r), flush=True)
                ok = [h for h in hand if "true_error" in h and _worst(h) <= target]
                best = min(ok, key=lambda h: h["cpu_s"]) if ok else None
                table.append((path.stem, target, r, best))
    print("\n| example | target | rungs (dofs: estimated error) | true error, a / p0 (/ c) | CPU (s) | wall (s) | "
          "cheapest hand grid reaching the target | its true error | its CPU (s) | its wall (s) | ratio, CPU | ratio, wall |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, target, r, best in table:
        ladder = "; ".join(f"{d}{' (around the contact)' if how == 'contact' else ''}: {100 * e:.2g} %"
                           for d, e, how in r.get("ladder", []))
        hand = f"{best['grid']}, {best['dofs']} dofs" if best else "none of the hand grids"
        nan = float("nan")
        ratio_cpu = f"{r['cpu_s'] / best['cpu_s']:.2f}" if best and "cpu_s" in r else "n/a"
        ratio_wall = f"{r['wall_s'] / best['wall_s']:.2f}" if best and "wall_s" in r else "n/a"
        print(f"| {name} | {target:g} | {ladder or r.get('error')} | {_pair(r)} | "
              f"{r.get('cpu_s', nan):.2f} | {r['wall_s']:.1f} | {hand} | {_pair(best) if best else 'n/a'} | "
              f"{best['cpu_s'] if best else nan:.2f} | {best['wall_s'] if best else nan:.1f} | {ratio_cpu} | {ratio_wall} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
