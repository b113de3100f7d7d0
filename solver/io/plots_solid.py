"""PNG pictures of a 3D run (``[output] plots = true``, model = "solid"), headless: the von Mises
stress and the displacement magnitude on the three section planes through the scene's centre
(``sections.png``; through the contact point when there is one), and one plot per output line
with the six stress components and von Mises."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

import numpy as np

from solver.model import problem as pb

__all__ = ["write_solid_plots", "section_grid"]

#: samples along each side of a section picture
SECTION_SAMPLES = 160
_VOIGT = ("sxx", "syy", "szz", "syz", "sxz", "sxy")


def section_grid(lower: np.ndarray, upper: np.ndarray, normal_axis: int, level: float, n: int = SECTION_SAMPLES):
    """Points (n*n, 3) on the plane x_k = level over the box [lower, upper], and the two in-plane
    axes and their sample coordinates."""
    a, b = [k for k in range(3) if k != normal_axis]
    sa = np.linspace(lower[a], upper[a], n)
    sb = np.linspace(lower[b], upper[b], n)
    ga, gb = np.meshgrid(sa, sb, indexing="xy")
    pts = np.zeros((ga.size, 3))
    pts[:, a], pts[:, b], pts[:, normal_axis] = ga.ravel(), gb.ravel(), level
    return pts, (a, b), (sa, sb)


def _scene_box(problem: pb.Problem) -> tuple[np.ndarray, np.ndarray]:
    lows, highs = zip(*(np.asarray(b.profile.bounds, dtype=float) for b in problem.bodies))
    return np.min(lows, axis=0), np.max(highs, axis=0)


def _sections(plt, problem: pb.Problem, solution: pb.Solution, centre: np.ndarray) -> Any:
    lower, upper = _scene_box(problem)
    fig, axes = plt.subplots(2, 3, figsize=(15, 9), constrained_layout=True)
    for k in range(3):
        pts, (a, b), (sa, sb) = section_grid(lower, upper, k, float(centre[k]))
        vm = solution.von_mises(pts).reshape(len(sb), len(sa))
        disp = np.linalg.norm(solution.displacement(pts), axis=1).reshape(len(sb), len(sa))
        for row, (values, label) in enumerate(((vm, "von Mises [Pa]"), (disp, "|u| [m]"))):
            ax = axes[row, k]
            image = ax.imshow(np.ma.masked_invalid(values), origin="lower", cmap="viridis",
                              extent=(sa[0], sa[-1], sb[0], sb[-1]), interpolation="nearest")
            fig.colorbar(image, ax=ax, shrink=0.8)
            ax.set_xlabel(f"{'xyz'[a]} [m]")
            ax.set_ylabel(f"{'xyz'[b]} [m]")
            ax.set_title(f"{label} on {'xyz'[k]} = {centre[k]:.4g}", fontsize=10)
            ax.set_aspect("equal")
    fig.suptitle(problem.name)
    return fig


def write_solid_plots(out_dir: Path, figs: Any, problem: pb.Problem, solution: pb.Solution,
                      summary: Mapping[str, Any]) -> None:
    """Section pictures and line plots into ``figs`` (solver.io.plots._Figures)."""
    contacts = [c for c in summary.get("contacts", []) if c.get("point") and None not in c["point"]]
    lower, upper = _scene_box(problem)
    centre = np.asarray(contacts[0]["point"], dtype=float) if contacts else 0.5 * (lower + upper)
    figs.save(_sections(figs.plt, problem, solution, centre), "sections.png")
    for name, line in summary.get("lines", {}).items():
        s = np.asarray(line["s"], dtype=float)
        stress = np.asarray(line["stress"], dtype=float).reshape(-1, 6)
        fig, ax = figs.plt.subplots(figsize=(7, 4.5), constrained_layout=True)
        for k, label in enumerate(_VOIGT):
            ax.plot(s, stress[:, k], label=label)
        ax.plot(s, np.asarray(line["von_mises"], dtype=float), "k", lw=2, label="von Mises")
        from .results import _file_stem

        figs.save_line_plot(fig, ax, "distance along the line [m]", "stress [Pa]", f"{problem.name}: line {name}",
                            f"line_{_file_stem(name)}.png")
