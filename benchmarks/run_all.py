"""``make bench``: every benchmark of SPEC section 6, one after the other, each in its own
process (so one's memory peak does not hide another's). Results land in benchmarks/results/.
Pass ``--quick`` for the short variants."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCHMARKS = ["import_time.py", "projection.py", "assembly.py", "contact.py"]


def main(argv: list[str]) -> int:
    failed = []
    for name in BENCHMARKS:
        path = HERE / name
        if not path.exists():
            print(f"bench: {name} not present, skipped", flush=True)
            continue
        print(f"\n=== {name} ===", flush=True)
        rc = subprocess.call([sys.executable, str(path), *argv])
        if rc != 0:
            failed.append(name)
    if failed:
        print(f"bench: failed: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
