"""Cost of the cut cells of a CAD part's grid (``solver.fem.cut_cells3d.inside_moments`` on a
``PartSolid``) on a real STEP file.

Reads the file given (measured on the M8 x 30 socket screw of the real-CAD files, see
docs/real-cad.md; not part of the repository), builds the body's ``PartSolid``, lays a uniform
grid of ``--cell`` metres (its origin the part's lower corner, no refinement) over the slab
``--zmin`` <= z <= ``--zmax`` of the part (its own frame; the whole part without them), classifies
the cells by the signed distance and integrates the cut cells' moments, counting the points the
signed distance is asked. Prints the cells, the points, the CPU seconds (user + system of this
process) and the volume of the slab's cells' inside parts.

``--save FILE.npy`` writes the moments; ``--against FILE.npy`` compares them with moments
written before (by another version of the code: run this script from a directory outside the
source tree, so that each interpreter imports its own installed ``ibfem``).

Run: python benchmarks/cad_cut_cells.py STEP_FILE [--cell 0.002] [--zmin 0.010 --zmax 0.014]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np


def slab_cells(bounds, cell: float, zmin: float | None, zmax: float | None):
    """Lower corners (n, 3) and sizes (n,) of a uniform grid over the part's box, cut to the slab."""
    lo, hi = np.array(bounds[0], float), np.array(bounds[1], float)
    shape = np.floor((hi - lo) / cell).astype(int) + 1
    ijk = np.stack(np.meshgrid(*(np.arange(n) for n in shape), indexing="ij"), axis=-1).reshape(-1, 3)
    lower = lo + ijk * cell
    keep = np.ones(len(lower), bool)
    if zmin is not None:
        keep &= lower[:, 2] + cell > zmin
    if zmax is not None:
        keep &= lower[:, 2] < zmax
    return lower[keep], np.full(int(keep.sum()), cell)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", help="a STEP or IGES file (the M8 socket screw of docs/real-cad.md)")
    ap.add_argument("--body", default=None)
    ap.add_argument("--cell", type=float, default=0.002)
    ap.add_argument("--zmin", type=float, default=None)
    ap.add_argument("--zmax", type=float, default=None)
    ap.add_argument("--save", default=None)
    ap.add_argument("--against", default=None)
    ap.add_argument("--profile", default=None, help="write a cProfile of the moments to this file")
    args = ap.parse_args()

    from ibfem.solver.fem.cut_cells3d import CUT, classify_cells, inside_moments

    from cad_signed_distance import loaded_part

    solid = loaded_part(args.file, args.body)
    asked = [0, 0]

    def phi(p):
        asked[0] += len(p)
        asked[1] += 1
        return solid.signed_distance(p)

    lower, size = slab_cells(solid.bounds, args.cell, args.zmin, args.zmax)
    solid.signed_distance(lower[:10])  # numba's compilation or cache load, outside the count
    c0, w0 = time.process_time(), time.perf_counter()
    status = classify_cells(lower, size, phi)
    cut = status == CUT
    profile = None
    if args.profile:
        import cProfile

        profile = cProfile.Profile()
        profile.enable()
    m = inside_moments(lower[cut], size[cut], phi, 0)
    if profile:
        profile.disable()
        profile.dump_stats(args.profile)
    cpu = time.process_time() - c0
    volume = float((m[:, 0] / 8.0 * size[cut] ** 3).sum() + ((status == 1) * size**3).sum())
    print(f"{len(size)} cells, {int(cut.sum())} cut; {asked[0]} points in {asked[1]} calls; "
          f"{cpu:.1f} s CPU, {time.perf_counter() - w0:.1f} s wall; inside volume {volume:.9e} m^3; "
          f"load average {os.getloadavg()[0]:.1f}")
    if args.save:
        np.save(args.save, m)
    if args.against:
        ref = np.load(args.against)
        diff = np.abs(m - ref).max(axis=1) if ref.shape == m.shape else None
        if diff is None:
            print(f"against {args.against}: shapes differ {ref.shape} {m.shape}")
        else:
            print(f"against {args.against}: largest difference {diff.max():.3e} (moments of the unit cube: "
                  f"8), {int((diff > 0).sum())} of {len(diff)} cells differ, volume "
                  f"{float(((m - ref)[:, 0] / 8.0 * size[cut] ** 3).sum()):+.3e} m^3")


if __name__ == "__main__":
    main()
