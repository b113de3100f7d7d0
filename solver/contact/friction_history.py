"""Partial slip with memory (2D): the band formulation (solver.contact.band) whose stick and slip
zones are found point by point from Coulomb's law on the increments of a load path.

State, kept on the contact's sample chords s_k (spacing ``sample_spacing`` finest cells) from
step to step: the tangential jump w_t (the relative tangential displacement of body 1 on body 2
along t_c) at the end of the last step, the zone of the current step (0 stick, +1 / -1 slipping
along +t_c / -t_c), the accumulated slip sum |dw_t| and the last slip direction.

In a step, a stick point keeps its tangential jump, w_t = w_t(previous step) (the band terms tie
the jump to that offset), and a slipping point carries Coulomb's traction -sign mu p t_c on
body 1, the sign that of its slip increment dw_t. The zones are an active set: after each
solve a stick point whose shear exceeds mu p starts slipping against its shear, and a slipping
point whose increment runs against its sign sticks (a point stuck again twice within a step
stays stuck for the rest of it: no endless flip at Coulomb's limit); repeated until no point
changes (the width search runs inside, as for any stick update); a point with a tensile mean
pressure slips (it cannot hold a shear). Then the stick/slip boundaries are refined between the
samples (the root of the stick side's edge singularity); one whose stick side then breaks
Coulomb's law goes back to where the zone updates put it. Shear and pressure are judged on their means
over one cell (``window``) around each sample: the point traction of the band terms oscillates
with the grid, its cell means do not. Zones of any number and direction follow (stick, forward
slip, reversed slip), none is assumed.

Reference: K. L. Johnson, Contact Mechanics (1985), sections 7.2 and 7.3 (Cattaneo-Mindlin and
Mindlin-Deresiewicz); the closed forms for the cylinder are in solver.reference.fretting.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..fem.step_boundary import PENALTY_FACTOR
from .band import BandContact, tangents, _tractions, build as band_build
from .history_terms import RegionPieces, history_terms
from .report import contact_block

__all__ = ["HistoryBandContact", "build"]

#: a stick point starts slipping when its mean shear exceeds mu p by this fraction
SLIP_MARGIN = 0.02
#: a step's boundary refinement stops after this many secant steps (counted in ``unsettled_steps``)
MAX_REFINEMENTS = 12
#: the edge singularity is fitted over this many cells of the stick side
EDGE_CELLS = 2.0
#: ... and a point stuck again in the same step when its mean shear exceeds mu p by this fraction
RESLIP_MARGIN = 0.1
#: a step's state breaks Coulomb's law when more than this share of its stick points carries a mean
#: shear above (1 + RESLIP_MARGIN) mu p (reported: the run is then not converged)
COULOMB_SHARE = 0.02
#: a boundary between stick and slip is settled when its secant step is below this many finest cells
BOUNDARY_TOLERANCE = 0.02
#: a slipping point sticks when its increment runs against its sign by more than this fraction
#: of the largest increment of the step
REVERSAL_MARGIN = 1e-3

@dataclass
class _Offset:
    """Contact points with the stick offset folded into their gap (the fields the band terms read)."""

    base: object
    delta: np.ndarray

    def __getattr__(self, name):
        return getattr(self.base, name)


@dataclass
class HistoryBandContact(BandContact):
    """Band contact with Coulomb friction on increments; see the module's docstring."""

    zone: np.ndarray = field(default_factory=lambda: np.zeros(0))  # per sample: 0 stick, +-1 slipping
    #: the zones as intervals: boundaries (sorted chords) and the zone of each interval (one more)
    bounds: np.ndarray = field(default_factory=lambda: np.zeros(0))
    values: np.ndarray = field(default_factory=lambda: np.zeros(1))
    refining: bool = False  # the zones' order is settled; their boundaries are being refined
    hold_width: bool = False  # the next width search keeps the width (a zone iteration)
    width_held: bool = False  # a width was kept in this step: search it once more at the end
    held_edge: float = math.nan  # the edge coefficient at the kept width
    secant: dict = field(default_factory=dict)  # boundary index -> [(position, edge singularity)] of its tries
    #: boundaries sent back to the zone updates' position in this step (their edge fit's root broke
    #: Coulomb's law beside them): not refined again in the step
    kept_bounds: set = field(default_factory=set)
    w_ref: np.ndarray = field(default_factory=lambda: np.zeros(0))  # the jump a stuck point is held at
    w_prev: np.ndarray = field(default_factory=lambda: np.zeros(0))  # tangential jump at the last step's end
    accumulated_slip: np.ndarray = field(default_factory=lambda: np.zeros(0))
    last_direction: np.ndarray = field(default_factory=lambda: np.zeros(0))
    step_increment: np.ndarray = field(default_factory=lambda: np.zeros(0))  # dw_t of the last step
    step_work: float = 0.0  # friction work of the last step (J/m), from the local tractions and slips
    shear_prev: np.ndarray = field(default_factory=lambda: np.zeros(0))  # mean shear at the last step's end
    raw_shear_prev: np.ndarray = field(default_factory=lambda: np.zeros(0))  # point shear at the last step's end
    raw_pressure_prev: np.ndarray = field(default_factory=lambda: np.zeros(0))  # point pressure at the last step's end
    zone_changes: int = 0
    refinements: int = 0  # secant steps of the boundaries in the current step
    unsettled_steps: list = field(default_factory=list)  # steps whose boundaries stopped at MAX_REFINEMENTS
    step_count: int = 0
    coulomb_violations: list = field(default_factory=list)  # (step, share of stick points above the limit)
    zone_updates: int = 0  # zone updates in the current step
    restuck: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # stuck again in this step
    settled_stuck: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # ... twice: stays stuck
    #: slip direction d -> (the deficit mu p + d q at the points, the zones) at the end of the last
    #: step with slip along d
    reversal: dict = field(default_factory=dict)
    #: d beta / d(move of a boundary into its stick side): the median of the last secants (0: none yet)
    edge_slope: float = 0.0
    slopes: list = field(default_factory=list)
    region_pieces: object = None  # the cache of the region's pieces (solver.contact.history_terms)
    #: (bounds, values, zone) of the last terms assembled: the zones of the last solve
    solved_zones: tuple | None = None
    history_rule = "incremental Coulomb: stick/slip state and accumulated slip carried per point"

    def start_history(self) -> None:
        n = len(self.samples.s)
        self.zone = np.zeros(n)
        self.w_ref = np.zeros(n)
        self.w_prev = np.zeros(n)
        self.accumulated_slip = np.zeros(n)
        self.last_direction = np.zeros(n)
        self.step_increment = np.zeros(n)
        self.shear_prev = np.zeros(n)
        self.raw_shear_prev = np.zeros(n)
        self.raw_pressure_prev = np.zeros(n)
        self.stick_ratio = 1.0
        self.slip_sign = 0.0

    # ------------------------------------------------------------------ the zones at any chord

    def _nearest(self, s: np.ndarray) -> np.ndarray:
        ks = self.samples.s
        return np.clip(np.searchsorted(0.5 * (ks[1:] + ks[:-1]), s), 0, len(ks) - 1)

    def zone_at(self, s: np.ndarray) -> np.ndarray:
        """The zone (0 stick, +-1 slipping) at chords s."""
        return self.values[np.searchsorted(self.bounds, np.asarray(s, dtype=float))]

    def _set_zones(self, zone: np.ndarray) -> None:
        """Zones from their values at the samples: the boundaries half-way between samples."""
        ks = self.samples.s
        change = np.flatnonzero(np.diff(zone) != 0.0)
        self.bounds = 0.5 * (ks[change] + ks[change + 1])
        self.values = np.concatenate([zone[:1], zone[change + 1]])
        self.zone = zone

    def region_zone(self, s: np.ndarray, a: float) -> np.ndarray:
        """The zone at chords s of the region of half-width a: zone_at, except between the outermost
        samples in the region and the region's ends, which take those samples' zones. The zones'
        boundary beside the last sample in the region lies half-way to the first one outside it
        (whose zone is none); a stretch of up to half a sample's spacing at the region's end would
        otherwise be tied to the reference jump of a point outside the region, set anew at every
        step, while the edge beside it slips (measured on the example: 17 J/m of the 363 J/m a
        cycle dissipates, in the outermost 0.5 % of the half-width, the share moving with the
        region's end among the samples)."""
        s = np.asarray(s, dtype=float)
        zone = self.zone_at(s)
        ks = self.samples.s
        inside = np.flatnonzero(np.abs(self.local(ks)) <= a)
        if len(inside) and len(self.zone) == len(ks):
            first, last = inside[0], inside[-1]
            zone = np.where(s > ks[last], self.zone[last], np.where(s < ks[first], self.zone[first], zone))
        return zone

    def tied_mask(self, s: np.ndarray, a: float) -> np.ndarray:
        return self.region_zone(s, a) == 0.0

    def slip_signs(self, s: np.ndarray, a: float) -> np.ndarray:
        s = np.asarray(s, dtype=float)
        inside = np.abs(self.local(s)) <= a
        return np.where(inside, self.region_zone(s, a), 0.0)

    def zone_breakpoints(self, a: float) -> list[float]:
        return self.bounds.tolist()

    def with_offset(self, pts):
        """The stick offset: a tied point's jump is held at w_ref t_c (delta less w_ref t_c)."""
        w = np.interp(pts.s, self.samples.s, self.w_ref)
        return _Offset(pts, pts.delta - w[:, None] * tangents(pts.normal))

    def terms(self, a: float):
        """Stiffness, load and quadrature data of the region at half-width a (the band terms with the
        zones of this contact, assembled from cached pieces: solver.contact.history_terms). The
        zones are kept as the last solved ones (a step that ends returns to them)."""
        self.solved_zones = (self.bounds.copy(), self.values.copy(), self.zone.copy())
        return history_terms(self, a)

    def stick(self, a: float) -> float:
        """Half-length of the stick zone about the region's centre: the mean distance from the centre
        to the nearest slip zone on either side (a where none), read at the zones' boundaries (which
        the refinement places between samples); 0 when the centre slips."""
        if not len(self.zone):
            return super().stick(a)
        if self.zone_at(np.array([self.centre]))[0] != 0.0:
            return 0.0
        r = self.local(self.bounds)
        right = r[(r > 0.0) & (self.values[1:] != 0.0) & (r <= a)]  # slip begins to the right of b
        left = r[(r < 0.0) & (self.values[:-1] != 0.0) & (r >= -a)]  # slip ends at b from the left
        hi = float(right.min()) if len(right) else a
        lo = float(-left.max()) if len(left) else a
        return float(min(0.5 * (hi + lo), a))

    def is_symmetric(self) -> bool:
        return not bool(np.any(self.zone != 0.0))

    # ------------------------------------------------------------------ states at the samples

    def sample_state(self, x: np.ndarray, a: float):
        """Cell means of pressure and shear (on body 1, along t_c) at the samples, and the tangential
        jump w_t there: (p, q, w_t, inside)."""
        pts = self.with_offset(self.samples)
        _, t1, inside = _tractions(self, pts, self.e_samples, self.f_samples, self.size_samples, x, a)
        tan = tangents(self.samples.normal)
        p = np.einsum("qi,qi->q", t1, self.samples.normal)
        q = np.einsum("qi,qi->q", t1, tan)
        w = (self.e_samples @ x).reshape(-1, 2) + self.samples.delta
        wt = np.einsum("qi,qi->q", w, tan)
        same = [self.zone == z for z in (-1.0, 0.0, 1.0)]
        self._raw = (p, q)
        return self._zone_mean(p, same), self._zone_mean(q, same), wt, inside

    def _zone_mean(self, v: np.ndarray, masks: list[np.ndarray]) -> np.ndarray:
        """Mean of v over one cell (``window``) about each sample, over the samples of its own zone
        only: a stick point's mean never mixes in the slip zone's Coulomb traction (which would
        hold a stick zone's boundary where a cell straddles it)."""
        ds = float(np.median(np.diff(self.samples.s)))
        k = max(int(round(self.options.window * self.h / ds)), 1)
        kernel = np.ones(k)
        out = np.zeros_like(v)
        for m in masks:
            num = np.convolve(np.where(m, v, 0.0), kernel, mode="same")
            den = np.convolve(m.astype(float), kernel, mode="same")
            out = np.where(m, num / np.maximum(den, 1.0), out)
        return out

    # ------------------------------------------------------------------ the driver's protocol

    def start_step(self) -> None:
        self.centre_tries = []  # (centre, centroid - centre) of this step's moves
        self.zone_changes = 0
        self.zone_updates = 0
        self._set_zones(np.zeros(len(self.zone)))  # the elastic predictor: every point stuck
        self.restuck = np.zeros(len(self.zone), dtype=bool)
        self.settled_stuck = np.zeros(len(self.zone), dtype=bool)
        self.refining, self.secant, self.refinements = False, {}, 0
        self.kept_bounds = set()
        # the step starts at the last step's width (one solve), searched only if it proves inconsistent
        self.hold_width = self.width_held = self.step_count > 0
        self.step_count += 1

    def region_search(self, a0: float, final: bool, max_iterations: int, estimate: bool = False):
        """The width search; between zone updates of a step the width is kept (the zones barely move
        it: one solve instead of a search), and searched again once the zones have settled unless
        the kept width's edge coefficient shows it consistent."""
        if self.hold_width:
            return hold_size(self, a0)
        return super().region_search(a0, final, max_iterations, estimate)

    def update_stick_and_shape(self, x: np.ndarray, a: float, info, final: bool = True) -> bool:
        """Centre, then the zones: a stick point above mu p slips against its shear; a slipping
        point whose increment reverses sticks. True when nothing changed (and the width was
        searched with the settled zones)."""
        if not self._update_centre(x, a, info, final):
            return False
        if self.width_held and self.zone_updates == 0 and not self._width_consistent(a):
            # the normal load changed since the last step: the predictor's width is searched first
            # (zone updates at a width that will move are wasted: each would be judged again)
            self.hold_width = self.width_held = False
            return False
        settled = self._update_zones(x, a)
        if not settled:
            self.hold_width = self.width_held = True
            return False
        self.hold_width = False
        if self.width_held:  # zones settled at a kept width: search it once more, unless it is consistent
            self.width_held = False
            if self._width_consistent(a):
                return True
            # the width moves (the normal load changed): the points it adds or removes are judged
            # again by zone updates before the boundaries are refined (a point entering contact
            # beside an edge slip zone would otherwise stay stuck above Coulomb's limit)
            self.refining, self.secant, self.kept_bounds = False, {}, set()
            return False
        return True

    def _width_consistent(self, a: float) -> bool:
        """Whether the kept width a is the one a search would find: the edge coefficient moves by
        about the relative change of the width, so within the width search's tolerance
        (``edge_tolerance`` cells) the kept width is the searched one."""
        if a <= 0.0:  # no region (a coarse grid lost it): a search decides
            return False
        return abs(self.held_edge) <= self.options.edge_tolerance * self.h / a

    def _update_zones(self, x: np.ndarray, a: float) -> bool:
        """One zone update (see update_stick_and_shape); True when nothing changed."""
        if self.refining:
            return self._refine_bounds(x, a)
        p, q, wt, inside = self.sample_state(x, a)
        dw = wt - self.w_prev  # the step's slip where slipping
        mu = self.friction
        zone = np.where(inside, self.zone, 0.0)  # outside the region: no zone
        outside = ~inside
        # a point in the region with a tensile mean pressure cannot hold a shear (Coulomb: |q| <= mu p
        # <= 0): it slips like a point above the limit (its tie would otherwise anchor the edge)
        # a point stuck again in this step slips again only well above the limit (no chatter at it)
        margin = np.where(self.restuck, RESLIP_MARGIN, SLIP_MARGIN)
        over = inside & (zone == 0.0) & (np.abs(q) > mu * p * (1.0 + margin))
        self.zone_updates += 1
        # the largest slip of the step, or (a step that hardly moves, a held load) a ten-thousandth
        # of the contact's elastic tangential displacement mu p_max a / E*: noise is no reversal
        floor = 1e-4 * mu * max(float(p.max()), 0.0) * a / self.e_star
        scale = max(float(np.abs(dw[inside]).max()) if inside.any() else 0.0, floor, 1e-300)
        back = (zone != 0.0) & (dw * zone < -REVERSAL_MARGIN * scale)
        over &= ~self.settled_stuck  # stuck again twice in this step: it stays stuck
        over &= self._excess_grew(p, q)
        zone[over] = -np.sign(q[over])
        zone[back] = 0.0
        self.settled_stuck |= back & self.restuck
        self.restuck |= back
        zone[outside] = 0.0
        changed = int(np.count_nonzero(zone != self.zone))
        self._set_zones(zone)
        self.zone_changes += changed
        self.stick_ratio = self.stick(a) / a if a > 0 else 1.0
        slipping = zone[zone != 0.0]
        self.slip_sign = float(np.sign(slipping.sum())) if len(slipping) else 0.0
        if changed == 0:
            self.refining = True
            return self._refine_bounds(x, a)
        return False

    def _excess_grew(self, p: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Whether each sample's excess of the mean shear over Coulomb's limit, |q| - mu p, grew
        since the last step's end, both read as cell means over the samples of the current
        zones (the last step's point tractions averaged like the current ones). Coulomb: a stuck
        point slips once its shear reaches the limit; one left at the limit by the last step and
        unloaded since stays stuck (measured: after a reversal, a sample at the last stick edge
        whose mean shear the grid's oscillation put at the margin slipped on in the old direction
        on 7 of 25 grids, that step's stick half-width 0.16 a off)."""
        same = [self.zone == z for z in (-1.0, 0.0, 1.0)]
        p_prev = self._zone_mean(self.raw_pressure_prev, same)
        q_prev = self._zone_mean(self.raw_shear_prev, same)
        mu = self.friction
        return np.abs(q) - mu * p > np.abs(q_prev) - mu * p_prev

    def _refine_bounds(self, x: np.ndarray, a: float) -> bool:
        """Move each stick/slip boundary to the root of its edge singularity (secant steps); True
        when every boundary's next move is below ``BOUNDARY_TOLERANCE`` cells (or the step's tries
        ran out). A step that ends keeps the boundaries of the solve just made, not the last small
        move: the step's forces, friction work and slips are then those of the solved field (the
        contact's force equals the loaded faces' reaction, and the loop's area equals the work
        of the contact's tractions)."""
        p_mean, q_mean, _, _ = self.sample_state(x, a)
        p, q = self._raw
        moves = []
        for i, b in enumerate(self.bounds):
            left, right = self.values[i], self.values[i + 1]
            into_stick = -1.0 if left == 0.0 else 1.0
            if (left == 0.0) == (right == 0.0) or i in self.kept_bounds or (
                    into_stick * self.local(b) > 0.0 and abs(self.local(b)) >= a - 0.5 * self.h):
                continue  # not between stick and slip, kept, or the slip zone's end at the region's edge
            sigma = right if left == 0.0 else left
            deficit = self.friction * p + sigma * q
            earlier = self.reversal.get(-sigma)  # the last state that slipped against sigma
            if earlier is not None and self._near_slip(earlier[1], b, into_stick, -sigma, a):
                deficit = deficit + earlier[0]  # that slip zone is within the fit's width: the increment's
            beta = self._edge_singularity(b, into_stick, deficit, p)
            if not math.isfinite(beta):
                continue
            tries = self.secant.get(i, []) + [(b, beta)]
            step = self._boundary_step(tries, into_stick)
            # a slip zone squeezed out at the region's end: the boundary stops at the end (beyond it
            # the pressure vanishes and the edge fit has no root: its coefficient grows without bound)
            end = self.centre + math.copysign(a, -into_stick)
            step = min(step, end - b) if into_stick < 0.0 else max(step, end - b)
            self.secant[i] = tries
            moves.append(abs(step))
            self.bounds[i] = b + step
        order_kept = bool(np.all(np.diff(self.bounds) > 0.0))
        if not order_kept:  # a zone vanished: back to the zones of the samples
            self.bounds = np.sort(self.bounds)
        self.zone = np.where(np.abs(self.local(self.samples.s)) <= a, self.zone_at(self.samples.s), 0.0)
        self.stick_ratio = self.stick(a) / a if a > 0 else 1.0
        self.refinements += 1
        settled = not moves or max(moves) <= BOUNDARY_TOLERANCE * self.h
        if not settled and self.refinements >= MAX_REFINEMENTS:
            self.unsettled_steps.append(self.step_count)
            settled = True
        if settled and self.solved_zones is not None:
            self.bounds, self.values, self.zone = (v.copy() for v in self.solved_zones)
            if order_kept and self._keep_coulomb_bounds(p_mean, q_mean, a):
                return False  # solve again with those boundaries where the zone updates put them
            self.stick_ratio = self.stick(a) / a if a > 0 else 1.0
        return settled

    def _keep_coulomb_bounds(self, p: np.ndarray, q: np.ndarray, a: float) -> bool:
        """After the boundaries settled: a refined boundary whose stick side, within one cell of it,
        has a stuck point with a mean shear above (1 + RESLIP_MARGIN) mu p (mean pressure p, mean
        shear q of the solved field) goes back to its first try, where the zone updates put it (at
        which no stuck point exceeded the limit), and is kept there for the rest of the step. The
        edge fit reads the point tractions, whose oscillation with the grid (+-30 % of the pressure
        within a cell) can give its coefficient a spurious root up to half a cell into the slip
        zone (measured on a shifted grid: a stick zone 0.05 a too large, its points up to 1.4 mu p,
        at the second step of a first loading). True when a boundary was sent back."""
        s, cell = self.samples.s, self.options.window * self.h
        back = False
        for i, b in enumerate(self.bounds):
            tries = self.secant.get(i)
            if i in self.kept_bounds or not tries or abs(tries[0][0] - b) <= BOUNDARY_TOLERANCE * self.h:
                continue
            into_stick = -1.0 if self.values[i] == 0.0 else 1.0
            d = into_stick * (s - b)
            beside = (d > 0.0) & (d <= cell) & (self.zone == 0.0) & (p > 0.0) & (np.abs(self.local(s)) <= a)
            if np.any(np.abs(q[beside]) > self.friction * p[beside] * (1.0 + RESLIP_MARGIN)):
                self.bounds[i] = tries[0][0]
                self.kept_bounds.add(i)
                back = True
        if back:
            self.zone = np.where(np.abs(self.local(s)) <= a, self.zone_at(s), 0.0)
        return back

    def _boundary_step(self, tries: list, into_stick: float) -> float:
        """The next move of a boundary from its tries [(position, beta)] in this step, beta growing
        with a move into the stick side: false position between the latest tries of either sign
        once they bracket the root (halving the kept end's beta when the same end is kept twice,
        Illinois), else a secant step while the last two tries show beta growing, else a step of
        -beta / edge_slope (the median slope of the last secants; a tenth of a cell until one is
        known). The edge fit's beta is not monotone everywhere (a locked-in edge of an earlier
        slip within the fit's width): a secant through a falling stretch would throw the boundary
        back and forth without end."""
        b, beta = tries[-1]
        u = [float(into_stick * t[0]) for t in tries]  # positions along the move into the stick side
        v = [float(t[1]) for t in tries]  # (Python floats: a quotient past the range is inf, not a warning)
        neg = [k for k in range(len(v)) if v[k] < 0.0]
        pos = [k for k in range(len(v)) if v[k] > 0.0]
        if neg and pos:
            kn, kp = neg[-1], pos[-1]
            vn, vp = v[kn], v[kp]
            if len(v) > 2 and (v[-1] > 0.0) == (v[-2] > 0.0):  # the same end moved twice: Illinois
                vn, vp = (0.5 * vn, vp) if v[-1] > 0.0 else (vn, 0.5 * vp)
            target = u[kn] + (u[kp] - u[kn]) * (-vn) / (vp - vn)
            step = into_stick * target - b
        elif len(tries) > 1 and (slope := _rising_slope(u[-2:], v[-2:], 1e-9 * self.h)) is not None:
            self.slopes = (self.slopes + [slope])[-8:]
            self.edge_slope = float(np.median(self.slopes))
            step = -into_stick * beta / slope
        else:
            step = -into_stick * (beta / self.edge_slope if self.edge_slope > 0.0
                                  else math.copysign(0.1 * self.h, beta))
        return float(np.clip(step, -0.5 * self.h, 0.5 * self.h))

    def _near_slip(self, zone: np.ndarray, b: float, into_stick: float, direction: float, a: float) -> bool:
        """Whether the zones ``zone`` (at the samples) slip along ``direction`` at the boundary b or
        within the edge fit's width of it on its slip side (beyond the region: taken as slipping)."""
        beside = b - into_stick * EDGE_CELLS * self.options.window * self.h
        at = zone[self._nearest(np.array([b, beside]))]
        return bool(at[0] == direction or at[1] == direction or abs(self.local(beside)) > a)

    def _edge_singularity(self, b: float, into_stick: float, deficit: np.ndarray, p: np.ndarray) -> float:
        """The coefficient beta of D ~ beta / sqrt(d) + alpha sqrt(d), fitted by its first two moments
        over ``EDGE_CELLS`` cells of the stick side (d the distance from the boundary b), of the
        stick zone's deficit D (zero in the adjacent slip zone), relative to mu p sqrt(cell): zero at
        a consistent boundary, < 0 where the stick zone is too large (its shear exceeds mu p,
        singular at its end), > 0 where too small (a finite deficit at its end).

        D is the deficit of the increment since slip last ran the other way (Mindlin and
        Deresiewicz: after a reversal the change of the tractions is a Cattaneo problem with twice
        the friction coefficient), D = mu p + sigma q + (mu p_r - sigma q_r), p_r and q_r the
        tractions at the end of the last step with slip against sigma, where that step's slip zone
        lies within the fit's width of the boundary on its slip side (nothing before any such
        step). The deficit mu p + sigma q alone
        carries the locked-in stick edge of that earlier slip, a second square root a fraction of
        a cell away while the new slip annulus is thin, which the two-term fit reads as a too
        small stick zone (measured: c' up to 0.024 a too large). A boundary deeper inside the
        earlier stick zone (a normal load that fell since: the new slip zone reaches into it) is fitted on
        mu p + sigma q: there the earlier deficit is a smooth positive background that would hold
        the stick zone above Coulomb's limit."""
        s = self.samples.s
        w = EDGE_CELLS * self.options.window * self.h
        d = into_stick * (s - b)
        near = (d > 0.0) & (d <= w)
        if np.count_nonzero(near) < 4:
            return math.nan
        dd, dv = d[near], deficit[near]
        order = np.argsort(dd)
        dd, dv = np.concatenate([[0.0], dd[order]]), np.concatenate([[dv[order][0]], dv[order]])
        m0 = float(np.trapezoid(dv, dd))
        m1 = float(np.trapezoid(dv * dd, dd))
        beta = (0.4 * m0 * w - (2.0 / 3.0) * m1) / ((0.8 - 4.0 / 9.0) * w ** 1.5)
        scale = self.friction * max(float(np.mean(p[near])), 1e-300) * math.sqrt(w)
        return beta / scale

    def end_step(self, x: np.ndarray, a: float, info) -> None:
        """Carry the step's state: the slips, their work, the new reference jumps."""
        p, q, wt, inside = self.sample_state(x, a)
        stuck = inside & (p > 0.0) & (self.zone == 0.0)
        share = float(np.mean(np.abs(q[stuck]) > self.friction * p[stuck] * (1.0 + RESLIP_MARGIN))) if stuck.any() else 0.0
        if share > COULOMB_SHARE:
            self.coulomb_violations.append((self.step_count, share))
        dw = np.where(self.zone != 0.0, wt - self.w_prev, 0.0)
        ds = np.gradient(self.samples.s)
        # friction work: -int q dw ds over the slipping points (positive: dissipated), q the step's
        # end shear at the point, the Coulomb traction -sign mu p the terms apply there (a point
        # slips once its shear reached it). Not its cell mean: the mean over one cell, truncated at
        # the region's edge, weights the edge's slip with the pressure further in (measured on the
        # example: +1.1 % to +4.3 % of the closed form across grid positions, the point traction
        # -0.7 % to +1.2 %)
        self.step_work = float(-np.sum(self._raw[1] * dw * ds))
        self.accumulated_slip = self.accumulated_slip + np.abs(dw)
        self.last_direction = np.where(self.zone != 0.0, self.zone, self.last_direction)
        self.step_increment = dw
        # a stuck point keeps its reference (the tie's elastic stretch is recoverable, not slip);
        # a slipping or open point takes the reference at which the tie, were it stuck now, would
        # carry the traction it carries (Coulomb's, or none): the traction stays continuous when
        # the point sticks
        free = (self.zone != 0.0) | ~inside | (p <= 0.0)
        self.w_ref = np.where(free, wt - self._tie_offset(x, np.where(inside, self._raw[1], 0.0)), self.w_ref)
        self.shear_prev = np.where(inside, q, 0.0)
        self.raw_shear_prev = self._raw[1].copy()
        self.raw_pressure_prev = self._raw[0].copy()
        p_raw, q_raw = self._raw
        for d in (-1.0, 1.0):
            if np.any(inside & (self.zone == d)):
                self.reversal[d] = (np.where(inside, self.friction * p_raw + d * q_raw, 0.0), self.zone.copy())
        self.w_prev = wt
        self.step_pressure = np.where(inside, p, 0.0)

    def hold_step(self, x: np.ndarray, a: float, info) -> None:
        """A step whose loads equal the last step's: the state is kept, its zones (the points of
        the slip zones stay at Coulomb's limit) with no slip increment and no work."""
        self.step_count += 1
        self.step_increment = np.zeros(len(self.zone))
        self.step_work = 0.0

    def _tie_offset(self, x: np.ndarray, shear: np.ndarray) -> np.ndarray:
        """(f_t - q) / L_tt at the samples: the tangential stretch of the tie whose traction
        -L_tt stretch + f_t (the layer plus the flux along t_c) is the shear q."""
        tan = tangents(self.samples.normal)
        flux = np.einsum("qi,qi->q", (self.f_samples @ x).reshape(-1, 2), tan)
        layer = PENALTY_FACTOR / (self.band_fraction * self.size_samples) * self.layer[1]
        return (flux - shear) / layer

    def slip_zones(self, a: float) -> list[list[float]]:
        """[s_lo, s_hi, direction] of each run of slipping samples within the region."""
        s = self.samples.s
        inside = np.abs(self.local(s)) <= a
        z = np.where(inside, self.zone, 0.0)
        out = []
        edges = np.flatnonzero(np.diff(np.concatenate([[0.0], z, [0.0]])) != 0.0)
        for lo, hi in zip(edges[:-1], edges[1:]):
            if lo < len(z) and z[lo] != 0.0:
                out.append([float(s[lo]), float(s[hi - 1]), float(z[lo])])
        return out

    def step_fields(self, u: np.ndarray, a: float, info) -> dict:
        """The per-step record beside the forces: friction work, and the profiles (for the files)."""
        inside = np.abs(self.local(self.samples.s)) <= a
        return {"friction_work": self.step_work, "slip_points": int(np.count_nonzero(self.zone)),
                "profile": {"s": self.samples.s, "pressure": self.step_pressure, "shear": self.shear_prev,
                            "points": self.samples.x2, "normal": self.samples.normal, "tangential_jump": self.w_prev,
                            "zone": np.where(inside, self.zone, 0.0), "slip_increment": self.step_increment,
                            "accumulated_slip": self.accumulated_slip.copy(), "inside": inside}}

    def summary_block(self, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
        """The contact block with the profiles of the history: pressure recovered as without
        history, shear the cell means (Coulomb's -sign mu p where slipping)."""
        block = contact_block(self, a, on2, u)
        s = np.asarray(block["shear"]["s"])
        p = np.asarray(block["pressure"]["value"])
        q = np.interp(s, self.samples.s, self.shear_prev)
        zone = self.slip_signs(s, a)
        q = np.where(zone != 0.0, -zone * self.friction * p, np.clip(q, -self.friction * p, self.friction * p))
        block["shear"] = {"s": s.tolist(), "value": np.where(np.abs(self.local(s)) <= a, q, 0.0).tolist()}
        block["slip_zones"] = self.slip_zones(a)
        block["friction_history"] = self.history_rule
        block["accumulated_slip"] = {"s": s.tolist(),
                                     "value": np.interp(s, self.samples.s, self.accumulated_slip).tolist()}
        return block

    def friction_checks(self, x: np.ndarray, a: float, info, on2: np.ndarray, block: dict) -> list[str]:
        nrm, tan = self.geom.normal, self.geom.tangent
        nf, qf = float(-on2 @ nrm), float(on2 @ tan)
        s = self.local(self.samples.s)
        stick = (np.abs(s) <= a) & (self.zone == 0.0)
        p = getattr(self, "step_pressure", np.zeros(len(s)))
        excess = stick & (np.abs(self.shear_prev) > 1.02 * self.friction * np.maximum(p, 0.0))
        block["checks"].update({"force_ratio": qf / nf if nf > 0 else math.nan,
                                "steps_with_unsettled_zone_boundaries": list(self.unsettled_steps),
                                "stick_shear_above_mu_p": float(excess.sum() / max(stick.sum(), 1)),
                                "zone_changes_last_step": self.zone_changes})
        block["gross_slip"] = bool(np.all(self.zone[np.abs(s) <= a] != 0.0)) if a > 0 else False
        block["checks"]["steps_breaking_coulomb"] = [[k, v] for k, v in self.coulomb_violations]
        return [f"{self.name}: load step {k}: {v:.1%} of the stick zone carries a shear above "
                f"{1.0 + RESLIP_MARGIN:g} mu p (the zones did not find Coulomb's state)"
                for k, v in self.coulomb_violations]


def hold_size(c, a: float):
    """A size search that keeps the size a (one trial): the contact's ``held_edge`` gets the
    trial's edge coefficient. Serves the 2D band and the 3D ellipse under load paths."""
    verdict = yield a
    c.held_edge = float(verdict.edge)
    return a, (a, a)


def build(problem, model, b1, b2, options) -> HistoryBandContact:
    """The band formulation of ``model`` with friction history (see :mod:`solver.contact.band`)."""
    base = band_build(problem, model, b1, b2, options)
    c = HistoryBandContact(**{f.name: getattr(base, f.name) for f in dataclasses.fields(BandContact)})
    c.region_pieces = RegionPieces(c)
    c.start_history()
    return c


def _rising_slope(u: list, v: list, du_min: float) -> float | None:
    """The slope of the secant through (u[0], v[0]) and (u[1], v[1]) where it rises to a finite
    value over a run of at least ``du_min``; None otherwise (two tries closer than that give no
    slope: their quotient is round-off; tries where the edge coefficient has no root, beyond the
    pressure's end, overflow: on floats the quotient is then inf, not a warning)."""
    du, dv = float(u[1] - u[0]), float(v[1] - v[0])
    if abs(du) < du_min or not all(map(math.isfinite, (*u, *v))):
        return None
    try:
        slope = dv / du
    except (ZeroDivisionError, OverflowError):
        return None
    return slope if math.isfinite(slope) and slope > 0.0 else None
