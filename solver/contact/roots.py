"""Root finding of the contact drivers: one bracketed solver (regula falsi with the Illinois
modification, bisection when slow) and the generators of trial half-widths built on it (edge
coefficient, window verdicts, the thesis's increment rule), and the stick-ratio root."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Bracket", "SecantBracket", "edge_search", "settling_tolerance", "bracket_search", "thesis_search", "StickRoot",
           "RegionTooSmall"]


class Bracket:
    """A bracket [lo, hi] on a transition with the scalar g (< 0 on the lo side) at both ends;
    proposes the next trial by regula falsi with the Illinois modification, kept at least
    tol/2 inside the bracket (so every trial shrinks it and the last one closes it), and
    bisection whenever g does not bracket or two trials shrank the bracket by less than half."""

    def __init__(self, lo, hi, glo, ghi, tol):
        self.lo, self.hi, self.glo, self.ghi, self.tol = lo, hi, glo, ghi, tol
        self.side, self.widths = 0, [hi - lo]

    def update(self, a, low_side: bool, g: float) -> None:
        if low_side:
            self.lo, self.glo = a, g
            if self.side < 0:
                self.ghi *= 0.5  # Illinois: the retained end's value is halved
            self.side = -1
        else:
            self.hi, self.ghi = a, g
            if self.side > 0:
                self.glo *= 0.5
            self.side = 1
        self.widths.append(self.hi - self.lo)

    def closed(self) -> bool:
        return self.hi - self.lo <= self.tol

    def propose(self) -> float:
        lo, hi = self.lo, self.hi
        mid = 0.5 * (lo + hi)
        slow = len(self.widths) >= 3 and self.widths[-1] > 0.5 * self.widths[-3]
        if slow or not (np.isfinite(self.glo) and np.isfinite(self.ghi) and self.glo < 0.0 < self.ghi):
            return mid
        x = lo + (hi - lo) * (-self.glo) / (self.ghi - self.glo)
        margin = min(0.5 * self.tol, 0.25 * (hi - lo))
        return float(np.clip(x, lo + margin, hi - margin))


def bracket_search(a0: float, h: float, tol: float, a_max: float, full: bool):
    """Generator of trial half-widths; receives the verdict of each, returns the final width
    and the bracket (a_pen, a_ten).

    Phase 1 brackets the smallest width without penetration a_pen (grow / shrink by a
    doubling step until the verdict changes), then closes the bracket to ``tol`` by a
    safeguarded secant on the edge gap (:class:`Bracket`). Phase 2 (``full``) brackets the
    largest width without tension a_ten above it the same way, on the edge pressure. The
    half-width is their midpoint: with bilinear cells both conditions are only resolved to
    about a cell (penetration shows only once a is about half a cell too small, the edge
    pressure turns tensile about when a passes the exact width), and the two err on opposite
    sides (benchmarks/contact.py measures both). Without ``full`` the result is a_pen."""
    step = max(0.05 * a0, 0.5 * h)
    lo, hi = None, None  # lo: penetrates, hi: does not
    a = a0
    seen = {}
    while True:  # expand or shrink until bracketed
        v = yield a
        seen[a] = v
        if v.penetration:
            lo = a if lo is None else max(lo, a)
        else:
            hi = a if hi is None else min(hi, a)
        if hi is None:
            if a >= a_max:
                raise RegionTooSmall()
            a = min(a + step, a_max)
            step *= 2.0
        elif lo is None:
            if a <= 0.0:
                return 0.0, (0.0, 0.0)
            a = max(a - step, 0.0)
            step *= 2.0
        else:
            break
    br = Bracket(lo, hi, seen[lo].gap, seen[hi].gap, tol)
    while not br.closed():
        a = br.propose()
        v = yield a
        seen[a] = v
        br.update(a, v.penetration, v.gap)
    a_pen = br.hi
    if not full or seen[a_pen].tension:
        return a_pen, (a_pen, a_pen)
    # phase 2: largest width without tension, from a_pen upwards (g = -pressure < 0 below)
    lo, hi = a_pen, None
    step = 0.5 * h
    a = min(a_pen + step, a_max)
    while True:
        if a in seen:
            v = seen[a]
        else:
            v = yield a
            seen[a] = v
        if v.tension:
            hi = a
            break
        lo = a
        if a >= a_max:
            return 0.5 * (a_pen + lo), (a_pen, lo)
        step *= 2.0
        a = min(a + step, a_max)
    br = Bracket(lo, hi, -seen[lo].pressure, -seen[hi].pressure, tol)
    while not br.closed():
        a = br.propose()
        v = seen[a] if a in seen else (yield a)
        seen[a] = v
        br.update(a, not v.tension, -v.pressure)
    a_ten = br.lo
    return 0.5 * (a_pen + a_ten), (a_pen, a_ten)


def thesis_search(a0: float, h: float, tol: float, a_max: float, max_iterations: int):
    """The thesis's width update (sections 5.5.3-5.5.4): grow on penetration only, shrink on
    tension only, the larger count decides when both are found (with half the step); the
    step starts at the cell size each load step, is halved on a change of direction and grown
    by 5 % while only penetration is found; stop when neither is found or the step is below
    ``tol``."""
    step, last, a = h, 0, a0
    for _ in range(max_iterations):
        v = yield a
        pen, ten = v.penetration_count, v.tension_count
        if not pen and not ten:
            break
        sign = 1 if pen >= ten else -1
        if last and sign != last:
            step *= 0.5
        elif sign > 0 and not ten and last > 0:
            step *= 1.05
        last = sign
        if step < tol:
            break
        a = float(np.clip(a + sign * step * (0.5 if (pen and ten) else 1.0), 0.0, a_max))
    return a, (a, a)


class SecantBracket(Bracket):
    """A :class:`Bracket` that proposes the secant step through the two latest trials while it
    falls inside the bracket (kept tol/2 from its ends, so that near the root the next trial
    lands across it and closes the bracket), regula falsi on the ends otherwise, and bisection
    when the bracket did not halve over three trials. For a smooth g the secant converges
    superlinearly where Illinois's retained-end halving alternates sides."""

    def __init__(self, lo, hi, glo, ghi, tol, last=()):
        super().__init__(lo, hi, glo, ghi, tol)
        self.last = list(last)[-2:]  # (a, g) of the latest trials

    def update(self, a, low_side: bool, g: float) -> None:
        super().update(a, low_side, g)
        self.last = (self.last + [(a, g)])[-2:]

    def propose(self) -> float:
        lo, hi = self.lo, self.hi
        margin = min(0.5 * self.tol, 0.25 * (hi - lo))
        slow = len(self.widths) >= 4 and self.widths[-1] > 0.5 * self.widths[-4]
        if len(self.last) == 2 and not slow:
            (a1, g1), (a2, g2) = self.last
            if np.isfinite(g1) and np.isfinite(g2) and g1 != g2:
                x = a2 - g2 * (a2 - a1) / (g2 - g1)
                if lo + margin <= x <= hi - margin:
                    return float(x)
                if lo < x < hi:
                    return float(np.clip(x, lo + margin, hi - margin))
        if slow or not (np.isfinite(self.glo) and np.isfinite(self.ghi) and self.glo < 0.0 < self.ghi):
            return 0.5 * (lo + hi)
        x = lo + (hi - lo) * (-self.glo) / (self.ghi - self.glo)
        return float(np.clip(x, lo + margin, hi - margin))


#: growth of a trial region per step while no bracket is found: at most this factor
_MAX_GROWTH = 4.0


#: the contact radius over the radius out to which a too small trial region leaves the bodies
#: overlapping: Hertz's a^2 = R delta against the rigid overlap's r^2 = 2 R delta
OVERLAP_SHARE = math.sqrt(0.5)


def _next_growing(a: float, step: float, seen: list[tuple[float, float]], a_max: float,
                  overlap: float = math.nan) -> float:
    """The next trial while every trial so far was too small (g > 0): 10 % beyond where the
    secant through the last two trials crosses zero (to bracket the root), at least the current
    step and at most four times a further; the step itself where g does not decrease yet. Where
    the verdict tells how far out the bodies still overlap (``overlap`` > a), at least
    OVERLAP_SHARE of the way there."""
    grown = a + step
    if len(seen) >= 2:
        (a1, g1), (a2, g2) = seen[-2:]
        if np.isfinite(g1) and np.isfinite(g2) and g2 < g1 and a2 > a1:
            root = a2 + g2 * (a2 - a1) / (g1 - g2)
            grown = float(np.clip(a + 1.1 * (root - a), a + step, _MAX_GROWTH * a))
    if np.isfinite(overlap) and overlap > a:
        grown = max(grown, a + OVERLAP_SHARE * (overlap - a))
    return min(grown, a_max)


def settling_tolerance(options, h: float, final: bool) -> float:
    """How closely a region's size (edge coefficient root) and centre are settled, in m:
    ``options.edge_tolerance`` cells of size h in the last load step, ``step_tolerance`` before."""
    return (options.edge_tolerance if final else options.step_tolerance) * h


def edge_search(a0: float, h: float, tol: float, a_max: float, step0: float | None = None,
                cap_is_end: bool = False):
    """Generator of trial half-widths for the root of the edge coefficient g(a) (> 0: a too
    small); receives the verdict of each trial, returns the width and the final bracket.

    Grow from a0 towards the root the secant through the last two trials predicts (a doubling
    step until g decreases), or shrink by a doubling step, until g changes sign; then close the
    bracket to ``tol`` by the safeguarded secant of :class:`SecantBracket`. Without compression
    (g = -inf) the trial is treated as too large. ``step0``: the first step (default the larger
    of a twentieth of a0 and half a cell; smaller where a0 is a close estimate). ``cap_is_end``:
    a_max is where the region must end (a corner of body 1: a complete contact), so a region
    still too small there is the answer, not a failure."""
    step = max(0.05 * a0, 0.5 * h) if step0 is None else step0
    lo = hi = None
    glo = ghi = None
    seen: list[tuple[float, float]] = []
    a = a0
    while True:
        v = yield a
        g = v.edge
        seen.append((a, g))
        if g > 0.0:
            lo, glo = a, g
            if hi is None:
                if a >= a_max:
                    if cap_is_end:
                        return a_max, (a_max, a_max)
                    raise RegionTooSmall()
                a = _next_growing(a, step, seen, a_max, getattr(v, "overlap", math.nan))
        else:
            hi, ghi = a, g
            if lo is None:
                if a <= 0.5 * h:
                    return 0.0, (0.0, 0.0)
                a = max(a - step, 0.25 * h)
        if lo is not None and hi is not None:
            break
        step *= 2.0
    br = SecantBracket(lo, hi, -glo, -ghi, tol, [(x, -y) for x, y in seen])  # g < 0 on the low side
    while not br.closed():
        a = br.propose()
        v = yield a
        br.update(a, v.edge > 0.0, -v.edge)
    # the end with the smaller |g| (the two are within tol)
    a = br.lo if abs(br.glo) <= abs(br.ghi) else br.hi
    return a, (br.lo, br.hi)


class StickRoot:
    """Root of F(k) = (1 - |Q(k)| / (mu N(k)))^e - k for the stick ratio k = c/a in [0, 1]
    (e = 1/2: eq. 2-29 of two cylinders; e = 1/3: Mindlin's spheres), consistent with the
    transmitted forces. F decreases in k (a larger stick
    zone transmits more shear), F(1) <= 0: fixed-point steps k <- k + F (halving instead where
    that would drop below k / 2) until the root is bracketed, then regula falsi with the
    Illinois modification. k = 0 (gross slip) only when F < 0 down to ``min_ratio``."""

    min_ratio = 0.01  # below this c/a a stick zone is not resolved: gross slip

    def __init__(self, tol: float, exponent: float = 0.5):
        self.tol = tol
        self.exponent = exponent  # 1/2: cylinders (eq. 2-29); 1/3: spheres (Mindlin)
        self.lo = self.hi = None  # k with F > 0 / F < 0
        self.flo = self.fhi = 0.0
        self.side = 0

    def update(self, k: float, normal: float, tangential: float, mu: float, ratio_of=None) -> tuple[float, bool]:
        """Next ratio and whether k is consistent (|F(k)| <= tol, or no compression). ``ratio_of``:
        c / a for the load share 1 - |Q| / (mu N) where the gap is not Hertz's (None: the share to
        the power ``exponent``)."""
        if not normal > 0.0:
            return k, True
        share = max(0.0, 1.0 - abs(tangential) / (mu * normal))
        g = ratio_of(share) if ratio_of is not None else share ** self.exponent
        f = g - k
        if abs(f) <= self.tol:
            return k, True
        if f > 0.0:
            self.lo, self.flo = k, f
            if self.side > 0:
                self.fhi *= 0.5
            self.side = 1
        else:
            self.hi, self.fhi = k, f
            if self.side < 0:
                self.flo *= 0.5
            self.side = -1
        if self.lo is None and (g <= 0.5 * k or k <= 0.0):
            # with the friction traction every ratio near 0 transmits |Q| = mu N, so F(0) = 0 always:
            # the partial-slip root is the largest one. Approach 0 by halving, never by a jump; gross
            # slip is the answer only once F < 0 all the way down (no stick zone can hold the shear)
            if k <= self.min_ratio:
                return 0.0, k <= 0.0
            return 0.5 * k, False
        if self.lo is None or self.hi is None:
            return g, False
        if abs(self.hi - self.lo) <= 0.25 * self.tol:
            return 0.5 * (self.lo + self.hi), True
        return self.lo + (self.hi - self.lo) * self.flo / (self.flo - self.fhi), False


class RegionTooSmall(Exception):
    pass
