"""Where the scatter of the 2D contact width comes from: the peer problem
(``benchmarks/scenes/peer_half_disc.toml``, steel) solved with the whole grid moved by
fractions of the finest cell (``[solver] grid_offset``), along the block's top (x) and across
it (y) separately, one process, one solve after the other. Prints a markdown table of a
(``half_width``), N, a against Hertz's a for the computed N (the part of a's scatter that N's
does not explain) and the spread of each over the x and the y offsets.

Also evaluates, at each solution, the width's edge coefficient (the root the width search
finds) at four trial widths evenly spaced over one finest cell about the found width, and the
root of the straight line through them: whether the scatter is a grid-periodic wiggle of that
function in the width (then the fitted root would not scatter) or a shift of the whole function
with the grid (it would).

    python benchmarks/accuracy_offsets.py --element-size 0.05 --levels 3 --fractions 0 0.1 0.2 0.3 0.5 0.7 0.9
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import peers  # noqa: E402

from ibfem.solver.contact import band, driver  # noqa: E402
from ibfem.solver.io.scene import scene_from_dict  # noqa: E402
from ibfem.solver.reference import theory  # noqa: E402
from ibfem.solver.solving import solve  # noqa: E402

E_STEEL, NU_STEEL, RADIUS = 2.0e11, 0.3, 1.0


class _EdgeProbe:
    """Records, before the final report of a contact solve, the edge coefficient at trial widths
    spread over one finest cell about the found width, and the root of their straight line."""

    def __init__(self, trials: int = 4):
        self.trials, self.root, self.slope = trials, math.nan, math.nan
        self._results = driver.ContactDriver._results

    def __enter__(self):
        probe = self

        def results(drv):
            c, a0, lam = drv.contacts[0], drv.widths[0], drv.prev[0]
            widths = a0 + (np.arange(probe.trials) + 0.5 - 0.5 * probe.trials) / probe.trials * c.h
            values = []
            for a in widths:
                kc, fc, infos = drv._assemble_trial([a])
                x, _ = drv._solve_small(lam, kc, fc)
                values.append(band._edge_coefficient(c, infos[0], x, a))
            slope, intercept = np.polyfit(widths - a0, values, 1)
            probe.root, probe.slope = a0 - intercept / slope, slope * c.h
            return probe._results(drv)

        driver.ContactDriver._results = results
        return self

    def __exit__(self, *exc):
        driver.ContactDriver._results = self._results


def solve_offset(element_size: float, levels: int, offset: tuple[float, float]) -> dict:
    """One solve of the peer problem with the grid moved by ``offset`` (fractions of the finest cell)."""
    data = peers.scene_data("steel", element_size, levels)
    data.setdefault("solver", {})["grid_offset"] = [f / 2 ** levels for f in offset]
    scene = scene_from_dict(data, label="offset study", base_dir=Path("."))
    with _EdgeProbe() as probe:
        block = solve(scene.problem).contacts[0]
    n, a = float(block["normal_force"]), float(block["half_width"])
    e_star = theory.effective_modulus(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL)
    return {"offset": offset, "a": a, "N": n, "a_fit": probe.root,
            "a_vs_hertz": a / theory.hertz_half_width(n, RADIUS, e_star) - 1.0}


def _spread(rows: list[dict], key: str) -> float:
    values = [r[key] for r in rows]
    return max(values) - min(values)


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--element-size", type=float, default=0.05, help="far-field element size h0 (both bodies)")
    ap.add_argument("--levels", type=int, default=3, help="refinement levels around the contact")
    ap.add_argument("--fractions", type=float, nargs="+", default=[0.0, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9],
                    help="offsets in fractions of the finest cell, applied along x and along y in turn")
    args = ap.parse_args(argv)
    groups = {"x": [], "y": []}
    print("| offset (finest cells) | a (m) | a, edge coefficient fitted over one cell (m) | N (N/m) | a / Hertz's a for N - 1 |")
    print("|---|---|---|---|---|")
    for axis in ("x", "y"):
        for f in args.fractions:
            if axis == "y" and f == 0.0 and groups["x"] and args.fractions[0] == 0.0:
                groups["y"].append(groups["x"][0])  # the same solve
                continue
            row = solve_offset(args.element_size, args.levels, (f, 0.0) if axis == "x" else (0.0, f))
            groups[axis].append(row)
            print(f"| {axis} {f:g} | {row['a']:.7f} | {row['a_fit']:.7f} | {row['N']:.6e} | "
                  f"{100 * row['a_vs_hertz']:+.3f} % |", flush=True)
    finest = args.element_size / 2 ** args.levels
    print(f"\nfinest cell {finest:g} m")
    for axis, rows in groups.items():
        print(f"offsets along {axis}: spread of a {_spread(rows, 'a'):.2e} m, of the fitted a {_spread(rows, 'a_fit'):.2e} m, "
              f"of N {100 * _spread(rows, 'N') / rows[0]['N']:.3f} %, of a / Hertz's a {100 * _spread(rows, 'a_vs_hertz'):.3f} %")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
