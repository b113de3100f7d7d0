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

so that <X^2> = <r^2> / (2 a^2) needs g alone. The load of the region of radius x is
P(x) = 2 E* int_0^x g'(t) t dt.

Partial slip under a tangential load Q below mu N (bodies of similar elasticity): the shear is mu
times the difference of the pressures of the region a and of a region c under the same gap, so the
stick radius has P(c) / P(a) = 1 - Q / (mu N) (Cattaneo and Mindlin for Hertz's gap, whence
c / a = (1 - Q / (mu N))^(1/3); J. Jaeger, Wear 1998; M. Ciavarella, Int. J. Solids Struct. 35
(1998) 2349-2362, for any gap of revolution: a cone's c / a = (1 - Q / (mu N))^(1/2)). Each axis of the ellipse takes the moment of the
axisymmetric gap that has that axis's profile (the even part of the gap along it, or its one
side on a symmetric model's sector): exact for Hertz's gap (1/5 on both axes at any ratio) and
for any axisymmetric one, an approximation for a gap that is neither."""

from __future__ import annotations

import numpy as np

__all__ = ["HERTZ_SECOND_MOMENT", "axis_second_moment", "second_moment_targets", "axis_stick_ratio", "stick_ratio_targets"]

#: <X^2> of Hertz's pressure sqrt(1 - X^2 - Y^2) over its ellipse
HERTZ_SECOND_MOMENT = 0.2
#: points of the profile between the contact point and the region's edge
PROFILE_POINTS = 257
#: Gauss-Legendre points of g's integral over theta
THETA_POINTS = 24
_THETA_X, _THETA_W = np.polynomial.legendre.leggauss(THETA_POINTS)
_THETA = 0.25 * np.pi * (_THETA_X + 1.0)
_THETA_WEIGHTS = 0.25 * np.pi * _THETA_W


def _g_slope(t: np.ndarray, slope: np.ndarray) -> np.ndarray:
    """g'(t) at the radii t, g(t) = t int_0^(pi/2) f'(t sin theta) d theta, for the gap of
    revolution whose slope f'(r) is ``slope`` at t."""
    g = t * (np.interp(np.outer(t, np.sin(_THETA)), t, slope) @ _THETA_WEIGHTS)
    return np.gradient(g, t)


def axis_second_moment(t: np.ndarray, slope: np.ndarray) -> float:
    """<X^2> of the singularity-free pressure of the axisymmetric gap whose slope f'(r) is
    ``slope`` at the radii ``t`` (increasing from 0 to the region's radius a). Hertz's value where
    the gap does not rise (no compression to speak of)."""
    a = float(t[-1])
    dg = _g_slope(t, slope)
    m1 = np.trapezoid(dg * t, t)
    m3 = (2.0 / 3.0) * np.trapezoid(dg * t**3, t)
    if not (a > 0.0 and m1 > 0.0 and m3 > 0.0):
        return HERTZ_SECOND_MOMENT
    return float(m3 / (2.0 * a * a * m1))


def _load_curve(t: np.ndarray, slope: np.ndarray) -> np.ndarray:
    """P(x) / P(a) at the radii t (from 0 to a) for the gap of revolution of this slope."""
    f = _g_slope(t, slope) * t
    load = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(t))])
    return load / load[-1] if load[-1] > 0.0 else (t / t[-1]) ** 3


def axis_stick_ratio(t: np.ndarray, slope: np.ndarray, fraction: float, hertz_slope: np.ndarray | None = None) -> float:
    """c / a with P(c) / P(a) = ``fraction`` for the gap of revolution of this slope (radii t
    from 0 to a), less the same reading's error on Hertz's gap (``hertz_slope``, default t),
    whose answer is the cube root."""
    fraction = min(max(fraction, 0.0), 1.0)
    own = np.interp(fraction, _load_curve(t, slope), t / t[-1])
    hertz = np.interp(fraction, _load_curve(t, t if hertz_slope is None else hertz_slope), t / t[-1])
    return float(min(max(fraction ** (1.0 / 3.0) + own - hertz, 0.0), 1.0))


def stick_ratio_targets(s: np.ndarray, gap: np.ndarray, axis: np.ndarray, semi_axes, fraction: float) -> float:
    """The stick ratio c / a with P(c) / P(a) = ``fraction`` (= 1 - Q / (mu N)) for the gap along
    the axes (the mean of the two axes' readings; Mindlin's cube root where neither axis's samples
    reach the region's edge)."""
    ratios = [axis_stick_ratio(t, slope, fraction, quadratic)
              for t, slope, quadratic in filter(None, _axis_profiles(s, gap, axis, semi_axes))]
    return float(np.mean(ratios)) if ratios else min(max(fraction, 0.0), 1.0) ** (1.0 / 3.0)


def _axis_profiles(s: np.ndarray, gap: np.ndarray, axis: np.ndarray, semi_axes) -> list:
    """Per axis k, :func:`_profile_slope` of the samples on it to the semi-axis (None where they
    are too few or do not reach)."""
    out = []
    for k, reach in enumerate(semi_axes):
        on = axis == k
        out.append(_profile_slope(s[on, k], gap[on], float(reach)) if on.sum() > 2 and reach > 0.0 else None)
    return out


def _profile_slope(s: np.ndarray, gap: np.ndarray, reach: float):
    """(radii, slope, quadratic's slope) of the axis's gap on [0, reach]: the even part where
    both sides are sampled that far, else the longer side; and the same of the quadratic
    kappa s^2 / 2 fitted to it, sampled at the same points and read the same way (a quadratic
    gap's two readings are then equal, whatever the samples' spacing). None where neither side
    reaches."""
    order = np.argsort(s)
    s, gap = s[order], gap[order]
    if s[0] > 0.0 or s[-1] < 0.0:
        return None
    sides = [side for side, ok in ((1.0, s[-1] >= reach), (-1.0, s[0] <= -reach)) if ok]
    if not sides:
        return None
    t = np.linspace(0.0, reach, PROFILE_POINTS)
    near = np.abs(s) <= reach
    kappa = 2.0 * float(gap[near] @ s[near] ** 2) / (float(np.sum(s[near] ** 4)) or 1.0)
    slopes = []
    for values in (gap, 0.5 * kappa * s * s):
        f = np.mean([np.interp(side * t, s, values) for side in sides], axis=0)
        slopes.append(np.gradient(f, t))
    return t, slopes[0], slopes[1]


def second_moment_targets(s: np.ndarray, gap: np.ndarray, axis: np.ndarray, semi_axes) -> tuple[float, float]:
    """<X^2> and <Y^2> the gap implies for the ellipse of ``semi_axes`` about the contact point:
    s (n, 2) the axis samples' tangent-plane coordinates from the contact point, ``gap`` (n,) the
    bodies' initial gap there, ``axis`` (n,) 0 or 1 the axis each lies on. Hertz's 1/5 where an
    axis's samples do not reach its semi-axis."""
    out = []
    for profile in _axis_profiles(s, gap, axis, semi_axes):
        if profile is None:
            out.append(HERTZ_SECOND_MOMENT)
            continue
        t, slope, quadratic = profile
        # less the same reading of the fitted quadratic: a quadratic gap gives 1/5 to round-off,
        # not to the samples' interpolation and the quadrature's error (2e-6 to 5e-6)
        out.append(HERTZ_SECOND_MOMENT + axis_second_moment(t, slope) - axis_second_moment(t, quadratic))
    return out[0], out[1]
