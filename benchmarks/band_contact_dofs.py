"""The contact dofs ``ibfem run --check`` counts for a followed line contact's fine pass
(solver.model.estimate.contact_dofs_per_body) against the ones the fine pass's grids hold, with
and without the thin balls along the straight sides (solver.contact.follow.SIDE_REACH_CELLS):
solves the coarse pass as the run does (solver.contact.follow.coarse_pass), then builds the fine
pass's grids and its contact (nothing more is solved).

    python benchmarks/band_contact_dofs.py examples/contact3d/crowned_roller.toml
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ibfem.solver.contact import follow
from ibfem.solver.contact.driver import ContactDriver
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model.estimate import contact_dofs_per_body
from ibfem.solver.model.resolve import resolve_problem
from ibfem.solver.solving import solve


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    args = parser.parse_args(argv)
    problem = load_scene(Path(args.scene)).problem
    lines = follow.line_contacts(problem)
    if not lines:
        raise SystemExit(f"{args.scene}: no followed line contact (contact ball of four levels or more)")
    coarse, fewer, _ = follow.coarse_pass(problem, lines, solve)
    for side in (follow.SIDE_REACH_CELLS, None):
        follow.SIDE_REACH_CELLS = side
        fine, _ = follow.band_problem(problem, lines, coarse.contacts, fewer)
        driver = ContactDriver(resolve_problem(fine))
        driver._discretise()
        driver._assemble()
        for k in lines:
            bodies, per_body = contact_dofs_per_body(fine, fine.contacts[k])
            built = len(driver.contacts[k].dofs)
            print(f"side balls {'on' if side is not None else 'off'}: contact {k}: estimated {bodies * per_body:.0f} "
                  f"contact dofs, built {built} ({bodies * per_body / built:.2f}); dofs built "
                  f"{sum(b.n_dofs for b in driver.bodies)}")


if __name__ == "__main__":
    main()
