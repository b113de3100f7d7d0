"""Solves with a multifrontal factor held on disk: its ranges mapped into memory (what the solver
does) against read into new arrays (what it falls back to where a file cannot be mapped), on the
trilinear-grid stiffness of an n x n x n block of nodes (3 dofs each) with its top face's dofs as
the root. Alternates the two ``--repeat`` times and prints each solve's wall and CPU time; both
give the same solution (checked to round-off).

    python benchmarks/factor_on_disk.py [--nodes 30] [--repeat 3]
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from unittest import mock

import numpy as np
import scipy.sparse as sp

from ibfem.solver.fem import multifrontal
from ibfem.solver.fem.linalg import metis_order, single_threaded_blas


def grid_stiffness(n: int) -> sp.csr_matrix:
    """SPD with the sparsity of a trilinear grid: the 27-point stencil, a node's 3 dofs coupled."""
    one_d = sp.diags([np.ones(n - 1), 4 * np.ones(n), np.ones(n - 1)], [-1, 0, 1])
    stencil = sp.kron(sp.kron(one_d, one_d), one_d)
    return sp.kron(stencil, np.eye(3) + 0.4 * (np.ones((3, 3)) - np.eye(3))).tocsr()


def timed(factor, f: np.ndarray) -> tuple[np.ndarray, float, float]:
    wall, cpu = time.perf_counter(), time.process_time()
    u = factor.solve(f)
    return u, time.perf_counter() - wall, time.process_time() - cpu


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nodes", type=int, default=30, help="nodes along each side of the block")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    k = grid_stiffness(args.nodes)
    top = np.arange(k.shape[0] - 3 * args.nodes**2, k.shape[0])
    order = metis_order(k, 3)
    order = np.concatenate([order[~np.isin(order, top)], top])
    with single_threaded_blas():
        factor = multifrontal.CholeskyFactor(k, order, len(top), keep_schur=False, on_disk=True)
    print(f"{k.shape[0]} dofs, factor {factor.factor_bytes / 2**30:.2f} GB on disk in {len(factor._chunks)} ranges")
    f = np.random.default_rng(0).standard_normal(k.shape[0])
    reference = None

    def unmappable(*_args, **_kwargs):
        raise OSError("reading instead of mapping")

    for _ in range(args.repeat):
        for how in ("mapped", "read"):
            with mock.patch.object(multifrontal.mmap, "mmap", unmappable) if how == "read" else contextlib.nullcontext():
                u, wall, cpu = timed(factor, f)
            reference = u if reference is None else reference
            diff = np.abs(u - reference).max() / np.abs(reference).max()
            print(f"{how:7} solve {wall:6.3f} s wall {cpu:6.3f} s CPU  (differs by {diff:.1e})", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
