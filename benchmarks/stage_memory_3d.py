"""Peak resident memory of a 3D contact run per stage: a thread samples the process's resident
set every 50 ms and the driver's progress reports name the stage (grids, "assembly" = assembly
and the condensed factorisation, each load step with its trials, the last one with the final
field). A run with a coarse pass (a large point contact, or a line contact) lists its stages
twice, the coarse pass first.

    python benchmarks/stage_memory_3d.py examples/solid/full/ball_on_block.toml
"""

from __future__ import annotations

import os
import sys
import threading
import time
import tomllib
from pathlib import Path

from ibfem.solver.io.scene import load_scene
from ibfem.solver.solving import solve

PERIOD_S = 0.05


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__)
        return 2
    path = Path(argv[0])
    data = tomllib.loads(path.read_text())
    data["output"] = {"vtk": False, "plots": False}
    scene = load_scene(data, label=str(path), base_dir=str(path.parent))
    page = os.sysconf("SC_PAGE_SIZE")
    stage = {"index": 0, "name": "start", "at": time.perf_counter()}
    peaks: dict[tuple[int, str], int] = {}
    spans: dict[tuple[int, str], float] = {}

    def sample() -> None:
        while True:
            with open("/proc/self/statm") as f:
                rss = int(f.read().split()[1]) * page
            key = (stage["index"], stage["name"])
            peaks[key] = max(peaks.get(key, 0), rss)
            time.sleep(PERIOD_S)

    def progress(name, fraction=None) -> None:
        if name != stage["name"]:
            now = time.perf_counter()
            spans[(stage["index"], stage["name"])] = now - stage["at"]
            stage.update(index=stage["index"] + 1, name=name, at=now)

    threading.Thread(target=sample, daemon=True).start()
    solve(scene.problem, progress)
    spans[(stage["index"], stage["name"])] = time.perf_counter() - stage["at"]
    print(f"{'stage':32} {'wall s':>7} {'peak GB':>8}")
    for key in sorted(peaks):
        print(f"{key[1]:32} {spans.get(key, 0.0):7.1f} {peaks[key] / 2**30:8.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
