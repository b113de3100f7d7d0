"""Speed of the multifrontal Cholesky's dense kernel (solver.fem._multifrontal_kernels._partial_ldlt:
the partial L D L^T of one front) on one core, in GFlop/s, beside numpy's dgemm on the same core.

Each front is a random symmetric positive definite matrix of F rows whose first NC columns are
factored (the update matrix of the other rows left behind); flops are counted as 2 sum_k
(F - k - 1)(F - k) / 2 over the NC pivots. CPU time (``time.process_time``), the best of
``--repeat`` runs, one BLAS thread.

    python benchmarks/multifrontal_kernels.py [--fronts 4000:2000 4000:4000 3000:1000 2000:2000] [--repeat 3]

``--kernels PATH`` times the kernels module of another checkout instead (a copy of an earlier
``solver/fem/_multifrontal_kernels.py``; called without the BLAS argument when it takes none)."""

from __future__ import annotations

import argparse
import importlib.util
import inspect
import sys
import time

import numpy as np


def load_kernels(path: str | None):
    if path is None:
        from ibfem.solver.fem import _multifrontal_kernels

        return _multifrontal_kernels
    spec = importlib.util.spec_from_file_location("kernels_under_test", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def partial_ldlt(kern):
    takes_blas = "gemm" in inspect.signature(kern._partial_ldlt.py_func).parameters
    if takes_blas:
        return lambda t, nc, f: kern._partial_ldlt(kern.DGEMM, t, nc, f, True)
    return lambda t, nc, f: kern._partial_ldlt(t, nc, f, True)


def time_front(factor, f: int, nc: int, repeat: int) -> float:
    rng = np.random.default_rng(f + nc)
    a = rng.standard_normal((f, f))
    s = a @ a.T + f * np.eye(f)
    best = np.inf
    for _ in range(repeat):
        t = s.copy()
        c = time.process_time()
        if factor(t, nc, f) != -1:
            raise RuntimeError("a pivot failed on a positive definite front")
        best = min(best, time.process_time() - c)
    flops = 2.0 * sum((f - k - 1) * (f - k) / 2.0 for k in range(nc))
    return flops / best / 1e9


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fronts", nargs="+", default=["4000:2000", "4000:4000", "3000:1000", "2000:2000"],
                    help="F:NC, front rows and pivot columns")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--kernels", default=None, help="path of another _multifrontal_kernels.py to time")
    args = ap.parse_args(argv)
    from ibfem.solver.fem.linalg import single_threaded_blas

    factor = partial_ldlt(load_kernels(args.kernels))
    with single_threaded_blas():
        factor(np.eye(300) * 2.0, 100, 300)  # compile or load the kernels
        a = np.random.default_rng(0).standard_normal((3000, 3000))
        c = time.process_time()
        _ = a @ a
        print(f"numpy dgemm 3000 x 3000, one thread: {2 * 3000**3 / (time.process_time() - c) / 1e9:.1f} GFlop/s")
        print(f"{'front rows':>10} {'pivots':>7} {'GFlop/s':>8}")
        for spec in args.fronts:
            f, nc = (int(v) for v in spec.split(":"))
            print(f"{f:10d} {nc:7d} {time_front(factor, f, nc, args.repeat):8.1f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
