"""The two ends of a 2D contact region: how the pressure behaves there, from its Chebyshev
moments and the gap's shape.

On a region e - a <= s <= e + a (x = (s - e) / a = cos(theta)) every pressure of a
half-plane-like contact has the form p = Q(x) / (a sqrt(1 - x^2)), and Q(+-1) says what happens
at each end: Q = 0 an incomplete end (the pressure vanishes like a square root: the region's
consistent end on a smooth surface), Q > 0 a square-root singular end (the region is too small,
or it ends at a corner of body 1: a complete contact, the punch's edge), Q < 0 tension (the
region is too large). The Chebyshev coefficients of Q are moments of the pressure,

    c_k = (2 / pi) int p T_k(x) ds,        Q = c_0 / 2 + c_1 T_1 + c_2 T_2 + ...

an integral over the whole region (blind to the grid-periodic oscillation of the discrete
traction, continuous in a). The degree-2 sum Q_2(+-1) = c_0/2 +- c_1 + c_2 is exact for a gap
quadratic in s (Hertz, Mindlin). For any other gap (a rounded punch: flat, then arcs) the
truncation errs by what the gap's own bounded pressure contributes, and that is known: with the
half-plane relation int p(t) / (s - t) dt = (pi E* / 2) h'(s) (h the initial gap, E* the
composite plane modulus; e.g. Johnson, Contact Mechanics, 1985, eq. 2.25; Barber, Contact
Mechanics, 2018, ch. 8) and the finite Hilbert transform pair
(1/pi) int sqrt(1 - t^2) U_(k-1)(t) / (x - t) dt = T_k(x), the bounded pressure of a gap with
(E* / 2) h'(e + a x) = sum_k b_k T_k(x) is sqrt(1 - x^2) sum_k b_k U_(k-1)(x), whose moments give

    Q_2(+1) = a (b_2 + b_3) / 2,     Q_2(-1) = a (b_3 - b_2) / 2

although its Q(+-1) is zero. Subtracting them gives the end values for any gap shape:

    Q(+-1) = c_0/2 +- c_1 + c_2 - a (b_3 +- b_2) / 2

(checked against the rounded flat punch's closed form, which the degree-2 sum alone puts 8 to 14 %
off in a). Near an end p ~ Q(+-1) / sqrt(2 a r) (r the distance from the end), so a complete
end's stress intensity K = lim p sqrt(2 pi r) = Q(+-1) sqrt(pi / a) (Sadowsky's flat punch:
Q = P / pi, K = P / sqrt(pi a)).

The same telescoping gives the sum to any even degree N: Q(+-1) = sum_(k<=N) (+-1)^k c_k
- a (b_(N+1) +- b_N) / 2. A conformal contact (two curved bodies over a large angle, a pin in a
bore) is not a half-plane's and its degree-2 sum errs whatever the gap (Persson's pressure at
1.3 rad: -2.3e-2); the degree-4 sum is within 4.5e-4, and is taken in as far as the grid
resolves the moments of degree 3 and 4 (conformal_weight).

A half model's region [0, a] on a symmetry line is the mirrored region [-a, a]: the pressure
is even, the gap's slope odd.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CONFORMAL_CELLS", "GAP_NODES", "EndValues", "chebyshev_ends", "conformal_weight",
           "gap_pressure", "gap_slope_coefficients", "mirrored"]

#: Gauss-Chebyshev nodes for the gap's slope coefficients (even: no node at the centre); the
#: gap's pressure shape (traction recovery) uses all of them, the end values b_2 to b_5
GAP_NODES = 128
#: half-widths in cells between which a conformal contact's end values take in the moments of
#: degree 3 and 4 (conformal_weight): the pressure of two curved bodies in contact over a large
#: angle is not the half-plane's, and its degree-2 sum errs (a pin in a bore at 1.3 rad: Q / (c_0 / 2)
#: of -2.3e-2 on the exact pressure, the degree-4 sum -4.5e-4), but the discrete pressure's
#: moments of degree 4 need a region of some 30 cells (at 11 cells they moved a by -0.6 %)
CONFORMAL_CELLS = (16.0, 32.0)
_THETA = (np.arange(GAP_NODES) + 0.5) * np.pi / GAP_NODES
_NODES = np.cos(_THETA)
_COSINES = np.cos(np.outer(np.arange(GAP_NODES), _THETA))  # cos(k theta_j), the discrete cosine transform


@dataclass
class EndValues:
    """Q at the region's two ends (upper x = +1, lower x = -1) and the mean c_0 / 2 (= the
    force / pi); ``coefficient`` the edge coefficient of each end, Q / (c_0 / 2)."""

    upper: float
    lower: float
    mean: float

    def coefficient(self, which: int) -> float:
        return (self.upper if which > 0 else self.lower) / self.mean

    def edge(self) -> float:
        """The two ends' mean edge coefficient (> 0: the region is too small)."""
        return 0.5 * (self.upper + self.lower) / self.mean

    def stress_intensity(self, which: int, a: float) -> float:
        """K = Q sqrt(pi / a) of an end (Pa m^0.5)."""
        return (self.upper if which > 0 else self.lower) * math.sqrt(math.pi / a)


def mirrored(s: np.ndarray, weights: np.ndarray, p: np.ndarray, mirror: int):
    """The points of a half model's region with their mirror images (s about 0): the full
    region's quadrature."""
    if not mirror:
        return s, weights, p
    return np.concatenate([s, -s]), np.concatenate([weights, weights]), np.concatenate([p, p])


def gap_slope_coefficients(slope, e: float, a: float, e_star: float, mirror: int = 0) -> np.ndarray:
    """b_k (k = 0 .. GAP_NODES - 1): the Chebyshev coefficients of (E*/2) h'(e + a x)
    (``slope(s)`` = h'(s), vectorised) by Gauss-Chebyshev quadrature on GAP_NODES nodes.
    ``mirror`` (+1 / -1): a half model's region on that side of s = 0, its slope extended as an
    odd function."""
    x = _NODES
    if mirror:
        hp = np.asarray(slope(mirror * a * np.abs(x)), dtype=float) * np.sign(x) * mirror
    else:
        hp = np.asarray(slope(e + a * x), dtype=float)
    return 0.5 * e_star * (2.0 / GAP_NODES) * (_COSINES @ hp)


def gap_pressure(b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The half-plane pressure of the gap whose slope has the coefficients b (bounded at both
    ends): sqrt(1 - x^2) sum_k b_k U_(k-1)(x) = sum_k b_k sin(k theta); zero for |x| >= 1."""
    x = np.asarray(x, dtype=float)
    theta = np.arccos(np.clip(x, -1.0, 1.0))
    out = np.sin(np.outer(theta, np.arange(len(b)))) @ b
    return np.where(np.abs(x) < 1.0, out, 0.0)


def _truncated(c: np.ndarray, c0h: float, a: float, b: np.ndarray, degree: int) -> tuple[float, float]:
    """Q(+1), Q(-1) from the moments up to the even ``degree`` N less the gap's part of that sum,
    a (b_(N+1) +- b_N) / 2 (c[k - 1] = c_k, b the gap's slope coefficients)."""
    even, odd = float(c[1:degree:2].sum()), float(c[0:degree:2].sum())
    bn, bn1 = float(b[degree]), float(b[degree + 1])
    return c0h + even + odd - 0.5 * a * (bn1 + bn), c0h + even - odd - 0.5 * a * (bn1 - bn)


def chebyshev_ends(x: np.ndarray, weights: np.ndarray, p: np.ndarray, a: float,
                   gap: np.ndarray | None = None, higher: float = 0.0, corner: int = 0) -> EndValues | None:
    """Q(+-1) of the pressure ``p`` at points x (in the region's units, -1..1) with weights ds:
    the degree-2 sum less the gap's part of it; ``gap`` = the b_k of the gap's slope (None: no gap
    part, exact for a quadratic gap). ``higher`` (0..1): the weight of the degree-4 sum's two
    further terms (a conformal contact, see CONFORMAL_CELLS). ``corner`` (+1 / -1): that end is a
    corner of body 1 (singular pressure); the other end's value is then taken from
    :func:`free_end_value`, which does not weigh the corner. None without compression."""
    wp = weights * p
    total = float(wp.sum())
    if not total > 0.0:
        return None
    c0h = total / math.pi
    k = np.arange(1, 5 if higher > 0.0 else 3)
    c = (2.0 / math.pi) * (np.cos(np.outer(k, np.arccos(np.clip(x, -1.0, 1.0)))) @ wp)
    b = np.zeros(6) if gap is None else np.asarray(gap[:6], dtype=float)
    upper, lower = _truncated(c, c0h, a, b, 2)
    if higher > 0.0:
        upper4, lower4 = _truncated(c, c0h, a, b, 4)
        upper, lower = upper + higher * (upper4 - upper), lower + higher * (lower4 - lower)
    if corner:
        free = free_end_value(x, weights, p, a, -corner, gap)
        upper, lower = (upper, free) if corner > 0 else (free, lower)
    return EndValues(upper=upper, lower=lower, mean=c0h)


#: Gauss-Chebyshev nodes of the free-end functional's weights (exact for its polynomials)
_FREE_NODES = np.cos((np.arange(16) + 0.5) * np.pi / 16)


#: the power of (1 + free x) in the free-end weight: it vanishes to this order at the corner. The
#: discrete pressure errs by O(1) of its singular value Q / sqrt(a r) within a few cells h of the
#: corner, and a weight ~ (r / a)^n takes in (h / a)^(n + 1/2) of Q from there: with n = 1 about 1 %
#: of Q at 20 cells, which moved a tilted flat punch's free end by 2 % on grids turned against it
#: (the error no longer periodic along the flat); with n = 2 twenty times less
FREE_END_ORDER = 2


@functools.cache
def _free_end_weight(free: int) -> tuple[float, float, float]:
    """Coefficients r (of 1, x, x^2) of the weight w(x) = (1 + free x)^2 r(x) with
    int Q(x) w(x) / sqrt(1 - x^2) dx = Q(free) for every Q of degree <= 2: the end value at
    x = free from a moment of the pressure that vanishes at the other end, x = -free."""
    t = np.cos(np.outer(np.arange(3), np.arccos(_FREE_NODES)))  # T_j at the nodes
    powers = _FREE_NODES[None, :] ** np.arange(3)[:, None]
    lhs = (np.pi / len(_FREE_NODES)) * (t * (1.0 + free * _FREE_NODES) ** FREE_END_ORDER) @ powers.T
    return tuple(np.linalg.solve(lhs, np.array([1.0, float(free), 1.0])))


def _free_weight(free: int, x: np.ndarray) -> np.ndarray:
    """The free-end weight w(x) = (1 + free x)^2 r(x) at x."""
    r = _free_end_weight(free)
    return (1.0 + free * x) ** FREE_END_ORDER * (r[0] + r[1] * x + r[2] * x * x)


def free_end_value(x: np.ndarray, weights: np.ndarray, p: np.ndarray, a: float, free: int,
                   gap: np.ndarray | None = None) -> float:
    """Q at the end x = ``free`` of a region whose other end is a corner of body 1, from the
    moment int p w ds with w(x) = (1 + free x)^2 r(x) (:func:`_free_end_weight`): exact, like the
    degree-2 sum, for Q of degree <= 2 (the half-plane's Q less the gap's own part is linear),
    but w vanishes at the corner, where the discrete pressure is singular and errs by O(1) of
    its value within a few cells; the degree-2 sum weighs the corner fully (T_k(+-1) = +-1) and
    puts a tilted flat punch's free end 10 % too far out at 35 cells, this within 1 %. The gap's
    own bounded pressure sum_k b_k sin(k theta), whose end values are zero, is subtracted
    through the same moment."""
    value = float(np.sum(weights * p * _free_weight(free, x)))
    if gap is not None:  # int a p_g(x) w(x) dx on the gap's nodes x = cos(theta)
        pg = gap_pressure(np.asarray(gap, dtype=float), _NODES)
        value -= a * (np.pi / GAP_NODES) * float(np.sum(pg * _free_weight(free, _NODES) * np.sin(_THETA)))
    return value


def conformal_weight(a: float, cell: float) -> float:
    """The weight of the degree-4 terms in a conformal contact's end values for a region of
    half-width ``a`` on cells of size ``cell``: 0 below CONFORMAL_CELLS[0] cells, 1 above
    CONFORMAL_CELLS[1], linear between (continuous in a for the width search)."""
    lo, hi = CONFORMAL_CELLS
    return float(np.clip((a / cell - lo) / (hi - lo), 0.0, 1.0))
