"""An elongated point contact (a thin rod across a thick cylinder, a ball in a race's groove) has
its grid follow the region as a line contact's does: a coarse pass, then a band of refinement
balls along the ellipse's long axis on body 1's surface, instead of the scene's whole ball at its
depth."""

import numpy as np
import pytest

from ibfem.solver.contact import follow
from ibfem.solver.contact.region_band import ellipse_band_balls
from ibfem.solver.io.scene import load_scene
from ibfem.solver.reference.theory import hertz_elliptic_contact

RODS = """
name = "a thin rod across a thick cylinder"
model = "solid"
[[materials]]
name = "steel"
youngs_modulus = 2.0e11
poissons_ratio = 0.3
[[bodies]]
name = "rod"
material = "steel"
element_size = 0.004
refinement = [{ levels = LEVELS, around = "contact", radius = 0.0025 }]
shape = { type = "half_cylinder", center = [0.0, 0.0, 0.01], axis = [1.0, 0.0, 0.0], radius = 0.01, length = 0.04, side = "below" }
[[bodies]]
name = "drum"
material = "steel"
element_size = 0.004
refinement = [{ levels = LEVELS, around = "contact", radius = 0.0025 }]
shape = { type = "half_cylinder", center = [0.0, 0.0, -RADIUS], axis = [0.0, 1.0, 0.0], radius = RADIUS, length = 0.04, side = "above" }
[[boundary_conditions]]
body = "rod"
face = "flat"
type = "displacement"
value = [0.0, 0.0, -1.0e-5]
[[boundary_conditions]]
body = "drum"
face = "flat"
type = "fixed"
[[contacts]]
bodies = ["rod", "drum"]
type = "frictionless"
"""


def _problem(tmp_path, radius: float, levels: int = 6):
    path = tmp_path / "rods.toml"
    path.write_text(RODS.replace("LEVELS", str(levels)).replace("RADIUS", repr(radius)))
    return load_scene(path).problem


def test_the_band_covers_the_ellipse_with_balls_a_radius_apart():
    block = {"semi_axes": [0.004, 0.0005], "region_centre": [0.001, -0.0002]}
    s, radius = ellipse_band_balls(block, margin=0.0002)
    assert radius == pytest.approx(0.0007)
    assert s[:, 1] == pytest.approx(np.full(len(s), -0.0002))  # the long axis through the centre
    assert s[0, 0] == pytest.approx(0.001 - 0.0042) and s[-1, 0] == pytest.approx(0.001 + 0.0042)
    assert np.diff(s[:, 0]).max() <= radius * (1.0 + 1e-12)


def test_the_bands_centres_lie_on_body_1s_curved_surface():
    """A ball of radius 10 mm above its contact point: along the long axis its surface rises by
    R - sqrt(R^2 - s^2), more than the band's radius at 3 mm; each centre lies on it."""
    from ibfem.geometry.solids import solid_from_dict

    ball = solid_from_dict({"type": "sphere", "center": [0.0, 0.0, 0.01], "radius": 0.01})
    block = {"point": [0.0, 0.0, 0.0], "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], "normal": [0.0, 0.0, 1.0],
             "semi_axes": [0.003, 0.0003], "region_centre": [0.0, 0.0], "relative_curvatures": [4.0, 137.0]}
    centres, radius = follow._on_surface(ball, block, *ellipse_band_balls(block, 0.0001))
    assert np.abs(ball.signed_distance(centres)).max() < 1e-12
    rise = 0.01 - np.sqrt(0.01**2 - centres[:, 0] ** 2)
    assert centres[:, 2] == pytest.approx(rise, abs=1e-12)
    assert rise.max() > radius


def test_an_elongated_ellipse_follows_its_region_and_a_round_one_does_not(tmp_path):
    """Relative curvatures 1/0.12 and 1/0.01 m^-1 (ratio 0.083, Hertz's b/a about 0.2): followed;
    a drum of radius 0.05 m (ratio 0.2, b/a about 0.35): its ball fits, not followed."""
    assert follow.line_contacts(_problem(tmp_path, 0.12)) == [0]
    assert follow.line_contacts(_problem(tmp_path, 0.05)) == []


def test_a_coarse_ellipse_block_counts_as_a_region():
    assert follow.has_region({"semi_axes": [0.001, 0.0002]})
    assert not follow.has_region({"semi_axes": [0.0, 0.0]})
    assert not follow.has_region({"boundary": None, "semi_axes": [0.001, 0.0002]})  # a line contact's, unfound


@pytest.mark.slow
def test_a_thin_rod_across_a_thick_cylinder_against_hertz(tmp_path):
    """The scene's ball at 6 levels would need about 9.3e5 dofs and 21 GB (`ibfem run --check`
    without the band); the band along the coarse ellipse about 1.05e5. Hertz's elliptical contact
    for the computed force: a (20 of the band's cells) within 0.5 %, b (4 of them) within 3.5 %
    (measured -0.33 % and -2.1 %)."""
    import json
    import subprocess
    import sys

    path = tmp_path / "rods.toml"
    path.write_text(RODS.replace("LEVELS", "6").replace("RADIUS", "0.12") + "[solver]\nload_steps = 1\n"
                    "[output]\nvtk = false\nplots = false\n")
    run = subprocess.run([sys.executable, "-m", "ibfem.solver.cli", "run", str(path), "--out", str(tmp_path / "out"),
                          "--quiet", "--no-estimate"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    (c,) = summary["contacts"]
    assert summary["iterations"]["refinement"]["band"]["rod"]["levels"] == 6
    a, b, _ = hertz_elliptic_contact(c["normal_force"], (1.0 / 0.12, 1.0 / 0.01), 2.0e11 / (2.0 * (1.0 - 0.3**2)))
    assert c["semi_axes"][0] == pytest.approx(a, rel=0.005)
    assert c["semi_axes"][1] == pytest.approx(b, rel=0.035)

