"""What the fuzz campaign calls a defect: a traceback or an internal
error (exit 5), an exit code outside the documented ones, an error line that does not name the
file, exit 1 without summary.json, a converged run whose summary fails its own contact checks,
or whose normal force changes by more than 1 % when the scene is turned or shifted. Each
oracle returns the list of defects found (empty: fine)."""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import time
from pathlib import Path
from typing import Any

#: a scene check using more CPU seconds than this is a defect (the check builds nothing) ...
CHECK_SECONDS = 30.0
#: ... but a check that solves a line contact's coarse passes, as the run does (its output says
#: so), is a solve: the crowned roller's two passes take about 40 s of CPU
COARSE_PASS_CHECK_SECONDS = 90.0


def run_cli(argv: list[str]) -> tuple[int | str, str, str, float]:
    """``ibfem`` in this process: (exit code or the escaped exception, stdout, stderr, CPU seconds).

    CPU time, not wall time: a limit on it finds a check that does too much work, whatever the
    machine's load."""
    from ibfem.solver.cli import main

    out, err = io.StringIO(), io.StringIO()
    t0 = time.process_time()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code: int | str = main(argv)
        except SystemExit as exc:  # argparse
            code = int(exc.code or 0)
        except BaseException as exc:  # noqa: BLE001 - an escaped exception is the defect we look for
            code = f"{type(exc).__name__}: {exc}"
    return code, out.getvalue(), err.getvalue(), time.process_time() - t0


def _strict_json(text: str) -> Any:
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


#: exit codes of the scene checks so far (the long run reports how many scenes were valid)
CHECK_CODES: dict = {}


def check_scene_file(path: Path, allowed=(0, 2)) -> list[str]:
    """``ibfem run PATH --check``: exit 0 (valid, with the size estimate) or 2 (each line names
    the file), quickly, never a traceback."""
    code, out, err, seconds = run_cli(["run", str(path), "--check"])
    CHECK_CODES[code] = CHECK_CODES.get(code, 0) + 1
    problems = []
    if code not in allowed:
        problems.append(f"check exit {code!r}: {(err or out).strip()[:400]}")
    if "Traceback" in err or "internal error" in err:
        problems.append(f"check traceback: {err.strip()[:400]}")
    if code == 2:
        for line in err.strip().splitlines():
            if not (line.startswith(f"ibfem run: {path.name}: ") or line.startswith(f"ibfem run: {path}: ")
                    or line.startswith("ibfem run: warning: ")):
                problems.append(f"error line does not name the file: {line[:300]}")
    if code == 0 and "dofs" not in out:
        problems.append(f"check output without the size estimate: {out.strip()[:200]}")
    if seconds > (COARSE_PASS_CHECK_SECONDS if "coarse pass solved" in out else CHECK_SECONDS):
        problems.append(f"check took {seconds:.1f} s of CPU")
    return problems


def check_part_directory(directory: Path, verify: bool) -> list[str]:
    """load_part raises only OnshapeFormatError; ``ibfem verify --json`` exits 0, 1 or 2 and
    prints strict JSON."""
    from ibfem.importers import OnshapeFormatError
    from ibfem.importers.onshape.parser import load_part

    problems = []
    try:
        load_part(directory)
    except OnshapeFormatError:
        pass
    except BaseException as exc:  # noqa: BLE001
        problems.append(f"load_part raised {type(exc).__name__}: {str(exc)[:300]}")
    if verify:
        code, out, err, _ = run_cli(["verify", str(directory), "--json"])
        if code not in (0, 1, 2):
            problems.append(f"verify exit {code!r}: {err.strip()[:300]}")
        if "Traceback" in err:
            problems.append(f"verify traceback: {err.strip()[:300]}")
        if code in (0, 1) and out.strip():
            try:
                _strict_json(out)
            except ValueError as exc:
                problems.append(f"verify --json is not strict JSON: {exc}")
    return problems


def contact_consistent(contact: dict) -> bool:
    checks = contact.get("checks") or {}
    return (not checks.get("penetration_found") and not checks.get("tension_at_region_edges")
            and not checks.get("overlapping_samples_outside_region"))


def run_scene(path: Path, out: Path, timeout: float) -> tuple[list[str], dict | None]:
    """``ibfem run`` in a child process with a time limit and a memory limit: exit 0/1/2 only,
    exit 1 with summary.json, a converged summary consistent with its own contact checks."""
    import subprocess
    import sys

    problems: list[str] = []
    env = dict(os.environ, MPLBACKEND="Agg", OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    try:
        r = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(path), "--quiet", "--out", str(out)],
                           capture_output=True, text=True, timeout=timeout, env=env, preexec_fn=_limit_memory)
    except subprocess.TimeoutExpired:
        return [f"run timed out after {timeout:.0f} s"], None
    summary_path = out / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else None
    if r.returncode not in (0, 1, 2):
        problems.append(f"run exit {r.returncode}: {r.stderr.strip()[-400:]}")
    if "Traceback" in r.stderr:
        problems.append(f"run traceback: {r.stderr.strip()[-400:]}")
    if r.returncode == 1 and summary is None:
        problems.append("exit 1 without summary.json")
    if r.returncode == 0 and summary is not None:
        for c in summary.get("contacts", []):
            if not contact_consistent(c):
                problems.append(f"converged but the contact checks fail: {c.get('checks')}")
    return problems, summary if r.returncode == 0 else None


def _limit_memory() -> None:  # pragma: no cover - runs in the child
    import resource

    limit = int(float(os.environ.get("IBFEM_FUZZ_MEMORY_GB", "6")) * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def forces_agree(a: dict, b: dict, rel: float = 0.01) -> list[str]:
    """Normal forces of two converged summaries of the same scene moved rigidly, to ``rel``."""
    problems = []
    for ca, cb in zip(a.get("contacts", []), b.get("contacts", [])):
        na, nb = ca.get("normal_force"), cb.get("normal_force")
        if not (isinstance(na, (int, float)) and isinstance(nb, (int, float))):
            continue
        scale = max(abs(na), abs(nb))
        if scale > 0 and not math.isclose(na, nb, rel_tol=rel):
            problems.append(f"normal force {na:.6g} vs {nb:.6g} turned/shifted ({abs(na - nb) / scale:.3%})")
    return problems
