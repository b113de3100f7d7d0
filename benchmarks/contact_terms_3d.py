"""One trial's contact terms of a 3D point contact, two ways on the same quadrature points, one
after the other (CPU seconds of this process; ratios are the steadier number on a shared machine):

* sparse: the jump and flux as sparse (3q x m) operators of the bodies' point operators, the
  band's stiffness and the slip zone's Coulomb block as their sparse products
  (solver.contact.ellipse.contact_operators, solver.fem.step_boundary.thin_band_terms);
* pair blocks: per-point blocks over each point's two cells, summed per cell pair and mapped onto
  the contact dofs once (solver.fem.pair_blocks, what the solver uses).

The candidate disc is set by ``--extent-fraction`` (the sized disc of a large contact), the
region's size by ``--a``; a slip zone (stick ratio 0.85, friction 0.2 along the first axis) is
switched on so that Coulomb's block is timed too. Prints the points, both times, their ratio and
the largest difference of the two stiffnesses relative to its largest entry.

    python benchmarks/contact_terms_3d.py [SCENE] [--extent-fraction 0.5] [--a 0.045] [--repeat 3]
"""

from __future__ import annotations

import argparse
import dataclasses
import time
import tomllib
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from ibfem.solver.contact import ellipse
from ibfem.solver.contact.driver import ContactDriver
from ibfem.solver.fem.step_boundary import BoundaryPoints, band_tensors, thin_band_terms
from ibfem.solver.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def _contact(path: Path, fraction: float):
    data = tomllib.loads(path.read_text())
    data["output"] = {"vtk": False, "plots": False}
    problem = load_scene(data, label=str(path), base_dir=str(path.parent)).problem
    c0 = problem.contacts[0]
    options = dataclasses.replace(c0.options, extent_fraction=fraction)
    problem = dataclasses.replace(problem, contacts=(dataclasses.replace(c0, options=options),))
    driver = ContactDriver(problem)
    driver._discretise()
    driver._assemble()
    c = driver.contacts[0]
    c.stick_ratio, c.slip_direction, c.friction = 0.85, np.array(c.frame.axes[0], float), 0.2
    return c


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene", nargs="?", default=str(ROOT / "examples/solid/full/ball_on_block_turned.toml"))
    ap.add_argument("--extent-fraction", type=float, default=0.5)
    ap.add_argument("--a", type=float, default=0.045, help="the region's first semi-axis (m)")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    c = _contact(Path(args.scene), args.extent_fraction)
    a = args.a
    pts = c.region_quadrature(a)
    proj = ellipse._projector(c, pts, a)
    wq = np.where(ellipse._slip_mask(c, pts, a), pts.weights, 0.0)
    e = np.broadcast_to(-c.friction * c.slip_direction, pts.x1.shape)

    def sparse_route():
        jump, flux, size = ellipse.contact_operators(c, pts)
        bp = BoundaryPoints(pts.x1, pts.weights, pts.normal, size, jump, flux)
        k, f = thin_band_terms(bp, proj, -pts.delta, c.b1.lam, c.b1.mu, c.band_fraction, 1.0, jump=jump)
        r, b = ellipse.pressure_rows(c, (pts, bp, proj, jump, flux, size, a))
        g = ellipse.point_blocks(e) @ jump
        return (sp.csr_matrix(k) - g.T @ sp.csr_matrix(r.multiply(wq[:, None]))).tocsr()

    def block_route():
        blocks, size = ellipse.contact_blocks(c, pts)
        bp = BoundaryPoints(pts.x1, pts.weights, pts.normal, size, blocks.jump, blocks.flux)
        k, _ = blocks.band_terms(*band_tensors(bp, proj, c.b1.lam, c.b1.mu, c.band_fraction), -pts.delta, 1.0)
        nl, npf, _ = ellipse._pressure_coefficients(c, pts, proj, size)
        return (k - blocks.outer(blocks.rows(e), blocks.rows(-nl, npf), wq)).tocsr()

    print(f"{len(pts.s)} quadrature points, {int((wq > 0).sum())} in the slip zone, {len(c.dofs)} contact dofs")
    for _ in range(args.repeat):
        t0 = time.process_time()
        k_sparse = sparse_route()
        t1 = time.process_time()
        k_blocks = block_route()
        t2 = time.process_time()
        diff = abs(k_sparse - k_blocks).max() / abs(k_sparse).max()
        print(f"sparse {t1 - t0:.3f} s  pair blocks {t2 - t1:.3f} s  ratio {(t2 - t1) / (t1 - t0):.2f}  "
              f"difference {diff:.1e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
