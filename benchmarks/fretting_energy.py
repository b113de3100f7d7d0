"""Energy audit of a fretting run: where the rig's work over a cycle goes.

Over a closed cycle the loop's area (Q against the relative displacement of the essential faces,
trapezoids over the steps) and the local friction work (the slipping points' shear times their
slip) are both the energy dissipated. This script solves a fretting scene and prints, per
complete cycle and for the first branch from a turning point to the next extreme (a half loop,
closed by its point symmetry), in the run's units (J/m in 2D, J in 3D, for the model):

- ``loop``: the area of the loop, as the run's ``fretting`` block computes it;
- ``into bodies``: the work of the essential conditions' terms on the bodies, the trapezoids of
  their force (the prescribed-displacement load less their stiffness times the field) times the
  field's increment over each step: the rig's work on the discrete model;
- ``contact``: the work of the contact's terms at the contact's dofs (trapezoids of their force
  times the increment of the contact dofs);
- ``friction``: the sum of the steps' friction work;
- ``strain``: the change of the bodies' strain energy 1/2 u K u over the same steps.

``into bodies`` = ``contact`` + ``strain`` holds to round-off (the equilibrium of each step), so
``loop`` against ``into bodies`` checks the loop's reading, and ``contact`` against ``friction``
says how much the discrete contact dissipates beyond the friction work.

    .venv/bin/python benchmarks/fretting_energy.py                       # the 2D example
    .venv/bin/python benchmarks/fretting_energy.py --grid-offset 0.37 0.21
    .venv/bin/python benchmarks/fretting_energy.py --sphere 0.3 [--edge-ring]  # 3D half loop

The 2D example takes about 10 s and 0.2 GB; the sphere's half loop about 40 s and 0.65 GB (with
``--edge-ring`` about 200 s and 1.8 GB). Prints only; writes nothing.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

import numpy as np
import scipy.sparse as sp

HERE = Path(__file__).resolve().parent
EXAMPLE_2D = HERE.parent / "examples" / "fretting" / "cylinder_on_flat_fretting.toml"


def _scene(args):
    from ibfem.solver.io.scene import scene_from_dict

    if args.sphere is not None:
        from ibfem.solver.reports.validate_fretting_sphere import EXAMPLE, amplitude_for, scene_data

        data = scene_data(amplitude_for(args.sphere), 0.75, args.points_per_cycle, args.grid_offset,
                          edge_ring=args.edge_ring)
        return scene_from_dict(data, label=str(EXAMPLE), base_dir=EXAMPLE.parent)
    data = tomllib.loads(EXAMPLE_2D.read_text(encoding="utf-8"))
    data["paths"][1]["cycle"]["points_per_cycle"] = args.points_per_cycle
    if args.grid_offset is not None:
        data["solver"]["grid_offset"] = list(args.grid_offset)
    data["output"] = {"vtk": False, "plots": False}
    return scene_from_dict(data, label=str(EXAMPLE_2D), base_dir=EXAMPLE_2D.parent)


def _solve_recording(problem):
    """Solve, keeping each step's contact state (dofs, terms) and the driver."""
    from ibfem.solver.contact import driver as contact_driver
    from ibfem.solver.solving import solve

    states, held = [], {}
    original = contact_driver.ContactDriver._load_step

    def recording(self, step):
        original(self, step)
        held["driver"] = self
        _, x, _, kc, fc, _ = self.prev
        states.append((x.copy(), kc, fc.copy()))

    contact_driver.ContactDriver._load_step = recording
    try:
        solution = solve(problem)
    finally:
        contact_driver.ContactDriver._load_step = original
    return solution, states, held["driver"]


def _trapezoids(forces: list, values: list) -> np.ndarray:
    return np.array([0.5 * (forces[i] + forces[i + 1]) @ (values[i + 1] - values[i]) for i in range(len(values) - 1)])


def audit_recording(problem, recording) -> tuple[dict, float]:
    """:func:`audit` with the 2D history contact's ``end_step`` replaced by ``recording`` (called
    as ``recording(contact, x, a, info)``; it calls the original itself), restored after: (the
    audit, its CPU seconds)."""
    import time

    from ibfem.solver.contact import friction_history as fh

    original = fh.HistoryBandContact.end_step
    fh.HistoryBandContact.end_step = recording
    cpu = time.process_time()
    try:
        r = audit(problem)
    finally:
        fh.HistoryBandContact.end_step = original
    return r, time.process_time() - cpu


def audit(problem) -> dict:
    """Per step the energies of the module's docstring (arrays over the steps, the work ones over
    the intervals between steps) and the loop's force and displacement."""
    from ibfem.solver.io.fretting_outputs import _relative_displacement, loop_force

    solution, states, drv = _solve_recording(problem)
    steps = solution.steps
    q = np.array([loop_force(st["contacts"][0]) for st in steps])
    delta = _relative_displacement(steps, 0, solution.contacts[0], problem)
    bodies = sp.block_diag([b.stiffness(drv.options.fictitious_stiffness) for b in drv.bodies], format="csr")
    essential = (drv.k0 - bodies).tocsr()
    fields = [st["field"] for st in steps]
    loads = [drv.path_steps.at(st["t"])[0] for st in steps]
    into = _trapezoids([f - essential @ u for f, u in zip(loads, fields)], fields)
    contact = _trapezoids([kc @ x - fc for x, kc, fc in states], [x for x, _, _ in states])
    return {"t": np.array([st["t"] for st in steps]), "q": q, "delta": delta, "into": into, "contact": contact,
            "friction": np.array([st["contacts"][0]["friction_work"] for st in steps]),
            "strain": np.array([0.5 * u @ (bodies @ u) for u in fields]), "converged": solution.converged,
            "normal": np.array([st["contacts"][0]["normal_force"] for st in steps]),
            "solves": solution.iterations["total"]}


def _line(label: str, r: dict, i: int, j: int, factor: float = 1.0) -> str:
    from ibfem.solver.io.fretting_outputs import loop_energy

    values = {"loop": abs(loop_energy(r["q"], r["delta"], i, j)), "into bodies": abs(r["into"][i:j].sum()),
              "contact": abs(r["contact"][i:j].sum()), "friction": r["friction"][i + 1:j + 1].sum(),
              "strain": r["strain"][j] - r["strain"][i]}
    text = "  ".join(f"{k} {factor * v:.6g}" for k, v in values.items())
    return f"{label} t {r['t'][i]:.3f}-{r['t'][j]:.3f}: {text}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sphere", type=float, default=None, metavar="RATIO",
                    help="the 3D example's half loop at about this Q*/(mu N) instead of the 2D example")
    ap.add_argument("--points-per-cycle", type=int, default=20)
    ap.add_argument("--grid-offset", type=float, nargs="+", default=None)
    ap.add_argument("--edge-ring", action="store_true", help="3D: one more refinement level about the contact's edge")
    args = ap.parse_args(argv)
    from ibfem.solver.io.fretting_outputs import cycles_of, turning_steps

    r = audit(_scene(args).problem)
    print(f"converged {r['converged']}, {r['solves']} solves")
    for i, j in cycles_of(r["q"]):
        print(_line("cycle", r, i, j))
    turns = turning_steps(r["q"])
    if turns:
        j = turns[1] if len(turns) > 1 else len(r["q"]) - 1
        print(_line("half loop (doubled)", r, turns[0], j, 2.0))
    return 0 if r["converged"] else 1


if __name__ == "__main__":
    sys.exit(main())
