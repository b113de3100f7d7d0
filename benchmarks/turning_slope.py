"""``ibfem run`` with the slope beyond which the refinement that follows a line contact's region
refines its edge one level more (solver.contact.region_band.TURNING_SLOPE, 0.25 in the code) set
to another value: 0 refines the coarse region's whole smooth edge, the straight sides included.
Prints the process's CPU time and peak resident memory after the run; compare the summary.json
with the default's (for the crowned roller: benchmarks/crowned_roller_halfspace.py).

    python benchmarks/turning_slope.py 0 examples/contact3d/crowned_roller.toml --out OUT

``--reach R`` after the slope also sets how far beyond the coarse edge those balls reach, in coarse
cells (solver.contact.follow.TURNING_REACH_CELLS, 1 in the code):

    python benchmarks/turning_slope.py 0.25 --reach 0.5 examples/contact3d/tilted_roller.toml --out OUT

``--side R W`` (after ``--reach`` if both) sets the thinner balls one level finer along the
straight sides: reaching R coarse cells beyond the coarse edge and W finer cells inside it
(solver.contact.follow.SIDE_REACH_CELLS, SIDE_WINDOW_CELLS: 0.25 and 2 in the code, used where the
band's cells resolve the half-width with fewer than SIDE_MIN_CELLS); ``--side none`` leaves them
out (the rule before them):

    python benchmarks/turning_slope.py 0.25 --side none examples/contact3d/crowned_roller.toml --out OUT

``--peak none`` (last of the three) leaves out the balls one level finer about the coarse pass's
pressure peaks next to where the edge turns (solver.contact.follow.PEAK_BALLS; the rule before
them):

    python benchmarks/turning_slope.py 0.25 --peak none examples/contact3d/crowned_roller.toml --out OUT
"""

from __future__ import annotations

import resource
import sys

from ibfem.solver.cli import main as cli
from ibfem.solver.contact import follow, region_band


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        print(__doc__)
        return 2
    region_band.TURNING_SLOPE = float(argv[0])
    rest = argv[1:]
    if rest[:1] == ["--reach"]:
        follow.TURNING_REACH_CELLS, rest = float(rest[1]), rest[2:]
    if rest[:1] == ["--side"]:
        if rest[1] == "none":
            follow.SIDE_REACH_CELLS, rest = None, rest[2:]
        else:
            follow.SIDE_REACH_CELLS, follow.SIDE_WINDOW_CELLS, rest = float(rest[1]), float(rest[2]), rest[3:]
    if rest[:1] == ["--peak"]:
        follow.PEAK_BALLS, rest = rest[1] != "none", rest[2:]
    code = cli(["run", *rest])
    usage = resource.getrusage(resource.RUSAGE_SELF)
    print(f"turning slope {region_band.TURNING_SLOPE}, reach {follow.TURNING_REACH_CELLS} coarse cells, "
          f"sides {follow.SIDE_REACH_CELLS} coarse + {follow.SIDE_WINDOW_CELLS} finer cells, peak balls {follow.PEAK_BALLS}: CPU {usage.ru_utime + usage.ru_stime:.1f} s, "
          f"peak {usage.ru_maxrss / 1024**2:.2f} GB")
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
