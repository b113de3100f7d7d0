"""The second moments of a point contact's pressure that the bodies' own gap implies.

An elliptical region is sized so that its pressure carries no square-root singularity at the
edge. For a gap quadratic in the tangent-plane coordinates (Hertz's) the pressure without it is
p0 sqrt(1 - X^2 - Y^2) on the ellipse, whose second moments are <X^2> = <Y^2> = 1/5 whatever the
axes' ratio (Galin's theorem); the region search takes the root of 5 <X^2> - 1. Where the gap is
not quadratic (a cone's apex, a rounded tip whose contact runs onto its flank, a curvature that
changes across the region) the pressure without the singularity has other moments, and the
root of Hertz's condition is biased: a 10-degree cone's radius read 10-14 % small.

For an axisymmetric gap f(r) on a circle of radius a the pressure without the singularity is
(I. N. Sneddon, Int. J. Engng Sci. 3 (1965) 47-57; J. R. Barber, Contact Mechanics, Springer
2018, ch. 6)

    p(r) = (E* / pi) int_r^a g'(t) / sqrt(t^2 - r^2) dt,   g(t) = t int_0^(pi/2) f'(t sin theta) d theta,

(Hertz's f = r^2 / 2R gives g = t^2 / R and p = 2 E* sqrt(a^2 - r^2) / (pi R); a cone f = r tan b
gives p = E* tan b arccosh(a / r) / 2). Its moments follow by exchanging the integrals,

    int_0^a p r dr ~ int_0^a g'(t) t dt,   int_0^a p r^3 dr ~ (2/3) int_0^a g'(t) t^3 dt,

so that <X^2> = <r^2> / (2 a^2) needs g alone. Each axis of the ellipse takes the moment of the
axisymmetric gap that has that axis's profile (the even part of the gap along it, or its one
side on a symmetric model's sector): exact for Hertz's gap (1/5 on both axes at any ratio) and
for any axisymmetric one, an approximation for a gap that is neither."""

from __future__ import annotations

import numpy as np

__all__ = ["HERTZ_SECOND_MOMENT", "axis_second_moment", "second_moment_targets"]

#: <X^2> of Hertz's pressure sqrt(1 - X^2 - Y^2) over its ellipse
HERTZ_SECOND_MOMENT = 0.2
#: points of the profile between the contact point and the region's edge
PROFILE_POINTS = 257
#: Gauss-Legendre points of g's integral over theta
THETA_POINTS = 24
_THETA_X, _THETA_W = np.polynomial.legendre.leggauss(THETA_POINTS)
_THETA = 0.25 * np.pi * (_THETA_X + 1.0)
_THETA_WEIGHTS = 0.25 * np.pi * _THETA_W


def axis_second_moment(t: np.ndarray, slope: np.ndarray) -> float:
    """<X^2> of the singularity-free pressure of the axisymmetric gap whose slope f'(r) is
    ``slope`` at the radii ``t`` (increasing from 0 to the region's radius a). Hertz's value where
    the gap does not rise (no compression to speak of)."""
    a = float(t[-1])
    g = t * (np.interp(np.outer(t, np.sin(_THETA)), t, slope) @ _THETA_WEIGHTS)
    dg = np.gradient(g, t)
    m1 = np.trapezoid(dg * t, t)
    m3 = (2.0 / 3.0) * np.trapezoid(dg * t**3, t)
    if not (a > 0.0 and m1 > 0.0 and m3 > 0.0):
        return HERTZ_SECOND_MOMENT
    return float(m3 / (2.0 * a * a * m1))


def _profile_slope(s: np.ndarray, gap: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray] | None:
    """(radii, slope) of the axis's gap on [0, reach]: the even part where both sides are sampled
    that far, else the longer side; None where neither side reaches."""
    order = np.argsort(s)
    s, gap = s[order], gap[order]
    t = np.linspace(0.0, reach, PROFILE_POINTS)
    sides = [side for side, ok in ((1.0, s[-1] >= reach), (-1.0, s[0] <= -reach)) if ok]
    if not sides or s[0] > 0.0 or s[-1] < 0.0:
        return None
    f = np.mean([np.interp(side * t, s, gap) for side in sides], axis=0)
    return t, np.gradient(f, t)


def second_moment_targets(s: np.ndarray, gap: np.ndarray, axis: np.ndarray, semi_axes) -> tuple[float, float]:
    """<X^2> and <Y^2> the gap implies for the ellipse of ``semi_axes`` about the contact point:
    s (n, 2) the axis samples' tangent-plane coordinates from the contact point, ``gap`` (n,) the
    bodies' initial gap there, ``axis`` (n,) 0 or 1 the axis each lies on. Hertz's 1/5 where an
    axis's samples do not reach its semi-axis."""
    out = []
    for k, reach in enumerate(semi_axes):
        on = axis == k
        profile = _profile_slope(s[on, k], gap[on], float(reach)) if on.sum() > 2 and reach > 0.0 else None
        if profile is None:
            out.append(HERTZ_SECOND_MOMENT)
            continue
        t, slope = profile
        # less the same quadrature's reading of Hertz's gap (slope t): a quadratic gap gives 1/5
        # to round-off, not to the quadrature's error (2e-6 on 257 points)
        out.append(HERTZ_SECOND_MOMENT + axis_second_moment(t, slope) - axis_second_moment(t, t))
    return out[0], out[1]
