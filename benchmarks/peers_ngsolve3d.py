"""The NGSolve side of the 3D peer study (benchmarks/peers.py --problem sphere3d): one run,
one process.

examples/solid/sphere_on_flat.toml as NGSolve sees it: a quarter of the lower half ball R = 1
centred (0, 0, 1) (x >= 0, y >= 0) on the block [0, 1] x [0, 1] x [-1, 0], steel on steel (E 2e11,
nu 0.3), the block's bottom fixed, the ball's flat top at z = 1 moved by (0, 0, -0.002), the x = 0
and y = 0 faces of both bodies sliding (the normal displacement zero), frictionless contact.

Curved P2 tetrahedra (``mesh.Curve(order)``, ``VectorH1``) on a mesh graded to h_c on both contact
surfaces within ``--zone`` of the contact point (and at the depth of that zone below it: the Hertz
field decays over a few a), the contact by NGSolve's ``ContactBoundary`` with the penalty energy
``k/2 cf^2`` where cf > 0, as the 2D model (benchmarks/peers_ngsolve.py) does. The pairing: master
the ball's dome, each point paired with the closest point of the block's flat top, i.e. the point
straight below it, and the penetration taken along the contact frame's normal,
``cf = (u - u.Other() + X - X.Other()) . (0, 0, -1)``. That is the small-strain gap Hertz's theory
uses (the initial separation of points at the same (x, y), measured along z) and the one the 2D
references use; pairing the block's points radially with their closest dome points shifts the
converged a by about +0.4 % in 2D (docs/peers.md). The pairs are found once on the undeformed
geometry (small strain). Solved by Newton (the active set by ``IfPos``) with a sparse Cholesky
factorisation per step, with penalty continuation k/1000, k/100, k/10, k (k = penalty E / h_c).

The bodies touch at one point, which a mesher would merge into a shared node (a tie): the ball is
meshed lifted by ``LIFT`` (1e-5 m) and its top moved by 0.002 + LIFT, the same deformed state by a
rigid translation of the ball (no strain changes).

Measured (as ibfem's ``semi_axes``): a is the radius on the block's top where the
gap closes, along radial lines at 15, 45 and 75 degrees from x, two ways, as in 2D: ``a_closing``,
the outermost closing of cf along each line (sampled every h_c / 40, interpolated linearly), and
``a``, the root of a quadratic fitted to g^(2/3) just outside (``peers_ngsolve.opening_fit``); both
the mean of the lines. N is the quarter's normal force: the reaction of the ball's flat top,
a(u, phi) with phi = (0, 0, 1) on that face's dofs (the block bottom's reaction agrees to
round-off).

    python benchmarks/peers_ngsolve3d.py --hc 0.004 [--hmax 0.2 --zone 0.12]

prints one JSON line (dofs, a, N, Newton iterations, timings). Needs the ``peers`` extra
(``pip install 'ibfem[peers]'``, ngsolve).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

from peers_ngsolve import _import_ngsolve, elasticity, newton, opening_fit, support_reactions

LIFT = 1e-5          # the ball is meshed this far above the block (m)
DISPLACEMENT = 0.002
R = 1.0
ANGLES_DEG = (15.0, 45.0, 75.0)   # the radial lines along which a is measured


def zone_points(hc: float, zone: float):
    """Points every h_c / 2 on the block's top within ``zone`` of the contact point (x, y >= 0)."""
    import numpy as np

    s = np.arange(0.0, zone + 0.25 * hc, 0.5 * hc)
    x, y = np.meshgrid(s, s, indexing="ij")
    keep = x * x + y * y <= zone * zone
    return x[keep], y[keep]


def build_mesh(hc: float, hmax: float, zone: float, grading: float, order: int, depth: float | None = None,
               lift: float = LIFT):
    """Block and lifted quarter ball, h_c on both contact surfaces within ``zone``, and below them
    (to ``depth``, default ``zone``) h growing like half the depth."""
    import numpy as np
    from netgen import occ
    from netgen.meshing import MeshingParameters
    from ngsolve import Mesh

    block = occ.Box(occ.Pnt(0.0, 0.0, -1.0), occ.Pnt(1.0, 1.0, 0.0))
    block.faces.name = "block_side"
    block.faces.Min(occ.Z).name = "bottom"
    block.faces.Max(occ.Z).name = "top"
    block.faces.Min(occ.X).name = "block_x0"
    block.faces.Min(occ.Y).name = "block_y0"
    block.solids.name = "block"
    cz = R + lift
    ball = occ.Sphere(occ.Pnt(0.0, 0.0, cz), R) * occ.Box(occ.Pnt(0.0, 0.0, lift - 0.5), occ.Pnt(1.5, 1.5, cz))
    ball.faces.name = "dome"
    ball.faces.Max(occ.Z).name = "flat"
    ball.faces.Min(occ.X).name = "ball_x0"
    ball.faces.Min(occ.Y).name = "ball_y0"
    ball.solids.name = "ball"
    geo = occ.OCCGeometry(occ.Glue([block, ball]))
    mp = MeshingParameters(maxh=hmax, grading=grading)
    x, y = zone_points(hc, zone)
    for xi, yi in zip(x.tolist(), y.tolist()):
        r2 = xi * xi + yi * yi
        mp.RestrictH(x=xi, y=yi, z=0.0, h=hc)
        mp.RestrictH(x=xi, y=yi, z=cz - math.sqrt(R * R - r2), h=hc)
    for d in np.arange(hc, zone if depth is None else depth, 2.0 * hc):   # below: h grows like the depth
        h = max(hc, 0.5 * d)
        for xi in np.arange(0.0, zone, h):
            for yi in np.arange(0.0, zone, h):
                if xi * xi + yi * yi + d * d <= zone * zone:
                    mp.RestrictH(x=float(xi), y=float(yi), z=-float(d), h=float(h))
                    mp.RestrictH(x=float(xi), y=float(yi), z=cz - R + float(d), h=float(h))
    mesh = Mesh(geo.GenerateMesh(mp=mp, closeedgefac=None, minedgelen=None))
    mesh.Curve(order)
    return mesh


def space(mesh, order: int):
    """P2 vectors: the bottom and the flat top fixed in all components, the symmetry faces in
    their normal component (sliding)."""
    import ngsolve as ng

    return ng.VectorH1(mesh, order=order, dirichletx="bottom|flat|block_x0|ball_x0",
                       dirichlety="bottom|flat|block_y0|ball_y0", dirichletz="bottom|flat")


def solve(args) -> dict:
    import ngsolve as ng

    t0 = time.perf_counter()
    ng.SetNumThreads(args.threads)
    mesh = build_mesh(args.hc, args.hmax, args.zone, args.grading, args.order, args.depth, args.lift)
    t_mesh = time.perf_counter()
    fes = space(mesh, args.order)
    form, energy = elasticity(mesh, fes, {m: (args.E, args.nu) for m in set(mesh.GetMaterials())})
    a = ng.BilinearForm(fes)
    a += energy
    uT = fes.TrialFunction()
    X = ng.CoefficientFunction((ng.x, ng.y, ng.z))
    cb = ng.ContactBoundary(mesh.Boundaries("dome"), mesh.Boundaries("top"))   # dome points paired straight down
    cf = (uT - uT.Other() + X - X.Other()) * ng.CoefficientFunction((0.0, 0.0, -1.0))
    k = ng.Parameter(args.penalty * args.E / args.hc)
    cb.AddEnergy(ng.IfPos(cf, 0.5 * k * cf * cf, 0))
    gfu = ng.GridFunction(fes)
    with ng.TaskManager():
        cb.Update(gfu, a, intorder=args.intorder, maxdist=args.maxdist)   # pairs on the undeformed geometry
    gfu.Set((0.0, 0.0, -(DISPLACEMENT + args.lift)), definedon=mesh.Materials("ball"))   # the ball moved rigidly
    iterations = 0
    full = args.penalty * args.E / args.hc
    for stage in range(args.continuation, -1, -1):    # penalty continuation: soft to full
        k.Set(full / 10.0 ** stage)
        its, step = newton(a, gfu, fes, args.inverse, args.tol)
        iterations += its
    t_solve = time.perf_counter()
    out = {"order": args.order, "hc": args.hc, "hmax": args.hmax, "zone": args.zone, "dofs": fes.ndof,
           "elements": mesh.ne, "newton_iterations": iterations, "last_step": step, "penalty": args.penalty}
    out.update(measure(mesh, fes, form, gfu, args.hc, args.zone, args.lift))
    out.update(mesh_s=t_mesh - t0, solve_s=t_solve - t_mesh, measure_s=time.perf_counter() - t_solve,
               total_in_process_s=time.perf_counter() - t0)
    return out


def evaluate_z(mesh, gfu, pts, inward):
    """u_z at boundary points, each moved inward by the smallest of 1e-12 .. 1e-8 m that lies in
    the curved mesh."""
    import numpy as np

    for off in (1e-12, 1e-10, 1e-9, 1e-8):
        q = pts + off * inward
        try:
            return gfu(mesh(q[:, 0], q[:, 1], q[:, 2]))[:, 2]
        except Exception:
            continue
    out = np.empty(len(pts))
    for i in range(len(pts)):
        for off in (1e-12, 1e-10, 1e-9, 1e-8):
            q = pts[i] + off * inward[i]
            try:
                out[i] = gfu(mesh(*map(float, q)))[2]
                break
            except Exception:
                continue
        else:
            raise RuntimeError(f"point {pts[i]} not found in the curved mesh")
    return out


def gap_line(mesh, gfu, theta: float, hc: float, zone: float, lift: float = LIFT):
    """Radii and penetration cf along the block's top at angle theta from x (cf >= 0: closed)."""
    import numpy as np

    rs = np.arange(0.0, max(zone, 0.2), hc / 40.0)
    c, s = math.cos(theta), math.sin(theta)
    block = np.stack([rs * c, rs * s, np.zeros_like(rs)], axis=1)
    cz = R + lift
    zd = cz - np.sqrt(R * R - rs * rs)
    dome = np.stack([rs * c, rs * s, zd], axis=1)
    to_centre = np.stack([-dome[:, 0], -dome[:, 1], cz - zd], axis=1) / R
    ub = evaluate_z(mesh, gfu, block, np.broadcast_to([0.0, 0.0, -1.0], block.shape))
    ud = evaluate_z(mesh, gfu, dome, to_centre)
    return rs, ub - ud - zd


def measure(mesh, fes, form, gfu, hc: float, zone: float, lift: float = LIFT) -> dict:
    """a from the closing of the gap along radial lines of the block's top, N from the reactions."""
    import numpy as np

    fits, closing = [], []
    for deg in ANGLES_DEG:
        rs, cf = gap_line(mesh, gfu, math.radians(deg), hc, zone, lift)
        closed = np.nonzero(cf >= 0.0)[0]
        if len(closed) == 0 or closed[-1] + 1 >= len(rs):
            fits.append(float("nan"))
            closing.append(float("nan"))
            continue
        i = closed[-1]
        t = cf[i] / (cf[i] - cf[i + 1])
        closing.append(float(rs[i] + t * (rs[i + 1] - rs[i])))
        fits.append(opening_fit(rs, cf, closing[-1], hc))
    reaction = support_reactions(mesh, fes, form, gfu)
    reactions = {name: reaction(name, (0.0, 0.0, 1.0)) for name in ("flat", "bottom")}
    return {"a": float(np.mean(fits)), "a_lines": fits, "a_closing": float(np.mean(closing)),
            "a_closing_lines": closing, "angles_deg": list(ANGLES_DEG), "N": -reactions["flat"],
            "N_bottom": reactions["bottom"]}


def parse(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hc", type=float, default=0.004, help="element size on the contact surfaces (m)")
    ap.add_argument("--hmax", type=float, default=0.2, help="largest element size (m)")
    ap.add_argument("--zone", type=float, default=0.12, help="radius of the fine zone about the contact point (m)")
    ap.add_argument("--depth", type=float, default=None, help="depth of the graded zone below the surfaces "
                    "(m; default --zone, 0: the surfaces only)")
    ap.add_argument("--grading", type=float, default=0.3)
    ap.add_argument("--lift", type=float, default=LIFT, help="the ball is meshed this far above the block (m)")
    ap.add_argument("--order", type=int, default=2)
    ap.add_argument("--penalty", type=float, default=1e3, help="k = penalty E / h_c")
    ap.add_argument("--continuation", type=int, default=3, help="penalty stages below the full one (x10 each)")
    ap.add_argument("--intorder", type=int, default=0, help="0: 2 order + 4")
    ap.add_argument("--maxdist", type=float, default=0.05)
    ap.add_argument("--inverse", default="sparsecholesky")
    ap.add_argument("--tol", type=float, default=1e-10)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--E", type=float, default=2.0e11, help="Young's modulus of both bodies (Pa)")
    ap.add_argument("--nu", type=float, default=0.3, help="Poisson's ratio of both bodies")
    args = ap.parse_args(argv)
    if args.intorder == 0:
        args.intorder = 2 * args.order + 4
    for name in ("hc", "hmax", "zone", "E"):
        if not getattr(args, name) > 0.0:
            ap.error(f"--{name} must be positive (got {getattr(args, name)})")
    return args


def main(argv: list[str]) -> int:
    args = parse(argv)
    _import_ngsolve()
    print(json.dumps(solve(args)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
