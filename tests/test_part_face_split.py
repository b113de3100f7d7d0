"""How a CAD face's triangles are split for its quadrature (geometry.solids.part_solid): at their
longest edges, so that the slivers of a planar face's fan (a CAD mesher's triangles from one
vertex to a far arc) become triangles of about the size asked.

Independent checks: the pieces tile their parent (their areas sum to it, wound the same way);
no angle falls below half of the parent's smallest (the bound of longest-edge bisection,
Rosenberg and Stenger, Math. Comp. 29 (1975) 390); the pieces' count is of the order of the
area over the size squared, not of the sliver's length over the size squared, which splitting
into four at the midpoints asks whatever the area."""

import math

import numpy as np

from ibfem.geometry.solids.part_solid import _split, _split_graded


def _fan(n: int = 19, radius: float = 25.0) -> np.ndarray:
    """A quarter disc as a fan of n slivers from its centre, wound counterclockwise (normal +z)."""
    th = np.linspace(0.0, 0.5 * math.pi, n + 1)
    rim = radius * np.column_stack([np.cos(th), np.sin(th), np.zeros(n + 1)])
    return np.stack([np.zeros((n, 3)), rim[:-1], rim[1:]], axis=1)


def _areas(tri: np.ndarray) -> np.ndarray:
    return 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 2]  # signed, +z


def _smallest_angles(tri: np.ndarray) -> np.ndarray:
    out = np.full(len(tri), np.pi)
    for k in range(3):
        u, v = tri[:, (k + 1) % 3] - tri[:, k], tri[:, (k + 2) % 3] - tri[:, k]
        cos = (u * v).sum(1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        out = np.minimum(out, np.arccos(np.clip(cos, -1.0, 1.0)))
    return out


def test_a_fan_of_slivers_splits_into_pieces_of_about_the_size_asked():
    fan = _fan()
    size = 1.0
    pieces = _split(fan, size)
    edges = np.linalg.norm(pieces - np.roll(pieces, 1, axis=1), axis=2).max(axis=1)
    assert edges.max() <= size
    area = _areas(fan).sum()
    assert _areas(pieces).min() > 0.0  # wound as the parent
    np.testing.assert_allclose(_areas(pieces).sum(), area, rtol=1e-13)
    assert _smallest_angles(pieces).min() >= 0.5 * _smallest_angles(fan).min() - 1e-12
    # a triangle with edges of at most `size` covers at most sqrt(3)/4 size^2: the fewest possible
    # pieces; the count stays within a small factor of it (splitting in four asks 4^5 per sliver: 3.7 times as many)
    fewest = area / (math.sqrt(3.0) / 4.0 * size**2)
    assert len(pieces) < 6.0 * fewest, (len(pieces), fewest)
    assert len(pieces) < 0.5 * 19 * 4**5


def test_graded_split_follows_the_size_asked_at_each_piece():
    fan = _fan()

    def size_at(points, normals):  # fine near the fan's centre (a contact there), coarse away
        return np.where(np.linalg.norm(points, axis=1) < 3.0, 0.25, 4.0)

    pieces = _split_graded(fan, size_at, 0.25)
    centroid = pieces.mean(axis=1)
    edges = np.linalg.norm(pieces - np.roll(pieces, 1, axis=1), axis=2).max(axis=1)
    assert np.all(edges <= size_at(centroid, None) + 1e-12)
    np.testing.assert_allclose(_areas(pieces).sum(), _areas(fan).sum(), rtol=1e-13)
    assert _smallest_angles(pieces).min() >= 0.5 * _smallest_angles(fan).min() - 1e-12
