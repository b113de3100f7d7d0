"""``[solver] accuracy`` against hand-chosen grids: for each scene and target, one ``ibfem run``
with the target (its own process, wall time of the whole process), and the scene's own grid
scaled by 2^-k (every element size, k in ``--scales``), with its deepest contact zone m levels
deeper (m in ``--levels-added``, radius kept), with a zone m levels deeper than the deepest
added within a radius r around the contact (``--zones-added m:r``) and with every body's zones
replaced by a given list about the contact, its element size too where given (``--hand-zones``:
a far field graded by hand); each its own process, ``--no-estimate``. ``--targets`` with no value
runs the hand grids alone. The true errors against Hertz's theory for the computed force decide which
hand-chosen grids reach the target: the contact's size (2D: half width; 3D: both semi-axes of
the circular contact), its peak pressure, the largest von Mises stress below it (Hertz's on the
load axis: plane strain in 2D, the sphere's axis stresses in 3D), a 2D stick half width against
Cattaneo-Mindlin's, and the normal force against ``--force-reference`` where given (3D: no
closed form holds for the finite bodies' force at the prescribed approach). The table gives the
accuracy run's time over the cheapest of them, in CPU time (user + system of the process: less
disturbed by other jobs on a shared machine) and wall time (docs/accuracy.md).

    python benchmarks/accuracy_target.py examples/mesh_convergence.toml --targets 0.01 0.002
    python benchmarks/accuracy_target.py examples/solid/sphere_on_flat.toml --scales 0 --levels-added \\
        --targets 0.01 0.002 --force-reference 1.3554268e7 \\
        --hand-zones "6,0.07;5,0.14;4,0.28;3,0.56;2,1.12;1,2.24" \\
        "0.1767767/6,0.07;5,0.14;4,0.28;3,0.56;2,1.12;1,2.24"

(the hand grids of the sphere: the far field graded about the contact, and the same grid with every
cell sqrt(2) times smaller, the cheapest found reaching 0.2 %.)

(1.3554268e7 N: the whole contact's force of the converged reference of sphere_on_flat's bodies,
four times ``ibfem.solver.reference.converged.SPHERE_ON_FLAT["N"]``; earlier tables used
1.36808e7 N, the limit of ibfem's own ladder on a far field that was never refined.)
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

import numpy as np  # noqa: E402

from ibfem.solver.io.scene import scene_from_dict  # noqa: E402
from ibfem.solver.model.accuracy import contact_quantities  # noqa: E402
from ibfem.solver.reference import theory  # noqa: E402
from ibfem.solver.reports.validate import effective_properties  # noqa: E402


def true_errors(data: dict, base: Path, summary: dict, force_reference: float | None = None) -> dict:
    """Relative errors (absolute values) against Hertz's theory for the computed force: ``a`` (2D
    half width; 3D the larger of both semi-axes'), ``p0``, ``von_mises`` (the largest below the
    contact against Hertz's largest on the load axis), ``stick`` (a 2D stick half width against
    Cattaneo-Mindlin's for the computed forces, c = a sqrt(1 - |Q| / (mu N))) and ``N`` against
    ``force_reference`` (the whole contact's force), each None where not defined."""
    scene = scene_from_dict(data, label="hertz", base_dir=base)
    c = summary["contacts"][0]
    p_max = contact_quantities(c)["max_pressure"]
    nu = scene.problem.body(c["bodies"][1]).material.poissons_ratio
    out = {"stick": None, "N": None, "von_mises": None}
    if "semi_axes" in c:
        mats = [scene.problem.body(n).material for n in c["bodies"]]
        e_star = 1.0 / sum((1 - m.poissons_ratio ** 2) / m.youngs_modulus for m in mats)
        n_full = c["normal_force"] / c.get("model_share", 1.0)
        a = theory.hertz_sphere_radius(n_full, 1.0 / c["relative_curvatures"][0], e_star)
        p0 = 3.0 * n_full / (2.0 * math.pi * a * a)
        sr, sz = theory.hertz_sphere_axis_stress(np.linspace(0.0, 3.0, 30001), 1.0, 1.0, nu)
        vm_peak = float(np.max(np.abs(sr - sz)))
        out.update(a=max(abs(s / a - 1.0) for s in c["semi_axes"]), p0=abs(p_max / p0 - 1.0))
        if force_reference:
            out["N"] = abs(n_full / force_reference - 1.0)
    else:
        r_eff, e_eff = effective_properties(scene.problem, c)
        a = theory.hertz_half_width(c["normal_force"], r_eff, e_eff)
        p0 = 2.0 * c["normal_force"] / (math.pi * a)
        vm_peak = theory.axis_peak(nu, "von_mises")[0]
        out.update(a=abs(c["half_width"] / a - 1.0), p0=abs(p_max / p0 - 1.0))
        if c.get("stick_half_width") and c.get("friction"):
            c_cm = a * math.sqrt(1.0 - abs(c["tangential_force"]) / (c["friction"] * c["normal_force"]))
            out["stick"] = abs(c["stick_half_width"] / c_cm - 1.0)
        if force_reference:
            out["N"] = abs(c["normal_force"] / force_reference - 1.0)
    vm = c.get("max_von_mises")
    if vm is not None and c.get("friction", 0.0) == 0.0:  # Hertz's field: frictionless only
        out["von_mises"] = abs(vm / (vm_peak * p0) - 1.0)
    return out


def run(data: dict, base: Path, tmp: Path, tag: str, estimate: bool, force_reference: float | None = None) -> dict:
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
           "true": true_errors(data, base, summary, force_reference)}
    if "accuracy" in summary:
        row["ladder"] = [(r["dofs"], r["largest_error"], r.get("refined")) for r in summary["accuracy"]["rungs"]]
        row["reached"] = summary["accuracy"]["reached"]
    return row


def scaled(data: dict, k: int) -> dict:
    out = json.loads(json.dumps(data))
    for body in out["bodies"]:
        body["element_size"] = body["element_size"] * 2.0 ** -k
    return out


_KEYS = ("a", "p0", "von_mises", "stick", "N")


def _worst(row: dict) -> float:
    return max(v for v in row["true"].values() if v is not None)


def _pair(row: dict) -> str:
    """The true errors present (a / p0 / von Mises / c / N), in per cent."""
    true = row.get("true") or {}
    return " / ".join(f"{k} {100 * true[k]:.3g}" for k in _KEYS if true.get(k) is not None) + " %"


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


def zoned(data: dict, m: int, radius: float) -> dict:
    """The scene with one more zone around the contact in each body that has one: ``m`` levels
    deeper than its deepest ``around = "contact"`` zone, within ``radius``."""
    out = json.loads(json.dumps(data))
    for body in out["bodies"]:
        zones = body.get("refinement") or []
        zones = [zones] if isinstance(zones, dict) else zones
        contact = [z for z in zones if z.get("around") == "contact"]
        if contact:
            deepest = max(contact, key=lambda z: z["levels"])
            zones = zones + [dict(deepest, levels=deepest["levels"] + m, radius=radius)]
        body["refinement"] = zones
    return out


def with_zones(data: dict, zones: list[tuple[int, float]], element_size: float | None = None) -> dict:
    """The scene with every body's refinement replaced by these (levels, radius) zones around the
    contact (a graded grid chosen by hand: the accuracy run's own last grid, or a cheaper one),
    and its element size where given."""
    out = json.loads(json.dumps(data))
    for body in out["bodies"]:
        body["refinement"] = [{"levels": lv, "around": "contact", "radius": r} for lv, r in zones]
        if element_size is not None:
            body["element_size"] = element_size
    return out


def parse_zones(text: str) -> tuple[float | None, list[tuple[int, float]]]:
    """``[ELEMENT_SIZE/]LEVELS,RADIUS;LEVELS,RADIUS;...`` as (element size or None, [(levels, radius)])."""
    size, _, zones = text.rpartition("/")
    pairs = [(int(z.split(",")[0]), float(z.split(",")[1])) for z in zones.split(";") if z.strip()]
    return (float(size) if size else None), pairs


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", type=Path)
    ap.add_argument("--targets", type=float, nargs="*", default=[0.01, 0.002], help="none: the hand grids alone")
    ap.add_argument("--scales", type=int, nargs="*", default=[-1, 0, 1, 2], help="hand grids: element sizes x 2^-k")
    ap.add_argument("--levels-added", type=int, nargs="*", default=[1, 2],
                    help="hand grids: the deepest contact zone m levels deeper")
    ap.add_argument("--zones-added", nargs="*", default=[], metavar="M:RADIUS",
                    help="hand grids: a zone M levels deeper than the deepest within RADIUS of the contact")
    ap.add_argument("--hand-zones", nargs="*", default=[], metavar="[SIZE/]LEVELS,RADIUS;...",
                    help="hand grids: every body's refinement replaced by these zones around the contact "
                         "(e.g. the far field graded about it), and its element size where given")
    ap.add_argument("--force-reference", type=float, default=None,
                    help="the converged normal force of the whole contact, to judge N against")
    args = ap.parse_args(argv)
    table = []
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        for path in args.scenes:
            data = tomllib.loads(path.read_text())
            data.pop("probes", None), data.pop("lines", None)
            base = path.resolve().parent
            ref = args.force_reference
            hand = [dict(run(scaled(data, k), base, tmp, f"{path.stem}_k{k}", False, ref), grid=f"sizes x 2^{-k}")
                    for k in args.scales]
            hand += [dict(run(deeper(data, m), base, tmp, f"{path.stem}_m{m}", False, ref), grid=f"contact levels + {m}")
                     for m in args.levels_added]
            for spec in args.zones_added:
                m, radius = int(spec.split(":")[0]), float(spec.split(":")[1])
                hand.append(dict(run(zoned(data, m, radius), base, tmp, f"{path.stem}_z{m}_{radius}", False, ref),
                                 grid=f"a zone {m} level(s) deeper within {radius:g} m"))
            for k, spec in enumerate(args.hand_zones):
                size, zones = parse_zones(spec)
                hand.append(dict(run(with_zones(data, zones, size), base, tmp, f"{path.stem}_zones{k}", False, ref),
                                 grid=(f"element size {size:g} m, " if size else "")
                                 + "zones " + ", ".join(f"{lv} within {r:g} m" for lv, r in zones)))
            for r in hand:
                print(json.dumps(r), flush=True)
            for target in args.targets:
                d = json.loads(json.dumps(data))
                d.setdefault("solver", {})["accuracy"] = target
                r = run(d, base, tmp, f"{path.stem}_acc{target}", True, ref)
                print(json.dumps(r), flush=True)
                ok = [h for h in hand if "true" in h and _worst(h) <= target]
                best = min(ok, key=lambda h: h["cpu_s"]) if ok else None
                table.append((path.stem, target, r, best))
    print("\n| example | target | rungs (dofs: estimated error) | true error, a / p0 (/ c) | CPU (s) | wall (s) | "
          "peak (MB) | cheapest hand grid reaching the target | its true errors | its CPU (s) | its wall (s) | its peak (MB) | "
          "ratio, CPU | ratio, wall |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, target, r, best in table:
        ladder = "; ".join(f"{d}{' (around the contact)' if how == 'contact' else ''}: {100 * e:.2g} %"
                           for d, e, how in r.get("ladder", []))
        hand = f"{best['grid']}, {best['dofs']} dofs" if best else "none of the hand grids"
        nan = float("nan")
        ratio_cpu = f"{r['cpu_s'] / best['cpu_s']:.2f}" if best and "cpu_s" in r else "n/a"
        ratio_wall = f"{r['wall_s'] / best['wall_s']:.2f}" if best and "wall_s" in r else "n/a"
        print(f"| {name} | {target:g} | {ladder or r.get('error')} | {_pair(r)} | "
              f"{r.get('cpu_s', nan):.2f} | {r['wall_s']:.1f} | {r.get('peak_mb', nan):.0f} | {hand} | "
              f"{_pair(best) if best else 'n/a'} | {best['cpu_s'] if best else nan:.2f} | "
              f"{best['wall_s'] if best else nan:.1f} | {best['peak_mb'] if best else nan:.0f} | {ratio_cpu} | {ratio_wall} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
