"""Speed of the closed-loop checks of 2D profiles (``ibfem.geometry.loop_checks.check_loops``):
loops of 2,500 to 40,000 straight segments, a circle and a zigzag, best of 5 runs each.
Target: 10,000 segments in under 0.1 s, and about n log n growth.

    .venv/bin/python benchmarks/loop_checks.py

Writes benchmarks/results/loop_checks.json."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from ibfem.geometry.loop_checks import check_loops
from ibfem.geometry.segments import Segment

OUT = Path(__file__).resolve().parent / "results"


def loop(kind: str, n: int) -> list[Segment]:
    if kind == "circle":
        th = np.linspace(0, 2 * np.pi, n, endpoint=False)
        pts = np.c_[np.cos(th), np.sin(th)]
    else:
        x = np.linspace(0, 1, n)
        pts = np.vstack([np.c_[x, np.where(np.arange(n) % 2, 1.0, 0.0)], [[1, -1], [0, -1]]])
    return [Segment(pts[i], pts[(i + 1) % len(pts)], f"e{i}") for i in range(len(pts))]


def best_time(segs: list[Segment], repeat: int = 5) -> float:
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        check_loops([segs], 2.83, 1e-6)
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> int:
    rows = []
    for kind in ("circle", "zigzag"):
        for n in (2_500, 10_000, 40_000):
            t = best_time(loop(kind, n))
            rows.append({"kind": kind, "segments": n, "seconds": t})
            print(f"{kind:7s} {n:6d} segments: {t * 1e3:8.2f} ms")
    OUT.mkdir(exist_ok=True)
    (OUT / "loop_checks.json").write_text(json.dumps(rows, indent=1))
    slow = [r for r in rows if r["segments"] == 10_000 and r["seconds"] >= 0.1]
    return 1 if slow else 0


if __name__ == "__main__":
    raise SystemExit(main())
