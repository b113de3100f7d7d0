"""Write lundberg_roller.toml beside this file: the crowned roller example's roller with Lundberg's
logarithmic crown instead of a straight middle and circular crowns (a scene of the tests).

Lundberg's profile (G. Lundberg, Elastische Berührung zweier Halbräume, Forschung auf dem Gebiete
des Ingenieurwesens 10 (1939) 201-211) drops the roller's radius by

    drop(x) = C ln(1 / (1 - (2 x / l)^2)),    C = 2 w / (pi E*),

so that a half-space pressed by the line load w along the length l carries it nearly uniformly.
The log is infinite at x = +-l / 2, so l is taken a little longer than the roller (0.21 m for
0.2 m): the drop at the end faces is finite. The profile's axial section is written as a cubic
B-spline interpolating the drop at 41 stations (its largest deviation from the formula is
printed); the half-space reference in the tests uses the same spline.

Run from the repository's root: ``python tests/scenes/make_lundberg_roller.py``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.interpolate import make_interp_spline

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent.parent / "examples" / "contact3d"
RADIUS, HALF_LENGTH, LOG_LENGTH = 0.5, 0.1, 0.21
E_STAR = 2.0e11 / (2.0 * (1.0 - 0.3**2))
DESIGN_LOAD = 2.0e8  # w, N/m
STATIONS = 41


def drop(x: np.ndarray) -> np.ndarray:
    c = 2.0 * DESIGN_LOAD / (math.pi * E_STAR)
    return c * np.log(1.0 / (1.0 - (2.0 * np.asarray(x) / LOG_LENGTH) ** 2))


def slope(x: float) -> float:
    c = 2.0 * DESIGN_LOAD / (math.pi * E_STAR)
    u = 2.0 * x / LOG_LENGTH
    return c * 2.0 * u * (2.0 / LOG_LENGTH) / (1.0 - u * u)


def profile_spline():
    """The axial section (radius, axial) as a cubic B-spline of x, axial = -x (the revolution's
    axis points along -x), tangent to the straight axial direction at mid-length."""
    x = np.linspace(0.0, HALF_LENGTH, STATIONS)
    points = np.stack([RADIUS - drop(x), -x], axis=1)
    ends = ([(1, np.array([0.0, -1.0]))], [(1, np.array([-slope(HALF_LENGTH), -1.0]))])
    return make_interp_spline(x, points, k=3, bc_type=ends)


HEADER = """\
# A steel roller with Lundberg's logarithmic crown on a steel block, frictionless: radius R = 0.5 m,
# length 0.2 m, the radius dropped by C ln(1 / (1 - (2 x / l)^2)) with C = 2 w / (pi E*) for a
# design line load w = 200 MN/m and l = 0.21 m (a little longer than the roller, so the drop at
# the end faces is finite: 2.75 mm), pressed 2 mm down. Written by make_lundberg_roller.py (the
# axial section a cubic B-spline through the drop at 41 stations).
# Quarter model as the crowned roller example: the lower quarter of the roller from its
# mid-length plane x = 0 to its end face x = 0.1, on the block's top face z = 0 along the x axis;
# the symmetry faces x = 0 and y = 0 of both bodies slide. Grid: as the crowned roller example's,
# around = "contact" on an elongated contact that reaches towards the roller's end: a coarse pass
# finds the region, then a band of 6.25 mm cells (0.1 / 2^4) along it and 3.125 mm cells about
# its edge where the edge turns away from the line.
"""


def scene(spline) -> str:
    """The crowned roller example's scene with the roller's axial section replaced."""
    control = ", ".join(f"[{p[0]:.12g}, {p[1]:.12g}]" for p in spline.c)
    knots = ", ".join(f"{k:.12g}" for k in spline.t)
    end_r = float(spline(HALF_LENGTH)[0])
    text = (EXAMPLES / "crowned_roller.toml").read_text(encoding="utf-8")
    body = text[text.index('name = "crowned_roller"'):].replace('name = "crowned_roller"', 'name = "lundberg_roller"', 1)
    first, last = body.index("  { type = \"line\", start = [0.5, 0], end = [0.5, -0.05]"), body.index("  { type = \"line\", start = [0, -0.1]")
    crown = (f"  {{ type = \"bspline\", degree = 3, control_points = [{control}], knots = [{knots}], name = \"crown\" }},\n"
             f"  {{ type = \"line\", start = [{end_r:.12g}, -0.1], end = [0, -0.1], name = \"end_face\" }},\n")
    return HEADER + body[:first] + crown + body[last:]


def main() -> None:
    spline = profile_spline()
    dense = np.linspace(0.0, HALF_LENGTH, 2001)
    error = float(np.abs(spline(dense)[:, 0] - (RADIUS - drop(dense))).max())
    print(f"largest deviation of the spline from Lundberg's drop: {error:.3g} m (drop at the end face "
          f"{float(drop(HALF_LENGTH)) * 1e3:.4g} mm)")
    (HERE / "lundberg_roller.toml").write_text(scene(spline), encoding="utf-8")


if __name__ == "__main__":
    main()
