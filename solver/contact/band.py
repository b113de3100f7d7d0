"""The band (half-width) contact formulation of thesis chapter 5 on the IBFEM core: tied,
frictionless and frictional (partial slip) contact of two bodies, the contact region |s| <= a of
body 1's contact curve, its half-width found by the load-step driver (solver.contact.driver)
through the region search this module supplies.

Discrete form (docs/contact.md). On body 1's contact curve, |s| <= a, with matched points
x1, x2 and w = u_h1(x1) - u_h2(x2) + Delta (eqs. 5-2 to 5-4 in the thin-band limit):

    K_c = J^T L J - (F^T W P J + J^T P W F),   f_c = -J^T L Delta + F^T W P Delta

J the jump operator u_h1(x1) - u_h2(x2) (each field in its own grid at its own matched point),
L = sum_q w_q 4/(3 delta) P A(n_c) P with body 1's moduli (delta = band_fraction x local cell
size), F the flux (default the band limit 1/2 sigma_1(u_h1) n1 + 1/2 sigma_2(u_h2) n1, the
symmetric average), P = I where tied (|s| <= stick half-width; all of a for tied contact) and
n_c n_c^T where sliding (frictionless: the tangential jump is free), n_c the pair's contact
normal (bisector of the two exact normals, or the frame normal).

The half-width (default ``width_update = "edge"``): the root of the edge coefficient
int p (4 s^2/a^2 - 1) ds / int p ds, the Chebyshev estimate of p sqrt(a^2 - s^2) at the
region's ends (zero for the consistent width, > 0 for a punch-like region that is too small,
< 0 with tension): continuous in a and blind to the grid-periodic traction oscillation. In the
last load step the width is the root of its straight line over one finest cell about that root
(_cell_averaged), which averages out a small wiggle of g of period one cell.

The region's centre (``region_centre = "pressure"``, the default): the region is
e - a <= s <= e + a, and e is moved to the centroid of the pressure, int p s ds / int p ds,
between width searches (as the stick ratio is). The two edge values Q(e +- a) of the same
Chebyshev fit differ by 2 q_1 with q_1 proportional to int p (s - e) ds, so at the fixed point
both ends are consistent, not only their mean: a contact whose gap is not symmetric about the
contact point (a cylinder on an inclined face, example 7: the region reaches 1.02 a up the face
and 0.98 a down it) gets its own two ends. Symmetric contacts give e = 0 to round-off on the
first update and cost nothing more. ``region_centre = "point"``: |s| <= a, as the thesis.
Alternatives: a bracket on the window verdicts (penetration / tension judged on one-cell means
at the edges) or the thesis's increment rule (sections 5.5.3-5.5.4). The final state is always
judged by the window verdicts.

Frictional contact: stick zone |s| < c tied, slip zones c <= |s| <= a sliding with Coulomb's
traction mu p along the pair's tangent (eq. 5-24; p is affine in the dofs, so the traction
enters exactly as a non-symmetric block); c/a is the root of sqrt(1 - |Q|/(mu N)) - c/a for the
transmitted forces (eq. 2-29); gross slip is reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..fem.step_boundary import PENALTY_FACTOR, BoundaryPoints, acoustic_tensor, projector, thin_band_terms
from ..model.elasticity import plane_modulus
from ..model.options import ContactOptions
from ..model.problem import Sliding
from .geometry import (ContactGeometry, chain_pieces, chord_weights, contact_geometry, contact_quadrature,
                       grid_breakpoints, sample_points)
from .interface_weights import flux_weights, layer_moduli
from .ends import GAP_NODES, chebyshev_ends, conformal_weight, gap_slope_coefficients, mirrored
from .roots import StickRoot, bracket_search, edge_search, settling_tolerance, thesis_search

__all__ = ["BandContact", "CandidateRegionExceeded", "build"]


class CandidateRegionExceeded(ValueError):
    """The contact region reaches the end of the candidate region and still penetrates; ``cause``
    names what bounds it ("refinement radius", a corner or far side of a body)."""

    def __init__(self, bodies: tuple[str, str], cause: str, message: str, point=None):
        super().__init__(message)
        self.bodies, self.cause = tuple(bodies), cause
        self.point = None if point is None else np.asarray(point, dtype=float)  # the contact's (its pair may have several)


def _cell_dofs_global(b, cells: np.ndarray) -> np.ndarray:
    """Global free dofs the nodes of the cells depend on (hanging nodes resolved)."""
    rows = b.cell_dofs(np.unique(cells)).ravel()
    m = b.node_dof_map[np.unique(rows)]
    return np.unique(m.indices)


@dataclass
class BandContact:
    """The band (half-width) formulation of one contact: its geometry, dofs, operators at the
    sample points and iteration state; the methods at the end are what the load-step driver
    (solver.contact.driver) calls (the :class:`solver.contact.formulation.ContactFormulation`
    protocol)."""

    model: object
    geom: ContactGeometry
    b1: object
    b2: object
    kind: str
    dofs: np.ndarray  # global contact dofs (sorted)
    h: float  # finest cell size along the contact
    samples: object  # ContactPoints at the sample chords
    e_samples: object  # (2 ns, m) jump operator at samples on the contact dofs (sparse)
    f_samples: object  # (2 ns, m) flux operator at samples (sparse)
    size_samples: np.ndarray  # (ns,) local size (sets delta) at the samples
    e_star: float
    breakpoints: np.ndarray
    history: list = field(default_factory=list)
    # stick ratio c/a: tied (P = I) for |s| <= c, sliding (P = n_c n_c^T) for c < |s| <= a.
    # Tied contact: inf; frictionless: 0; frictional (Cattaneo-Mindlin): sqrt(1 - |beta| / mu), iterated.
    stick_ratio: float = 0.0
    friction: float = 0.0  # mu: the slip zone carries mu p along -slip_sign t_c on body 1
    slip_sign: float = 0.0  # sign of the tangential force on body 2 (0: no friction traction)
    beta: float = math.nan  # Q / N of the last state (frictional)
    gross_slip: bool = False
    options: ContactOptions = field(default_factory=ContactOptions)
    # the node-dof maps of both bodies restricted to the contact dofs, and which grid nodes they
    # hold completely (solver.fem.space.BodyDiscretisation.restricted_dof_map)
    maps: tuple = ()
    band_fraction: float = 0.25  # the step-boundary band of the terms ([solver].band_fraction)
    #: the region is centre - a <= s <= centre + a (the pressure's centroid; 0 with region_centre "point")
    centre: float = 0.0
    #: a half model (+1 / -1): the region runs from the symmetry line s = 0 to that side, mirrored there
    mirror: int = 0
    #: a region pinned at a corner of body 1 on its + (+1) or - (-1) side: that end is the corner (a
    #: complete end) for every half-width, the centre is the corner -+ a and the width is found
    #: from the other (incomplete) end alone
    pinned: int = 0
    _gap_cache: dict = field(default_factory=dict)
    _stick_root: object = None
    #: (centre, centroid - centre) of the load step's centre moves (reset at every step)
    centre_tries: list = field(default_factory=list)

    @property
    def layer(self) -> tuple[float, float]:
        """(lambda, mu) of the penalty layer's acoustic tensor (solver.contact.interface_weights)."""
        return layer_moduli(self.options.flux, self.b1, self.b2)

    def stick(self, a: float) -> float:
        """Stick half-width c for the half-width a."""
        return math.inf if math.isinf(self.stick_ratio) else self.stick_ratio * a

    def local(self, s: np.ndarray) -> np.ndarray:
        """Chords measured from the region's centre (the stick zone is centred there too)."""
        return np.asarray(s, dtype=float) - self.centre

    def region_ends(self, a: float) -> tuple[float, float]:
        """The region's ends (s_lo, s_hi) for half-width a, within the candidate region (a half
        model's region runs from the symmetry line, s = 0, to one side)."""
        s_plus, s_minus = self.geom.s_limits
        if self.mirror > 0:
            return 0.0, min(a, s_plus)
        if self.mirror < 0:
            return max(-a, -s_minus), 0.0
        return max(self.centre - a, -s_minus), min(self.centre + a, s_plus)

    # the zones of the region's points; a formulation with friction history overrides these four
    def tied_mask(self, s: np.ndarray, a: float) -> np.ndarray:
        """Points (chords s) whose full jump is constrained (the stick zone)."""
        return np.abs(self.local(s)) < self.stick(a)  # strict: with c = 0 (frictionless, gross slip) nothing is tied

    def slip_signs(self, s: np.ndarray, a: float) -> np.ndarray:
        """Per point the direction of slip of body 1 on body 2 along t_c where the friction traction
        -sign mu p t_c acts (0: none)."""
        if not (self.friction > 0.0 and self.slip_sign != 0.0) or a <= 0.0:
            return np.zeros(len(s))
        r = np.abs(self.local(s))
        return np.where((r >= self.stick(a)) & (r <= a), self.slip_sign, 0.0)

    def zone_breakpoints(self, a: float) -> list[float]:
        """Chords where the zones change (the quadrature's pieces end there)."""
        stick = self.stick(a)
        return [self.centre - stick, self.centre + stick] if 0.0 < stick < a else []

    def with_offset(self, pts):
        """Contact points whose gap ``delta`` includes a prescribed tangential offset (none here)."""
        return pts

    def a_max(self) -> float:
        """The largest half-width about the current centre within the candidate region."""
        if self.pinned:
            return 0.5 * sum(self.geom.s_limits)
        if self.mirror:
            return self.geom.s_limits[0 if self.mirror > 0 else 1]
        return max(self.geom.s_max() - abs(self.centre), 0.0)

    def _limit(self):
        """The SideLimit that bounds the largest region about the current centre."""
        plus, minus = self.geom.limits
        if self.pinned:
            return minus if self.pinned > 0 else plus
        if self.mirror:
            return plus if self.mirror > 0 else minus
        return plus if plus.chord - self.centre <= minus.chord + self.centre else minus

    def end_types(self, a: float) -> tuple[str, str]:
        """Type of the region's (lower, upper) end for half-width a: "symmetry" (a half model's
        symmetry line), "complete" (at a corner of body 1) or "incomplete" (inside a smooth
        stretch of the boundary, the pressure vanishing there)."""
        lo, hi = self.region_ends(a)
        out = []
        for end, lim, sgn in ((lo, self.geom.limits[1], -1), (hi, self.geom.limits[0], 1)):
            if self.mirror == -sgn and end == 0.0:
                out.append("symmetry")
            elif lim.corner and abs(sgn * end - lim.chord) <= 1e-9 * max(lim.chord, self.h):
                out.append("complete")
            else:
                out.append("incomplete")
        return out[0], out[1]

    # -------------------------------------------------- the formulation protocol

    @property
    def name(self) -> str:
        return f"contact {self.geom.bodies[0]}/{self.geom.bodies[1]}"


    def initial_region(self) -> float:
        """First trial half-width: two finest cells."""
        return 2.0 * self.h


    def next_region(self, a: float, load_ratio: float) -> float:
        """Start of the next load step from the last width, scaled as Hertz (a ~ sqrt(load))."""
        return max(a * math.sqrt(load_ratio), 2.0 * self.h)


    def region_search(self, a0: float, final: bool, max_iterations: int, estimate: bool = False):
        """Generator of trial half-widths (receives each trial's verdict, returns the width and the
        final bracket), by the contact's ``width_update``. ``estimate``: a0 is a close estimate
        (the previous load step's width scaled, or the same step's width before a stick update),
        so the edge search starts with a step of a twentieth of a cell instead of half a cell."""
        o = self.options
        if o.width_update == "edge":
            step0 = 0.05 * self.h if estimate else None
            tol = settling_tolerance(self.options, self.h, final)
            search = edge_search(a0, self.h, tol, self.a_max(), step0=step0, cap_is_end=self._limit().corner)
            # the final width from the edge coefficient's line over one cell; a subclass with a width
            # logic of its own (one that keeps a width between the steps of a load path and judges
            # it by its raw edge coefficient) gets the plain search
            own = type(self).region_search is BandContact.region_search
            return _cell_averaged(search, self.h, self.a_max()) if final and own else search
        if o.width_update == "thesis":
            return thesis_search(a0, self.h, o.width_tolerance * self.h, self.a_max(), max_iterations)
        tol = (o.width_tolerance if final else o.step_tolerance) * self.h
        return bracket_search(a0, self.h, tol, self.a_max(), final)

    def region_too_small(self) -> ValueError:
        lim = self._limit()
        fix = {"refinement radius": "enlarge the radius of the contact refinement (around = \"contact\")"}.get(
            lim.cause, "the bodies are too small for this load, or the contact point or load is wrong")
        return CandidateRegionExceeded(
            self.geom.bodies, lim.cause,
            f"{self.name}: the contact region reaches the end of the candidate region (s = {self.a_max():.4g} m "
            f"from the region's centre {self.centre:.4g} m, bounded by the {lim.cause}) "
            f"and still penetrates; {fix}", point=self.geom.point,
        )


    def at_width(self, a: float) -> None:
        """A pinned region's centre for the half-width a (the corner -+ a)."""
        if self.pinned > 0:
            self.centre = self.geom.s_limits[0] - a
        elif self.pinned < 0:
            self.centre = a - self.geom.s_limits[1]

    def judge(self, x: np.ndarray, a: float, info) -> _Verdict:
        """Verdict of a trial state (contact dof values x at half-width a), edge coefficient included."""
        self.at_width(a)
        gap, pres, inside = _sample_state(self, x, a)
        v = _judge(self, gap, pres, inside, a)
        v.edge = _edge_coefficient(self, info, x, a)
        return v


    def terms(self, a: float):
        """Contact stiffness (m, m) and load (m,) on the contact dofs for half-width a, and the
        quadrature data the other methods take as ``info``."""
        self.at_width(a)
        return _terms(self, a)

    def force(self, x: np.ndarray, a: float, info) -> np.ndarray:
        """Force (2,) on body 1 from body 2 for contact dof values x."""
        return _contact_force(self, info, x, a)

    def traction_samples(self, u: np.ndarray, a: float, s: np.ndarray):
        """Traction on body 1 (q, 2) at the chords ``s`` of the contact curve for the field u,
        with the sample points (their ``normal`` is the contact normal used)."""
        pts = self.with_offset(sample_points(self.geom, s))
        jump, flux, size = contact_operators(self, pts)
        _, t1, _ = _tractions(self, pts, jump, flux, size, u[self.dofs], a)
        return pts, t1

    def is_symmetric(self) -> bool:
        """Whether the contact terms are symmetric (no friction traction in a slip zone)."""
        return not (self.slip_sign != 0.0 and self.friction > 0.0)


    def start_step(self) -> None:
        """Before a load step: frictional contacts restart their stick-ratio root."""
        self.centre_tries = []
        if self.kind == "frictional":
            if self.stick_ratio <= 0.0:
                self.stick_ratio = StickRoot.min_ratio
            self._stick_root = StickRoot(self.options.stick_tolerance)


    def update_stick_and_shape(self, x: np.ndarray, a: float, info, final: bool = True) -> bool:
        """After a width search at fixed stick ratio and centre: move the region's centre to the
        pressure's centroid, then (once the centre has settled) update c/a from the transmitted
        forces (root of sqrt(1 - |Q|/(mu N)) - c/a); True when both are consistent."""
        if not self._update_centre(x, a, info, final):
            return False
        if self.kind != "frictional":
            return True
        on2 = -_contact_force(self, info, x, a)
        normal, tangential = float(-on2 @ self.geom.normal), float(on2 @ self.geom.tangent)
        nxt, finished = self._stick_root.update(self.stick_ratio, normal, tangential, self.friction)
        self.beta = tangential / normal if normal > 0 else math.nan
        if self.options.friction_traction and tangential != 0.0:
            sign = math.copysign(1.0, tangential)
            if sign != self.slip_sign and self.stick_ratio < 1.0:
                finished = False  # the friction traction pointed the wrong way
            self.slip_sign = sign
        if not finished:
            self.stick_ratio = nxt
        return finished


    def _update_centre(self, x: np.ndarray, a: float, info, final: bool) -> bool:
        """Move the centre to the pressure's centroid; True when it moved by less than the width
        search's tolerance (``edge_tolerance`` cells in the last load step, ``step_tolerance``
        before), or when the centre is fixed (``region_centre = "point"``)."""
        if self.options.region_centre != "pressure" or info is None or a <= 0.0 or self.mirror:
            return True
        if self.pinned:
            if self._release(x, a, info):
                return False
            self.at_width(a)
            return True
        if self._pin(x, a, info):
            return False
        centroid = _pressure_centroid(self, info, x, a)
        if not math.isfinite(centroid):
            return True  # no compression: nothing to centre on (the width search reports it)
        tol = settling_tolerance(self.options, self.h, final)
        lo, hi = -self.geom.s_limits[1] + a, self.geom.s_limits[0] - a  # keep the region in range
        nxt = float(np.clip(centroid, min(lo, 0.0), max(hi, 0.0)))
        if abs(nxt - self.centre) <= tol:
            return True
        self.centre, settled = self._next_centre(nxt, tol)
        return settled

    def _next_centre(self, centroid: float, tol: float) -> tuple[float, bool]:
        """(the next centre, whether the centre has settled) from the centroid the current one
        gave. The centroid itself while the centroid's offset keeps its sign; once two centres
        bracket the point where the centre equals its centroid (moving to each centroid in turn
        can swing between two centres without end, as a pin in a bore under a turning load did),
        false position within the bracket, and settled when the bracket is narrower than ``tol``
        (the centroid jumps there as points change zone: the end with the smaller offset)."""
        tries = self.centre_tries
        tries.append((self.centre, centroid - self.centre))
        ahead = [t for t in tries if t[1] > 0.0]  # centres whose centroid lies beyond them (+s)
        behind = [t for t in tries if t[1] < 0.0]
        if not ahead or not behind:
            return centroid, False
        lo, hi = min(((p, q) for p in ahead for q in behind), key=lambda pq: abs(pq[0][0] - pq[1][0]))
        if abs(hi[0] - lo[0]) <= tol:
            return min((lo, hi), key=lambda t: abs(t[1]))[0], True
        return lo[0] - lo[1] * (hi[0] - lo[0]) / (hi[1] - lo[1]), False

    def _pin(self, x: np.ndarray, a: float, info) -> bool:
        """Pin the region at a corner of body 1 when one end has reached it (a complete end) while
        the other, incomplete end is still too small (its end value positive): the region then
        grows away from the corner (a punch with one sharp and one rounded edge); or when both ends
        are corners and one of them is in tension (its end value negative) while the other is
        compressed: that end cannot be a corner, and the region shrinks from it towards the other
        corner (a tilted flat punch)."""
        kinds = self.end_types(a)
        values = _end_values(self, info, x, a) if "complete" in kinds and "symmetry" not in kinds else None
        if values is None:
            return False
        if kinds[0] != kinds[1]:  # one corner: the other, incomplete end must still be too small
            free = -1 if kinds[0] == "incomplete" else 1
            if not values.coefficient(free) > 0.0:
                return False
        else:  # two corners: one in tension, the other compressed
            lower, upper = values.coefficient(-1), values.coefficient(1)
            if not (min(lower, upper) < 0.0 < max(lower, upper)):
                return False
            free = -1 if lower < 0.0 else 1
        self.pinned = -free
        self.at_width(a)
        return True

    def _release(self, x: np.ndarray, a: float, info) -> bool:
        """Release a pinned corner that is in tension (its end value negative: the region was pinned
        at the wrong corner, e.g. one reached first from a contact point beside it): pinned at the
        other end instead when that end is a compressed corner, else free (centred on the pressure
        again). True when the region changed."""
        values = _end_values(self, info, x, a)
        if values is None or values.coefficient(self.pinned) >= 0.0:
            return False
        other = -self.pinned
        kinds = self.end_types(a)
        self.pinned = other if kinds[(other + 1) // 2] == "complete" and values.coefficient(other) > 0.0 else 0
        self.at_width(a)
        return True

    def finish(self) -> list[str]:
        """After the last load step: gross slip, reported."""
        if self.kind != "frictional":
            return []
        self.gross_slip = bool(self.stick_ratio == 0.0 and abs(self.beta) >= self.friction * (1.0 - 1e-6))
        if not self.gross_slip:
            return []
        return [f"{self.name}: gross slip, |Q|/N = {abs(self.beta):.4g} >= mu = {self.friction:g}: no stick zone; solved with "
                "full sliding friction (the constraints still hold the bodies)"]


    def check_final(self, u: np.ndarray, a: float, info, bracket, block: dict) -> list[str]:
        """Judge the final state (displacement u) and record it in the contact ``block`` of the
        summary (``checks``, and ``gross_slip`` for friction); the messages of every contact
        condition it fails (empty: the state is consistent)."""
        x = u[self.dofs]
        messages = []
        v = self.judge(x, a, info)
        force1 = _contact_force(self, info, x, a)  # force on body 1 from body 2
        on2 = -force1
        nrm, tan = self.geom.normal, self.geom.tangent
        if v.penetration or v.tension:
            messages.append(
                f"{self.name}: final state has penetration {v.penetration} (edge gap {v.gap:.3g} m) and tension "
                f"{v.tension} (edge pressure {v.pressure:.3g} Pa) at a = {a:.6g} m"
            )
        elif v.penetration_count:
            # the window verdicts look one cell beyond the edges: the bodies may still overlap
            # farther out (a region found far too small, even empty); never report that as solved
            messages.append(
                f"{self.name}: the bodies interpenetrate outside the contact region at {v.penetration_count} "
                f"sample points (smallest gap {v.min_gap:.3g} m) at a = {a:.6g} m: the region search did not "
                "find the contact (refine the grid near the contact, or check the contact point and loads)"
            )
        if messages and a <= self.h:
            messages.append(
                f"{self.name}: the region found has a half-width of {a:.3g} m, at most one finest cell ({self.h:.3g} m): the "
                "contact is smaller than the grid resolves and needs a finer grid there (more refinement levels "
                "around the contact, or a smaller element_size)"
            )
        centred = a > 0.0 and not (self.mirror or self.pinned)  # a pinned region's centre is not its centroid
        offset = (_pressure_centroid(self, info, x, a) - self.centre) / a if centred else 0.0
        if abs(offset) > CENTROID_TOLERANCE:
            messages.append(
                f"{self.name}: the pressure's centroid lies {offset:+.3g} a from the contact region's centre "
                f"(s = {self.centre:.6g} m): the region is off-centre, so its two ends cannot both be consistent "
                "(region_centre = \"pressure\" centres it)"
            )
        block["checks"] = {"penetration": bool(v.penetration or v.penetration_count), "tension": v.tension,
                           "centroid_offset": offset,
                           "edge_penetration": v.penetration, "edge_gap": v.gap,
                           "edge_pressure": v.pressure, "penetration_points": v.penetration_count,
                           "tension_points": v.tension_count, "min_gap": v.min_gap, "min_pressure": v.min_pressure,
                           "half_width_bracket": list(bracket), "force_on_first": force1.tolist(),
                           "edge_coefficient": v.edge}
        block["ends"] = self.ends_block(x, a, info)
        if self.kind == "frictional":
            messages += self.friction_checks(x, a, info, on2, block)
        return messages

    def friction_checks(self, x: np.ndarray, a: float, info, on2: np.ndarray, block: dict) -> list[str]:
        """Coulomb's checks of the final state into ``block`` (and ``gross_slip``); their messages."""
        messages = []
        nrm, tan = self.geom.normal, self.geom.tangent
        nf, qf = float(-on2 @ nrm), float(on2 @ tan)
        ca = math.sqrt(max(0.0, 1.0 - abs(qf) / (self.friction * nf))) if nf > 0 else math.nan
        block["checks"].update({"stick_ratio": self.stick_ratio, "stick_ratio_from_forces": ca,
                                "force_ratio": qf / nf if nf > 0 else math.nan,
                                "friction_traction": self.options.friction_traction})
        block["checks"].update(_friction_checks(self, info, x, a, block))
        block["gross_slip"] = self.gross_slip
        if not nf > 0.0:
            messages.append(f"{self.name}: the contact carries no compressive normal force (N = {nf:.3g}): no stick "
                            "zone follows from the forces")
        elif not abs(ca - self.stick_ratio) <= 2.0 * self.options.stick_tolerance:
            messages.append(f"{self.name}: c/a = {self.stick_ratio:.4g} but the forces give sqrt(1 - |Q|/(mu N)) = {ca:.4g}")
        return messages


    def gap_shape(self, a: float) -> np.ndarray:
        """Coefficients of the half-plane pressure of the initial gap's shape over the region
        of half-width a (solver.contact.ends.gap_pressure): the traction recovery adds it to
        its modes, so a gap that is not quadratic (a rounded punch) keeps its pressure's shape."""
        return _gap_coefficients(self, a)

    def ends_block(self, x: np.ndarray, a: float, info) -> list[dict]:
        """The region's two ends for the summary: where (s), their type, the edge coefficient
        Q / (c_0 / 2) and, at a complete end, the stress intensity K = lim p sqrt(2 pi r)."""
        values = _end_values(self, info, x, a)
        out = []
        for which, end, kind in zip((-1, 1), self.region_ends(a), self.end_types(a)):
            item = {"s": float(end), "type": kind}
            if values is not None and kind != "symmetry":
                item["edge_coefficient"] = values.coefficient(which)
                if kind == "complete":
                    item["stress_intensity"] = values.stress_intensity(which, a)
            out.append(item)
        return out

    def history_entry(self, v: _Verdict, a: float, step: int, iteration: int, tag: int, ratio: float) -> None:
        self.history.append({"step": step, "iteration": iteration, "a": a, "penetration": v.penetration,
                          "tension": v.tension, "edge_gap": v.gap, "edge_pressure": v.pressure,
                          "edge_coefficient": v.edge, "stick_ratio": self.stick_ratio,
                          "stick_iteration": tag, "work_ratio": ratio})


#: trial widths, evenly spread over one finest cell about the edge coefficient's root, whose
#: straight line gives the final width (:func:`_cell_averaged`)
CELL_AVERAGE_WIDTHS = 4


def _cell_averaged(search, h: float, a_max: float):
    """The edge search ``search`` (a generator of trial widths returning (width, bracket)), then
    the root of the straight line through the edge coefficient at CELL_AVERAGE_WIDTHS widths
    evenly spread over one finest cell h about its root, and a last trial at that width; the
    bracket returned spans the search's and that width.

    The edge coefficient g(a) is smooth in a but carries a small wiggle of period h: the discrete
    pressure near the region's end depends on where the end lies in its cell. Its root moved
    with the grid's position along the contact (the half disc R = 1 on a block, finest cell
    3.1e-3 m: over grid offsets along the block by fractions of a cell, 5.1e-5 m, against 2.5e-6 m
    across it); the line through g over one whole period averages the wiggle out (1.7e-5 m)."""
    a0, bracket = yield from search
    if CELL_AVERAGE_WIDTHS < 2:
        return a0, bracket
    widths = a0 + (np.arange(CELL_AVERAGE_WIDTHS) + 0.5 - 0.5 * CELL_AVERAGE_WIDTHS) / CELL_AVERAGE_WIDTHS * h
    if not 0.5 * h < widths[0] or widths[-1] > a_max:
        return a0, bracket
    values = []
    for a in widths:
        verdict = yield float(a)
        values.append(verdict.edge)
    values = np.asarray(values, dtype=float)
    if not np.isfinite(values).all():
        return a0, bracket
    slope, intercept = np.polyfit(widths - a0, values, 1)
    if not slope < 0.0:  # g falls as the region grows; anything else is not a root to refine
        return a0, bracket
    a = float(np.clip(a0 - intercept / slope, a0 - h, min(a0 + h, a_max)))
    yield a
    # the bracket spans the plain root's bracket and the width returned
    return a, (min(bracket[0], a), max(bracket[1], a))


def locate_cells(b, x, n) -> np.ndarray:
    """Cells holding boundary points (nudged into the material, as the grid assigns pieces)."""
    cells = b.grid.locate(x - 1e-7 * b.grid.min_size * n)
    if (cells < 0).any():
        bad = x[cells < 0][0]
        raise ValueError(f"body {b.name!r}: the contact region's point {np.round(bad, 9).tolist()} lies outside the "
                         "body's grid: the region reaches where the body has no material (check that the "
                         "bodies meet there: the contact point, the bodies' placement and sizes)")
    return cells


def _smoothstep(t: np.ndarray) -> np.ndarray:
    """3 t^2 - 2 t^3 on [0, 1], 0 below, 1 above: continuous with its slope."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


@dataclass
class Support:
    """Which cells represent a body at boundary points: each point's own cell, the cell behind
    it (across the face where the inward normal leaves the own cell) and the own cell's weight
    (the fields are weight x own + (1 - weight) x behind, both bilinear fields at the point)."""

    own: np.ndarray
    behind: np.ndarray
    weight: np.ndarray

    def size(self, grid) -> np.ndarray:
        """The cell size at each point, blended as the fields are (sets the band delta)."""
        return self.weight * grid.size[self.own] + (1.0 - self.weight) * grid.size[self.behind]


def _support(b, x, n, depth_fraction: float) -> Support:
    """The support of boundary points x (outward normals n) of body b: a point lying d deep in
    its own cell along the inward normal (the distance to where -n leaves the cell) takes the
    own cell's fields with the weight smoothstep(d / (depth_fraction h)) and those of the cell
    behind with the rest.

    Near the face where the inward normal leaves the cell the own cell holds only a sliver of
    material under the point: its stress (the flux) is unreliable and its far nodes are held by
    a fragment. A switch between the two cells at a fixed thickness made the result jump as the
    surface moved through its cells (the half disc on a block: a by 2.2e-4 m between grid offsets
    0.10 and 0.15 of the finest cell); the blend is continuous in the surface's position, and as
    the surface crosses into the next cell the weight goes to 0 where the old cell becomes the
    cell behind. The depth over which it blends is small (an eighth of a cell by default): the
    field behind is extrapolated over at most that depth (a blend over half a cell scattered a
    by 1.6e-4 m over the grid offsets, an eighth by 1.4e-5 m). ``depth_fraction`` 0: own cells
    only."""
    own = locate_cells(b, x, n)
    if depth_fraction <= 0.0:
        return Support(own, own, np.ones(len(own)))
    g = b.grid
    lower, h = g.lower[own], g.size[own]
    inward = -np.asarray(n, dtype=float)
    t = np.full(x.shape, np.inf)
    np.divide(lower + h[:, None] - x, inward, out=t, where=inward > 1e-12)
    np.divide(lower - x, inward, out=t, where=inward < -1e-12)
    depth = np.clip(t.min(axis=1), 0.0, None)
    behind = g.locate(x + (depth + 1e-6 * h)[:, None] * inward)
    weight = _smoothstep(depth / (depth_fraction * h))
    missing = behind < 0
    weight[missing] = 1.0
    return Support(own, np.where(missing, own, behind), weight)


def _blended(op_own, op_behind, weight: np.ndarray, dim: int = 2):
    """weight x op_own + (1 - weight) x op_behind for (dim q, m) point operators."""
    w = np.repeat(weight, dim)
    if np.all(w == 1.0):
        return op_own
    return sp.diags(w) @ op_own + sp.diags(1.0 - w) @ op_behind


def _body_operators(b, x, n, normal, dof_map, node_ok, depth_fraction: float):
    """Displacement and traction (sigma . normal) operators of body b at its points x, and the
    local size there, from the blended support."""
    sup = _support(b, x, n, depth_fraction)
    used = np.concatenate([sup.own, sup.behind[sup.weight < 1.0]])
    if not node_ok[b.grid.cells[used]].all():
        raise RuntimeError("contact terms reach beyond the contact dofs")
    disp = b.displacement_operator(x, sup.own, dof_map)
    trac = b.traction_operator(x, sup.own, normal, dof_map)
    if (sup.weight < 1.0).any():
        disp = _blended(disp, b.displacement_operator(x, sup.behind, dof_map), sup.weight)
        trac = _blended(trac, b.traction_operator(x, sup.behind, normal, dof_map), sup.weight)
    return disp, trac, sup.size(b.grid)


def contact_operators(c: BandContact, pts):
    """Jump J and flux F (2q, m) on the contact dofs and the local size at contact points (the
    smaller of the two bodies' blended cell sizes)."""
    map1, ok1, map2, ok2 = c.maps
    f = c.options.sliver_fraction
    d1, t1, h1 = _body_operators(c.b1, pts.x1, pts.n1, pts.n1, map1, ok1, f)
    d2, t2, h2 = _body_operators(c.b2, pts.x2, pts.n2, pts.n1, map2, ok2, f)
    th1, th2 = flux_weights(c.options.flux, c.b1, c.b2)
    flux = th1 * t1
    if th2:
        flux = flux + th2 * t2
    return (d1 - d2).tocsr(), sp.csr_matrix(flux), np.minimum(h1, h2)


def zone_projector(c: BandContact, pts, a: float) -> np.ndarray:
    """Constrained components of the jump per point: all where tied (|s| <= stick half-width,
    eq. 5-20), the contact normal n_c where sliding (eqs. 5-22, 5-23)."""
    tied = c.tied_mask(pts.s, a)
    return np.where(tied[:, None, None], projector("fixed", pts.normal), projector("sliding", pts.normal))


def region_quadrature(c: BandContact, a: float):
    """Quadrature points of the region e - a <= s <= e + a, split at both grids' lines and at the
    stick zone's ends (where the projector changes), with the jump and flux operators and the
    local size there: (points, jump, flux, size)."""
    lo, hi = c.region_ends(a)
    brk = np.concatenate([c.breakpoints, c.zone_breakpoints(a)])
    pts = c.with_offset(contact_quadrature(c.geom, (c.b1.grid, c.b2.grid), lo, hi, c.options.order, brk))
    return (pts,) + contact_operators(c, pts)


def _terms(c: BandContact, a: float):
    """Contact stiffness and load on the contact dofs (sparse m x m, m) for half-width a."""
    m = len(c.dofs)
    if a <= 0.0:
        return sp.csr_matrix((m, m)), np.zeros(m), None
    pts, jump, flux, size = region_quadrature(c, a)
    bp = BoundaryPoints(pts.x1, pts.weights, pts.normal, size, jump, flux)
    proj = zone_projector(c, pts, a)
    k, f = thin_band_terms(bp, proj, -pts.delta, *c.layer, c.band_fraction, 1.0, jump=jump)
    kc = sp.csr_matrix(k)
    e_q, f_q = sp.csr_matrix(jump), sp.csr_matrix(flux)
    slip = _slip_mask(c, pts, a)
    if slip.any():
        # friction traction of the slip zone (eq. 5-24), linear in the contact dofs through the
        # pressure p = n_c . (-L w + P F x) = r x + b: body 1 gets t_f = -sign mu p t_c, whose
        # virtual work moves to the left side as the non-symmetric K_f = sum w g^T r with
        # g = (-sign mu t_c)^T J (docs/contact.md); exact for the width, no inner iteration
        r, b = _pressure_rows(c, pts, proj, e_q, f_q, size)
        tdir = -(c.slip_signs(pts.s, a) * c.friction)[:, None] * tangents(pts.normal)  # (q, 2) per unit pressure
        g = _along(e_q, tdir)  # (q, m)
        wq = np.where(slip, pts.weights, 0.0)
        kc = (kc - g.T @ (sp.diags(wq) @ r)).tocsr()
        f = f + g.T @ (wq * b)
    return kc, f, (pts, bp, proj, e_q, f_q, size)


def tangents(normal: np.ndarray) -> np.ndarray:
    """(q, 2) tangent t_c = (-n_y, n_x) of each contact normal."""
    return np.stack([-normal[:, 1], normal[:, 0]], axis=1)


def _slip_mask(c: BandContact, pts, a: float) -> np.ndarray:
    """Points of the slip zone c <= |s| <= a that carry a friction traction."""
    return c.slip_signs(pts.s, a) != 0.0


def _pressure_rows(c: BandContact, pts, proj, e_q, f_q, size):
    """Pressure at points as an affine function of the contact dofs: p = r @ x + b (r (q, m), sparse)."""
    nc = pts.normal
    layer = (PENALTY_FACTOR / (c.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nc, *c.layer) @ proj
    )
    nl = np.einsum("qi,qij->qj", nc, layer)  # n^T L (q, 2)
    npf = np.einsum("qi,qij->qj", nc, proj)  # n^T P
    r = (_along(f_q, npf) - _along(e_q, nl)).tocsr()
    b = -np.einsum("qi,qi->q", nl, pts.delta)
    return r, b


def _along(op, v: np.ndarray):
    """Rows v_q . (op x)_q of an operator op (2 q, m) giving a 2-vector per point: (q, m), sparse."""
    return sp.diags(v[:, 0]) @ op[0::2] + sp.diags(v[:, 1]) @ op[1::2]


def _friction_traction(c: BandContact, pts, t1: np.ndarray, a: float) -> np.ndarray:
    """Friction traction (q, 2) on body 1 in the slip zone: -sign mu p t_c with p = t1 . n_c."""
    signs = c.slip_signs(pts.s, a)
    slip = signs != 0.0
    out = np.zeros_like(t1)
    if slip.any():
        p = np.einsum("qi,qi->q", t1, pts.normal)
        out[slip] = (-signs[slip] * c.friction * p[slip])[:, None] * tangents(pts.normal[slip])
    return out


def _tractions(c: BandContact, samples, e_op: np.ndarray, f_op: np.ndarray, size: np.ndarray, x: np.ndarray, a: float):
    """Normal gap (ns,), traction on body 1 (ns, 2) and the inside mask at sample points, from
    the contact dof values x: the layer's -4/(3 delta) P A P w plus the flux P F (zero outside a)."""
    w = (e_op @ x).reshape(-1, 2) + samples.delta
    nc = samples.normal
    gap = np.einsum("qi,qi->q", w, nc)
    inside = np.abs(c.local(samples.s)) <= a
    proj = zone_projector(c, samples, a)
    layer = (PENALTY_FACTOR / (c.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nc, *c.layer) @ proj
    )
    t1 = -np.einsum("qij,qj->qi", layer, w) + np.einsum("qij,qj->qi", proj, (f_op @ x).reshape(-1, 2))
    t1 = t1 + _friction_traction(c, samples, t1, a)
    t1[~inside] = 0.0
    return gap, t1, inside


def _sample_state(c: BandContact, x: np.ndarray, a: float):
    """Normal gap (ns,) and contact pressure (ns,) at the samples for contact dof values x."""
    gap, t1, inside = _tractions(c, c.samples, c.e_samples, c.f_samples, c.size_samples, x, a)
    return gap, np.einsum("qi,qi->q", t1, c.samples.normal), inside


@dataclass
class _Verdict:
    """Contact conditions at the region's edges. ``gap`` / ``pressure``: the smaller of the two
    sides' mean normal gap just outside / mean pressure just inside, over a window of
    ``c.options.window`` cells; the counts are the thesis's per-sample counts."""

    penetration: bool
    tension: bool
    gap: float
    pressure: float
    penetration_count: int
    tension_count: int
    min_gap: float
    min_pressure: float
    edge: float = math.nan  # edge coefficient (see _edge_coefficient); > 0: a too small


def _quadrature_traction(c: BandContact, info, x: np.ndarray, a: float) -> np.ndarray:
    """Traction (q, 2) on body 1 at the quadrature points of the region, friction included."""
    pts, _, proj, e_q, f_q, size = info
    w = (e_q @ x).reshape(-1, 2) + pts.delta
    nc = pts.normal
    layer = (PENALTY_FACTOR / (c.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nc, *c.layer) @ proj
    )
    t1 = -np.einsum("qij,qj->qi", layer, w) + np.einsum("qij,qj->qi", proj, (f_q @ x).reshape(-1, 2))
    return t1 + _friction_traction(c, pts, t1, a)


def _end_values(c: BandContact, info, x: np.ndarray, a: float):
    """Q at the region's two ends (solver.contact.ends) of the pressure at the quadrature points,
    the truncation of the gap's own shape removed; a conformal contact (pairs along their own
    normals) takes in the degree-4 moments as far as the grid resolves them. None without
    compression."""
    if info is None or a <= 0.0:
        return None
    pts = info[0]
    p = np.einsum("qi,qi->q", _quadrature_traction(c, info, x, a), pts.normal)
    s, w, p = mirrored(c.local(pts.s), chord_weights(c.geom, pts), p, c.mirror)
    higher = conformal_weight(a, c.h) if c.geom.normal_mode == "pair" and not _faceted(c) else 0.0
    return chebyshev_ends(s / a, w, p, a, _gap_coefficients(c, a), higher, corner=c.pinned)


def _gap_coefficients(c: BandContact, a: float) -> np.ndarray:
    """The Chebyshev coefficients b_k of (E*/2) times the initial normal gap's slope over the
    region (solver.contact.ends), the slope interpolated in the sample points' (every 1/16 cell)."""
    if _faceted(c):
        # the thesis's variant on tessellated boundaries: a faceted gap's slope jumps at every
        # vertex, and its "shape" is the tessellation's error, not the part's: the degree-2 sum
        return np.zeros(GAP_NODES)
    s, slope = _gap_slope(c)
    return gap_slope_coefficients(lambda x: np.interp(x, s, slope), c.centre, a, c.e_star, c.mirror)


def _gap_slope(c: BandContact) -> tuple[np.ndarray, np.ndarray]:
    """The initial normal gap's slope dh/ds at the sample chords (central differences; exact for a
    gap quadratic in s), computed once."""
    if "slope" not in c._gap_cache:
        s = c.samples.s
        h = np.einsum("qi,qi->q", c.samples.delta, c.samples.normal)
        order = np.argsort(s)
        s, h = s[order], h[order]
        keep = np.concatenate([[True], np.diff(s) > 0.0])
        s, h = s[keep], h[keep]
        c._gap_cache["slope"] = (s, np.gradient(h, s) if len(s) > 2 else np.zeros_like(s))
    return c._gap_cache["slope"]


def _faceted(c: BandContact) -> bool:
    """Whether the contact curves are tessellated polylines (``exact_geometry = false``)."""
    return any(getattr(getattr(b, "boundary", None), "tolerance", 0.0) > 0.0 for b in (c.b1, c.b2))


def _edge_coefficient(c: BandContact, info, x: np.ndarray, a: float) -> float:
    """Mean edge coefficient of the region's two ends, (Q(e + a) + Q(e - a)) / (2 Q_mean) with Q
    the pressure times sqrt(a^2 - (s - e)^2), from the pressure's Chebyshev moments of degree
    <= 2 less what the gap's own shape contributes to them (solver.contact.ends; for a gap
    quadratic in s, Hertz's and Mindlin's, nothing: int p (4 x^2 - 1) ds / int p ds).

    Q(+-a) != 0 is the square-root singularity of a region too small (Q > 0: a punch's edges) or
    the tension of one too large (Q < 0); the consistent width has Q(+-a) = 0. An integral of
    the traction over the whole region: unlike point or cell values it does not see the
    grid-periodic oscillation of the discrete traction, and its quadrature points move
    continuously with a (the pieces end at +-a exactly): a continuous, grid-position
    independent function of a whose root is the width."""
    values = _end_values(c, info, x, a)
    if values is None:
        return -math.inf if info is not None and a > 0.0 else math.inf
    return values.coefficient(-c.pinned) if c.pinned else values.edge()


#: the final check: the pressure's centroid within this fraction of a of the region's centre (a
#: region about the contact point of a contact that is not symmetric about it, example 7 with
#: region_centre "point": 0.021 a; centred regions: below 1e-3 cells)
CENTROID_TOLERANCE = 0.01


def _pressure_centroid(c: BandContact, info, x: np.ndarray, a: float) -> float:
    """int p s ds / int p ds over the region (nan without compression)."""
    if info is None or a <= 0.0:
        return math.nan
    pts = info[0]
    wp = chord_weights(c.geom, pts) * np.einsum("qi,qi->q", _quadrature_traction(c, info, x, a), pts.normal)
    total = float(wp.sum())
    return float(wp @ pts.s) / total if total > 0.0 else math.nan


def _judge(c: BandContact, gap, pressure, inside, a) -> _Verdict:
    s = c.local(c.samples.s)
    p_mean = max(float(np.mean(pressure[inside])) if inside.any() else 0.0, 0.0)
    g_tol = c.options.gap_tolerance * c.h * max(p_mean, 1e-30) / c.e_star
    p_tol = c.options.tension_tolerance * p_mean
    width = c.options.window * c.h
    # a pinned end is body 1's corner: nothing of body 1 lies beyond it to penetrate (a sample at
    # the corner itself, outside by round-off, reads the singular corner's gap)
    outside = ~inside
    if c.pinned and a > 0:
        outside &= c.pinned * s < a
    gaps, pressures = [], []
    for sgn in (1.0, -1.0):
        r = sgn * s
        out_w = (r > a) & (r <= a + width) & outside
        in_w = (r <= a) & (r > a - width) & inside
        gaps.append(float(gap[out_w].mean()) if out_w.any() else np.inf)
        pressures.append(float(pressure[in_w].mean()) if in_w.any() else np.inf)
    g, p = min(gaps), min(pressures)
    return _Verdict(
        penetration=bool(g < -g_tol),
        tension=bool(a > 0 and p < -p_tol),
        gap=g,
        pressure=p,
        # overlap beyond the edge windows (which the means above judge, the discrete traction's
        # oscillation at the edge included): a region found too small; without a region, any
        penetration_count=int((outside & ((np.abs(s) > a + width) | (a <= 0)) & (gap < -g_tol)).sum()),
        tension_count=int((inside & (pressure < -p_tol)).sum()) if p_mean > 0 else 0,
        min_gap=float(gap[outside].min()) if outside.any() else 0.0,
        min_pressure=float(pressure[inside].min()) if inside.any() else 0.0,
    )


def _contact_force(c: BandContact, info, x: np.ndarray, a: float) -> np.ndarray:
    """Force (2,) on body 1 from body 2: the traction integrated over the region."""
    if info is None:
        return np.zeros(2)
    return (_quadrature_traction(c, info, x, a) * info[0].weights[:, None]).sum(axis=0)


def _friction_checks(c: BandContact, info, x: np.ndarray, a: float, block: dict) -> dict:
    """Coulomb's conditions on the returned state: in the slip zone the tangential jump (the
    slip of body 1 on body 2) must point along slip_sign (the friction traction opposes it); in
    the stick zone the shear profile must stay within mu times the pressure profile. Reported as
    the fractions of each zone (by length) where they fail; not used to steer the iterations."""
    out = {"slip_direction_violations": 0.0, "slip_against_traction": 0.0, "stick_shear_above_mu_p": 0.0}
    if info is not None and c.slip_sign != 0.0:
        pts, e_q = info[0], info[3]
        w = (e_q @ x).reshape(-1, 2) + pts.delta
        wt = np.einsum("qi,qi->q", w, tangents(pts.normal))
        slip = _slip_mask(c, pts, a)
        scale = max(float(np.abs(wt[slip]).max()) if slip.any() else 0.0, 1e-300)
        wrong = slip & (wt * c.slip_sign < -1e-6 * scale)
        if slip.any():
            out["slip_direction_violations"] = float(pts.weights[wrong].sum() / pts.weights[slip].sum())
            # the same by the slip's amount: a zone whose inner part creeps back by a few per cent of
            # the slip counts little, a whole end slipping the other way about half
            amount = pts.weights * np.abs(wt)
            out["slip_against_traction"] = float(amount[wrong].sum() / max(float(amount[slip].sum()), 1e-300))
    s = np.asarray(block["shear"]["s"])
    stick = np.abs(c.local(s)) <= min(c.stick(a), a)
    if stick.any():
        q = np.abs(np.asarray(block["shear"]["value"])[stick])
        p = np.asarray(block["pressure"]["value"])[stick]
        out["stick_shear_above_mu_p"] = float(np.mean(q > 1.02 * c.friction * np.maximum(p, 0.0)))
    return out


def _neighbours(grid, cells: np.ndarray) -> np.ndarray:
    """The cells around ``cells`` (their eight neighbours, finer ones included): where a point's
    cell behind (:func:`_support`) may lie, whatever the point's position in its own cell."""
    if not len(cells):
        return cells
    centre = grid.lower[cells] + 0.5 * grid.size[cells][:, None]
    g = np.array([-1.2, -0.75, -0.25, 0.25, 0.75, 1.2])
    offs = np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
    near = grid.locate((centre[:, None, :] + grid.size[cells][:, None, None] * offs[None]).reshape(-1, 2))
    return near[near >= 0]


def _setup_contact(model, geom, b1, b2, band_fraction: float) -> BandContact:
    """The contact's dofs (every cell the candidate region touches), finest cell and sample
    operators."""
    opts = model.options
    s_plus, s_minus = geom.s_limits
    bk = grid_breakpoints(geom, (b1.grid, b2.grid), -s_minus, s_plus)
    # finest cell along the candidate region of body 1
    near = chain_pieces(geom, 0, b1.grid, -s_minus, s_plus)
    h = float(min(b1.grid.size[b1.grid.pieces.cell[near]].min(), b2.grid.min_size))
    # dofs of every cell the candidate region touches: the pieces of both curves in range and
    # the cells of the (dense) sample points
    ds = opts.sample_spacing * h
    n_plus, n_minus = int(math.ceil(s_plus / ds)), int(math.ceil(s_minus / ds))
    s = np.concatenate([-np.linspace(s_minus, 0, n_minus + 1)[:-1], np.linspace(0, s_plus, n_plus + 1)])
    samples = sample_points(geom, s)
    full = contact_quadrature(geom, (b1.grid, b2.grid), -s_minus, s_plus, opts.order, bk)
    cells1, cells2 = [], []
    for pts in (samples, full):
        for b, x, nn, out in ((b1, pts.x1, pts.n1, cells1), (b2, pts.x2, pts.n2, cells2)):
            sup = _support(b, x, nn, opts.sliver_fraction)
            out += [sup.own, _neighbours(b.grid, np.unique(sup.own[sup.weight < 1.0]))]
    cells1, cells2 = np.concatenate(cells1), np.concatenate(cells2)
    dofs = np.union1d(_cell_dofs_global(b1, cells1), _cell_dofs_global(b2, cells2))
    c = BandContact(model=model, geom=geom, b1=b1, b2=b2, kind=model.type, dofs=dofs, h=h, samples=samples,
                    e_samples=None, f_samples=None, size_samples=None, e_star=0.0, breakpoints=bk,
                    stick_ratio={"tied": math.inf, "frictionless": 0.0}.get(model.type, 1.0),
                    friction=float(model.friction or 0.0) if model.type == "frictional" else 0.0,
                    options=opts, band_fraction=band_fraction)
    c.maps = b1.restricted_dof_map(dofs) + b2.restricted_dof_map(dofs)
    jump, flux, size = contact_operators(c, samples)
    c.e_samples, c.f_samples = jump, flux
    c.size_samples = size
    c.e_star = 1.0 / (1.0 / plane_modulus(b1.elasticity) + 1.0 / plane_modulus(b2.elasticity))
    return c



def build(problem, model, b1, b2, options) -> BandContact:
    """The band formulation of ``model`` (a ContactModel with its point resolved) between the
    discretised bodies b1, b2; ``options`` the problem's SolverOptions."""
    opts = model.options
    geom = contact_geometry((b1, b2), model.bodies, np.asarray(model.point, dtype=float),
                            problem.candidate_extent(model, opts.extent_fraction))
    geom.normal_mode = opts.contact_normal
    if getattr(model, "moved_from", None) is not None:  # the scene's point, at a corner of body 1
        geom.given_point = np.asarray(model.moved_from, dtype=float)
    contact = _setup_contact(model, geom, b1, b2, options.band_fraction)
    contact.mirror = _symmetry_side(problem, geom, model.bodies[0])
    return contact


def _symmetry_side(problem, geom: ContactGeometry, body: str) -> int:
    """+1 / -1 when the contact point lies on a corner of body 1 that bounds one side of the
    region (a half model cut through the contact), after checking that the edge beyond it is a
    symmetry line (a sliding condition holds there); 0 otherwise."""
    side = geom.mirror_side()
    if not side:
        return 0
    chain = geom.curves[0]
    edge = chain.edge_at(geom.t_origin[0] - 0.5 * side * geom.directions[0])
    sliding = any(isinstance(bc, Sliding) and bc.body == body and bc.edge == edge for bc in problem.boundary_conditions)
    if not sliding:
        raise ValueError(
            f"contact {geom.bodies[0]}/{geom.bodies[1]}: the contact point {geom.point.tolist()} lies on a corner of "
            f"body {body!r} (edges {geom.edges[0]!r} and {edge!r}); a contact region can end there only on a "
            f"symmetry line, which needs a sliding condition on edge {edge!r} (or give a point inside an edge)"
        )
    return side
