"""What the contact Schur complement would cost from iterative block solves instead of the direct
factor of K0: one body of a full-model scene (examples/solid/full), its contact dofs c and the
rest i. The condensed path reads S = K_cc - K_ci K_ii^-1 K_ic and G = S^-1 off one multifrontal
factorisation; the iterative alternative needs K_ii^-1 K_ic, one solve per contact dof, here by
conjugate gradients preconditioned by smoothed-aggregation AMG (pyamg, the rigid-body modes as
near-null space, the set-up of the linear solver's solver.fem.linalg.amg_cg_solve) to a relative
residual of 1e-8. Prints the CPU time of the AMG set-up, of a sample of column solves (their
mean times the body's contact dofs: the time to form S by solves) and of the direct condensed
factorisation of the same body.

    python benchmarks/schur_by_amg.py [--scene ball_on_block] [--levels 3] [--body 1] [--columns 8]
"""

from __future__ import annotations

import argparse
import time
import tomllib
from pathlib import Path

import numpy as np
import scipy.sparse as sp

ROOT = Path(__file__).resolve().parent.parent


def body_blocks(scene: str, levels: int, body: int):
    """(K of the body with its essential terms, its contact dofs in body numbering, the body)."""
    from ibfem.solver.contact.driver import ContactDriver
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.model.resolve import resolve_problem

    path = ROOT / "examples" / "solid" / "full" / f"{scene}.toml"
    data = tomllib.loads(path.read_text())
    data["output"] = {"vtk": False, "plots": False}
    for b in data["bodies"]:
        for zone in b.get("refinement", []):
            zone["levels"] = levels
    problem = resolve_problem(load_scene(data, label=path.name, base_dir=path.parent).problem)
    driver = ContactDriver(problem)
    driver._discretise()
    driver._assemble()
    b = driver.bodies[body]
    own = np.arange(b.dof_offset, b.dof_offset + b.n_dofs)
    dofs = np.unique(np.concatenate([c.dofs for c in driver.contacts]))
    contact = dofs[(dofs >= own[0]) & (dofs <= own[-1])] - b.dof_offset
    modes = _rigid_modes(b)
    return driver.k0[own][:, own].tocsr(), contact, modes


def _rigid_modes(body) -> np.ndarray:
    """(n_dofs, 6): the body's three translations and three rotations about its centroid."""
    nodes = body.grid.nodes[body.grid.free_nodes]
    rel = nodes - nodes.mean(axis=0)
    cols = [np.tile(np.eye(3)[k], len(nodes)) for k in range(3)]
    for i, j in ((0, 1), (0, 2), (1, 2)):
        rot = np.zeros_like(rel)
        rot[:, i], rot[:, j] = -rel[:, j], rel[:, i]
        cols.append(rot.ravel() / np.abs(rot).max())
    return np.stack(cols, axis=1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="ball_on_block")
    ap.add_argument("--levels", type=int, default=3)
    ap.add_argument("--body", type=int, default=1)
    ap.add_argument("--columns", type=int, default=8)
    args = ap.parse_args(argv)
    import pyamg

    from ibfem.solver.fem.linalg import metis_order
    from ibfem.solver.fem.multifrontal import condensed_cholesky

    k, contact, modes = body_blocks(args.scene, args.levels, args.body)
    n, m = k.shape[0], len(contact)
    inner = np.ones(n, dtype=bool)
    inner[contact] = False
    ii = np.flatnonzero(inner)
    k_ii, k_ic = k[ii][:, ii].tocsr(), k[ii][:, contact].tocsc()
    print(f"{args.scene}, {args.levels} levels, body {args.body}: {n} dofs, {m} contact dofs")
    t = time.process_time()
    scale = 1.0 / np.sqrt(np.abs(k_ii.diagonal()))
    a = (sp.diags(scale) @ k_ii @ sp.diags(scale)).tocsr()
    ml = pyamg.smoothed_aggregation_solver(
        a, B=modes[ii] / scale[:, None], symmetry="symmetric", max_coarse=500,
        strength=("symmetric", {"theta": 0.0}), smooth=("jacobi", {"omega": 4.0 / 3.0, "weighting": "local"}))
    print(f"AMG set-up: {time.process_time() - t:.2f} s CPU, {len(ml.levels)} levels")
    coupled = np.flatnonzero(np.diff(k_ic.indptr) > 0)  # contact dofs with a nonzero column
    rng = np.random.default_rng(0)
    times, iterations = [], []
    for j in rng.choice(coupled, min(args.columns, len(coupled)), replace=False):
        rhs = scale * k_ic[:, j].toarray().ravel()
        residuals: list[float] = []
        t = time.process_time()
        ml.solve(rhs, tol=1e-8, accel="cg", maxiter=500, residuals=residuals)
        times.append(time.process_time() - t)
        iterations.append(len(residuals) - 1)
    per_column = float(np.mean(times))
    print(f"one column of K_ii^-1 K_ic: {per_column:.3f} s CPU (mean of {len(times)}), "
          f"CG iterations {min(iterations)}-{max(iterations)}")
    print(f"S by solves: {len(coupled)} columns x {per_column:.3f} s = {len(coupled) * per_column:.0f} s CPU")
    t = time.process_time()
    order = metis_order(k, 3)
    is_contact = np.zeros(n, dtype=bool)
    is_contact[contact] = True
    condensed_cholesky(k, np.concatenate([order[~is_contact[order]], contact]), m)
    print(f"direct condensed factorisation (S and G): {time.process_time() - t:.1f} s CPU")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
