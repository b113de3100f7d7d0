"""Error estimates of a contact result from a second solution on a grid twice as coarse
(Richardson extrapolation, e.g. Roache, Verification and Validation in Computational Science
and Engineering, 1998, ch. 5): a quantity q that converges like q_h = q + C h^p has the error

    q_h - q = (q_h - q_2h) / (2^p - 1)

on the finer grid. In 2D the sizes also have a third grid, 4 times as coarse, which gives them
their observed order and sees through two grids that agree by chance (:func:`three_grid_error`). The orders p are those of bilinear / trilinear elements where the fields are
smooth, and of the contact's edge where they are not:

- 2 for the normal force (a reaction: an integral of the stresses, superconvergent like the
  energy), the 2D peak pressure (the traction in the region's smooth interior) and the largest
  von Mises stress (the recovered stresses, below the surface where the field is smooth);
- 3/2 for the 3D peak pressure where it is the centre value of a fit over the whole computed
  region, which converges with the region's edge; 2 where it is read by Hertz's shape over the
  region's inner part (clear of the edge's cells; what it takes from the edge, through the
  semi-axes that scale its basis, is the size floor below);
- 3/2 for the contact's sizes (half widths, semi-axes, stick sizes): they are where the pressure's
  end values vanish, and the end values are moments of the pressure, which falls like
  sqrt(a - x) at the edge: the cell containing the edge interpolates it with an error of
  O(h^(1/2)) of the peak pressure over a length h, so the moments and the edge err by O(h^(3/2))
  (the smooth rest by O(h^2)).

Each estimate is relative, |q_h - q_2h| / ((2^p - 1) |q_h|). The peak pressure is read from a
profile whose support is the computed region, and a region's force is fixed by the bodies'
equilibrium: p0 scales like N / a in 2D and N / (a b) in 3D, so the region's own size error
passes into p0 once per in-plane dimension. Its estimate is the larger of its own Richardson
estimate and the sum of the sizes' (half_width; both semi_axes): with the two-grid estimate alone
the 3D p0 was estimated at 0.14 % where it erred by 0.8 % against Hertz's (its own grid pair
differs little while a still converges). A 3D peak read by Hertz's shape over the region's inner
part (solver.contact.ellipse_report) takes half that sum, the semi-axes' mean
(HERTZ_SHAPE_PEAK_SIZE_SHARE). Its own Richardson estimate needs the coarser grid to read p0 the
same way: where that grid's inner pressure fails the Hertz-like test (its inner part reaches into
the cells holding the edge, or the cells' scatter is not averaged out: a / h below about 5), its
inner reading moves with which cells it takes in, not with h (the partial-slip sphere on a flat's
grid twice as coarse, a / h 2.9: +6.9 % from Hertz's p0 over X^2 + Y^2 < 0.64, -4.3 % to +11 %
over inner radii 0.3 to 0.9 a, where the grid read +1.1 %), and the estimate is the semi-axes'
mean alone, the share of p0's error the sizes carry: on grids that pass the test p0 erred by
0.9-1.2 times the semi-axes' mean error (the sphere on a flat, a / h 5.8-23). Measured against
exact theory on the shipped examples (docs/accuracy.md).

Pure functions on the summary's contact blocks: the solves are the caller's."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

__all__ = ["complementary_energy_density", "far_field_force_error", "HERTZ_SHAPE_PEAK_SIZE_SHARE", "ORDERS", "peak_size_share", "WARN_ABOVE", "SIZE_ORDER_RANGE", "contact_quantities", "has_complete_end", "observed_order",
           "orders_for", "relative_errors", "largest_error", "three_grid_error", "refinement_ratio", "TARGET_SHARE",
           "RATIO_RANGE", "size_orders"]

#: convergence order of each quantity on Q1 elements
ORDERS = {"half_width": 1.5, "stick_half_width": 1.5, "semi_axes": 1.5, "stick_semi_axes": 1.5,
          "normal_force": 2.0, "max_pressure": 2.0, "max_von_mises": 2.0}
#: runs without an accuracy target warn above this estimated relative error
WARN_ABOVE = 0.01
#: the sizes' order of a 2D region with a complete end (at a corner of body 1) when the run has
#: only two grids: the corner's stress is square-root singular, and the energy error of such a
#: field falls only like h^(1/2) (e.g. Strang and Fix, An Analysis of the Finite Element Method,
#: 1973, ch. 8), the safe order of what it governs. Measured on the tilted flat punch
#: (examples/contact2d/tilted_punch.toml, the contact zones 1 level coarser, as shipped, 1 and 2
#: finer): half widths 4.92736, 4.96491, 4.98959, 5.00348 mm, observed orders 0.60 and 0.83; the
#: earlier order 1 estimated the shipped grid's error at 0.58 % where it was 1.22 % from Johnson's
#: closed form for the computed force (order 1/2: 2.22 % against 1.31 %, docs/accuracy.md). The peak pressure is the corner's singular value, which
#: grows under refinement instead of converging: it gets no estimate
COMPLETE_END_SIZE_ORDER = 0.5
#: the range of an observed order (three grids) taken for a complete end's sizes: up to 1, the
#: order at which the tilted punch's error against Johnson's closed form halves per level; its
#: scene's grid and the grids 2 and 4 times as coarse show 1.19 (half widths 4.9606, 4.9150,
#: 4.8108 mm), which taken as it is estimated 0.72 % where the error is 1.31 %; carried down at
#: order 1 the coarser pair's difference gives 1.05 %
COMPLETE_END_ORDER_RANGE = (0.5, 1.0)
#: the peak pressure's order in 3D: there p0 is the centre value of a fit over the computed
#: region, so it converges with the region's edge (3/2) rather than with the smooth interior (2).
#: Measured on the sphere on a flat: p0 -0.776 % from Hertz's on the shipped grid (a/h 11.6) and
#: -0.255 % one level deeper around the region, a ratio of 3.04 (observed order 1.6); with order
#: 2 the two-grid estimate was 0.18 %, below the true 0.255 %
SOLID_PEAK_PRESSURE_ORDER = 1.5
#: the range of an observed order (three grids) taken for the sizes of a region whose ends are
#: incomplete: the nominal 3/2 widened by 1/2 on either side. Measured on the rounded flat
#: punch and the pin in a bore against fitted-mesh solutions of the same bodies (docs/accuracy.md):
#: observed orders 1.2 and 2.2 on the examples' grid and the grids 2 and 4 times as coarse
SIZE_ORDER_RANGE = (1.0, 2.0)
#: the share of the region's size error (the sum of both semi-axes' relative errors) taken into
#: the estimate of a 3D peak pressure read by Hertz's shape over the region's inner part: that
#: fit's basis is scaled by the computed semi-axes, and for Hertz's pressure a relative error e of
#: both semi-axes moves it by about -0.47 e (least squares over X^2 + Y^2 < 0.64: the integral of
#: X^2 over that of 1 - X^2), a quarter of the sum; half of it is taken, the semi-axes' mean.
#: Measured on the sphere on a flat (finest cells 3.9 and 2.0 mm): semi-axes -0.331 % and
#: -0.087 %, that reading +0.387 % and +0.078 % from Hertz's p0 for the computed force
HERTZ_SHAPE_PEAK_SIZE_SHARE = 0.5
_SIZES = ("half_width", "stick_half_width", "semi_axes", "stick_semi_axes")


def orders_for(block: Mapping[str, Any], observed: float | None = None) -> dict[str, float | None]:
    """The convergence order of each quantity of a contact block: ORDERS, except for the peak
    pressure of a 3D region read over the whole region (SOLID_PEAK_PRESSURE_ORDER; read by
    Hertz's shape over the inner part it keeps the interior's order 2, the edge's share being the
    size floor of :func:`relative_errors`) and for a 2D region with a complete end
    (``ends`` of type "complete"), whose sizes take the order ``observed`` on the run's own grids
    (:func:`observed_order`) or else COMPLETE_END_SIZE_ORDER, and whose peak pressure (singular)
    has none (None: not estimated)."""
    if block.get("semi_axes") is not None:
        interior = peak_size_share(block) == HERTZ_SHAPE_PEAK_SIZE_SHARE  # read clear of the edge
        return {**ORDERS, "max_pressure": ORDERS["max_pressure"] if interior else SOLID_PEAK_PRESSURE_ORDER}
    if not has_complete_end(block):
        return dict(ORDERS)
    size_order = COMPLETE_END_SIZE_ORDER if observed is None else observed
    return {**ORDERS, **{k: size_order for k in _SIZES}, "max_pressure": None}


def peak_size_share(block: Mapping[str, Any]) -> float:
    """The share of the region's size error (:func:`relative_errors`) the peak pressure of a
    contact block takes: HERTZ_SHAPE_PEAK_SIZE_SHARE where its profile's peak was read by Hertz's
    shape over the inner part (``profile_recovery.peak.reading``), else 1."""
    peak = (block.get("profile_recovery") or {}).get("peak") or {}
    return HERTZ_SHAPE_PEAK_SIZE_SHARE if peak.get("reading") == "hertz_shape_inner" else 1.0


def has_complete_end(block: Mapping[str, Any]) -> bool:
    """Whether a 2D contact block's region ends at a corner of body 1 (an end of type "complete")."""
    return any(isinstance(e, Mapping) and e.get("type") == "complete" for e in block.get("ends") or [])


def observed_order(fine: float, coarse: float, coarsest: float,
                   bounds: tuple[float, float] = COMPLETE_END_ORDER_RANGE,
                   ratios: tuple[float, float] = (2.0, 2.0)) -> float | None:
    """The observed order log2(|q_2h - q_4h| / |q_h - q_2h|) of a quantity on three grids, each
    twice as fine as the one before (with ``ratios`` r1, r2 between them: the p whose
    r1^p (r2^p - 1) / (r1^p - 1) is that quotient), clamped to ``bounds``; None when the two
    differences do not have one sign (the grids are not yet in the range where q_h = q + C h^p)
    or vanish."""
    d_fine, d_coarse = fine - coarse, coarse - coarsest
    values = (fine, coarse, coarsest)
    if not all(math.isfinite(v) for v in values) or d_fine * d_coarse <= 0.0:
        return None
    quotient, (lo, hi) = d_coarse / d_fine, bounds
    if quotient <= _difference_ratio(lo, ratios):
        return float(lo)
    if quotient >= _difference_ratio(hi, ratios):
        return float(hi)
    return float(_order_between(quotient, ratios, lo, hi))


def _profile_max(profile: Any) -> float:
    """The largest value of a pressure profile ({"s", "value"} in 2D, one per axis in 3D)."""
    if not isinstance(profile, Mapping):
        return math.nan
    parts = [profile] if "value" in profile else [p for p in profile.values() if isinstance(p, Mapping)]
    values = [np.asarray(p.get("value") or [], dtype=float) for p in parts]
    values = [v[np.isfinite(v)] for v in values]
    return max((float(v.max()) for v in values if len(v)), default=math.nan)


def contact_quantities(block: Mapping[str, Any], like: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The estimated quantities of one contact block: sizes (2D half widths, 3D semi-axes as a
    list), the normal force, the peak pressure (``max_pressure``) and ``max_von_mises`` where
    the block has it. A frictionless contact has no stick size; a zero size is left out. With
    ``like`` (the finer grid's block of the same contact) the peak must be read as there, so that
    Richardson's difference compares one reading on two grids: where that block's peak is Hertz's
    shape over the inner part and this block's own inner part failed the Hertz-like test
    (solver.contact.ellipse_report: its profile kept the whole-region fit), ``max_pressure`` is
    None, a peak without a comparable reading on this grid (:func:`relative_errors`)."""
    out: dict[str, Any] = {}
    for key in ("half_width", "stick_half_width", "semi_axes", "stick_semi_axes", "normal_force", "max_von_mises"):
        value = block.get(key)
        if value is None:
            continue
        if isinstance(value, (list, tuple)):
            value = [float(v) if v is not None else math.nan for v in value]
            if all(v > 0.0 for v in value):
                out[key] = value
        elif float(value) != 0.0 and math.isfinite(float(value)):
            out[key] = float(value)
    if block.get("type") in ("frictionless", "tied"):  # no stick zone of its own
        out.pop("stick_half_width", None)
        out.pop("stick_semi_axes", None)
    p0 = _profile_max(block.get("pressure"))
    if like is not None and peak_size_share(like) == HERTZ_SHAPE_PEAK_SIZE_SHARE and p0 > 0.0:
        if peak_size_share(block) != HERTZ_SHAPE_PEAK_SIZE_SHARE:  # its inner pressure is not resolved
            out["max_pressure"] = None
            return out
        p0 = float(block["profile_recovery"]["peak"].get("hertz_shape") or p0)  # the centre value, as read
    if p0 > 0.0:
        out["max_pressure"] = p0
    return out


def _relative(fine: float, coarse: float, order: float, ratio: float = 2.0) -> float:
    """Richardson's |q_h - q_rh| / ((r^p - 1) |q_h|) for grids whose cells differ by ``ratio`` r."""
    if not (math.isfinite(fine) and math.isfinite(coarse)) or fine == 0.0:
        return math.nan
    return abs(fine - coarse) / ((ratio ** order - 1.0) * abs(fine))


def _difference_ratio(p: float, ratios: tuple[float, float]) -> float:
    """(q_r1r2h - q_r1h) / (q_r1h - q_h) of q_h = q + C h^p: r1^p (r2^p - 1) / (r1^p - 1)."""
    r1, r2 = ratios
    return r1 ** p * (r2 ** p - 1.0) / (r1 ** p - 1.0)


def _order_between(big_over_d: float, ratios: tuple[float, float], lo: float, hi: float) -> float:
    """The order p in [lo, hi] whose :func:`_difference_ratio` is ``big_over_d`` (it grows with p),
    by bisection (log2 of it where both ratios are 2); ``big_over_d`` lies between its values at lo
    and hi."""
    if ratios == (2.0, 2.0):
        return math.log2(big_over_d)
    a, b = lo, hi
    for _ in range(50):
        m = 0.5 * (a + b)
        a, b = (m, b) if _difference_ratio(m, ratios) < big_over_d else (a, m)
    return 0.5 * (a + b)


def three_grid_error(fine: float, coarse: float, coarsest: float, order: float,
                     bounds: tuple[float, float] = SIZE_ORDER_RANGE, ratios: tuple[float, float] = (2.0, 2.0)) -> float:
    """Estimated relative error of a quantity on the finest of three grids, each twice as fine as
    the one before (or finer by ``ratios`` = (r1, r2): the finest's cells r1 times smaller than the
    middle grid's, those r2 times smaller than the coarsest's), with d = q_h - q_r1h and
    D = q_r1h - q_r1r2h:

    - d and D of one sign, observed order p within ``bounds`` (D / d = 2^p, or in general
      r1^p (r2^p - 1) / (r1^p - 1)): Richardson's |d| / ((r1^p - 1) |q_h|);
    - p above the range (d smaller than the coarser pair predicts): D carried down to the finest
      grid at the range's fastest order P, |D| / ((r2^P - 1) r1^P |q_h|);
    - p below it: |d| / ((r1^P - 1) |q_h|) with its slowest order;
    - opposite signs (the grids' positions scatter the value as much as refining moves it): the
      larger of the two-grid estimate with the nominal ``order`` and D carried down at it.

    Two grids alone cannot tell a converged value from two scattered ones that happen to agree:
    the half rounded punch's width agreed on its grid and the one twice as coarse to 1e-7 m, a
    two-grid estimate of 5e-6 where its error was about 8e-5; D, 6e-6 m, gives 7.9e-5."""
    values = (fine, coarse, coarsest)
    if not all(math.isfinite(v) for v in values) or fine == 0.0:
        return math.nan
    d, big = fine - coarse, coarse - coarsest
    lo, hi = bounds
    r1, r2 = ratios
    if d * big > 0.0:
        if big / d > _difference_ratio(hi, ratios):
            return abs(big) / ((r2 ** hi - 1.0) * r1 ** hi * abs(fine))
        p = lo if big / d <= _difference_ratio(lo, ratios) else _order_between(big / d, ratios, lo, hi)
        return abs(d) / ((r1 ** p - 1.0) * abs(fine))
    return max(_relative(fine, coarse, order, r1), abs(big) / ((r2 ** order - 1.0) * r1 ** order * abs(fine)))


def relative_errors(fine: Mapping[str, Any], coarse: Mapping[str, Any],
                    orders: Mapping[str, float | None] | None = None, coarsest: Mapping[str, Any] | None = None,
                    order_range: tuple[float, float] = SIZE_ORDER_RANGE, size_share: float = 1.0,
                    ratios: tuple[float, float] = (2.0, 2.0)) -> dict[str, Any]:
    """Estimated relative error of each quantity present in both (lists element by element), with
    the convergence ``orders`` (default ORDERS; see :func:`orders_for`); a quantity the coarse
    solution lacks (no stick zone there) or without an order is None. ``ratios``: how many times
    smaller the fine grid's cells are than the coarse grid's, and those than the coarsest's (2
    and 2 unless an accuracy ladder chose otherwise). With ``coarsest`` (the
    quantities on a third grid, coarser again) the sizes take :func:`three_grid_error`
    with observed orders in ``order_range``. The peak pressure's estimate is at least
    ``size_share`` times the region's size error (:func:`peak_size_share`), and only that where
    the coarse quantities hold ``max_pressure`` None (no comparable reading on the coarser grid:
    :func:`contact_quantities` with ``like``). In 3D, where the peak is not read by Hertz's shape
    (``size_share`` not HERTZ_SHAPE_PEAK_SIZE_SHARE), the largest von Mises stress's estimate is
    at least the peak pressure's."""
    out: dict[str, Any] = {}
    orders = ORDERS if orders is None else orders
    for key, value in fine.items():
        other = coarse.get(key)
        order = orders.get(key)
        third = coarsest.get(key) if coarsest is not None and key in _SIZES else None
        if other is None or order is None:
            out[key] = None
        elif third is not None:
            triples = zip(value, other, third) if isinstance(value, list) else [(value, other, third)]
            errors = [three_grid_error(float(f), float(c), float(t), order, order_range, ratios) for f, c, t in triples]
            out[key] = errors if isinstance(value, list) else errors[0]
        elif isinstance(value, list):
            out[key] = [_relative(f, c, order, ratios[0]) for f, c in zip(value, other)]
        else:
            out[key] = _relative(value, float(other), order, ratios[0])
    unresolved = fine.get("max_pressure") is not None and "max_pressure" in coarse and coarse["max_pressure"] is None
    if out.get("max_pressure") is not None or unresolved:
        out["max_pressure"] = max(out["max_pressure"] or 0.0, size_share * _size_error(out))
    if "semi_axes" in fine and size_share != HERTZ_SHAPE_PEAK_SIZE_SHARE \
            and out.get("max_von_mises") is not None and out.get("max_pressure") is not None:
        # a 3D region whose pressure is not Hertz-like on this grid (too few cells for the inner
        # reading): the stress below it scales with p0 and takes at least p0's estimate (the
        # turned sphere on a flat at a / h 5.8 and 2.9: von Mises -5.4 % and -8.8 % from Hertz's,
        # a difference that at order 2 estimated 1.07 %)
        out["max_von_mises"] = max(out["max_von_mises"], out["max_pressure"])
    return out


#: an accuracy ladder's next rung aims every estimated error at this share of the target: the
#: estimate, scaled by the cells' ratio to the power of its order, lands within that margin below
#: the target, so that one rung reaches it although the estimate of the next rung scatters about
#: that prediction (its grid's cut cells lie elsewhere)
TARGET_SHARE = 0.9
#: the range of a rung's refinement ratio (how many times smaller its cells are than the rung
#: before): at least 1.25, below which Richardson's denominator r^p - 1 (0.56 at order 2) would
#: magnify the grids' scatter into the estimate; at most 2, one octree / quadtree level
RATIO_RANGE = (1.25, 2.0)


def size_orders(fine: Mapping[str, Any], coarse: Mapping[str, Any], coarsest: Mapping[str, Any],
                bounds: tuple[float, float] = SIZE_ORDER_RANGE, ratios: tuple[float, float] = (2.0, 2.0)) -> dict[str, float]:
    """The observed order of each size (:func:`observed_order` within ``bounds``; of a list the
    slowest element's) of the quantities on three grids (:func:`contact_quantities`), where its
    two differences have one sign."""
    out = {}
    for key in _SIZES:
        if not all(isinstance(q.get(key), (float, list)) for q in (fine, coarse, coarsest)):
            continue
        triples = zip(*(q[key] if isinstance(q[key], list) else [q[key]] for q in (fine, coarse, coarsest)))
        orders = [observed_order(float(f), float(c), float(t), bounds, ratios) for f, c, t in triples]
        if orders and all(o is not None for o in orders):
            out[key] = min(orders)
    return out


def refinement_ratio(errors: Mapping[str, Any], orders: Mapping[str, float | None], target: float,
                     share: float = TARGET_SHARE, bounds: tuple[float, float] = RATIO_RANGE) -> float:
    """How many times smaller the cells must be for every estimated relative error ``errors`` to
    fall to ``share`` of ``target``: a quantity estimated at E with order p needs the ratio
    (E / (share target))^(1/p), its estimate scaled by h^p; the largest over the quantities (lists
    element by element), within ``bounds``; the smallest ratio where none is above. A quantity
    without an order is not counted."""
    need = bounds[0]
    for key, value in errors.items():
        order = orders.get(key)
        if order is None or not order > 0.0:
            continue
        for v in value if isinstance(value, list) else [value]:
            if v is not None and math.isfinite(v) and v > share * target:
                need = max(need, (v / (share * target)) ** (1.0 / order))
    return float(min(max(need, bounds[0]), bounds[1]))


def _size_error(errors: Mapping[str, Any]) -> float:
    """The region's size error as it passes into the peak pressure: the half width's (2D) or the
    sum of both semi-axes' (3D); 0 when not estimated."""
    sizes = errors.get("semi_axes", errors.get("half_width"))
    values = sizes if isinstance(sizes, list) else [sizes]
    return float(sum(v for v in values if v is not None and math.isfinite(v)))


def largest_error(errors: Mapping[str, Any]) -> tuple[str | None, float]:
    """(quantity, value) of the largest estimated relative error."""
    best: tuple[str | None, float] = (None, 0.0)
    for key, value in errors.items():
        for v in value if isinstance(value, list) else [value]:
            if v is not None and math.isfinite(v) and v > best[1]:
                best = (key, float(v))
    return best


def complementary_energy_density(stress: np.ndarray, youngs_modulus: float, poissons_ratio: float) -> np.ndarray:
    """s : C^-1 : s of 3D stresses ``stress`` (n, 6), [sxx, syy, szz, syz, sxz, sxy], in an
    isotropic material: ((1 + nu) s:s - nu tr(s)^2) / E (twice the energy density)."""
    stress = np.asarray(stress, dtype=float)
    trace = stress[:, :3].sum(axis=1)
    squares = (stress[:, :3] ** 2).sum(axis=1) + 2.0 * (stress[:, 3:] ** 2).sum(axis=1)
    return ((1.0 + poissons_ratio) * squares - poissons_ratio * trace ** 2) / youngs_modulus


def far_field_force_error(error_energy: float, strain_energy: float) -> float:
    """The relative error of a displacement-driven contact's normal force that an energy error
    ``error_energy`` (||u - u_h||^2 in the energy norm, integral of (s - s_h) : C^-1 : (s - s_h))
    causes, with ``strain_energy`` U_h the solution's: error_energy / (2 U_h).

    With the displacement prescribed, the discrete solution is stiffer than the exact one and its
    energy exceeds it by half the error's energy norm squared (Galerkin orthogonality), U_h - U =
    ||e||^2 / 2, and the force is the energy's derivative with respect to the approach delta. For
    N ~ delta^m (m = 1 linear, 3/2 Hertz) both energies scale like delta^(m + 1), so
    N_h - N = (m + 1) ||e||^2 / (2 delta) and, with U_h = N_h delta / (m + 1), the relative error
    is ||e||^2 / (2 U_h) whatever m. Where the load is a force the force has no such error, and
    this overestimates."""
    if not (strain_energy > 0.0 and math.isfinite(error_energy)):
        return math.nan
    return float(error_energy / (2.0 * strain_energy))
