"""PNG pictures of a 3D run (``[output] plots = true``, model = "solid"), headless: the von Mises
stress and the displacement magnitude on the three section planes through the scene's centre
(``sections.png``; through the contact point when there is one), and one plot per output line
with the six stress components and von Mises."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ibfem.solver.model import problem as pb

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


def _hertz(problem: pb.Problem, c: Mapping[str, Any]):
    """Hertz's semi-axes and p0 for the computed force of the whole contact (the model's force over
    its share: a quarter model carries a quarter), when both bodies' moduli and the relative
    curvatures are known (None otherwise)."""
    from ibfem.solver.reference.theory import hertz_elliptic_contact

    curv = c.get("relative_curvatures")
    if not curv or min(curv) <= 0 or not c.get("normal_force"):
        return None
    mats = [problem.body(n).material for n in c["bodies"]]
    e_star = 1.0 / sum((1 - m.poissons_ratio**2) / m.youngs_modulus for m in mats)
    share = float(c.get("model_share") or 1.0)
    a, b, p0 = hertz_elliptic_contact(c["normal_force"] / share, tuple(curv), e_star)
    return (a, b, p0) if curv[0] <= curv[1] else (b, a, p0)


def _contact_figure(plt, problem: pb.Problem, c: Mapping[str, Any]) -> Any:
    """Pressure and shear along both axes (Hertz beside them) and the pressure over the patch
    with the computed and Hertz ellipses."""
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5), constrained_layout=True)
    hertz = _hertz(problem, c)
    for k, style in ((0, "-"), (1, "--")):
        pr, sh = c["pressure"][f"axis{k}"], (c.get("shear") or {}).get(f"axis{k}") or {"s": [], "value": []}
        ax.plot(pr["s"], pr["value"], style, color="C0", label=f"pressure, axis {k}")
        if any(sh["value"]):
            ax.plot(sh["s"], sh["value"], style, color="C1", label=f"shear, axis {k}")
        if hertz is not None:
            s = np.asarray(pr["s"], dtype=float)
            ax.plot(s, hertz[2] * np.sqrt(np.clip(1 - (s / hertz[k]) ** 2, 0, None)), style, color="k", lw=0.8,
                    label=f"Hertz, axis {k}")
    ax.set_xlabel("s along the axis [m]")
    ax.set_ylabel("traction [Pa]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    a, b = c["semi_axes"]
    coef = np.asarray(c.get("profile_recovery", {}).get("pressure_coefficients", []), dtype=float)
    g0, g1 = np.meshgrid(np.linspace(-1.3 * a, 1.3 * a, 161), np.linspace(-1.3 * b, 1.3 * b, 161))
    X, Y = g0 / a, g1 / b
    if coef.size == 6:
        root = np.sqrt(np.clip(1 - X**2 - Y**2, 0, None))
        p = root * (coef[0] + coef[1] * X + coef[2] * Y + coef[3] * X**2 + coef[4] * X * Y + coef[5] * Y**2)
        image = ax2.imshow(np.clip(p, 0, None), origin="lower", extent=(g0.min(), g0.max(), g1.min(), g1.max()),
                           cmap="viridis")
        fig.colorbar(image, ax=ax2, shrink=0.8, label="pressure [Pa]")
    t = np.linspace(0, 2 * np.pi, 361)
    ax2.plot(a * np.cos(t), b * np.sin(t), "w-", lw=1.5, label="computed")
    if hertz is not None:
        ax2.plot(hertz[0] * np.cos(t), hertz[1] * np.sin(t), "r--", lw=1.0, label="Hertz")
    ax2.set_aspect("equal")
    ax2.set_xlabel("axis 0 [m]")
    ax2.set_ylabel("axis 1 [m]")
    ax2.legend(fontsize=8)
    fig.suptitle(f"{problem.name}: contact {'/'.join(c['bodies'])}, semi-axes {a:.4g} x {b:.4g} m")
    return fig


def write_solid_plots(out_dir: Path, figs: Any, problem: pb.Problem, solution: pb.Solution,
                      summary: Mapping[str, Any]) -> None:
    """Section pictures and line plots into ``figs`` (solver.io.plots._Figures)."""
    contacts = [c for c in summary.get("contacts", []) if c.get("point") and None not in c["point"]]
    lower, upper = _scene_box(problem)
    centre = np.asarray(contacts[0]["point"], dtype=float) if contacts else 0.5 * (lower + upper)
    figs.save(_sections(figs.plt, problem, solution, centre), "sections.png")
    for k, c in enumerate(summary.get("contacts", [])):
        if c.get("semi_axes") and c["semi_axes"][0]:
            figs.save(_contact_figure(figs.plt, problem, c), f"contact_{k}.png")
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
