"""Lundberg's log-crowned roller (tests/scenes/lundberg_roller.toml, a quarter model) or the tilted
crowned roller (examples/contact3d/tilted_roller.toml, a half model) against the frictionless
half-space solution of the same gap at the run's force (Boussinesq's influence coefficients,
K. L. Johnson, Contact Mechanics, 1985, section 5.9): the region's ends along the line, its
half-width (Lundberg's at mid-length; the tilted roller's at x = -0.05 and +0.05 m), the largest
square of the pressure map against the half-space's mean over the same squares, and the peak's
fit (``peak_fit``) against the half-space read the same way, through the corners of the same
squares, in value and in position (as a share of the half-length), and the peak's place
(``peak_place``: the centroid of the plateau above 99 % of the largest square) read the same way
on both. Also the grid the run had:
the cells per semi-axis and the refinement record (coarse pass, band, finer balls).

    python -m ibfem run tests/scenes/lundberg_roller.toml --out OUT
    python benchmarks/followed_rollers_halfspace.py lundberg OUT/summary.json
    python benchmarks/followed_rollers_halfspace.py tilted OUT/summary.json

The tilted roller's half-space is solved on 1 x 0.8 mm rectangles (2.1 GB, about a minute): on
2 mm along the line its loaded end's peak is read 3.2 mm further out (59.0 mm from the contact
point, against 55.8 mm on 1 mm and 55.9 mm on 0.5 mm rectangles), 4 % of the half-length.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tomllib
from pathlib import Path

import numpy as np

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.contact.region_report import (PLATEAU_SHARE, WINDOW_CELLS, fitted_peak, grid_peak_as_map,
                                                   grid_peak_place_as_map, mirror_images, peak_place)
from ibfem.solver.reference.crowned_roller import edge_from_row, solid_bottom, square_means
from ibfem.solver.reference.halfspace import halfspace_contact

ROOT = Path(__file__).resolve().parent.parent
E_STAR = 2.0e11 / (2 * (1 - 0.3**2))
R = 0.5


def lundberg_gap():
    """The Lundberg roller's height above the flat from the scene's own axial section (the B-spline
    written by tests/scenes/make_lundberg_roller.py)."""
    sys.path.insert(0, str(ROOT / "tests" / "scenes"))
    from make_lundberg_roller import profile_spline

    spline = profile_spline()

    def gap(X, Y):
        radius = spline(np.clip(np.abs(X), 0.0, 0.1))[..., 0]
        return np.where(np.abs(X) > 0.1, 1.0, R - np.sqrt(np.maximum(radius**2 - Y**2, 0.0)))

    return gap


def edge_xy(block: dict) -> np.ndarray:
    """The boundary polyline's points in the block's top face (x along the roller's axis, y
    across it), from the contact point: both rollers' scenes lie along x."""
    return (np.array(block["boundary"]["points"]) - np.array(block["point"]))[:, :2]


def width_at(xy: np.ndarray, station: float) -> float:
    """The region's half-width at ``station`` along the line: |s1| of the boundary polyline (a
    symmetric model's side of the line, the cut along it left out) interpolated along s0."""
    off = np.abs(xy[:, 1]) > 1e-9 * float(np.abs(xy).max())  # not on the symmetry cut along the line
    upper = np.abs(xy[off])
    upper[:, 0] = xy[off, 0]
    order = np.argsort(upper[:, 0])
    return float(np.interp(station, upper[order, 0], upper[order, 1]))


def local_cell(block: dict, cell: float | None) -> float:
    """The grid's cell at the peak that the peak's fit reads: ``cell`` if given, else the
    summary's (``peak_fit.cell``), else the map's squares' side."""
    return float(cell or block["peak_fit"].get("cell") or block["pressure_map"]["cell"])


def peak(block: dict, ref, maps, cell: float | None = None) -> dict:
    """The largest square and the peak's fit of the 3D map (re-read from the stored map with the
    local ``cell``) against the half-space's."""
    m = block["pressure_map"]
    value = np.array(m["value"])
    top = int(np.argmax(value))
    cell = local_cell(block, cell)
    at, fit = fitted_peak(np.array(m["s"]), value, np.array(m["area"]), np.array(m["square"]), m["cell"], cell, maps)
    ref_at, ref_fit = grid_peak_as_map(block, ref.x, ref.y, ref.pressure, maps, cell)
    return {"largest_square": (float(value[top]), float(square_means(block, ref)[top]), list(m["s"][top])),
            "cell": cell, "fit": (fit, ref_fit), "fit_at": (float(at[0]), float(ref_at[0])),
            "place": (float(peak_place(np.array(m["s"]), value, np.array(m["area"]), np.array(m["square"]), m["cell"], maps)[0]),
                      float(grid_peak_place_as_map(block, ref.x, ref.y, ref.pressure, maps)[0]))}


def compare_lundberg(block: dict, dx: float, dy: float, cell: float | None = None) -> dict:
    x, y = np.arange(0.5 * dx, 0.1, dx), np.arange(0.5 * dy, 0.032, dy)
    ref = halfspace_contact(lundberg_gap(), x, y, E_STAR, force=block["normal_force"], symmetric=True)
    length = edge_from_row(ref.x, ref.pressure[:, 0])
    xy = edge_xy(block)
    out = {"ends": [(float(xy[:, 0].max()), length)], "half_length": length,
           "widths": [(0.0, width_at(xy, 0.0), edge_from_row(ref.y, ref.pressure[0, :]))]}
    out.update(peak(block, ref, mirror_images([(0.0, 0.5 * math.pi)]), cell))
    return out


def compare_tilted(block: dict, scene: Path, dx: float, dy: float, cell: float | None = None) -> dict:
    roller = solid_from_dict(tomllib.loads(scene.read_text())["bodies"][0]["shape"])
    x, y = np.arange(-0.1 + 0.5 * dx, 0.1, dx), np.arange(0.5 * dy, 0.032, dy)
    ref = halfspace_contact(lambda X, Y: solid_bottom(roller, X, Y), x, y, E_STAR, force=block["normal_force"],
                            symmetric="y")
    row = ref.pressure[:, 0]
    back = -edge_from_row(-ref.x[::-1], row[::-1])
    front = edge_from_row(ref.x, row)
    xy = edge_xy(block)
    widths = [(s, width_at(xy, s), edge_from_row(ref.y, ref.pressure[int(np.argmin(np.abs(x - s)))])) for s in (-0.05, 0.05)]
    out = {"ends": [(float(xy[:, 0].min()), back), (float(xy[:, 0].max()), front)],
           "half_length": 0.5 * (front - back), "widths": widths}
    out.update(peak(block, ref, mirror_images([(0.0, math.pi)]), cell))
    return out


def report(block: dict, refinement: dict | None, result: dict) -> str:
    hl = result["half_length"]
    lines = [f"force (model) {block['normal_force']:.6g} N, semi-axes {block['semi_axes']}, "
             f"cells per semi-axis {block.get('cells_per_semi_axis')}, knots {len(block['knots']['phi'])}"]
    for got, ref in result["ends"]:
        lines.append(f"end {got:+.5f} m against the half-space's {ref:+.5f} m: {100 * (got - ref) / hl:+.2f} % of the half-length")
    for s, got, ref in result["widths"]:
        lines.append(f"half-width at x = {s:+.3f} m: {got:.5f} against {ref:.5f} m ({100 * (got / ref - 1):+.2f} %)")
    v, r, at = result["largest_square"]
    lines.append(f"largest square {v / 1e9:.4f} GPa at {np.round(at, 4).tolist()} against the half-space's mean "
                 f"{r / 1e9:.4f} GPa ({100 * (v / r - 1):+.2f} %)")
    (fit, ref_fit), (fat, ref_at) = result["fit"], result["fit_at"]
    lines.append(f"peak's fit (a local quadratic within {WINDOW_CELLS:g} local cells of {result['cell'] * 1e3:.4g} mm "
                 f"about the peak's place) {fit / 1e9:.4f} GPa at x = {fat:+.5f} m against the half-space read the same way "
                 f"{ref_fit / 1e9:.4f} GPa at {ref_at:+.5f} m ({100 * (fit / ref_fit - 1):+.2f} %, place "
                 f"{100 * (fat - ref_at) / hl:+.2f} % of the half-length)")
    place, ref_place = result["place"]
    lines.append(f"peak place (centroid of the plateau above {100 * PLATEAU_SHARE:g} % of the largest square, read the "
                 f"same way on both) x = {place:+.5f} m against {ref_place:+.5f} m "
                 f"({100 * (place - ref_place) / hl:+.2f} % of the half-length)")
    if refinement:
        coarse = refinement.get("coarse_pass") or {}
        lines.append(f"coarse pass: {coarse.get('levels_fewer')} levels shallower, tried {coarse.get('tried')}")
        for name, band in (refinement.get("band") or {}).items():
            lines.append(f"band of {name}: {len(band['centres'])} balls, radius {band['radius']:.4f} m at {band['levels']} "
                         f"levels; finer: {[(f['levels'], round(f['radius'], 4), len(f['centres'])) for f in band['finer']]}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("roller", choices=["lundberg", "tilted"])
    parser.add_argument("summary")
    parser.add_argument("--dx", type=float, default=None, help="rectangles along the line (default 1 mm)")
    parser.add_argument("--dy", type=float, default=0.0008)
    parser.add_argument("--cell", type=float, default=None,
                        help="the grid's cell at the peak, m (default: the summary's peak_fit.cell; for a summary "
                             "written before it, the map's squares' side)")
    args = parser.parse_args(argv)
    summary = json.loads(Path(args.summary).read_text())
    block = summary["contacts"][0]
    if args.roller == "lundberg":
        result = compare_lundberg(block, args.dx or 0.001, args.dy, args.cell)
    else:
        result = compare_tilted(block, ROOT / "examples" / "contact3d" / "tilted_roller.toml", args.dx or 0.001, args.dy,
                                args.cell)
    print(f"converged: {summary['converged']}; iterations {summary['iterations']['total']}")
    print(report(block, summary["iterations"].get("refinement"), result))


if __name__ == "__main__":
    main()
