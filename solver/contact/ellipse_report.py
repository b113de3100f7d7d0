"""The summary.json contact block of a contact between solids: the frame, the semi-axes, the
forces, and the pressure and shear along both axes.

The band traction at the quadrature points oscillates from cell to cell (trilinear fields) while
its integrals are accurate; the profiles written are its weighted least-squares fit by
sqrt(1 - X^2 - Y^2) times a quadratic in (X, Y) = (s0 / a, s1 / b) (Hertz's pressure is the
constant term), evaluated along the axes and clipped to compression. A half or quarter model's
points are fitted with their mirror images in its symmetry planes (the sector's boundary lines
around the contact point): on the model's part alone the odd terms (X, Y, XY) are nearly
indistinguishable from the even ones over a quadrant and take up the traction's scatter (measured
on the quarter sphere on a flat: X and Y terms of -8 % of the constant term, the peak 1.7 % above
Hertz's on the finest grids and moving away from it with refinement).

The shear of a partial-slip contact follows the structure of its solution: in the slip zone it
is the friction traction -mu p d (d the slip direction) of the fitted pressure; inside the stick
ellipse (radius ratio c) the difference of the traction from that is fitted by
sqrt(1 - (X^2 + Y^2) / c^2) times a quadratic (Cattaneo-Mindlin's correction is its constant
term), and vanishes at the stick edge. A tied contact's shear takes the pressure's basis.

The peak pressure of a region whose pressure is Hertz-like is read by Hertz's shape alone,
p0 sqrt(1 - X^2 - Y^2), fitted over the region's inner part X^2 + Y^2 < 0.64, clear of the
edge's cells: there the pressure is smooth, while the cells holding the edge interpolate a
pressure falling like the root of the distance to it, and a quadratic fitted over the whole
region carries their error into its centre value. The profile's other terms are then the
least-squares fit of the rest over the whole region, so that the profile's centre value is that
p0. Measured on the quarter sphere on a flat against Hertz's p0 for the computed force, finest
cells 3.9 and 2.0 mm (a / h 11.6 and 23): the whole-region fit read -0.776 % and -0.236 %,
Hertz's shape over the inner part +0.387 % and +0.078 %. The region is Hertz-like when a
quadratic fitted over the same inner part explains little more than Hertz's shape alone: the
part of the shape fit's RMS residual the quadratic removes (a smooth departure from the shape;
the traction's cell-to-cell scatter is in both) is at most HERTZ_LIKE_MISFIT of p0. Otherwise
(a flattened or hollow pressure, too few points inside) the profile is the whole-region fit, as
before, and the peak its largest value along the axes."""

from __future__ import annotations

import numpy as np

from .ellipse_geometry import sector_share

__all__ = ["HERTZ_LIKE_MISFIT", "PEAK_INNER", "ellipse_block", "fit_profile", "peak_reading", "symmetry_reflections"]

#: the peak pressure is read over the region's inner part X^2 + Y^2 < PEAK_INNER^2
PEAK_INNER = 0.8
#: the largest smooth departure of the inner pressure from Hertz's shape (the RMS by which the
#: quadratic's fit improves on the shape's, relative to p0) for the peak to be read by the shape.
#: Measured on the sphere on a flat: 0.27, 0.19 and 0.04 % at a / h 5.8, 11.6 and 23 (the shape's
#: reading within 1.1, 0.39 and 0.06 % of Hertz's p0); 4.9 % at a / h 2.8 (the shape read +7.9 %,
#: the whole-region fit +1.8 %); 1.97 % on its scene turned by 25 degrees at a / h 5.8 (a quadratic
#: flattening of 5 % of p0; the shape read +1.9 %, the whole-region fit -1.8 %)
HERTZ_LIKE_MISFIT = 0.01
#: fewest quadrature points in the inner part (with their mirror images) for the shape's fit
PEAK_MIN_POINTS = 24


def _basis(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    root = np.sqrt(np.clip(1.0 - X**2 - Y**2, 0.0, None))
    return root[:, None] * np.stack([np.ones_like(X), X, Y, X**2, X * Y, Y**2], axis=1)


def fit_profile(X: np.ndarray, Y: np.ndarray, weights: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Coefficients of the weighted least-squares fit of ``values`` at (X, Y) by _basis."""
    b = _basis(X, Y)
    w = np.sqrt(np.maximum(weights, 0.0))
    coef, *_ = np.linalg.lstsq(b * w[:, None], values * w, rcond=None)
    return coef


def peak_reading(X: np.ndarray, Y: np.ndarray, weights: np.ndarray, values: np.ndarray) -> dict:
    """The pressure profile's coefficients (of _basis) and how its centre value, the peak, was read
    (module docstring): ``reading`` "hertz_shape_inner" (the constant term is Hertz's shape fitted
    over X^2 + Y^2 < PEAK_INNER^2, the other terms the least-squares fit of the rest over the whole
    region) or "whole_region_fit" (the plain fit_profile), with ``misfit`` (the smooth departure
    from Hertz's shape over the inner part, relative to p0; None with too few points),
    ``residual`` (the shape fit's weighted RMS residual there, cell-to-cell scatter included)
    and ``hertz_shape`` (that fit's p0, also where it is not taken: a finer grid's estimate
    compares its own such reading with it)."""
    coef = fit_profile(X, Y, weights, values)
    inner = X**2 + Y**2 < PEAK_INNER**2
    out = {"reading": "whole_region_fit", "inner": PEAK_INNER, "misfit": None, "residual": None, "hertz_shape": None,
           "coefficients": coef}
    w = np.maximum(weights[inner], 0.0)
    if inner.sum() < PEAK_MIN_POINTS or not w.sum() > 0.0:
        return out
    root = np.sqrt(1.0 - X[inner] ** 2 - Y[inner] ** 2)
    p0 = float((w * root) @ values[inner] / ((w * root) @ root))
    if not p0 > 0.0:
        return out
    shape_rms = float(np.sqrt(w @ (values[inner] - p0 * root) ** 2 / w.sum()))
    quadratic = _basis(X[inner], Y[inner]) @ fit_profile(X[inner], Y[inner], weights[inner], values[inner])
    quadratic_rms = float(np.sqrt(w @ (values[inner] - quadratic) ** 2 / w.sum()))
    misfit = float(np.sqrt(max(shape_rms**2 - quadratic_rms**2, 0.0))) / p0
    out.update(misfit=misfit, residual=shape_rms / p0, hertz_shape=p0)
    if misfit > HERTZ_LIKE_MISFIT:
        return out
    rest = values - p0 * np.sqrt(np.clip(1.0 - X**2 - Y**2, 0.0, None))
    sw = np.sqrt(np.maximum(weights, 0.0))
    higher, *_ = np.linalg.lstsq(_basis(X, Y)[:, 1:] * sw[:, None], rest * sw, rcond=None)
    out.update(reading="hertz_shape_inner", coefficients=np.concatenate([[p0], higher]))
    return out


def ellipse_block(c, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
    aa, bb = c.semi_axes(a)
    frame = c.frame
    out = {"bodies": list(c.model.bodies), "type": c.kind, "friction": float(getattr(c.model, "friction", 0.0) or 0.0),
           "point": frame.point.tolist(), "normal": frame.normal.tolist(), "axes": frame.axes.tolist(),
           "semi_axes": [float(aa), float(bb)],
           # the final grid's resolution of the region: each semi-axis over the finest cell there
           "cells_per_semi_axis": [float(aa / c.h), float(bb / c.h)],
           # the ellipse's centre from the contact point along the axes (the pressure's centroid)
           "region_centre": [float(v) for v in c.centre],
           "stick_semi_axes": [float(min(c.stick_ratio, 1.0) * aa), float(min(c.stick_ratio, 1.0) * bb)],
           # the share of the whole contact the model holds: the angle of body 1's sectors around
           # the contact point over 2 pi (a quarter model cut by two symmetry planes: 0.25)
           "model_share": sector_share(c.ranges),
           "normal_force": float(-on2 @ frame.normal),
           "tangential_force": [float(on2 @ frame.axes[0]), float(on2 @ frame.axes[1])],
           "pressure": {}, "shear": {}}
    if c.given_point is not None:  # the frame sits at the touching point nearest the scene's point
        out["given_point"] = c.given_point.tolist()
    if info is None or a <= 0.0:
        for key in ("pressure", "shear"):
            out[key] = {f"axis{k}": {"s": [], "value": []} for k in (0, 1)}
        return out
    pts = info[0]
    t1 = c.quadrature_traction(info, u[c.dofs])
    local = c.local(pts.s)
    X, Y = local[:, 0] / aa, local[:, 1] / bb
    p = np.einsum("qi,qi->q", t1, pts.normal)
    images = [local] + [local @ m.T for m in symmetry_reflections(c.ranges)]
    whole = np.concatenate(images)
    k = len(images)
    peak = peak_reading(whole[:, 0] / aa, whole[:, 1] / bb, np.tile(pts.weights, k), np.tile(p, k))
    fit_p = peak["coefficients"]
    shear_at = _shear_profiles(c, X, Y, pts.weights, t1, fit_p)
    for k, reach in ((0, aa), (1, bb)):  # along the axis through the ellipse's centre, s from the contact point
        s = c.centre[k] + np.linspace(-1.25 * reach, 1.25 * reach, 201)
        present = c.on_body1(k, s) if not np.any(c.centre) else np.ones(len(s), bool)
        XY = np.zeros((len(s), 2))
        XY[:, k] = (s - c.centre[k]) / reach
        pressure = np.clip(_basis(XY[:, 0], XY[:, 1]) @ fit_p, 0.0, None)
        shear = shear_at(k, XY[:, 0], XY[:, 1])
        out["pressure"][f"axis{k}"] = {"s": s[present].tolist(), "value": pressure[present].tolist()}
        out["shear"][f"axis{k}"] = {"s": s[present].tolist(), "value": shear[present].tolist()}
    out["relative_curvatures"] = [float(k) for k in frame.curvatures]
    out["gap_at_edge_over_quadratic"] = gap_at_edge_over_quadratic(c, (aa, bb))
    out["profile_recovery"] = {"method": "least squares on sqrt(1 - X^2 - Y^2) x [1, X, Y, X^2, XY, Y^2]"
                               + (", the constant term Hertz's shape fitted over the inner part"
                                  if peak["reading"] == "hertz_shape_inner" else ""),
                               "shear": "slip zone: -mu p d; stick zone: + sqrt(1 - R^2 / c^2) x quadratic"
                               if _partial_slip(c) else "as the pressure",
                               "pressure_coefficients": fit_p.tolist(),
                               "peak": {key: value for key, value in peak.items() if key != "coefficients"},
                               "quadrature_points": int(len(p))}
    return out


def gap_at_edge_over_quadratic(c, reach: tuple[float, float]) -> list[float]:
    """Per axis, the bodies' initial gap where the region's edge crosses it, over the gap the
    contact point's curvatures give there (kappa s^2 / 2, Hertz's model): the end of the axis
    farther from 1. Near 1 where the gap is quadratic across the region (a ball: 1 + (a / R)^2 / 4);
    far from it at a cone's apex or a vertex (a 10-degree cone: about 0.004), where the region is
    not Hertzian and its size follows the gap's own profile (solver.contact.gap_moments). nan
    where the axis samples do not reach the edge."""
    s, gap = c.initial_sample_gap()  # from the contact point, where the curvatures are taken
    out = []
    for k, (r, kappa) in enumerate(zip(reach, c.frame.curvatures)):
        on = c.sample_axis == k
        if on.sum() < 2 or not (kappa > 0.0 and r > 0.0):
            out.append(float("nan"))
            continue
        order = np.argsort(s[on, k])
        sk, gk = s[on, k][order], gap[on][order]
        ratios = [float(np.interp(e, sk, gk)) / (0.5 * kappa * e * e)
                  for e in (c.centre[k] - r, c.centre[k] + r) if sk[0] <= e <= sk[-1] and e != 0.0]
        out.append(max(ratios, key=lambda v: abs(np.log(v)) if v > 0.0 else np.inf) if ratios else float("nan"))
    return out


def _reflection(theta: float) -> np.ndarray:
    """The reflection of the tangent plane in the line through the contact point at angle theta."""
    c2, s2 = np.cos(2.0 * theta), np.sin(2.0 * theta)
    return np.array([[c2, s2], [s2, -c2]])


def symmetry_reflections(ranges: list[tuple[float, float]]) -> list[np.ndarray]:
    """The maps (2, 2) taking a half or quarter model's part of the contact to the rest of it:
    reflections in the symmetry lines that bound body 1's angular range around the contact point
    (a half model: one line; a quarter: two at right angles, and their product). Empty for a
    whole model or any other sector."""
    share = sector_share(ranges)
    ends = [t for r in ranges for t in r]
    if 0.0 in ends and 2.0 * np.pi in ends:  # a range across angle 0: that is no boundary
        ends = [t for t in ends if t not in (0.0, 2.0 * np.pi)]
    if abs(share - 0.5) < 1e-6 and ends:
        return [_reflection(ends[0])]
    if abs(share - 0.25) < 1e-6 and len(ends) == 2:
        first, second = _reflection(ends[0]), _reflection(ends[1])
        return [first, second, first @ second]
    return []


def _partial_slip(c) -> bool:
    return c.kind == "frictional" and c.slip_direction is not None and 0.0 < c.stick_ratio < 1.0


def _shear_profiles(c, X: np.ndarray, Y: np.ndarray, weights: np.ndarray, t1: np.ndarray, fit_p: np.ndarray):
    """``shear(k, X, Y)``: the fitted shear component along axis k at normalised points."""
    axes = c.frame.axes
    if c.kind == "frictionless":
        return lambda k, Xs, Ys: np.zeros(len(Xs))
    if not _partial_slip(c):  # tied, or all stuck / all sliding: the pressure's basis
        fits = [fit_profile(X, Y, weights, t1 @ axes[k]) for k in (0, 1)]
        return lambda k, Xs, Ys: _basis(Xs, Ys) @ fits[k]
    ratio, d = c.stick_ratio, c.slip_direction
    slip_part = -c.friction * np.clip(_basis(X, Y) @ fit_p, 0.0, None)
    stuck = np.hypot(X, Y) < ratio
    fits = []
    for k in (0, 1):
        residual = t1[stuck] @ axes[k] - slip_part[stuck] * float(d @ axes[k])
        fits.append(fit_profile(X[stuck] / ratio, Y[stuck] / ratio, weights[stuck], residual)
                    if stuck.sum() >= 6 else np.zeros(6))

    def shear(k: int, Xs: np.ndarray, Ys: np.ndarray) -> np.ndarray:
        slip = -c.friction * np.clip(_basis(Xs, Ys) @ fit_p, 0.0, None) * float(d @ axes[k])
        return slip + _basis(Xs / ratio, Ys / ratio) @ fits[k]

    return shear
