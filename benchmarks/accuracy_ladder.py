"""Convergence ladders of the peer problems (``benchmarks/scenes/peer_half_disc.toml``, 2D, and
``examples/solid/sphere_on_flat.toml``, 3D): each rung one ``ibfem run`` process, one at a time,
every cell size halved per rung (the far-field element size h0 halved, the levels around the
contact kept). Prints a
markdown table of a and N, their errors against the converged references, the differences
between successive rungs, the observed order of a's differences and the Richardson limit of a
from the last three rungs (docs/accuracy.md).

    python benchmarks/accuracy_ladder.py --problem steel --element-sizes 0.1 0.05 0.025 0.0125 --levels 3
    python benchmarks/accuracy_ladder.py --problem sphere3d --element-sizes 0.5 0.25 0.125 --levels 5
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import peers  # noqa: E402

# The reference of the problem ibfem solves (contact pairs on the undeformed geometry, the gap
# along the contact frame's normal): converged NGSolve P3, Richardson-checked (docs/accuracy.md)
REFERENCE_2D = {"steel": {"N": 5.09163e8, "a": (0.07664, 0.07673)}}


def along_flat(chord: float, radius: float = 1.0) -> float:
    """The half width along the block's flat top of a region whose end lies at ``chord`` from the
    disc's lowest point (summary.json's half_width: body 1's chord): x = R sin(2 asin(s / 2R))."""
    return radius * math.sin(2.0 * math.asin(chord / (2.0 * radius)))


def richardson(values: list[float]) -> tuple[float, float]:
    """(limit, observed order) from the last three values of a ladder refined by 2 per rung:
    p = log2(d1 / d2) of the successive differences, limit = last + d2 / (2^p - 1)."""
    f0, f1, f2 = values[-3:]
    d1, d2 = f1 - f0, f2 - f1
    if d1 == 0.0 or d2 == 0.0 or d1 / d2 <= 1.0:
        return f2, float("nan")
    p = math.log2(d1 / d2)
    return f2 + d2 / (2.0 ** p - 1.0), p


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problem", default="steel", choices=["steel", "aluminium", "sphere3d"])
    ap.add_argument("--element-sizes", type=float, nargs="+", required=True,
                    help="far-field element size h0 of each rung (both bodies)")
    ap.add_argument("--levels", type=int, nargs="+", required=True,
                    help="refinement levels around the contact: one for all rungs, or one per rung")
    ap.add_argument("--json", type=Path, default=None, help="write the rows here")
    args = ap.parse_args(argv)
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
