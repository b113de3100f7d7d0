"""Geometry of a contact between two solids: the contact frame and
the points of an elliptical contact region on the exact surfaces.

Frame: at the contact point, ``normal`` is the outward unit normal of body 2 (pointing into
body 1); the axes are the principal directions of the relative curvature K = K1 + K2 of the two
surfaces in the tangent plane (each K_i = -P H_i P from the Hessian H_i of the body's exact signed
distance at its surface point, positive for a convex body): the gap is 1/2 s^T K s to second
order, so these are the axes of Hertz's ellipse. ``axes[0]`` carries the smaller curvature (the
larger semi-axis); a circular contact takes ``tangential_direction`` (or the first coordinate
axis not along the normal) for axes[0]; axes[0] x axes[1] = normal.

Region: the ellipse (s0/a)^2 + (s1/b)^2 <= 1 in the tangent plane, laid on body 1's surface
along the normal (x1 = y + t n with the exact zero of body 1's signed distance on the line), over
the angular sectors where body 1 has surface (a quarter model's region is a quarter ellipse).
Its quadrature: polar panels cut at the planes of both bodies' octrees (the integrand's kinks:
solver.fem.surface_quadrature), a collapsed Gauss rule on the pieces, the area element
a b rho / |n1 . n|. Each point is matched on body 2 by exact projection along the gradient of its
signed distance (delta = x1 - x2 as in 2D, eq. 5-2 in 3D)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ibfem.geometry.bisection import bisection_tree

from ..fem.surface_quadrature import MAX_VERTICES, clip_to_grid, triangle_nodes
from .graded_quadrature import clip_to_cells, graded_star_panels

__all__ = ["ContactFrame3D", "RegionPoints", "contact_frame_3d", "tangent_basis", "region_points", "axis_points", "sectors",
           "sector_share", "surrounds",
           "surface_point", "closest_on", "matched_points"]


def _gradient(phi, x: np.ndarray, step: float) -> np.ndarray:
    """(n, 3) central differences of phi at the points x (n, 3): one call of 6n points."""
    e = step * np.concatenate([np.eye(3), -np.eye(3)])
    v = np.asarray(phi((x[None, :, :] + e[:, None, :]).reshape(-1, 3)), float).reshape(6, len(x))
    return ((v[:3] - v[3:]) / (2.0 * step)).T


def _hessian(phi, x: np.ndarray, step: float) -> np.ndarray:
    """(3, 3) Hessian of phi at one point by central differences: its 19 points in one call."""
    e = step * np.eye(3)
    pairs = [(i, j) for i in range(3) for j in range(i + 1, 3)]
    pts = [x[None]] + [np.array([x + e[i], x - e[i]]) for i in range(3)]
    pts += [np.array([x + e[i] + e[j], x + e[i] - e[j], x - e[i] + e[j], x - e[i] - e[j]]) for i, j in pairs]
    v = np.asarray(phi(np.concatenate(pts)), float)
    f0, diag, off = v[0], v[1:7].reshape(3, 2), v[7:].reshape(3, 4)
    h = np.empty((3, 3))
    for i in range(3):
        h[i, i] = (diag[i, 0] + diag[i, 1] - 2.0 * f0) / step**2
    for (i, j), w in zip(pairs, off):
        h[i, j] = h[j, i] = (w[0] - w[1] - w[2] + w[3]) / (4.0 * step**2)
    return h


_LATTICE = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)], dtype=float)
_LATTICE = _LATTICE[np.argsort(np.linalg.norm(_LATTICE, axis=1), kind="stable")]  # the point itself first


def smooth_point(solid, x: np.ndarray, step: float, toward: np.ndarray | None = None) -> np.ndarray:
    """A point within 10 steps of x (one point of the surface) where the signed distance is
    smooth: x itself where it is smooth, or else among the lattice neighbours on the surface whose
    second differences are small, the one whose outward normal points most along ``toward`` (the
    other body); a neighbour of a smooth x would carry a tilted normal and, on a surface curved
    both ways, another curvature (a torus's ring read -0.0126 1/m where it is 0). At the
    edge where a symmetry plane meets a face (a quarter model's contact point) the distance has
    a kink, and a central difference there mixes the two faces' gradients; the contact face's
    normal and curvature are those just inside it. Two calls of the distance: the lattice, then
    the central differences about its points near the surface."""
    phi = solid.signed_distance
    y = x + 10.0 * step * _LATTICE
    f0 = np.asarray(phi(y), float)
    near = np.nonzero(np.abs(f0) <= 11.0 * step)[0]
    if not len(near):
        return x
    e = step * np.eye(3)
    f = np.asarray(phi((y[near, None, None, :] + np.stack([e, -e], axis=1)[None]).reshape(-1, 3)), float)
    f = f.reshape(len(near), 3, 2)
    bends = np.abs(f[:, :, 0] + f[:, :, 1] - 2.0 * f0[near, None])
    grad = (f[:, :, 0] - f[:, :, 1]) / (2.0 * step)
    best, best_dot = x, -np.inf
    for k, v in enumerate(near):  # the lattice's order: the point itself first
        if bends[k].max() > 1e-3 * step:
            continue
        if toward is None or not _LATTICE[v].any():  # x itself is smooth: its own normal and curvatures
            return y[v]
        dot = float(-grad[k] @ toward) / max(np.linalg.norm(grad[k]), 1e-300)
        if dot > best_dot + 1e-9:
            best, best_dot = y[v], dot
    return best


def closest_on(solid, x: np.ndarray, step: float, sweeps: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Closest points (n, 3) on a solid's surface and its outward unit normals there, by
    x <- x - phi(x) grad phi(x) on the exact signed distance (exact in one step where it is
    smooth; a few sweeps settle the finite differences)."""
    x = np.asarray(x, dtype=float).reshape(-1, 3)
    for _ in range(sweeps):
        g = _gradient(solid.signed_distance, x, step)
        g /= np.maximum(np.linalg.norm(g, axis=1), 1e-300)[:, None]
        x = x - np.asarray(solid.signed_distance(x), float)[:, None] * g
    g = _gradient(solid.signed_distance, x, step)
    return x, -g / np.maximum(np.linalg.norm(g, axis=1), 1e-300)[:, None]


@dataclass(frozen=True)
class ContactFrame3D:
    point: np.ndarray  # (3,) on the tangent plane, midway between the closest points
    normal: np.ndarray  # (3,) outward normal of body 2
    axes: np.ndarray  # (2, 3) principal directions of the relative curvature
    curvatures: np.ndarray  # (2,) relative principal curvatures along the axes (1/R'_0 <= 1/R'_1)
    conforming: bool = False  # the relative curvature a small difference of the bodies' own


def tangent_basis(normal: np.ndarray, hint: np.ndarray | None) -> np.ndarray:
    candidates = ([] if hint is None else [np.asarray(hint, float)]) + list(np.eye(3))
    for c in candidates:
        t = c - (c @ normal) * normal
        if np.linalg.norm(t) > 1e-6 * max(np.linalg.norm(c), 1e-300):
            t0 = t / np.linalg.norm(t)
            return np.array([t0, np.cross(normal, t0)])
    raise ValueError("no tangent direction")  # pragma: no cover - eye(3) always has one


#: frames computed lately, newest last: (solid1, solid2, key, frame)
_RECENT_FRAMES: list = []
#: how many frames :func:`contact_frame_3d` keeps
RECENT_FRAMES = 8


def contact_frame_3d(solid1, solid2, point: np.ndarray, scale: float,
                     tangential_direction: np.ndarray | None = None) -> ContactFrame3D:
    """The frame at the contact point (``scale``: the finest cell, sets the difference steps).
    A run asks for the same frame several times (the scene's checks, the line-contact test, the
    contact's set-up): the last few are kept, for the same two solid objects (the solids are not
    changed once built) and the same point, scale and direction, and returned again (their
    arrays read-only)."""
    key = (np.asarray(point, float).tobytes(), float(scale),
           None if tangential_direction is None else np.asarray(tangential_direction, float).tobytes())
    for entry in _RECENT_FRAMES:
        if entry[0] is solid1 and entry[1] is solid2 and entry[2] == key:
            return entry[3]
    frame = _contact_frame_3d(solid1, solid2, point, scale, tangential_direction)
    for a in (frame.point, frame.normal, frame.axes, frame.curvatures):
        a.flags.writeable = False
    _RECENT_FRAMES.append((solid1, solid2, key, frame))
    del _RECENT_FRAMES[:-RECENT_FRAMES]
    return frame


def _contact_frame_3d(solid1, solid2, point: np.ndarray, scale: float,
                      tangential_direction: np.ndarray | None) -> ContactFrame3D:
    step = 1e-4 * scale
    x2, _ = closest_on(solid2, np.asarray(point, float)[None], step)
    x1, _ = closest_on(solid1, np.asarray(point, float)[None], step)
    centres = [0.5 * (np.asarray(sol.bounds[0], float) + np.asarray(sol.bounds[1], float)) for sol in (solid1, solid2)]
    s2 = smooth_point(solid2, x2[0], step, centres[0] - x2[0])  # on a symmetry edge: just inside the face
    g = _gradient(solid2.signed_distance, s2[None], step)[0]
    normal = -g / np.linalg.norm(g)
    basis = tangent_basis(normal, tangential_direction)
    hstep = 1e-2 * scale
    k = np.zeros((2, 2))
    own = []
    for solid, x, other in ((solid1, x1[0], centres[1]), (solid2, x2[0], centres[0])):
        h = _hessian(solid.signed_distance, smooth_point(solid, x, hstep, other - x), hstep)
        k -= basis @ h @ basis.T
        own.append(float(np.abs(np.linalg.eigvalsh(0.5 * (h + h.T))).max()))
    k = 0.5 * (k + k.T)
    mid = 0.5 * (x1[0] + x2[0])
    round_off = 1e-4  # the differences resolve ~1e-5 of the curvatures
    conforming = float(np.abs(np.linalg.eigvalsh(k)).max()) < CONFORMAL_SHARE * max(own)
    if conforming:
        step = min(2.0 * scale, 0.05 / max(own))  # within a twentieth of the bodies' smaller radius
        k = _overlap_curvature(solid1, solid2, ContactFrame3D(mid, normal, basis, np.zeros(2)), step)
        round_off = CONFORMAL_ROUND_OFF
    values, vectors = np.linalg.eigh(k)  # ascending: the smaller curvature first
    if abs(values[1] - values[0]) <= round_off * max(abs(values).max(), 1e-300):
        axes, curv = basis, np.array([values.mean(), values.mean()])  # circular: the hint's axes
    else:
        axes = vectors.T @ basis
        curv = values
    if np.cross(axes[0], axes[1]) @ normal < 0.0:
        axes = np.array([axes[0], -axes[1]])
    return ContactFrame3D(point=mid, normal=normal, axes=axes, curvatures=curv, conforming=conforming)


#: the relative curvature below this share of a body's own: conforming surfaces (a ball in a
#: socket), whose relative curvature is the small difference of the two bodies' large ones
CONFORMAL_SHARE = 0.1
#: the overlap's fit resolves conforming surfaces' relative curvatures to about 2e-4 of them (a
#: ball in a socket: 0.19806 and 0.19810 1/m for 0.19802): closer than this share, the contact
#: is circular (the hint's axes, not the fit's noise)
CONFORMAL_ROUND_OFF = 2e-3


def _overlap_curvature(solid1, solid2, frame: ContactFrame3D, t: float) -> np.ndarray:
    """(2, 2) the relative curvature K of conforming surfaces in the frame's basis, from the overlap
    O(s) = phi_2(x_1(s)) of body 1's surface points in body 2 over the tangent-plane coordinates s
    (O = O0 + g.s - 1/2 s^T K s + higher terms): a least-squares quartic in s on rings of radius
    t, 2t, 3t, 4t, 48 points each, where body 1 has surface (a symmetric model's sector is
    enough). The bodies' own curvatures (each 1/R) cancel to 1/R1 - 1/R2 there: taken
    one by one from the signed distances' Hessians at a small step, their round-off (about 1e-10 m
    of distance) would be most of the difference."""
    angle = np.deg2rad(3.75 + 7.5 * np.arange(48))  # off a quarter model's symmetry planes
    radius = t * np.repeat(np.arange(1.0, 5.0), len(angle))
    s = np.vstack([np.zeros((1, 2)), radius[:, None] * np.tile(np.stack([np.cos(angle), np.sin(angle)], 1), (4, 1))])
    x1, ok = surface_point(solid1, frame, s, 20.0 * t)
    u = s[ok] / t
    powers = [(i, n - i) for n in range(5) for i in range(n + 1)]  # the 15 monomials of degree <= 4
    if len(u) < 2 * len(powers):
        raise ValueError(f"conforming surfaces at {np.round(frame.point, 6).tolist()}: body 1 has surface at only "
                         f"{len(u)} of {len(s)} points within {4.0 * t:.3g} m of the contact point, too few to "
                         "measure their relative curvature")
    design = np.stack([u[:, 0] ** i * u[:, 1] ** j for i, j in powers], axis=1)
    c = np.linalg.lstsq(design, np.asarray(solid2.signed_distance(x1[ok]), float), rcond=None)[0]
    c20, c11, c02 = (c[powers.index(p)] for p in ((2, 0), (1, 1), (0, 2)))
    return -np.array([[2.0 * c20, c11], [c11, 2.0 * c02]]) / t**2


#: secant rounds of the fast path before a line goes through the scan
SECANT_ROUNDS = 10
#: the largest ratio of successive distances below the root at which the fast path checks that the
#: line is outside the body all the way down to -reach (each sample's |phi| clears a ball around it)
COVER_RATIO = 16.0


def surface_point(solid, frame: ContactFrame3D, s: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Points x1 = y + t n (n, 3) of a solid's surface above the tangent-plane points y(s) (s (n, 2)
    along the frame's axes), the exact zero of its signed distance on t in [-reach, reach] (the
    first entry into the body going up the line), and a mask of the lines that cross the surface
    there (the distance grows across the root: slope >= 1/4 along n).

    Fast path: a secant from the tangent plane (t = 0), the root then certified as the first entry
    by the distance's Lipschitz bound (|phi(x)| clears a ball around x: samples below the root at
    geometrically growing distances whose balls overlap down to -reach) and a strict sign change
    around it. Lines it cannot certify (no crossing near the plane, a line along a face such as a
    quarter model's symmetry plane, a steep or re-entrant surface) go through a 33-sample scan of
    [-reach, reach] and an Illinois regula falsi on the first bracketed entry."""
    y = frame.point + s[:, :1] * frame.axes[0] + s[:, 1:] * frame.axes[1]
    n = frame.normal
    tol = 1e-12 * reach

    def f(x):  # round-off of a face's distance (a point on a symmetry plane: +-1e-17) is on it
        v = np.asarray(solid.signed_distance(x), float)
        return np.where(np.abs(v) <= tol, 0.0, v)

    t, found, rate = _secant_roots(f, y, n, reach)
    ok = np.zeros(len(s), dtype=bool)
    i = np.nonzero(found)[0]
    ok[i], on_face, f_below = _certified(f, y[i], n, t[i], rate[i], reach)
    j = np.nonzero(on_face)[0]
    if len(j):  # a face along the line above the root: its lower end, within d below (bisection)
        d = 1e-10 * reach
        k = i[j]
        t[k] = _illinois(f, y[k], n, t[k] - d, t[k], f_below[j], np.zeros(len(k)), reach)
        ok[k] = _slope_test(f, y[k] + t[k, None] * n, n, reach)
    rest = np.nonzero(~ok)[0]
    if len(rest):
        t[rest], ok[rest] = _scanned_roots(f, y[rest], n, reach)
    return y + t[:, None] * n, ok


def _secant_roots(f, y: np.ndarray, n: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Zeros t (m,) of f(y + t n) by a secant from t = 0 (first step: slope 1, the signed
    distance's along the normal at the contact point), iterating only the lines not yet on the
    surface; the mask of lines that reached it (|phi| <= tol) inside [-reach, reach], and the last
    secant slope of each line (1 where the plane point is on the surface)."""
    m = len(y)
    t = np.zeros(m)
    found = np.zeros(m, dtype=bool)
    rate = np.ones(m)
    t0 = np.zeros(m)
    f0 = f(y)
    found[f0 == 0.0] = True
    act = np.nonzero(~found)[0]
    t1 = t0[act] - f0[act]
    t0, f0 = t0[act], f0[act]
    for _ in range(SECANT_ROUNDS):
        inside = np.abs(t1) <= reach
        act, t0, f0, t1 = act[inside], t0[inside], f0[inside], t1[inside]
        if not len(act):
            break
        f1 = f(y[act] + t1[:, None] * n)
        hit = f1 == 0.0
        t[act[hit]] = t1[hit]
        found[act[hit]] = True
        slope = (f1 - f0) / np.where(t1 != t0, t1 - t0, np.inf)
        rate[act] = slope
        going = ~hit & (slope >= 0.125)  # a shallow or falling line: the scan decides
        act, t0, f0, t1, f1, slope = act[going], t1[going], f1[going], t1[going], f1[going], slope[going]
        t1 = t1 - f1 / slope
    return t, found, rate


def _certified(f, y: np.ndarray, n: np.ndarray, t: np.ndarray, rate: np.ndarray, reach: float):
    """Whether the zeros t (m,) on the lines y + t n are their first entries into the body in
    [-reach, reach] with a real crossing: samples at t - d q^k (k = 0, 1, ...; and -reach) all
    outside (f < 0) with balls of radius |f| overlapping, f > 0 just above (d) and the scan path's
    slope test. Also: the lines that pass all but f > 0 above (a face along the line from the root
    up, whose lower end lies within d below t) and f(t - d). The ratio q per line from its slope
    ``rate`` along the line (|f| ~ rate x distance below the root: balls overlap up to
    q = (1 + rate) / (1 - rate)), with margins."""
    m = len(t)
    if not m:
        return np.zeros(0, bool), np.zeros(0, bool), np.zeros(0)
    d, eps = 1e-10 * reach, 1e-6 * reach
    r = 0.9 * np.clip(rate, 0.0, 1.0)  # a margin for distances that are not exactly Lipschitz-1
    q = np.clip(0.8 * (1.0 + r) / np.maximum(1.0 - r, 1e-3), 2.0, COVER_RATIO)  # 0.8: slack
    span = np.maximum(t + reach, d)
    count = np.ceil(np.log(span / d) / np.log(q)).astype(int)  # d q^count >= span: at -reach
    k = np.arange(count.max() + 1)
    below = np.maximum(t[:, None] - d * q[:, None] ** k[None, :], -reach)
    below[k[None, :] >= count[:, None]] = -reach
    valid = k[None, :] <= count[:, None]  # the last one at -reach
    v = np.full(below.shape, -np.inf)
    extra = np.column_stack([t + d, t + eps, t - eps])
    chain = (y[:, None, :] + below[:, :, None] * n)[valid]
    values = f(np.concatenate([chain, (y[:, None, :] + extra[:, :, None] * n).reshape(-1, 3)]))
    v[valid] = values[:len(chain)]
    up_d, up, down = values[len(chain):].reshape(m, 3).T
    radius = np.where(valid, 0.9 * np.abs(v), np.inf)
    cover = (below[:, :-1] - below[:, 1:] <= radius[:, :-1] + radius[:, 1:]).all(axis=1)
    first = (v < 0.0).all(axis=1) & cover & (up - down > 0.5 * eps)
    return first & (up_d > 0.0), first & (up_d == 0.0), v[:, 0]


def _slope_test(f, x1: np.ndarray, n: np.ndarray, reach: float) -> np.ndarray:
    """A real crossing of the surface at x1: the distance grows across it (slope >= 1/4 along n).
    A line that runs along a face a hair outside it (a symmetry plane at a quarter model's sector
    edge) sees only round-off change sign, and its "root" may lie anywhere on the face; a line on
    the face itself still crosses the contact surface properly."""
    eps = 1e-6 * reach
    up, down = (np.asarray(f(x1 + sign * eps * n), float) for sign in (1.0, -1.0))
    return up - down > 0.5 * eps


def _scanned_roots(f, y: np.ndarray, n: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """The robust path: the first entry among 33 samples of [-reach, reach], an Illinois regula
    falsi in it (only the lines not yet converged), and the slope test."""
    m = len(y)
    t = np.linspace(-reach, reach, 33)
    values = np.asarray(f((y[:, None, :] + t[None, :, None] * n).reshape(-1, 3)), float).reshape(m, len(t))
    entry = (values[:, :-1] < 0.0) & (values[:, 1:] >= 0.0)
    ok = entry.any(axis=1)
    first = np.argmax(entry, axis=1)
    rows = np.arange(m)
    lo, hi, flo, fhi = t[first], t[first + 1], values[rows, first], values[rows, first + 1]
    t = np.zeros(m)
    i = np.nonzero(ok)[0]
    if len(i):
        t[i] = _illinois(f, y[i], n, lo[i], hi[i], flo[i], fhi[i], reach)
        ok[i] = _slope_test(f, y[i] + t[i, None] * n, n, reach)
    return t, ok


#: bisection levels of a line on a face (f = 0 at the bracket's upper end) evaluated per call:
#: the 2^k - 1 midpoints the next k bisection steps may take, in one batch
PLATEAU_LEVELS = 4
#: the regula falsi's iterations at most
ILLINOIS_STEPS = 200


def _illinois(f, y, n, a, b, fa, fb, reach: float) -> np.ndarray:
    """Zeros in the brackets [a, b] (f(a) < 0 <= f(b)) on the lines y + t n, each line iterated
    until its bracket or step is at round-off. Where b lies exactly on the surface the line may run
    along a face there (phi = 0 on a stretch, a quarter model's axis on its symmetry plane), whose
    lower end is the point: it is bisected, PLATEAU_LEVELS steps per call of the distance (the
    midpoints each outcome leads to evaluated together; the steps, and so the zeros, are those of
    one step per call)."""
    st = _Falsi(a.copy(), b.copy(), fa.copy(), fb.copy(), len(a))
    out = np.zeros(len(a))
    act = np.arange(len(a))
    while True:
        act = act[st.steps[act] < ILLINOIS_STEPS]
        if len(act):
            act = act[~st.begin(act, out, reach)]
        if not len(act):
            return out
        flat = st.fb[act] == 0.0
        single, lines = act[~flat], act[flat]
        ahead = bisection_tree(st.a[lines], st.b[lines], PLATEAU_LEVELS)  # its root: the step begun
        values = np.asarray(f(y[np.concatenate([single, np.repeat(lines, ahead.shape[1])])]
                              + np.concatenate([st.x[single], ahead.ravel()])[:, None] * n), float)
        st.update(single, values[:len(single)])
        _walk(st, lines, values[len(single):].reshape(ahead.shape), out, reach)
        act = act[~st.closed[act]]


def _walk(st, lines: np.ndarray, tree: np.ndarray, out: np.ndarray, reach: float) -> None:
    """The bisection steps of the lines on a face along their evaluated trees, while they stay on
    it (f = 0 at the bracket's upper end) and open."""
    rows, node = np.arange(len(lines)), np.zeros(len(lines), dtype=np.int64)
    for level in range(PLATEAU_LEVELS):
        up = st.update(lines, tree[rows, node])
        if level == PLATEAU_LEVELS - 1:
            return
        walk = (st.fb[lines] == 0.0) & (st.steps[lines] < ILLINOIS_STEPS)
        lines, rows, node, up = lines[walk], rows[walk], node[walk], up[walk]
        if not len(lines):
            return
        done = st.begin(lines, out, reach)
        lines, rows, node = lines[~done], rows[~done], np.where(up, 2 * node + 1, 2 * node + 2)[~done]
        if not len(lines):
            return


class _Falsi:
    """The brackets of :func:`_illinois`' lines: [a, b] with f(a), f(b), the side the last step
    moved, the last point, the steps begun and whether the line is closed."""

    def __init__(self, a, b, fa, fb, m: int):
        self.a, self.b, self.fa, self.fb, self.x = a, b, fa, fb, a.copy()
        self.side = np.zeros(m, dtype=np.int8)
        self.steps = np.zeros(m, dtype=np.int64)
        self.closed = np.zeros(m, dtype=bool)

    def begin(self, lines: np.ndarray, out: np.ndarray, reach: float) -> np.ndarray:
        """A step of ``lines``: the next point (bisection on a face, else the Illinois regula falsi),
        written to ``out``; returns the lines whose bracket or step is at round-off (closed)."""
        a, b, fa, fb, x = self.a[lines], self.b[lines], self.fa[lines], self.fb[lines], self.x[lines]
        plateau = fb == 0.0
        xn = np.where(plateau, 0.5 * (a + b), b - fb * (b - a) / np.where(fb != fa, fb - fa, 1.0))
        done = (np.abs(b - a) <= 1e-13 * reach) | (~plateau & (np.abs(xn - x) <= 1e-16 * reach))
        out[lines] = xn
        self.x[lines] = xn
        self.steps[lines] += 1
        self.closed[lines[done]] = True
        return done

    def update(self, lines: np.ndarray, fx: np.ndarray) -> np.ndarray:
        """The brackets of ``lines`` after f = fx at their points; returns where the zero lies above."""
        a, b, fa, fb, side, x = (v[lines] for v in (self.a, self.b, self.fa, self.fb, self.side, self.x))
        left = (fx < 0.0) == (fa < 0.0)
        a, fa = np.where(left, x, a), np.where(left, fx, fa)
        fb = np.where(left & (side == 1), 0.5 * fb, fb)
        b, fb = np.where(left, b, x), np.where(left, fb, fx)
        fa = np.where(~left & (side == -1), 0.5 * fa, fa)
        self.a[lines], self.b[lines], self.fa[lines], self.fb[lines] = a, b, fa, fb
        self.side[lines] = np.where(left, 1, -1)
        return left


def sector_share(ranges: list[tuple[float, float]]) -> float:
    """The share of the full turn the angular ranges of :func:`sectors` cover (1 where body 1 is
    all around the contact point, 0.25 for a quarter model)."""
    return float(sum(t1 - t0 for t0, t1 in ranges) / (2.0 * math.pi))


def surrounds(ranges: list[tuple[float, float]]) -> bool:
    """Whether the ranges of :func:`sectors` cover the full turn (body 1 all around the point)."""
    return sector_share(ranges) >= 1.0 - 1e-9 / (2.0 * math.pi)


def sectors(solid1, frame: ContactFrame3D, radius: float, reach: float, samples: int = 720) -> list[tuple[float, float]]:
    """Angular ranges [theta0, theta1] around the contact point where body 1 has surface above the
    tangent plane (the whole circle, or a quarter model's quarter), ends found by bisection."""
    theta = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)

    def present(th):
        s = radius * np.stack([np.cos(th), np.sin(th)], axis=1)
        return surface_point(solid1, frame, s, reach)[1]

    has = present(theta)
    if has.all():
        return [(0.0, 2.0 * math.pi)]
    if not has.any():
        raise ValueError("body 1 has no surface over the contact point's tangent plane")
    brackets = []  # (outside, inside) of each range's two ends
    start = int(np.argmin(has))  # a missing direction: ranges start after it
    order = np.roll(np.arange(samples), -start)
    k = 0
    while k < samples:
        if not has[order[k]]:
            k += 1
            continue
        j = k
        while j + 1 < samples and has[order[j + 1]]:
            j += 1
        lo_in, hi_in = theta[order[k]], theta[order[j]]
        lo_out, hi_out = lo_in - 2 * math.pi / samples, hi_in + 2 * math.pi / samples
        brackets += [(lo_out, lo_in), (hi_out, hi_in)]
        k = j + 1
    ends = _edges(present, brackets)
    out = list(zip(ends[0::2], ends[1::2]))
    return [(a0, a1 if a1 > a0 else a1 + 2 * math.pi) for a0, a1 in out]


def _edges(present, brackets: list[tuple[float, float]], split: int = 16) -> list[float]:
    """The angles where surface appears between ``outside`` (none) and ``inside`` of each bracket:
    each bracket cut into ``split`` pieces per round down to 2^-50 of its width (or round-off),
    the first present angle from the outside end kept as the new inside; the cuts of all the
    brackets in one batch of lines per round."""
    outside = np.array([b[0] for b in brackets], dtype=float)
    inside = np.array([b[1] for b in brackets], dtype=float)
    pieces = np.arange(1, split)
    for _ in range(math.ceil(50 / math.log2(split))):
        cut = outside[:, None] + (inside - outside)[:, None] * pieces[None, :] / split
        has = present(cut.ravel()).reshape(cut.shape)
        for m in range(len(brackets)):
            if not has[m].any():
                outside[m] = cut[m, -1]
                continue
            j = int(np.argmax(has[m]))
            outside[m], inside[m] = (cut[m, j - 1] if j > 0 else outside[m]), cut[m, j]
    return [float(v) for v in inside]


@dataclass
class RegionPoints:
    """Quadrature or sample points of a contact region, with their matched points."""

    s: np.ndarray  # (q, 2) tangent-plane coordinates along the axes
    x1: np.ndarray  # (q, 3) on body 1
    x2: np.ndarray  # (q, 3) matched on body 2
    n1: np.ndarray  # (q, 3) outward normals of body 1
    n2: np.ndarray  # (q, 3) outward normals of body 2
    weights: np.ndarray  # (q,) surface area
    normal: np.ndarray  # (q, 3) contact normal (the frame's)

    @property
    def delta(self) -> np.ndarray:
        """X1 - X2 (the 2D formulation's convention: the jump's target is -delta)."""
        return self.x1 - self.x2

    @property
    def pair_normal(self) -> np.ndarray:
        """(q, 3) bisector of body 2's outward normal and body 1's inward one (the 2D default)."""
        v = self.n2 - self.n1
        return v / np.linalg.norm(v, axis=1)[:, None]


def matched_points(solid1, solid2, frame, s, weights, reach, step, on_body1=None) -> RegionPoints:
    """Points of body 1 above the tangent-plane points s and their closest points on body 2
    (``on_body1``: :func:`surface_point`'s answer for s when the caller has it)."""
    x1, ok = surface_point(solid1, frame, s, reach) if on_body1 is None else on_body1
    if not ok.all():
        keep = ok
        s, x1, weights = s[keep], x1[keep], weights[keep]
    g1 = _gradient(solid1.signed_distance, x1, step)
    n1 = -g1 / np.maximum(np.linalg.norm(g1, axis=1), 1e-300)[:, None]
    x2, n2 = closest_on(solid2, x1, step, sweeps=2)
    # the contact's normal: the frame's (the small slopes of a contact small against the radii,
    # as in Hertz's theory), or on conforming surfaces, whose contact spans a large angle, body
    # 2's at each point (the closest point's gap runs along it)
    normal = np.broadcast_to(frame.normal, x1.shape).copy()
    if frame.conforming:
        normal = np.where((n2 @ frame.normal > 0.5)[:, None], n2, normal)
    return RegionPoints(s=s, x1=x1, x2=x2, n1=n1, n2=n2, weights=weights, normal=normal)


def _ellipse_panels(ranges, a: float, b: float, panel: float) -> tuple[list, list]:
    """(r, phi) panels of the ellipse: a product grid per angular range."""
    lowers, uppers = [], []
    n_rho = max(2, int(math.ceil(max(a, b) / panel)))
    for t0, t1 in ranges:
        n_theta = max(2, int(math.ceil((t1 - t0) * max(a, b) / panel)))
        r, t = np.linspace(0.0, 1.0, n_rho + 1), np.linspace(t0, t1, n_theta + 1)
        r0, t_0 = np.meshgrid(r[:-1], t[:-1], indexing="ij")
        r1, t_1 = np.meshgrid(r[1:], t[1:], indexing="ij")
        lowers.append(np.column_stack([r0.ravel(), t_0.ravel()]))
        uppers.append(np.column_stack([r1.ravel(), t_1.ravel()]))
    return lowers, uppers


#: angles per range on which a star-shaped region's edge length is measured
EDGE_SAMPLES = 2048


def _star_panels(ranges, a: float, b: float, radius, panel: float) -> tuple[list, list]:
    """(r, phi) panels of the star-shaped region s = r rho(phi) (a cos phi, b sin phi) at most
    about ``panel`` across in the tangent plane: angular strips cut every ``panel`` of the edge's
    length (an elongated region has short strips at its ends and long ones along its sides), each
    strip cut radially into pieces of its own ray's length over ``panel``."""
    lowers, uppers = [], []
    for t0, t1 in ranges:
        phi = np.linspace(t0, t1, EDGE_SAMPLES + 1)
        edge = radius(phi)[:, None] * np.stack([a * np.cos(phi), b * np.sin(phi)], axis=1)
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(edge, axis=0), axis=1))])
        n_theta = max(2, int(math.ceil(arc[-1] / panel)))
        cuts = np.interp(np.linspace(0.0, arc[-1], n_theta + 1), arc, phi)
        ray = np.linalg.norm(edge, axis=1)
        strip = np.clip(np.searchsorted(cuts, phi, side="right") - 1, 0, n_theta - 1)
        longest = np.zeros(n_theta)
        np.maximum.at(longest, strip, ray)
        for k in range(n_theta):
            n_rho = max(2, int(math.ceil(longest[k] / panel)))
            r = np.linspace(0.0, 1.0, n_rho + 1)
            lowers.append(np.column_stack([r[:-1], np.full(n_rho, cuts[k])]))
            uppers.append(np.column_stack([r[1:], np.full(n_rho, cuts[k + 1])]))
    return lowers, uppers


def region_points(solid1, solid2, frame: ContactFrame3D, a: float, b: float, ranges, grids, panel: float,
                  reach: float, order: int = 3, centre=(0.0, 0.0), radius=None, cells=None) -> RegionPoints:
    """Quadrature of the ellipse ((s0 - e0)/a)^2 + ((s1 - e1)/b)^2 <= 1 (``centre`` e in the
    tangent plane; a symmetric model's sectors only about e = 0) on body 1 over the angular
    ``ranges``, cut at both bodies' octree planes (``grids``: (origin, spacing) pairs), panels at
    most ``panel`` across. With ``radius`` (a function rho(phi) of the angle), the
    star-shaped region s = e + r rho(phi) (a cos phi, b sin phi), r <= 1 (area
    element a b rho^2 r dr dphi); where body 1's surface ends inside it (a free edge), the
    points beyond the edge are dropped. With ``cells`` (each body's leaf size at 3D points,
    solver.contact.graded_quadrature.leaf_size), a star-shaped region's panels follow the cells
    they lie in (``panel`` per finest cell) instead of the finest cell everywhere."""
    scale, shift = np.array([a, b]), np.asarray(centre, dtype=float)
    if radius is None:
        lowers, uppers = _ellipse_panels(ranges, a, b, panel)
    elif cells is None:
        lowers, uppers = _star_panels(ranges, a, b, radius, panel)
    else:
        panel_at = _panel_sizes(frame, shift, grids, cells, panel)
        lowers, uppers = graded_star_panels(ranges, a, b, radius, panel, panel_at, EDGE_SAMPLES)
    lower, upper = np.concatenate(lowers), np.concatenate(uppers)

    def plane(rt):
        r = rt[:, :1] if radius is None else rt[:, :1] * radius(rt[:, 1])[:, None]
        return shift + scale * r * np.stack([np.cos(rt[:, 1]), np.sin(rt[:, 1])], axis=1)

    corners = np.stack([lower, np.column_stack([upper[:, 0], lower[:, 1]]), upper,
                        np.column_stack([lower[:, 0], upper[:, 1]])], axis=1).reshape(-1, 2)
    step = 1e-4 * panel
    # neighbouring panels share corners (a product grid's inner corner is four panels'): each
    # corner's line is followed once
    unique, back = np.unique(corners, axis=0, return_inverse=True)
    x1u, _ = surface_point(solid1, frame, plane(unique), reach)
    x2u, _ = closest_on(solid2, x1u, step, sweeps=2)
    x1c, x2c = x1u[back.ravel()], x2u[back.ravel()]
    poly = np.zeros((len(lower), MAX_VERTICES, 2))
    poly[:, :4] = corners.reshape(-1, 4, 2)
    count = np.full(len(lower), 4, dtype=np.int64)
    owner = np.arange(len(lower))
    for k, ((origin, spacing), pts) in enumerate(zip(grids, (x1c, x2c))):
        if cells is None or radius is None:
            poly, count, owner = clip_to_grid(poly, count, owner, lower, upper, pts.reshape(-1, 4, 3), origin, spacing)
        else:
            poly, count, owner = clip_to_cells(poly, count, owner, lower, upper, pts.reshape(-1, 4, 3), origin,
                                               spacing, cells[k])
    rt, w, _ = triangle_nodes(poly, count, order)
    keep = w > 1e-12 * w.max()  # slivers cut off at a plane through a range's edge: nothing to integrate
    rt, w = rt[keep], w[keep]
    s = plane(rt)
    jacobian = a * b * rt[:, 0] if radius is None else a * b * rt[:, 0] * radius(rt[:, 1]) ** 2
    pts = matched_points(solid1, solid2, frame, s, w * jacobian, reach, step)
    cos = np.abs(np.einsum("qi,i->q", pts.n1, frame.normal))
    pts.weights = pts.weights / np.maximum(cos, 1e-12)
    return pts


def _panel_sizes(frame: ContactFrame3D, shift: np.ndarray, grids, cells, panel: float):
    """The panel's size at tangent-plane points s (n, 2) from the region's centre: ``panel`` per
    finest cell times the finer of the two bodies' leaves there (found just inside each body:
    body 1 above the tangent plane, body 2 below it)."""
    finest = min(float(spacing) for _, spacing in grids)
    nudge = 1e-6 * finest * frame.normal

    def panel_at(s: np.ndarray) -> np.ndarray:
        s = shift + np.asarray(s, dtype=float).reshape(-1, 2)
        y = frame.point + s[:, :1] * frame.axes[0] + s[:, 1:] * frame.axes[1]
        size = np.minimum(cells[0](y + nudge), cells[1](y - nudge))
        return panel * np.maximum(size / finest, 1.0)

    return panel_at


def axis_points(solid1, solid2, frame: ContactFrame3D, axis: int, s: np.ndarray, reach: float,
                step: float, offset: np.ndarray | None = None) -> RegionPoints:
    """Sample points along one axis of the frame (s signed along it; ``offset`` across it)."""
    st = np.zeros((len(s), 2))
    st[:, axis] = s
    if offset is not None:
        st[:, 1 - axis] = offset
    return matched_points(solid1, solid2, frame, st, np.zeros(len(s)), reach, step)
