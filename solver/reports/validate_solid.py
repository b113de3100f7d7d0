"""``make validate``, 3D part (SPEC section 7): run the scenes of ``examples/solid/`` and compare
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

Usage: ``python -m solver.reports.validate_solid [--only NAME ...] [--report PATH]``.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from solver.reference import theory

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "solid"
#: acceptance (issues 14 and 15)
LAME_DISPLACEMENT_TOL = 0.002
LAME_STRESS_TOL = 0.01  # of p
HERTZ_A_TOL = 0.01
HERTZ_P0_TOL = 0.02
GOODIER_TOL = 0.02


def _run(name: str, out_root: Path) -> tuple[object, dict, float]:
    from solver.io.output import write_results
    from solver.io.scene import load_scene
    from solver.solve import solve

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


def hertz_rows(scene, summary: dict) -> tuple[list[str], bool]:
    c = summary["contacts"][0]
    mats = [scene.problem.body(n).material for n in c["bodies"]]
    e_star = 1.0 / sum((1 - m.poissons_ratio**2) / m.youngs_modulus for m in mats)
    coverage = 4.0  # a quarter model: the full force is 4 N
    n_full = coverage * c["normal_force"]
    a_h = theory.hertz_sphere_radius(n_full, 1.0 / c["relative_curvatures"][0], e_star)
    p0_h = theory.hertz_sphere_peak_pressure(n_full, a_h)
    pr = c["pressure"]["axis0"]
    p0 = float(pr["value"][int(np.argmin(np.abs(pr["s"])))])
    err_a, err_p = c["semi_axes"][0] / a_h - 1.0, p0 / p0_h - 1.0
    # equilibrium of the two bodies together: every support's reaction sums to zero (the contact
    # forces cancel)
    balance = float(np.linalg.norm(np.sum([np.asarray(f, float) for f in summary["reactions"].values()], axis=0)))
    ok = abs(err_a) <= HERTZ_A_TOL and abs(err_p) <= HERTZ_P0_TOL and bool(summary["converged"])
    return [f"| a | {c['semi_axes'][0]:.6g} m | {a_h:.6g} m | {100 * err_a:+.2f} % | {'ok' if abs(err_a) <= HERTZ_A_TOL else 'FAIL'} |",
            f"| p0 (fit at the centre) | {p0:.5g} Pa | {p0_h:.5g} Pa | {100 * err_p:+.2f} % | "
            f"{'ok' if abs(err_p) <= HERTZ_P0_TOL else 'FAIL'} |",
            f"| N (quarter) | {c['normal_force']:.6g} N | all supports' reactions sum to {balance / c['normal_force']:.1e} of N | | |"], ok


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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m solver.reports.validate_solid", description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="*", default=None,
                    help="scene names (default: lame_sphere sphere_on_flat spherical_cavity crossed_cylinders)")
    ap.add_argument("--report", default=str(ROOT / "docs" / "validation-solid.md"))
    args = ap.parse_args(argv)
    names = args.only or ["lame_sphere", "sphere_on_flat", "spherical_cavity", "crossed_cylinders"]
    out_root = ROOT / "out" / "validation" / "solid"
    fig_dir = ROOT / "docs" / "validation" / "solid"
    fig_dir.mkdir(parents=True, exist_ok=True)
    lines = ["# Validation in 3D (SPEC section 7)", "",
             "Written by `make validate` (`python -m solver.reports.validate_solid`); scenes in `examples/solid/`.", ""]
    all_ok = True
    for name in names:
        scene, summary, elapsed = _run(name, out_root)
        dofs = sum(b["dofs"] for b in summary["bodies"].values())
        lines += [f"## {name}", "", f"{dofs} dofs, solved in {elapsed:.1f} s (this machine, 2 cores).", ""]
        if name == "lame_sphere":
            rows, ok = lame_rows(summary)
            lines += ["| where | u_r | s_rr | s_tt | |", "|---|---|---|---|---|"] + rows
        elif name == "crossed_cylinders":
            rows, ok = elliptic_rows(scene, summary)
            lines += ["| quantity | ibfem | Hertz (elliptic integrals) | error | |", "|---|---|---|---|---|"] + rows
        elif name == "spherical_cavity":
            rows, ok = goodier_rows(summary)
            lines += ["| quantity | ibfem | Goodier | error | |", "|---|---|---|---|---|"] + rows
        else:
            rows, ok = hertz_rows(scene, summary)
            lines += ["| quantity | ibfem | Hertz | error | |", "|---|---|---|---|---|"] + rows
        all_ok &= ok
        for png in sorted((out_root / name).glob("*.png")):
            shutil.copy(png, fig_dir / f"{name}_{png.name}")
            lines += ["", f"![{name} {png.stem}](validation/solid/{name}_{png.name})"]
        lines.append("")
        print(f"{name}: {'ok' if ok else 'FAIL'} ({elapsed:.1f} s)")
    Path(args.report).write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"written {args.report}")
    return 0 if all_ok else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
