"""Extra cost of the error estimate of ``ibfem run``: the same scene run with and without
``--no-estimate``, alternating, each run its own process (VTU and plots off); prints each pair's
CPU time (user + system) and wall time and the median ratio of both (docs/accuracy.md).

    python benchmarks/accuracy_estimate_cost.py examples/mesh_convergence.toml --pairs 3
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import peers  # noqa: E402


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", type=Path)
    ap.add_argument("--pairs", type=int, default=3)
    args = ap.parse_args(argv)
    ibfem = str(Path(sys.executable).with_name("ibfem"))
    with tempfile.TemporaryDirectory() as t:
        for path in args.scenes:
            data = tomllib.loads(path.read_text())
            data["output"] = {"vtk": False, "plots": False}
            scene = Path(t) / f"{path.stem}.json"
            scene.write_text(json.dumps(data))
            cpu, wall = [], []
            for k in range(args.pairs):
                runs = {}
                for flag in ([], ["--no-estimate"]):
                    code, _, err, w, peak, c = peers.run_child([ibfem, "run", str(scene), "--out", f"{t}/o{k}", "--quiet"] + flag)
                    if code != 0:
                        print(f"{path}: exit {code}: {err.strip().splitlines()[-1:]}")
                        return 1
                    runs["with" if not flag else "without"] = (c, w)
                cpu.append(runs["with"][0] / runs["without"][0])
                wall.append(runs["with"][1] / runs["without"][1])
                print(f"{path.stem} pair {k + 1}: CPU {runs['with'][0]:.2f} / {runs['without'][0]:.2f} s, "
                      f"wall {runs['with'][1]:.2f} / {runs['without'][1]:.2f} s", flush=True)
            print(f"| {path.stem} | {statistics.median(cpu):.2f} | {statistics.median(wall):.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
