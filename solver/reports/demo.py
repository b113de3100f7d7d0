"""``make demo``: the main job end to end on cached Onshape parts (2D, then 3D).

1. Loads the cached part studio ``fixtures/onshape/half_cylinder_on_block`` and checks the
   projection of its tessellated vertices onto the exact surfaces (``ibfem verify``).
2. Cuts both bodies into 2D profiles and solves the contact scene
   ``examples/onshape/half_cylinder_on_block.toml`` (``ibfem run``).
3. Prints the contact half-width and peak pressure against Hertz for the force found, and writes
   ``summary.json``, the VTU files and the pictures to ``out/demo`` (or ``--out``).
4. In 3D (``--no-3d`` skips it, about ten seconds): the "Cone with sphere cap" body of the cached
   part studio ``fixtures/onshape/cone_sphere`` pressed cap down onto a block
   (``examples/solid/onshape_ball_on_block.toml``), its contact circle and centre pressure
   against Hertz's sphere on a flat for the force found; results in ``out/demo/solid``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIXTURE = ROOT / "fixtures" / "onshape" / "half_cylinder_on_block"
SCENE = ROOT / "examples" / "onshape" / "half_cylinder_on_block.toml"
SOLID_SCENE = ROOT / "examples" / "solid" / "onshape_ball_on_block.toml"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m ibfem.solver.reports.demo", description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    parser.add_argument("--no-3d", action="store_true", help="skip the 3D part (about ten seconds)")
    args = parser.parse_args(argv)
    out = Path(args.out)

    from ibfem.geometry.verify import verify_projection
    from ibfem.importers.onshape import load_part

    print(f"1. Onshape part studio (cached): {FIXTURE.relative_to(ROOT)}")
    part = load_part(FIXTURE)
    report = verify_projection(part, offset=1e-3)
    exact = [f for f in report["faces"] if f.get("max_error") is not None]
    print(
        f"   {len(part.bodies)} bodies, {len(part.faces)} faces ({len(exact)} exact), {len(part.edges)} edges;"
        f" projection of tessellated vertices: max position error {report['max_error']:.2e} m"
    )

    from ibfem.solver.reference import theory
    from ibfem.solver.solving import solve
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import SceneError, load_scene
    from ibfem.solver.reports.validate import effective_properties

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
    print(f"   Results written to {out}/: summary.json" + (", " + ", ".join(files) if files else ""))
    solid_ok = True if args.no_3d else solid_demo(out / "solid")
    return 0 if summary["converged"] and solid_ok else 1


def solid_demo(out: Path) -> bool:
    """The 3D part: a cached Onshape solid on a block against Hertz; whether it converged."""
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.reports.validate_solid import centre_pressure, circular_reference
    from ibfem.solver.solving import solve

    print(f"4. 3D contact of a CAD solid: {SOLID_SCENE.relative_to(ROOT)} (about ten seconds)")
    scene = load_scene(SOLID_SCENE)
    t0 = time.perf_counter()
    solution = solve(scene.problem)
    summary = write_scene_results(out, scene, solution, total_s=time.perf_counter() - t0)
    dofs = sum(b["dofs"] for b in summary["bodies"].values())
    print(f"   {dofs} dofs, solved in {summary['timings']['total_s']:.1f} s, converged: {summary['converged']}")
    c = summary["contacts"][0]
    n_full, a_h, p0_h = circular_reference(scene, c, 1.0 / c["model_share"])
    a = c["semi_axes"][0]
    p_centre = centre_pressure(c)
    print(f"   normal force N      {n_full:12.5g} N")
    print(f"   contact radius a    {a:12.5g} m      Hertz {a_h:.5g} m   error {100 * (a / a_h - 1):+.2f} %")
    print(f"   centre pressure p0  {p_centre:12.5g} Pa     Hertz {p0_h:.5g} Pa  error {100 * (p_centre / p0_h - 1):+.2f} %")
    print(f"   Results written to {out}/ (contact patch picture: contact_0.png)")
    return bool(summary["converged"])


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
