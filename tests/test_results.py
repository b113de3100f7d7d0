"""Result writers against a stand-in Solution whose fields are known in closed form
(tests/_scene_standins.py): every number written must be the field at the right point, in
the right body, with NaN -> null; VTU files read back with the same field."""

import json
import math

import numpy as np
import pytest

from _scene_standins import E, NU, FieldBody, FieldSolution, plane_strain_stress
from ibfem.solver.model import problem as pb
from ibfem.solver.io import output, results

STEEL = pb.Material("steel", E, NU)
UPPER = FieldBody("upper", (0.0, 0.0), (1.0, 1.0), a=1e-4, b=-2e-4)
LOWER = FieldBody("lower", (0.0, -1.0), (1.0, 0.0), a=3e-4, b=5e-5, c=1e-3, d=-2e-3)


def make_problem(model="plane_strain"):
    bodies = tuple(pb.BodyModel(name=b.name, profile=None, material=STEEL, element_size=0.25) for b in (UPPER, LOWER))
    return pb.Problem(name="two blocks", model=model, thickness=1.0, bodies=bodies)


def make_solution(**kw):
    return FieldSolution(bodies=[UPPER, LOWER], **kw)


def vm_reference(s, nu=NU):
    """Von Mises from the principal stresses (an independent route from the component formula)."""
    sxx, syy, sxy = s
    c, r = 0.5 * (sxx + syy), math.hypot(0.5 * (sxx - syy), sxy)
    s1, s2, s3 = c + r, c - r, nu * (sxx + syy)
    return math.sqrt(0.5 * ((s1 - s2) ** 2 + (s2 - s3) ** 2 + (s3 - s1) ** 2))


def test_von_mises_matches_principal_stress_form():
    rng = np.random.default_rng(1)
    s = rng.normal(size=(50, 3)) * 1e8
    got = results.von_mises(s, "plane_strain", NU)
    assert np.allclose(got, [vm_reference(x) for x in s], rtol=1e-12)
    got_ps = results.von_mises(s, "plane_stress", NU)
    assert np.allclose(got_ps, [vm_reference(x, nu=0.0) for x in s], rtol=1e-12)
    # uniaxial tension in plane stress: von Mises equals the stress
    assert results.von_mises(np.array([5.0, 0, 0]), "plane_stress", NU) == pytest.approx(5.0)


def test_summary_has_exactly_the_spec_keys_and_values(tmp_path):
    problem = make_problem()
    reactions = {"upper/top": np.array([1.5, -2.0]), "lower/bottom": np.array([-1.5, 2.0])}
    solution = make_solution(reactions=reactions)
    probes = [[0.25, 0.5], [0.75, -0.25], [3.0, 3.0]]
    lines = [{"name": "down", "start": [0.5, 0.9], "end": [0.5, -0.9], "n": 37}]
    written = output.write_results(tmp_path, problem, solution, probes=probes, lines=lines, vtk=False, total_s=1.5)
    data = json.loads((tmp_path / "summary.json").read_text())
    spec_keys = {"name", "converged", "model", "bodies", "reactions", "contacts", "probes", "lines", "iterations", "timings"}
    assert spec_keys <= set(data)
    # the documented extensions at top level: the files written, the version, the time, the units
    assert set(data) - spec_keys == {"files", "ibfem_version", "created", "units"}
    from importlib import metadata
    from datetime import datetime, timezone

    assert data["ibfem_version"] == metadata.version("ibfem")
    created = datetime.fromisoformat(data["created"])
    assert created.tzinfo is not None and abs((datetime.now(timezone.utc) - created).total_seconds()) < 600
    assert data["units"]["force"] == "N/m" and data["units"]["stress"] == "Pa" and data["units"]["length"] == "m"
    assert data == json.loads(json.dumps(results.json_safe(written)))
    assert data["name"] == "two blocks" and data["converged"] is True and data["model"] == "plane_strain"
    assert data["bodies"]["upper"] == {"elements": 8, "dofs": 30, "element_size": 0.25, "min_element_size": 0.125}
    assert data["reactions"] == {"upper/top": [1.5, -2.0], "lower/bottom": [-1.5, 2.0]}
    assert data["iterations"] == {"total": 3, "per_step": [1, 2]}
    timings = data["timings"]
    assert {k: timings[k] for k in ("assembly_s", "solver_total_s")} == {"assembly_s": 0.1, "solver_total_s": 0.25}
    # the run's total includes the output written, and says how long that took
    assert timings["output_s"] >= timings["summary_s"] > 0.0 and "vtk_s" not in timings
    assert timings["total_s"] == pytest.approx(1.5 + timings["output_s"], abs=1e-12)

    # probes: the closed-form field of the body containing each point
    p0, p1, p2 = data["probes"]
    x0, x1 = np.array([probes[0]]), np.array([probes[1]])
    assert p0["body"] == "upper" and p1["body"] == "lower"
    assert np.allclose(p0["displacement"], [1e-4 * 0.25**2, -2e-4 * 0.25 * 0.5], rtol=1e-14)
    assert np.allclose(p1["displacement"], [3e-4 * 0.75**2 + 1e-3, 5e-5 * 0.75 * -0.25 - 2e-3], rtol=1e-14)
    assert np.allclose(p0["stress"], UPPER.stress(x0)[0], rtol=1e-14)
    assert np.allclose(p1["stress"], LOWER.stress(x1)[0], rtol=1e-14)
    assert p1["von_mises"] == pytest.approx(vm_reference(LOWER.stress(x1)[0]), rel=1e-12)
    # outside every body: nulls, not NaN (valid JSON)
    assert p2 == {"point": [3.0, 3.0], "body": None, "displacement": [None, None],
                  "stress": [None, None, None], "von_mises": None}

    # line: points from start to end, each sampled in its own body
    line = data["lines"]["down"]
    pts = np.array(line["points"])
    assert pts.shape == (37, 2) and np.allclose(pts[0], [0.5, 0.9]) and np.allclose(pts[-1], [0.5, -0.9])
    assert np.allclose(np.diff(line["s"]), 1.8 / 36)
    stress = np.array(line["stress"], dtype=float)
    upper = pts[:, 1] >= 0  # the interface y = 0 belongs to the first body (body_at order)
    assert np.allclose(stress[upper], UPPER.stress(pts[upper]), rtol=1e-14)
    assert np.allclose(stress[~upper], LOWER.stress(pts[~upper]), rtol=1e-14)
    disp = np.array(line["displacement"])
    assert np.allclose(disp[~upper], LOWER.displacement(pts[~upper]), rtol=1e-14)
    assert line["body"] == ["upper" if u else "lower" for u in upper]
    assert np.allclose(line["von_mises"], [vm_reference(s) for s in stress], rtol=1e-12)


def test_non_converged_history_kept_and_json_strict(tmp_path):
    history = {"total": 100, "per_step": [100], "residual": [1.0, 0.5, float("nan")], "status": "max_iterations"}
    solution = make_solution(converged=False, iterations=history)
    output.write_results(tmp_path, make_problem(), solution, vtk=False)
    text = (tmp_path / "summary.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    data = json.loads(text)
    assert data["converged"] is False
    assert data["iterations"] == {"total": 100, "per_step": [100], "residual": [1.0, 0.5, None], "status": "max_iterations"}
    assert data["probes"] == [] and data["lines"] == {}


def test_contacts_pass_through_json_safe(tmp_path):
    block = {"bodies": ["upper", "lower"], "type": "frictionless", "friction": 0.0, "point": np.array([0.5, 0.0]),
             "normal": np.array([0.0, 1.0]), "tangent": [-1.0, 0.0], "half_width": np.float64(0.01),
             "stick_half_width": 0.0, "normal_force": 12.0, "tangential_force": 0.0,
             "pressure": {"s": np.linspace(-0.01, 0.01, 5), "value": np.ones(5)}, "shear": {"s": [], "value": []}}
    output.write_results(tmp_path, make_problem(), make_solution(contacts=[block]), vtk=False, plots=True)
    data = json.loads((tmp_path / "summary.json").read_text())
    c = data["contacts"][0]
    assert c["point"] == [0.5, 0.0] and c["half_width"] == 0.01 and c["pressure"]["value"] == [1.0] * 5
    assert data["files"] == ["contact_0.png", "contact_0_fields.png", "fields.png", "report.html"]


def test_vtu_files_hold_the_field(tmp_path):
    pv = pytest.importorskip("pyvista")
    problem = make_problem()
    summary = output.write_results(tmp_path, problem, make_solution(), vtk=True)
    assert summary["files"] == ["lower.vtu", "result.vtm", "upper.vtu"]
    for body in (UPPER, LOWER):
        grid = pv.read(tmp_path / f"{body.name}.vtu")
        assert grid.n_cells == 8 and grid.n_points == 15
        pts = np.asarray(grid.points)[:, :2]
        assert np.allclose(np.asarray(grid.point_data["displacement"])[:, :2], body.displacement(pts), rtol=1e-14)
        assert np.allclose(np.asarray(grid.point_data["displacement"])[:, 2], 0.0)
        # point stress: the field at the points, in VTK's tensor order with szz = nu (sxx + syy)
        expected = plane_strain_stress(body.strain(pts))
        tensor = np.asarray(grid.point_data["stress"])
        assert np.allclose(tensor[:, [0, 1, 3]], expected, rtol=1e-12)
        assert np.allclose(tensor[:, 2], NU * (expected[:, 0] + expected[:, 1]), rtol=1e-12)
        assert np.allclose(tensor[:, [4, 5]], 0.0)
        assert np.allclose(grid.point_data["von_mises"], [vm_reference(s) for s in expected], rtol=1e-12)
        # principal stresses are the tensor's eigenvalues: their sum is its trace
        principal = np.asarray(grid.point_data["principal_stress"])
        assert np.all(np.diff(principal, axis=1) <= 1e-6 * np.abs(principal).max())
        assert np.allclose(principal.sum(axis=1), tensor[:, :3].sum(axis=1), rtol=1e-10)
        centres = np.asarray(grid.cell_centers().points)[:, :2]
        raw = plane_strain_stress(body.strain(centres))
        assert np.allclose(np.asarray(grid.cell_data["cell_stress"])[:, [0, 1, 3]], raw, rtol=1e-12)
        assert np.allclose(grid.cell_data["cell_von_mises"], [vm_reference(s) for s in raw], rtol=1e-12)
        # the cells tile the body: total area = the rectangle's
        areas = grid.compute_cell_sizes(length=False, volume=False)["Area"]
        assert np.sum(areas) == pytest.approx((body.hi[0] - body.lo[0]) * (body.hi[1] - body.lo[1]))
    index = pv.read(tmp_path / "result.vtm")
    assert index.n_blocks == 2


def test_plots_are_png_images(tmp_path):
    lines = [{"name": "across body", "start": [0.0, 0.5], "end": [1.0, 0.5], "n": 20}]
    summary = output.write_results(tmp_path, make_problem(), make_solution(), lines=lines, vtk=False, plots=True)
    assert summary["files"] == ["fields.png", "line_across_body.png", "report.html"]
    page = (tmp_path / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 2 and "src=\"http" not in page  # self-contained
    for name in summary["files"][:2]:
        head = (tmp_path / name).read_bytes()[:8]
        assert head == b"\x89PNG\r\n\x1a\n" and (tmp_path / name).stat().st_size > 5000


def test_json_safe_rejects_unknown_objects():
    with pytest.raises(TypeError, match="not JSON-serialisable"):
        results.json_safe({"x": object()})
    assert results.json_safe({"a": np.array([1.0, np.inf]), "b": np.int64(3), "c": np.bool_(True)}) == {
        "a": [1.0, None], "b": 3, "c": True}


def test_contact_blocks_get_every_spec_key_in_order(tmp_path):
    problem = make_problem()
    problem = pb.Problem(name=problem.name, model=problem.model, thickness=1.0, bodies=problem.bodies,
                         contacts=(pb.ContactModel(bodies=("upper", "lower"), type="frictional", friction=0.3),))
    partial = {"normal": [0.6, 0.8], "normal_force": 5.0, "width_iterations": 4}
    output.write_results(tmp_path, problem, make_solution(contacts=[partial]), vtk=False)
    (c,) = json.loads((tmp_path / "summary.json").read_text())["contacts"]
    assert list(c)[:12] == ["bodies", "type", "friction", "point", "normal", "tangent", "half_width",
                            "stick_half_width", "normal_force", "tangential_force", "pressure", "shear"]
    assert c["bodies"] == ["upper", "lower"] and c["type"] == "frictional" and c["friction"] == 0.3
    assert c["tangent"] == [-0.8, 0.6]  # the tangent is (-n_y, n_x)
    assert c["half_width"] is None and c["pressure"] == {"s": [], "value": []}
    assert c["normal_force"] == 5.0 and c["width_iterations"] == 4


def test_contact_checks_say_what_they_count_and_a_half_model_names_the_full_force(tmp_path):
    problem = make_problem()
    block = {"normal": [0.0, 1.0], "normal_force": 5.0, "half_width": 0.01, "stick_half_width": 0.0,
             "tangential_force": 0.0, "model_share": 0.5,
             "checks": {"tension": False, "tension_points": 4, "min_pressure": -2.0}}
    contacts = (pb.ContactModel(bodies=("upper", "lower"), type="frictionless"),)
    p = pb.Problem(name="p", model="plane_strain", thickness=1.0, bodies=problem.bodies, contacts=contacts)
    output.write_results(tmp_path, p, make_solution(contacts=[dict(block)]), vtk=False)
    (c,) = json.loads((tmp_path / "summary.json").read_text())["contacts"]
    assert c["checks"] == {"tension_at_region_edges": False, "tensile_samples_inside_region": 4,
                           "smallest_pressure_inside_region": -2.0}
    assert c["full_contact"] == {"model_share": 0.5, "normal_force": 10.0}  # a half model carries half


def test_the_result_line_names_the_models_share_and_the_full_force():
    from ibfem.solver.io.result_line import contact_line

    quarter = {"bodies": ["ball", "block"], "type": "frictionless", "semi_axes": [0.04, 0.04], "normal_force": 3.42e6,
               "model_share": 0.25, "full_contact": {"model_share": 0.25, "normal_force": 1.368e7}}
    line = contact_line(quarter)
    assert "normal_force (quarter model) = 3.42e+06 N; full contact 1.368e+07 N" in line
    assert "stick" not in line and "tangential" not in line
    quarter["stick_semi_axes"], quarter["tangential_force"] = [0.0, 0.0], [0.0, 0.0]
    assert contact_line(quarter) == line  # a frictionless contact has neither
    frictional = {"type": "frictional", "half_width": 0.01, "stick_half_width": 0.007, "normal_force": 2.0,
                  "tangential_force": 0.1}
    assert contact_line(frictional) == ("half_width = 0.01 m, stick_half_width = 0.007 m, normal_force = 2 N/m, "
                                        "tangential_force = 0.1 N/m")


def test_progress_names_every_output_being_written(tmp_path):
    messages = []
    output.write_results(tmp_path, make_problem(), make_solution(), vtk=True, plots=True,
                         progress=lambda *a, **k: messages.append(" ".join(map(str, a))))
    assert messages[0].startswith("results: summary")
    assert {"results: upper.vtu", "results: lower.vtu", "results: plots"} <= {m.split(" (")[0] for m in messages}


def test_the_reports_checks_carry_their_units(tmp_path):
    # the documented units of the checks: gaps and brackets in m, pressures in Pa, the force on
    # the first body in the summary's force unit; counts and flags bare
    from ibfem.solver.io.report_html import write_report

    checks = {"gap_beyond_region_edges": 2.5e-05, "pressure_inside_region_edges": 6.5e8, "size_bracket": [0.045, 0.046],
              "force_on_first": [0.0, -3.0e6], "tensile_samples_inside_region": 12, "penetration_found": False}
    summary = {"name": "t", "units": {"force": "N"}, "bodies": {},
               "contacts": [{"bodies": ["a", "b"], "type": "frictionless", "semi_axes": [0.045, 0.045],
                             "normal_force": 3.0e6, "checks": checks}]}
    page = write_report(tmp_path, summary, [], None).read_text()
    for text in ("2.5e-05 m", "6.5e+08 Pa", "[0.045, 0.046] m", "[0, -3e+06] N", "<td>12</td>", "<td>false</td>"):
        assert text in page


def test_pictures_started_before_the_estimate_are_waited_for_and_timed(tmp_path):
    """The pictures start right after the solve (the error estimate then adds to the contact
    blocks): the files and summary hold the later additions, the pictures are listed, and the
    start's seconds, spent before ``total_s`` was taken, count in ``output_s`` but not twice in
    ``total_s``."""
    block = {"bodies": ["upper", "lower"], "type": "frictionless", "friction": 0.0, "point": [0.5, 0.0],
             "normal": [0.0, 1.0], "tangent": [-1.0, 0.0], "half_width": 0.01, "stick_half_width": 0.0,
             "normal_force": 12.0, "tangential_force": 0.0,
             "pressure": {"s": list(np.linspace(-0.01, 0.01, 5)), "value": [1.0] * 5}, "shear": {"s": [], "value": []}}
    problem, solution = make_problem(), make_solution(contacts=[block])
    started = output.start_pictures(tmp_path, problem, solution, vtk=False, plots=True)
    assert output.start_pictures(tmp_path, problem, solution, vtk=False, plots=False) is None
    block["estimated_error"] = {"half_width": 0.001}  # what the estimate adds after the start
    summary = output.write_results(tmp_path, problem, solution, vtk=False, plots=True, total_s=2.0, pictures=started)
    data = json.loads((tmp_path / "summary.json").read_text())
    assert data["contacts"][0]["estimated_error"] == {"half_width": 0.001}
    assert data["files"] == ["contact_0.png", "contact_0_fields.png", "fields.png", "report.html"]
    assert all((tmp_path / f).stat().st_size > 0 for f in data["files"])
    t = summary["timings"]
    earlier = sum(started.times.values())
    assert t["output_s"] >= earlier > 0.0 and t["output_s"] >= t["plots_s"] > 0.0
    assert t["total_s"] - 2.0 == pytest.approx(t["output_s"] - earlier, abs=1e-9)
