"""Fuzz (long run only): plane examples with random physical variations (load scaled, contact
type and friction, grid a little coarser or finer, load steps) solved by ``ibfem run`` in a child
process with a time and memory limit, then the same scene turned and shifted: exit 0, 1 or 2
only, exit 1 with its summary, a converged summary consistent with its own contact checks, and
the normal force of the moved scene within 1 % where the grid resolves the contact as the shipped
example's does (what ``make fuzz`` accepts); coarser variants check the rest."""

from __future__ import annotations

import json
import math
import tempfile
import time
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from _oracles import forces_agree, run_scene
from _transform import moved

ROOT = Path(__file__).resolve().parents[2]
CONTACT_EXAMPLES = ["cylinder_on_cylinder_frictionless", "cylinder_on_wedge_frictionless", "ellipse_on_block",
                    "ellipse_on_block_tessellated", "cylinder_on_flat_partial_slip", "cylinder_in_concave_partial_slip",
                    "cylinder_on_cylinder_partial_slip"]
WORK = Path(tempfile.mkdtemp(prefix="ibfem-fuzz-solve-"))
#: a solve longer than this is a defect (the examples take 1-20 s)
TIMEOUT = 240.0


def _variant(data) -> tuple[dict, str, bool]:
    """A varied example, its description, and whether its grid resolves the contact as the
    shipped one does (only then is a 1 % agreement of N across rigid motions a fair demand: with
    two refinement levels fewer or a grid twice as coarse, the cylinder on flat at a quarter load
    is 2.5 % off its fine N and its a 15 % off, and N moves by as much with the grid's position)."""
    name = data.draw(st.sampled_from(CONTACT_EXAMPLES))
    d = tomllib.loads((ROOT / "examples" / f"{name}.toml").read_text())
    d["output"] = {"vtk": False, "plots": False}
    notes = [name]
    load = data.draw(st.sampled_from([0.25, 0.5, 1.0, 1.5, 2.0]))
    for bc in d["boundary_conditions"]:
        if bc["type"] == "displacement":
            bc["value"] = [v if v == "free" else v * load for v in bc["value"]]
    notes.append(f"load x{load}")
    grid = data.draw(st.sampled_from([1.0, 1.0, 0.8, 1.25, 2.0]))
    coarser = data.draw(st.sampled_from([0, 0, 1, 2]))  # finest refinement levels fewer by this
    for body in d["bodies"]:
        body["element_size"] *= grid
        for zone in body.get("refinement", []):
            zone["levels"] = max(1, zone["levels"] - coarser)
    notes.append(f"element_size x{grid}, levels -{coarser}")
    resolved = coarser == 0 and grid <= 1.25
    if data.draw(st.integers(0, 3)) == 0:  # the tessellated variant (where non-converged runs were once reported as converged)
        d["solver"]["exact_geometry"] = not d["solver"].get("exact_geometry", True)
        notes.append(f"exact_geometry {d['solver']['exact_geometry']}")
    contact = d["contacts"][0]
    kind = data.draw(st.sampled_from([contact["type"], "tied", "frictionless", "frictional"]))
    if kind != contact["type"]:
        contact["type"] = kind
        contact.pop("friction", None)
        if kind == "frictional":
            contact["friction"] = data.draw(st.sampled_from([0.1, 0.3, 0.6]))
        notes.append(f"contact {kind}")
    if data.draw(st.booleans()):
        contact.pop("point", None)
        notes.append("no contact point")
    return d, ", ".join(notes), resolved


def _motion(data, d) -> tuple[float, tuple[float, float]]:
    free = any("free" in bc.get("value", []) for bc in d["boundary_conditions"] if bc["type"] == "displacement")
    deg = data.draw(st.sampled_from([90.0, 180.0, 270.0])) if free else data.draw(
        st.sampled_from([90.0, 180.0, 17.0, 33.0, 45.0, 120.0]))
    shift = (data.draw(st.sampled_from([0.0, 0.37, -1.9])), data.draw(st.sampled_from([0.0, 0.21, 2.6])))
    return deg, shift


def solve_case(data, k: int) -> tuple[list[str], dict]:
    d, what, resolved = _variant(data)
    deg, shift = _motion(data, d)
    case = {"change": what, "turn": deg, "shift": shift}
    problems = []
    summaries = []
    for tag, doc in (("a", d), ("b", moved(d, deg, shift))):
        path = WORK / f"{k}{tag}.json"
        path.write_text(json.dumps(doc))
        found, summary = run_scene(path, WORK / f"{k}{tag}", TIMEOUT)
        problems += [f"{tag}: {p}" for p in found]
        summaries.append(summary)
        if found:
            case[f"scene_{tag}"] = doc
    if all(summaries) and resolved:
        problems += forces_agree(*summaries)
        case["normal_force"] = [s["contacts"][0].get("normal_force") for s in summaries]
    return problems, case


@pytest.mark.slow
@pytest.mark.fuzz_long
def test_fuzz_long_solves(findings):
    stop = findings.budget("solves")
    counter = iter(range(10**9))

    @settings(max_examples=2, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(st.data())
    def one(data):
        problems, case = solve_case(data, next(counter))
        findings.record("solves", problems, case)
        findings.record("solves-ok" if not problems else "solves-bad", [], case)

    while time.monotonic() < stop:
        one()
    print(findings.summary("solves"))
    assert not [f for f in findings.found if f["family"] == "solves"], findings.summary("solves")
