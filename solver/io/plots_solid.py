"""PNG pictures of a 3D run (``[output] plots = true``, model = "solid"), headless: the von Mises
stress and the displacement magnitude on three section planes (``sections.png``: about the
contact region when there is one, see :func:`section_planes`; else the coordinate planes through
the point of the largest von Mises stress), the contact's pressure and shear beside Hertz with
the computed and theory values of the semi-axes and peak pressure (``contact_<k>.png``), and one
plot per output line with the six stress components and von Mises. Numbers in the units that fit them (solver.io.plot_units)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ibfem.solver.model import problem as pb
from ibfem.solver.model.elasticity import von_mises

from .plot_units import length_unit, stress_unit

__all__ = ["write_solid_plots", "section_grid", "section_planes"]

#: samples along each side of a section picture
SECTION_SAMPLES = 140
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


def section_planes(problem: pb.Problem, contacts, through=None) -> list[dict]:
    """The planes of ``sections.png``: about the first contact with a region, the two planes
    through the contact point along each axis of the region and the normal, and the plane
    parallel to the contact at the depth of the largest shear (0.48 a) in the second body, each
    4 semi-axes (and at least 8 of the finest cells) on either side; without one, the three
    coordinate planes through the point ``through`` (the scene's centre when None) across the
    scene's box. Each: title, origin, in-plane unit vectors ``u``, ``v``, half-extents and
    ``offset``, the coordinates along ``u`` and ``v`` of the origin (the axes show them)."""
    c = next((c for c in contacts if c.get("semi_axes") and c["semi_axes"][0]), None)
    if c is None:
        lower, upper = _scene_box(problem)
        centre, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
        point = centre if through is None else np.asarray(through, dtype=float)
        planes = []
        for k in range(3):
            a, b = (j for j in range(3) if j != k)
            origin = centre.copy()
            origin[k] = point[k]
            planes.append({"title": f"{'xyz'[k]} = {point[k]:.4g} m", "origin": origin, "u": np.eye(3)[a],
                           "v": np.eye(3)[b], "half": (half[a], half[b]), "offset": (centre[a], centre[b]),
                           "labels": ("xyz"[a], "xyz"[b])})
        return planes
    point, normal = np.asarray(c["point"], float), np.asarray(c["normal"], float)
    axes, semi = np.asarray(c["axes"], float), np.asarray(c["semi_axes"], float)
    finest = min(float(b.element_size) / 2 ** max([z.levels for z in b.refinements] or [0]) for b in problem.bodies)
    w = max(4.0 * float(semi.max()), 8.0 * finest)
    depth = 0.48 * float(semi.min())
    second = c["bodies"][1]
    return [
        {"title": "along axis 0 and the normal", "origin": point, "u": axes[0], "v": normal, "half": (w, w),
         "labels": ("axis 0", "normal"), "semi": float(semi[0])},
        {"title": "along axis 1 and the normal", "origin": point, "u": axes[1], "v": normal, "half": (w, w),
         "labels": ("axis 1", "normal"), "semi": float(semi[1])},
        {"title": f"parallel to the contact, 0.48 b into {second}", "origin": point - depth * normal,
         "u": axes[0], "v": axes[1], "half": (w, w), "labels": ("axis 0", "axis 1"), "semi": None},
    ]


def _section_values(problem: pb.Problem, solution: pb.Solution, plane: dict, n: int | None = None):
    """Samples (n x n) of von Mises and |u| on a plane, each point in the body that holds it
    (one look-up of the bodies for both fields); NaN outside every body."""
    n = n or SECTION_SAMPLES
    su = np.linspace(-plane["half"][0], plane["half"][0], n)
    sv = np.linspace(-plane["half"][1], plane["half"][1], n)
    gu, gv = np.meshgrid(su, sv, indexing="xy")
    pts = plane["origin"] + gu.reshape(-1, 1) * plane["u"] + gv.reshape(-1, 1) * plane["v"]
    which = np.asarray(solution.body_at(pts), dtype=int).reshape(-1)
    vm, disp = np.full(len(pts), np.nan), np.full(len(pts), np.nan)
    for k, body in enumerate(problem.bodies):
        sel = np.nonzero(which == k)[0]
        if len(sel):
            stress = np.asarray(solution.stress(pts[sel], body=body.name), dtype=float)
            vm[sel] = von_mises(stress, problem.model, body.material.poissons_ratio)
            disp[sel] = np.linalg.norm(np.asarray(solution.displacement(pts[sel], body=body.name), dtype=float), axis=1)
    return su, sv, vm.reshape(n, n), disp.reshape(n, n)


def _peak(problem: pb.Problem, solution: pb.Solution):
    """The grid node inside a body with the largest recovered von Mises stress (None when the
    solution has no recovered nodal stresses)."""
    best, point = -np.inf, None
    for body in getattr(solution, "bodies", ()):
        if not hasattr(solution, "nodal_stress") or not hasattr(body, "grid"):
            return None
        nodes = np.asarray(body.grid.nodes, dtype=float)
        inside = np.nonzero(np.asarray(body.contains(nodes), bool))[0]
        if len(inside) == 0:
            continue
        material = problem.body(body.name).material
        vm = von_mises(np.asarray(solution.nodal_stress(body.name))[inside], problem.model, material.poissons_ratio)
        k = int(np.nanargmax(vm)) if np.isfinite(vm).any() else -1
        if k >= 0 and vm[k] > best:
            best, point = float(vm[k]), nodes[inside[k]]
    return point


def _crop(ax, su: np.ndarray, sv: np.ndarray, values: np.ndarray) -> None:
    """Limits to the part of the panel that holds material (a symmetric model fills a part of it)."""
    rows, cols = np.nonzero(np.isfinite(values).any(axis=1))[0], np.nonzero(np.isfinite(values).any(axis=0))[0]
    if len(rows) and len(cols):
        ax.set_xlim(su[cols[0]], su[cols[-1]])
        ax.set_ylim(sv[rows[0]], sv[rows[-1]])


def _ticks(ax, most: int = 5) -> None:
    """At most ``most`` ticks along the longer side of an equal-aspect panel and fewer along the
    shorter one, in proportion: a narrow panel's tick labels do not run into each other."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    width, height = abs(x1 - x0), abs(y1 - y0)
    longest = max(width, height) or 1.0
    ax.locator_params(axis="x", nbins=max(2, round(most * width / longest)))
    ax.locator_params(axis="y", nbins=max(2, round(most * height / longest)))


def _sections(plt, problem: pb.Problem, solution: pb.Solution, contacts) -> Any:
    """von Mises and |u| on the section planes (:func:`section_planes`), each panel's colour
    scale from 0 to the largest value it shows; numbers in MPa / GPa and mm / um as they fit."""
    region = any(c.get("semi_axes") and c["semi_axes"][0] for c in contacts)
    planes = section_planes(problem, contacts, None if region else _peak(problem, solution))
    fig, axes = plt.subplots(2, 3, figsize=(15, 9.5))
    fig.subplots_adjust(left=0.06, right=0.97, bottom=0.07, top=0.92, wspace=0.45, hspace=0.3)  # fixed: fast
    for k, plane in enumerate(planes):
        su, sv, vm, disp = _section_values(problem, solution, plane)
        lname, lscale = length_unit(2.0 * max(plane["half"]))
        su, sv = su + plane.get("offset", (0.0, 0.0))[0], sv + plane.get("offset", (0.0, 0.0))[1]
        extent = (su[0] / lscale, su[-1] / lscale, sv[0] / lscale, sv[-1] / lscale)
        for row, values in enumerate((vm, disp)):
            ax = axes[row, k]
            finite = values[np.isfinite(values)]
            top = float(finite.max()) if finite.size else 1.0
            if row == 0:
                uname, uscale = stress_unit(top)
                label = f"von Mises [{uname}]"
            else:
                uname, uscale = length_unit(top)
                label = f"|u| [{uname}]"
            image = ax.imshow(np.ma.masked_invalid(values / uscale), origin="lower", cmap="viridis",
                              extent=extent, interpolation="bilinear", vmin=0.0, vmax=top / uscale or 1.0)
            fig.colorbar(image, ax=ax, shrink=0.85, label=label)
            if plane.get("semi"):
                ax.plot([-plane["semi"] / lscale, plane["semi"] / lscale], [0.0, 0.0], "w-", lw=2.0,
                        label="contact region")
                ax.legend(loc="upper right", fontsize=7, facecolor="0.3", labelcolor="white", framealpha=0.8)  # the white line shows
            _crop(ax, su / lscale, sv / lscale, values)
            ax.set_xlabel(f"{plane['labels'][0]} [{lname}]")
            ax.set_ylabel(f"{plane['labels'][1]} [{lname}]")
            ax.set_title(plane["title"], fontsize=10)
            ax.set_aspect("equal")
            _ticks(ax)
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


def contact_numbers(problem: pb.Problem, c: Mapping[str, Any]) -> list[tuple[str, float, float | None]]:
    """(name, computed, Hertz or None) of the semi-axes a, b (m) and the peak pressure p0 (Pa,
    the largest of the pressure profiles) of a 3D contact block."""
    hertz = _hertz(problem, c)
    a, b = (float(v) for v in c["semi_axes"])
    peaks = [max(c["pressure"][f"axis{k}"]["value"] or [0.0]) for k in (0, 1)]
    rows = [("a", a, None if hertz is None else hertz[0]), ("b", b, None if hertz is None else hertz[1]),
            ("p0", float(max(peaks)), None if hertz is None else hertz[2])]
    return rows


def _annotation(rows, lscale: float, lname: str, sscale: float, sname: str) -> str:
    lines = []
    for name, value, theory in rows:
        scale, unit = (sscale, sname) if name == "p0" else (lscale, lname)
        text = f"{name} = {value / scale:.4g} {unit}"
        if theory:
            text += f"  (Hertz {theory / scale:.4g}, {100.0 * (value / theory - 1.0):+.2f} %)"
        lines.append(text)
    return "\n".join(lines)


def _contact_figure(plt, problem: pb.Problem, c: Mapping[str, Any]) -> Any:
    """Pressure and shear along both axes (Hertz beside them) and the pressure over the patch
    with the computed and Hertz ellipses; a, b and p0 with their Hertz values written on it."""
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5.2))
    fig.subplots_adjust(left=0.06, right=0.96, bottom=0.1, top=0.88, wspace=0.22)  # fixed: a computed layout costs more
    hertz = _hertz(problem, c)
    a, b = c["semi_axes"]
    rows = contact_numbers(problem, c)
    lname, lscale = length_unit(2.5 * max(a, b))
    sname, sscale = stress_unit(rows[2][1])
    for k, style in ((0, "-"), (1, "--")):
        pr = c["pressure"][f"axis{k}"]
        sh = (c.get("shear") or {}).get(f"axis{k}") or {"s": [], "value": []}
        s = np.asarray(pr["s"], dtype=float)
        ax.plot(s / lscale, np.asarray(pr["value"], float) / sscale, style, color="C0", label=f"pressure, axis {k}")
        if any(sh["value"]):
            ax.plot(np.asarray(sh["s"], float) / lscale, np.asarray(sh["value"], float) / sscale, style, color="C1",
                    label=f"shear, axis {k}")
        if hertz is not None:
            ax.plot(s / lscale, hertz[2] * np.sqrt(np.clip(1 - (s / hertz[k]) ** 2, 0, None)) / sscale, style,
                    color="k", lw=0.8, label=f"Hertz, axis {k}")
    ax.set_xlabel(f"s along the axis [{lname}]")
    ax.set_ylabel(f"traction [{sname}]")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    ax.text(0.02, 0.03, _annotation(rows, lscale, lname, sscale, sname), transform=ax.transAxes, va="bottom",
            fontsize=8, family="monospace", bbox={"facecolor": "white", "alpha": 0.8, "edgecolor": "0.7"})
    coef = np.asarray(c.get("profile_recovery", {}).get("pressure_coefficients", []), dtype=float)
    g0, g1 = np.meshgrid(np.linspace(-1.3 * a, 1.3 * a, 161), np.linspace(-1.3 * b, 1.3 * b, 161))
    X, Y = g0 / a, g1 / b
    if coef.size == 6:
        root = np.sqrt(np.clip(1 - X**2 - Y**2, 0, None))
        p = root * (coef[0] + coef[1] * X + coef[2] * Y + coef[3] * X**2 + coef[4] * X * Y + coef[5] * Y**2)
        image = ax2.imshow(np.clip(p, 0, None) / sscale, origin="lower", cmap="viridis",
                           extent=(g0.min() / lscale, g0.max() / lscale, g1.min() / lscale, g1.max() / lscale))
        fig.colorbar(image, ax=ax2, shrink=0.85, label=f"pressure [{sname}]")
    t = np.linspace(0, 2 * np.pi, 361)
    ax2.plot(a * np.cos(t) / lscale, b * np.sin(t) / lscale, "w-", lw=1.5, label="computed")
    if hertz is not None:
        ax2.plot(hertz[0] * np.cos(t) / lscale, hertz[1] * np.sin(t) / lscale, "r--", lw=1.0, label="Hertz")
    ax2.set_aspect("equal")
    ax2.set_xlabel(f"axis 0 [{lname}]")
    ax2.set_ylabel(f"axis 1 [{lname}]")
    ax2.legend(fontsize=8, loc="upper right")
    share = c.get("full_contact")
    force = f"N = {c['normal_force']:.4g} N" + (f" ({share['model_share']:.3g} of the contact; full {share['normal_force']:.4g} N)"
                                                if share else "")
    fig.suptitle(f"{problem.name}: contact {' / '.join(c['bodies'])}, {force}")
    return fig


def write_solid_plots(out_dir: Path, figs: Any, problem: pb.Problem, solution: pb.Solution,
                      summary: Mapping[str, Any], groups=("fields", "profiles")) -> None:
    """Section pictures (group ``fields``), contact and line plots (``profiles``) into ``figs``
    (solver.io.plots._Figures)."""
    if "fields" in groups:
        contacts = [c for c in summary.get("contacts", []) if c.get("point") and None not in c["point"]]
        figs.save(_sections(figs.plt, problem, solution, contacts), "sections.png")
    if "profiles" not in groups:
        return
    for k, c in enumerate(summary.get("contacts", [])):
        if c.get("boundary"):  # a region of general shape (a line contact)
            from .plots_region import region_figure

            figs.save(region_figure(figs.plt, problem.name, c), f"contact_{k}.png")
        elif c.get("semi_axes") and c["semi_axes"][0]:
            figs.save(_contact_figure(figs.plt, problem, c), f"contact_{k}.png")
    for name, line in summary.get("lines", {}).items():
        from .results import _file_stem

        stress = np.asarray(line["stress"], dtype=float).reshape(-1, 6)
        figs.save_stress_line(np.asarray(line["s"], dtype=float), stress, np.asarray(line["von_mises"], dtype=float),
                              _VOIGT, f"{problem.name}: line {name}", f"line_{_file_stem(name)}.png")
