"""``make bench``: every benchmark of benchmarks/, one after the other, each in its own
process (so one's memory peak does not hide another's). Results land in benchmarks/results/.

    python benchmarks/run_all.py [--quick] [--large]

``--quick`` runs the short variants; ``--large`` adds the ~10^6 dof assembly case and the
10^6-dof 2D contact scene (million_dofs.py --2d: about 30 s and 3 GB)."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--large", action="store_true")
    args = ap.parse_args(argv)
    quick = ["--quick"] if args.quick else []
    benchmarks = [
        ("import_time.py", []),
        ("projection.py", quick),
        ("loop_checks.py", []),
        ("assembly.py", ["--large"] if args.large else []),
        ("contact.py", quick),
        ("error_vs_time.py", quick),
        ("linear_solvers.py", ["--quick"] if args.quick else []),
        ("step_import.py", []),
        ("fretting.py", []),
    ] + ([("million_dofs.py", ["--2d"])] if args.large else [])
    failed = []
    for name, extra in benchmarks:
        print(f"\n=== {name} {' '.join(extra)} ===", flush=True)
        if subprocess.call([sys.executable, str(HERE / name), *extra]) != 0:
            failed.append(name)
    if failed:
        print(f"bench: failed: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
