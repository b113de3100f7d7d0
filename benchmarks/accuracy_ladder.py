"""Convergence ladders of the peer problems (``benchmarks/scenes/peer_half_disc.toml``, 2D, and
``examples/solid/sphere_on_flat.toml``, 3D): each rung one ``ibfem run`` process, one at a time,
every cell size divided by the same ratio per rung (the far-field element size h0 divided, the
levels and radii of the zones around the contact kept). Prints a
markdown table of a and N, their errors against the converged references, the differences
between successive rungs, the observed order of a's differences and the Richardson limit of a
from the last three rungs (docs/accuracy.md).

    python benchmarks/accuracy_ladder.py --problem steel --element-sizes 0.1 0.05 0.025 0.0125 --levels 3
    python benchmarks/accuracy_ladder.py --problem sphere3d --element-sizes 0.5 0.25 0.125 --levels 5
    python benchmarks/accuracy_ladder.py --problem sphere3d --element-sizes 0.5 0.354 0.25 \
        --zones 6,0.07 5,0.14 4,0.28 3,0.56

``--offsets`` (3D, with ``--zones``): each rung solved with the grid moved along the contact
normal by these fractions of the finest cell; the table gives their means and spreads.

``--zones`` (3D): refinement zones about the contact, each ``levels,radius``, replacing the
scene's one zone: a grading whose cells grow in proportion to the distance from the contact, so
that halving h0 halves every cell of the bodies (the normal force of a point contact takes up the
far field's error: the displacement at a distance r from the contact falls only like 1 / r).
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

from ibfem.solver.reference.converged import SPHERE_ON_FLAT  # noqa: E402

# The reference of the problem ibfem solves (contact pairs on the undeformed geometry, the gap
# along the contact frame's normal): converged NGSolve P3, Richardson-checked (docs/accuracy.md)
REFERENCE_2D = {"steel": {"N": 5.09163e8, "a": (0.07664, 0.07673)}}


#: the 3D ladder's grading about the contact: each zone twice the radius of the one inside it and
#: one level coarser, so that the cells grow in proportion to the distance from the contact, out
#: to the bodies' far corners (the ladder of docs/accuracy.md; the default of --zones is now
#: found_zones(), which adds a last zone of 1 level within 2.24 m)
GRADED_ZONES = [(6, 0.07), (5, 0.14), (4, 0.28), (3, 0.56), (2, 1.2)]


def found_zones() -> list[tuple[int, float]]:
    """The default --zones: the accuracy target's grading of the far field
    (``ibfem.solver.solving.graded_around_contacts``) about the region the scene's own grid finds,
    from its deepest zone (at least 1.5 times the region's extent) one level coarser at every
    doubling of the radius out to the bodies' bounding boxes: derived from the contact and the
    bodies, not from this example (on sphere_on_flat: 6 ... 1 levels within 0.07 ... 2.24 m)."""
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import graded_around_contacts, resolve_problem, solve

    scene = load_scene(peers.SPHERE_SCENE)
    solution = solve(scene.problem)
    graded = graded_around_contacts(resolve_problem(scene.problem), solution)
    zones = {(int(r.levels), float(r.radius)) for b in graded.bodies for r in b.refinements}
    return sorted(zones, reverse=True)


def sphere_zones_scene(element_size: float, zones: list[tuple[int, float]], offset: float = 0.0) -> dict:
    """sphere_on_flat with both bodies' element size and these refinement zones about the contact
    (levels, radius), VTU, plots, probes and lines off; with ``offset`` the grid moved along the
    contact normal (z) by that fraction of the finest cell (``[solver] grid_offset``; along z the
    quarter model's symmetry planes stay on grid planes)."""
    data = tomllib.loads(peers.SPHERE_SCENE.read_text())
    for body in data["bodies"]:
        body["element_size"] = element_size
        body["refinement"] = [{"levels": lv, "around": "contact", "radius": r} for lv, r in zones]
    data["name"] = f"sphere3d h0 {element_size:.6g} zones {zones}"
    data["output"] = {"vtk": False, "plots": False}
    if offset:
        data.setdefault("solver", {})["grid_offset"] = [0.0, 0.0, offset / 2 ** max(lv for lv, _ in zones)]
    return data


def run_zones(element_size: float, zones: list[tuple[int, float]], workdir: Path, offset: float = 0.0) -> dict:
    """One rung of the 3D ladder with graded zones: its own ``ibfem run`` process (no estimate)."""
    tag = f"sphere3d_{element_size:.6g}_{offset:g}"
    scene = workdir / f"{tag}.json"
    scene.write_text(json.dumps(sphere_zones_scene(element_size, zones, offset)))
    row = {"code": "ibfem", "problem": "sphere3d", "rung": f"h0 {element_size:.4g}", "element_size": element_size,
           "zones": zones, "finest_cell": element_size / 2 ** max(lv for lv, _ in zones), "offset": offset}
    return peers.ibfem_row(scene, workdir / tag, row)


def mean_over_offsets(rows: list[dict]) -> list[dict]:
    """One row per element size: a and N averaged over the rung's grid offsets (the rows that
    solved), with their spread (largest minus smallest), the dofs' mean and the CPU and wall
    times' sums, the peak's largest."""
    out = []
    for h0 in dict.fromkeys(r["element_size"] for r in rows):
        group = [r for r in rows if r["element_size"] == h0 and "a" in r]
        if not group:
            out.append(next(r for r in rows if r["element_size"] == h0))
            continue
        row = dict(group[0])
        for key in ("a", "N"):
            values = [r[key] for r in group]
            row[key], row[key + "_spread"] = sum(values) / len(values), max(values) - min(values)
        row["dofs"] = round(sum(r["dofs"] for r in group) / len(group))
        row["offsets"] = [r.get("offset", 0.0) for r in group]
        for key in ("cpu_s", "wall_s"):
            row[key] = sum(r[key] for r in group)
        row["peak_mb"] = max(r["peak_mb"] for r in group)
        out.append(row)
    return out


def parse_zones(text: list[str]) -> list[tuple[int, float]]:
    zones = []
    for item in text:
        levels, radius = item.split(",")
        zones.append((int(levels), float(radius)))
    return zones


def along_flat(chord: float, radius: float = 1.0) -> float:
    """The half width along the block's flat top of a region whose end lies at ``chord`` from the
    disc's lowest point (summary.json's half_width: body 1's chord): x = R sin(2 asin(s / 2R))."""
    return radius * math.sin(2.0 * math.asin(chord / (2.0 * radius)))


def richardson(values: list[float], ratio: float = 2.0) -> tuple[float, float]:
    """(limit, observed order) from the last three values of a ladder refined by ``ratio`` per
    rung: p = log(d1 / d2) / log(ratio) of the successive differences, limit = last + d2 /
    (ratio^p - 1)."""
    f0, f1, f2 = values[-3:]
    d1, d2 = f1 - f0, f2 - f1
    if d1 == 0.0 or d2 == 0.0 or d1 / d2 <= 1.0:
        return f2, float("nan")
    p = math.log(d1 / d2) / math.log(ratio)
    return f2 + d2 / (ratio ** p - 1.0), p


def table_3d(rows: list[dict], ratio: float) -> str:
    """The 3D ladder against the converged reference of the same bodies (SPHERE_ON_FLAT): a, N,
    the differences between rungs, their observed order and each rung's error."""
    ref = SPHERE_ON_FLAT
    several = len(rows) > len({r["element_size"] for r in rows})
    if several:  # each rung at several grid offsets: their means, and the spread beside
        rows = mean_over_offsets(rows)
    spread = "| a spread | N spread " if several else ""
    lines = ["| h0 (m) | finest cell (m) | dofs | a (m) | a - previous | a error | N, quarter (N) | N - previous "
             f"| N error {spread}| CPU (s) | wall (s) | peak (MB) |", "|---|" * (12 + 2 * several)]
    lines[1] = lines[1].replace("||", "|")
    prev = None
    for r in rows:
        if "a" not in r:
            lines.append(f"| {r['rung']} | failed: {r.get('error')} |")
            continue
        da = "" if prev is None else f"{r['a'] - prev['a']:+.3e}"
        dn = "" if prev is None else f"{r['N'] - prev['N']:+.4e}"
        a_err, n_err = (r["a"] / ref["a"] - 1) * 100, (r["N"] / ref["N"] - 1) * 100
        extra = (f"| {r['a_spread'] / r['a'] * 100:.3f} % | {r['N_spread'] / r['N'] * 100:.3f} % "
                 if several else "")
        lines.append(f"| {r['element_size']:.4g} | {r.get('finest_cell', float('nan')):.3g} | {r['dofs']} | {r['a']:.6f} "
                     f"| {da} | {a_err:+.3f} % | {r['N']:.6e} | {dn} | {n_err:+.3f} % {extra}"
                     f"| {r['cpu_s']:.1f} | {r['wall_s']:.1f} | {r['peak_mb']:.0f} |")
        prev = r
    good = [r for r in rows if "a" in r]
    if len(good) >= 3:
        for key in ("a", "N"):
            lim, p = richardson([r[key] for r in good], ratio)
            lines.append(f"\nRichardson {key} (last three rungs, ratio {ratio:.4g}): {lim:.7g}, "
                         f"observed order {p:.2f}, "
                         f"{(lim / ref[key] - 1) * 100:+.3f} % from the reference {ref[key]:.7g}")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problem", default="steel", choices=["steel", "aluminium", "sphere3d"])
    ap.add_argument("--element-sizes", type=float, nargs="+", required=True,
                    help="far-field element size h0 of each rung (both bodies)")
    ap.add_argument("--levels", type=int, nargs="+", default=None,
                    help="refinement levels around the contact: one for all rungs, or one per rung")
    ap.add_argument("--zones", nargs="*", default=None, help="3D: refinement zones about the contact, "
                    "each LEVELS,RADIUS, the same on every rung (instead of --levels; none given: found_zones(), the accuracy target's grading about the region the scene's grid finds)")
    ap.add_argument("--offsets", type=float, nargs="+", default=[0.0],
                    help="3D with --zones: solve each rung with the grid moved along the contact normal by these "
                    "fractions of the finest cell, and tabulate their means (the grid's position scatters a and N)")
    ap.add_argument("--json", type=Path, default=None, help="write the rows here")
    ap.add_argument("--report", type=Path, default=None, help="3D: the table again from rows written by --json")
    args = ap.parse_args(argv)
    if args.report:
        sizes = args.element_sizes
        print(table_3d(json.loads(args.report.read_text()), sizes[-2] / sizes[-1] if len(sizes) > 1 else 2.0))
        return 0
    if args.zones is not None:
        if args.problem != "sphere3d":
            ap.error("--zones is for --problem sphere3d")
        zones = parse_zones(args.zones) if args.zones else found_zones()
        print(f"zones (levels, radius): {zones}", flush=True)
        rows = []
        with tempfile.TemporaryDirectory() as tmp:
            for h0 in args.element_sizes:
                for offset in args.offsets:
                    rows.append(run_zones(h0, zones, Path(tmp), offset))
                    print(json.dumps(rows[-1]), flush=True)
                    if args.json:  # written as it goes: a long ladder keeps the rungs it solved
                        args.json.write_text(json.dumps(rows, indent=1))
        sizes = args.element_sizes
        print()
        print(table_3d(rows, sizes[-2] / sizes[-1] if len(sizes) > 1 else 2.0))
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
        return 0
    if not args.levels:
        ap.error("give --levels (or --zones in 3D)")
    levels_of = args.levels * len(args.element_sizes) if len(args.levels) == 1 else args.levels
    if len(levels_of) != len(args.element_sizes):
        ap.error("--levels takes one value or one per element size")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for h0, levels in zip(args.element_sizes, levels_of):
            row = peers.run_ibfem(args.problem, h0, levels, Path(tmp))
            rows.append(row)
            print(json.dumps(row), flush=True)
    ref = REFERENCE_2D.get(args.problem)
    print("\n| h0, levels | dofs | a (m) | a - previous | a along the flat (m) | N (N/m) | N error | CPU (s) | wall (s) | peak (MB) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    prev = None
    for r in rows:
        if "a" not in r:
            print(f"| {r['rung']} | failed: {r.get('error')} |")
            continue
        da = "" if prev is None else f"{r['a'] - prev:+.3e}"
        ne = f"{(r['N'] / ref['N'] - 1) * 100:+.4f} %" if ref else ""
        flat = f"{along_flat(r['a']):.6f}" if ref else ""
        print(f"| {r['rung']} | {r['dofs']} | {r['a']:.6f} | {da} | {flat} | {r['N']:.6e} | {ne} | {r['cpu_s']:.1f} | "
              f"{r['wall_s']:.1f} | {r['peak_mb']:.0f} |")
        prev = r["a"]
    good = [r for r in rows if "a" in r]
    if len(good) >= 3:
        for key in ("a", "N", "p0"):
            if any(r.get(key) is None for r in good):
                continue
            lim, p = richardson([r[key] for r in good])
            print(f"Richardson {key} (last three rungs): {lim:.7g}, observed order {p:.2f}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
