"""The tilted flat punch (examples/contact2d/tilted_punch.toml) against Johnson's closed form of a
rigid tilted punch on a half-plane held against rotation (Contact Mechanics, 1985, sec. 2.8): a
region of length 2 a with P = pi E* eps a / 2 and the corner's stress intensity
K = E* eps sqrt(pi a), for the computed force P. Each rung moves the deepest contact refinement of
both bodies by the same number of levels (0: the example's grid), and each rung is solved with
the contact point at the touching corner (the example's), beside the other corner, and left out
(the bodies' closest points). Prints a markdown table of the errors in the region's length and in
K, and whether each run converged.

    python benchmarks/tilted_punch.py --shifts -1 0 1
"""

from __future__ import annotations

import argparse
import copy
import math
import time
from pathlib import Path

from ibfem.solver.io.scene import load_scene, scene_from_dict
from ibfem.solver.solving import solve

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "contact2d" / "tilted_punch.toml"


def _variant(data: dict, shift: int, point: str) -> dict:
    """The example's data with every body's deepest contact refinement ``shift`` levels deeper and
    the contact point at the corner ("corner"), a quarter cell inside the flat beside the other
    corner ("far") or left out ("none")."""
    out = copy.deepcopy(data)
    out["output"] = {"vtk": False, "plots": False}
    for body in out["bodies"]:
        zones = [z for z in body.get("refinement", []) if z.get("around") == "contact"]
        if zones:
            max(zones, key=lambda z: z["levels"])["levels"] += shift
    contact = out["contacts"][0]
    if point == "none":
        contact.pop("point", None)
    elif point == "far":  # the punch's flat runs from x = -0.01 to the corner at x = 0.01
        eps = -math.radians(out["bodies"][0]["shape"]["rotate_deg"])
        x = -0.01 + 0.25 * 0.04 / 2 ** (7 + shift)
        contact["point"] = [0.01 - (0.01 - x) * math.cos(eps), (0.01 - x) * math.sin(eps)]
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shifts", type=int, nargs="+", default=[-1, 0, 1], help="levels added to the example's grid")
    parser.add_argument("--points", nargs="+", default=["corner", "far", "none"], choices=["corner", "far", "none"])
    args = parser.parse_args(argv)
    scene = load_scene(EXAMPLE)
    data = scene.spec.model_dump(mode="json", exclude_none=True)
    eps = -math.radians(data["bodies"][0]["shape"]["rotate_deg"])
    moduli = {m["name"]: (m["youngs_modulus"], m["poissons_ratio"]) for m in data["materials"]}
    e_star = 1.0 / sum((1.0 - nu * nu) / e for e, nu in (moduli[b["material"]] for b in data["bodies"]))
    print("| levels added | contact point | region length vs Johnson | corner K vs Johnson | converged | CPU (s) |")
    print("|---|---|---|---|---|---|")
    for shift in args.shifts:
        for point in args.points:
            t = time.process_time()
            sol = solve(scene_from_dict(_variant(data, shift, point), base_dir=EXAMPLE.parent).problem)
            c = sol.contacts[0]
            a = 2.0 * c["normal_force"] / (math.pi * e_star * eps)
            corner = [e for e in c["ends"] if e["type"] == "complete"]
            k = corner[0]["stress_intensity"] / (e_star * eps * math.sqrt(math.pi * a)) - 1.0 if corner else math.nan
            print(f"| {shift:+d} | {point} | {100 * ((c['region'][1] - c['region'][0]) / (2 * a) - 1):+.2f} % | "
                  f"{100 * k:+.1f} % | {sol.converged} | {time.process_time() - t:.1f} |")


if __name__ == "__main__":
    main()
