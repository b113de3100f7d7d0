"""PNG pictures of a run (``[output] plots = true``), headless (matplotlib's Agg canvas without
pyplot, imported only here and only when pictures are written): ``fields.png`` (von Mises and displacement magnitude
over every body), ``contact_<k>_fields.png`` (the same close to each contact point),
``line_<name>.png`` per output line, ``contact_<k>.png`` (pressure and shear) per contact, with
Hertz and Cattaneo-Mindlin for the computed forces beside them when the contact is Hertzian."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ibfem.solver.model import problem as pb

from .plot_units import length_unit, stress_unit
from .png import write_png
from .body_output import body_output
from .results import _file_stem, json_safe

__all__ = ["write_plots", "field_layout", "prepare_field_background"]

#: the pictures' resolution (dots per inch)
_DPI = 110


class AggFigures:
    """Figures drawn by Agg without pyplot: ``subplots`` as pyplot's, on a figure no window
    manager tracks (nothing to close, no global state shared with the caller's own figures)."""

    def __init__(self):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self._figure, self._canvas = Figure, FigureCanvasAgg

    def figure(self, figsize=None):
        fig = self._figure(figsize=figsize)
        self._canvas(fig)
        return fig

    def subplots(self, nrows: int = 1, ncols: int = 1, figsize=None, constrained_layout: bool = False, **kwargs):
        fig = self._figure(figsize=figsize, layout="constrained" if constrained_layout else None)
        self._canvas(fig)
        return fig, fig.subplots(nrows, ncols, **kwargs)


class _Figures:
    """Saves figures into ``out_dir`` and remembers the files written."""

    def __init__(self, out_dir: Path):
        self.plt = AggFigures()
        self.out_dir = out_dir
        self.written: list[Path] = []

    def save(self, fig: Any, name: str) -> None:
        path = self.out_dir / name
        blit = getattr(fig, "_ibfem_background", None)
        if blit is not None:  # its fixed parts drawn ahead (:func:`prepare_field_background`)
            _save_on_background(fig, *blit, path)
        else:
            _save_drawn(fig, path)
        self.written.append(path)

    def save_line_plot(self, fig: Any, ax: Any, xlabel: str, ylabel: str, title: str, name: str,
                       outside: bool = False) -> None:
        """Labels, legend (beside the axes when ``outside``: it never hides a curve), grid."""
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        if outside:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
        else:
            ax.legend()
        ax.grid(alpha=0.3)
        self.save(fig, name)


    def save_stress_line(self, s: np.ndarray, stress: np.ndarray, vm: np.ndarray, components, title: str,
                         name: str) -> None:
        """The stress components and von Mises along an output line, in the units that fit."""
        finite = np.abs(np.concatenate([stress.ravel(), vm]))
        finite = finite[np.isfinite(finite)]
        sname, sscale = stress_unit(float(finite.max()) if finite.size else 1.0)
        lname, lscale = length_unit(float(np.ptp(s)) if len(s) else 1.0)
        fig, ax = _prepared.pop("line", None) or self.plt.subplots(figsize=_LINE_SIZE)
        fig.subplots_adjust(left=0.12, right=0.97, bottom=0.12, top=0.92)  # fixed: short tick labels in these units
        for k, label in enumerate(components):
            ax.plot(s / lscale, stress[:, k] / sscale, label=label)
        ax.plot(s / lscale, vm / sscale, "k", lw=2, label="von Mises")
        self.save_line_plot(fig, ax, f"distance along the line [{lname}]", f"stress [{sname}]", title, name)


def _triangles(out) -> np.ndarray:
    """(k, 3) triangles of a 2D output mesh (solver.io.body_output): quadrilaterals split in two."""
    starts = np.concatenate([[0], out.offsets[:-1]])
    sizes = out.offsets - starts
    tris = []
    quads = np.nonzero(sizes == 4)[0]
    if len(quads):
        q = out.connectivity[starts[quads, None] + np.arange(4)]
        tris += [q[:, [0, 1, 2]], q[:, [0, 2, 3]]]
    simplices = np.nonzero(sizes == 3)[0]
    if len(simplices):
        tris.append(out.connectivity[starts[simplices, None] + np.arange(3)])
    return np.concatenate(tris) if tris else np.zeros((0, 3), dtype=np.int64)


def _point_values(out, key: str) -> np.ndarray:
    if key == "von_mises":
        return np.asarray(out.point_data["von_mises"], dtype=float)
    return np.linalg.norm(np.asarray(out.point_data["displacement"], dtype=float)[:, :2], axis=1)


def _colour_range(outputs, values: list[np.ndarray], window) -> tuple[float, float]:
    """Colour scale from the smallest to the largest value at the points in ``window`` (x0, x1,
    y0, y1): the field's peak there is always on the scale."""
    x0, x1, y0, y1 = window
    shown = []
    for out, v in zip(outputs, values):
        p = out.points
        shown.append(v[(p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)])
    finite = np.concatenate(shown) if shown else np.zeros(0)
    finite = finite[np.isfinite(finite)]
    vmin, vmax = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if vmax <= vmin:
        vmax = vmin + max(abs(vmin), 1.0) * 1e-12 + 1e-300
    return vmin, vmax


def _draw_field(fig: Any, ax: Any, cax: Any, outputs, key: str, label: str, window) -> bool:
    """The recovered field over the bodies as they are (cells clipped at the exact boundary),
    drawn on the deformed shape at true scale (touching bodies close over the contact), smoothly
    shaded between the points; lengths and stresses in the units that fit. False when no
    triangle reaches into the window (nothing drawn, the colour bar removed)."""
    from matplotlib.ticker import MaxNLocator

    values = [_point_values(out, key) for out in outputs]
    vmin, vmax = _colour_range(outputs, values, window)
    x0, x1, y0, y1 = window
    lscale = _field_panel(ax, cax, label, window)
    uname, uscale = stress_unit(max(abs(vmin), abs(vmax))) if key == "von_mises" else length_unit(vmax)
    image = None
    for out, v in zip(outputs, values):
        xy = (out.points + np.asarray(out.point_data["displacement"], dtype=float)[:, :2]) / lscale
        tris = _triangles(out)
        corners = xy[tris]  # only the triangles that reach into the window are drawn
        ok = np.all(np.isfinite(v[tris]), axis=1) \
            & (corners[:, :, 0].max(axis=1) >= x0 / lscale) & (corners[:, :, 0].min(axis=1) <= x1 / lscale) \
            & (corners[:, :, 1].max(axis=1) >= y0 / lscale) & (corners[:, :, 1].min(axis=1) <= y1 / lscale)
        if not ok.any():
            continue
        image = ax.tripcolor(xy[:, 0], xy[:, 1], tris[ok], np.nan_to_num(v) / uscale, shading="gouraud",
                             cmap="viridis", vmin=vmin / uscale, vmax=vmax / uscale)
    if image is not None:
        cax.set_visible(True)
        bar = fig.colorbar(image, cax=cax, label=f"{label} [{uname}]")
        bar.locator = MaxNLocator(nbins=6)
    else:
        cax.remove()
    return image is not None


def _field_panel(ax: Any, cax: Any, label: str, window) -> float:
    """What a field panel shows whatever the field: its window at equal scales, title and axis
    labels in the length unit that fits; the colour bar's axes hidden until a field is drawn.
    Returns the length unit's size in metres."""
    x0, x1, y0, y1 = window
    lname, lscale = length_unit(max(x1 - x0, y1 - y0))
    ax.set_xlim(x0 / lscale, x1 / lscale)
    ax.set_ylim(y0 / lscale, y1 / lscale)
    ax.set_aspect("equal", anchor="E")  # against its colour bar
    ax.locator_params(nbins=5)
    ax.set_title(f"{label} (deformed, true scale)", fontsize=10, y=1.0, pad=6)
    ax.set_xlabel(f"x [{lname}]")
    ax.set_ylabel(f"y [{lname}]")
    cax.set_visible(False)
    return lscale


#: the field pictures' panels: (left edge, field, label)
_PANELS = ((0.06, "von_mises", "von Mises stress"), (0.575, "displacement", "displacement magnitude"))

#: tick marks made ahead per axis: as many as five bins ask for, and a spare
_TICKS = 8

#: empty figures made ahead (:func:`prepare_figures`), by kind ("field", "line"), each taken by
#: the next picture of its kind
_prepared: dict[str, Any] = {}


def _empty_field_figure(plt) -> tuple[Any, list[tuple[Any, Any]]]:
    """The field picture's figure with its panels' axes and colour bars' axes and their tick
    marks made, nothing drawn: (figure, [(axes, colour bar axes) per panel])."""
    fig = plt.figure(figsize=(12, 5))
    # fixed places (no computed layout, no colour bar taking its room from its panel, which
    # re-lays the figure out): room for the tick labels, the colour bars' labels and a title
    # over each panel
    panels = []
    for left, _, _ in _PANELS:
        ax = fig.add_axes((left, 0.1, 0.32, 0.77))
        cax = fig.add_axes((left + 0.335, 0.177, 0.012, 0.616))
        for axis in (ax.xaxis, ax.yaxis, cax.yaxis):  # the tick marks the panels draw (made once, moved after)
            axis.get_major_ticks(_TICKS)
        panels.append((ax, cax))
    return fig, panels


#: a stress line picture's size (inches)
_LINE_SIZE = (7, 4.5)


def prepare_figures() -> None:
    """Make the next field picture's and stress line picture's empty figures now, with their
    axes and tick marks (a process waiting for a run's solution calls this while it waits: a
    quarter of those pictures' time, then off the run's critical path)."""
    plt = AggFigures()
    _prepared["field"] = _empty_field_figure(plt)
    fig, ax = plt.subplots(figsize=_LINE_SIZE)
    for axis in (ax.xaxis, ax.yaxis):
        axis.get_major_ticks(_TICKS + 2)  # up to nine bins
    _prepared["line"] = fig, ax


def prepare_field_background(title: str, window) -> None:
    """Draw now what the next field picture shows whatever the solution, when it is ``title``
    over ``window`` (:func:`field_layout`): the figure's title, each panel's frame, ticks and
    labels. Its picture then draws only the fields and their colour bars onto a copy of it
    (0.05 s of the 0.13 s a field picture of 12 000 triangles takes)."""
    fig, panels = _prepared.pop("field", None) or _empty_field_figure(AggFigures())
    fig.suptitle(title)
    for (ax, cax), (_, _, label) in zip(panels, _PANELS):
        _field_panel(ax, cax, label, window)
    fig.set_dpi(_DPI)
    frames = [spine for ax, _ in panels for spine in ax.spines.values()]
    for spine in frames:  # drawn once, over the fields (twice, their anti-aliased edges darken)
        spine.set_visible(False)
    fig.canvas.draw()
    for spine in frames:
        spine.set_visible(True)
    _prepared["field"] = fig, panels
    _prepared["field_background"] = (title, tuple(window)), fig.canvas.copy_from_bbox(fig.bbox)


def field_layout(problem: pb.Problem) -> tuple[str, tuple[float, float, float, float]] | None:
    """``fields.png``'s title and window: the problem's name and every body's exact bounding box
    (None when a body has no profile)."""
    boxes = [getattr(getattr(b, "profile", None), "bounds", None) for b in problem.bodies]
    if not boxes or any(box is None for box in boxes):
        return None
    lo = np.min([box[0] for box in boxes], axis=0)
    hi = np.max([box[1] for box in boxes], axis=0)
    return problem.name, (float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]))


def _save_on_background(fig: Any, background: Any, panels, path: Path) -> None:
    """Write ``fig`` drawing only its fields (and the frames over them) and colour bars onto
    ``background`` (the rest of it, drawn ahead), as an RGB PNG (solver.io.png)."""
    canvas = fig.canvas
    canvas.restore_region(background)
    renderer = canvas.get_renderer()
    for ax, cax in panels:
        for artist in [*ax.collections, *ax.spines.values()]:
            ax.draw_artist(artist)
        cax.draw(renderer)
    _write_canvas(fig, path)


def _save_drawn(fig: Any, path: Path) -> None:
    """``fig`` drawn at the pictures' resolution and written as an RGB PNG (solver.io.png: the same
    pixels as matplotlib's ``savefig``, encoded in less than half of Pillow's time)."""
    fig.set_dpi(_DPI)
    fig.canvas.draw()
    _write_canvas(fig, path)


def _write_canvas(fig: Any, path: Path) -> None:
    """What ``fig``'s canvas holds now, as an RGB PNG at the figure's resolution."""
    write_png(path, np.asarray(fig.canvas.buffer_rgba())[:, :, :3], dpi=fig.dpi)


def _field_figure(plt, outputs, title: str, window) -> Any:
    """von Mises and displacement magnitude side by side over ``window`` (None: the points'
    extent)."""
    fig, panels = _prepared.pop("field", None) or _empty_field_figure(plt)
    background = _prepared.pop("field_background", None)
    fig.suptitle(title)
    allpoints = np.concatenate([out.points for out in outputs])
    window = window or (allpoints[:, 0].min(), allpoints[:, 0].max(), allpoints[:, 1].min(), allpoints[:, 1].max())
    drawn = [_draw_field(fig, ax, cax, outputs, key, label, window) for (ax, cax), (_, key, label) in zip(panels, _PANELS)]
    if background is not None and background[0] == (title, tuple(window)) and all(drawn):
        fig._ibfem_background = background[1], panels
    return fig


def _close_up(c: Mapping[str, Any]) -> bool:
    return c.get("point") is not None and None not in c["point"]


def _field_figures(figs: _Figures, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
                   outputs: Mapping[str, Any], parts=None) -> None:
    """``fields.png`` (part "scene") and each contact's close-up (part k); every part when None."""
    held = [p["point"] for p in summary.get("probes") or [] if p.get("point") is not None]
    bodies = [outputs.get(b.name) or body_output(problem, solution, b, held) for b in problem.bodies]
    if not bodies:
        return
    if parts is None or "scene" in parts:
        layout = field_layout(problem)
        figs.save(_field_figure(figs.plt, bodies, problem.name, layout and layout[1]), "fields.png")
    # a close-up of each contact: 4 half-widths (at least 8 of the finest cells) around it
    finest = min(float(summary["bodies"].get(b.name, {}).get("min_element_size") or b.element_size)
                 for b in problem.bodies)
    for k, c in enumerate(summary.get("contacts", [])):
        if not _close_up(c) or (parts is not None and k not in parts):
            continue
        half = max(4.0 * float(c.get("half_width") or 0.0), 8.0 * finest)
        px, py = c["point"]
        window = (px - half, px + half, py - half, py + half)
        figs.save(_field_figure(figs.plt, bodies, f"{problem.name}, contact {k}", window), f"contact_{k}_fields.png")


def _line_figures(figs: _Figures, problem: pb.Problem, summary: Mapping[str, Any]) -> None:
    for name, line in summary.get("lines", {}).items():
        s = np.asarray(line.get("s") or np.linalg.norm(np.subtract(line["points"], line["points"][0]), axis=1), dtype=float)
        stress = np.asarray(line["stress"], dtype=float).reshape(-1, 3)
        vm = np.asarray(line["von_mises"], dtype=float)
        figs.save_stress_line(s, stress, vm, ("sxx", "syy", "sxy"), f"{problem.name}: line {name}",
                              f"line_{_file_stem(name)}.png")


def _curvature(body: pb.BodyModel, point: np.ndarray) -> float | None:
    """Signed curvature (convex positive) of the body's exact boundary at ``point``, or None
    where the profile cannot say (no projection or no curvature on that edge)."""
    try:
        proj = body.profile.project(np.asarray(point, dtype=float)[None, :])
        curve = body.profile.edge(body.profile.edge_names[int(proj.edge_index[0])])
        k = float(np.asarray(curve.curvature(np.asarray(proj.parameters[:1])))[0])
    except (AttributeError, NotImplementedError, TypeError, ValueError, IndexError):
        return None
    return k if np.isfinite(k) else None


def hertz_reference(problem: pb.Problem, c: Mapping[str, Any]) -> dict | None:
    """Hertz (and, frictional, Cattaneo-Mindlin) for the computed forces of a contact block when
    the contact is Hertzian: both radii of curvature known at the contact point, a convex pair
    (k1 + k2 > 0), a compressive force. Returns a, p0, R*, E* and the stick ratio, or None."""
    from ibfem.solver.reference import theory

    try:
        b1, b2 = (problem.body(n) for n in c["bodies"])
        point = np.asarray(c["point"], dtype=float)
        n_force = float(c["normal_force"])
    except (KeyError, TypeError, ValueError):
        return None
    k1, k2 = _curvature(b1, point), _curvature(b2, point)
    if k1 is None or k2 is None or not k1 + k2 > 1e-12 or not n_force > 0.0:
        return None
    m1, m2 = b1.material, b2.material
    e_star = theory.effective_modulus(m1.youngs_modulus, m1.poissons_ratio, m2.youngs_modulus, m2.poissons_ratio)
    r_star = 1.0 / (k1 + k2)
    a = theory.hertz_half_width(n_force, r_star, e_star)
    out = {"a": a, "p0": theory.hertz_peak_pressure(n_force, a), "R_eff": r_star, "E_eff": e_star}
    mu = float(c.get("friction") or 0.0)
    if c.get("type") == "frictional" and mu > 0.0:
        q_force = float(c.get("tangential_force") or 0.0)
        out.update(mu=mu, sign=float(np.sign(q_force)) or 1.0,
                   stick_ratio=float(theory.cattaneo_mindlin_stick_ratio(q_force, n_force, mu, allow_gross_slip=True)))
    return out


def _reference_curves(ax, ref: dict, s: np.ndarray, lscale: float = 1.0, sscale: float = 1.0) -> None:
    from ibfem.solver.reference import theory

    x = np.linspace(min(s.min(), -1.3 * ref["a"]), max(s.max(), 1.3 * ref["a"]), 600)
    ax.plot(x / lscale, theory.hertz_pressure(x, ref["a"], ref["p0"]) / sscale, "k--", lw=1.2,
            label=f"Hertz for the computed N (R* = {ref['R_eff']:.4g} m)")
    if "mu" in ref:
        q = theory.cattaneo_mindlin_shear(x, ref["a"], ref["stick_ratio"] * ref["a"], ref["mu"], ref["p0"], sign=ref["sign"])
        ax.plot(x / lscale, q / sscale, "k:", lw=1.2, label="Cattaneo-Mindlin for the computed Q, N")


def _contact_numbers(c: Mapping[str, Any], ref: dict | None, lscale: float, lname: str, sscale: float, sname: str) -> str:
    """a, c and p0 with their theory values (Hertz, Cattaneo-Mindlin) where a theory applies."""
    p0 = max((c.get("pressure") or {}).get("value") or [0.0])
    rows = [("a", c.get("half_width"), None if ref is None else ref["a"], lscale, lname),
            ("p0", p0, None if ref is None else ref["p0"], sscale, sname)]
    if c.get("type") == "frictional":
        rows.insert(1, ("c", c.get("stick_half_width"), None if ref is None or "stick_ratio" not in ref
                        else ref["stick_ratio"] * ref["a"], lscale, lname))
    out = []
    for name, value, theory, scale, unit in rows:
        if value is None:
            continue
        text = f"{name} = {value / scale:.4g} {unit}"
        if theory:
            text += f"  (theory {theory / scale:.4g}, {100.0 * (value / theory - 1.0):+.2f} %)"
        out.append(text)
    return "\n".join(out)


def _contact_figures(figs: _Figures, problem: pb.Problem, summary: Mapping[str, Any]) -> None:
    """Pressure and shear of every contact; Hertz / Cattaneo-Mindlin beside them when the
    contact is Hertzian (:func:`hertz_reference`), the legend says which curve is which, and a,
    c, p0 are written with their theory values."""
    for k, c in enumerate(summary.get("contacts", [])):
        pressure, shear = c.get("pressure") or {}, c.get("shear") or {}
        if not (pressure.get("s") or shear.get("s")):
            continue
        s_all = np.asarray(pressure.get("s") or shear.get("s"), float)
        lname, lscale = length_unit(float(np.ptp(s_all)) or 1.0)
        sname, sscale = stress_unit(max(np.abs(pressure.get("value") or [0.0]).max(), 1e-300))
        fig, ax = figs.plt.subplots(figsize=(9.6, 4.8))
        fig.subplots_adjust(left=0.085, right=0.66, bottom=0.11, top=0.92)  # fixed: the legend beside the axes
        if pressure.get("s"):
            ax.plot(np.asarray(pressure["s"], float) / lscale, np.asarray(pressure["value"], float) / sscale, lw=2,
                    label="pressure (computed)")
        if shear.get("s"):
            ax.plot(np.asarray(shear["s"], float) / lscale, np.asarray(shear["value"], float) / sscale, lw=2,
                    label="shear (computed)")
        ref = hertz_reference(problem, c)
        if ref is not None:
            _reference_curves(ax, ref, s_all, lscale, sscale)
        for line in _contact_numbers(c, ref, lscale, lname, sscale, sname).splitlines():
            ax.plot([], [], " ", label=line)  # the numbers listed in the legend, beside the axes
        title = f"{problem.name}: contact {' / '.join(c.get('bodies', []))}"
        figs.save_line_plot(fig, ax, f"s along the contact curve [{lname}]", f"traction [{sname}]", title,
                            f"contact_{k}.png", outside=True)


#: the kinds of pictures, which can be rendered apart: the fields over the bodies (2D: fields.png
#: and the contact close-ups; 3D: sections.png) and the profiles (contacts and output lines)
GROUPS = ("fields", "profiles")


def picture_tasks(problem: pb.Problem | None, summary: Mapping[str, Any]) -> tuple[str, ...]:
    """The pictures of a run in pieces that can be rendered apart (each a ``groups`` entry of
    :func:`write_plots`), the dearest first: in 2D ``fields:scene`` (fields.png), ``fields:<k>``
    (contact k's close-up) and ``profiles``; in 3D (or without a problem) :data:`GROUPS`."""
    if getattr(problem, "dim", None) != 2:
        return GROUPS
    contacts = json_safe(summary).get("contacts", [])
    return ("fields:scene", *(f"fields:{k}" for k, c in enumerate(contacts) if _close_up(c)), "profiles")


def _field_parts(groups) -> set | None:
    """The parts of the 2D field pictures ``groups`` asks for (None: all of them)."""
    if "fields" in groups:
        return None
    names = [g.split(":", 1)[1] for g in groups if g.startswith("fields:")]
    return {n if n == "scene" else int(n) for n in names}


def write_plots(
    out_dir: str | Path, problem: pb.Problem, solution: pb.Solution, summary: Mapping[str, Any],
    outputs: Mapping[str, Any] | None = None, groups=GROUPS,
) -> list[Path]:
    """Write the PNG pictures of ``groups`` (:data:`GROUPS`, or the pieces of
    :func:`picture_tasks`); returns their paths. ``outputs``: the bodies' output meshes
    (solver.io.body_output) already made for the VTU files, by body name."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    figs = _Figures(out_dir)
    summary = json_safe(summary)  # plain lists; None where a value is missing
    if problem.dim == 3:
        from .plots_solid import write_solid_plots

        write_solid_plots(out_dir, figs, problem, solution, summary, groups)
        return figs.written
    parts = _field_parts(groups)
    if parts is None or parts:
        _field_figures(figs, problem, solution, summary, outputs or {}, parts)
    if "profiles" in groups:
        _line_figures(figs, problem, summary)
        _contact_figures(figs, problem, summary)
    return figs.written

