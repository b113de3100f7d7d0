"""The peer study (``make bench-peers``): ibfem beside NGSolve P2 on the same contact
problem, time to error.

Problem (benchmarks/scenes/peer_half_disc.toml): lower half disc R = 1 centred (0, 1) on the block
[-2, 2] x [-2, 0], plane strain, the block's bottom fixed, the disc's flat top moved by
(0, -0.0107), frictionless. ``steel``: both E 2e11, nu 0.3; ``aluminium``: the disc E 7e10,
nu 0.33 on the steel block. Errors in the half-width a and the normal force N against the
converged references below (docs/peers.md says how they were obtained).

Each run is its own process (``ibfem run`` on a scene generated from the base scene with the
rung's element size and refinement levels, VTU and plots off; ``benchmarks/peers_ngsolve.py``
for NGSolve), the two ladders interleaved (ibfem, NGSolve, ibfem, ...), each rung ``--repeat``
times (the fastest kept). Wall time is the child process's whole life (imports, meshing, solve,
output); CPU time and peak memory (maximum resident set) come from ``os.wait4``. NGSolve's a is
reported twice: where its gap closes (the definition) and from a fit of the gap opening
(docs/peers.md). The time to reach 1 %, 0.3 % and 0.1 % error in a is interpolated on each
ladder (log-log between the last rung above and the first rung at or below the error, on the
running best error), the ratio NGSolve/ibfem printed beside it, on wall and on CPU time.

The 3D problem (``--problem sphere3d``): examples/solid/sphere_on_flat.toml, a quarter of
the half ball R = 1 on the block [0, 1] x [0, 1] x [-1, 0], steel on steel, frictionless, the
symmetry faces sliding; ibfem over element sizes and refinement levels (probes, lines, VTU and
plots off), NGSolve P2 on curved tetrahedra (``benchmarks/peers_ngsolve3d.py``) over h_c. The error
in a is against Hertz for each run's own force (:func:`hertz_sphere_radius`, as
docs/validation-solid.md does), at 1 % and 0.3 %.

    python benchmarks/peers.py [--quick] [--problem steel|aluminium|all|sphere3d] [--repeat N]
    python benchmarks/peers.py --report benchmarks/results/peers.json   # the tables again, no runs

Writes benchmarks/results/peers.json and peers.md (peers3d.json and peers3d.md for sphere3d). Needs
the ``peers`` extra (ngsolve).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BASE_SCENE = HERE / "scenes" / "peer_half_disc.toml"
RESULTS = HERE / "results"
TARGETS = (0.01, 0.003, 0.001)

STEEL = (2.0e11, 0.3)
ALUMINIUM = (7.0e10, 0.33)
# Converged references (docs/peers.md): NGSolve P3, curved, gap along the frame normal between
# points at the same x, a from the fitted gap opening, meshes h_c 0.004 .. 0.00025 agreeing to
# 6e-5 (a) and 1.5e-5 (N). The issue's own steel reference is kept beside it ("issue").
PROBLEMS = {
    "steel": {"disc": STEEL, "block": STEEL, "a": 0.076644, "N": 5.09190e8,
              "issue": {"a": 0.076667, "N": 5.09216e8}},
    "aluminium": {"disc": ALUMINIUM, "block": STEEL, "a": 0.078940, "N": 2.84707e8},
}
# (element_size, refinement levels, radius of the deepest zone) of both bodies: the deepest zone
# 0.12 m about the contact (the width NGSolve's ladder grades to h_c), then a zone one level
# coarser at every doubling of the radius, as ibfem's accuracy ladder grades a far field
# (solver.solving.graded_around_contacts): the cells grow in proportion to the distance
IBFEM_LADDER = [(0.2, 4, 0.12), (0.2, 5, 0.12), (0.2, 6, 0.12), (0.2, 7, 0.12)]
# the ladder of the earlier tables (``--ibfem-ladder uniform``): the base scene's one zone of
# radius 0.3 m, the far field uniform
IBFEM_LADDER_UNIFORM = [(0.1, 2), (0.1, 3), (0.05, 3), (0.05, 4), (0.05, 5)]
# NGSolve: (element size along the contact h_c, largest element size)
NGSOLVE_LADDER = [(0.016, 0.25), (0.008, 0.25), (0.004, 0.2), (0.002, 0.1), (0.001, 0.1), (0.0005, 0.05), (0.00025, 0.05)]
QUICK_IBFEM = [(0.2, 5, 0.12), (0.2, 6, 0.12)]
QUICK_NGSOLVE = [(0.004, 0.2), (0.002, 0.1)]

# The 3D problem: the shipped scene, steel on steel; a against Hertz for each run's own force
SPHERE_SCENE = ROOT / "examples" / "solid" / "sphere_on_flat.toml"
SPHERE3D = {"E": 2.0e11, "nu": 0.3, "R": 1.0, "model_share": 4, "reference": "Hertz for the run's own force"}
TARGETS_3D = (0.01, 0.003)
# (element_size, refinement levels) of both bodies, the refinement radius as shipped (0.07); the
# finest cell shrinks by about 1.1-1.25 per rung near the targets (h0 0.225 with 6 levels between
# 0.25 and 0.2), so that the rung reaching an error is not far past it
IBFEM_LADDER_3D = [(0.25, 4), (0.25, 5), (0.2, 5), (0.25, 6), (0.225, 6), (0.2, 6)]
# NGSolve: (element size on the contact surfaces h_c, largest element size), as dense near the
# targets (h_c 0.01 between 0.012 and 0.008)
NGSOLVE_LADDER_3D = [(0.024, 0.2), (0.02, 0.2), (0.016, 0.2), (0.012, 0.2), (0.01, 0.2), (0.008, 0.2)]
QUICK_IBFEM_3D = [(0.25, 4), (0.25, 5)]
QUICK_NGSOLVE_3D = [(0.024, 0.2), (0.016, 0.2)]


def hertz_sphere_radius(model_force: float, radius: float, youngs_modulus: float, poissons_ratio: float,
                        model_share: int = 1) -> float:
    """Hertz's contact radius of a sphere on a flat of the same material (Johnson eq. 4.22):
    a = (3 N R / (4 E*))^(1/3), 1/E* = 2 (1 - nu^2) / E, N = model_share x the model's force (4 for
    a quarter model)."""
    if not (model_force > 0.0 and radius > 0.0 and youngs_modulus > 0.0 and -1.0 < poissons_ratio < 0.5):
        raise ValueError(f"Hertz radius needs a positive force, radius and E and -1 < nu < 0.5 (got N "
                         f"{model_force}, R {radius}, E {youngs_modulus}, nu {poissons_ratio})")
    e_star = youngs_modulus / (2.0 * (1.0 - poissons_ratio ** 2))
    return (3.0 * model_share * model_force * radius / (4.0 * e_star)) ** (1.0 / 3.0)


def graded_zones(levels: int, radius: float) -> list[dict]:
    """Refinement zones about the contact: ``levels`` within ``radius``, then one level fewer at
    every doubling of the radius, down to one level."""
    return [{"levels": n, "around": "contact", "radius": radius * 2.0 ** (levels - n)}
            for n in range(levels, 0, -1)]


def scene_data(problem: str, element_size: float, levels: int, radius: float | None = None) -> dict:
    """The base scene with this problem's materials and this rung's grids, VTU and plots off:
    with ``radius``, the zones of :func:`graded_zones`; without, the base scene's zone with
    ``levels``."""
    data = tomllib.loads(BASE_SCENE.read_text())
    spec = PROBLEMS[problem]
    data["materials"] = [
        {"name": "disc_material", "youngs_modulus": spec["disc"][0], "poissons_ratio": spec["disc"][1]},
        {"name": "block_material", "youngs_modulus": spec["block"][0], "poissons_ratio": spec["block"][1]},
    ]
    for body in data["bodies"]:
        body["material"] = f"{body['name']}_material"
        body["element_size"] = element_size
        if radius is not None:
            body["refinement"] = graded_zones(levels, radius)
        for ref in body.get("refinement") or []:
            ref["levels"] = ref["levels"] if radius is not None else levels
    graded = f" graded from {radius}" if radius is not None else ""
    data["name"] = f"peer {problem} h0 {element_size} levels {levels}{graded}"
    data.setdefault("output", {}).update(vtk=False, plots=False)
    return data


def sphere_scene_data(element_size: float, levels: int) -> dict:
    """sphere_on_flat with this rung's grids (both bodies), VTU, plots, probes and lines off."""
    data = tomllib.loads(SPHERE_SCENE.read_text())
    for body in data["bodies"]:
        body["element_size"] = element_size
        body["refinement"]["levels"] = levels
    data["name"] = f"peer sphere3d h0 {element_size} levels {levels}"
    data["output"] = {"vtk": False, "plots": False}
    return data


def run_child(cmd: list[str]) -> tuple[int, str, str, float, float, float]:
    """Runs one process: return code, stdout, stderr, wall time (s), peak resident memory (MB),
    CPU time (user + system, s)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=out, stderr=err, cwd=ROOT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return (proc.returncode, out.read(), err.read(), wall, usage.ru_maxrss / 1024.0,
                usage.ru_utime + usage.ru_stime)


def run_ibfem(problem: str, element_size: float, levels: int, workdir: Path, radius: float | None = None) -> dict:
    tag = f"ibfem_{problem}_{element_size}_{levels}_{radius}"
    scene = workdir / f"{tag}.json"
    data = (sphere_scene_data(element_size, levels) if problem == "sphere3d"
            else scene_data(problem, element_size, levels, radius))
    scene.write_text(json.dumps(data))
    graded = f", graded from r {radius}" if radius is not None else ""
    row = {"code": "ibfem", "problem": problem, "rung": f"h0 {element_size}, {levels} levels{graded}",
           "element_size": element_size, "levels": levels}
    if radius is not None:
        row["radius"] = radius
    return ibfem_row(scene, workdir / tag, row)


def ibfem_row(scene: Path, out: Path, row: dict) -> dict:
    """``row`` with one ``ibfem run SCENE`` (its own process, results into ``out``, no error
    estimate: the peer computes none either, and ibfem's costs a second, coarser solve): wall and
    CPU seconds, peak memory, exit code and, when it ran to the end, the first contact's a (3D: the
    first semi-axis), N, p0, the dofs, the iterations and the solver's seconds."""
    ibfem = Path(sys.executable).with_name("ibfem")
    code, _, err, wall, peak, cpu = run_child([str(ibfem), "run", str(scene), "--out", str(out), "--quiet",
                                               "--no-estimate"])
    row.update(wall_s=wall, cpu_s=cpu, peak_mb=peak, exit=code)
    if code not in (0, 1):
        row["error"] = err.strip().splitlines()[-1:] if err.strip() else [f"exit {code}"]
        return row
    summary = json.loads((out / "summary.json").read_text())
    contact = summary["contacts"][0]
    a = contact["semi_axes"][0] if "semi_axes" in contact else contact["half_width"]
    row.update(converged=bool(summary["converged"]), a=a, N=contact["normal_force"], p0=contact.get("max_pressure"),
               dofs=sum(b["dofs"] for b in summary["bodies"].values()),
               iterations=summary["iterations"]["total"], solver_s=summary["timings"].get("solver_total_s"))
    return row


def _ngsolve_row(cmd: list[str], label: str, problem: str, hc: float, hmax: float) -> tuple[dict, dict | None]:
    """Run one NGSolve child: (the table row, the child's JSON result or None when it failed)."""
    code, out, err, wall, peak, cpu = run_child(cmd)
    row = {"code": label, "problem": problem, "rung": f"h_c {hc}, h_max {hmax}", "hc": hc,
           "hmax": hmax, "wall_s": wall, "cpu_s": cpu, "peak_mb": peak, "exit": code}
    if code != 0:
        row["error"] = err.strip().splitlines()[-1:] if err.strip() else [f"exit {code}"]
        return row, None
    res = json.loads(out.strip().splitlines()[-1])
    row.update(converged=True, a=res["a_closing"], a_fit=res["a"], N=res["N"], dofs=res["dofs"],
               iterations=res["newton_iterations"], solver_s=res["total_in_process_s"])
    return row, res


def run_ngsolve(problem: str, hc: float, hmax: float, order: int = 2, threads: int = 2) -> dict:
    spec = PROBLEMS[problem]
    cmd = [sys.executable, str(HERE / "peers_ngsolve.py"), "--hc", str(hc), "--hmax", str(hmax), "--threads", str(threads),
           "--order", str(order), "--disc-E", str(spec["disc"][0]), "--disc-nu", str(spec["disc"][1]),
           "--block-E", str(spec["block"][0]), "--block-nu", str(spec["block"][1])]
    return _ngsolve_row(cmd, f"NGSolve P{order}", problem, hc, hmax)[0]


def run_ngsolve3d(hc: float, hmax: float, threads: int = 2) -> dict:
    cmd = [sys.executable, str(HERE / "peers_ngsolve3d.py"), "--hc", str(hc), "--hmax", str(hmax),
           "--threads", str(threads), "--E", str(SPHERE3D["E"]), "--nu", str(SPHERE3D["nu"])]
    row, res = _ngsolve_row(cmd, "NGSolve P2", "sphere3d", hc, hmax)
    if res is not None:
        row.update(a_lines=res["a_closing_lines"], a_fit_lines=res["a_lines"])
    return row


def best_of(run, repeat: int) -> dict:
    """The run repeated: the fastest of ``repeat`` (the results are deterministic; the machine is shared)."""
    rows = [run() for _ in range(repeat)]
    best = min(rows, key=lambda r: r["wall_s"])
    best["wall_all_s"] = [r["wall_s"] for r in rows]
    best["cpu_all_s"] = [r["cpu_s"] for r in rows]
    best["peak_mb"] = max(r["peak_mb"] for r in rows)
    return best


def add_errors(row: dict) -> dict:
    if row["problem"] == "sphere3d":
        return add_hertz_errors(row)
    spec = PROBLEMS[row["problem"]]
    for key in ("a", "a_fit", "N"):
        if key in row:
            row[f"{key}_error"] = row[key] / spec[key[0]] - 1.0
            if "issue" in spec:
                row[f"{key}_error_issue"] = row[key] / spec["issue"][key[0]] - 1.0
    if "N_error" in row:     # the larger of the two errors: "within 0.1 % in a and N"
        for key in ("a", "a_fit"):
            if f"{key}_error" in row:
                row[f"{key}N_error"] = max(abs(row[f"{key}_error"]), abs(row["N_error"]))
    return row


def add_hertz_errors(row: dict) -> dict:
    """The 3D rows: a (and NGSolve's fitted a) against Hertz for the row's own force."""
    if isinstance(row.get("N"), float) and row["N"] > 0.0:
        s = SPHERE3D
        row["a_hertz"] = hertz_sphere_radius(row["N"], s["R"], s["E"], s["nu"], s["model_share"])
        for key in ("a", "a_fit"):
            if key in row:
                row[f"{key}_error"] = row[key] / row["a_hertz"] - 1.0
    return row


def cross_check(rows: list[dict]) -> dict | None:
    """The two codes' finest rungs (most dofs) side by side: a, N, and a / a_Hertz (NGSolve's fitted a)."""
    ib = [r for r in rows if r["code"] == "ibfem" and "a_error" in r]
    ng = [r for r in rows if r["code"].startswith("NGSolve") and "a_fit_error" in r]
    if not ib or not ng:
        return None
    i, n = max(ib, key=lambda r: r["dofs"]), max(ng, key=lambda r: r["dofs"])
    return {"ibfem": i["rung"], "ngsolve": n["rung"], "a_ibfem": i["a"], "a_ngsolve_fit": n["a_fit"],
            "a_difference": i["a"] / n["a_fit"] - 1.0, "N_difference": i["N"] / n["N"] - 1.0,
            "a_over_hertz_difference": (1.0 + i["a_error"]) / (1.0 + n["a_fit_error"]) - 1.0}


def time_to_error(rows: list[dict], target: float, key: str = "a_error", clock: str = "wall_s") -> dict | None:
    """Time (``clock``: wall_s or cpu_s) and peak memory to reach |error| <= target on one ladder
    (None: never)."""
    pts = sorted((r[clock], abs(r[key]), r["peak_mb"]) for r in rows
                 if isinstance(r.get(key), float) and math.isfinite(r[key]))
    best, prev = math.inf, None
    for wall, err, peak in pts:
        if err < best:
            if err <= target:
                if prev is None or prev[1] <= 0 or err <= 0:
                    return {"time_s": wall, "peak_mb": peak, "bound": prev is None}
                f = (math.log(target) - math.log(prev[1])) / (math.log(err) - math.log(prev[1]))
                t = math.exp(math.log(prev[0]) + f * (math.log(wall) - math.log(prev[0])))
                return {"time_s": t, "peak_mb": peak, "bound": False}
            best, prev = err, (wall, err)
    return None


def comparison(rows: list[dict], problem: str, ng_key: str = "a_error", targets=TARGETS,
               ib_key: str = "a_error") -> list[dict]:
    """Time to each target error, ibfem's ``ib_key`` against NGSolve's ``ng_key``: ``a_error``
    (a, NGSolve's where its gap closes), ``a_fit_error`` (NGSolve's fitted opening), or with N
    too, ``aN_error`` / ``a_fitN_error`` (the larger of the errors in a and N)."""
    out = []
    ib = [r for r in rows if r["problem"] == problem and r["code"] == "ibfem"]
    ng = [r for r in rows if r["problem"] == problem and r["code"].startswith("NGSolve")]
    for target in targets:
        ti, tn = time_to_error(ib, target, ib_key), time_to_error(ng, target, ng_key)
        ci, cn = time_to_error(ib, target, ib_key, "cpu_s"), time_to_error(ng, target, ng_key, "cpu_s")
        out.append({"problem": problem, "ngsolve_a": "gap opening fit" if ng_key.startswith("a_fit") else "gap closing",
                    "of": "a and N" if ib_key == "aN_error" else "a", "target": target, "ibfem": ti, "ngsolve": tn,
                    "ratio": tn["time_s"] / ti["time_s"] if ti and tn else None,
                    "ibfem_cpu": ci, "ngsolve_cpu": cn,
                    "ratio_cpu": cn["time_s"] / ci["time_s"] if ci and cn else None})
    return out


def comparisons_2d(rows: list[dict], problems: list[str]) -> list[dict]:
    """The 2D problems' times to each error in a and N (the larger of the two), NGSolve's a read
    both ways."""
    return [c for p in problems for key in ("aN_error", "a_fitN_error")
            for c in comparison(rows, p, key, ib_key="aN_error")]


def fmt_row(r: dict) -> str:
    if "a" not in r:
        return (f"| {r['problem']} | {r['code']} | {r['rung']} | | | {r['wall_s']:.2f} | {r['cpu_s']:.2f} "
                f"| {r['peak_mb']:.0f} | failed: {r.get('error')} | | |")
    fit = f"{r['a_fit']:.6f} ({100 * r['a_fit_error']:+.3f} %)" if "a_fit" in r else ""
    unconverged = ", not converged" if r.get("converged") is False else ""
    force = f"{r['N']:.5e} ({100 * r['N_error']:+.3f} %)" if "N_error" in r else f"{r['N']:.5e}"
    return (f"| {r['problem']} | {r['code']} | {r['rung']} | {r['dofs']} | {r['iterations']} | {r['wall_s']:.2f} "
            f"| {r['cpu_s']:.2f} | {r['peak_mb']:.0f} | {r['a']:.6f} ({100 * r['a_error']:+.3f} %{unconverged}) | {fit} "
            f"| {force} |")


def fmt_cmp(c: dict) -> str:
    def cell(t):
        if t is None:
            return "not reached"
        return f"{'<= ' if t['bound'] else ''}{t['time_s']:.2f} s, {t['peak_mb']:.0f} MB"
    def ratio(x):
        return f"{x:.2f}" if x else "-"
    return (f"| {c['problem']} | {c['ngsolve_a']} | {100 * c['target']:g} % | {cell(c['ibfem'])} "
            f"| {cell(c['ngsolve'])} | {ratio(c['ratio'])} | {ratio(c['ratio_cpu'])} |")


def write_results(rows: list[dict], cmps: list[dict], quick: bool, stem: str = "peers",
                  references: dict = PROBLEMS, extra: dict | None = None) -> str:
    lines = ["| problem | code | rung | dofs | iterations | wall (s) | CPU (s) | peak (MB) | a (error) "
             "| a, NGSolve's gap-opening fit (error) | N (error) |",
             "|---|---|---|---|---|---|---|---|---|---|---|", *map(fmt_row, rows), "",
             f"| problem | NGSolve's a | error in {cmps[0].get('of', 'a') if cmps else 'a'} | ibfem (wall, memory) | NGSolve P2 (wall, memory) "
             "| NGSolve / ibfem, wall | same, CPU time |", "|---|---|---|---|---|---|---|", *map(fmt_cmp, cmps)]
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    suffix = "_quick" if quick else ""
    (RESULTS / f"{stem}{suffix}.json").write_text(json.dumps(
        {"references": references, "rows": rows, "comparison": cmps, "quick": quick, **(extra or {})}, indent=2))
    command = "benchmarks/peers.py" + (" --problem sphere3d" if stem == "peers3d" else "") + (" --quick" if quick else "")
    title = "3D peer study" if stem == "peers3d" else "Peer study"
    (RESULTS / f"{stem}{suffix}.md").write_text(f"# {title} ({command})\n\n{text}\n")
    return text


#: the package's source folders (setup.py maps ibfem.geometry, ibfem.importers and ibfem.solver to them)
PACKAGE_DIRS = ("geometry", "importers", "solver", "ibfem")


def compile_bytecode() -> int:
    """Writes the bytecode of ibfem's modules into their ``__pycache__`` folders once, before the
    timed runs, and returns how many files it compiled. An environment with
    ``PYTHONDONTWRITEBYTECODE`` set (this machine's shells have it) never writes it, so every
    ``ibfem run`` would compile each module it imports from source again, about 0.18 s of CPU in a
    small 2D run (docs/peers.md); an installed package has its bytecode, and Python reads it
    whatever that variable says. NGSolve's solver is compiled code."""
    import compileall
    import io
    from contextlib import redirect_stdout

    count = 0
    for name in PACKAGE_DIRS:
        folder = ROOT / name
        if folder.is_dir():
            with redirect_stdout(io.StringIO()):
                compileall.compile_dir(folder, quiet=2, workers=1)
            count += sum(1 for _ in folder.rglob("*.py"))
    return count


def check_ngsolve() -> None:
    r = subprocess.run([sys.executable, "-c", "import ngsolve"], capture_output=True)
    if r.returncode != 0:
        raise SystemExit("benchmarks/peers.py needs NGSolve: pip install -e '.[peers]' (the `peers` extra)")


def warn_load() -> float:
    load = os.getloadavg()[0]
    if load > 0.5:
        print(f"warning: load average {load:.1f} before the runs: wall times include other processes' "
              "(compare cpu_s in the JSON, or rerun on a quiet machine)", file=sys.stderr)
    return load


def interleaved(problems: list[str], ib_runs: list, ng_runs: list, repeat: int) -> list[dict]:
    """The two ladders' runs in turn (ibfem rung 1, NGSolve rung 1, ibfem rung 2, ...), each rung
    ``repeat`` times; ``ib_runs`` / ``ng_runs`` are functions of (problem) -> row."""
    rows = []
    for problem in problems:
        for i in range(max(len(ib_runs), len(ng_runs))):
            for runs in (ib_runs, ng_runs):
                if i < len(runs):
                    rows.append(add_errors(best_of(lambda f=runs[i], p=problem: f(p), repeat)))
                    print(fmt_row(rows[-1]), flush=True)
    return rows


def study_3d(args, tmp: Path) -> tuple[list[dict], list[dict], dict]:
    """The sphere_on_flat ladders (or, with --report, their rows again): rows, comparison, extras."""
    if args.report:
        data = json.loads(args.report.read_text())
        rows, extra = [add_errors(r) for r in data["rows"]], {k: data[k] for k in ("load_average", "load_average_after") if k in data}
    else:
        extra = {"load_average": warn_load()}
        ib = QUICK_IBFEM_3D if args.quick else IBFEM_LADDER_3D
        ng = QUICK_NGSOLVE_3D if args.quick else NGSOLVE_LADDER_3D
        rows = interleaved(["sphere3d"], [lambda p, r=r: run_ibfem(p, *r, tmp) for r in ib],
                           [lambda p, r=r: run_ngsolve3d(*r, threads=args.ngsolve_threads) for r in ng], args.repeat)
        extra["load_average_after"] = os.getloadavg()[0]
    cmps = [c for key in ("a_error", "a_fit_error") for c in comparison(rows, "sphere3d", key, TARGETS_3D)]
    extra["cross_check"] = cross_check(rows)
    return rows, cmps, extra


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="two rungs per code (a smoke check)")
    ap.add_argument("--problem", choices=["steel", "aluminium", "all", "sphere3d"], default="all",
                    help="all: the two 2D problems; sphere3d: the 3D problem")
    ap.add_argument("--repeat", type=int, default=2, help="runs per rung, the fastest kept (default 2: the machine may be shared)")
    ap.add_argument("--ngsolve-threads", type=int, default=2, help="NGSolve's TaskManager threads (default 2)")
    ap.add_argument("--report", type=Path, help="no runs: the tables again from the rows of this peers.json")
    ap.add_argument("--ibfem-ladder", choices=["graded", "uniform"], default="graded",
                    help="2D: ibfem's grids graded about the contact (default) or the earlier tables' uniform far field")
    args = ap.parse_args(argv)
    if not args.report:
        compile_bytecode()
    if args.problem == "sphere3d":
        if not args.report:
            check_ngsolve()
        with tempfile.TemporaryDirectory(prefix="ibfem_peers3d_") as tmp:
            rows, cmps, extra = study_3d(args, Path(tmp))
        print()
        print(write_results(rows, cmps, args.quick, "peers3d", {"sphere3d": SPHERE3D}, extra))
        print(f"\ncross-check (finest rungs): {json.dumps(extra['cross_check'])}")
        return 0 if all("a" in r for r in rows) else 1
    problems = ["steel", "aluminium"] if args.problem == "all" else [args.problem]
    if args.report:
        rows = [add_errors(r) for r in json.loads(args.report.read_text())["rows"] if r["problem"] in problems]
        cmps = comparisons_2d(rows, problems)
        print(write_results(rows, cmps, args.quick))
        return 0
    check_ngsolve()
    extra = {"load_average": warn_load(), "ibfem_ladder": "quick" if args.quick else args.ibfem_ladder}
    ib_ladder = QUICK_IBFEM if args.quick else IBFEM_LADDER if args.ibfem_ladder == "graded" else IBFEM_LADDER_UNIFORM
    ng_ladder = QUICK_NGSOLVE if args.quick else NGSOLVE_LADDER
    with tempfile.TemporaryDirectory(prefix="ibfem_peers_") as tmp:
        rows = interleaved(problems, [lambda p, r=r: run_ibfem(p, r[0], r[1], Path(tmp), *r[2:]) for r in ib_ladder],
                           [lambda p, r=r: run_ngsolve(p, *r, threads=args.ngsolve_threads) for r in ng_ladder],
                           args.repeat)
    extra["load_average_after"] = os.getloadavg()[0]
    ok = all("a" in r for r in rows)
    previous = RESULTS / f"peers{'_quick' if args.quick else ''}.json"
    if args.problem != "all" and previous.exists():   # keep the other problem's rows
        rows += [r for r in json.loads(previous.read_text())["rows"] if r["problem"] not in problems]
        problems = [p for p in PROBLEMS if any(r["problem"] == p for r in rows)]
        rows.sort(key=lambda r: problems.index(r["problem"]))
    cmps = comparisons_2d(rows, problems)
    print()
    print(write_results(rows, cmps, args.quick, extra=extra))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
