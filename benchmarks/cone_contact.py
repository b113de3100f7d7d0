"""Point contacts that are not Hertzian: a steel cone of 10 degrees and a cone whose tip is rounded
to 2 mm, each pressed into a steel block, against Sneddon's solution for a punch of revolution; and
the cone pulled sideways with friction 0.3, its stick radius against Jaeger's rule.

Sneddon (Int. J. Engng Sci. 3 (1965) 47-57): a gap of revolution f(r) pressed to the contact radius
a carries P(a) = 2 E* int_0^a x^2 f'(x) / sqrt(a^2 - x^2) dx; the benchmark inverts it for each
run's computed force. A cone f = r tan b gives a = sqrt(2 P / (pi E* tan b)). Under a tangential
load Q < mu N (bodies of one material) P(c) / P(a) = 1 - Q / (mu N) (Jaeger 1998; Ciavarella 1998):
for a cone c / a = sqrt(1 - Q / (mu N)), where Mindlin's rule for Hertz's gap gives the cube root.

    python benchmarks/cone_contact.py            # the cone at 4 and 5 levels, the rounded tip, friction
    python benchmarks/cone_contact.py --quick    # without the 5-level cone (about 90 s of the total)

Each run is ``ibfem run --quiet --no-estimate`` in its own process; the table gives the cells
across the radius, the error against Sneddon (and the stick ratio against Jaeger's) and the wall
time."""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from scipy.integrate import quad
from scipy.optimize import brentq

E, NU = 2.0e11, 0.3
E_STAR = E / (2.0 * (1.0 - NU * NU))
ANGLE = math.radians(10.0)
TIP = 0.002  # the rounded tip's radius (m)

SCENE = """
name = "{name}"
model = "solid"
[solver]
load_steps = {steps}
[output]
vtk = false
plots = false
[[materials]]
name = "steel"
youngs_modulus = 2.0e11
poissons_ratio = 0.3
[[bodies]]
name = "cone"
material = "steel"
element_size = 0.004
refinement = [{{ levels = {levels}, around = "contact", radius = 0.003 }}]
shape = {{ type = "revolution", axis_origin = [0, 0, 0], axis = [0, 0, 1], profile = {{ type = "profile", edges = [
{edges}
  {{ type = "line", start = [0.01, 0.01], end = [0, 0.01], name = "top" }},
  {{ type = "line", start = [0, 0.01], end = [0, 0], name = "axis" }},
] }} }}
[[bodies]]
name = "block"
material = "steel"
element_size = 0.004
refinement = [{{ levels = {levels}, around = "contact", radius = 0.003 }}]
shape = {{ type = "box", min = [-0.02, -0.02, -0.015], max = [0.02, 0.02, 0.0] }}
[[boundary_conditions]]
body = "cone"
face = "top"
type = "displacement"
value = [{ux}, 0.0, -2.0e-4]
[[boundary_conditions]]
body = "block"
face = "z_min"
type = "fixed"
[[contacts]]
bodies = ["cone", "block"]
{contact}
"""


def _edges(rounded: bool) -> str:
    """The flank (from the apex, or from a tip of radius TIP tangent to it) and the side."""
    z_end = 0.01 * math.tan(ANGLE)
    if not rounded:
        return (f'  {{ type = "line", start = [0, 0], end = [0.01, {z_end!r}], name = "flank" }},\n'
                f'  {{ type = "line", start = [0.01, {z_end!r}], end = [0.01, 0.01], name = "side" }},')
    xt, zt = TIP * math.sin(ANGLE), TIP * (1.0 - math.cos(ANGLE))
    z_end = zt + (0.01 - xt) * math.tan(ANGLE)
    return (f'  {{ type = "arc", center = [0, {TIP!r}], radius = {TIP!r}, start_angle = -90, end_angle = -80, '
            f'name = "tip" }},\n'
            f'  {{ type = "line", start = [{xt!r}, {zt!r}], end = [0.01, {z_end!r}], name = "flank" }},\n'
            f'  {{ type = "line", start = [0.01, {z_end!r}], end = [0.01, 0.01], name = "side" }},')


def slope(rounded: bool):
    """f'(r) of the gap of revolution."""
    xt = TIP * math.sin(ANGLE)
    if not rounded:
        return lambda r: math.tan(ANGLE)
    return lambda r: r / math.sqrt(TIP * TIP - r * r) if r < xt else math.tan(ANGLE)


def sneddon_radius(force: float, f_slope) -> float:
    """The contact radius a with P(a) = force (x = a sin t in Sneddon's integral)."""
    def load(a):
        return 2.0 * E_STAR * quad(lambda t: (a * math.sin(t)) ** 2 * f_slope(a * math.sin(t)), 0.0,
                                   0.5 * math.pi, limit=200)[0]
    return brentq(lambda a: load(a) - force, 1e-7, 0.01)


CASES = {  # name: (levels, rounded, friction)
    "cone, 4 levels": (4, False, False),
    "cone, 5 levels": (5, False, False),
    "rounded tip, 4 levels": (4, True, False),
    "cone with friction, 4 levels": (4, False, True),
}


def run_case(name: str, work: Path) -> dict:
    levels, rounded, friction = CASES[name]
    contact = 'type = "frictional"\nfriction = 0.3' if friction else 'type = "frictionless"'
    text = SCENE.format(name=name, steps=3 if friction else 1, levels=levels, edges=_edges(rounded),
                        ux=1.5e-5 if friction else 0.0, contact=contact)
    scene, out = work / f"{name.replace(' ', '_').replace(',', '')}.toml", work / "out"
    scene.write_text(text)
    t0 = time.perf_counter()
    run = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(scene), "--out", str(out),
                          "--quiet", "--no-estimate"], capture_output=True, text=True)
    row = {"case": name, "exit": run.returncode, "wall_s": time.perf_counter() - t0}
    if run.returncode not in (0, 1):
        row["error"] = run.stderr.strip().splitlines()[-1:] if run.stderr.strip() else []
        return row
    summary = json.loads((out / "summary.json").read_text())
    c = summary["contacts"][0]
    a = c["semi_axes"][0]
    row.update(converged=summary["converged"], a=a, N=c["normal_force"], cells=c["cells_per_semi_axis"][0],
               a_error=a / sneddon_radius(c["normal_force"], slope(rounded)) - 1.0)
    if friction:
        share = 1.0 - math.hypot(*c["tangential_force"]) / (0.3 * c["normal_force"])
        row.update(stick_ratio=c["stick_semi_axes"][0] / a, jaeger=math.sqrt(share), mindlin=share ** (1.0 / 3.0))
    return row


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="without the 5-level cone")
    args = ap.parse_args(argv)
    names = [n for n in CASES if not (args.quick and "5 levels" in n)]
    rows = []
    with tempfile.TemporaryDirectory(prefix="ibfem_cone_") as tmp:
        for name in names:
            rows.append(run_case(name, Path(tmp)))
            r = rows[-1]
            extra = (f", c/a {r['stick_ratio']:.4f} (Jaeger {r['jaeger']:.4f}, Mindlin's rule {r['mindlin']:.4f})"
                     if "stick_ratio" in r else "")
            print(f"{name}: " + (f"a {100 * r['a_error']:+.2f} % from Sneddon at {r['cells']:.1f} cells, "
                                 f"converged {r['converged']}{extra}, {r['wall_s']:.0f} s" if "a" in r
                                 else f"exit {r['exit']}: {r.get('error')}"), flush=True)
    return 0 if all("a" in r for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
