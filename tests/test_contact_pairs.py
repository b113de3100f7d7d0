"""Two bodies touching at several places: a pin pressed into a 90-degree V-groove touches both
flanks. Checked against symmetry (the two contacts equal), equilibrium (the hub's vertical
reaction is 2 N cos 45 degrees) and Hertz's line contact for each flank's own force; the scene
errors when a pair's contacts lack points or share one; overlapping regions are reported."""

import math

import numpy as np
import pytest

from ibfem.solver.contact.region_overlap import overlapping_regions
from ibfem.solver.io.scene import SceneError, scene_from_dict
from ibfem.solver.solving import solve

E, NU, R = 2.0e11, 0.3, 0.4
# the pin's centre above the groove's root so that it touches both flanks (y = |x| - 0.5): the
# flanks are R from the centre at (+-R / sqrt(2), yc - R / sqrt(2))
YC = R * math.sqrt(2.0) - 0.5
TOUCH = (R / math.sqrt(2.0), YC - R / math.sqrt(2.0))


def v_groove(contacts=None, levels=5) -> dict:
    zone = [{"levels": levels, "around": "contact", "radius": 0.1}]
    edges = [((-2.0, -2.0), (2.0, -2.0), "bottom"), ((2.0, -2.0), (2.0, 0.0), "right"),
             ((2.0, 0.0), (0.5, 0.0), "top_right"), ((0.5, 0.0), (0.0, -0.5), "flank_right"),
             ((0.0, -0.5), (-0.5, 0.0), "flank_left"), ((-0.5, 0.0), (-2.0, 0.0), "top_left"),
             ((-2.0, 0.0), (-2.0, -2.0), "left")]
    if contacts is None:
        contacts = [{"bodies": ["pin", "block"], "type": "frictionless", "point": [sx * TOUCH[0], TOUCH[1]]}
                    for sx in (1.0, -1.0)]
    return {
        "name": "pin in a V-groove", "model": "plane_strain", "output": {"vtk": False, "plots": False},
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU}],
        "bodies": [
            {"name": "pin", "material": "steel", "element_size": 0.1, "refinement": zone, "shape": {
                "type": "profile",
                "edges": [{"name": "rim", "type": "arc", "center": [0.0, YC], "radius": R, "start_angle": 0.0,
                           "end_angle": 360.0}],
                "holes": [[{"name": "hub", "type": "arc", "center": [0.0, YC], "radius": 0.05, "start_angle": 0.0,
                            "end_angle": 360.0}]]}},
            {"name": "block", "material": "steel", "element_size": 0.1, "refinement": zone, "shape": {
                "type": "profile",
                "edges": [{"name": n, "type": "line", "start": list(a), "end": list(b)} for a, b, n in edges]}},
        ],
        "boundary_conditions": [
            {"body": "pin", "edge": "hub", "type": "displacement", "value": [0.0, -0.001]},
            {"body": "block", "edge": "bottom", "type": "fixed"},
        ],
        "contacts": contacts,
    }


def test_a_pin_in_a_v_groove_touches_both_flanks_alike():
    solution = solve(scene_from_dict(v_groove(), label="groove.toml").problem)
    assert solution.converged
    right, left = solution.contacts
    assert right["half_width"] == pytest.approx(left["half_width"], rel=1e-6)  # the groove's symmetry
    assert right["normal_force"] == pytest.approx(left["normal_force"], rel=1e-6)
    assert np.allclose(right["normal"], [-1 / math.sqrt(2), 1 / math.sqrt(2)], atol=1e-9)  # each flank's normal
    assert np.allclose(left["normal"], [1 / math.sqrt(2), 1 / math.sqrt(2)], atol=1e-9)
    hub = solution.reactions["pin/hub"]
    assert -hub[1] == pytest.approx(2.0 * right["normal_force"] / math.sqrt(2.0), rel=1e-6)  # equilibrium
    assert abs(hub[0]) < 1e-6 * abs(hub[1])
    e_star = E / (2.0 * (1.0 - NU ** 2))
    for c in (right, left):  # Hertz's line contact, a = sqrt(4 P R / (pi E*)), at 3.2 cells across a
        assert c["half_width"] == pytest.approx(math.sqrt(4.0 * c["normal_force"] * R / (math.pi * e_star)), rel=0.03)


@pytest.mark.parametrize("change, message", [
    (lambda cs: cs[1].pop("point"), "contacts[1].point: missing"),
    (lambda cs: cs[1].update(point=list(cs[0]["point"])), "the same point as contacts[0]"),
])
def test_a_pairs_contacts_each_need_their_own_point(change, message):
    data = v_groove()
    change(data["contacts"])
    with pytest.raises(SceneError) as err:
        scene_from_dict(data, label="groove.toml")
    assert "groove.toml: contacts[1].point" in str(err.value) and message in str(err.value)


def test_two_contacts_found_at_one_place_are_reported_not_converged():
    """Two points 5 mm apart on the same flank: both contacts settle on the same touching point."""
    right = [TOUCH[0], TOUCH[1]]
    near = [TOUCH[0] + 0.0025 * math.sqrt(2.0), TOUCH[1] + 0.0025 * math.sqrt(2.0)]
    contacts = [{"bodies": ["pin", "block"], "type": "frictionless", "point": p} for p in (right, near)]
    solution = solve(scene_from_dict(v_groove(contacts, levels=4), label="groove.toml").problem)
    assert not solution.converged
    assert any("their regions may overlap" in m for m in solution.iterations["messages"])


def test_overlap_is_judged_per_pair_by_the_regions_reach():
    a = {"bodies": ["pin", "block"], "point": [0.0, 0.0], "region": [-0.01, 0.012]}
    b = {"bodies": ["block", "pin"], "point": [0.03, 0.0], "region": [-0.01, 0.01]}
    assert overlapping_regions([a, b]) == []  # 0.012 + 0.01 < 0.03
    c = dict(b, point=[0.02, 0.0])
    assert "contacts 0 and 1 of pin / block" in overlapping_regions([a, c])[0]
    other = dict(c, bodies=["pin", "lid"])  # another pair: no business of this one
    assert overlapping_regions([a, other]) == []
    ball = {"bodies": ["ball", "race"], "point": [0.0, 0.0, 0.0], "semi_axes": [0.003, 0.004], "region_centre": [0.0, 0.0]}
    assert overlapping_regions([ball, dict(ball, point=[0.0, 0.0095, 0.0])])  # 0.005 + 0.005 > 0.0095
    assert not overlapping_regions([ball, dict(ball, point=[0.0, 0.0105, 0.0])])
