"""The NGSolve side of the peer study (benchmarks/peers.py): one run, one process.

Lower half disc R = 1 centred (0, 1) on the block [-2, 2] x [-2, 0], plane strain, the block's
bottom fixed, the disc's flat top moved by (0, -0.0107), frictionless contact. Curved P2/P3
elements (``mesh.Curve(order)``) on a mesh graded to h_c along the contact, the contact by
NGSolve's ``ContactBoundary`` with a penalty energy ``k/2 cf^2`` where cf > 0 as in NGSolve's own
contact tests and tutorial, the penetration ``cf = (u - u.Other() + X - X.Other()) . n``:

- ``--pairing vertical`` (default): master the disc's arc, whose points are paired with the block
  point straight below them, n = (0, -1): the small-strain gap along the contact frame's normal;
- ``--pairing radial``: master the block's top, paired with the closest point of the arc (along
  the radius), n the block's normal (0, 1). The pairing shifts the converged a by +0.39 %
  (docs/peers.md).

The pairs are found once on the undeformed geometry (small strain, as ibfem pairs them). Solved by
Newton (semismooth: the active set by ``IfPos``) with a sparse Cholesky factorisation per step,
with penalty continuation k/1000, k/100, k/10, k (k = penalty E_block / h_c).

The two bodies touch at one point, which a mesher would merge into a shared node (a tie): the disc
is meshed lifted by ``LIFT`` (1e-5 m) and its top moved down by 0.0107 + LIFT, the same deformed
state by a rigid translation of the disc (no strain changes).

Measured (as ibfem reports ``half_width``): a is the x-coordinate on the block's top where the gap closes, two ways:
``a_closing``, the outermost closing of cf along |x| (sampled every h_c / 40, interpolated
linearly), and ``a``, the root of a quadratic fitted to g^(2/3) just outside (g ~ (x - a)^1.5 at a
contact edge; see :func:`opening_fit`); both the mean of the two sides. N is the reaction of the
disc's flat top, a(u, phi) with phi = (0, 1) on that edge's dofs (the block bottom's reaction
agrees to round-off).

    python benchmarks/peers_ngsolve.py --hc 0.002 --order 2 [--disc-E 7e10 --disc-nu 0.33]

prints one JSON line (dofs, a, N, Newton iterations, timings). Needs the ``peers`` extra
(``pip install 'ibfem[peers]'``, ngsolve).
"""

from __future__ import annotations

import argparse
import json
import sys
import time

LIFT = 1e-5          # the disc is meshed this far above the block (m)
DISPLACEMENT = 0.0107
R = 1.0
DEBUG = False


def _import_ngsolve():
    try:
        import ngsolve  # noqa: F401
        from netgen import occ  # noqa: F401
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise SystemExit(f"peers_ngsolve.py needs ngsolve: pip install 'ibfem[peers]' ({exc})")


def build_mesh(hc: float, hmax: float, width: float, grading: float, order: int):
    """Block and lifted half disc, h_c along |x| <= width on the block's top and on the arc."""
    import numpy as np
    from netgen import occ
    from netgen.meshing import MeshingParameters
    from ngsolve import Mesh

    block = occ.MoveTo(-2.0, -2.0).Rectangle(4.0, 2.0).Face()
    block.edges.name = "block_side"
    block.edges.Min(occ.Y).name = "bottom"
    block.edges.Max(occ.Y).name = "top"
    block.faces.name = "block"
    cy = R + LIFT
    disc = occ.Circle((0.0, cy), R).Face() * occ.MoveTo(-1.5, LIFT - 0.5).Rectangle(3.0, 1.5).Face()
    disc.edges.name = "arc"
    disc.edges.Max(occ.Y).name = "flat"
    disc.faces.name = "disc"
    geo = occ.OCCGeometry(occ.Glue([block, disc]), dim=2)
    mp = MeshingParameters(maxh=hmax, grading=grading)
    for x in np.arange(-width, width + 0.5 * hc, 0.5 * hc):
        mp.RestrictH(x=float(x), y=0.0, z=0.0, h=hc)
        mp.RestrictH(x=float(x), y=float(cy - np.sqrt(R * R - x * x)), z=0.0, h=hc)
    mesh = Mesh(geo.GenerateMesh(mp=mp, closeedgefac=None, minedgelen=None))
    mesh.Curve(order)
    return mesh


def lame(E: float, nu: float) -> tuple[float, float]:
    """Plane strain: mu and lambda of the 3D law (eps_zz = 0)."""
    return E / (2.0 * (1.0 + nu)), E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))


def hooke(eps, mu, lam, dim: int):
    """sigma = 2 mu eps + lambda tr(eps) I (NGSolve coefficient functions; dim 2 or 3)."""
    import ngsolve as ng

    return 2.0 * mu * eps + lam * ng.Trace(eps) * ng.Id(dim)


def elasticity(mesh, fes, materials: dict):
    """sigma(u) : eps(v) over the bodies (``materials``: mesh material name -> (E, nu)), and the
    energy for the nonlinear form; plane strain on a 2D mesh."""
    import ngsolve as ng

    mus = {k: lame(*v)[0] for k, v in materials.items()}
    lams = {k: lame(*v)[1] for k, v in materials.items()}
    mu, lam = mesh.MaterialCF(mus), mesh.MaterialCF(lams)
    u, v = fes.TnT()
    eps_u, eps_v = ng.Sym(ng.Grad(u)), ng.Sym(ng.Grad(v))
    sigma = hooke(eps_u, mu, lam, mesh.dim)
    return ng.InnerProduct(sigma, eps_v) * ng.dx, ng.Variation(0.5 * ng.InnerProduct(sigma, eps_u) * ng.dx)


def solve(args) -> dict:
    import ngsolve as ng

    t0 = time.perf_counter()
    ng.SetNumThreads(args.threads)
    mesh = build_mesh(args.hc, args.hmax, args.width, args.grading, args.order)
    t_mesh = time.perf_counter()
    materials = {"disc": (args.disc_E, args.disc_nu), "block": (args.block_E, args.block_nu)}
    fes = ng.VectorH1(mesh, order=args.order, dirichlet="bottom|flat")
    form, energy = elasticity(mesh, fes, materials)
    a = ng.BilinearForm(fes)
    a += energy
    uT = fes.TrialFunction()
    X = ng.CoefficientFunction((ng.x, ng.y))
    if args.pairing == "vertical":     # master: the disc's arc, its points paired straight down
        cb = ng.ContactBoundary(mesh.Boundaries("arc"), mesh.Boundaries("top"))
        cf = (uT - uT.Other() + X - X.Other()) * ng.CoefficientFunction((0.0, -1.0))
    else:                              # master: the block's top, paired radially onto the arc
        cb = ng.ContactBoundary(mesh.Boundaries("top"), mesh.Boundaries("arc"))
        cf = (uT - uT.Other() + X - X.Other()) * cb.normal
    k = ng.Parameter(args.penalty * args.block_E / args.hc)
    cb.AddEnergy(ng.IfPos(cf, 0.5 * k * cf * cf, 0))
    gfu = ng.GridFunction(fes)
    with ng.TaskManager():
        cb.Update(gfu, a, intorder=args.intorder, maxdist=args.maxdist)   # pairs on the undeformed geometry
    # initial guess: the disc moved rigidly (overlapping the block; Newton's active set then shrinks)
    gfu.Set((0.0, -(DISPLACEMENT + LIFT)), definedon=mesh.Materials("disc"))
    iterations = 0
    full = args.penalty * args.block_E / args.hc
    for stage in range(args.continuation, -1, -1):    # penalty continuation: soft to full
        k.Set(full / 10.0 ** stage)
        its, step = newton(a, gfu, fes, args.inverse, args.tol)
        iterations += its
    t_solve = time.perf_counter()
    out = {"order": args.order, "hc": args.hc, "hmax": args.hmax, "dofs": fes.ndof,
           "elements": mesh.ne, "newton_iterations": iterations, "last_step": step, "penalty": args.penalty, "pairing": args.pairing}
    out.update(measure(mesh, fes, form, gfu, args.hc, args.width, args.pairing))
    out.update(mesh_s=t_mesh - t0, solve_s=t_solve - t_mesh, measure_s=time.perf_counter() - t_solve,
               total_in_process_s=time.perf_counter() - t0)
    return out


def newton(a, gfu, fes, inverse: str, tol: float) -> tuple[int, float, float]:
    """Semismooth Newton on the penalty energy (full steps): stops when the step is round-off."""
    import ngsolve as ng

    free = fes.FreeDofs()
    r = gfu.vec.CreateVector()
    du = gfu.vec.CreateVector()
    scale = ng.Norm(gfu.vec)
    for it in range(1, 61):
        with ng.TaskManager():
            a.Apply(gfu.vec, r)
            a.AssembleLinearization(gfu.vec)
            inv = a.mat.Inverse(free, inverse=inverse)
            du.data = inv * r
        gfu.vec.data -= du
        step = ng.Norm(du) / scale
        if DEBUG:
            print(it, step, file=sys.stderr)
        if step < tol:
            return it, step
    raise RuntimeError(f"Newton did not converge in {it} iterations (last step {step:.3g})")


def evaluate_y(mesh, gfu, xs, ys, inward):
    """u_y at boundary points, each moved inward by the smallest of 1e-12 .. 1e-8 m that lies in
    the curved mesh (the curved edges approximate the circle to ~h^(p+1))."""
    import numpy as np

    ix, iy = np.broadcast_to(inward[0], xs.shape), np.broadcast_to(inward[1], xs.shape)
    try:
        return gfu(mesh(xs + 1e-12 * ix, ys + 1e-12 * iy))[:, 1]
    except Exception:
        pass
    out = np.empty(len(xs))
    for i, (x, y) in enumerate(zip(xs, ys)):
        for off in (1e-12, 1e-10, 1e-9, 1e-8):
            try:
                out[i] = gfu(mesh(float(x + off * ix[i]), float(y + off * iy[i])))[1]
                break
            except Exception:
                continue
        else:
            raise RuntimeError(f"point ({x}, {y}) not found in the curved mesh")
    return out


def opening_fit(xs, cf, a_closing: float, hc: float) -> float:
    """a from the gap just outside the contact: g^(2/3) is smooth through the edge (g ~ (x - a)^1.5,
    Hertz's edge), fitted by a quadratic in x over [a_c + 2 h_c, a_c + 2 h_c + 0.1 a_c] (clear of
    the elements at the edge), its root nearest a_c."""
    import numpy as np

    lo = a_closing + 2.0 * hc
    m = (xs > lo) & (xs < lo + 0.1 * a_closing) & (cf < 0.0)
    if m.sum() < 5:
        return float("nan")
    c = np.polyfit(xs[m] - a_closing, (-cf[m]) ** (2.0 / 3.0), 2)
    roots = np.roots(c)
    roots = roots[np.isreal(roots)].real
    return float(a_closing + roots[np.argmin(np.abs(roots))]) if len(roots) else float("nan")


def support_reactions(mesh, fes, form, gfu):
    """``reaction(names, direction)``: the force the support on the boundaries ``names`` exerts
    along ``direction``, <A(u), phi> with phi the unit field along it there (A the assembled
    form at the solution u; every script here reads its reactions this way)."""
    import ngsolve as ng

    k = ng.BilinearForm(fes)
    k += form
    with ng.TaskManager():
        k.Assemble()
    r = gfu.vec.CreateVector()
    r.data = k.mat * gfu.vec

    def reaction(names: str, direction) -> float:
        phi = ng.GridFunction(fes)
        phi.Set(tuple(float(v) for v in direction), ng.BND, definedon=mesh.Boundaries(names))
        return float(ng.InnerProduct(r, phi.vec))

    return reaction


def measure(mesh, fes, form, gfu, hc: float, width: float, pairing: str) -> dict:
    """a from the closing of the gap along the block's top, N from the reactions."""
    import numpy as np

    cy = R + LIFT
    halves, closing = [], []
    for sign in (1.0, -1.0):
        xs = sign * np.arange(0.0, width, hc / 40.0)
        xb, yb = xs, np.full_like(xs, -1e-12)
        d = np.stack([xs, -cy * np.ones_like(xs)], axis=1)
        d /= np.linalg.norm(d, axis=1)[:, None]
        if pairing == "vertical":
            px, py = xs, cy - np.sqrt(R * R - xs * xs)
        else:
            px, py = d[:, 0] * R, cy + d[:, 1] * R
        ub = evaluate_y(mesh, gfu, xb, yb, (0.0, -1.0))
        ud = evaluate_y(mesh, gfu, px, py, (-d[:, 0], -d[:, 1]))
        cf = ub - ud + (0.0 - py)          # penetration along the block's normal (0, 1)
        if DEBUG:
            np.save(f"/tmp/peers_cf_{int(sign)}.npy", np.stack([xs, cf]))
        closed = np.nonzero(cf >= 0.0)[0]
        if len(closed) == 0 or closed[-1] + 1 >= len(xs):
            halves.append(float("nan"))
            closing.append(float("nan"))
            continue
        i = closed[-1]
        t = cf[i] / (cf[i] - cf[i + 1])
        closing.append(abs(xs[i] + t * (xs[i + 1] - xs[i])))
        halves.append(opening_fit(np.abs(xs), cf, closing[-1], hc))
    reaction = support_reactions(mesh, fes, form, gfu)
    reactions = {name: reaction(name, (0.0, 1.0)) for name in ("flat", "bottom")}
    return {"a": float(np.mean(halves)), "a_sides": halves, "a_closing": float(np.mean(closing)), "N": -reactions["flat"],
            "N_bottom": reactions["bottom"]}


def parse(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hc", type=float, default=0.002, help="element size along the contact (m)")
    ap.add_argument("--hmax", type=float, default=0.25, help="largest element size (m)")
    ap.add_argument("--width", type=float, default=0.12, help="half-width of the fine zone (m)")
    ap.add_argument("--grading", type=float, default=0.3)
    ap.add_argument("--order", type=int, default=2)
    ap.add_argument("--penalty", type=float, default=1e3, help="k = penalty E_block / h_c")
    ap.add_argument("--continuation", type=int, default=3, help="penalty stages below the full one (x10 each)")
    ap.add_argument("--pairing", choices=["vertical", "radial"], default="vertical",
                    help="vertical: disc points paired with the block point below (the small-strain gap along "
                         "the frame normal); radial: block points paired with their closest disc point")
    ap.add_argument("--intorder", type=int, default=0, help="0: 2 order + 4")
    ap.add_argument("--maxdist", type=float, default=0.05)
    ap.add_argument("--inverse", default="sparsecholesky")
    ap.add_argument("--tol", type=float, default=1e-10)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--disc-E", type=float, default=2.0e11)
    ap.add_argument("--disc-nu", type=float, default=0.3)
    ap.add_argument("--block-E", type=float, default=2.0e11)
    ap.add_argument("--block-nu", type=float, default=0.3)
    args = ap.parse_args(argv)
    if args.intorder == 0:
        args.intorder = 2 * args.order + 4
    return args


def main(argv: list[str]) -> int:
    args = parse(argv)
    _import_ngsolve()
    print(json.dumps(solve(args)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
