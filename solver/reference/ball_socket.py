"""A ball pressed into a spherical socket, frictionless, solved independently of the 3D solver:
axisymmetric linear elasticity on fitted meshes of the two sections (scikit-fem, linear
triangles) and node-to-node contact along the radii, by an active set on the contact's
flexibility.

Geometry in the (r, z) half-plane, the socket's centre at the origin: the socket is the rectangle
[0, W] x [-H, 0] less the disc of radius R2 (its cup); the ball is the lower half of the disc of
radius R1 < R2 about (0, -c), c = R2 - R1 the radial clearance, so the two touch at (0, -R2). The
ball's flat top (its equator plane) is moved down by delta (both components prescribed, as a
rigid platen), the socket's bottom is fixed, and u_r = 0 on the axis.

Both meshes are polar: the socket's nodes on rays from its centre at angles theta from -90
degrees (the axis, below) to 0, uniform at ``spacing`` degrees over ``fine_to`` degrees and
growing beyond, from its cup to the rectangle; the ball's on rays from its own centre, whose
surface nodes over the uniform stretch lie on the socket's rays (at the distance rho(theta) from
the socket's centre, |rho n - (0, -c)| = R1), from its centre to its surface; both graded towards
the contact surface. Each surface node of the socket and the ball's on the same ray is a contact
pair with the normal n = (cos theta, sin theta): their normal displacements obey
(u_ball - u_socket) . n <= g0 = R2 - rho(theta), the initial gap. The bodies' stiffness (2 pi r dr dz with the hoop strain u_r / r) is
condensed onto the pairs (one factorisation per body), and the active set iterates on the dense
flexibility until no pair is in tension and none penetrates.

The contact's edge is where the pressure (the pairs' ring forces over 2 pi r and their share of
the arc) vanishes: where p^2, linear in the angle next to a smooth edge, extrapolates to zero from
the last three loaded pairs. Its distance from the axis is the contact radius a, and the ball's
semi-angle from its bottom is asin(a / R1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["BallSocketSolution", "ball_in_socket", "polar_angles"]


@dataclass
class BallSocketSolution:
    theta: np.ndarray  # (m,) angles of the contact pairs, rad (-pi/2 at the bottom)
    pressure: np.ndarray  # (m,) contact pressure at the pairs, Pa
    force: float  # the total normal force along z on the ball, N (the whole ball, not a sector)
    radius: float  # the contact's radius about the axis, m (the edge's distance from it)
    semi_angle: float  # the contact's semi-angle on the ball, from its bottom: asin(radius / R1), rad
    iterations: int


def polar_angles(spacing_deg: float, fine_to_deg: float, growth: float = 1.15, start_deg: float = -90.0,
                 fine: np.ndarray | None = None) -> np.ndarray:
    """Angles (rad) from ``start_deg`` to 0: uniform at ``spacing_deg`` over ``fine_to_deg``
    (or the given ``fine`` angles, rad), then steps growing by ``growth`` (at most 5 degrees)."""
    if fine is None:
        fine = np.deg2rad(start_deg + spacing_deg * np.arange(int(round(fine_to_deg / spacing_deg)) + 1))
    out = list(np.rad2deg(fine))
    step = spacing_deg
    while out[-1] < 0.0:
        step = min(step * growth, 5.0)
        out.append(min(out[-1] + step, 0.0))
    if out[-1] - out[-2] < 0.3 * step:  # no sliver at the end
        out.pop(-2)
    return np.deg2rad(np.array(out))


def _graded(n: int, first: float) -> np.ndarray:
    """(n + 1,) from 0 to 1, the first interval ``first`` and the rest growing geometrically."""
    lo, hi = 1.0, 2.0
    while sum(first * hi**k for k in range(n)) < 1.0:
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sum(first * mid**k for k in range(n)) < 1.0 else (lo, mid)
    steps = first * lo ** np.arange(n)
    return np.concatenate([[0.0], np.cumsum(steps) / steps.sum()])


def _structured(radius: np.ndarray, theta: np.ndarray):
    """Points (2, N) and triangles (3, T) of the grid of radii (nr, nt) (row i: along the rays,
    row 0 the contact surface) at the angles theta (nt,), centred at the origin; rows of zero
    radius collapse to one node."""
    nr, nt = radius.shape
    pts = np.stack([radius * np.cos(theta)[None, :], radius * np.sin(theta)[None, :]], axis=0).reshape(2, -1)
    index = np.arange(nr * nt).reshape(nr, nt)
    a, b, c, d = index[:-1, :-1], index[:-1, 1:], index[1:, 1:], index[1:, :-1]
    tri = np.concatenate([np.stack([a, b, c]).reshape(3, -1), np.stack([a, c, d]).reshape(3, -1)], axis=1)
    return pts, tri, index


def _stiffness(pts: np.ndarray, tri: np.ndarray, young: float, poisson: float):
    """The axisymmetric stiffness (2 pi r dr dz) on linear triangles by scikit-fem."""
    from skfem import Basis, BilinearForm, ElementTriP1, ElementVector, MeshTri

    mesh = MeshTri(np.ascontiguousarray(pts), np.ascontiguousarray(tri))
    basis = Basis(mesh, ElementVector(ElementTriP1()))
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))

    @BilinearForm
    def axisymmetric(u, v, w):
        r = w.x[0]

        def strain(f):  # (rr, zz, hoop, engineering shear rz)
            g = f.grad
            return g[0][0], g[1][1], f[0] / r, g[0][1] + g[1][0]

        eu, ev = strain(u), strain(v)
        tr_u, tr_v = eu[0] + eu[1] + eu[2], ev[0] + ev[1] + ev[2]
        inner = eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2] + 0.5 * eu[3] * ev[3]
        return 2.0 * math.pi * r * (lam * tr_u * tr_v + 2.0 * mu * inner)

    return axisymmetric.assemble(basis).tocsc(), basis


def _condensed(k, fixed: np.ndarray, values: np.ndarray, rows: np.ndarray, normals: np.ndarray):
    """(the normal displacements at the contact nodes under the prescribed values, their
    flexibility (m, m) to unit ring forces along the normals): one sparse factorisation, solves
    for the load and the m unit forces."""
    n = k.shape[0]
    free = np.setdiff1d(np.arange(n), fixed)
    lu = spla.splu(k[free][:, free].tocsc())
    u0 = np.zeros(n)
    u0[fixed] = values
    rhs = -(k[free][:, fixed] @ values)
    u0[free] = lu.solve(rhs)
    m = len(rows)
    cols = np.repeat(np.arange(m), 2)
    e = sp.csr_matrix((normals.ravel(), ((2 * rows[:, None] + np.arange(2)).ravel(), cols)), shape=(n, m))
    ef = e[free].toarray()  # the ring forces' components at the nodes
    flex = ef.T @ lu.solve(ef)
    d0 = e.T @ u0
    return d0, flex


def ball_in_socket(r1: float, r2: float, young: float, poisson: float, delta: float, width: float,
                   height: float, spacing_deg: float = 0.1, fine_to_deg: float = 35.0, layers: int = 60,
                   max_iterations: int = 200) -> BallSocketSolution:
    """The axisymmetric contact of a ball (radius r1) in a socket (cup radius r2 > r1, the block
    ``width`` x ``height`` about it), both of the material (E, nu), the ball's top moved down by
    ``delta``. See the module's docstring."""
    if not (0.0 < r1 < r2 < min(width, height)) or delta <= 0.0:
        raise ValueError(f"a ball in a socket needs 0 < R1 < R2 < the block and delta > 0 (got R1 = {r1}, R2 = {r2}, "
                         f"block {width} x {height}, delta = {delta})")
    c = r2 - r1
    theta = polar_angles(spacing_deg, fine_to_deg)
    paired = int(round(fine_to_deg / spacing_deg)) + 1
    ds = math.radians(spacing_deg)
    # the ball: its surface points on the socket's rays through the paired angles (about the
    # ball's centre at the angles phi), its own angles beyond; rows from its surface (row 0) to
    # its centre (one node)
    t = theta[:paired]
    rho = -c * np.sin(t) + np.sqrt(r1 * r1 - (c * np.cos(t)) ** 2)  # |rho n - (0, -c)| = R1
    phi = polar_angles(spacing_deg, 0.0, fine=np.arctan2(rho * np.sin(t) + c, rho * np.cos(t)))
    s = 1.0 - _graded(layers, ds)[:, None]  # radius over R1, 1 at row 0
    ball_pts, ball_tri, ball_index = _structured(r1 * s * np.ones((1, len(phi))), phi)
    ball_pts[1] -= c
    keep, ball_tri = _merge_centre(ball_pts, ball_tri, ball_index)
    ball_pts = ball_pts[:, keep[0]]
    # the socket: rows from its cup (row 0) to the rectangle along each ray
    reach = np.minimum(width / np.maximum(np.cos(theta), 1e-300), height / np.maximum(-np.sin(theta), 1e-300))
    eta = _graded(layers, ds * r2 / (reach.min() - r2))[:, None]
    sock_pts, sock_tri, sock_index = _structured(r2 + (reach[None, :] - r2) * eta, theta)
    return _solve_pairs(r1, r2, young, poisson, delta, theta, rho, (ball_pts, ball_tri, keep[1]),
                        (sock_pts, sock_tri, sock_index), max_iterations)


def _merge_centre(pts: np.ndarray, tri: np.ndarray, index: np.ndarray):
    """((kept node ids, the surface row's new ids), triangles) with the last row (the centre, all
    at one point) merged into one node and the degenerate triangles dropped."""
    last = index[-1]
    remap = np.arange(pts.shape[1])
    remap[last] = last[0]
    tri = remap[tri]
    tri = tri[:, (tri[0] != tri[1]) & (tri[1] != tri[2]) & (tri[0] != tri[2])]
    used = np.unique(tri)
    new = -np.ones(pts.shape[1], dtype=int)
    new[used] = np.arange(len(used))
    return (used, new[index[0]]), new[tri]


def _solve_pairs(r1, r2, young, poisson, delta, theta, rho, ball, socket, max_iterations) -> BallSocketSolution:
    """Condense both bodies onto the pairs (the first len(rho) angles: the ball's surface at the
    distances rho from the socket's centre on its rays) and run the active set."""
    c = r2 - r1
    normals = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    ball_pts, ball_tri, ball_surface = ball
    sock_pts, sock_tri, sock_index = socket
    kb, _ = _stiffness(ball_pts, ball_tri, young, poisson)
    ks, _ = _stiffness(sock_pts, sock_tri, young, poisson)
    # the ball: u_r = 0 on the axis, (0, -delta) on its top (z = -c); the socket: u_r = 0 on the
    # axis, fixed at its bottom
    tol = 1e-9 * r1
    top = np.nonzero(np.abs(ball_pts[1] + c) <= tol)[0]
    axis_b = np.nonzero(np.abs(ball_pts[0]) <= tol)[0]
    fixed_b = np.unique(np.concatenate([2 * top, 2 * top + 1, 2 * axis_b]))
    values_b = np.where(np.isin(fixed_b, 2 * top + 1), -delta, 0.0)
    bottom = np.nonzero(np.abs(sock_pts[1] - sock_pts[1].min()) <= tol)[0]
    axis_s = np.nonzero(np.abs(sock_pts[0]) <= tol)[0]
    fixed_s = np.unique(np.concatenate([2 * bottom, 2 * bottom + 1, 2 * axis_s]))
    pairs = np.arange(len(rho))
    db, fb = _condensed(kb, fixed_b, values_b, ball_surface[pairs], normals[pairs])
    ds_, fs = _condensed(ks, fixed_s, np.zeros(len(fixed_s)), sock_index[0][pairs], normals[pairs])
    gap0 = r2 - rho
    # normal approach d = db - ds - (fb + fs) lam <= gap0 (ring forces lam >= 0 push them apart)
    flex = fb + fs
    free_approach = db - ds_
    active = free_approach > gap0
    lam = np.zeros(len(pairs))
    for it in range(1, max_iterations + 1):
        lam[:] = 0.0
        a = np.nonzero(active)[0]
        if len(a):
            lam[a] = np.linalg.solve(flex[np.ix_(a, a)], free_approach[a] - gap0[a])
        over = free_approach - flex @ lam - gap0
        nxt = (lam > 0.0) | (~active & (over > 1e-12 * c))
        if np.array_equal(nxt, active):
            break
        active = nxt
    else:
        raise RuntimeError(f"the ball-in-socket active set did not settle in {max_iterations} iterations")
    t = theta[pairs]
    # each pair's share of the surface, the integral of its hat function: a ring of radius
    # rho cos(theta) and half the arcs to its neighbours; on the axis, the cone of the first
    # interval's radius d: int_0^d (1 - r / d) 2 pi r dr = pi d^2 / 3
    arc = 0.5 * rho * (theta[pairs + 1] - np.concatenate([[t[0]], theta[pairs[1:] - 1]]))
    ring = 2.0 * math.pi * rho * np.cos(t) * arc
    ring[0] = math.pi * (rho[0] * (theta[1] - theta[0])) ** 2 / 3.0
    pressure = lam / ring
    force = float(np.sum(lam * -np.sin(t)))
    edge = _edge_angle(t, pressure)  # on the socket's rays: the ball's point there
    c_edge = -c * math.sin(edge) + math.sqrt(r1 * r1 - (c * math.cos(edge)) ** 2)
    radius = c_edge * math.cos(edge)
    return BallSocketSolution(t, pressure, force, radius, math.asin(radius / r1), it)


def _edge_angle(theta: np.ndarray, pressure: np.ndarray) -> float:
    """The socket's angle theta where the pressure ends: p^2 extrapolated linearly to zero over
    the last three loaded pairs."""
    loaded = np.nonzero(pressure > 0.0)[0]
    if loaded[-1] == len(theta) - 1:
        raise ValueError(f"the ball-in-socket contact reaches the last paired angle "
                         f"({math.degrees(theta[-1]) + 90.0:.4g} degrees from the bottom): raise fine_to_deg")
    last = loaded[-3:]
    slope, icpt = np.polyfit(theta[last], pressure[last] ** 2, 1)
    return float(-icpt / slope if slope < 0.0 else theta[loaded[-1]])
