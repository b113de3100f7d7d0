"""Converged references of the rounded flat punch examples (examples/contact2d/rounded_punch.toml and
rounded_punch_half.toml) and of the pin in a bore (pin_in_bore.toml) computed by an independent
code on fitted meshes: the same finite bodies, supports and load, not the closed forms of
half-planes and of an infinite plate.

NGSolve P3 (or --order) on curved meshes of the half model (x >= 0, both symmetry lines sliding;
the full scene's punch top is held in x, which by symmetry is the half model with the top's x held
too, the half scene's top is free in x). The mesh size is h_c along both contact curves for
0 <= x <= 2 a (a from the ibfem run or --a-est) and 3 h_c over the window 2 a x 1.5 a below; the
punch is meshed LIFT above the block and moved back by its load. Frictionless penalty contact
(``ContactBoundary``: the punch's points paired with their closest points on the block's flat top,
straight down: ibfem's pairs along the contact frame's normal on the undeformed geometry), the
penalty k = penalty E / h_c, Newton with continuation (benchmarks/peers_ngsolve.py).

Measured on each mesh: N (the block's bottom reaction, doubled to the full model), a where the gap
closes and a from the fitted opening just outside (peers_ngsolve.opening_fit). Three meshes h_c,
h_c / 2, h_c / 4 give the observed order and Richardson's limit of each reading; the penalty doubled
on the finest shows the penalty's share.

The pin (``--scene pin``): the plate 20 m square with fixed edges, the pin held by a rigid hub
moved down 1 mm, meshed with h_c along both circles for |theta| <= 1.5 alpha (``--a-est``: the
contact semi-angle, rad) and 2 h_c in a ring 0.1 m wide on either side; the penalty on the gap of
ibfem's pairs (``pin_pairs``), a as the chord on the pin (solve_pin).

    .venv/bin/python benchmarks/accuracy_reference_2d.py --scene full --hc 4e-4
    .venv/bin/python benchmarks/accuracy_reference_2d.py --scene half --hc 4e-4
    .venv/bin/python benchmarks/accuracy_reference_2d.py --scene pin --hc 0.016 --a-est 1.0 --hmax 1.0

Prints one JSON line per mesh and the Richardson lines. Needs ngsolve (the ``peers`` extra).
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

LIFT = 1e-5                 # the punch is meshed this far above the block (m)
E, NU = 2.0e11, 0.3         # steel, both bodies
B = 0.01                    # the flat's half width (m)
R = 1.0                     # the edges' radius (m)
ARC_DEG = 10.0              # the arcs turn this far before the straight flanks
FLANK_END = (1.7988732094112365, 0.3)
APPROACH = 8.5e-5           # the punch top's prescribed downward displacement (m)


def punch_height(x):
    """Height of the punch's undeformed surface above the flat at |x| (flat, then the arc)."""
    s = np.maximum(np.abs(np.asarray(x, dtype=float)) - B, 0.0)
    return R - np.sqrt(R * R - s * s)


def build_mesh(a: float, hc: float, hmax: float, order: int):
    """The half model: punch (lifted) and block; edges c1 (flat and arc), c2 (block top)."""
    from netgen import occ
    from netgen.meshing import MeshingParameters
    from ngsolve import Mesh

    wp = occ.WorkPlane().MoveTo(0.0, LIFT).LineTo(B, LIFT).Arc(R, ARC_DEG)
    punch = wp.LineTo(FLANK_END[0], FLANK_END[1] + LIFT).LineTo(0.0, FLANK_END[1] + LIFT).Close().Face()
    block = occ.MoveTo(0.0, -0.6).Rectangle(0.6, 0.6).Face()
    punch.edges.name = "flank"
    punch.edges.Min(occ.Y).name = "c1"                 # the flat
    punch.edges.Max(occ.Y).name = "top"
    punch.edges.Min(occ.X).name = "psym"
    for e in punch.edges:
        if e.name == "flank" and e.center.x < 0.1 and e.center.y < 0.1:
            e.name = "c1"                              # the arc (the straight flank's centre is at x 0.99)
    block.edges.name = "side"
    block.edges.Max(occ.Y).name = "c2"
    block.edges.Min(occ.Y).name = "bottom"
    block.edges.Min(occ.X).name = "bsym"
    punch.faces.name, block.faces.name = "punch", "block"
    geo = occ.OCCGeometry(occ.Glue([punch, block]), dim=2)
    mp = MeshingParameters(maxh=hmax, grading=0.3)
    for x in np.arange(0.0, 2.0 * a + 0.25 * hc, 0.5 * hc):
        mp.RestrictH(x=float(x), y=0.0, z=0.0, h=hc)
        mp.RestrictH(x=float(x), y=float(punch_height(x) + LIFT), z=0.0, h=hc)
    for x in np.arange(0.0, 2.0 * a, 3.0 * hc):
        for z in np.arange(0.0, 1.5 * a, 3.0 * hc):
            mp.RestrictH(x=float(x), y=float(-z), z=0.0, h=3.0 * hc)
    mesh = Mesh(geo.GenerateMesh(mp=mp))
    mesh.Curve(order)
    return mesh


def solve(scene: str, a: float, hc: float, hmax: float, order: int, penalty: float) -> dict:
    import ngsolve as ng
    from peers_ngsolve import elasticity, newton, support_reactions

    t0 = time.perf_counter()
    ng.SetNumThreads(2)
    mesh = build_mesh(a, hc, hmax, order)
    bnames = set(mesh.GetBoundaries())
    if not {"c1", "c2", "top", "psym", "bsym", "bottom"} <= bnames:
        raise RuntimeError(f"boundary names {sorted(bnames)}")
    dirx = "psym|bsym|bottom" + ("|top" if scene == "full" else "")
    fes = ng.VectorH1(mesh, order=order, dirichletx=dirx, dirichlety="top|bottom")
    form, energy = elasticity(mesh, fes, {"punch": (E, NU), "block": (E, NU)})
    bf = ng.BilinearForm(fes)
    bf += energy
    uT = fes.TrialFunction()
    X = ng.CoefficientFunction((ng.x, ng.y))
    cb = ng.ContactBoundary(mesh.Boundaries("c1"), mesh.Boundaries("c2"))
    pen = -(uT - uT.Other() + X - X.Other())[1]       # penetration along the block's normal (0, 1)
    full = penalty * E / hc
    k = ng.Parameter(full)
    cb.AddEnergy(ng.IfPos(pen, 0.5 * k * pen * pen, 0))
    gfu = ng.GridFunction(fes)
    with ng.TaskManager():
        cb.Update(gfu, bf, intorder=2 * order + 4, maxdist=0.01)
    gfu.Set((0.0, -APPROACH - LIFT), definedon=mesh.Materials("punch"))
    t_mesh = time.perf_counter()
    its = 0
    for stage in range(3, -1, -1):
        k.Set(full / 10.0 ** stage)
        n, _ = newton(bf, gfu, fes, "sparsecholesky", 1e-11)
        its += n
    reaction = support_reactions(mesh, fes, form, gfu)
    n_block = reaction("bottom", (0.0, 1.0))
    n_punch = -reaction("top", (0.0, 1.0))
    xs = np.arange(0.5 * a, 1.6 * a, hc / 40.0)
    y1 = punch_height(xs) + LIFT
    u1 = _eval(mesh, gfu, xs, y1, (0.0, 1.0))
    u2 = _eval(mesh, gfu, xs, np.zeros_like(xs), (0.0, -1.0))
    gap = y1 + u1[:, 1] - u2[:, 1]
    cf = -gap
    closed = np.nonzero(cf >= 0.0)[0]
    i = closed[-1]
    closing = float(xs[i] + cf[i] / (cf[i] - cf[i + 1]) * (xs[i + 1] - xs[i]))
    from peers_ngsolve import opening_fit

    fit = opening_fit(xs, cf, closing, hc)
    return {"scene": scene, "hc": hc, "order": order, "penalty": penalty, "dofs": fes.ndof, "newton": its,
            "N": 2.0 * n_block, "N_punch": 2.0 * n_punch, "a_closing": closing, "a_fit": fit,
            "mesh_s": t_mesh - t0, "solve_s": time.perf_counter() - t_mesh}


def _eval(mesh, gfu, xs, ys, inward):
    """u at boundary points moved inward by the smallest of 1e-12 .. 1e-8 m inside the mesh."""
    out = np.empty((len(xs), 2))
    for j, (x, y) in enumerate(zip(xs, ys)):
        for off in (1e-12, 1e-10, 1e-9, 1e-8):
            try:
                out[j] = gfu(mesh(float(x + off * inward[0]), float(y + off * inward[1])))
                break
            except Exception:
                continue
        else:
            raise RuntimeError(f"point ({x}, {y}) not found in the mesh")
    return out


# --------------------------------------------------------------------------- the pin in a bore

R1, R2, E1 = 0.5, 0.5005, 5e-4       # pin radius, bore radius, the pin centre's offset below the bore's (m)
HUB, HUB_DOWN, PLATE = 0.04, 1e-3, 10.0
PIN_LIFT = 1e-6


def pin_pairs(theta):
    """ibfem's pairing of the pin's rim point at the angle theta (from the pin's lowest point, about
    its centre): the bore's point at the same chord from the touching point (0, -R2), the pair's
    direction (the bisector of the bore's outward normal and the pin's inward one) and the initial
    gap along it. Returns (x1, x2, direction, gap0) on the undeformed geometry."""
    import numpy as np

    th = np.asarray(theta, dtype=float)
    t2 = 2.0 * np.arcsin(R1 * np.sin(0.5 * th) / R2)
    n1 = np.stack([np.sin(th), -np.cos(th)], axis=-1)
    x1 = np.array([0.0, -E1]) + R1 * n1
    x2 = R2 * np.stack([np.sin(t2), -np.cos(t2)], axis=-1)
    v = -x2 / R2 - n1
    v /= np.linalg.norm(v, axis=-1)[..., None]
    return x1, x2, v, np.einsum("...i,...i->...", x1 - x2, v)


def _pin_cf():
    """The direction and the initial gap of ibfem's pair as NGSolve coefficient functions of the
    (lifted) pin's rim point: the same formulas as pin_pairs."""
    import ngsolve as ng

    th = ng.atan2(ng.x, -(ng.y + E1 - PIN_LIFT))
    t2 = 2.0 * ng.asin(R1 * ng.sin(0.5 * th) / R2)
    v = ng.CoefficientFunction((-ng.sin(t2) - ng.sin(th), ng.cos(t2) + ng.cos(th)))
    v = v / ng.sqrt(v * v)
    x1 = ng.CoefficientFunction((R1 * ng.sin(th), -E1 - R1 * ng.cos(th)))
    x2 = ng.CoefficientFunction((R2 * ng.sin(t2), -R2 * ng.cos(t2)))
    return v, (x1 - x2) * v, x2


def build_pin_mesh(alpha: float, hc: float, hmax: float, order: int):
    """Plate 20 m square with the bore; the pin (lifted PIN_LIFT) with its hub hole; h_c along both
    circles for |theta| <= 1.5 alpha and 2 h_c in a ring 0.1 m wide on either side of them."""
    import numpy as np
    from netgen import occ
    from netgen.meshing import MeshingParameters
    from ngsolve import Mesh

    cy = -E1 + PIN_LIFT
    pin = occ.Circle((0.0, cy), R1).Face() - occ.Circle((0.0, cy), HUB).Face()
    plate = occ.MoveTo(-PLATE, -PLATE).Rectangle(2 * PLATE, 2 * PLATE).Face() - occ.Circle((0.0, 0.0), R2).Face()
    for e in pin.edges:                       # the rim (length pi) and the hub (0.25 m)
        e.name = "c1" if e.mass > 1.0 else "hub"
    for e in plate.edges:                     # the bore (length pi) and the outer sides (20 m)
        e.name = "c2" if e.mass < 10.0 else "outer"
    pin.faces.name, plate.faces.name = "pin", "plate"
    mp = MeshingParameters(maxh=hmax, grading=0.3)
    for th in np.arange(-1.5 * alpha, 1.5 * alpha + 1e-12, 0.5 * hc / R1):
        for r, c in ((R1, cy), (R2, 0.0)):
            mp.RestrictH(x=float(r * np.sin(th)), y=float(c - r * np.cos(th)), z=0.0, h=hc)
        for r in np.arange(R1 - 0.1, R2 + 0.1, 2.0 * hc):
            if abs(r - R1) > hc:
                mp.RestrictH(x=float(r * np.sin(th)), y=float(-r * np.cos(th)), z=0.0, h=2.0 * hc)
    geo = occ.OCCGeometry(occ.Glue([pin, plate]), dim=2)
    mesh = Mesh(geo.GenerateMesh(mp=mp))
    mesh.Curve(order)
    return mesh


def solve_pin(alpha: float, hc: float, hmax: float, order: int, penalty: float) -> dict:
    """The pin in a bore: the hub moved down HUB_DOWN, the plate's outer sides fixed; the penalty on
    the gap of ibfem's pairs (pin_pairs: the initial gap and the direction exactly, the bore's
    displacement at ibfem's paired point, from its value and gradient at the pin point's closest
    bore point, which ``ContactBoundary`` finds: they lie 0.13 mm apart at the region's end, where
    the value alone shifted the gap by 1e-7 m, ten times the penalty's penetration). a: the chord on the pin from the touching
    point to where the gap closes / to the fitted opening's root, the gap read at ibfem's pairs."""
    import ngsolve as ng
    from peers_ngsolve import elasticity, newton, opening_fit, support_reactions

    t0 = time.perf_counter()
    ng.SetNumThreads(2)
    mesh = build_pin_mesh(alpha, hc, hmax, order)
    fes = ng.VectorH1(mesh, order=order, dirichlet="hub|outer")
    form, energy = elasticity(mesh, fes, {"pin": (E, NU), "plate": (E, NU)})
    bf = ng.BilinearForm(fes)
    bf += energy
    uT = fes.TrialFunction()
    v, gap0, x2 = _pin_cf()
    cb = ng.ContactBoundary(mesh.Boundaries("c1"), mesh.Boundaries("c2"))
    X = ng.CoefficientFunction((ng.x, ng.y))
    u2 = uT.Other() + ng.Grad(uT).Other() * (x2 - X.Other())    # at ibfem's paired point, to O(shift^2)
    pen = -(gap0 + (uT - u2) * v + PIN_LIFT * v[1])
    full = penalty * E / hc
    k = ng.Parameter(full)
    cb.AddEnergy(ng.IfPos(pen, 0.5 * k * pen * pen, 0))
    gfu = ng.GridFunction(fes)
    with ng.TaskManager():
        cb.Update(gfu, bf, intorder=2 * order + 4, maxdist=0.01)
    gfu.Set((0.0, -HUB_DOWN - PIN_LIFT), definedon=mesh.Materials("pin"))
    t_mesh = time.perf_counter()
    its = 0
    for stage in range(3, -1, -1):
        k.Set(full / 10.0 ** stage)
        n, _ = newton(bf, gfu, fes, "sparsecholesky", 1e-11)
        its += n
    reaction = support_reactions(mesh, fes, form, gfu)
    load = -reaction("hub", (0.0, 1.0))
    th = np.arange(0.5 * alpha, min(1.45 * alpha, 1.5), hc / (40.0 * R1))
    x1, x2, d, g0 = pin_pairs(th)
    n1 = np.stack([np.sin(th), -np.cos(th)], axis=-1)
    u1 = np.array([_eval(mesh, gfu, [p[0]], [p[1] + PIN_LIFT], -q)[0] for p, q in zip(x1, n1)])
    u2 = np.array([_eval(mesh, gfu, [p[0]], [p[1]], q)[0] for p, q in zip(x2, n1)])
    gap = g0 + np.einsum("ij,ij->i", u1 + np.array([0.0, PIN_LIFT]) - u2, d)
    chord = 2.0 * R1 * np.sin(0.5 * th)
    cf = -gap
    i = np.nonzero(cf >= 0.0)[0][-1]
    closing = float(chord[i] + cf[i] / (cf[i] - cf[i + 1]) * (chord[i + 1] - chord[i]))
    return {"scene": "pin", "hc": hc, "order": order, "penalty": penalty, "dofs": fes.ndof, "newton": its,
            "N": load, "a_closing": closing, "a_fit": opening_fit(chord, cf, closing, hc),
            "mesh_s": t_mesh - t0, "solve_s": time.perf_counter() - t_mesh}


def richardson(q: list[float], ratio: float = 2.0) -> tuple[float, float]:
    """Observed order and limit of three values on meshes refined by ``ratio`` in turn (nan if
    not converging monotonically)."""
    d1, d2 = q[1] - q[0], q[2] - q[1]
    if d1 == 0.0 or d2 / d1 <= 0.0 or abs(d2) >= abs(d1):
        return math.nan, math.nan
    p = math.log(d1 / d2) / math.log(ratio)
    return p, q[2] + d2 / (ratio ** p - 1.0)


def run_meshes(commands: list[list[str]]) -> list[dict]:
    """Each command (one mesh's ``--one`` run) in a process of its own, one after the other; the
    JSON rows their last output lines hold, each printed as it comes."""
    import subprocess

    rows = []
    for cmd in commands:
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode:
            raise SystemExit(r.stderr[-3000:])
        rows.append(json.loads(r.stdout.strip().splitlines()[-1]))
        print(json.dumps(rows[-1]), flush=True)
    return rows


def print_richardson(rows: list[dict], keys: tuple[str, ...], ratio: float = 2.0) -> None:
    """Each key's last three values, their observed order and Richardson's limit."""
    if len(rows) < 3:
        return
    for key in keys:
        p, lim = richardson([r[key] for r in rows[-3:]], ratio)
        print(f"{key}: {', '.join(f'{r[key]:.8g}' for r in rows[-3:])}; observed order {p:.2f}, limit {lim:.8g}")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", choices=("full", "half", "pin"), required=True)
    ap.add_argument("--hc", type=float, default=2e-4, help="h_c of the coarsest mesh (m)")
    ap.add_argument("--meshes", type=int, default=3)
    ap.add_argument("--a-est", type=float, default=0.0148, help="the punch's half width (m) or the pin's semi-angle (rad)")
    ap.add_argument("--hmax", type=float, default=0.05)
    ap.add_argument("--order", type=int, default=3)
    ap.add_argument("--penalty", type=float, default=1e3)
    ap.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        if args.scene == "pin":
            row = solve_pin(args.a_est, args.hc, args.hmax, args.order, args.penalty)
        else:
            row = solve(args.scene, args.a_est, args.hc, args.hmax, args.order, args.penalty)
        print(json.dumps(row), flush=True)
        return 0
    rows = run_meshes([[sys.executable, __file__, "--one", "--scene", args.scene, "--hc", repr(args.hc / 2 ** m),
                        "--a-est", repr(args.a_est), "--hmax", repr(args.hmax), "--order", str(args.order),
                        "--penalty", repr(args.penalty)] for m in range(args.meshes)])
    print_richardson(rows, ("N", "a_closing", "a_fit"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
