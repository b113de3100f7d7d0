"""The bracketed zeros of solver.contact.ellipse_geometry._illinois on lines that run along a face
(the distance exactly 0 on a stretch [z0, z0 + w] above the entry z0, as a quarter model's
symmetry plane makes it) and on lines that cross a surface properly, against the closed-form
entry z0; and the plateau's bisection taking several steps per call of the distance."""

import numpy as np

from ibfem.solver.contact.ellipse_geometry import PLATEAU_LEVELS, _illinois

N = np.array([0.0, 0.0, 1.0])


class Faces:
    """Lines x = k (k = 0, 1, ...) along z: phi = z - z0 below z0, 0 on [z0, z0 + w], then
    ``slope`` (z - z0 - w) above; counts its calls."""

    def __init__(self, z0, w, slope):
        self.z0, self.w, self.slope, self.calls = z0, w, slope, 0

    def __call__(self, x):
        self.calls += 1
        k = np.rint(x[:, 0]).astype(int)
        d = x[:, 2] - self.z0[k]
        return np.where(d < 0.0, d, np.where(d <= self.w[k], 0.0, self.slope[k] * (d - self.w[k])))


def _lines(m):
    y = np.zeros((m, 3))
    y[:, 0] = np.arange(m)
    return y


def test_lines_along_a_face_end_at_its_lower_end():
    rng = np.random.default_rng(7)
    m, reach, d = 40, 0.03, 1e-10 * 0.03
    z0 = rng.uniform(-0.01, 0.01, m)
    f = Faces(z0, np.full(m, 1e-3), rng.uniform(0.3, 1.0, m))
    b = z0 + d * rng.uniform(0.0, 1.0, m)  # a root on the face, its lower end within d below
    a = b - d
    y = _lines(m)
    fa, fb = f(y + a[:, None] * N), f(y + b[:, None] * N)
    assert np.all(fb == 0.0)
    f.calls = 0
    t = _illinois(f, y, N, a, b, fa, fb, reach)
    assert np.all(np.abs(t - z0) <= 1e-13 * reach)
    # 10 halvings of d = 1e-10 reach down to 1e-13 reach, PLATEAU_LEVELS of them per call
    assert f.calls == int(np.ceil(10 / PLATEAU_LEVELS))


def test_lines_that_cross_take_the_regula_falsi():
    rng = np.random.default_rng(11)
    m, reach = 25, 0.05
    z0 = rng.uniform(-0.02, 0.02, m)
    f = Faces(z0, np.zeros(m), rng.uniform(0.5, 2.0, m))
    a, b = z0 - rng.uniform(0.001, 0.01, m), z0 + rng.uniform(0.001, 0.01, m)
    y = _lines(m)
    t = _illinois(f, y, N, a, b, f(y + a[:, None] * N), f(y + b[:, None] * N), reach)
    assert np.all(np.abs(t - z0) <= 1e-13 * reach)


def test_a_face_and_a_crossing_in_one_batch():
    """Lines of both kinds together: each ends where it would alone."""
    rng = np.random.default_rng(3)
    m, reach = 30, 0.02
    z0 = rng.uniform(-0.005, 0.005, m)
    w = np.where(rng.random(m) < 0.5, 2e-4, 0.0)
    f = Faces(z0, w, rng.uniform(0.3, 1.0, m))
    a = z0 - np.where(w > 0, 1e-10 * reach, rng.uniform(1e-4, 1e-3, m))
    b = np.where(w > 0, z0 + 0.5 * w, z0 + rng.uniform(1e-4, 1e-3, m))
    y = _lines(m)
    together = _illinois(f, y, N, a, b, f(y + a[:, None] * N), f(y + b[:, None] * N), reach)
    for k in range(m):
        alone = _illinois(f, y[k:k + 1], N, a[k:k + 1], b[k:k + 1], f(y[k:k + 1] + a[k] * N),
                          f(y[k:k + 1] + b[k] * N), reach)
        assert alone[0] == together[k]
    assert np.all(np.abs(together - z0) <= 1e-13 * reach)
