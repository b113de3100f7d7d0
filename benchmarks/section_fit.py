"""``ibfem run`` with a long region's sides read by the fit of the square-root form on merged
squares (``on``) or by the point traction's moment on the sections (``off``; the code's setting is
solver.contact.section_fit.SECTION_FIT). Prints the process's CPU time and peak resident memory
after the run; compare the summary.json with the other reading's (for the crowned roller:
benchmarks/crowned_roller_halfspace.py).

    python benchmarks/section_fit.py on examples/contact3d/crowned_roller.toml --out OUT
"""

from __future__ import annotations

import resource
import sys

from ibfem.solver.cli import main as cli
from ibfem.solver.contact import section_fit


def main(argv: list[str]) -> int:
    if len(argv) < 2 or argv[0] not in ("on", "off"):
        print(__doc__)
        return 2
    section_fit.SECTION_FIT = argv[0] == "on"
    code = cli(["run", *argv[1:]])
    usage = resource.getrusage(resource.RUSAGE_SELF)
    print(f"section fit {argv[0]}: CPU {usage.ru_utime + usage.ru_stime:.1f} s, peak {usage.ru_maxrss / 1024**2:.2f} GB")
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
