"""A refinement ladder of one 2D scene: the deepest ``around = "contact"`` refinement of every body
set to each of the given numbers of levels (all else as the scene has it, no output files), one
solve per rung in this process. Prints a markdown table of each contact's half-width, stick
half-width and normal force, their change from the finest rung, the dofs and the CPU time, so a
scene's grid-converged values (and how far its own grid is from them) can be read off; run it in
two checkouts to compare what a change does to the converged values rather than to one grid.

    python benchmarks/contact_levels.py examples/cylinder_in_concave_partial_slip.toml --levels 3 4 5 6
"""

from __future__ import annotations

import argparse
import time

from ibfem.solver.io.scene import load_scene, scene_from_dict
from ibfem.solver.solving import solve


def _rung(data: dict, levels: int) -> dict:
    """The scene's data with every body's deepest contact refinement at ``levels``."""
    out = dict(data, output=dict(data.get("output", {}), vtk=False, plots=False))
    bodies = []
    for body in data["bodies"]:
        zones = [dict(z) for z in body.get("refinement", [])]
        contact = [z for z in zones if z.get("around") == "contact"]
        if contact:
            max(contact, key=lambda z: z["levels"])["levels"] = levels
        bodies.append(dict(body, refinement=zones))
    out["bodies"] = bodies
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="a 2D scene file")
    parser.add_argument("--levels", type=int, nargs="+", required=True, help="levels of the contact refinement, one per rung")
    args = parser.parse_args(argv)
    scene = load_scene(args.scene)
    data = scene.spec.model_dump(mode="json", exclude_none=True)
    rows = []
    for levels in args.levels:
        t = time.process_time()
        sol = solve(scene_from_dict(_rung(data, levels), base_dir=scene.path.parent).problem)
        rows.append((levels, sol, time.process_time() - t))
    finest = rows[-1][1].contacts
    print("| levels | contact | a (m) | c (m) | N (N/m) | a vs finest | N vs finest | dofs | CPU (s) | converged |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for levels, sol, cpu in rows:
        for k, (c, f) in enumerate(zip(sol.contacts, finest)):
            print(f"| {levels} | {k} | {c['half_width']:.7g} | {c.get('stick_half_width', 0.0):.7g} | {c['normal_force']:.7g} | "
                  f"{100 * (c['half_width'] / f['half_width'] - 1):+.4f} % | {100 * (c['normal_force'] / f['normal_force'] - 1):+.4f} % | "
                  f"{sol.u.size} | {cpu:.1f} | {sol.converged} |")


if __name__ == "__main__":
    main()
