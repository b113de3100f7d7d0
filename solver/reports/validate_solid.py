"""``make validate``, 3D part: run the scenes of ``examples/solid/`` and compare
them with theory; writes ``docs/validation-solid.md`` and copies each scene's pictures to
``docs/validation/solid/``.

- ``lame_sphere``: radial displacement and the radial and hoop stresses at the probes against
  Lame's thick sphere; the symmetry faces' reactions against the pressure's resultant
  p pi a^2 / 4 on each.
- ``sphere_on_flat`` (quarter model): the contact radius a and the peak pressure p0 against Hertz
  for the computed force (4 N), the two bodies' reactions against each other.
- ``spherical_cavity`` (octant): the axial stress at the cavity's equator over the remote one
  against Goodier's (27 - 15 nu) / (2 (7 - 5 nu)).
- ``crossed_cylinders``: an elliptical contact's semi-axes against Hertz's elliptic-integral
  solution (2 %), its axes against the principal directions (1 degree).
- ``sphere_on_sphere`` (R1 = R2), ``sphere_on_flat_tied``, ``sphere_on_flat_aluminium`` (a
  dissimilar pair): as sphere_on_flat, plus the pressure along both axes (RMS inside 0.9 a within
  3 % of p0) and, where the scene samples the line ``axis``, the largest shear stress under the
  contact against Hertz's 0.31 p0 at 0.48 a (3 %).
- ``sphere_on_flat_turned``: the scene turned by 25 degrees about (1, 2, 3) against the upright one
  solved on the same grid (a, N, p0 within 0.5 %).
- ``sphere_on_flat_partial_slip`` (half model, mu 0.3): c/a against Mindlin's
  (1 - |Q| / (mu N))^(1/3) (0.01), the shear along the slip against Cattaneo-Mindlin (RMS 5 % of mu p0).

Usage: ``python -m ibfem.solver.reports.validate_solid [--only NAME ...] [--report PATH]``.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from ibfem.solver.reference import theory

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "solid"
#: acceptance against the closed-form references
LAME_DISPLACEMENT_TOL = 0.002
LAME_STRESS_TOL = 0.01  # of p
HERTZ_A_TOL = 0.01
HERTZ_P0_TOL = 0.02
GOODIER_TOL = 0.02
PRESSURE_RMS_TOL = 0.03  # of p0, along both axes
AXIS_SHEAR_TOL = 0.03  # the largest shear on the axis: value and depth
STICK_RATIO_TOL = 0.01  # c/a against Mindlin
SHEAR_RMS_TOL = 0.05  # of mu p0
TURNED_TOL = 0.005  # a, N, p0 of a turned scene against the upright one on the same grid



def _run(name: str, out_root: Path) -> tuple[object, dict, float]:
    from ibfem.solver.io.output import write_results
    from ibfem.solver.io.scene import load_scene
    from ibfem.solver.solving import solve

    scene = load_scene(EXAMPLES / f"{name}.toml")
    t = time.perf_counter()
    solution = solve(scene.problem)
    elapsed = time.perf_counter() - t
    out = out_root / name
    summary = write_results(out, scene.problem, solution, probes=scene.output.probes, lines=scene.output.lines,
                            vtk=False, plots=True, total_s=elapsed)
    return scene, summary, elapsed


def _stress_tensor(v) -> np.ndarray:
    s = np.asarray(v, dtype=float)
    return np.array([[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]])


def lame_rows(summary: dict) -> tuple[list[str], bool]:
    """Table rows of the Lame sphere and whether every check holds."""
    p, a, b, e, nu = 1.0e8, 1.0, 2.0, 2.0e11, 0.3
    rows, ok = [], True
    for probe in summary["probes"]:
        x = np.asarray(probe["point"], dtype=float)
        r = float(np.linalg.norm(x))
        d = x / r
        u, srr, stt = theory.lame_sphere(r, a, b, p, e, nu)
        s = _stress_tensor(probe["stress"])
        t = np.cross(d, [0.0, 0.0, 1.0])
        t /= np.linalg.norm(t)
        err_u = float(np.dot(probe["displacement"], d) / u - 1.0)
        err_r, err_t = float((d @ s @ d - srr) / p), float((t @ s @ t - stt) / p)
        good = abs(err_u) <= LAME_DISPLACEMENT_TOL and max(abs(err_r), abs(err_t)) <= LAME_STRESS_TOL
        ok &= good
        rows.append(f"| r = {r:.3f} | {100 * err_u:+.3f} % | {100 * err_r:+.3f} % p | {100 * err_t:+.3f} % p | "
                    f"{'ok' if good else 'FAIL'} |")
    resultant = p * np.pi * a**2 / 4.0
    worst = max(abs(np.linalg.norm(f) / resultant - 1.0) for f in summary["reactions"].values())
    ok &= worst <= 1e-8
    rows.append(f"| reactions of the three symmetry faces | {worst:.1e} from p pi a^2 / 4 | | | "
                f"{'ok' if worst <= 1e-8 else 'FAIL'} |")
    return rows, ok


def _mark(ok: bool) -> str:
    return "ok" if ok else "FAIL"


def circular_reference(scene, c: dict, coverage: float) -> tuple[float, float, float]:
    """(full N, Hertz a, Hertz p0) of a circular contact for the computed force."""
    mats = [scene.problem.body(n).material for n in c["bodies"]]
    e_star = 1.0 / sum((1 - m.poissons_ratio**2) / m.youngs_modulus for m in mats)
    n_full = coverage * c["normal_force"]
    a_h = theory.hertz_sphere_radius(n_full, 1.0 / c["relative_curvatures"][0], e_star)
    return n_full, a_h, theory.hertz_sphere_peak_pressure(n_full, a_h)


def centre_pressure(c: dict) -> float:
    """The pressure of the axis0 profile at the sample nearest the contact point (NaN: no profile)."""
    pr = c["pressure"]["axis0"]
    if not pr["s"]:
        return float("nan")  # no profile along the axis (it leaves the model's sector): a FAIL
    return float(pr["value"][int(np.argmin(np.abs(pr["s"])))])


def pressure_rms(c: dict, a_h: float, p0_h: float) -> float:
    """The larger over both axes of the pressure's RMS difference from Hertz inside 0.9 a, over p0."""
    worst = 0.0
    for k in (0, 1):
        s, p = (np.asarray(c["pressure"][f"axis{k}"][key], dtype=float) for key in ("s", "value"))
        inner = np.abs(s) <= 0.9 * a_h
        if inner.any():
            ref = theory.hertz_sphere_pressure(s[inner], a_h, p0_h)
            worst = max(worst, float(np.sqrt(np.mean((p[inner] - ref) ** 2)) / p0_h))
    return worst


def hertz_rows(scene, summary: dict, coverage: float = 4.0, judged: bool = True) -> tuple[list[str], bool]:
    """A circular contact against Hertz for the computed force: a, p0, the pressure along both
    axes, the balance of the two bodies' supports (for information only when not ``judged``)."""
    c = summary["contacts"][0]
    n_full, a_h, p0_h = circular_reference(scene, c, coverage)
    p0 = centre_pressure(c)
    err_a, err_p = c["semi_axes"][0] / a_h - 1.0, p0 / p0_h - 1.0
    rms = pressure_rms(c, a_h, p0_h)
    # equilibrium of the two bodies together: every support's reaction sums to zero (the contact
    # forces cancel)
    balance = float(np.linalg.norm(np.sum([np.asarray(f, float) for f in summary["reactions"].values()], axis=0)))
    ok_a, ok_p, ok_rms = abs(err_a) <= HERTZ_A_TOL, abs(err_p) <= HERTZ_P0_TOL, rms <= PRESSURE_RMS_TOL
    if c["type"] == "frictional":  # judged by c/a and the shear (partial_slip_rows), on a coarser grid
        ok_a = ok_p = True
    if not judged:  # e.g. a turned scene: judged against the upright one (turned_rows)
        ok_a = ok_p = ok_rms = True
    share = {4.0: "quarter", 2.0: "half", 1.0: "full"}.get(round(coverage, 6), f"1/{coverage:.4g}")
    note = " (not judged)" if c["type"] == "frictional" or not judged else ""
    return [f"| a | {c['semi_axes'][0]:.6g} m | {a_h:.6g} m | {100 * err_a:+.2f} %{note} | {_mark(ok_a)} |",
            f"| p0 (fit at the centre) | {p0:.5g} Pa | {p0_h:.5g} Pa | {100 * err_p:+.2f} %{note} | {_mark(ok_p)} |",
            f"| pressure RMS inside 0.9 a, both axes | | | {100 * rms:.2f} % p0 | {_mark(ok_rms)} |",
            f"| N ({share}) | {c['normal_force']:.6g} N | all supports' reactions sum to {balance / c['normal_force']:.1e} "
            "of N | | |"], ok_a and ok_p and ok_rms and bool(summary["converged"])


def axis_shear_rows(scene, summary: dict, coverage: float) -> tuple[list[str], bool]:
    """The largest shear stress (sigma_1 - sigma_3) / 2 along the line ``axis`` under the contact
    against Hertz's 0.31 p0 at 0.48 a (nu = 0.3), its value and depth within 3 %."""
    line = summary.get("lines", {}).get("axis")
    if not line:
        return [], True
    c = summary["contacts"][0]
    _, a_h, p0_h = circular_reference(scene, c, coverage)
    nu = scene.problem.body(c["bodies"][1]).material.poissons_ratio
    depth = np.abs(np.asarray(line["points"], dtype=float)[:, 2] - c["point"][2])
    stress = np.asarray(line["stress"], dtype=float)
    good = np.all(np.isfinite(stress), axis=1)
    eig = np.linalg.eigvalsh(np.array([_stress_tensor(v) for v in stress[good]]))
    tau = 0.5 * (eig[:, -1] - eig[:, 0])
    z_peak, tau_peak = _parabola_peak(depth[good] / a_h, tau / p0_h)
    z = np.linspace(0.0, 3.0, 30001)
    sr, sz = theory.hertz_sphere_axis_stress(z, 1.0, 1.0, nu)
    zh_peak, tauh_peak = _parabola_peak(z, 0.5 * (sr - sz))
    err_v, err_z = tau_peak / tauh_peak - 1.0, z_peak / zh_peak - 1.0
    ok_v, ok_z = abs(err_v) <= AXIS_SHEAR_TOL, abs(err_z) <= AXIS_SHEAR_TOL
    return [f"| largest shear on the axis | {tau_peak:.4f} p0 | {tauh_peak:.4f} p0 | {100 * err_v:+.2f} % | "
            f"{_mark(ok_v)} |",
            f"| its depth | {z_peak:.4f} a | {zh_peak:.4f} a | {100 * err_z:+.2f} % | {_mark(ok_z)} |"], \
        ok_v and ok_z


def _parabola_peak(z: np.ndarray, f: np.ndarray, window: float = 0.1) -> tuple[float, float]:
    """Vertex of the parabola fitted to f within ``window`` of its largest sample (the shear's
    peak is flat: the largest sample alone moves with the recovery's cell-scale ripples)."""
    k = int(np.argmax(f))
    near = np.abs(z - z[k]) <= window
    c2, c1, c0 = np.polyfit(z[near], f[near], 2)
    if c2 >= 0.0:
        return float(z[k]), float(f[k])
    zv = -c1 / (2.0 * c2)
    return float(zv), float(np.polyval((c2, c1, c0), zv))


def partial_slip_rows(scene, summary: dict, coverage: float) -> tuple[list[str], bool]:
    """Mindlin's stick circle for the transmitted forces and the shear along the axis nearest the
    tangential force against Cattaneo-Mindlin (RMS inside 0.95 a, of mu p0)."""
    c = summary["contacts"][0]
    _, a_h, p0_h = circular_reference(scene, c, coverage)
    mu, n = float(c["friction"]), float(c["normal_force"])
    q = np.asarray(c["tangential_force"], dtype=float)
    k = int(np.argmax(np.abs(q)))
    ratio_t = theory.mindlin_sphere_stick_ratio(float(np.linalg.norm(q)), n, mu)
    ratio = c["stick_semi_axes"][0] / c["semi_axes"][0]
    s, value = (np.asarray(c["shear"][f"axis{k}"][key], dtype=float) for key in ("s", "value"))
    inner = np.abs(s) <= 0.95 * a_h
    # the profile is the traction on body 1; tangential_force is the force on body 2
    ref = theory.cattaneo_mindlin_shear(s[inner], a_h, ratio_t * a_h, mu, p0_h, sign=-np.sign(q[k]) or 1.0)
    rms = float(np.sqrt(np.mean((value[inner] - ref) ** 2)) / (mu * p0_h))
    ok_c, ok_q = abs(ratio - ratio_t) <= STICK_RATIO_TOL, rms <= SHEAR_RMS_TOL
    return [f"| Q / N | {np.linalg.norm(q) / n:.4f} | | | |",
            f"| c / a | {ratio:.4f} | {ratio_t:.4f} (Mindlin) | {ratio - ratio_t:+.4f} | {_mark(ok_c)} |",
            f"| shear RMS along axis {k} inside 0.95 a | | Cattaneo-Mindlin | {100 * rms:.2f} % mu p0 | {_mark(ok_q)} |"], \
        ok_c and ok_q


def turned_rows(turned: dict, upright: dict) -> tuple[list[str], bool]:
    """a, N and the centre pressure of a turned scene against the upright scene on the same grid."""
    rows, ok = [], True
    ct, cu = turned["contacts"][0], upright["contacts"][0]
    for label, got, want in (("a", ct["semi_axes"][0], cu["semi_axes"][0]), ("N", ct["normal_force"], cu["normal_force"]),
                             ("p0", centre_pressure(ct), centre_pressure(cu))):
        err = got / want - 1.0
        judged = label != "p0"  # the invariants are a, b, c and the forces; p0 is a fit's value
        good = abs(err) <= TURNED_TOL or not judged
        ok &= good
        rows.append(f"| {label} | {got:.6g} | {want:.6g} | {100 * err:+.3f} %{'' if judged else ' (not judged)'} | "
                    f"{_mark(good)} |")
    return rows, ok and bool(turned["converged"])


#: a grid offset of the shifted check, fractions of the coarse cell (0.42, 0.67, 0.54 of the finest)
SHIFT = (0.013, 0.021, 0.017)


def upright_on_same_grid(turned_scene, offset=None) -> dict:
    """sphere_on_flat solved on the refinement of the turned scene (the reference of turned_rows),
    its grid shifted by ``offset`` (fractions of the coarse cell) when given."""
    import tomllib

    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.solving import solve

    data = tomllib.loads((EXAMPLES / "sphere_on_flat.toml").read_text(encoding="utf-8"))
    zone = turned_scene.problem.bodies[0].refinements[0]
    for body in data["bodies"]:
        body["refinement"] = {"levels": zone.levels, "around": "contact", "radius": zone.radius}
    data["output"] = {"vtk": False, "plots": False}
    if offset is not None:
        data.setdefault("solver", {})["grid_offset"] = list(offset)
    scene = scene_from_dict(data, label="sphere_on_flat (turned scene's grid)", base_dir=EXAMPLES)
    solution = solve(scene.problem)
    return {"contacts": solution.contacts, "converged": solution.converged}


def elliptic_rows(scene, summary: dict) -> tuple[list[str], bool]:
    """Crossed cylinders: the semi-axes against Hertz's elliptic-integral solution for the
    computed force, the axes against the principal directions (a along y, b along x)."""
    c = summary["contacts"][0]
    mats = [scene.problem.body(n).material for n in c["bodies"]]
    e_star = 1.0 / sum((1 - m.poissons_ratio**2) / m.youngs_modulus for m in mats)
    a_h, b_h, _ = theory.hertz_elliptic_contact(c["normal_force"], (1.0, 2.0), e_star)
    (a, b), axes = c["semi_axes"], np.asarray(c["axes"], dtype=float)
    angle = float(np.degrees(np.arccos(min(1.0, abs(axes[0] @ [0.0, 1.0, 0.0])))))
    rows, ok = [], angle <= 1.0
    for label, got, want in (("a (along y)", a, a_h), ("b (along x)", b, b_h)):
        err = got / want - 1.0
        ok &= abs(err) <= HERTZ_A_TOL * 2
        rows.append(f"| {label} | {got:.6g} m | {want:.6g} m | {100 * err:+.2f} % | "
                    f"{'ok' if abs(err) <= 2 * HERTZ_A_TOL else 'FAIL'} |")
    rows.append(f"| axis 0 against y | {angle:.2g} degrees | 0 | | {'ok' if angle <= 1.0 else 'FAIL'} |")
    return rows, ok


def goodier_rows(summary: dict) -> tuple[list[str], bool]:
    """The first probe sits on the cavity's equator, the last far from it (the remote stress)."""
    remote = float(summary["probes"][-1]["stress"][2])
    scf_theory = theory.goodier_concentration(0.3)
    rows, ok = [], True
    for probe in summary["probes"][:-1]:
        scf = float(probe["stress"][2]) / 1.0e8
        err = scf / scf_theory - 1.0
        good = abs(err) <= GOODIER_TOL
        ok &= good
        rows.append(f"| s_zz / s_remote at {np.round(probe['point'], 4).tolist()} | {scf:.4f} | {scf_theory:.4f} | "
                    f"{100 * err:+.2f} % | {'ok' if good else 'FAIL'} |")
    rows.append(f"| remote s_zz (probe {np.round(summary['probes'][-1]['point'], 3).tolist()}) | {remote / 1e8:.4f} x 100 MPa "
                "| 1 | | |")
    return rows, ok


#: the scenes of ``make validate`` in order (the contact ones after the linear ones)
SCENES = ["lame_sphere", "spherical_cavity", "sphere_on_flat", "sphere_on_sphere", "sphere_on_flat_tied",
          "sphere_on_flat_aluminium", "sphere_on_flat_turned", "sphere_on_flat_partial_slip", "crossed_cylinders"]


def scene_rows(name: str, scene, summary: dict) -> tuple[list[str], bool]:
    """The table of one scene (header included) and whether every check holds."""
    if name == "lame_sphere":
        rows, ok = lame_rows(summary)
        return ["| where | u_r | s_rr | s_tt | |", "|---|---|---|---|---|"] + rows, ok
    if name == "crossed_cylinders":
        rows, ok = elliptic_rows(scene, summary)
        return ["| quantity | ibfem | Hertz (elliptic integrals) | error | |", "|---|---|---|---|---|"] + rows, ok
    if name == "spherical_cavity":
        rows, ok = goodier_rows(summary)
        return ["| quantity | ibfem | Goodier | error | |", "|---|---|---|---|---|"] + rows, ok
    coverage = 1.0 / summary["contacts"][0]["model_share"]  # a quarter model: 4
    rows, ok = hertz_rows(scene, summary, coverage, judged=name != "sphere_on_flat_turned")
    more, ok_more = axis_shear_rows(scene, summary, coverage)
    rows, ok = rows + more, ok and ok_more
    if summary["contacts"][0]["type"] == "frictional":
        more, ok_more = partial_slip_rows(scene, summary, coverage)
        rows, ok = rows + more, ok and ok_more
    table = ["| quantity | ibfem | Hertz | error | |", "|---|---|---|---|---|"] + rows
    if name == "sphere_on_flat_turned":  # judged against the upright scene on its (coarser) grid
        upright = upright_on_same_grid(scene)
        more, ok = turned_rows(summary, upright)
        shifted, ok_shift = turned_rows(upright_on_same_grid(scene, SHIFT), upright)
        ok = ok and ok_shift
        table += ["", "Against the upright sphere_on_flat on the same grid (Hertz above for information):", "",
                  "| quantity | turned | upright | difference | |", "|---|---|---|---|---|"] + more
        table += ["", f"The upright scene on that grid shifted by {SHIFT} of the coarse cell (0.42, 0.67, 0.54 of "
                  "the finest) against it unshifted:", "",
                  "| quantity | shifted | unshifted | difference | |", "|---|---|---|---|---|"] + shifted
    return table, ok


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m ibfem.solver.reports.validate_solid", description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="*", default=None, help=f"scene names (default: {' '.join(SCENES)})")
    ap.add_argument("--report", default=str(ROOT / "docs" / "validation-solid.md"))
    args = ap.parse_args(argv)
    names = args.only or SCENES
    out_root = ROOT / "out" / "validation" / "solid"
    fig_dir = ROOT / "docs" / "validation" / "solid"
    fig_dir.mkdir(parents=True, exist_ok=True)
    lines = ["# Validation in 3D", "",
             "Written by `make validate` (`python -m ibfem.solver.reports.validate_solid`); scenes in `examples/solid/`.", ""]
    all_ok = True
    for name in names:
        scene, summary, elapsed = _run(name, out_root)
        dofs = sum(b["dofs"] for b in summary["bodies"].values())
        lines += [f"## {name}", "", f"{dofs} dofs, solved in {elapsed:.1f} s (this machine, 2 cores).", ""]
        table, ok = scene_rows(name, scene, summary)
        lines += table
        all_ok &= ok
        for png in sorted((out_root / name).glob("*.png")):
            shutil.copy(png, fig_dir / f"{name}_{png.name}")
            lines += ["", f"![{name} {png.stem}](validation/solid/{name}_{png.name})"]
        lines.append("")
        print(f"{name}: {'ok' if ok else 'FAIL'} ({elapsed:.1f} s)", flush=True)
    Path(args.report).write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"written {args.report}")
    return 0 if all_ok else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
