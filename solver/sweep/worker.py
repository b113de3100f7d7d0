"""What runs on a worker: one case from its scene data to a result record.

:func:`run_case` is the task the engine submits (to Dask workers, or called in-process by
``--serial``). The case travels as data (scene dict, and the files its shapes read); the
result travels back as data (status, message, summary and the files of the case's result
directory), so workers need no disk shared with the driver. With a time limit the case runs
in a child process (``python -m ibfem.solver.sweep.worker DIR``) that is killed when the limit
passes; a child killed by a signal (the kernel's out-of-memory killer, a crash) is a ``killed``
case and the worker lives on.
"""

from __future__ import annotations

import os
import pickle
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

#: statuses of a case (``killed``: its worker or process died running it)
STATUSES = ("ok", "not_converged", "error", "timeout", "invalid", "killed")


def fingerprint() -> str:
    """The installed ibfem: ``VERSION+HASH``, its version and a hash of the sources of its three
    packages (so a worker whose sources differ from the driver's is noticed too)."""
    import hashlib
    from importlib import metadata

    try:
        version = metadata.version("ibfem")
    except metadata.PackageNotFoundError:
        version = "unknown"
    root = Path(__file__).resolve().parents[2]
    h = hashlib.sha256()
    for package in ("geometry", "importers", "solver"):
        for p in sorted((root / package).rglob("*.py")):
            h.update(p.relative_to(root).as_posix().encode())
            h.update(p.read_bytes())
    return f"{version}+{h.hexdigest()[:12]}"


def where() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


#: a small contact scene a fresh worker solves once, so that imports and first-call costs (numba
#: kernels, caches) are paid while the driver still prepares the cases
_WARM_SCENE = {
    "name": "warm-up", "model": "plane_strain", "solver": {"load_steps": 1},
    "materials": [{"name": "m", "youngs_modulus": 2.0e11, "poissons_ratio": 0.3}],
    "bodies": [{"name": "c", "material": "m", "element_size": 0.25,
                "shape": {"type": "half_disk", "center": [0, 1], "radius": 1.0, "side": "below"}},
               {"name": "b", "material": "m", "element_size": 0.25,
                "shape": {"type": "rectangle", "min": [-1.5, -1.0], "max": [1.5, 0.0]}}],
    "boundary_conditions": [{"body": "c", "edge": "flat", "type": "displacement", "value": [0.0, -2e-3]},
                            {"body": "b", "edge": "bottom", "type": "fixed"}],
    "contacts": [{"bodies": ["c", "b"], "type": "frictional", "friction": 0.3, "point": [0, 0]}],
    "output": {"vtk": False, "plots": False},
}


def warm_up() -> str:
    """Import the solver and solve a tiny scene (a worker's first case is then not slower), and
    load the compiled kernels the tiny scene is too small to use (the multifrontal Cholesky of
    larger condensed systems: 0.3-0.5 s of numba's start-up and cache loading, measured as the
    first case's extra time in each worker)."""
    with tempfile.TemporaryDirectory(prefix="ibfem-warm-") as tmp:
        solve_case(dict(_WARM_SCENE), "warm-up", Path(tmp), Path(tmp) / "out")
    _load_factor_kernels()
    return fingerprint()


def _load_factor_kernels() -> None:
    import numpy as np
    import scipy.sparse as sp

    from ibfem.solver.fem import multifrontal

    if not multifrontal.available():
        return
    n = 40  # a chain of springs, two dofs per node, the last four condensed
    lap = sp.diags([-np.ones(n // 2 - 1), 2.0 * np.ones(n // 2), -np.ones(n // 2 - 1)], [-1, 0, 1])
    k = sp.kron(lap + sp.identity(n // 2), sp.identity(2), format="csr")
    factor, _, _ = multifrontal.condensed_cholesky(k, np.arange(n), 4)
    factor.solve(np.ones(n))


def _reset_peak() -> None:
    try:  # Linux: "5" resets the process's peak resident set size (VmHWM)
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass


def _peak_mb() -> float | None:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return round(int(line.split()[1]) / 1024, 1)
    except (OSError, ValueError, IndexError):
        pass
    try:
        import resource

        return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)
    except (ImportError, OSError):
        return None


def _first_line(err: BaseException) -> str:
    text = str(err).strip().splitlines()
    return f"{type(err).__name__}: {text[0]}" if text else type(err).__name__


def solve_case(scene_data: dict, label: str, base_dir: Path, out: Path) -> tuple[str, str, dict | None]:
    """Validate, solve and write one case: (status, message, summary)."""
    from ibfem.solver.io.output import write_scene_results
    from ibfem.solver.io.scene import SceneError, scene_from_dict
    from ibfem.solver.solving import solve

    t0 = time.perf_counter()
    try:
        scene = scene_from_dict(scene_data, label=label, base_dir=base_dir)
    except SceneError as err:
        return "invalid", str(err).replace("\n", "; "), None
    try:
        solution = solve(scene.problem)
        summary = write_scene_results(out, scene, solution, total_s=time.perf_counter() - t0)
    except MemoryError:
        return "error", "out of memory: coarsen the grid", None
    except Exception as err:  # noqa: BLE001 - a failing case is recorded, the others go on
        return "error", _first_line(err), None
    if summary.get("converged"):
        return "ok", "", summary
    return "not_converged", f"not converged after {summary['iterations']['total']} iterations", summary


def _write_files(files: dict[str, bytes], root: Path) -> None:
    for rel, data in files.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(data)


def _read_files(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()} \
        if root.is_dir() else {}


def _in_process(payload: dict) -> dict:
    with tempfile.TemporaryDirectory(prefix="ibfem-case-") as tmp:
        base_dir = Path(payload.get("base_dir") or ".")
        if payload.get("files"):
            base_dir = Path(tmp) / "files"
            _write_files(payload["files"], base_dir)
        out = Path(tmp) / "out"
        _reset_peak()
        status, message, summary = solve_case(payload["scene"], payload["label"], base_dir, out)
        return {"status": status, "message": message, "summary": summary, "files": _read_files(out),
                "peak_memory_mb": _peak_mb()}


def _in_child(payload: dict, timeout: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="ibfem-case-") as tmp:
        with open(Path(tmp) / "payload.pkl", "wb") as f:
            pickle.dump(payload, f)
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
        child = subprocess.Popen([sys.executable, "-m", "ibfem.solver.sweep.worker", tmp], env=env,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        try:
            _, err = child.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            child.kill()
            child.communicate()
            return {"status": "timeout", "message": f"still running after {timeout:g} s (--case-timeout); stopped"}
        result = Path(tmp) / "result.pkl"
        if child.returncode == 0 and result.is_file():
            with open(result, "rb") as f:
                return pickle.load(f)
        if child.returncode < 0:
            return {"status": "killed", "message": f"the case's process was killed by signal {-child.returncode}"
                    + (" (out of memory?)" if -child.returncode == 9 else "")}
        tail = err.decode(errors="replace").strip().splitlines()[-1:] or ["no message"]
        return {"status": "error", "message": f"the case's process failed (exit {child.returncode}): {tail[0]}"}


def run_case(payload: dict) -> dict[str, Any]:
    """The task: one case (scene data) -> its result record (status, message, summary, the
    result directory's files, wall time, peak memory, where it ran)."""
    t0 = time.perf_counter()
    expected, mine = payload.get("fingerprint"), fingerprint()
    if expected and expected.split("+")[0] != mine.split("+")[0]:
        result = {"status": "error", "message": f"ibfem on this worker is {mine}, the driver's is "
                  f"{expected}: install the same version on every worker"}
    elif payload.get("timeout"):
        result = _in_child({**payload, "timeout": None}, float(payload["timeout"]))
    else:
        result = _in_process(payload)
    result.setdefault("summary", None)
    result.setdefault("files", {})
    result.setdefault("peak_memory_mb", None)
    result.update(hash=payload["hash"], wall_s=round(time.perf_counter() - t0, 3), worker=where(), ibfem=mine)
    return result


def _child_main(directory: str) -> int:
    """``python -m ibfem.solver.sweep.worker DIR``: run DIR/payload.pkl, write DIR/result.pkl."""
    d = Path(directory)
    with open(d / "payload.pkl", "rb") as f:
        payload = pickle.load(f)
    result = _in_process(payload)
    with open(d / "result.pkl.tmp", "wb") as f:
        pickle.dump(result, f)
    os.replace(d / "result.pkl.tmp", d / "result.pkl")
    return 0


if __name__ == "__main__":  # pragma: no cover - the child process of a case with a time limit
    sys.exit(_child_main(sys.argv[1]))
