"""The pure helpers of benchmarks/examples_ngsolve.py against hand computations; no
NGSolve needed (the module imports it only inside the functions that solve)."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import examples_ngsolve as ex  # noqa: E402


def test_pressure_rms_difference_by_hand():
    # reference 1 on s = -1, -0.5, 0, 0.5, 1; the compared profile p = 1 + s sampled elsewhere
    # (linear, so interpolation is exact): inside 0.9 * 1 the samples -0.5, 0, 0.5 differ by
    # -0.5, 0, 0.5 -> RMS sqrt((0.25 + 0 + 0.25) / 3) = sqrt(1/6), in p0 = 2: sqrt(1/6) / 2
    s_ref = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
    s = np.linspace(-1.0, 1.0, 7)[::-1]            # unsorted on purpose
    got = ex.pressure_rms_difference(s_ref, np.ones(5), s, 1.0 + s, half_width=1.0, p0=2.0)
    assert got == pytest.approx(math.sqrt(1.0 / 6.0) / 2.0, rel=1e-12)


def test_pressure_rms_difference_rejects_bad_scales():
    with pytest.raises(ValueError, match="half_width"):
        ex.pressure_rms_difference([0.0], [1.0], [0.0], [1.0], half_width=0.0, p0=1.0)
    with pytest.raises(ValueError, match="no reference sample"):
        ex.pressure_rms_difference([2.0], [1.0], [2.0], [1.0], half_width=1.0, p0=1.0)


def test_resultant_offset_of_a_shifted_hertz_profile():
    # a semi-ellipse centred at e has its resultant at e exactly
    a, e = 0.03, 0.0006
    s = np.linspace(-2 * a, 2 * a, 40001)
    p = np.sqrt(np.clip(1.0 - ((s - e) / a) ** 2, 0.0, None))
    assert ex.resultant_offset(s, p, a) == pytest.approx(e / a, rel=1e-4)


@pytest.mark.parametrize("key", ["ex7", "ex3", "ex4"])
def test_initial_gap_along_the_frame_normal(key):
    # body 1 is the unit disc tangent at the contact point; body 2 a line (gap 1 - sqrt(1 - s^2))
    # or the mirrored unit disc (twice that)
    scene = ex.SCENES[key]
    s = np.linspace(-0.2, 0.2, 9)
    q, normals = ex.surface2(scene, s)
    x1, g0 = ex.paired1(scene, q)
    one = 1.0 - np.sqrt(1.0 - s * s)
    expected = 2.0 * one if scene.centre2 is not None else one
    np.testing.assert_allclose(g0, expected, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(x1 - np.asarray(scene.centre1), axis=1), 1.0, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-14)
    # the feet of body 1's points on body 2 are body 2's own points for the lines
    if scene.centre2 is None:
        np.testing.assert_allclose(ex.foot2(scene, x1), q, atol=1e-14)


def test_wedge_scene_is_the_examples_geometry():
    # examples/cylinder_on_wedge_frictionless.toml: centre (0, 1/cos 15), contact point on y = x tan 15
    sc = ex.SCENES["ex7"]
    assert sc.centre1[1] == pytest.approx(1.035276180410083, abs=1e-12)
    assert sc.point[0] == pytest.approx(0.25881904510252074, abs=1e-12)
    assert sc.point[1] == pytest.approx(0.06935035412101465, abs=1e-12)
    assert np.dot(sc.normal, sc.tangent) == pytest.approx(0.0, abs=1e-15)


def test_hertz_reference_mcewen_peak():
    # plane strain, nu = 0.3: von Mises peak 0.5575 p0 at 0.704 a below the centre (McEwen 1949;
    # Johnson, Contact Mechanics, fig. 4.5); a = sqrt(4 N R / (pi E*))
    N, R = 1.0e8, 1.0
    h = ex.hertz_reference(N, R)
    e_star = 2.0e11 / (2.0 * (1.0 - 0.09))
    assert h["a"] == pytest.approx(math.sqrt(4.0 * N * R / (math.pi * e_star)), rel=1e-12)
    assert h["p0"] == pytest.approx(2.0 * N / (math.pi * h["a"]), rel=1e-12)
    assert h["vm_peak"] / h["p0"] == pytest.approx(0.5575, abs=5e-4)
    assert h["vm_z_a"] == pytest.approx(0.704, abs=5e-3)
