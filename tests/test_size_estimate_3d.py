"""The size estimate of a 3D scene (``ibfem run --check``, solver.model.estimate) against the
grids and the contact then built: cells, dofs and the condensed contact dofs within 30 %, for a
full model turned by 37 degrees about (1, 2, 3) (a turned part's bounding box is
about twice its volume: the estimate follows the part, as the octree does, not its box) and for
a quarter model (two symmetry planes through the contact point hold a quarter of the contact
disc: its contact dofs, whose dense blocks grow with their square, are a quarter of a full
model's)."""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from ibfem.solver.contact.formulation import formulation
from ibfem.solver.fem.bodies import discretise
from ibfem.solver.io.scene import load_scene
from ibfem.solver.model.estimate import estimate_contact_dofs, estimate_size
from ibfem.solver.model.resolve import resolve_problem

SOLID = Path(__file__).resolve().parent.parent / "examples" / "solid"


@pytest.mark.parametrize("name, element_size, levels", [("full/ball_on_block_turned", 0.125, 2),
                                                        ("sphere_on_flat", 0.5, 5)])
def test_estimate_against_the_built_octrees(name, element_size, levels):
    path = SOLID / f"{name}.toml"
    data = tomllib.loads(path.read_text())
    for body in data["bodies"]:
        body["element_size"] = element_size
        zones = body["refinement"]
        (zones[0] if isinstance(zones, list) else zones)["levels"] = levels
    problem = resolve_problem(load_scene(data, label=path.name, base_dir=path.parent).problem)
    size = estimate_size(problem)
    bodies = discretise(problem, problem.options)
    cells = sum(len(b.grid.level) for b in bodies)
    dofs = sum(b.n_dofs for b in bodies)
    assert size.cells == pytest.approx(cells, rel=0.3)
    assert size.dofs == pytest.approx(dofs, rel=0.3)
    (cm,) = problem.contacts
    contact = formulation(cm.options.formulation, 3)(problem, cm, *bodies, problem.options)
    assert estimate_contact_dofs(problem) == pytest.approx(len(contact.dofs), rel=0.3)
    # every octree cell holds material or lies within its half diagonal of the part
    for b in bodies:
        phi = b.boundary.signed_distance(b.grid.center)
        assert np.all(phi > -0.5 * np.sqrt(3.0) * b.grid.size * (1 + 1e-6))


def test_contact_dofs_of_a_zone_off_the_contact_point_in_a_quarter_model():
    """A quarter model holds a quarter of the contact's candidate disc, and a refinement zone off the
    contact point (a band's ball, a finer ball where a region's edge turns) lies in that quarter
    only: the disc's cell density is the held quarter's. Averaged over the whole disc, the zone's
    fine cells counted a quarter of their share (0.48 of the built contact dofs here)."""
    path = SOLID / "sphere_on_flat.toml"
    data = tomllib.loads(path.read_text())
    for body in data["bodies"]:
        body["refinement"] = [{"levels": 3, "around": "contact", "radius": 0.1},
                              {"levels": 5, "radius": 0.025, "around": [0.045, 0.03, 0.0]}]
    problem = resolve_problem(load_scene(data, label=path.name, base_dir=path.parent).problem)
    bodies = discretise(problem, problem.options)
    (cm,) = problem.contacts
    contact = formulation(cm.options.formulation, 3)(problem, cm, *bodies, problem.options)
    assert estimate_contact_dofs(problem) == pytest.approx(len(contact.dofs), rel=0.3)


@pytest.mark.parametrize("scene, point", [("solid/sphere_on_flat", True), ("solid/crossed_cylinders", True),
                                          ("contact3d/roller_on_flat", False), ("contact3d/rounded_punch", False)])
def test_a_region_not_found_yet_fills_a_point_contacts_disc_less(scene, point):
    """Before a solve, a point contact's region (surfaces curving apart along both axes: an
    ellipse) is counted as a sixteenth of its candidate disc, a line contact's or a flat punch's,
    which grow along the disc, as a quarter."""
    from ibfem.solver.io.run_size import region_fills
    from ibfem.solver.model.estimate import POINT_REGION_FILL, REGION_FILL, trial_bytes

    problem = load_scene(SOLID.parent / f"{scene}.toml").problem
    fills = region_fills(problem)
    assert fills == [POINT_REGION_FILL if point else REGION_FILL]
    assert trial_bytes(problem, region_fills=fills)[0] == pytest.approx(
        trial_bytes(problem)[0] * fills[0] / REGION_FILL)
