"""``make demo``: the main job end to end on a cached Onshape part.

1. Loads the cached part studio ``fixtures/onshape/half_cylinder_on_block`` and checks the
   projection of its tessellated vertices onto the exact surfaces (``ibfem verify``).
2. Cuts both bodies into 2D profiles and solves the contact scene
   ``examples/onshape/half_cylinder_on_block.toml`` (``ibfem run``).
3. Prints the contact half-width and peak pressure against Hertz for the force found, and writes
   ``summary.json``, the VTU files and the pictures to ``out/demo`` (or ``--out``).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIXTURE = ROOT / "fixtures" / "onshape" / "half_cylinder_on_block"
SCENE = ROOT / "examples" / "onshape" / "half_cylinder_on_block.toml"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m solver.reports.demo", description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    args = parser.parse_args(argv)
    out = Path(args.out)

    from geometry.verify import verify_projection
    from importers.onshape import load_part

    print(f"1. Onshape part studio (cached): {FIXTURE.relative_to(ROOT)}")
    part = load_part(FIXTURE)
    report = verify_projection(part, offset=1e-3)
    exact = [f for f in report["faces"] if f.get("max_error") is not None]
    print(
        f"   {len(part.bodies)} bodies, {len(part.faces)} faces ({len(exact)} exact), {len(part.edges)} edges;"
        f" projection of tessellated vertices: max position error {report['max_error']:.2e} m"
    )

    from solver.reference import theory
    from solver.solve import solve
    from solver.io.output import write_scene_results
    from solver.io.scene import SceneError, load_scene
    from solver.reports.validate import effective_properties

    print(f"2. Contact scene: {SCENE.relative_to(ROOT)}")
    try:
        scene = load_scene(SCENE)
    except SceneError as err:
        print(err, file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    solution = solve(scene.problem)
    summary = write_scene_results(out, scene, solution, total_s=time.perf_counter() - t0)
    print(f"   solved in {summary['timings']['total_s']:.2f} s, converged: {summary['converged']},"
          f" {summary['iterations']['total']} iterations")
    for block in summary["contacts"]:
        r_eff, e_eff = effective_properties(scene.problem, block)
        N = block["normal_force"]
        a = block["half_width"]
        a_ref = theory.hertz_half_width(N, r_eff, e_eff)
        p0_ref = theory.hertz_peak_pressure(N, a_ref)
        p_max = max(block["pressure"]["value"], default=float("nan"))
        print("3. Contact results against Hertz (for the normal force found):")
        print(f"   normal force N      {N:12.5g} N/m    tangential force Q {block['tangential_force']:.3g} N/m")
        print(f"   half-width a        {a:12.5g} m      Hertz {a_ref:.5g} m   error {100 * abs(a - a_ref) / a_ref:.2f} %")
        print(f"   peak pressure p0    {p_max:12.5g} Pa     Hertz {p0_ref:.5g} Pa  error {100 * abs(p_max - p0_ref) / p0_ref:.2f} %")
    files = summary.get("files", [])
    print(f"4. Results written to {out}/: summary.json" + (", " + ", ".join(files) if files else ""))
    return 0 if summary["converged"] else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
