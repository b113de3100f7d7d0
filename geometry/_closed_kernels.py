"""Compiled projection of the closed-form primitives and the ellipse (numba, the ``fast``
extra): one pass over the points, everything per point in registers, results written into
arrays the caller allocated. Imported only through :mod:`geometry._jit` (never by ``import
geometry``); :mod:`geometry._jit` runs the kernel on ranges of the points on threads (the
kernel releases the GIL), so both cores work on one call.

One kernel, ``project_range``, serves every primitive (``kind``), so numba compiles one
signature (on-disk cache, ``cache=True``): the branch on ``kind`` is outside the loop over
the points. The arithmetic is the numpy path's, point by point (``geometry.curves``,
``geometry.surfaces``, ``geometry.ellipse``: same formulas, same order, so the two agree to
a few ulp; the local coordinates are formed by plain sums here and by a BLAS product there).

``prm`` (float64): origin (3), frame rows e1, e2, e3 (9), then the primitive's scalars:
circle R; ellipse a, b; sphere R; cylinder R; cone R, sin, cos, t_apex; torus R, r.
Outputs: ``closest`` and ``normals`` (n, 3), ``dist`` (n,), ``par`` (n npar,) with npar = 1
for curves and 2 for surfaces (row-major (n, 2)).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

jit = njit(cache=True, nogil=True, fastmath=False, error_model="numpy")

LINE, CIRCLE, ELLIPSE, PLANE, SPHERE, CYLINDER, CONE, TORUS = range(8)
KINDS = {"line": LINE, "circle": CIRCLE, "ellipse": ELLIPSE, "plane": PLANE, "sphere": SPHERE,
         "cylinder": CYLINDER, "cone": CONE, "torus": TORUS}

_BIG = 2.0**600
_MAX_NEWTON = 200
_STEP_TOL = 4.5e-16


@jit
def _fmin(a, b):
    """min ignoring NaN (np.fmin)."""
    if a != a:
        return b
    if b != b:
        return a
    return a if a < b else b


@jit
def _fmax(a, b):
    """max ignoring NaN (np.fmax)."""
    if a != a:
        return b
    if b != b:
        return a
    return a if a > b else b


@jit
def _radial(x, y):
    """(rho, cx, cy): |(x, y)| and the unit direction, (1, 0) at the origin; under- and
    overflow of the squares handled as in geometry.curves.unit_radial."""
    rho = math.sqrt(x * x + y * y)
    cx = x / rho
    cy = y / rho
    if rho < 1e-150 or rho > 1e150:
        scale = _BIG if rho < 1e-150 else 1.0
        xt = x * scale
        yt = y * scale
        rt = math.hypot(xt, yt)
        if rt == 0.0:
            return 0.0, 1.0, 0.0
        return rt / scale, xt / rt, yt / rt
    return rho, cx, cy


@jit
def _signed_hypot(s, h):
    """sign(s) hypot(s, h), plus where s >= 0 (geometry._base.signed_hypot)."""
    d = math.sqrt(s * s + h * h)
    if d < 1e-150 or d > 1e150:
        scale = _BIG if d < 1e-150 else 1.0
        d = math.hypot(s * scale, h * scale) / scale
    return -d if s < 0.0 else d


@jit
def _local(P, i, prm):
    q0 = P[i, 0] - prm[0]
    q1 = P[i, 1] - prm[1]
    q2 = P[i, 2] - prm[2]
    x = prm[3] * q0 + prm[4] * q1 + prm[5] * q2
    y = prm[6] * q0 + prm[7] * q1 + prm[8] * q2
    z = prm[9] * q0 + prm[10] * q1 + prm[11] * q2
    return x, y, z


@jit
def _put(out, i, prm, c1, c2, c3, offset):
    """out[i] = c1 e1 + c2 e2 + c3 e3 (+ origin)."""
    for k in range(3):
        v = c1 * prm[3 + k] + c2 * prm[6 + k] + c3 * prm[9 + k]
        out[i, k] = v + prm[k] if offset else v


@jit
def _newton_step(X, c0, z1, d):
    """The Newton step of geometry.ellipse._newton_step, with two reciprocals instead of
    four divisions (the same to a few ulp)."""
    ixd = 1.0 / (X + d)
    iX = 1.0 / X
    u0 = c0 * ixd
    u1 = z1 * iX
    u0 *= u0
    u1 *= u1
    w = u0 + u1
    den = u0 * ixd + u1 * iX
    return (w - 1.0) * w / ((math.sqrt(w) + 1.0) * den)


@jit
def ellipse_first_quadrant(r0, d, y0e, y1e):
    """(u0, u1), closest point (e0 u0, e1 u1), for the scaled first-quadrant point
    (y0/e0, y1/e1) and r0 = (e0/e1)^2 >= 1, d = r0 - 1 (computed without cancellation): the
    monotone Newton of geometry.ellipse, for one point."""
    z1 = y1e
    c0 = y0e * r0
    if z1 <= 1e-100 and c0 <= d:  # on the major axis inside the evolute (or within 1e-100 of it: ellipse.AXIS_HEIGHT)
        v0 = c0 / d if d > 0.0 else 0.0
        v1 = math.sqrt(max(1.0 - v0 * v0, 0.0))
        w = math.sqrt(v0 * v0 + v1 * v1)
        return v0 / w, v1 / w
    lb = max(z1, c0 - d)
    u0 = c0 / (lb + d)
    u1 = z1 / lb
    ub = z1 / math.sqrt(1.0 - u0 * u0)
    ub = _fmin(ub, c0 / math.sqrt(1.0 - u1 * u1) - d)
    ub = _fmin(ub, math.sqrt(c0 * c0 + z1 * z1))
    ub = _fmax(ub, lb)
    ub = min(ub, 1e300)
    ub += _newton_step(ub, c0, z1, d)
    X = _fmax(lb, ub)
    for _ in range(_MAX_NEWTON):
        step = _fmax(_newton_step(X, c0, z1, d), 0.0)
        X += step
        if not step > _STEP_TOL * X:
            break
    u0 = c0 / (X + d)
    u1 = z1 / X
    w = math.sqrt(u0 * u0 + u1 * u1)
    return u0 / w, u1 / w


@jit
def _line(P, lo, hi, prm, closest, normals, dist, par):
    for i in range(lo, hi):
        x, y, t = _local(P, i, prm)
        rho, cx, cy = _radial(x, y)
        _put(normals, i, prm, cx, cy, 0.0, False)
        _put(closest, i, prm, 0.0, 0.0, t, True)
        dist[i] = rho
        par[i] = t


@jit
def _circle(P, lo, hi, prm, closest, normals, dist, par):
    R = prm[12]
    for i in range(lo, hi):
        x, y, h = _local(P, i, prm)
        rho, cx, cy = _radial(x, y)
        par[i] = math.atan2(cy, cx)
        dist[i] = _signed_hypot(rho - R, h)
        _put(normals, i, prm, cx, cy, 0.0, False)
        _put(closest, i, prm, R * cx, R * cy, 0.0, True)


@jit
def _ellipse(P, lo, hi, prm, closest, normals, dist, par):
    a = prm[12]
    b = prm[13]
    k = (b / a) ** 2
    r0 = (a / b) ** 2
    d = (a - b) * (a + b) / (b * b)
    ia = 1.0 / a
    ib = 1.0 / b
    for i in range(lo, hi):
        x, y, h = _local(P, i, prm)
        u0, u1 = ellipse_first_quadrant(r0, d, abs(x) * ia, abs(y) * ib)
        cx = math.copysign(a * u0, x)
        cy = math.copysign(b * u1, y)
        nx = k * cx
        norm = math.sqrt(nx * nx + cy * cy)
        nx /= norm
        ny = cy / norm
        _put(closest, i, prm, cx, cy, 0.0, True)
        _put(normals, i, prm, nx, ny, 0.0, False)
        dist[i] = _signed_hypot((x - cx) * nx + (y - cy) * ny, h)
        par[i] = math.atan2(math.copysign(u1, y), math.copysign(u0, x))


@jit
def _plane(P, lo, hi, prm, closest, normals, dist, par):
    for i in range(lo, hi):
        u, v, h = _local(P, i, prm)
        for c in range(3):
            closest[i, c] = P[i, c] - h * prm[9 + c]
            normals[i, c] = prm[9 + c]
        dist[i] = h
        par[2 * i] = u
        par[2 * i + 1] = v


@jit
def _sphere(P, lo, hi, prm, closest, normals, dist, par):
    R = prm[12]
    for i in range(lo, hi):
        x = P[i, 0] - prm[0]
        y = P[i, 1] - prm[1]
        z = P[i, 2] - prm[2]
        rho = math.sqrt(x * x + y * y + z * z)
        if rho < 1e-150 or rho > 1e150:
            big = max(abs(x), max(abs(y), abs(z)))
            scale = _BIG if big < 1e-140 else 1.0 / _BIG
            xt = x * scale
            yt = y * scale
            zt = z * scale
            rt = math.sqrt(xt * xt + yt * yt + zt * zt)
            if rt == 0.0:  # the centre: the fixed direction e_z
                x, y, z, rho = 0.0, 0.0, 1.0, 0.0
            else:
                x, y, z, rho = xt / rt, yt / rt, zt / rt, rt / scale
        else:
            x /= rho
            y /= rho
            z /= rho
        dist[i] = rho - R
        par[2 * i] = math.atan2(y, x)
        par[2 * i + 1] = math.atan2(z, math.sqrt(x * x + y * y))
        normals[i, 0] = x
        normals[i, 1] = y
        normals[i, 2] = z
        closest[i, 0] = R * x + prm[0]
        closest[i, 1] = R * y + prm[1]
        closest[i, 2] = R * z + prm[2]


@jit
def _revolved(kind, P, lo, hi, prm, closest, normals, dist, par):
    """Cylinder, cone, torus: the foot in the meridian half-plane (rho, t), turned back."""
    R = prm[12]
    for i in range(lo, hi):
        x, y, t = _local(P, i, prm)
        rho, cx, cy = _radial(x, y)
        if kind == CYLINDER:
            rc, tc, nr, nt, d, v = R, t, 1.0, 0.0, rho - R, t
        elif kind == CONE:
            sa, ca, ta = prm[13], prm[14], prm[15]
            d = rho * ca - t * sa - R * ca
            rc = rho - d * ca
            tc = t + d * sa
            nr, nt = ca, -sa
            if rc <= 0.0:  # foot at or behind the apex: the apex
                da, nr, nt = _radial(rho, t - ta)
                if da == 0.0:
                    nr, nt = ca, -sa
                d, rc, tc = da, 0.0, ta
            v = tc
        else:  # torus
            r = prm[13]
            dq, nr, nt = _radial(rho - R, t)
            rc = nr * r + R
            tc = r * nt
            d = dq - r
            v = math.atan2(nt, nr)
        _put(normals, i, prm, nr * cx, nr * cy, nt, False)
        _put(closest, i, prm, rc * cx, rc * cy, tc, True)
        dist[i] = d
        par[2 * i] = math.atan2(cy, cx)
        par[2 * i + 1] = v


@jit
def project_range(kind, P, lo, hi, prm, closest, normals, dist, par):
    """Projects points P[lo:hi] ((n, 3), C order) onto the primitive ``kind`` (module doc)."""
    if kind == LINE:
        _line(P, lo, hi, prm, closest, normals, dist, par)
    elif kind == CIRCLE:
        _circle(P, lo, hi, prm, closest, normals, dist, par)
    elif kind == ELLIPSE:
        _ellipse(P, lo, hi, prm, closest, normals, dist, par)
    elif kind == PLANE:
        _plane(P, lo, hi, prm, closest, normals, dist, par)
    elif kind == SPHERE:
        _sphere(P, lo, hi, prm, closest, normals, dist, par)
    else:
        _revolved(kind, P, lo, hi, prm, closest, normals, dist, par)


def parameters(origin: np.ndarray, frame: np.ndarray, *scalars: float) -> np.ndarray:
    """The ``prm`` vector of a primitive (module doc)."""
    return np.concatenate([np.asarray(origin, float), np.asarray(frame, float).ravel(), np.asarray(scalars, float)])
