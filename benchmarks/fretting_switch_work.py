"""Where the 2D fretting example's contact terms dissipate beyond Coulomb's friction work, per point.

The loop's energy per cycle equals the work of the contact's terms (benchmarks/fretting_energy.py).
This script splits that work over the terms' points: each step's terms are the sum of the
points' blocks (solver.contact.history_terms.point_blocks), a point's force on the contact dofs is
k x - load, and a step's trapezoid 1/2 (F_before + F_after) . (x_after - x_before) (F_before with
the last step's terms, as the audit's) is split into its two halves, each over the points of its
own end's terms. Each point of each step of the first complete cycle is put in one class by the
zone at its chord at the last step's end and at this step's end (the friction work by the zones
of the samples):

- ``stick``: stuck at both; ``slip``: slipping the same way at both; ``stick->slip``: stuck, then
  slipping; ``slip->stick``: slipping, then stuck; ``reversed``: slipping both ways; ``open``:
  outside the region at either end;

and per class it prints, in J/m over the cycle: the contact terms' work, the friction work as the
run reports it (the Coulomb traction the terms apply at each slipping sample times its slip
increment) and Coulomb's
work on the slip alone (the same shear times the slip increment less the change of the tie's
stretch, (f_t - q) / L_tt: what a point that slides only once its shear reaches mu p dissipates).
Also the same split by tenths of |x| / a.

    .venv/bin/python benchmarks/fretting_switch_work.py                       # aligned
    .venv/bin/python benchmarks/fretting_switch_work.py --offsets 0.025 0 0.0125 0
    .venv/bin/python benchmarks/fretting_switch_work.py --without-edge-discs --offsets 0.0125 0

About 5 s of CPU and 0.3 GB a grid; prints only, writes nothing.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))

import fretting_energy  # noqa: E402  (the audit)
import fretting_work_profile  # noqa: E402  (the example's scene on a shifted grid)

BINS = np.linspace(0.0, 1.0, 11)
CLASSES = ("stick", "slip", "stick->slip", "slip->stick", "reversed", "open")


def _point_forces(c, x: np.ndarray, a: float):
    """(chords, forces (q, k), their dofs (q, k)) of the terms' points: the force of each point on
    the contact dofs, k x - load."""
    from ibfem.solver.contact.history_terms import point_blocks

    if a <= 0.0:
        return np.zeros(0), np.zeros((0, 1)), np.zeros((0, 1), dtype=int)
    k, load, rows, info = point_blocks(c, a)
    return info[0].s, np.einsum("qlk,qk->ql", k, x[rows.cols]) - load, rows.cols


def _zone(bounds: np.ndarray, values: np.ndarray, s: np.ndarray) -> np.ndarray:
    return values[np.searchsorted(bounds, s)]


def _class(z0: np.ndarray, z1: np.ndarray, in0: np.ndarray, in1: np.ndarray) -> np.ndarray:
    out = np.full(len(z0), 5)
    both = in0 & in1
    out[both & (z0 == 0) & (z1 == 0)] = 0
    out[both & (z0 != 0) & (z0 == z1)] = 1
    out[both & (z0 == 0) & (z1 != 0)] = 2
    out[both & (z0 != 0) & (z1 == 0)] = 3
    out[both & (z0 != 0) & (z1 == -z0)] = 4
    return out


def run(offset, edge_discs: bool = True, points_per_cycle: int = 20) -> dict:
    from ibfem.solver.contact import friction_history as fh
    from ibfem.solver.io.fretting_outputs import cycles_of, loop_energy

    problem = fretting_work_profile._scene(offset, None, None, False, points_per_cycle, edge_discs).problem
    rec, original = [], fh.HistoryBandContact.end_step

    def recording(self, x, a, info):
        forces = _point_forces(self, x, a)
        lo, hi = self.region_ends(a)
        p, q, wt, inside = self.sample_state(x, a)
        stretch = self._tie_offset(x, np.where(inside, self._raw[1], 0.0))
        zone = np.where(inside, self.zone, 0.0)
        original(self, x, a, info)
        rec.append({"x": x.copy(), "F": forces, "ends": (lo, hi), "zones": (self.bounds.copy(), self.values.copy()), "zone": zone, "inside": inside, "q": np.where(inside, self._raw[1], 0.0),
                    "wt": wt, "stretch": np.where(inside, stretch, 0.0), "loc": self.local(self.samples.s) / a, "s": self.samples.s.copy(),
                    "loc_of": (lambda v, c=self, a=a: c.local(v) / a),
                    "ds": np.gradient(self.samples.s), "work": self.step_work})

    r, cpu = fretting_energy.audit_recording(problem, recording)
    first = len(r["t"]) - len(rec)
    i, j = cycles_of(r["q"])[0]
    bins = BINS
    table = np.zeros((len(CLASSES), 3))
    by_tenth = np.zeros((len(bins) - 1, len(CLASSES), 3))
    check = 0.0
    per_sample = np.zeros((len(rec[0]["zone"]), 3))
    for k in range(i + 1, j + 1):
        before, after = rec[k - 1 - first], rec[k - first]
        dx = after["x"] - before["x"]
        work = np.zeros(len(before["zone"]))
        for side in (before, after):  # each end's points carry half the trapezoid
            s_q, f_q, cols = side["F"]
            w_q = 0.5 * np.einsum("ql,ql->q", f_q, dx[cols])
            check += w_q.sum()
            z0, z1 = (_zone(*st["zones"], s_q) for st in (before, after))
            in0, in1 = ((s_q >= st["ends"][0]) & (s_q <= st["ends"][1]) for st in (before, after))
            cq = _class(z0, z1, in0, in1)
            tq = np.clip(np.digitize(np.abs(side["loc_of"](s_q)), bins) - 1, 0, len(bins) - 2)
            np.add.at(table[:, 0], cq, w_q)
            np.add.at(by_tenth[:, :, 0], (tq, cq), w_q)
            np.add.at(work, np.clip(np.searchsorted(0.5 * (after["s"][1:] + after["s"][:-1]), s_q), 0, len(work) - 1), w_q)
        cls = _class(before["zone"], after["zone"], before["inside"], after["inside"])
        slipping = after["zone"] != 0.0
        dw = np.where(slipping, after["wt"] - before["wt"], 0.0)
        friction = np.where(slipping, -after["q"] * dw * after["ds"], 0.0)
        slide = dw - np.where(slipping, after["stretch"] - before["stretch"], 0.0)
        coulomb = np.where(slipping, -after["q"] * slide * after["ds"], 0.0)
        tenth = np.clip(np.digitize(np.abs(after["loc"]), bins) - 1, 0, len(bins) - 2)
        for col, v in ((1, friction), (2, coulomb)):
            np.add.at(table[:, col], cls, v)
            np.add.at(by_tenth[:, :, col], (tenth, cls), v)
        per_sample += np.stack([work, friction, coulomb], axis=1)
    return {"cpu_s": cpu, "solves": r["solves"], "loop": abs(loop_energy(r["q"], r["delta"], i, j)),
            "contact": abs(r["contact"][i:j].sum()), "split_sum": check, "friction": float(r["friction"][i + 1:j + 1].sum()),
            "table": table, "by_tenth": by_tenth,
            "per_sample": per_sample, "loc": rec[j - first]["loc"]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--offsets", type=float, nargs="*", default=[], help="pairs of grid offsets; the aligned grid always runs")
    ap.add_argument("--without-edge-discs", action="store_true",
                    help="the example's grid without its finer discs about the contact's edges")
    ap.add_argument("--points-per-cycle", type=int, default=20)
    args = ap.parse_args(argv)
    for off in [None] + [args.offsets[k:k + 2] for k in range(0, len(args.offsets), 2)]:
        r = run(off, not args.without_edge_discs, args.points_per_cycle)
        label = "aligned" if off is None else f"shift {off[0]:g}, {off[1]:g}"
        print(f"{label}: {r['solves']} solves, {r['cpu_s']:.1f} s CPU; first cycle (J/m): loop {r['loop']:.2f}, "
              f"contact terms {r['contact']:.2f} (split over the points {r['split_sum']:.2f}), "
              f"friction work {r['friction']:.2f}")
        print(f"  {'class':12s} {'contact':>9s} {'friction':>9s} {'coulomb':>9s}")
        for name, row in zip(CLASSES, r["table"]):
            print(f"  {name:12s} {row[0]:9.2f} {row[1]:9.2f} {row[2]:9.2f}")
        print("  by |x|/a tenths 0.5..1.0, contact - friction for stick->slip / slip / stick / slip->stick:")
        for t in range(5, 10):
            d = r["by_tenth"][t, :, 0] - r["by_tenth"][t, :, 1]
            print(f"    {0.1 * t:.1f}-{0.1 * t + 0.1:.1f}: " + " ".join(f"{d[c]:+7.2f}" for c in (2, 1, 0, 3)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
