"""Where the condensed factorisation of a 3D contact scene spends its flops and memory, counted
on its symbolic phase (no numeric factorisation): per body, the stored entries of L, the
update-matrix stack and the largest front below the root (work space), and the dense flops of
the root (the contact dofs' front), of the fronts whose rows reach the contact dofs, and of the
others (sum over supernodes of the flops of their pivot columns).

``--no-size-check`` counts a scene the scene check refuses (such as the full ball on a block at
five levels, about 1.4 million dofs). ``--extent-fraction F`` sets the contacts' candidate disc (default: the scene's; the sized
disc of a run with a coarse pass is recorded in its summary's ``iterations.candidate_region``).

    python benchmarks/factor_profile_3d.py examples/solid/full/crossed_cylinders.toml --extent-fraction 0.5924

Candidates for a scene of a million dofs are compared this way before any is run (docs/scale-3d.md,
"A million dofs"): ``benchmarks/scenes/ball_on_plate_million.toml`` (1,008,240 dofs) counts 8.76
TFlop, 14.7 GB of factor and 4.0 GB of work space for its larger body in 91 s and 5.3 GB.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

import numpy as np

from ibfem.solver.contact.driver import ContactDriver
from ibfem.solver.fem import multifrontal
from ibfem.solver.fem.linalg import ORDER_CHOICE_DOFS, _cheaper_order, dof_order, uncoupled_groups
from ibfem.solver.io.scene import load_scene


def symbolic(k, order: np.ndarray, m: int):
    """The symbolic phase of the condensed Cholesky factor of k in ``order`` (m contact dofs last)."""
    kern = multifrontal._kernels()
    f = multifrontal.CholeskyFactor.__new__(multifrontal.CholeskyFactor)
    f.n, f.m, f.definite = k.shape[0], m, False
    f.order = f._postordered(k, order, kern)
    f._symbolic(k, kern)
    return f


def flops(f) -> tuple[float, float, float]:
    """Dense flops (root, fronts reaching the contact dofs, other fronts) of a symbolic factor."""
    ncol = np.diff(f.sn_start).astype(float)
    front = ncol + np.diff(f.row_ptr)
    work = ncol * front**2 - ncol**2 * front + ncol**3 / 3.0
    last_row = np.array([f.rows[f.row_ptr[s]:f.row_ptr[s + 1]].max(initial=-1) for s in range(len(ncol))])
    reach = last_row >= f.n - f.m
    return float(work[-1]), float(work[:-1][reach[:-1]].sum()), float(work[:-1][~reach[:-1]].sum())


def body_factors(problem):
    """(group, symbolic factor) of each body of a 3D contact problem that holds contact dofs: its
    block of K0 in the order the run factors it in (the cheaper of the two orders where the run
    chooses), the contact dofs last."""
    driver = ContactDriver(problem)
    driver._discretise()
    driver._assemble()
    dofs = np.unique(np.concatenate([c.dofs for c in driver.contacts]))
    k0 = driver.k0.tocsr()
    groups = uncoupled_groups(k0, dofs)
    if groups is None:
        groups = np.zeros(k0.shape[0], dtype=np.int64)
    order = dof_order(driver.bodies, k0)
    for g in range(int(groups.max()) + 1):
        idx = np.flatnonzero(groups == g)
        local = np.full(k0.shape[0], -1, dtype=np.int64)
        local[idx] = np.arange(len(idx))
        contact = local[dofs[groups[dofs] == g]]
        if not len(contact):
            continue
        sub = local[order[groups[order] == g]]
        is_contact = np.zeros(len(idx), dtype=bool)
        is_contact[contact] = True
        block = k0[idx][:, idx]
        if len(idx) >= ORDER_CHOICE_DOFS:  # the order the run factors in (the cheaper of the two)
            sub = _cheaper_order(block, contact, sub)
        yield g, symbolic(block, np.concatenate([sub[~is_contact[sub]], contact]), len(contact))


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--extent-fraction", type=float, default=None)
    ap.add_argument("--no-size-check", action="store_true",
                    help="count a scene the size check refuses (its symbolic phase only: no numeric factorisation)")
    args = ap.parse_args(argv)
    if args.no_size_check:
        from ibfem.solver.io import scene_solid

        scene_solid.size_problems = lambda problem, label: []
    problem = load_scene(args.scene).problem
    if args.extent_fraction is not None:
        contacts = tuple(dataclasses.replace(c, options=dataclasses.replace(c.options, extent_fraction=args.extent_fraction))
                         for c in problem.contacts)
        problem = dataclasses.replace(problem, contacts=contacts)
    print(f"{'body':>4} {'dofs':>8} {'m_b':>6} {'L entries':>10} {'L GB':>6} {'stack GB':>8} {'front GB':>8} "
          f"{'root GF':>8} {'reach GF':>8} {'other GF':>8} {'block GB':>8} {'range GB':>8}")
    for g, f in body_factors(problem):
        root, reach, other = flops(f)
        ptr = f.factor_ptr
        largest_block = int(np.diff(ptr[:f.n_supernodes]).max(initial=0))
        largest_range = max((int(ptr[s1] - ptr[s0]) for s0, s1 in f._chunk_bounds()), default=0)
        print(f"{g:4d} {f.n:8d} {f.m:6d} {f.nnz:10.3g} {f.factor_bytes / 2**30:6.2f} {f.stack_bytes / 2**30:8.2f} "
              f"{f.front_bytes / 2**30:8.2f} {root / 1e9:8.0f} {reach / 1e9:8.0f} {other / 1e9:8.0f} "
              f"{8 * largest_block / 2**30:8.2f} {8 * largest_range / 2**30:8.2f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
