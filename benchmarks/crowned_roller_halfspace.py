"""The crowned roller's 3D region against the half-space solution of the same gap at the run's
force: length, the half-width along the line (stations every 5 mm and at the widest), the
widest half-width against the region's extent across, and the peak's fit read the same way on
both; the line load along the line per row of the 3D map's squares against the half-space's
averaged over the same rows, and at mid-length the plane-strain invariant b / sqrt(P') of both
(Hertz: b^2 = 4 P' R / (pi E*), K. L. Johnson, Contact Mechanics, 1985, eq. 4.43). Input: the
summary.json of a run of examples/contact3d/crowned_roller.toml or of
tests/scenes/crowned_roller_large_block.toml (the same roller on a 1 m block).

    python benchmarks/crowned_roller_halfspace.py OUT/summary.json [--dx 0.001 --dy 0.0008]
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from ibfem.solver.contact.region_report import (PLATEAU_SHARE, WINDOW_CELLS, fitted_peak, grid_peak_as_map, grid_peak_place_as_map,
                                                   mirror_images, peak_place)
from ibfem.solver.reference.crowned_roller import (crowned_gap, half_length, half_widths, region_half_widths,
                                                   square_means)
from ibfem.solver.reference.halfspace import halfspace_contact

E_STAR = 2.0e11 / (2 * (1 - 0.3**2))
#: rows of the map's squares from mid-length over which the mid-length line load is read
MID_ROWS = 4


def row_loads(block: dict, ref, dx: float, dy: float) -> tuple[np.ndarray, np.ndarray]:
    """(3D, half-space) full line loads P' (both sides of the line) per row of the map's squares
    along the line from mid-length: the 3D map's force in each row over the row's length, and the
    half-space's line load at its stations averaged over the same row."""
    m = block["pressure_map"]
    cell = m["cell"]
    s, value, area = np.array(m["s"]), np.array(m["value"]), np.array(m["area"])
    row = np.floor(s[:, 0] / cell + 1e-9).astype(int)
    rows = np.arange(row.max() + 1)
    loads = np.array([2.0 * float((value[row == i] * area[row == i]).sum()) / cell for i in rows])
    line = 2.0 * ref.pressure.sum(axis=1) * dy
    ref_loads = np.array([line[(ref.x >= i * cell) & (ref.x < (i + 1) * cell)].mean() for i in rows])
    return loads, ref_loads


def compare(block: dict, dx: float, dy: float, cell: float | None = None) -> dict:
    x, y = np.arange(0.5 * dx, 0.09, dx), np.arange(0.5 * dy, 0.032, dy)
    ref = halfspace_contact(crowned_gap(), x, y, E_STAR, force=block["normal_force"], symmetric=True)
    length = half_length(ref)
    widths = half_widths(ref)
    ok = np.isfinite(widths)
    widest = int(np.nanargmax(np.where(ok, widths, -1.0)))
    stations = np.unique(np.concatenate([np.arange(0.0, 0.0751, 0.005), [x[widest]]]))
    ref_w = np.interp(stations, x[ok], widths[ok])
    w3 = region_half_widths(block, stations)
    m = block["pressure_map"]
    centres, value, keys = np.array(m["s"]), np.array(m["value"]), np.array(m["square"])
    maps = mirror_images([(0.0, 0.5 * math.pi)])
    reference = square_means(block, ref)
    area, size = np.array(m["area"]), m["cell"]
    cell = float(cell or block["peak_fit"].get("cell") or size)
    at, fit = fitted_peak(centres, value, area, keys, size, cell, maps)
    ref_at, ref_fit = fitted_peak(centres, reference, area, keys, size, cell, maps)
    corner_at, corner_fit = grid_peak_as_map(block, ref.x, ref.y, ref.pressure, maps, cell)
    place = peak_place(centres, value, np.array(m["area"]), keys, m["cell"], maps)
    ref_place = grid_peak_place_as_map(block, ref.x, ref.y, ref.pressure, maps)
    return {"force": block["normal_force"], "cell": m["cell"], "local_cell": cell,
            "length": (block["semi_axes"][0], length), "widest": (float(region_half_widths(block, np.linspace(0.0, 0.09, 901)).max()),
                       float(widths[widest]), float(x[widest])),
            "extents": block["extents"],
            "stations": [(float(s), float(a), float(b)) for s, a, b in zip(stations, w3, ref_w)],
            "peak_fit": (fit, float(at[0]), ref_fit, float(ref_at[0])),
            "peak_fit_corners": (corner_fit, float(corner_at[0])),
            "peak_place": (float(place[0]), float(ref_place[0])),
            "point_peak": float(ref.pressure.max()),
            "rows": row_loads(block, ref, dx, dy),
            "mid_length": (float(w3[0]), float(np.mean(row_loads(block, ref, dx, dy)[0][:MID_ROWS])),
                           float(widths[0]), float(2.0 * ref.pressure[0].sum() * dy))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("summary")
    parser.add_argument("--dx", type=float, default=0.001)
    parser.add_argument("--dy", type=float, default=0.0008)
    parser.add_argument("--cell", type=float, default=None,
                        help="the grid's cell at the peak, m (default: the summary's peak_fit.cell; for a summary "
                             "written before it, the map's squares' side)")
    args = parser.parse_args()
    summary = json.load(open(args.summary))
    block = summary["contacts"][0]
    r = compare(block, args.dx, args.dy, args.cell)
    print(f"converged {summary.get('converged')}; quarter force {r['force']:.5g} N; cell {r['cell'] * 1e3:.3g} mm")
    a, b = r["length"]
    print(f"half-length: 3D {a:.5f} m, half-space {b:.5f} m: {100 * (a / b - 1):+.2f} % ({(a - b) / r['cell']:+.2f} cell)")
    a, b, xw = r["widest"]
    print(f"widest half-width: 3D boundary {a:.5f} m, half-space {b:.5f} m at x = {xw * 1e3:.1f} mm: "
          f"{100 * (a / b - 1):+.2f} %; extents {r['extents']}")
    for s, a, b in r["stations"]:
        print(f"  x = {s * 1e3:5.1f} mm: 3D {a * 1e3:7.3f} mm, half-space {b * 1e3:7.3f} mm, {100 * (a / b - 1):+6.2f} %")
    v, xa, rv, rx = r["peak_fit"]
    b = r["length"][1]
    print(f"peak fit (a local quadratic within {WINDOW_CELLS:g} local cells of {r['local_cell'] * 1e3:.4g} mm about the "
          f"peak's place): 3D {v / 1e9:.4f} GPa at x = {xa * 1e3:.2f} mm; half-space {rv / 1e9:.4f} GPa at "
          f"{rx * 1e3:.2f} mm (its plain means over the same squares): {100 * (v / rv - 1):+.2f} %, position "
          f"{100 * (xa - rx) / b:+.2f} % of the half-length")
    cv, cx = r["peak_fit_corners"]
    print(f"  half-space read through the squares' corners as the 3D map: {cv / 1e9:.4f} GPa at {cx * 1e3:.2f} mm: "
          f"{100 * (v / cv - 1):+.2f} %, position {100 * (xa - cx) / b:+.2f} % of the half-length; its point peak "
          f"{r['point_peak'] / 1e9:.4f} GPa")
    pa, pr = r["peak_place"]
    print(f"peak place (centroid of the plateau above {100 * PLATEAU_SHARE:g} % of the largest square, read the same "
          f"way on both): 3D x = {pa * 1e3:.2f} mm, half-space {pr * 1e3:.2f} mm: {100 * (pa - pr) / b:+.2f} % of the half-length")
    loads, ref_loads = r["rows"]
    cell = r["cell"]
    print("line load P' per row of squares (both sides of the line), 3D against the half-space's mean over the row:")
    for i, (a, b) in enumerate(zip(loads, ref_loads)):
        print(f"  x = {i * cell * 1e3:5.1f}-{(i + 1) * cell * 1e3:5.1f} mm: 3D {a / 1e6:7.2f} MN/m, half-space "
              f"{b / 1e6:7.2f} MN/m, {100 * (a / b - 1):+6.2f} %")
    b3, p3, bh, ph = r["mid_length"]
    print(f"mid-length b / sqrt(P') (P' over the first {MID_ROWS} rows in 3D, at the first station on the half-space): "
          f"3D {b3 / math.sqrt(p3):.5g}, half-space {bh / math.sqrt(ph):.5g}, Hertz "
          f"{math.sqrt(4 * 0.5 / (math.pi * E_STAR)):.5g} m^1.5 N^-0.5")


if __name__ == "__main__":
    main()
