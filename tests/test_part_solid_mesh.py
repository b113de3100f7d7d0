"""The nearest-triangle distance of a CAD face's mesh (geometry.solids.part_solid._Mesh), used by
a part solid's 'is this foot on the face' test: equal to the brute-force minimum over every
triangle, also where big triangles sit next to small ones (a fan at a cone's tip), where the k
nearest centroids do not hold the nearest triangle."""

import numpy as np

from ibfem.geometry.solids.part_solid import _Mesh, point_triangle_distance


def _fan_and_big(rng):
    # a fan of 200 thin triangles around the origin (a cone's tip) and 20 big ones far out
    th = np.linspace(0.0, 2 * np.pi, 201)
    fan = np.stack([np.zeros((200, 3)),
                    np.column_stack([np.cos(th[:-1]), np.sin(th[:-1]), np.zeros(200)]),
                    np.column_stack([np.cos(th[1:]), np.sin(th[1:]), np.zeros(200)])], axis=1)
    big = rng.uniform(-20, 20, size=(20, 3, 3))
    return np.concatenate([fan, big])


def test_nearest_triangle_distance_equals_brute_force():
    rng = np.random.default_rng(7)
    tri = _fan_and_big(rng)
    mesh = _Mesh(tri)
    p = rng.uniform(-25, 25, size=(400, 3))
    brute = np.array([point_triangle_distance(np.repeat(q[None], len(tri), 0), tri).min() for q in p])
    np.testing.assert_allclose(mesh.distance(p), brute, rtol=0, atol=1e-12)


def test_point_triangle_distance_against_dense_samples():
    # the distance is the minimum over the triangle: dense barycentric samples bound it from above
    # and come within the sampling's resolution of it
    rng = np.random.default_rng(3)
    tri = rng.normal(size=(1, 3, 3))
    u, v = np.meshgrid(np.linspace(0, 1, 401), np.linspace(0, 1, 401))
    keep = u + v <= 1
    pts = tri[0, 0] + u[keep, None] * (tri[0, 1] - tri[0, 0]) + v[keep, None] * (tri[0, 2] - tri[0, 0])
    for q in rng.normal(scale=2.0, size=(20, 3)):
        d = point_triangle_distance(q[None], tri)[0]
        sampled = np.linalg.norm(pts - q, axis=1).min()
        assert d <= sampled + 1e-12 and sampled - d < 1e-2


def test_within_a_tolerance_agrees_with_the_distance():
    rng = np.random.default_rng(11)
    tri = _fan_and_big(rng)
    mesh = _Mesh(tri)
    p = np.concatenate([rng.uniform(-25, 25, size=(300, 3)),
                        np.column_stack([rng.uniform(-1, 1, (200, 2)), rng.normal(scale=0.05, size=200)])])
    d = mesh.distance(p)
    for tol in (1e-3, 0.05, 1.0):
        np.testing.assert_array_equal(mesh.within(p, tol), d <= tol)
