"""Writing a run's results: ``summary.json`` (solver.io.results), one VTU file per body and the
PNG pictures (solver.io.plots) the scene's ``[output]`` asks for."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping

from ibfem.solver.model import problem as pb

if TYPE_CHECKING:
    from .scene import Scene

from .results import build_summary, write_summary, write_vtu

__all__ = ["write_results", "write_scene_results"]


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
) -> dict[str, Any]:
    """Write every requested file into ``out_dir``; returns the summary written. The summary
    lists the other files under ``files`` (names relative to ``out_dir``)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    summary = build_summary(problem, solution, probes, lines, total_s=total_s, extra=extra)
    files: list[Path] = []
    missing: list[str] = []
    # a missing optional library costs its files, not the summary
    if vtk:
        try:
            files += write_vtu(out_dir, problem, solution)
        except ImportError as err:
            missing.append(f"VTU files not written: pyvista is not installed ({err}); pip install 'ibfem[pictures]'")
    if getattr(solution, "steps", None):  # load paths: the step series and the history's tables
        from .step_outputs import write_step_files

        files += write_step_files(out_dir, problem, solution, summary, write_vtu=write_vtu if vtk else None,
                                  plots=plots, missing=missing)
    if plots:
        try:
            from .plots import write_plots

            files += write_plots(out_dir, problem, solution, summary)
        except ImportError as err:
            missing.append(f"plots not written: matplotlib is not installed ({err}); pip install 'ibfem[pictures]'")
    if missing:
        summary["warnings"] = list(summary.get("warnings", [])) + missing
    summary["files"] = sorted(str(p.relative_to(out_dir)) for p in files)
    write_summary(out_dir / "summary.json", summary)
    return summary


def write_scene_results(
    out_dir: str | Path,
    scene: Scene,
    solution: pb.Solution,
    total_s: float | None = None,
    extra: Mapping[str, Any] | None = None,
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
    )
