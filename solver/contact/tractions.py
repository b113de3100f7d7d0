"""Contact tractions recovered from the solution: a projection of the band terms' traction onto
a smooth space over the contact region that reproduces the transmitted force exactly
(docs/contact.md, "Traction recovery").

The point traction of the thin-band terms (layer plus flux, friction included) jumps from cell
to cell with bilinear fields; its integrals over the region are accurate (the force, the edge
coefficient). With s = a cos(theta) on the region |s| <= a, the space is

    V_K = span{ phi_k(s) = sqrt(1 - s^2/a^2) U_k(s/a) = sin((k + 1) theta) / ... , k = 0..K }

(U_k the Chebyshev polynomials of the second kind), the form of every pressure whose region has
the consistent width (zero at +-a with a square-root edge; Hertz is phi_0 alone). The recovered
profile p_h in V_K is the Galerkin projection

    int p_h U_j(s/a) ds = int p U_j(s/a) ds,   j = 0..K,

i.e. the orthogonal projection in the norm weighted by 1/sqrt(1 - s^2/a^2), in which the phi_k
are orthogonal. The test function U_0 = 1 makes the integral of p_h the transmitted force, and
U_1 its first moment, both exactly (the integrals are the formulation's own quadrature: the
Gauss points of the region split at both grids' lines). K + 1 = sqrt(a / cell) modes (2 to
``MAX_MODES``, see :func:`modes_for`): the grid-periodic part of the point traction (wavelength
one cell) has vanishing moments against these slowly varying U_j.

Shear. Where no friction traction acts the slip zones carry no shear (frictionless: none at
all). Tied (c = a): projected over the region as the pressure (bounded at +-a; a fully stuck
region's shear is square-root singular at its edges, which the sampled profile does not
resolve, but it integrates to the force). The thesis's variant without the slip traction
(0 < c < a): projected over the tied zone |s| <= c onto T_k(s/c) / sqrt(1 - s^2/c^2) with the
tests T_j (orthogonal in the same weight, T_0 = 1 keeps the force): its shear concentrates at
the tied zone's ends like a punch's, which this space holds (and checks.stick_shear_above_mu_p
sees). Frictional with a stick zone |s| <= c: in the slip zones the
shear is Coulomb's sign mu p exactly (the formulation's friction traction), so the shear is
written q = sign mu p - r with r = sign mu p - q the stick zone's deficit, zero in the slip
zones; r is projected the same way over |s| <= c (Cattaneo-Mindlin's deficit is
mu p0 (c/a) sqrt(1 - s^2/c^2), the first mode of that zone). Both forces stay exact.

Complementarity in what is reported: p_h >= 0 and |q_h| <= mu p_h are enforced by clipping
(the force the clipping removes is returned, ``clipped_force``; round-off on the examples).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .ends import gap_pressure, mirrored

__all__ = ["TractionProfile", "recover_tractions", "modes_for"]

#: fewest and most modes of a projection (degree of the Chebyshev polynomials + 1)
MIN_MODES, MAX_MODES = 2, 12
#: a region with a complete (corner) end takes the modes of cells this many times larger
#: (measured on a sharp flat punch, a / cell = 32: 2 modes 2.4 %, 5 modes 5.7 %, 8 modes 13 % of
#: P / (2 a) from Sadowsky's pressure at most on |s| < 0.9 a)
COMPLETE_END_CELLS = 16


@dataclass
class TractionProfile:
    """Projected pressure and shear of one contact region (callable at chords s)."""

    a: float
    c: float  # stick half-width (0: none; >= a: all stick / tied)
    sign: float  # sign of the slip shear (0: no Coulomb relation)
    friction: float
    p_coef: np.ndarray  # pressure modes over |s| <= a
    q_coef: np.ndarray  # shear modes over |s| <= a (when not frictional with a stick zone)
    r_coef: np.ndarray  # stick deficit modes over |s| <= c (frictional with a stick zone)
    clipped_force: float = 0.0  # |force| removed by clipping tension / shear above mu p
    clipped: float = 0.0  # fraction of the region where the clipping acted
    singular: bool = False  # shear modes T_k / sqrt(1 - x^2) (a tied zone inside a frictionless region)
    centre: float = 0.0  # the region (and the stick zone) is centred at s = centre
    #: the half-plane pressure of the gap's own shape over the region (solver.contact.ends.gap_pressure
    #: coefficients), added to the projected modes; empty: none
    p_shape: np.ndarray = field(default_factory=lambda: np.zeros(0))
    p_singular: bool = False  # pressure modes T_k / sqrt(1 - x^2): the region ends at corners (complete)

    def raw_pressure(self, s: np.ndarray) -> np.ndarray:
        """The projected pressure before clipping to compression."""
        s = np.asarray(s, dtype=float) - self.centre
        out = _series(self.p_coef, s, self.a, singular=self.p_singular)
        if len(self.p_shape):
            out = out + gap_pressure(self.p_shape, s / self.a)
        return out

    def pressure(self, s: np.ndarray) -> np.ndarray:
        return np.maximum(self.raw_pressure(s), 0.0)

    def shear(self, s: np.ndarray) -> np.ndarray:
        p = self.pressure(s)
        s = np.asarray(s, dtype=float) - self.centre
        if self.sign == 0.0:
            q = _series(self.q_coef, s, self.c, singular=self.singular)
            if self.friction > 0.0:
                q = np.clip(q, -self.friction * p, self.friction * p)
            return q
        r = _series(self.r_coef, s, self.c) if self.c > 0.0 else np.zeros_like(s)
        r = np.clip(self.sign * r, 0.0, 2.0 * self.friction * p)  # |q| <= mu p <=> 0 <= sign r <= 2 mu p
        return self.sign * (self.friction * p - r)


def _basis(s: np.ndarray, half: float, n: int) -> np.ndarray:
    """(len(s), n): sqrt(1 - x^2) U_k(x) = sin((k + 1) theta) with x = s / half = cos(theta);
    zero for |x| >= 1."""
    x = np.clip(np.asarray(s, dtype=float) / half, -1.0, 1.0)
    theta = np.arccos(x)
    return np.sin(np.outer(theta, np.arange(1, n + 1)))


def _singular_basis(s: np.ndarray, half: float, n: int) -> np.ndarray:
    """(len(s), n): T_k(x) / sqrt(1 - x^2) = cos(k theta) / sin(theta), x = s / half: the form of
    a traction with square-root edges (a tied zone whose ends do not slide with friction)."""
    x = np.clip(np.asarray(s, dtype=float) / half, -1.0 + 1e-12, 1.0 - 1e-12)
    theta = np.arccos(x)
    return np.cos(np.outer(theta, np.arange(n))) / np.sin(theta)[:, None]


def _tests(s: np.ndarray, half: float, n: int, first: bool = False) -> np.ndarray:
    """(len(s), n): U_k(s / half) (``first``: T_k) by the three-term recurrence."""
    x = np.asarray(s, dtype=float) / half
    out = np.empty((len(x), n))
    out[:, 0] = 1.0
    if n > 1:
        out[:, 1] = x if first else 2.0 * x
    for k in range(2, n):
        out[:, k] = 2.0 * x * out[:, k - 1] - out[:, k - 2]
    return out


def _series(coef: np.ndarray, s, half: float, singular: bool = False) -> np.ndarray:
    s = np.asarray(s, dtype=float)
    if half <= 0.0 or len(coef) == 0:
        return np.zeros_like(s)
    out = (_singular_basis if singular else _basis)(s, half, len(coef)) @ coef
    return np.where(np.abs(s) < half, out, 0.0)


def project(s: np.ndarray, w: np.ndarray, values: np.ndarray, half: float, n: int,
            singular: bool = False) -> np.ndarray:
    """Modes of the Galerkin projection onto V_n over |s| <= half of ``values`` given at
    quadrature points (s, weights w): sum_k c_k int phi_k U_j = int values U_j, j < n, with the
    same quadrature (so that the integral of the projection is that of the values exactly).
    ``singular``: onto T_k / sqrt(1 - x^2) with the tests T_j instead (orthogonal in the same
    way; T_0 = 1 keeps the force)."""
    inside = np.abs(s) <= half
    s, w, v = s[inside], w[inside], values[inside]
    if len(s) == 0 or half <= 0.0:
        return np.zeros(0)
    n = max(1, min(n, len(s)))
    test = _tests(s, half, n, first=singular) * w[:, None]
    gram = test.T @ (_singular_basis if singular else _basis)(s, half, n)  # diagonal but for the quadrature
    return np.linalg.solve(gram, test.T @ v)


def modes_for(half: float, cell: float) -> int:
    """Number of modes over a zone of half-width ``half`` on cells of size ``cell``:
    floor(sqrt(half / cell)) between MIN_MODES and MAX_MODES.

    The test function U_k rises to k + 1 at the zone's ends with curvature ~ k^3 / half near
    them: over the last cell, U_k(1 - cell / half) differs from U_k(1) by about
    (k + 1)^2 cell / (3 half). Beyond k + 1 ~ sqrt(half / cell) the moments see the cell-scale
    structure of the edge cells (the traction's grid-periodic part and the region's cut edge)
    instead of averaging it out (measured: 12 modes at a = 11 cells put 3-5 % of p0 of
    cell-scale ripple back into the profile, 2-3 modes 0.3 %). Two modes at least: the force and
    its first moment about the contact point are always reproduced."""
    if not half > 0.0:
        return 0
    return int(max(MIN_MODES, min(MAX_MODES, math.floor(math.sqrt(half / cell)))))


def quadrature_tractions(c, u: np.ndarray, a: float):
    """Quadrature points of the region |s - e| <= a (e the region's centre; split at both grids'
    lines and the stick zone's ends, as the formulation's terms) with the traction on body 1
    there, friction included: (points, pressure, shear) with compression positive and the shear
    on body 2 along the local tangent."""
    from .band import _tractions, region_quadrature

    pts, jump, flux, size = region_quadrature(c, a)
    _, t1, _ = _tractions(c, pts, jump, flux, size, u[c.dofs], a)
    nl = pts.normal
    tl = np.stack([-nl[:, 1], nl[:, 0]], axis=1)
    return pts, np.einsum("qi,qi->q", t1, nl), -np.einsum("qi,qi->q", t1, tl)


def recover_tractions(c, u: np.ndarray, a: float, cell: float) -> TractionProfile:
    """The projected pressure and shear of contact ``c`` (a BandContact) for the field u at
    half-width a; ``cell`` the cell size that sets the number of modes. The shear is bounded by
    mu p only where the formulation enforces Coulomb's law (the slip-zone friction traction);
    the thesis's variant without it is reported as solved, its excess visible."""
    friction = float(getattr(c, "friction", 0.0) or 0.0)
    coulomb = c.kind == "frictional" and friction > 0.0 and bool(c.options.friction_traction)
    if not a > 0.0:
        return TractionProfile(a, 0.0, 0.0, friction, np.zeros(0), np.zeros(0), np.zeros(0))
    pts, p, q = quadrature_tractions(c, u, a)
    mirror = int(getattr(c, "mirror", 0))
    s, w, p = mirrored(c.local(pts.s), pts.weights, p, mirror)  # from the region's centre (a half model mirrored)
    q = mirrored(pts.s, pts.weights, q, mirror)[2] * (np.repeat([1.0, -1.0], len(pts.s)) if mirror else 1.0)
    complete = "complete" in c.end_types(a) if hasattr(c, "end_types") else False
    shape = np.zeros(0) if not hasattr(c, "gap_shape") else c.gap_shape(a)  # a complete end: the rest singular
    shape = shape if np.any(shape) else np.zeros(0)
    rest = p - gap_pressure(shape, s / a) if len(shape) else p
    # a complete end's discrete pressure errs within a few cells of the corner by O(1) of its
    # singular value, and every singular mode's test T_j weighs that equally: fewer modes there
    p_coef = project(s, w, rest, a, modes_for(a, COMPLETE_END_CELLS * cell if complete else cell), singular=complete)
    stick = min(c.stick(a), a)
    sign = float(c.slip_sign) if (coulomb and stick < a) else 0.0
    if sign == 0.0:  # the shear lives on the tied zone |s| <= c (frictionless: none)
        singular = 0.0 < stick < a  # the thesis's variant: a tied zone between frictionless slip zones
        q_coef = project(s, w, q, stick, modes_for(stick, cell), singular=singular) if stick > 0.0 else np.zeros(0)
        prof = TractionProfile(a, stick, 0.0, friction if coulomb else 0.0, p_coef, q_coef, np.zeros(0),
                               singular=singular)
    else:
        r = sign * friction * p - q  # zero in the slip zones
        r_coef = project(s, w, r, stick, modes_for(stick, cell)) if stick > 0.0 else np.zeros(0)
        prof = TractionProfile(a, stick, sign, friction, p_coef, np.zeros(0), r_coef)
    prof.centre = float(c.centre)
    prof.p_shape, prof.p_singular = shape, complete
    sc = s + prof.centre
    prof.clipped_force = float(abs(w @ prof.pressure(sc) - w @ p) + abs(w @ prof.shear(sc) - w @ q))
    prof.clipped = _clipped_fraction(prof, np.linspace(-a, a, 401))
    return prof


def _clipped_fraction(prof: TractionProfile, s: np.ndarray) -> float:
    """Fraction of the region where the projection before clipping had tension or shear above
    mu p (more than 1e-9 of the peak pressure)."""
    p = prof.raw_pressure(s + prof.centre)
    tol = 1e-9 * max(float(np.abs(p).max()), 1e-300)
    bad = p < -tol
    if prof.sign != 0.0 and prof.c > 0.0:
        r = prof.sign * _series(prof.r_coef, s, prof.c)
        bad |= (r < -tol) | (r > 2.0 * prof.friction * np.maximum(p, 0.0) + tol)
    elif prof.friction > 0.0:
        bad |= np.abs(_series(prof.q_coef, s, prof.c, singular=prof.singular)) > prof.friction * np.maximum(p, 0.0) + tol
    return float(bad.mean())
