"""``make validate``: run the validation scenes (the thesis's chapter 6) and compare them with theory.

Writes ``docs/validation.md`` (tables) and ``docs/validation/*.png`` (plots), and every scene's
results under ``out/validation/<scene>/``. Each contact is compared with the analytical
references of :mod:`solver.reference.theory` *for the forces the solver computed*: the half-width a with
Hertz, c/a with Cattaneo-Mindlin, the pressure and shear sampled on the exact contact curve, and
the subsurface von Mises stress on the ``subsurface`` line with McEwen's field.

Usage: ``python -m ibfem.solver.reports.validate [--quick] [--only NAME ...] [--report PATH]``.
``--quick`` skips the load and grid sweeps of example 2.
"""

from __future__ import annotations

import argparse
import copy
import json
import shutil
import math
import sys
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ibfem.solver.reference import theory
from ibfem.solver.reference.converged import vm_peak_for_force

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
SWEEPS = EXAMPLES / "sweeps"

# What the thesis reported (chapter 6; tables 6-1 to 6-4): error in a, error in c/a.
THESIS = {
    "ellipse_on_block": {"a_error": 0.0288},
    "ellipse_on_block_tessellated": {"a_error": 0.314},
    "mesh_convergence": {"a_error": 0.03},
    "cylinder_on_cylinder_frictionless": {"a_error": 0.0137},
    "cylinder_on_flat_partial_slip": {"a_error": 0.0052, "ca_error": 0.0022},
    "cylinder_on_cylinder_partial_slip": {"a_error": 0.0106, "ca_error": 0.0110},
    "cylinder_in_concave_partial_slip": {"a_error": 0.0353, "ca_error": 0.0004},
    "cylinder_on_wedge_frictionless": {"a_error": 0.0415},
}

# Acceptance of the contact width, stick ratio, pressure and shear.
A_TOL = 0.02
CA_TOL = 0.02
PRESSURE_RMS_TOL = 0.02
PRESSURE_MIN_TOL = -0.005  # the most negative reported pressure, in p0
SHEAR_RMS_TOL = 0.05
# von Mises peak against the half-space references (McEwen, Cattaneo-Mindlin): 3 %.
# A 1 % target is too tight here: the examples' finite bodies put their converged peaks 0.8-5 % above the
# half-space value (benchmarks/tractions.py: the peak on two more refinement levels), so 1 % is
# checked there against the finest grid, not here.
VM_PEAK_TOL = 0.03
# Where a converged solution of the same bodies by another code is stored
# (solver.reference.converged: NGSolve P3, benchmarks/examples_ngsolve.py), the 1 % target is
# checked against it instead of the half-space field.
VM_CONVERGED_TOL = 0.01


@dataclass
class Result:
    name: str
    ok: bool
    message: str = ""
    summary: dict[str, Any] = field(default_factory=dict)
    metrics: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0


def run_scene_data(data: dict, label: str, out_dir: Path, base_dir: Path = EXAMPLES) -> tuple[Any, Any, dict]:
    """Validate, solve and write one scene given as a dict; returns (scene, solution, summary)."""
    from ibfem.solver.solving import solve
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import scene_from_dict

    t0 = time.perf_counter()
    scene = scene_from_dict(data, label=label, base_dir=base_dir)
    solution = solve(scene.problem)
    summary = write_scene_results(out_dir, scene, solution, total_s=time.perf_counter() - t0)
    return scene, solution, summary


def _curvature_at(profile, point: np.ndarray) -> float:
    """Signed curvature of the profile's boundary at ``point`` (convex positive)."""
    proj = profile.project(np.asarray(point, dtype=float)[None, :])
    name = profile.edge_names[int(proj.edge_index[0])]
    curve = profile.edge(name)
    return float(np.asarray(curve.curvature(np.asarray(proj.parameters[:1])))[0])


def effective_properties(problem, block: dict) -> tuple[float, float]:
    """(R*, E*) of a contact from the exact curvatures at the contact point and the materials."""
    b1, b2 = (problem.body(n) for n in block["bodies"])
    point = np.asarray(block["point"], dtype=float)
    k = _curvature_at(b1.profile, point) + _curvature_at(b2.profile, point)
    r_eff = math.inf if abs(k) < 1e-12 else 1.0 / k
    m1, m2 = b1.material, b2.material
    e_eff = theory.effective_modulus(m1.youngs_modulus, m1.poissons_ratio, m2.youngs_modulus, m2.poissons_ratio)
    return r_eff, e_eff


def hertz_for_force(problem, block: dict) -> tuple[float, float, float]:
    """(R*, a, p0) of a 2D contact: Hertz's half-width and peak pressure for its computed normal
    force (N > 0), with :func:`effective_properties`."""
    r_eff, e_eff = effective_properties(problem, block)
    n = float(block["normal_force"])
    a = theory.hertz_half_width(n, r_eff, e_eff)
    return r_eff, a, theory.hertz_peak_pressure(n, a)


def compare_contact(problem, block: dict, summary: dict) -> dict[str, Any]:
    """Metrics of one contact block against Hertz / Cattaneo-Mindlin / McEwen."""
    r_eff, e_eff = effective_properties(problem, block)
    N = float(block["normal_force"])
    Q = float(block["tangential_force"])
    a = float(block["half_width"])
    c = float(block["stick_half_width"])
    m: dict[str, Any] = {"R_eff": r_eff, "E_eff": e_eff, "N": N, "Q": Q, "a": a, "c": c, "type": block["type"]}
    if not N > 0:
        m["error"] = "no compressive force transmitted"
        return m
    a_ref = theory.hertz_half_width(N, r_eff, e_eff)
    p0 = theory.hertz_peak_pressure(N, a_ref)
    m.update(a_hertz=a_ref, a_error=abs(a - a_ref) / a_ref, p0=p0)
    s = np.asarray(block["pressure"]["s"], dtype=float)
    p = np.asarray(block["pressure"]["value"], dtype=float)
    inner = np.abs(s) <= 0.9 * a_ref
    if inner.any():
        ref = theory.hertz_pressure(s[inner], a_ref, p0)
        m["pressure_rms"] = float(np.sqrt(np.mean((p[inner] - ref) ** 2)) / p0)
    if len(p):
        m["pressure_min"] = float(p.min() / p0)
    if block["type"] == "frictional":
        mu = float(block["friction"])
        m["Q_over_N"] = Q / N
        ca = theory.cattaneo_mindlin_stick_ratio(Q, N, mu, allow_gross_slip=True)
        m["ca_theory"] = float(ca)
        m["ca"] = c / a if a > 0 else float("nan")
        m["ca_error"] = abs(m["ca"] - m["ca_theory"])
        s_q = np.asarray(block["shear"]["s"], dtype=float)
        q = np.asarray(block["shear"]["value"], dtype=float)
        inner = np.abs(s_q) <= 0.95 * a_ref
        if inner.any():
            ref = theory.cattaneo_mindlin_shear(s_q[inner], a_ref, ca * a_ref, mu, p0, sign=np.sign(Q) or 1.0)
            m["shear_rms"] = float(np.sqrt(np.mean((q[inner] - ref) ** 2)) / (mu * p0))
    else:
        m["abs_Q"] = abs(Q)
    line = summary.get("lines", {}).get("subsurface")
    if line:
        vm = np.asarray(line["von_mises"], dtype=float)
        pts = np.asarray(line["points"], dtype=float)
        depth = np.linalg.norm(pts - np.asarray(block["point"]), axis=1)
        good = np.isfinite(vm)
        if good.any():
            i = int(np.nanargmax(np.where(good, vm, -np.inf)))
            m["vm_peak"] = float(vm[i] / p0)
            m["vm_peak_depth"] = float(depth[i] / a_ref)
    return m


def reference_field(block: dict, metrics: dict):
    """The analytical subsurface field for this contact: McEwen's (frictionless or tied) or
    the Cattaneo-Mindlin superposition (frictional), as ``f(x, z) -> (sxx, szz, sxz)``."""
    a, p0 = metrics["a_hertz"], metrics["p0"]
    if block["type"] == "frictional" and "ca_theory" in metrics:
        mu = float(block["friction"])
        sign = float(np.sign(metrics["Q"])) or 1.0
        return lambda x, z: theory.cattaneo_mindlin_stress(x, z, a, metrics["ca_theory"] * a, mu, p0, sign)
    return lambda x, z: theory.mcewen_stress(x, z, a, p0)


def field_peak_comparison(problem, solution, block: dict, metrics: dict, n: int = 121) -> dict[str, float]:
    """Largest von Mises stress below the contact, computed and analytical: peak / p0 and its
    position (x along the tangent, z depth along -normal, both / a). With partial slip the peak
    leaves the load axis (the tilt of the thesis's figure 6-17)."""
    a, p0 = metrics["a_hertz"], metrics["p0"]
    point = np.asarray(block["point"], dtype=float)
    normal = np.asarray(block["normal"], dtype=float)
    tangent = np.asarray(block["tangent"], dtype=float)
    xs = np.linspace(-2.0, 2.0, 2 * n - 1)
    zs = np.linspace(0.02, 2.0, n)
    X, Z = np.meshgrid(xs, zs)
    pts = point + a * (X.ravel()[:, None] * tangent - Z.ravel()[:, None] * normal)
    vm = np.asarray(solution.von_mises(pts, body=block["bodies"][1]), dtype=float)
    k = int(np.nanargmax(vm))
    nu = problem.body(block["bodies"][1]).material.poissons_ratio
    field = reference_field(block, metrics)
    peak, x_ref, z_ref = theory.field_peak(lambda x, z: field(x * a, z * a), nu=nu, extent=2.0, n=81)
    return {
        "field_peak": float(vm[k] / p0), "field_peak_x": float(X.ravel()[k]), "field_peak_z": float(Z.ravel()[k]),
        "field_peak_theory": float(peak / p0), "field_peak_x_theory": float(x_ref), "field_peak_z_theory": float(z_ref),
    }


def _plot(name: str, problem, block: dict, summary: dict, metrics: dict, out_dir: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    files = []
    a_ref, p0 = metrics.get("a_hertz"), metrics.get("p0")
    if not a_ref:
        return files
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    s = np.asarray(block["pressure"]["s"], dtype=float)
    x = np.linspace(-1.3 * a_ref, 1.3 * a_ref, 400)
    axes[0].plot(x / a_ref, theory.hertz_pressure(x, a_ref, p0) / p0, "k-", label="Hertz")
    axes[0].plot(s / a_ref, np.asarray(block["pressure"]["value"], dtype=float) / p0, "o", ms=3, label="IBFEM")
    axes[0].set(xlabel="s / a", ylabel="p / p0", title="contact pressure")
    axes[0].legend()
    sq = np.asarray(block["shear"]["s"], dtype=float)
    q = np.asarray(block["shear"]["value"], dtype=float)
    if block["type"] == "frictional" and "ca_theory" in metrics:
        mu = float(block["friction"])
        ref = theory.cattaneo_mindlin_shear(x, a_ref, metrics["ca_theory"] * a_ref, mu, p0, sign=np.sign(metrics["Q"]) or 1.0)
        axes[1].plot(x / a_ref, ref / p0, "k-", label="Cattaneo-Mindlin")
    axes[1].plot(sq / a_ref, q / p0, "o", ms=3, label="IBFEM")
    axes[1].set(xlabel="s / a", ylabel="q / p0", title="contact shear")
    axes[1].legend()
    line = summary.get("lines", {}).get("subsurface")
    if line:
        pts = np.asarray(line["points"], dtype=float)
        depth = np.linalg.norm(pts - np.asarray(block["point"]), axis=1)
        z = np.linspace(1e-6, depth.max(), 300)
        nu = problem.body(block["bodies"][1]).material.poissons_ratio
        sxx, szz, sxz = reference_field(block, metrics)(np.zeros_like(z), z)
        label = "Cattaneo-Mindlin (McEwen superposition)" if block["type"] == "frictional" else "McEwen"
        axes[2].plot(theory.von_mises_plane_strain(sxx, szz, sxz, nu) / p0, z / a_ref, "k-", label=label)
        axes[2].plot(np.asarray(line["von_mises"], dtype=float) / p0, depth / a_ref, ".", ms=3, label="IBFEM")
        axes[2].invert_yaxis()
        axes[2].set(xlabel="von Mises / p0", ylabel="depth / a", title="subsurface von Mises")
        axes[2].legend()
    fig.suptitle(name)
    fig.tight_layout()
    path = out_dir / f"{name}.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    files.append(path)
    return files


def validate_scene(path: Path, out_root: Path, fig_dir: Path) -> Result:
    name = path.stem
    t0 = time.perf_counter()
    try:
        data = tomllib.loads(path.read_text())
        scene, solution, summary = run_scene_data(data, path.name, out_root / name, base_dir=path.parent)
    except Exception as err:  # a validation run reports every failure and goes on
        return Result(name, False, f"{type(err).__name__}: {err}", seconds=time.perf_counter() - t0)
    res = Result(name, bool(summary["converged"]), "" if summary["converged"] else "not converged", summary)
    for block in summary.get("contacts", []):
        m = compare_contact(scene.problem, block, summary)
        if "a_hertz" in m:
            m.update(field_peak_comparison(scene.problem, solution, block, m))
            converged = vm_peak_for_force(name, m["N"])
            if converged is not None:
                m["field_peak_converged"] = converged / m["p0"]
        res.metrics.append(m)
        try:
            _plot(name, scene.problem, block, summary, m, fig_dir)
        except ImportError:
            pass
    for picture in ("contact_0_fields.png",):
        src = out_root / name / picture
        if src.exists():
            shutil.copyfile(src, fig_dir / f"{name}_fields.png")
    res.seconds = time.perf_counter() - t0
    return res


def _sweep_engine():
    """The embedded Dask cluster when the ``sweep`` extra is installed, else one case at a time."""
    from ibfem.solver.sweep.engine import EngineOptions

    try:
        import distributed  # noqa: F401
    except ImportError:
        return EngineOptions(serial=True)
    return EngineOptions()


def run_example_sweep(name: str, out_root: Path) -> list[tuple[dict, dict]]:
    """Run ``examples/sweeps/<name>.toml`` through the sweep module (``ibfem sweep``; earlier
    results removed first) and compare each case's contact with theory: (parameters, metrics)."""
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.sweep.run import run_sweep
    from ibfem.solver.sweep.spec import load_sweep

    sweep = load_sweep(SWEEPS / f"{name}.toml")
    out = out_root / "sweeps" / name
    shutil.rmtree(out, ignore_errors=True)
    outcome = run_sweep(sweep, out, _sweep_engine(), quiet=True)
    rows = []
    for case in outcome.cases:
        rec = outcome.record(case)
        try:
            if rec.get("status") not in ("ok", "not_converged"):
                raise RuntimeError(f"{rec.get('status')}: {rec.get('message')}")
            summary = json.loads((out / rec["dir"] / "summary.json").read_text())
            scene = scene_from_dict(copy.deepcopy(case.scene), label=f"{name} case {case.index}", base_dir=sweep.base_dir)
            m = compare_contact(scene.problem, summary["contacts"][0], summary)
            m["cells_across"] = 2 * m["a_hertz"] / min(b["min_element_size"] for b in summary["bodies"].values())
            m["seconds"] = summary["timings"]["total_s"]
        except Exception as err:
            m = {"error": f"{type(err).__name__}: {err}"}
        rows.append((case.params, m))
    return rows


def mesh_convergence_sweeps(out_root: Path) -> dict[str, list[dict]]:
    """Example 2: the eight loads on one grid and the grid sweep at the representative load
    (examples/sweeps/mesh_convergence_load.toml and mesh_convergence_grid.toml)."""
    rows: dict[str, list[dict]] = {"loads": [], "grids": []}
    for params, m in run_example_sweep("mesh_convergence_load", out_root):
        rows["loads"].append({**m, "uy": params["boundary_conditions.cylinder/flat.value.1"]})
    for params, m in run_example_sweep("mesh_convergence_grid", out_root):
        rows["grids"].append({**m, "element_size": params["bodies.*.element_size"],
                              "levels": params["bodies.*.refinement.-1.levels"]})
    return rows


def _pct(x: Any) -> str:
    return "–" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{100 * x:.2f} %"


def _num(x: Any, fmt: str = ".4g") -> str:
    return "–" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, fmt)


def _verdict(ok: bool | None) -> str:
    return "–" if ok is None else ("pass" if ok else "**fail**")


def _contact_rows(results: list[Result]) -> list[str]:
    lines: list[str] = []
    for r in results:
        if not r.metrics:
            lines.append(f"| {r.name} | {_verdict(False) if r.message else '–'} | {r.message or 'no contact'} |" + " |" * 16)
            continue
        for m in r.metrics:
            th = THESIS.get(r.name, {})
            checks = []
            if "a_error" in m:
                checks.append(m["a_error"] <= A_TOL)
            if "ca_error" in m:
                checks.append(m["ca_error"] <= CA_TOL)
            if "pressure_rms" in m:
                checks.append(m["pressure_rms"] <= PRESSURE_RMS_TOL)
            if "pressure_min" in m:
                checks.append(m["pressure_min"] >= PRESSURE_MIN_TOL)
            if "field_peak_converged" in m:
                checks.append(abs(m["field_peak"] / m["field_peak_converged"] - 1.0) <= VM_CONVERGED_TOL)
            elif "field_peak" in m:
                checks.append(abs(m["field_peak"] / m["field_peak_theory"] - 1.0) <= VM_PEAK_TOL)
            if "shear_rms" in m:
                checks.append(m["shear_rms"] <= SHEAR_RMS_TOL)
            if "abs_Q" in m and m["type"] == "frictionless":
                checks.append(m["abs_Q"] < 1e-3)
            if r.name == "ellipse_on_block_tessellated":
                verdict = "degraded without exact geometry" if m.get("a_error", 0) > A_TOL else "not degraded"
            else:
                verdict = _verdict(r.ok and all(checks)) if checks else _verdict(None)
            vm = f"{_num(m.get('vm_peak'), '.4f')} ({_num(m.get('vm_peak_depth'), '.3f')})" if "vm_peak" in m else "–"
            lines.append(
                f"| {r.name} | {r.ok} | {_num(m.get('N'))} | {_num(m.get('Q_over_N', m.get('Q', 0) / m['N'] if m.get('N') else None), '.4f')} "
                f"| {_num(m.get('a'))} | {_num(m.get('a_hertz'))} | {_pct(m.get('a_error'))} | {_pct(th.get('a_error'))} "
                f"| {_num(m.get('ca'), '.4f')} | {_num(m.get('ca_theory'), '.4f')} | {_num(m.get('ca_error'), '.4f')} | {_pct(th.get('ca_error'))} "
                f"| {_pct(m.get('pressure_rms'))} | {_pct(m.get('pressure_min'))} | {_pct(m.get('shear_rms'))} | {vm} "
                f"| {_vm_against(m)} | {r.seconds:.1f} | {verdict} |"
            )
    return lines


def _vm_against(m: dict) -> str:
    """The von Mises peak against the half-space field, and against the converged solution of
    the same bodies where one is stored (the one judged there)."""
    if "field_peak" not in m:
        return "–"
    text = _pct(m["field_peak"] / m["field_peak_theory"] - 1.0)
    if "field_peak_converged" in m:
        text += f"; converged: {_pct(m['field_peak'] / m['field_peak_converged'] - 1.0)}"
    return text


def _peak_table(results: list[Result]) -> list[str]:
    lines: list[str] = []
    lines += [
        "",
        "Largest von Mises stress below the contact (computed on a 2a x 2a window of the lower body;",
        "theory: McEwen, or the Cattaneo-Mindlin superposition for partial slip), peak / p0 at (x, z) / a,",
        "x along the contact tangent, z the depth. With partial slip the peak leaves the axis: the",
        "tilt of the thesis's figure 6-17.",
        "",
        "| scene | computed peak | at (x, z) / a | theory peak | at (x, z) / a |",
        "|---|---|---|---|---|",
    ]
    for r in results:
        for m in r.metrics:
            if "field_peak" in m:
                lines.append(
                    f"| {r.name} | {m['field_peak']:.4f} | ({m['field_peak_x']:+.3f}, {m['field_peak_z']:.3f}) "
                    f"| {m['field_peak_theory']:.4f} | ({m['field_peak_x_theory']:+.3f}, {m['field_peak_z_theory']:.3f}) |"
                )
    return lines


def _figure_sections(results: list[Result], path: Path, fig_dir: Path) -> list[str]:
    lines: list[str] = []
    lines.append("")
    for r in results:
        png = fig_dir / f"{r.name}.png"
        if png.exists():
            lines += [f"## {r.name}", "", f"![{r.name}]({png.relative_to(path.parent).as_posix()})", ""]
        fields = fig_dir / f"{r.name}_fields.png"
        if fields.exists():
            lines += [f"![{r.name}: von Mises and displacement]({fields.relative_to(path.parent).as_posix()})", ""]
        if r.message:
            lines += [f"## {r.name}", "", f"Not validated: `{r.message}`", ""]
    return lines


def _sweep_tables(sweeps: dict) -> list[str]:
    lines: list[str] = []
    lines += ["## Example 2: load sweep", "", "| uy [mm] | N [N/m] | a [m] | a Hertz [m] | error | cells across 2a | time [s] |", "|---|---|---|---|---|---|---|"]
    for m in sweeps["loads"]:
        if "error" in m and isinstance(m["error"], str):
            lines.append(f"| {m['uy']*1e3:g} | {m['error']} | | | | | |")
        else:
            lines.append(f"| {m['uy']*1e3:g} | {_num(m['N'])} | {_num(m['a'])} | {_num(m['a_hertz'])} | {_pct(m['a_error'])} | {m['cells_across']:.1f} | {m['seconds']:.1f} |")
    lines += ["", "## Example 2: grid sweep", "", "| element_size | levels | cells across 2a | a [m] | a Hertz [m] | error | time [s] |", "|---|---|---|---|---|---|---|"]
    for m in sweeps["grids"]:
        if "error" in m and isinstance(m["error"], str):
            lines.append(f"| {m['element_size']} | {m['levels']} | {m['error']} | | | | |")
        else:
            lines.append(f"| {m['element_size']} | {m['levels']} | {m['cells_across']:.1f} | {_num(m['a'])} | {_num(m['a_hertz'])} | {_pct(m['a_error'])} | {m['seconds']:.1f} |")
    lines.append("")
    return lines


def write_report(results: list[Result], sweeps: dict | None, path: Path, fig_dir: Path) -> None:
    lines = [
        "# Validation report",
        "",
        "Written by `make validate` (`python -m ibfem.solver.reports.validate`): every scene of the thesis's chapter 6 in",
        "`examples/`, solved as it is, compared with theory for the forces the solver computed",
        "(`solver/reference/theory.py`). Acceptance: a within 2 % of Hertz, c/a within",
        "0.02 of Cattaneo-Mindlin, pressure RMS within 2 % of p0 inside 0.9 a and no reported pressure",
        "below -0.5 % p0, shear RMS within 5 % of mu p0 inside 0.95 a, frictionless |Q| < 1e-3 N, the",
        "largest von Mises stress below the contact within 3 % of the half-space field's (McEwen, or the",
        "Cattaneo-Mindlin superposition; the bodies' finite size moves the converged peaks 0.8-5 % above",
        "it: benchmarks/tractions.py measures the 1 % target against the grid two levels finer),",
        "and within 1 % of the converged solution of the same bodies by another code where one is stored",
        "(`solver/reference/converged.py`: NGSolve P3, `benchmarks/examples_ngsolve.py`; then that is judged).",
        "",
        f"Run on {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}.",
        "",
        "| scene | converged | N [N/m] | Q/N | a [m] | a Hertz [m] | error in a | thesis | c/a | c/a theory | error c/a | thesis | p RMS / p0 | min p / p0 | q RMS / mu p0 | vM on the axis / p0 (depth / a) | vM peak vs theory | time [s] | verdict |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines += _contact_rows(results) + _peak_table(results) + _figure_sections(results, path, fig_dir)
    if sweeps:
        lines += _sweep_tables(sweeps)
    path.write_text("\n".join(lines) + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m ibfem.solver.reports.validate", description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="skip the load and grid sweeps of example 2")
    parser.add_argument("--only", nargs="*", default=None, help="scene names (file stems) to run")
    parser.add_argument("--report", default=str(ROOT / "docs" / "validation.md"), help="report path")
    parser.add_argument("--out", default="out/validation", help="directory for the scenes' results")
    args = parser.parse_args(argv)
    report = Path(args.report)
    fig_dir = report.parent / "validation"
    fig_dir.mkdir(parents=True, exist_ok=True)
    out_root = Path(args.out)
    scenes = sorted(EXAMPLES.glob("*.toml"))
    if args.only:
        scenes = [p for p in scenes if p.stem in args.only]
    results = []
    for p in scenes:
        print(f"validate: {p.stem} ...", file=sys.stderr, flush=True)
        r = validate_scene(p, out_root, fig_dir)
        print(f"validate: {p.stem}: {'ok' if r.ok else 'FAILED ' + r.message} ({r.seconds:.1f} s)", file=sys.stderr, flush=True)
        results.append(r)
    sweeps = None if args.quick or (args.only and "mesh_convergence" not in args.only) else mesh_convergence_sweeps(out_root)
    write_report(results, sweeps, report, fig_dir)
    print(f"validate: report written to {report}", file=sys.stderr)
    return 0 if all(r.ok for r in results) else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
