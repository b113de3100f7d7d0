"""The examples' contact pressure and subsurface von Mises against an independent
converged solution of the same problem (NGSolve), not only against Hertz / McEwen's half-space.

Per scene (the same geometry, materials, supports and load as the example, plane strain):

- NGSolve P3 on curved meshes graded to h_c along both contact curves (|s| <= 3 a) and over the
  subsurface window, the frictionless penalty contact of benchmarks/peers_ngsolve.py
  (``ContactBoundary``, master body 1's arc, the penetration along the contact frame's normal,
  pairs on the undeformed geometry, Newton with penalty continuation), on h_c and h_c / 2, and
  on h_c with the penalty doubled;
- ibfem on the example as shipped (one solve, summary.json written), its von Mises peak found as
  benchmarks/tractions.py finds it (``tractions._vm_peak``).

Reported: N (reactions of body 2's supports, checked against body 1's), a (where the gap closes
and from the fitted gap opening, ``peers_ngsolve.opening_fit``, each side), the pressure
p(s) = -sigma_nn just inside body 2 on 201 points s in [-1.25 a, 1.25 a] along the contact
frame's tangent (and the penalty traction k max(-gap, 0) beside it), the largest von Mises stress
in body 2 in the window 3 a x 1.6 a below the contact and its position. Then ibfem against
NGSolve (a, N, pressure RMS difference inside 0.9 a in NGSolve's p0 = max p, vM peak and depth)
and both against Hertz / McEwen for their own N.

    .venv/bin/python benchmarks/examples_ngsolve.py                # ex7, ex3, ex4 (frictionless)
    .venv/bin/python benchmarks/examples_ngsolve.py --only ex7 --hc 0.0008

Writes benchmarks/results/examples_ngsolve.json (or --out). Needs ngsolve (the ``peers`` extra).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import subprocess
import sys
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

LIFT = 1e-5                      # body 1 is meshed this far above body 2 (m), taken back by its load
E, NU = 2.0e11, 0.3              # steel, every example here
S15, C15 = math.sin(math.radians(15.0)), math.cos(math.radians(15.0))
YC7 = 1.0 / C15                  # example 7: the cylinder's centre height


@dataclass(frozen=True)
class Scene:
    """One example in NGSolve's terms. Body 1 is a disc of radius 1 about ``centre1`` (cut to the
    example's half / quarter), body 2 below it; ``point``, ``normal`` (body 2's outward normal at
    the contact point, into body 1) and ``tangent`` the contact frame; ``centre2`` None for a
    straight body-2 contact edge, else the centre of its (radius 1) arc."""

    name: str
    file: str
    frictionless_variant: bool
    point: tuple
    normal: tuple
    tangent: tuple
    centre1: tuple
    centre2: tuple | None
    r_eff: float
    dirichletx: str
    dirichlety: str
    loads: dict                  # boundary -> (ux, uy) prescribed, lift included
    supports2: tuple             # (x-constrained, y-constrained) boundaries of body 2
    supports1: tuple             # the same of body 1


def _lifted_load(ux, uy):
    return (ux, uy - LIFT)


SCENES = {
    "ex7": Scene("ex7_cylinder_on_wedge", "cylinder_on_wedge_frictionless.toml", False,
                 (S15, S15 * S15 / C15), (-S15, C15), (C15, S15), (0.0, YC7), None, 1.0,
                 "csym|wsym|bottom", "top|bottom", {"top": _lifted_load(None, -2.5e-3)},
                 ("wsym|bottom", "bottom"), ("csym", "top")),
    "ex3": Scene("ex3_cylinder_on_cylinder", "cylinder_on_cylinder_frictionless.toml", False,
                 (0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (0.0, 1.0), (0.0, -1.0), 0.5,
                 "top|bottom", "top|bottom", {"top": _lifted_load(2.0e-4, -3.5e-3)},
                 ("bottom", "bottom"), ("top", "top")),
    "ex4": Scene("ex4_cylinder_on_flat_frictionless", "cylinder_on_flat_partial_slip.toml", True,
                 (0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (0.0, 1.0), None, 1.0,
                 "top|bottom", "top|bottom", {"top": _lifted_load(3.65e-4, -2.5e-3)},
                 ("bottom", "bottom"), ("top", "top")),
}


# --------------------------------------------------------------------------- pure helpers

def pressure_rms_difference(s_ref, p_ref, s, p, half_width: float, p0: float, inside: float = 0.9) -> float:
    """RMS of p (sampled at s, interpolated linearly onto s_ref) minus p_ref over the samples
    |s_ref| <= inside * half_width, in p0."""
    s_ref, p_ref = np.asarray(s_ref, dtype=float), np.asarray(p_ref, dtype=float)
    s, p = np.asarray(s, dtype=float), np.asarray(p, dtype=float)
    if not (half_width > 0 and p0 > 0):
        raise ValueError(f"half_width and p0 must be positive, got {half_width!r} and {p0!r}")
    order = np.argsort(s)
    m = np.abs(s_ref) <= inside * half_width
    if not m.any():
        raise ValueError(f"no reference sample inside {inside} * {half_width}")
    d = np.interp(s_ref[m], s[order], p[order]) - p_ref[m]
    return float(np.sqrt(np.mean(d * d)) / p0)


def resultant_offset(s, p, half_width: float) -> float:
    """Where the resultant of the pressure p(s) passes, int p s ds / int p ds, in half_width."""
    s, p = np.asarray(s, dtype=float), np.asarray(p, dtype=float)
    force = np.trapezoid(p, s)
    if not force > 0:
        raise ValueError(f"the pressure transmits no compressive force ({force!r})")
    return float(np.trapezoid(p * s, s) / force / half_width)


def surface2(scene: Scene, s):
    """Points of body 2's contact edge at tangent coordinate s and its outward normals there."""
    s = np.asarray(s, dtype=float)
    P, n, t = (np.asarray(v, dtype=float) for v in (scene.point, scene.normal, scene.tangent))
    if scene.centre2 is None:
        return P + s[:, None] * t, np.broadcast_to(n, (len(s), 2)).copy()
    drop = 1.0 - np.sqrt(1.0 - s * s)                   # radius-1 convex arc below the frame
    pts = P + s[:, None] * t - drop[:, None] * n
    nrm = pts - np.asarray(scene.centre2)
    return pts, nrm / np.linalg.norm(nrm, axis=1)[:, None]


def paired1(scene: Scene, q):
    """Body 1's point paired with body 2's point q along the frame normal (the small-strain gap
    the scenes' contact measures), and the initial gap: the first hit of q + g n on the radius-1 disc."""
    n = np.asarray(scene.normal, dtype=float)
    d = q - np.asarray(scene.centre1)
    b = d @ n
    g0 = -b - np.sqrt(b * b - (np.einsum("ij,ij->i", d, d) - 1.0))
    return q + g0[:, None] * n, g0


def hertz_reference(N: float, r_eff: float) -> dict:
    """Hertz's a and p0 and McEwen's von Mises peak (value, x / a, depth / a) for the force N."""
    from ibfem.solver.reference import theory

    e_eff = theory.effective_modulus(E, NU, E, NU)
    a = theory.hertz_half_width(N, r_eff, e_eff)
    p0 = theory.hertz_peak_pressure(N, a)
    peak, x, z = theory.field_peak(lambda xx, zz: theory.mcewen_stress(xx * a, zz * a, a, p0), nu=NU, extent=2.0, n=81)
    return {"a": a, "p0": p0, "vm_peak": peak, "vm_x_a": x, "vm_z_a": z}


# --------------------------------------------------------------------------- NGSolve model

def _bodies(scene: Scene):
    """The two OCC faces, body 1 lifted by LIFT, edges named c1 / c2 (contact curves), top,
    bottom, csym / wsym (the half model's symmetry lines)."""
    from netgen import occ

    cx, cy = scene.centre1[0], scene.centre1[1] + LIFT
    if scene.name.startswith("ex7"):
        b1 = occ.Circle((cx, cy), 1.0).Face() * occ.MoveTo(0.0, cy - 1.5).Rectangle(1.5, 1.5).Face()
        b2 = occ.MoveTo(0.0, -1.5).LineTo(1.5, -1.5).LineTo(1.5, 1.5 * S15 / C15).LineTo(0.0, 0.0).Close().Face()
    else:
        b1 = occ.Circle((cx, cy), 1.0).Face() * occ.MoveTo(-1.5, cy - 1.5).Rectangle(3.0, 1.5).Face()
        if scene.centre2 is None:
            b2 = occ.MoveTo(-2.0, -2.0).Rectangle(4.0, 2.0).Face()
        else:
            c2 = scene.centre2
            b2 = occ.Circle(c2, 1.0).Face() * occ.MoveTo(-1.5, c2[1]).Rectangle(3.0, 1.5).Face()
    b1.edges.name = "c1"
    b1.edges.Max(occ.Y).name = "top"
    b2.edges.name = "c2"
    b2.edges.Min(occ.Y).name = "bottom"
    if scene.name.startswith("ex7"):
        b1.edges.Min(occ.X).name = "csym"
        b2.edges.Min(occ.X).name = "wsym"
        b2.edges.Max(occ.X).name = "side"
    elif scene.centre2 is None:
        b2.edges.Min(occ.X).name = "side"
        b2.edges.Max(occ.X).name = "side"
    b1.faces.name, b2.faces.name = "b1", "b2"
    return occ.OCCGeometry(occ.Glue([b1, b2]), dim=2)


def build_mesh(scene: Scene, a: float, hc: float, hmax: float, order: int):
    """h_c along |s| <= 3 a of both contact curves, 3 h_c over the window 3 a x 1.6 a below."""
    from netgen.meshing import MeshingParameters
    from ngsolve import Mesh

    mp = MeshingParameters(maxh=hmax, grading=0.3)
    s = np.arange(-3.0 * a, 3.0 * a + 0.25 * hc, 0.5 * hc)
    q, _ = surface2(scene, s)
    x1, _ = paired1(scene, q)
    for pts in (q, x1 + np.array([0.0, LIFT])):
        for x, y in pts:
            mp.RestrictH(x=float(x), y=float(y), z=0.0, h=hc)
    P, n, t = (np.asarray(v, dtype=float) for v in (scene.point, scene.normal, scene.tangent))
    for xs in np.arange(-1.6, 1.61, 3.0 * hc / a):
        for zs in np.arange(0.0, 1.8, 3.0 * hc / a):
            x, y = P + a * (xs * t - zs * n)
            mp.RestrictH(x=float(x), y=float(y), z=0.0, h=3.0 * hc)
    mesh = Mesh(_bodies(scene).GenerateMesh(mp=mp, closeedgefac=None, minedgelen=None))
    mesh.Curve(order)
    return mesh


def stress_cf(mesh, gfu):
    import ngsolve as ng
    from peers_ngsolve import hooke, lame

    mu, lam = lame(E, NU)
    return hooke(ng.Sym(ng.Grad(gfu)), mu, lam, 2)


def evaluate(mesh, cf, pts, inward=None):
    """cf at points (n x 2); boundary points moved inward by the smallest of 1e-12 .. 1e-8 m that
    lies in the curved mesh; NaN where none does."""
    pts = np.asarray(pts, dtype=float)
    inward = np.zeros_like(pts) if inward is None else np.broadcast_to(inward, pts.shape)
    try:
        q = pts + 1e-12 * inward
        return np.asarray(cf(mesh(q[:, 0], q[:, 1])))
    except Exception:
        pass
    out = np.full((len(pts), cf.dim), np.nan)
    for i, (p, d) in enumerate(zip(pts, inward)):
        for off in (1e-12, 1e-10, 1e-9, 1e-8):
            try:
                out[i] = cf(mesh(float(p[0] + off * d[0]), float(p[1] + off * d[1])))
                break
            except Exception:
                continue
    return out


def solve_ngsolve(scene: Scene, a_est: float, hc: float, hmax: float, order: int, penalty: float, threads: int):
    """Mesh, the penalty contact, Newton with continuation; returns (mesh, fes, form, gfu, k, info)."""
    import ngsolve as ng
    from peers_ngsolve import elasticity, newton

    t0 = time.perf_counter()
    ng.SetNumThreads(threads)
    mesh = build_mesh(scene, a_est, hc, hmax, order)
    fes = ng.VectorH1(mesh, order=order, dirichletx=scene.dirichletx, dirichlety=scene.dirichlety)
    form, energy = elasticity(mesh, fes, {"b1": (E, NU), "b2": (E, NU)})
    bf = ng.BilinearForm(fes)
    bf += energy
    uT = fes.TrialFunction()
    X = ng.CoefficientFunction((ng.x, ng.y))
    cb = ng.ContactBoundary(mesh.Boundaries("c1"), mesh.Boundaries("c2"))
    cf = (uT - uT.Other() + X - X.Other()) * ng.CoefficientFunction(tuple(-v for v in scene.normal))
    full = penalty * E / hc
    k = ng.Parameter(full)
    cb.AddEnergy(ng.IfPos(cf, 0.5 * k * cf * cf, 0))
    gfu = ng.GridFunction(fes)
    with ng.TaskManager():
        cb.Update(gfu, bf, intorder=2 * order + 4, maxdist=0.05)
    (name, (ux, uy)), = scene.loads.items()
    gfu.Set((ux or 0.0, uy), definedon=mesh.Materials("b1"))      # body 1 moved rigidly: first guess
    t_mesh = time.perf_counter()
    iterations = 0
    for stage in range(3, -1, -1):
        k.Set(full / 10.0 ** stage)
        its, step = newton(bf, gfu, fes, "sparsecholesky", 1e-10)
        iterations += its
    info = {"hc": hc, "hmax": hmax, "order": order, "penalty": penalty, "k": full, "dofs": fes.ndof,
            "elements": mesh.ne, "newton_iterations": iterations, "mesh_s": t_mesh - t0,
            "solve_s": time.perf_counter() - t_mesh}
    return mesh, fes, form, gfu, full, info


def reactions(mesh, fes, form, gfu, scene: Scene) -> dict:
    """Support reactions of each body (sum of a(u, phi) over its constrained components) and the
    normal force they give: N = R2 . n = -R1 . n, Q = R2 . t."""
    from peers_ngsolve import support_reactions

    reaction = support_reactions(mesh, fes, form, gfu)
    out = {body: np.array([reaction(bx, (1.0, 0.0)), reaction(by, (0.0, 1.0))])
           for body, (bx, by) in (("1", scene.supports1), ("2", scene.supports2))}
    n, t = np.asarray(scene.normal), np.asarray(scene.tangent)
    return {"N": float(out["2"] @ n), "N_body1": float(-out["1"] @ n), "Q": float(out["2"] @ t),
            "R_body2": out["2"].tolist()}


def foot2(scene: Scene, pts):
    """Closest points of body 2's contact curve (a line, or a radius-1 arc) to pts."""
    P, n = np.asarray(scene.point, dtype=float), np.asarray(scene.normal, dtype=float)
    if scene.centre2 is None:
        return pts - ((pts - P) @ n)[:, None] * n
    d = pts - np.asarray(scene.centre2)
    return np.asarray(scene.centre2) + d / np.linalg.norm(d, axis=1)[:, None]


def gap_profile(mesh, gfu, scene: Scene, s):
    """Gap along the frame normal (negative: penetration) between body 1's points paired with
    body 2's points s along that normal and their closest points on body 2 in the lifted mesh,
    which is how ``ContactBoundary`` pairs them (with the lift (0, LIFT): 2.6e-6 m along the
    wedge's face; O(s^3) along the lower cylinder); pairs on the undeformed geometry (small
    strain). Returns (s of body 2's points, gap)."""
    P, n, t = (np.asarray(v, dtype=float) for v in (scene.point, scene.normal, scene.tangent))
    q, _ = surface2(scene, s)
    x1, _ = paired1(scene, q)
    x1m = x1 + np.array([0.0, LIFT])
    f = foot2(scene, x1m)
    inward2 = -np.asarray(surface2(scene, (f - P) @ t)[1])
    u2 = evaluate(mesh, gfu, f, inward2)
    inward1 = np.asarray(scene.centre1) + np.array([0.0, LIFT]) - x1m
    u1 = evaluate(mesh, gfu, x1m, inward1 / np.linalg.norm(inward1, axis=1)[:, None])
    return (f - P) @ t, (x1m + u1 - f - u2) @ n


def half_widths(mesh, gfu, scene: Scene, a_est: float, hc: float) -> dict:
    """a on each side: where the gap closes (interpolated) and the fitted opening."""
    from peers_ngsolve import opening_fit

    out = {}
    for side, sign in (("plus", 1.0), ("minus", -1.0)):
        sf, g = gap_profile(mesh, gfu, scene, sign * np.arange(0.0, 1.6 * a_est, hc / 40.0))
        xs = sign * sf
        cf = -g                                          # penetration
        closed = np.nonzero(cf >= 0.0)[0]
        if len(closed) == 0 or closed[-1] + 1 >= len(xs):
            out[side] = {"closing": math.nan, "fit": math.nan}
            continue
        i = closed[-1]
        t = cf[i] / (cf[i] - cf[i + 1])
        closing = float(xs[i] + t * (xs[i + 1] - xs[i]))
        out[side] = {"closing": closing, "fit": opening_fit(xs, cf, closing, hc)}
    return out


def pressure_profile(mesh, gfu, scene: Scene, a: float, k: float) -> dict:
    """-sigma_nn just inside body 2 and the penalty traction k max(-gap, 0) on 201 points."""
    s = np.linspace(-1.25 * a, 1.25 * a, 201)
    q, n2 = surface2(scene, s)
    sig = evaluate(mesh, stress_cf(mesh, gfu), q, -n2).reshape(-1, 2, 2)
    p = -np.einsum("ni,nij,nj->n", n2, sig, n2)
    sf, g = gap_profile(mesh, gfu, scene, s)
    g = np.interp(s, sf, g)
    return {"s": s.tolist(), "sigma_nn": p.tolist(), "penalty": (k * np.maximum(-g, 0.0)).tolist()}


def vm_peak(mesh, gfu, scene: Scene, a: float) -> dict:
    """Largest plane-strain von Mises stress of body 2 in the window x in [-1.5, 1.5] a, depth
    [0.05, 1.6] a (as benchmarks/tractions.py), refined by tractions._quadratic_vertex."""
    from ibfem.solver.reference import theory
    from tractions import _quadratic_vertex

    P, n, t = (np.asarray(v, dtype=float) for v in (scene.point, scene.normal, scene.tangent))
    sig = stress_cf(mesh, gfu)

    def vm_at(x, z):
        pts = P + a * (np.atleast_1d(x)[:, None] * t - np.atleast_1d(z)[:, None] * n)
        sg = evaluate(mesh, sig, pts).reshape(-1, 2, 2)
        sxx = np.einsum("i,nij,j->n", t, sg, t)
        szz = np.einsum("i,nij,j->n", n, sg, n)
        sxz = np.einsum("i,nij,j->n", t, sg, n)
        return np.asarray(theory.von_mises_plane_strain(sxx, szz, sxz, NU), dtype=float)

    X, Z = np.meshgrid(np.linspace(-1.5, 1.5, 121), np.linspace(0.05, 1.6, 63))
    vm = vm_at(X.ravel(), Z.ravel())
    i = int(np.nanargmax(vm))
    peak, x, z = _quadratic_vertex(vm_at, float(X.ravel()[i]), float(Z.ravel()[i]), 0.04)
    return {"vm_peak": peak, "vm_x": x * a, "vm_z": z * a}


def ngsolve_case(scene: Scene, a_est: float, hc: float, hmax: float, order: int, penalty: float, threads: int) -> dict:
    """One NGSolve solve and everything measured on it."""
    mesh, fes, form, gfu, k, info = solve_ngsolve(scene, a_est, hc, hmax, order, penalty, threads)
    t = time.perf_counter()
    out = dict(info)
    out.update(reactions(mesh, fes, form, gfu, scene))
    sides = half_widths(mesh, gfu, scene, a_est, hc)
    out["a_sides"] = sides
    out["a_closing"] = 0.5 * (sides["plus"]["closing"] + sides["minus"]["closing"])
    out["a"] = 0.5 * (sides["plus"]["fit"] + sides["minus"]["fit"])
    out["pressure"] = pressure_profile(mesh, gfu, scene, out["a"], k)
    p = np.asarray(out["pressure"]["sigma_nn"])
    out["p0"] = float(np.nanmax(p))
    out["p_force"] = float(np.trapezoid(np.where(np.isfinite(p), p, 0.0), out["pressure"]["s"]))
    out.update(vm_peak(mesh, gfu, scene, out["a"]))
    out["measure_s"] = time.perf_counter() - t
    return out


# --------------------------------------------------------------------------- ibfem side

def scene_data(scene: Scene, extra_levels: int = 0) -> dict:
    """The example's scene as shipped, output off; the frictionless variant where asked; with
    ``extra_levels`` more levels on each body's finest refinement zone."""
    data = tomllib.loads((EXAMPLES / scene.file).read_text())
    data.pop("output", None)
    for b in data["bodies"]:
        max(b["refinement"], key=lambda r: r["levels"])["levels"] += extra_levels
    if scene.frictionless_variant:
        for c in data["contacts"]:
            c["type"] = "frictionless"
            c.pop("friction", None)
    return data


def ibfem_case(scene: Scene, out_dir: Path, extra_levels: int = 0) -> dict:
    """Solve the example with ibfem (summary.json in out_dir) and find its von Mises peak as
    benchmarks/tractions.py does."""
    from ibfem.solver.reports.validate import compare_contact, run_scene_data
    from tractions import _vm_peak

    t = time.perf_counter()
    sc, sol, _ = run_scene_data(scene_data(scene, extra_levels), scene.file, out_dir)
    wall = time.perf_counter() - t
    summary = json.loads((out_dir / "summary.json").read_text())
    block = summary["contacts"][0]
    m = compare_contact(sc.problem, block, summary)
    vm = _vm_peak(sc.problem, sol, sol.contacts[0], m)
    a_h = m["a_hertz"]
    return {"a": block["half_width"], "N": block["normal_force"], "Q": block["tangential_force"],
            "point": block["point"], "normal": block["normal"], "tangent": block["tangent"],
            "pressure": {"s": block["pressure"]["s"], "value": block["pressure"]["value"]},
            "p_rms_hertz": m.get("pressure_rms"), "vm_peak": vm["vm_peak_p0"] * m["p0"],
            "vm_x": vm["vm_x"] * a_h,                  # McEwen's peak is on the axis (x_ref = 0)
            "vm_z": vm["vm_z"] * a_h, "vm_vs_mcewen": vm["vm_peak"], "wall_s": wall,
            "extra_levels": extra_levels, "cells_across_a": block["half_width"] / min(
                v["min_element_size"] for v in sol.body_info.values())}


# --------------------------------------------------------------------------- comparison

def ibfem_vs_ngsolve(scene: Scene, ib: dict, ng: dict) -> dict:
    """a, N, the pressure RMS difference inside 0.9 a (NGSolve's a) in NGSolve's p0 = max p, the
    von Mises peak and its position, the resultants' offsets from the contact point."""
    s_ng, p_ng = np.asarray(ng["pressure"]["s"]), np.asarray(ng["pressure"]["sigma_nn"])
    flip = -1.0 if np.dot(ib["tangent"], scene.tangent) < 0 else 1.0
    s_ib, p_ib = flip * np.asarray(ib["pressure"]["s"]), np.asarray(ib["pressure"]["value"])
    order = np.argsort(s_ib)
    a_ng = ng["a"]
    return {"extra_levels": ib["extra_levels"], "cells_across_a": ib["cells_across_a"],
            "a": ib["a"] / a_ng - 1.0, "N": ib["N"] / ng["N"] - 1.0,
            "p_rms": pressure_rms_difference(s_ng, p_ng, s_ib, p_ib, a_ng, ng["p0"]),
            "vm_peak": ib["vm_peak"] / ng["vm_peak"] - 1.0, "vm_depth_a": (ib["vm_z"] - ng["vm_z"]) / a_ng,
            "vm_x_a": (flip * ib["vm_x"] - ng["vm_x"]) / a_ng,
            "resultant_offset_ngsolve": resultant_offset(s_ng, p_ng, a_ng),
            "resultant_offset_ibfem": resultant_offset(s_ib[order], p_ib[order], a_ng), "wall_s": ib["wall_s"]}


def compare(scene: Scene, ib: dict, ng: dict, ng_coarse: dict, ng_stiff: dict) -> dict:
    """ibfem against NGSolve's finer mesh; both against Hertz / McEwen for their own N."""
    s_ng, p_ng = np.asarray(ng["pressure"]["s"]), np.asarray(ng["pressure"]["sigma_nn"])
    flip = -1.0 if np.dot(ib["tangent"], scene.tangent) < 0 else 1.0
    s_ib, p_ib = flip * np.asarray(ib["pressure"]["s"]), np.asarray(ib["pressure"]["value"])
    a_ng, p0_ng = ng["a"], ng["p0"]
    h_ng, h_ib = hertz_reference(ng["N"], scene.r_eff), hertz_reference(ib["N"], scene.r_eff)
    from ibfem.solver.reference import theory

    def vs_hertz(s, p, h):
        return pressure_rms_difference(s, theory.hertz_pressure(s, h["a"], h["p0"]), s, p, h["a"], h["p0"])

    s_c, p_c = np.asarray(ng_coarse["pressure"]["s"]), np.asarray(ng_coarse["pressure"]["sigma_nn"])
    return {
        "scene": scene.name, "file": scene.file, "frictionless_variant": scene.frictionless_variant,
        "ibfem": {"a": ib["a"], "N": ib["N"], "vm_peak": ib["vm_peak"], "vm_z": ib["vm_z"], "vm_x": ib["vm_x"]},
        "ngsolve": {k: ng[k] for k in ("a", "a_closing", "a_sides", "N", "N_body1", "Q", "p0", "vm_peak", "vm_z", "vm_x", "dofs", "hc")},
        "ibfem_vs_ngsolve": ibfem_vs_ngsolve(scene, ib, ng),
        "ngsolve_convergence": {   # h_c against h_c / 2, and the penalty doubled on h_c
            "a": ng_coarse["a"] / a_ng - 1.0, "N": ng_coarse["N"] / ng["N"] - 1.0,
            "p_rms": pressure_rms_difference(s_ng, p_ng, s_c, p_c, a_ng, p0_ng),
            "vm_peak": ng_coarse["vm_peak"] / ng["vm_peak"] - 1.0,
            "vm_depth_a": (ng_coarse["vm_z"] - ng["vm_z"]) / a_ng,
            "penalty_x2_N": ng_stiff["N"] / ng_coarse["N"] - 1.0, "penalty_x2_a": ng_stiff["a"] / ng_coarse["a"] - 1.0,
            "penalty_x2_vm": ng_stiff["vm_peak"] / ng_coarse["vm_peak"] - 1.0},
        "vs_half_space": {
            "ngsolve_a": a_ng / h_ng["a"] - 1.0, "ibfem_a": ib["a"] / h_ib["a"] - 1.0,
            "ngsolve_p_rms": vs_hertz(s_ng, p_ng, h_ng), "ibfem_p_rms": vs_hertz(s_ib, p_ib, h_ib),
            "ngsolve_p0": p0_ng / h_ng["p0"] - 1.0,
            "ngsolve_vm": ng["vm_peak"] / h_ng["vm_peak"] - 1.0, "ibfem_vm": ib["vm_peak"] / h_ib["vm_peak"] - 1.0,
            "ngsolve_depth_a": ng["vm_z"] / a_ng - h_ng["vm_z_a"], "ibfem_depth_a": ib["vm_z"] / h_ib["a"] - h_ib["vm_z_a"]},
        "hertz": {"ngsolve_N": h_ng, "ibfem_N": h_ib},
        "profiles": {"s": s_ng.tolist(), "ngsolve": p_ng.tolist(), "ngsolve_penalty": ng["pressure"]["penalty"],
                     "ibfem": np.interp(s_ng, np.sort(s_ib), p_ib[np.argsort(s_ib)]).tolist()},
    }


def _sub(args: list[str]) -> dict:
    r = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed: {r.stderr.strip()[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def run_scene(key: str, hc_over_a: float, hc: float | None, hmax: float, penalty: float, threads: int, out_root: Path,
              extra_levels: list[int]) -> dict:
    scene = SCENES[key]
    ib = _sub(["--ibfem", key, "--out-dir", str(out_root / key)])
    finer = [_sub(["--ibfem", key, "--out-dir", str(out_root / f"{key}_{k}"), "--extra-levels", str(k)]) for k in extra_levels]
    hc = hc or ib["a"] / hc_over_a
    common = ["--a-est", repr(ib["a"]), "--hmax", repr(hmax), "--threads", str(threads)]
    ng_coarse = _sub(["--ngsolve", key, "--hc", repr(hc), "--penalty", repr(penalty), *common])
    ng_stiff = _sub(["--ngsolve", key, "--hc", repr(hc), "--penalty", repr(2 * penalty), *common])
    ng = _sub(["--ngsolve", key, "--hc", repr(hc / 2), "--penalty", repr(penalty), *common])
    row = compare(scene, ib, ng, ng_coarse, ng_stiff)
    row["ibfem_finer_vs_ngsolve"] = [ibfem_vs_ngsolve(scene, f, ng) for f in finer]
    row["runs"] = {"ibfem_wall_s": ib["wall_s"],
                   "ngsolve": [{k: r[k] for k in ("hc", "penalty", "dofs", "newton_iterations", "mesh_s", "solve_s", "a", "N", "vm_peak")}
                               for r in (ng_coarse, ng_stiff, ng)]}
    return row


def _line(r: dict) -> str:
    iv, cv, hs = r["ibfem_vs_ngsolve"], r["ngsolve_convergence"], r["vs_half_space"]
    return (f"{r['scene']:36s} ibfem-NG: a {iv['a']:+.3%} N {iv['N']:+.3%} p_rms {iv['p_rms']:.3%} vM {iv['vm_peak']:+.3%} "
            f"depth {iv['vm_depth_a']:+.4f} a | NG h_c vs h_c/2: a {cv['a']:+.3%} p_rms {cv['p_rms']:.3%} vM {cv['vm_peak']:+.3%}; "
            f"k x2: N {cv['penalty_x2_N']:+.1e} | vs half-space NG/ib: p_rms {hs['ngsolve_p_rms']:.3%}/{hs['ibfem_p_rms']:.3%} "
            f"vM {hs['ngsolve_vm']:+.3%}/{hs['ibfem_vm']:+.3%}")


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", help="ex7, ex3 or ex4 (comma-separated)")
    ap.add_argument("--hc-over-a", type=float, default=40.0, help="h_c = a / this on the coarser NGSolve mesh")
    ap.add_argument("--hc", type=float, help="h_c (m) of the coarser mesh (overrides --hc-over-a)")
    ap.add_argument("--hmax", type=float, default=0.1)
    ap.add_argument("--penalty", type=float, default=1e3, help="k = penalty E / h_c")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default=str(HERE / "results" / "examples_ngsolve.json"))
    ap.add_argument("--ibfem", help=argparse.SUPPRESS)
    ap.add_argument("--ngsolve", help=argparse.SUPPRESS)
    ap.add_argument("--out-dir", help=argparse.SUPPRESS)
    ap.add_argument("--finer", default="1,2", help="ibfem also with these more refinement levels ('' for none)")
    ap.add_argument("--extra-levels", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--a-est", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.ibfem:
        print(json.dumps(ibfem_case(SCENES[args.ibfem], Path(args.out_dir), args.extra_levels)))
        return 0
    if args.ngsolve:
        print(json.dumps(ngsolve_case(SCENES[args.ngsolve], args.a_est, args.hc, args.hmax, 3, args.penalty, args.threads)))
        return 0
    import tempfile

    keys = args.only.split(",") if args.only else ["ex7", "ex3", "ex4"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for key in keys:
            if key not in SCENES:
                raise SystemExit(f"--only: unknown scene {key!r} (ex7, ex3, ex4)")
            finer = [int(k) for k in args.finer.split(",") if k.strip()]
            rows.append(run_scene(key, args.hc_over_a, args.hc, args.hmax, args.penalty, args.threads, Path(tmp), finer))
            print(_line(rows[-1]), flush=True)
            for f in rows[-1]["ibfem_finer_vs_ngsolve"]:
                print(f"{'':36s} ibfem +{f['extra_levels']} levels (a/h {f['cells_across_a']:.1f}) - NG: a {f['a']:+.3%} "
                      f"N {f['N']:+.3%} p_rms {f['p_rms']:.3%} vM {f['vm_peak']:+.3%} depth {f['vm_depth_a']:+.4f} a", flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": platform.platform(), "command": " ".join(["benchmarks/examples_ngsolve.py", *argv]),
                               "cases": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
