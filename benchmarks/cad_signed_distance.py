"""Cost of a CAD part's signed distance (``PartSolid.signed_distance``) on a real STEP file.

Reads the file given (measured on the M8 x 30 socket screw of the real-CAD files, see
docs/real-cad.md; not part of the repository), builds the body's ``PartSolid`` and evaluates
the signed distances of ``--points`` points drawn uniformly (seed 0) in a box about the part's head: the part's bounding box in x and
y, and in z the lowest ``--head`` metres of it, each side widened by ``--margin`` metres. The
evaluation is repeated ``--repeat`` times (the first also pays numba's compilation or cache load,
so the best is printed too). Prints the CPU seconds (user + system of this process, its threads
included) and wall seconds of each evaluation, and microseconds of CPU per point.

``--save FILE.npy`` writes the values; ``--against FILE.npy`` compares them with values written
before (by another version of the code: run this script from a directory outside the source
tree, so that each interpreter imports its own installed ``ibfem``), printing the largest
difference and how many differ at all.

``--points-file FILE.npy`` evaluates the points (n, 3) stored there (in the part's frame) instead.

Run: python benchmarks/cad_signed_distance.py STEP_FILE [--points 20000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

def head_points(bounds, count: int, head: float, margin: float, seed: int = 0) -> np.ndarray:
    lo, hi = np.array(bounds[0], float), np.array(bounds[1], float)
    hi[2] = min(hi[2], lo[2] + head)
    rng = np.random.default_rng(seed)
    return rng.uniform(lo - margin, hi + margin, size=(count, 3))


def loaded_part(path: str, body: str | None):
    """The part's solid from a STEP or IGES file, with a line saying which code built it and how
    large it is (shared by the CAD benchmarks)."""
    from ibfem.geometry.solids import part_solid
    from ibfem.importers.step import load_part

    t = time.perf_counter()
    solid = part_solid.PartSolid(load_part(path), body)
    print(f"code: {os.path.dirname(part_solid.__file__)}")
    print(f"part: {len(solid.faces)} faces, {len(solid.edges)} edges, {len(solid.triangles)} triangles, "
          f"tolerance {solid.tolerance:.3e} m; read and built in {time.perf_counter() - t:.1f} s")
    return solid


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="a STEP or IGES file (the M8 socket screw of docs/real-cad.md)")
    ap.add_argument("--body", default=None)
    ap.add_argument("--points", type=int, default=20000)
    ap.add_argument("--head", type=float, default=0.0085, help="height (m) of the box from the part's lowest z")
    ap.add_argument("--margin", type=float, default=0.001)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--save", default=None)
    ap.add_argument("--against", default=None)
    ap.add_argument("--points-file", default=None)
    ap.add_argument("--profile", default=None, help="write a cProfile of the evaluations to this file")
    args = ap.parse_args()

    solid = loaded_part(args.file, args.body)
    p = np.load(args.points_file) if args.points_file else head_points(solid.bounds, args.points, args.head, args.margin)
    profile = None
    if args.profile:
        import cProfile

        profile = cProfile.Profile()
    cpu = []
    for _ in range(args.repeat):
        c0, w0 = time.process_time(), time.perf_counter()
        if profile:
            profile.enable()
        d = np.asarray(solid.signed_distance(p), float)
        if profile:
            profile.disable()
        cpu.append(time.process_time() - c0)
        print(f"{len(p)} points: {cpu[-1]:.2f} s CPU, {time.perf_counter() - w0:.2f} s wall, "
              f"{1e6 * cpu[-1] / len(p):.1f} us CPU per point; inside {int((d > 0).sum())}")
    print(f"best: {min(cpu):.2f} s CPU, {1e6 * min(cpu) / len(p):.1f} us per point; "
          f"load average {os.getloadavg()[0]:.1f}")
    if profile:
        profile.dump_stats(args.profile)
    if args.save:
        np.save(args.save, d)
    if args.against:
        ref = np.load(args.against)
        diff = np.abs(d - ref)
        print(f"against {args.against}: largest difference {diff.max():.3e} m, {int((diff > 0).sum())} differ, "
              f"{int((np.sign(d) != np.sign(ref)).sum())} of another sign")


if __name__ == "__main__":
    main()
