"""Frictionless contact of two elastic half-spaces with a given initial gap, by Boussinesq's
influence coefficients on a grid of rectangles (the classical numerical method: K. L. Johnson,
Contact Mechanics, Cambridge University Press 1985, sections 3.2-3.3 and 5.9; J. J. Kalker's
active-set solution of the contact problem).

Each rectangle carries a uniform pressure. The normal surface displacement of a half-space under a
unit uniform pressure on the rectangle [x1, x2] x [y1, y2] is (1 - nu^2) / (pi E) times
int int dA' / r over it (Boussinesq's point-load solution integrated: Johnson eq. 3.25 is its
closed form, given here through F(X, Y) = X asinh(Y / |X|) + Y asinh(X / |Y|), whose mixed
second derivative is 1 / sqrt(X^2 + Y^2)): the sum of F over the four corners, signs alternating. Two
bodies add their compliances: 1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2.

Contact conditions at the rectangles' centres: the gap after deformation
g + u - delta >= 0, the pressure p >= 0, and one of them zero; delta is the bodies' approach (or
the total force is prescribed and delta found). The active set of loaded rectangles is found by
Kalker's iteration: solve the loaded ones with zero gap, drop those in tension, add those that
overlap, until neither happens.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["rectangle_integral", "influence_matrix", "HalfSpaceContact", "halfspace_contact"]


def _corner(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """F(X, Y) = X asinh(Y / |X|) + Y asinh(X / |Y|), continuous (0) where X or Y vanishes: the
    antiderivative X ln(Y + r) + Y ln(X + r) less X ln|X| + Y ln|Y|, which cancel over a
    rectangle's corners."""
    ax, ay = np.abs(X), np.abs(Y)
    fx = np.where(ax > 0.0, X * np.arcsinh(Y / np.where(ax > 0.0, ax, 1.0)), 0.0)
    fy = np.where(ay > 0.0, Y * np.arcsinh(X / np.where(ay > 0.0, ay, 1.0)), 0.0)
    return fx + fy


def rectangle_integral(x: np.ndarray, y: np.ndarray, x1, x2, y1, y2) -> np.ndarray:
    """int int over [x1, x2] x [y1, y2] of dA' / sqrt((x - x')^2 + (y - y')^2) at points (x, y)."""
    return (_corner(x - x1, y - y1) - _corner(x - x2, y - y1) - _corner(x - x1, y - y2) + _corner(x - x2, y - y2))


#: entries of the influence matrix computed at once (a block of rows): the rectangle integral's
#: temporaries stay about 20 such arrays of this size (8000 rectangles whole took 5.6 GB)
ROW_BLOCK = 1_000_000
#: the mirror images of each rectangle for each kind of symmetry of the pressure
MIRRORS = {False: ((1.0, 1.0),), True: ((1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)),
           "y": ((1.0, 1.0), (1.0, -1.0))}


def influence_matrix(xc: np.ndarray, yc: np.ndarray, dx: float, dy: float, e_star: float,
                     symmetric: bool | str = False) -> np.ndarray:
    """(n, n): the normal displacement at the centres (xc, yc) (n,) of rectangles dx x dy under a
    unit pressure on each (1 / (pi E*) times the rectangle integral). ``symmetric``: True, the
    pressure is even in x and in y, the rectangles cover the quarter x, y > 0, and each carries its
    three mirror images (-x, y), (x, -y), (-x, -y); "y", even in y only, the rectangles cover the
    half y > 0 and each carries its image (x, -y)."""
    if symmetric not in MIRRORS:
        raise ValueError(f"symmetric must be False, True or 'y', got {symmetric!r}")
    out = np.zeros((len(xc), len(xc)))
    rows = max(1, ROW_BLOCK // max(len(xc), 1))  # rows per block: the temporaries stay small
    for start in range(0, len(xc), rows):
        part = slice(start, start + rows)
        for sx, sy in MIRRORS[symmetric]:
            X = xc[part, None] - sx * xc[None, :]
            Y = yc[part, None] - sy * yc[None, :]
            out[part] += rectangle_integral(X, Y, -0.5 * dx, 0.5 * dx, -0.5 * dy, 0.5 * dy)
    return out / (np.pi * e_star)


@dataclass
class HalfSpaceContact:
    x: np.ndarray  # (nx,) centres along x
    y: np.ndarray  # (ny,) centres along y
    pressure: np.ndarray  # (nx, ny)
    approach: float  # delta
    force: float
    iterations: int

    @property
    def area(self) -> float:
        return float((self.pressure > 0.0).sum() * (self.x[1] - self.x[0]) * (self.y[1] - self.y[0]))

    def extent(self, axis: int) -> float:
        """The half-length of the loaded region along an axis through the grid's middle: the
        outermost loaded centre plus half a rectangle."""
        loaded = self.pressure > 0.0
        coords = self.x if axis == 0 else self.y
        if not loaded.any():
            return 0.0
        span = coords[loaded.any(axis=1 - axis)]
        return float(max(abs(span.min()), abs(span.max())) + 0.5 * abs(coords[1] - coords[0]))


def halfspace_contact(gap, x: np.ndarray, y: np.ndarray, e_star: float, force: float | None = None,
                      approach: float | None = None, max_iterations: int = 200,
                      symmetric: bool | str = False) -> HalfSpaceContact:
    """The contact of a gap function ``gap(X, Y)`` (the initial separation of the two surfaces at
    the grid's centres, X, Y (nx, ny)) on the equally spaced centres x (nx,), y (ny,), under a total
    ``force`` or a prescribed ``approach``. ``symmetric``: True, a gap even in x and in y solved on
    the quarter x, y > 0 (the centres there, the first at half a spacing from 0); "y", a gap even in
    y solved on the half y > 0; ``force`` and the result's force are then the quarter's or the
    half's."""
    if (force is None) == (approach is None):
        raise ValueError("give exactly one of force and approach")
    dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
    X, Y = np.meshgrid(x, y, indexing="ij")
    g = np.asarray(gap(X, Y), dtype=float).ravel()
    c = influence_matrix(X.ravel(), Y.ravel(), dx, dy, e_star, symmetric)
    area = dx * dy
    active = g <= np.sort(g)[min(len(g) - 1, 8)]  # the few closest points first
    for it in range(1, max_iterations + 1):
        idx = np.flatnonzero(active)
        p, delta = _loaded(c[np.ix_(idx, idx)], g[idx], area, force, approach)
        full = np.zeros(len(g))
        full[idx] = p
        overlap = g + c @ full - delta
        tension = idx[p < 0.0]
        entering = np.flatnonzero(~active & (overlap < -1e-12 * max(abs(delta), 1e-300)))
        if not len(tension) and not len(entering):
            return HalfSpaceContact(x, y, full.reshape(X.shape), float(delta), float(full.sum() * area), it)
        active[tension] = False
        active[entering] = True
    raise RuntimeError(f"the half-space contact's active set did not settle in {max_iterations} iterations")


def _loaded(c: np.ndarray, g: np.ndarray, area: float, force, approach):
    """Pressures on the loaded rectangles with zero gap (c p = delta - g), and delta."""
    if approach is not None:
        return np.linalg.solve(c, approach - g), float(approach)
    # unknowns (p, delta): c p - delta = -g, area sum(p) = force
    n = len(g)
    m = np.zeros((n + 1, n + 1))
    m[:n, :n] = c
    m[:n, n] = -1.0
    m[n, :n] = area
    rhs = np.concatenate([-g, [force]])
    sol = np.linalg.solve(m, rhs)
    return sol[:n], float(sol[n])
