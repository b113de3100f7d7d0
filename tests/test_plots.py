"""Every kind of plot rendered headless on a solved 2D and 3D contact and checked: PNG size, no
NaN in the picture, each colour scale reaching above the 99th percentile of the field it shows
in the contact window (the contact's peak is never cut off), the numbers in fitting units."""

import numpy as np
import pytest

plt = pytest.importorskip("matplotlib.pyplot")

from _contact_scenes import cylinder_on_block  # noqa: E402
from ibfem.solver.io import plots, plots_solid  # noqa: E402
from ibfem.solver.io.output import write_results  # noqa: E402
from ibfem.solver.io.plot_units import length_unit, stress_unit  # noqa: E402
from ibfem.solver.io.results import json_safe  # noqa: E402
from ibfem.solver.io.scene import scene_from_dict  # noqa: E402
from ibfem.solver.solving import solve  # noqa: E402

image = pytest.importorskip("matplotlib.image")


def _check_png(path, min_width=600, min_height=400):
    pixels = image.imread(path)
    assert pixels.shape[0] >= min_height and pixels.shape[1] >= min_width
    assert np.all(np.isfinite(pixels)) and pixels.std() > 0.01  # a picture, not a blank


def test_units_fit_the_numbers():
    assert stress_unit(2.3e9) == ("GPa", 1e9) and stress_unit(4.5e8) == ("MPa", 1e6)
    assert length_unit(0.05) == ("mm", 1e-3) and length_unit(3e-4) == ("um", 1e-6) and length_unit(2.0) == ("m", 1.0)


def test_2d_plots_show_the_contacts_peak(tmp_path):
    problem = cylinder_on_block("frictional", ux=2e-4, friction=0.3)
    solution = solve(problem)
    summary = write_results(tmp_path, problem, solution, vtk=False, plots=True)
    pngs = [f for f in summary["files"] if f.endswith(".png")]
    assert set(pngs) == {"contact_0.png", "contact_0_fields.png", "fields.png"}
    for name in pngs:
        _check_png(tmp_path / name)
    # the contact window's field picture: its von Mises scale reaches the 99th percentile of the
    # field at the points in that window
    from ibfem.solver.io.body_output import body_output

    c = json_safe(summary)["contacts"][0]
    outputs = [body_output(problem, solution, b) for b in problem.bodies]
    half = max(4.0 * c["half_width"], 8.0 * min(b["min_element_size"] for b in summary["bodies"].values()))
    window = (c["point"][0] - half, c["point"][0] + half, c["point"][1] - half, c["point"][1] + half)
    fig = plots._field_figure(plt, outputs, "t", window)
    unit = stress_unit(max(np.nanmax(o.point_data["von_mises"]) for o in outputs))[1]
    top = fig.axes[0].collections[0].get_clim()[1] * unit
    inside = []
    for o in outputs:
        near = np.all(np.abs(o.points - c["point"]) < half, axis=1)
        inside.append(np.asarray(o.point_data["von_mises"])[near])
    assert top >= np.percentile(np.concatenate(inside), 99) * (1 - 1e-12)
    plt.close(fig)


def test_field_and_line_pictures_made_ahead_are_the_same_pictures(tmp_path):
    """A picture process that makes the empty figures while it waits for the run
    (plots.prepare_figures) writes, pixel for pixel, the pictures made all at once."""
    problem = cylinder_on_block("frictionless", ux=0.0)
    solution = solve(problem)
    line = {"name": "down", "start": [0.0, 0.5], "end": [0.0, -0.5], "n": 40}
    summary = write_results(tmp_path / "first", problem, solution, lines=[line], vtk=False, plots=False)
    pictures = []
    for ahead in ("nothing", "empty figures", "fixed parts drawn"):
        if ahead != "nothing":
            plots.prepare_figures()
        if ahead == "fixed parts drawn":  # the title, frames, ticks and labels drawn ahead
            plots.prepare_field_background(*plots.field_layout(problem))
        written = plots.write_plots(tmp_path / ahead, problem, solution, summary,
                                    groups=("fields:scene", "profiles"))
        pictures.append({p.name: image.imread(p)[:, :, :3] for p in written})  # RGB from the drawn ahead
        assert not plots._prepared  # each taken by its picture
    assert {"fields.png", "line_down.png"} <= set(pictures[0]) == set(pictures[1]) == set(pictures[2])
    for name in pictures[0]:
        assert np.array_equal(pictures[0][name], pictures[1][name]), name
        assert np.array_equal(pictures[0][name], pictures[2][name]), name


def test_fixed_parts_drawn_for_another_picture_are_drawn_again(tmp_path):
    """Fixed parts drawn ahead for another title or window are not used: the picture is drawn
    whole, the same as without them."""
    problem = cylinder_on_block("frictionless", ux=0.0)
    solution = solve(problem)
    summary = write_results(tmp_path / "first", problem, solution, vtk=False, plots=False)
    title, (x0, x1, y0, y1) = plots.field_layout(problem)
    assert x1 > x0 and y1 > y0
    drawn = []
    for layout in (None, ("another scene", (x0, x1, y0, y1)), (title, (x0, x1, y0, 0.5 * (y0 + y1)))):
        if layout is not None:
            plots.prepare_field_background(*layout)
        written = plots.write_plots(tmp_path / str(len(drawn)), problem, solution, summary, groups=("fields:scene",))
        drawn.append(image.imread(written[0])[:, :, :3])
        assert not plots._prepared
    assert np.array_equal(drawn[0], drawn[1]) and np.array_equal(drawn[0], drawn[2])


SOLID = {
    "model": "solid", "name": "ball on block",
    "materials": [{"name": "steel", "youngs_modulus": 2e11, "poissons_ratio": 0.3}],
    "bodies": [
        {"name": "ball", "material": "steel", "element_size": 0.25,
         "refinement": {"levels": 2, "around": "contact", "radius": 0.15},
         "shape": {"type": "half_sphere", "center": [0, 0, 1], "radius": 1.0}},
        {"name": "block", "material": "steel", "element_size": 0.25,
         "refinement": {"levels": 2, "around": "contact", "radius": 0.15},
         "shape": {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 0]}},
    ],
    "boundary_conditions": [
        {"type": "displacement", "body": "ball", "face": "flat", "value": [0, 0, -0.002]},
        {"type": "fixed", "body": "block", "face": "z_min"},
    ],
    "contacts": [{"bodies": ["ball", "block"], "type": "frictionless"}],
}


def test_3d_sections_reach_the_peak_and_name_theory(tmp_path):
    problem = scene_from_dict(SOLID).problem
    solution = solve(problem)
    lines = [{"name": "axis", "start": [0, 0, 0], "end": [0, 0, -0.2], "n": 50}]
    summary = write_results(tmp_path, problem, solution, lines=lines, vtk=False, plots=True)
    assert {"sections.png", "contact_0.png", "line_axis.png", "report.html"} <= set(summary["files"])
    for name in ("sections.png", "contact_0.png", "line_axis.png"):
        _check_png(tmp_path / name)
    contacts = json_safe(summary)["contacts"]
    fig = plots_solid._sections(plt, problem, solution, contacts)
    images = [ax.images[0] for ax in fig.axes if ax.images]
    assert len(images) == 6
    for im in images:  # each panel's scale reaches above the 99th percentile of what it shows
        shown = np.ma.masked_invalid(im.get_array()).compressed()
        assert shown.size > 1000 and im.get_clim()[1] >= np.percentile(shown, 99)
    plt.close(fig)
    # the contact picture names the semi-axes and p0 beside Hertz's for the computed force
    rows = plots_solid.contact_numbers(problem, contacts[0])
    assert [r[0] for r in rows] == ["a", "b", "p0"] and all(r[2] is not None and r[2] > 0 for r in rows)


def test_sections_without_a_contact_pass_through_the_largest_von_mises_inside_a_body():
    # a stand-in solution: s_xx = 1 / (0.1 + |x - x0|), peaked at x0 inside the unit ball, and a
    # larger value at a grid node outside the ball (extrapolated there) that must not count
    from types import SimpleNamespace

    g = np.linspace(-1.5, 1.5, 13)
    nodes = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    peak = np.array([0.5, -0.25, 0.0])
    stress = np.zeros((len(nodes), 6))
    stress[:, 0] = 1.0 / (0.1 + np.linalg.norm(nodes - peak, axis=1))
    outside = np.argmax(np.linalg.norm(nodes, axis=1))
    stress[outside, 0] = 1e3
    ball = SimpleNamespace(name="ball", grid=SimpleNamespace(nodes=nodes),
                           contains=lambda p: np.linalg.norm(p, axis=1) <= 1.0)
    solution = SimpleNamespace(bodies=[ball], nodal_stress=lambda name: stress)
    material = SimpleNamespace(poissons_ratio=0.3)
    problem = SimpleNamespace(model="solid", body=lambda name: SimpleNamespace(material=material),
                              bodies=[SimpleNamespace(profile=SimpleNamespace(bounds=([-1, -1, -1], [1, 1, 1])))])
    point = plots_solid._peak(problem, solution)
    assert np.allclose(point, peak)
    planes = plots_solid.section_planes(problem, [], point)
    for k, plane in enumerate(planes):  # the plane x_k = peak_k, the axes in absolute coordinates
        assert plane["origin"][k] == pytest.approx(peak[k]) and plane["title"].startswith("xyz"[k])
        a, b = (j for j in range(3) if j != k)
        assert plane["offset"] == (plane["origin"][a], plane["origin"][b]) == (0.0, 0.0)
