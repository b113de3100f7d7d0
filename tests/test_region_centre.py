"""The 2D contact region's centre (ContactOptions.region_centre, solver.contact.band): the region
e - a <= s <= e + a with e at the pressure's centroid.

Independent truth: the physical problem does not depend on where the scene puts its contact
point. A cylinder on a flat block touches at x = 0 whatever point the scene gives; given the
point (d, 0) the region must come out centred d from it (s runs along t = (-1, 0), so x = 0 is
at s = +d), with the half-width and the force of the run given the true point. The thesis's
region |s| <= a about the given point cannot hold both ends and is reported as not converged."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from solver.model.options import ContactOptions, OptionError
from solver.solve import solve

from _contact_scenes import cylinder_on_block


def _scene_with_point(d: float, region_centre: str = "pressure"):
    p = cylinder_on_block("frictionless", load_steps=1)
    cm = p.contacts[0]
    opts = replace(cm.options, region_centre=region_centre)
    return replace(p, contacts=(replace(cm, point=np.array([d, 0.0]), options=opts),))


@pytest.fixture(scope="module")
def centred():
    return solve(_scene_with_point(0.0))


@pytest.mark.parametrize("d", [0.01, -0.02])
def test_region_follows_the_contact_not_the_given_point(centred, d):
    ref = centred.contacts[0]
    assert centred.converged
    assert abs(ref["region_centre"]) <= 1e-9 * ref["half_width"]  # symmetric: centred to round-off
    sol = solve(_scene_with_point(d))
    c = sol.contacts[0]
    assert sol.converged, sol.iterations["messages"]
    a = ref["half_width"]
    # the chord from the given point to the touching point is d to O(d^3 / R^2)
    assert c["region_centre"] == pytest.approx(d, abs=2e-3 * a)
    assert c["region"] == pytest.approx([c["region_centre"] - c["half_width"], c["region_centre"] + c["half_width"]])
    assert c["half_width"] == pytest.approx(a, rel=1e-3)
    assert c["normal_force"] == pytest.approx(ref["normal_force"], rel=1e-4)
    # the reported pressure is Hertz's about the shifted centre: its peak sits there, and it
    # vanishes beyond the region's ends
    s, p = np.asarray(c["pressure"]["s"]), np.asarray(c["pressure"]["value"])
    assert abs(s[np.argmax(p)] - c["region_centre"]) <= 0.05 * a
    assert np.all(p[(s < c["region"][0]) | (s > c["region"][1])] == 0.0)


def test_the_region_about_the_given_point_is_refused_as_inconsistent(centred):
    sol = solve(_scene_with_point(0.01, region_centre="point"))
    c = sol.contacts[0]
    assert c["region_centre"] == 0.0
    assert not sol.converged  # one end penetrates, the other pulls: never reported as solved
    assert any("penetration" in m for m in sol.iterations["messages"])


def test_region_centre_option_is_checked():
    with pytest.raises(OptionError, match="region_centre"):
        ContactOptions(region_centre="middle")
