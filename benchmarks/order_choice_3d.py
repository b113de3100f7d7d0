"""The elimination order of the condensed factorisation: each body of a 3D contact scene factored
with its contact dofs last in the driver's order (METIS's dissection of the whole system, the
contact dofs moved last) and in the order with the contact nodes contracted into one vertex
(``linalg.contact_last_order``), the two alternately in one process, ``--repeat`` times each:
the flops (counted on the supernodes of the symbolic phase), the CPU seconds of the
factorisation (``condensed_cholesky``: symbolic and numeric, one BLAS thread, the factor
streamed to disk where the run would), the time of the choice itself (the contracted order
and the two flop counts on the node graph), and which order the run would take. Timings on a
shared machine are noisy: compare the ratio of alternating runs.

``--extent-fraction F`` sets the contacts' candidate disc (default: the scene's; the sized disc
of a run with a coarse pass is recorded in its summary's ``iterations.candidate_region``).

    python benchmarks/order_choice_3d.py examples/solid/full/crossed_cylinders.toml --extent-fraction 0.5924
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time

import numpy as np

from factor_profile_3d import flops, symbolic
from ibfem.solver.contact.driver import ContactDriver
from ibfem.solver.fem import linalg
from ibfem.solver.fem.multifrontal import condensed_cholesky
from ibfem.solver.io.scene import load_scene


def bodies(scene: str, extent_fraction: float | None):
    """(block of K0, its contact dofs, its part of the driver's order) per body with contact dofs."""
    problem = load_scene(scene).problem
    if extent_fraction is not None:
        contacts = tuple(dataclasses.replace(c, options=dataclasses.replace(c.options, extent_fraction=extent_fraction))
                         for c in problem.contacts)
        problem = dataclasses.replace(problem, contacts=contacts)
    driver = ContactDriver(problem)
    driver._discretise()
    driver._assemble()
    dofs = np.unique(np.concatenate([c.dofs for c in driver.contacts]))
    k0 = driver.k0.tocsr()
    groups = linalg.uncoupled_groups(k0, dofs)
    if groups is None:
        groups = np.zeros(k0.shape[0], dtype=np.int64)
    order = linalg.dof_order(driver.bodies, k0)
    out = []
    for g in range(int(groups.max()) + 1):
        idx = np.flatnonzero(groups == g)
        local = np.full(k0.shape[0], -1, dtype=np.int64)
        local[idx] = np.arange(len(idx))
        contact = local[dofs[groups[dofs] == g]]
        if len(contact):
            out.append((k0[idx][:, idx].tocsr(), contact, local[order[groups[order] == g]]))
    return out


def factor_cpu(k, order: np.ndarray, m: int) -> float:
    c = time.process_time()
    factor = condensed_cholesky(k, order, m, guard=linalg.single_threaded_blas, on_disk=None)
    cpu = time.process_time() - c
    del factor
    return cpu


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--extent-fraction", type=float, default=None)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args(argv)
    print(f"{'body':>4} {'dofs':>7} {'m_b':>6} {'order':>10} {'GFlop':>6} {'CPU s':>16} {'GFlop/s':>7}")
    for b, (k, contact, given) in enumerate(bodies(args.scene, args.extent_fraction)):
        is_contact = np.zeros(k.shape[0], dtype=bool)
        is_contact[contact] = True
        c = time.process_time()
        chosen = linalg._cheaper_order(k, contact, given)
        choice_cpu = time.process_time() - c
        orders = {"given": np.concatenate([given[~is_contact[given]], contact]),
                  "contracted": linalg.contact_last_order(k, contact, 3)}
        work = {name: sum(flops(symbolic(k, o, len(contact)))) for name, o in orders.items()}
        cpu = {name: [] for name in orders}
        for _ in range(args.repeat):
            for name, o in orders.items():
                cpu[name].append(factor_cpu(k, o, len(contact)))
        for name, o in orders.items():
            times = " ".join(f"{t:.1f}" for t in cpu[name])
            print(f"{b:4d} {k.shape[0]:7d} {len(contact):6d} {name:>10} {work[name] / 1e9:6.0f} {times:>16} "
                  f"{work[name] / 1e9 / min(cpu[name]):7.1f}", flush=True)
        taken = "contracted" if np.array_equal(chosen, orders["contracted"]) else "given"
        print(f"     the choice: {choice_cpu:.1f} s CPU, takes the {taken} order", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
