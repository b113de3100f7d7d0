"""Converged reference of the ball on a block (examples/solid/sphere_on_flat.toml) by an independent
code: NGSolve on curved tetrahedral meshes fitted to the bodies, the same finite bodies, supports and
prescribed displacement as the scene.

The scene: a quarter of the lower half ball R = 1 centred (0, 0, 1) (x >= 0, y >= 0) on the block
[0, 1] x [0, 1] x [-1, 0], steel on steel (E 2e11, nu 0.3), the block's bottom fixed, the ball's
flat top at z = 1 moved by (0, 0, -0.002), the x = 0 and y = 0 faces of both bodies sliding,
frictionless contact. The ball is meshed LIFT above the block and its top moved by 0.002 + LIFT (a
rigid translation: the same deformed state; touching bodies would share a node).

The mesh (``build_mesh``): h_c on both contact surfaces within ``1.6 a`` of the contact point, h
growing like ``slope`` times the distance beyond that and below the surfaces (the Hertz field
decays over a few a), h_max far away; every size of a mesh is its level's h_c times a fixed
factor, so a ladder of meshes (h_c halved per rung) refines the contact, the field below it and
the far field together. Curved elements of the space's order (``mesh.Curve(order)``).

Contact: NGSolve's ``ContactBoundary`` with the penalty energy k/2 g^2 where the bodies overlap,
master the ball's dome, each point paired with the point of the block's top straight below it
(the closest point of the flat): the gap along the contact frame's normal between points at the
same (x, y) on the undeformed geometry, the pairing ibfem solves (docs/accuracy.md). k = penalty E
/ h_c; Newton with the penalty raised tenfold per stage (benchmarks/peers_ngsolve.py). A finite
penalty lets the bodies overlap by p / k and lowers N at a fixed displacement: each mesh is solved
at two penalties and N and a are extrapolated linearly in 1 / k to the exact contact (the
difference between the two is printed).

Read on each mesh: N, the quarter's normal force (the reaction of the ball's flat top; the block's
bottom agrees to round-off), and a, the radius on the block's top where the gap closes, from the
gap just outside the region: g^(2/3) is smooth through an incomplete contact's end (g ~ (r -
a)^(3/2)), and the root of a quadratic fitted to it over [a_c + 2 h_c, a_c + 2 h_c + 0.1 a_c]
(``peers_ngsolve.opening_fit``; a_c where the penalty gap closes) on each of ``--lines`` radial
lines between 5 and 85 degrees from x, their mean (the lines' spread is printed: the mesh is not
symmetric about the lines).

    .venv/bin/python benchmarks/accuracy_reference_3d.py --hc 0.016 --meshes 3 --order 2
    .venv/bin/python benchmarks/accuracy_reference_3d.py --hc 0.016 --one --order 3   # one mesh

Prints one JSON line per mesh and the Richardson lines (observed order and limit of N and a from
the last three meshes). Needs ngsolve (the ``peers`` extra).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

LIFT = 1e-5                 # the ball is meshed this far above the block (m)
DISPLACEMENT = 0.002        # the ball's top moved down (m)
R = 1.0                     # the ball's radius (m)
E, NU = 2.0e11, 0.3         # steel, both bodies
A_EST = 0.0454              # the contact radius about which the mesh is graded (m)


def build_mesh(hc: float, hmax: float, slope: float, order: int, lift: float = LIFT):
    """Block and lifted quarter ball; h_c on both contact surfaces within 1.6 A_EST of the contact
    point, h = h_c + slope (rho - 1.6 A_EST) beyond (rho: the distance from the contact point, on
    the surfaces and inside both bodies), at most hmax."""
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
    mp = MeshingParameters(maxh=hmax, grading=0.3)
    rc = 1.6 * A_EST
    for x, y in _disc_points(rc, 0.5 * hc):                      # the contact surfaces: h_c
        mp.RestrictH(x=x, y=y, z=0.0, h=hc)
        mp.RestrictH(x=x, y=y, z=cz - math.sqrt(R * R - x * x - y * y), h=hc)
    rho = rc
    while True:                                                  # shells about the contact point
        h = hc + slope * (rho - rc)
        if h >= hmax or rho > 0.9:
            break
        for p in _shell_points(rho, 0.5 * h):
            for z in (-p[2], cz - R + p[2]):                     # below the block's top, above the dome's bottom
                mp.RestrictH(x=p[0], y=p[1], z=z, h=h)
        rho += 0.5 * h
    mesh = Mesh(geo.GenerateMesh(mp=mp, closeedgefac=None, minedgelen=None))
    mesh.Curve(order)
    return mesh


def _disc_points(radius: float, step: float):
    s = np.arange(0.0, radius + 0.5 * step, step)
    x, y = np.meshgrid(s, s, indexing="ij")
    keep = x * x + y * y <= radius * radius
    return list(zip(x[keep].tolist(), y[keep].tolist()))


def _shell_points(rho: float, step: float):
    """Points about ``step`` apart on the eighth of the sphere of radius rho with x, y, z >= 0."""
    n = max(2, int(math.ceil(0.5 * math.pi * rho / step)))
    out = []
    for i in range(n + 1):
        th = 0.5 * math.pi * i / n                               # from the vertical
        m = max(1, int(math.ceil(0.5 * math.pi * rho * math.sin(th) / step)))
        for j in range(m + 1):
            ph = 0.5 * math.pi * j / m
            out.append((rho * math.sin(th) * math.cos(ph), rho * math.sin(th) * math.sin(ph), rho * math.cos(th)))
    return out


def solve(hc: float, hmax: float, slope: float, order: int, penalties: tuple[float, ...], lines: int,
          threads: int = 2, lift: float = LIFT) -> dict:
    """One mesh, solved at each penalty in turn (continuation from k/1000); N and a at each."""
    import ngsolve as ng
    from peers_ngsolve import elasticity

    t0 = time.perf_counter()
    ng.SetNumThreads(threads)
    mesh = build_mesh(hc, hmax, slope, order, lift)
    fes = ng.VectorH1(mesh, order=order, dirichletx="bottom|flat|block_x0|ball_x0",
                      dirichlety="bottom|flat|block_y0|ball_y0", dirichletz="bottom|flat")
    form, energy = elasticity(mesh, fes, {"block": (E, NU), "ball": (E, NU)})
    bf = ng.BilinearForm(fes)
    bf += energy
    uT = fes.TrialFunction()
    X = ng.CoefficientFunction((ng.x, ng.y, ng.z))
    cb = ng.ContactBoundary(mesh.Boundaries("dome"), mesh.Boundaries("top"))
    pen = (uT - uT.Other() + X - X.Other()) * ng.CoefficientFunction((0.0, 0.0, -1.0))
    k = ng.Parameter(1.0)
    cb.AddEnergy(ng.IfPos(pen, 0.5 * k * pen * pen, 0))
    gfu = ng.GridFunction(fes)
    with ng.TaskManager():
        cb.Update(gfu, bf, intorder=2 * order + 4, maxdist=0.05)
    gfu.Set((0.0, 0.0, -(DISPLACEMENT + lift)), definedon=mesh.Materials("ball"))
    t_mesh = time.perf_counter()
    row = {"order": order, "hc": hc, "hmax": hmax, "slope": slope, "dofs": fes.ndof, "elements": mesh.ne,
           "mesh_s": t_mesh - t0, "readings": []}
    its = 0
    stages = [max(penalties) / 10.0 ** s for s in (3, 2, 1)]
    for penalty in sorted(set(stages) | set(penalties)):
        k.Set(penalty * E / hc)
        n = newton(bf, gfu, fes)
        its += n
        if penalty in penalties:
            reading = {"penalty": penalty, **measure(mesh, fes, form, gfu, hc, lines, lift)}
            row["readings"].append(reading)
    row.update(newton=its, solve_s=time.perf_counter() - t_mesh)
    row.update(extrapolated(row["readings"]))
    return row


def extrapolated(readings: list[dict]) -> dict:
    """N and a extrapolated linearly in 1 / penalty from the two largest penalties (the overlap p / k
    is proportional to 1 / k); the last reading alone if there is one."""
    last = readings[-1]
    if len(readings) < 2:
        return {"N": last["N"], "a": last["a"], "a_spread": last["a_spread"], "penalty_shift_N": math.nan}
    r1, r2 = readings[-2], readings[-1]
    w = r1["penalty"] / (r2["penalty"] - r1["penalty"])   # f(inf) = f2 + (f2 - f1) k1 / (k2 - k1)
    return {"N": r2["N"] + w * (r2["N"] - r1["N"]), "a": r2["a"] + w * (r2["a"] - r1["a"]),
            "a_spread": r2["a_spread"], "penalty_shift_N": (r2["N"] - r1["N"]) / r2["N"]}


def newton(bf, gfu, fes, tol: float = 1e-11, max_iterations: int = 80) -> int:
    """Newton on the penalty energy with a backtracking line search on the energy (the active set
    of a semismooth Newton step can cycle on a fine contact mesh); stops when the step is
    round-off."""
    import ngsolve as ng

    free = fes.FreeDofs()
    r, du, trial = gfu.vec.CreateVector(), gfu.vec.CreateVector(), gfu.vec.CreateVector()
    scale = ng.Norm(gfu.vec)
    for it in range(1, max_iterations + 1):
        with ng.TaskManager():
            bf.Apply(gfu.vec, r)
            bf.AssembleLinearization(gfu.vec)
            du.data = bf.mat.Inverse(free, inverse="sparsecholesky") * r
        energy = bf.Energy(gfu.vec)
        t = 1.0
        while True:
            trial.data = gfu.vec - t * du
            if bf.Energy(trial) <= energy or t < 1e-3:
                break
            t *= 0.5
        gfu.vec.data = trial
        step = t * ng.Norm(du) / scale
        if step < tol:
            return it
    raise RuntimeError(f"Newton did not converge in {max_iterations} iterations (last step {step:.3g})")


def measure(mesh, fes, form, gfu, hc: float, lines: int, lift: float) -> dict:
    """N from the reactions; a, the mean over ``lines`` radial lines of the fitted opening's root."""
    from peers_ngsolve import opening_fit, support_reactions
    from peers_ngsolve3d import evaluate_z

    rs = np.arange(0.5 * A_EST, 1.3 * A_EST + 3.0 * hc, hc / 40.0)
    cz = R + lift
    zd = cz - np.sqrt(R * R - rs * rs)
    fits, closing = [], []
    for deg in np.linspace(5.0, 85.0, lines):
        c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        block = np.stack([rs * c, rs * s, np.zeros_like(rs)], axis=1)
        dome = np.stack([rs * c, rs * s, zd], axis=1)
        to_centre = np.stack([-dome[:, 0], -dome[:, 1], cz - zd], axis=1) / R
        cf = evaluate_z(mesh, gfu, block, np.broadcast_to([0.0, 0.0, -1.0], block.shape)) \
            - evaluate_z(mesh, gfu, dome, to_centre) - zd
        closed = np.nonzero(cf >= 0.0)[0]
        if len(closed) == 0 or closed[-1] + 1 >= len(rs):
            raise RuntimeError(f"no closing point on the line at {deg:.1f} degrees")
        i = closed[-1]
        closing.append(float(rs[i] + cf[i] / (cf[i] - cf[i + 1]) * (rs[i + 1] - rs[i])))
        fits.append(opening_fit(rs, cf, closing[-1], hc))
    reaction = support_reactions(mesh, fes, form, gfu)
    fits = np.asarray(fits)
    return {"N": -reaction("flat", (0.0, 0.0, 1.0)), "N_bottom": reaction("bottom", (0.0, 0.0, 1.0)),
            "a": float(np.mean(fits)), "a_spread": float(np.std(fits) / np.sqrt(len(fits))),
            "a_closing": float(np.mean(closing))}


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hc", type=float, default=0.016, help="h_c of the coarsest mesh (m)")
    ap.add_argument("--hmax", type=float, default=0.2, help="largest element size of the coarsest mesh (m)")
    ap.add_argument("--slope", type=float, default=0.5, help="growth of h with the distance from the contact "
                    "zone on the coarsest mesh (divided by the ratio per mesh with every other size)")
    ap.add_argument("--meshes", type=int, default=3)
    ap.add_argument("--ratio", type=float, default=math.sqrt(2.0), help="every size divided by this per mesh")
    ap.add_argument("--first", type=int, default=0, help="start the ladder at this mesh (sizes / ratio^first)")
    ap.add_argument("--order", type=int, default=2)
    ap.add_argument("--penalty", type=float, nargs="+", default=[1e3, 1e4], help="k = penalty E / h_c")
    ap.add_argument("--lines", type=int, default=17, help="radial lines along which a is read")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--one", action="store_true", help="solve the mesh of --hc alone in this process")
    args = ap.parse_args(argv)
    try:
        import ngsolve  # noqa: F401
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise SystemExit(f"accuracy_reference_3d.py needs ngsolve: pip install 'ibfem[peers]' ({exc})")
    if args.one:
        row = solve(args.hc, args.hmax, args.slope, args.order, tuple(args.penalty), args.lines, args.threads)
        print(json.dumps(row), flush=True)
        return 0
    from accuracy_reference_2d import print_richardson, run_meshes

    scales = [args.ratio ** m for m in range(args.first, args.first + args.meshes)]
    rows = run_meshes([[sys.executable, __file__, "--one", "--hc", repr(args.hc / scale), "--hmax",
                        repr(args.hmax / scale), "--slope", repr(args.slope / scale), "--order", str(args.order),
                        "--lines", str(args.lines), "--threads", str(args.threads), "--penalty",
                        *map(repr, args.penalty)] for scale in scales])
    print_richardson(rows, ("N", "a"), args.ratio)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
