"""Writing a run's results: ``summary.json`` (solver.io.results), the VTK files of the bodies
and contact regions (solver.io.vtu), and the PNG pictures (solver.io.plots) with ``report.html``
(solver.io.report_html) when the scene's ``[output]`` asks for plots."""

from __future__ import annotations

import hashlib
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping

import numpy as np

from ibfem.solver.model import problem as pb

from .body_output import body_output
from .parallel_plots import PictureWorker, PlotJob
from .report_html import write_report
from .results import build_summary, json_safe, write_summary
from .vtu import step_contacts, write_step_bodies, write_vtk_files

if TYPE_CHECKING:
    from .scene import Scene

__all__ = ["start_pictures", "start_scene_pictures", "write_results", "write_scene_results"]


#: stress values (nodes x components x steps) recovered in one batch of the load-step series:
#: each body keeps one batch of centroid and nodal values, 16 MB each at most
_BATCH_VALUES = 2e6


class _StepStresses:
    """The load steps' (centroid stresses, recovered nodal stresses) of each body, a batch of
    steps at a time: both are linear in the field and the recovery's fits depend only on the
    grid, so a batch's steps are taken side by side, one stress operator and one set of fits
    per batch; each body keeps only the batch of the step asked for last."""

    def __init__(self, solution: pb.Solution, steps: list[dict]):
        self.solution = solution
        self.fields = [st["field"] for st in steps if st.get("field") is not None]
        self.batches: dict[str, dict[int, tuple[np.ndarray, np.ndarray]]] = {}  # by body, by field's id

    def get(self, body: str, field: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        if id(field) not in self.batches.get(body, {}):
            where = next((k for k, u in enumerate(self.fields) if u is field), None)
            if where is None:
                return None
            self.batches[body] = self._batch(body, where)
        return self.batches[body][id(field)]

    def _batch(self, body: str, first: int) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        sol = self.solution
        width = sol.centroid_stress(body).shape[1]
        per_batch = max(1, int(_BATCH_VALUES // max(1, sol.nodal_stress(body).size * 2)))
        batch = self.fields[first:first + per_batch]
        centroid = sol.centroid_stress(body, np.column_stack(batch))
        nodal = sol.nodal_stress(body, centroid)
        return {id(u): (centroid[:, k * width:(k + 1) * width], nodal[:, k * width:(k + 1) * width])
                for k, u in enumerate(batch)}


def _step_writer(problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any]):
    """The VTU writer of the load-step series: each step's bodies with that step's contact
    pressure (the step is the one whose field the solution it is given carries) and its
    stresses, computed for a batch of steps together (:class:`_StepStresses`)."""
    final = json_safe(summary).get("contacts") or []
    probes = json_safe(summary).get("probes") or []
    steps = getattr(solution, "steps", None) or []
    stresses = _StepStresses(solution, steps) if hasattr(solution, "centroid_stress") else None

    def write(folder: Path, problem: pb.Problem, step_solution: pb.Solution) -> list[Path]:
        for body in problem.bodies if stresses is not None else ():  # the caches the step fills on demand
            both = stresses.get(body.name, step_solution.u)
            if both is not None:
                step_solution.__dict__.setdefault("_centroid_stress", {}).setdefault(body.name, both[0])
                step_solution.__dict__.setdefault("_nodal_stress", {}).setdefault(body.name, both[1])
        step = next((st for st in steps if st.get("field") is step_solution.u), {})
        return write_step_bodies(folder, problem, step_solution, step_contacts(final, step), probes)

    return write


class StartedPictures:
    """The pictures of a run started before its last stages (:func:`start_pictures`): the job
    rendering them, the summary they show (its probes and lines reused by summary.json), the
    bodies' output meshes made for them (reused by the VTU files) and the seconds the start took
    (``summary_s``: the recovery and that summary; ``vtk_s``: the 2D output meshes)."""

    def __init__(self, job: PlotJob, summary: Mapping[str, Any], outputs: dict[str, Any], times: dict[str, float]):
        self.job, self.summary, self.outputs, self.times = job, summary, outputs, times


def start_pictures(out_dir: str | Path, problem: pb.Problem, solution: pb.Solution, probes: Iterable[Any] = (),
                   lines: Iterable[Any] = (), vtk: bool = True, plots: bool = False,
                   parallel: bool = True, summary: Mapping[str, Any] | None = None,
                   worker: PictureWorker | None = None) -> StartedPictures | None:
    """Start rendering the pictures (when ``plots``) in other processes while the caller goes on
    (the error estimate's second solve, then the other files) when the machine has idle cores;
    the stresses are recovered once, here, and the children inherit them. Pass the result to
    :func:`write_results`, which waits for the pictures. The pictures show the solution as it is
    now: what the caller adds to the contact blocks later (the estimated errors) is in
    summary.json and report.html, not in them. ``summary``: the run's summary when already built
    (else built here for the pictures). ``worker``: the picture process started earlier in the
    run (:class:`solver.io.parallel_plots.PictureWorker`), which renders them when it can.
    Returns None when no picture is asked."""
    if not plots:
        if worker is not None:
            worker.stop()
        return None
    t0 = time.perf_counter()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for body in problem.bodies if hasattr(solution, "nodal_stress") else ():
        solution.nodal_stress(body.name)  # recovered once, before the fork: every process uses it
    if summary is None:
        summary = build_summary(problem, solution, probes, lines)
    times = {"summary_s": time.perf_counter() - t0}
    t0 = time.perf_counter()
    outputs: dict[str, Any] = {}
    if vtk and problem.dim == 2:  # the 2D pictures draw the bodies' output meshes (the VTU files' cells)
        held = [p["point"] for p in summary.get("probes") or []]  # the output cells hold the probes
        outputs.update((b.name, body_output(problem, solution, b, held)) for b in problem.bodies)
    job = PlotJob(out_dir, problem, solution, summary, outputs, parallel, worker)
    times["vtk_s"] = time.perf_counter() - t0
    return StartedPictures(job, summary, outputs, times)


def write_results(
    out_dir: str | Path,
    problem: pb.Problem,
    solution: pb.Solution,
    probes: Iterable[Any] = (),
    lines: Iterable[Any] = (),
    vtk: bool = True,
    plots: bool = False,
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
    progress: Callable[..., None] | None = None,
    parallel: bool = True,
    pictures: StartedPictures | None = None,
) -> dict[str, Any]:
    """Write every requested file into ``out_dir``; returns the summary written. The summary
    lists the other files under ``files`` (names relative to ``out_dir``) and the time each kind
    of output took under ``timings`` (``summary_s``, ``vtk_s``, ``plots_s``, together
    ``output_s``; ``total_s``, the run's time until now, includes them). ``progress`` is told
    which file is being written. The pictures are rendered in other processes while the VTK
    files are written when the machine has idle cores (solver.io.parallel_plots), unless
    ``parallel`` is false. ``pictures``: the pictures :func:`start_pictures` started earlier in
    the run (the seconds of that start, which ``total_s`` holds, count in ``output_s``)."""
    report = progress or (lambda *a, **k: None)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    earlier = sum(pictures.times.values()) if pictures is not None else 0.0
    report("results: summary (probes, lines)")
    summary = build_summary(problem, solution, probes, lines, total_s=total_s, extra=extra,
                            earlier=pictures.summary if pictures is not None else None)
    scene = Path(str(summary.get("scene") or ""))
    if summary.get("scene") and scene.is_file():  # the scene file's fingerprint, to tell runs apart
        summary["scene_sha256"] = hashlib.sha256(scene.read_bytes()).hexdigest()
    output_times = {"summary_s": time.perf_counter() - start}
    if pictures is None:
        pictures = start_pictures(out_dir, problem, solution, probes, lines, vtk, plots, parallel, summary)
    if pictures is not None:
        for key, seconds in pictures.times.items():
            if key == "summary_s" or pictures.outputs:  # vtk_s: the 2D output meshes made there
                output_times[key] = output_times.get(key, 0.0) + seconds
        report("results: plots" + (" (rendered beside the other files)" if pictures.job.parallel else ""))
    files, missing = _write_files(out_dir, problem, solution, summary, vtk, pictures, report, output_times)
    if missing:
        summary["warnings"] = list(summary.get("warnings", [])) + missing
    if plots:  # the page that shows the run: numbers and pictures in one file
        scene_text = scene.read_text(encoding="utf-8", errors="replace") if summary.get("scene") and scene.is_file() else None
        pictures_written = sorted(p for p in files if p.suffix == ".png")
        files.append(out_dir / "report.html")
    summary["files"] = sorted(str(p.relative_to(out_dir)) for p in files)
    here = time.perf_counter() - start
    output_times["output_s"] = here + earlier
    summary["timings"].update(output_times)
    if total_s is not None:
        summary["timings"]["total_s"] = float(total_s) + here
    if plots:
        write_report(out_dir, json_safe(summary), pictures_written, scene_text)
    write_summary(out_dir / "summary.json", summary)
    return summary


def _write_files(out_dir: Path, problem: pb.Problem, solution: pb.Solution, summary: dict[str, Any], vtk: bool,
                 pictures: StartedPictures | None, report, output_times: dict[str, float]) -> tuple[list[Path], list[str]]:
    """The VTK files, the load-step series and the pictures (waited for); (files, warnings)."""
    files: list[Path] = []
    missing: list[str] = []
    outputs = pictures.outputs if pictures is not None else {}
    if vtk:  # VTK's XML format written directly: no optional library needed
        t0 = time.perf_counter()
        files += write_vtk_files(out_dir, problem, solution, json_safe(summary), progress=report, outputs=outputs)
        output_times["vtk_s"] = output_times.get("vtk_s", 0.0) + time.perf_counter() - t0
    if getattr(solution, "steps", None):  # load paths: the step series and the history's tables
        from .step_outputs import write_step_files

        files += write_step_files(out_dir, problem, solution, summary, write_vtu=_step_writer(problem, solution, summary) if vtk else None,
                                  plots=pictures is not None, missing=missing)
    if pictures is not None:  # a missing optional library costs its files, not the summary
        report("results: plots")
        written, reason, output_times["plots_s"] = pictures.job.result()
        output_times["plots_processes"] = pictures.job.processes  # 0: rendered in this process
        if pictures.job.worker is not None:  # its imports, made while the run solved
            output_times["plots_warm_up_s"] = pictures.job.warm_up_s
        files += written
        missing += [reason] if reason else []
    return files, missing


def write_scene_results(
    out_dir: str | Path,
    scene: Scene,
    solution: pb.Solution,
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
    progress: Callable[..., None] | None = None,
    pictures: StartedPictures | None = None,
) -> dict[str, Any]:
    """:func:`write_results` with the probes, lines and file choices of a loaded
    :class:`solver.io.scene.Scene`'s ``[output]`` table: writes ``summary.json`` (and the VTU
    files and pictures the table asks for) into ``out_dir``, created when missing, and returns
    the summary as a dict.

    :raises OSError: ``out_dir`` or a file in it cannot be written."""
    output = scene.output
    return write_results(
        out_dir,
        scene.problem,
        solution,
        probes=output.probes,
        lines=output.lines,
        vtk=output.vtk,
        plots=output.plots,
        total_s=total_s,
        extra=extra,
        progress=progress,
        pictures=pictures,
    )


def start_scene_pictures(out_dir: str | Path, scene: Scene, solution: pb.Solution,
                         worker: PictureWorker | None = None) -> StartedPictures | None:
    """:func:`start_pictures` with the ``[output]`` table of a loaded scene: pass the result to
    :func:`write_scene_results`."""
    output = scene.output
    return start_pictures(out_dir, scene.problem, solution, output.probes, output.lines, output.vtk, output.plots,
                          worker=worker)
