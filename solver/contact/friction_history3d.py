"""Partial slip with memory between solids (3D): the ellipse formulation (solver.contact.ellipse)
whose stick and slip zones are found point by point on the region's quadrature points from
Coulomb's law on the increments of a load path.

State, kept per quadrature point from step to step (carried to a new region's points by the
nearest point of the last one when the normal load moves the region):

- the tangential jump w_t (the relative tangential displacement of body 1 on body 2, a vector
  in the tangent plane) at the end of the last step, and the jump w_ref at which a stuck point
  is held (a point stuck since the last step keeps it: the tie's elastic stretch is not slip; a
  point that slipped or was open takes the jump at which the tie carries the traction it
  carried, so that its traction is continuous when it sticks);
- the zone of the current step (stuck or slipping), the slip direction e of a slipping point
  (the direction of its slip increment; Coulomb's traction on body 1 is -mu p e), the
  accumulated slip and the friction work.

A step starts with every point stuck (the elastic predictor) at the last step's region. After
each solve a stuck point whose shear |q| exceeds mu p by 2 % starts slipping against its shear
(e = -q / |q|, kept while it slips), and a slipping point whose increment
dw_t = w_t - w_t(last step) runs against e (or whose pressure vanishes) sticks again; repeated
until nothing changes (a point stuck again twice within a step stays stuck for the rest of it;
after 15 updates, until at most 0.05 % of the points change).
The pressure p of Coulomb's law (the limit mu p and the slipping points' traction) is the
region's edge-consistent fit of the point pressures (solver.contact.friction_history_pressure:
sqrt(1 - X^2 - Y^2) times a quadratic with the same moments up to the second order): the point
pressures of trilinear cells oscillate with the grid (up to +-60 % of the mean pressure) and
cannot follow the square root at the region's edge, where a slip annulus lies (measured on the
half sphere at a / h = 5.8: 0.6 % of N beyond 0.95 a, Hertz 3.0 %; the fit: 2.9 %). The shear is
judged on its means over a disc of one cell about each point among points of the same zone
(the point tractions oscillate, their means do not). (Letting a slipping point's direction
follow its increment within a step was tried: where the slip is small its increment's direction
is noise, thousands of points turned at every update and the zones never settled.)
Zones of any number and direction follow (stick, forward slip, reversed slip); none is assumed.
A stuck point is tied by the contact's thin band terms; its tangential tie sits on a layer
``TANGENTIAL_BAND`` times the contact's band (1 by default; measured on the fretting example, the
loop's energy at Q*/(mu N) = 0.3 hangs on that tie's stiffness, the whole stick zone's, and does
not settle as it stiffens; the diagnostic ties of solver.contact.friction_history_ties, each
cell's stuck points by their mean jump, drift alike: docs/load-paths.md).
Every trial is one solve of the condensed system on the contact dofs (the driver's factor of the
bodies' stiffness and its Schur complement are formed once per run); the region's size is kept
through a step's zone updates and searched again only where its edge coefficient shows that the
normal load moved it.

The stick zone is reported as ``stick_semi_axes``: the ellipse of the region's shape (and the
model's sector) with the stick zone's area, read from the quadrature weights of the stuck
points (for the concentric stick circle of a sphere, its radius).

Reference: R. D. Mindlin, H. Deresiewicz, J. Appl. Mech. 20 (1953) 327-344; K. L. Johnson,
Contact Mechanics (1985), sections 7.2 and 7.3 (closed forms in solver.reference.fretting_sphere).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..fem.step_boundary import PENALTY_FACTOR, BoundaryPoints, projector, thin_band_terms
from .ellipse import (PANELS_PER_CELL, REGION_ORDER, EllipseContact, build as ellipse_build, contact_operators,
                      layer_tensor, plane_weights, point_blocks, pressure_rows)
from .ellipse_geometry import region_points
from .graded_quadrature import leaf_size
from .disc_means import DiscBins
from .band import locate_cells
from .friction_history import hold_size
from .friction_history_pressure import PressureFit, low_rank, pressure_fit
from .friction_history_profiles import axis_profiles
from . import friction_history_ties as ties

__all__ = ["HistoryEllipseContact", "build"]

#: a stuck point starts slipping when its mean shear exceeds mu p by this fraction
SLIP_MARGIN = 0.02
#: ... a point stuck again in the same step only above this fraction
RESLIP_MARGIN = 0.1
#: a slipping point sticks when its increment runs against its direction by more than this
#: fraction of the step's largest increment
REVERSAL_MARGIN = 1e-3
#: the means that judge the zones are taken over a disc of this many cells in diameter
MEAN_CELLS = 1.0
#: a stuck point within the disc of the region's edge averages only over the points at most twice
#: its distance from the edge (a window symmetric about it, as at the slip zone)
EDGE_WINDOWS = True
#: region quadratures kept (by size): the width search tries a few, the zone updates one (the
#: ``--check`` estimate counts as many regions: solver.model.estimate.HISTORY_REGIONS)
KEEP_REGIONS = 3
#: a zone update re-assembles only its changed points while they are at most this share of all
INCREMENTAL_SHARE = 0.3
#: after this many zone updates in a step, an update that changes at most LATE_CHANGE_SHARE of the
#: points (at least one) settles the step: the points still changing sit at Coulomb's limit within
#: the grid's oscillation of the point tractions (measured: the first step after a reversal, whose
#: reversed slip annulus is thinner than a cell, had one to five of 10 456 points changing at every
#: update from the 18th to the 30th)
LATE_UPDATES = 15
LATE_CHANGE_SHARE = 5e-4
#: the stuck points' tangential tie is a layer this many times the contact's band (its stiffness
#: divided by it); the normal tie, and so the normal contact, keeps the contact's band
TANGENTIAL_BAND = 1.0
#: the region's quadrature follows the cells it lies in (PANELS_PER_CELL panels per cell of each
#: size, solver.contact.graded_quadrature) instead of the finest cell's panels everywhere: a grid
#: refined further only about the contact's edge (a ring of finer cells) then adds points only
#: there (measured on the fretting example with a ring one level finer about its edge: 31 446
#: points against 45 036 at a = 0.0449 m, the cheap stick-circle measure 0.95 GB and 30 s CPU
#: against 1.16 GB and 41 s); a region in cells of the finest size only keeps the ellipse's panels
GRADED_QUADRATURE = True


@dataclass
class _Region:
    """A region of size a: its quadrature data, the layer's tangential stiffness per point, the
    same-zone mean operator and the step's state carried onto its points."""

    a: float
    info: tuple
    layer_t: np.ndarray  # (q,) PENALTY / (band h) mu: the tie's tangential stiffness per area
    neighbours: DiscBins  # the bins of the region's points for the same-zone disc means
    w_ref: np.ndarray  # (q, 3)
    w_prev: np.ndarray  # (q, 3)
    accumulated: np.ndarray  # (q,)
    last_direction: np.ndarray  # (q, 3)
    #: (slip, direction, stiffness, load, Coulomb's left factor) of the last terms assembled on it
    #: (None: none since the references changed)
    assembled: tuple | None = None
    #: the pressure Coulomb's law uses (solver.contact.friction_history_pressure)
    fit: PressureFit | None = None
    #: (q,) each point's group of the diagnostic mean ties (solver.contact.friction_history_ties)
    group: np.ndarray | None = None
    #: (slip, flux) the diagnostic recovered flux (3 q, m) for the zones slip (friction_history_ties)
    recovered: tuple | None = None
    #: (q, 3) the jump at which a stuck point is held exactly by the diagnostic augmented-Lagrangian
    #: ties (friction_history_ties.UZAWA_TOLERANCE; w_ref is then the tie's anchor, moved by them)
    hold: np.ndarray | None = None


def _unit_radius(phi: np.ndarray) -> np.ndarray:
    """The ellipse as a star-shaped region: its radius function is 1."""
    return np.ones_like(np.asarray(phi, dtype=float))


def _tangential(v: np.ndarray, normal: np.ndarray) -> np.ndarray:
    return v - np.einsum("qi,qi->q", v, normal)[:, None] * normal


def _tie_projectors(normal: np.ndarray, slip: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(normal, tangential) projectors of the ties: every point tied along the normal, the stuck
    ones also in the tangent plane (their sum is the stuck points' "fixed" projector; the
    acoustic tensor couples no normal to tangential component, so the two layers add exactly)."""
    p_normal = projector("sliding", normal)
    eye = np.broadcast_to(np.eye(normal.shape[1]), p_normal.shape)
    return p_normal, np.where(slip[:, None, None], 0.0, eye - p_normal)


@dataclass
class HistoryEllipseContact(EllipseContact):
    """Ellipse contact with Coulomb friction on increments; see the module's docstring."""

    history_rule = "incremental Coulomb: stick/slip state, slip direction and accumulated slip carried per point"
    shape_iterated = False  # b / a stays Hertz's under a path: the points' memory lives on it
    regions: dict = field(default_factory=dict)  # a -> _Region of this step
    carrier: object = None  # the _Region of the last step's end (its state is the memory)
    x_prev: np.ndarray | None = None  # contact dofs at the last step's end
    zone_s: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))  # points of the zones below
    slipping: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    direction: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    restuck: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    settled_stuck: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    hold_width: bool = False
    width_held: bool = False
    held_edge: float = math.nan
    step_count: int = 0
    zone_updates: int = 0
    zone_changes: int = 0
    unsettled_steps: list = field(default_factory=list)
    late_settled: list = field(default_factory=list)  # [step, points still changing] settled late
    #: the diagnostic augmented-Lagrangian ties: the updates of each step, the step's stretch history, the
    #: steps that ended on UZAWA_UPDATES updates with their history (friction_history_ties.UZAWA_TOLERANCE)
    uzawa_updates: list = field(default_factory=list)
    uzawa_history: list = field(default_factory=list)
    uzawa_unconverged: list = field(default_factory=list)
    step_work: float = 0.0
    step_state: dict = field(default_factory=dict)  # the last step's end: per-point arrays for the records
    #: zones imposed instead of Coulomb's rule (a validation's diagnostic: the closed form's zones
    #: separate the zone rule's error from the discretisation's): an object with
    #: ``zones(contact, s, a, force) -> (slipping, direction)`` and ``step_end(contact, force)``
    #: (None: Coulomb's rule, the module's docstring)
    zone_rule = None

    # ------------------------------------------------------------------ regions and their state

    def region_quadrature(self, a: float):
        """The region's quadrature points on body 1, matched on body 2: with ``GRADED_QUADRATURE``,
        both bodies on octrees and cells coarser than the finest under the region, panels that
        follow the cells they lie in (the ellipse as the star-shaped region of unit radius
        function); else the ellipse's panels of the finest cell (the same points as before)."""
        cells = self.cell_sizes(a) if GRADED_QUADRATURE else None
        if cells is None:
            return super().region_quadrature(a)
        aa, bb = self.semi_axes(a)
        return region_points(*self.solids, self.frame, aa, bb, self.ranges, self.grids, self.h / PANELS_PER_CELL,
                             self.reach, REGION_ORDER, centre=self.centre, radius=_unit_radius, cells=cells)

    def cell_sizes(self, a: float):
        """Each body's leaf size at 3D points, or None where a body has no octree or the region of
        size a lies in cells of the finest size only (read on a polar lattice of its points)."""
        grids = [getattr(getattr(self, n, None), "grid", None) for n in ("b1", "b2")]
        if not all(hasattr(g, "locate") for g in grids):
            return None
        cells = tuple(leaf_size(g, spacing) for g, (_, spacing) in zip(grids, self.grids))
        aa, bb = self.semi_axes(a)
        r = np.linspace(0.0, 1.0, 17)[:, None]
        phi = np.concatenate([np.linspace(t0, t1, 129) for t0, t1 in self.ranges])[None, :]
        s = self.centre + np.column_stack([(aa * r * np.cos(phi)).ravel(), (bb * r * np.sin(phi)).ravel()])
        y = self.frame.point + s[:, :1] * self.frame.axes[0] + s[:, 1:] * self.frame.axes[1]
        nudge = 1e-6 * self.h * self.frame.normal  # just inside each body: body 1 above the tangent plane
        coarsest = max(float(np.max(cells[0](y + nudge))), float(np.max(cells[1](y - nudge))))
        return cells if coarsest > 1.5 * self.h else None

    def region(self, a: float) -> _Region:
        """The region of size a with the memory carried onto its points (cached for the step)."""
        if a in self.regions:
            return self.regions[a]
        pts = self.region_quadrature(a)
        if not len(pts.s):
            raise ValueError(f"{self.name}: body 1 has no surface under the trial contact ellipse of semi-axes "
                             f"{np.round(self.semi_axes(a), 6).tolist()} m")
        jump, flux, size = contact_operators(self, pts)
        info = (pts, BoundaryPoints(pts.x1, pts.weights, pts.normal, size, jump, flux), None, jump, flux, size, a)
        layer_t = PENALTY_FACTOR / (TANGENTIAL_BAND * self.band_fraction * size) * self.layer[1]
        radius = 0.5 * MEAN_CELLS * self.options.window * self.h
        neighbours = DiscBins.build(pts.s, plane_weights(self, pts), radius)
        carried, hold = self._carried(pts, jump, flux, layer_t)
        reg = _Region(a, info, layer_t, neighbours, *carried, hold=hold)
        fixed = projector("fixed", pts.normal)  # the pressure rows are the same for either zone's projector
        r, b = pressure_rows(self, (pts, None, fixed, jump, flux, size, a))
        reg.fit = pressure_fit(self.local(pts.s), self.semi_axes(a), pts.weights, r, b)
        if ties.CUT_CELL_TIE != "points":
            reg.group = ties.tie_groups(self.local(pts.s), self.h, locate_cells(self.b1, pts.x1, pts.n1),
                                        locate_cells(self.b2, pts.x2, pts.n2))
        self.regions[a] = reg
        for old in list(self.regions)[:-KEEP_REGIONS]:
            del self.regions[old]
        return reg

    def _carried(self, pts, jump, flux, layer_t):
        """((w_ref, w_prev, accumulated slip, last direction), hold) at new points: the nearest point of the
        last step's region where inside it; elsewhere a point entering contact, stuck with no
        traction at the jump of the last step's end."""
        q = len(pts.s)
        if self.x_prev is None:
            return (np.zeros((q, 3)), np.zeros((q, 3)), np.zeros(q), np.zeros((q, 3))), np.zeros((q, 3))
        w = _tangential((jump @ self.x_prev).reshape(-1, 3) + pts.delta, pts.normal)
        f = _tangential((flux @ self.x_prev).reshape(-1, 3), pts.normal)
        w_ref, w_prev, hold = w - f / layer_t[:, None], w.copy(), w.copy()
        acc, last = np.zeros(q), np.zeros((q, 3))
        old = self.carrier
        if old is not None:
            old_pts = old.info[0]
            inside = self.normalised_radius(pts.s, old.a) <= 1.0
            if np.array_equal(old_pts.s, pts.s):
                idx, inside = np.arange(q), np.ones(q, dtype=bool)
            else:
                idx = cKDTree(old_pts.s).query(pts.s)[1]
            w_ref[inside], w_prev[inside] = old.w_ref[idx[inside]], old.w_prev[idx[inside]]
            acc[inside], last[inside] = old.accumulated[idx[inside]], old.last_direction[idx[inside]]
            hold[inside] = (old.w_ref if old.hold is None else old.hold)[idx[inside]]
        return (w_ref, w_prev, acc, last), hold

    def zones_at(self, reg: _Region) -> tuple[np.ndarray, np.ndarray]:
        """(slipping, direction) of the current zones at a region's points."""
        s = reg.info[0].s
        if len(self.zone_s) == len(s) and np.array_equal(self.zone_s, s):
            return self.slipping, self.direction
        if not len(self.zone_s):
            return np.zeros(len(s), dtype=bool), np.zeros((len(s), 3))
        idx = cKDTree(self.zone_s).query(s)[1]
        return self.slipping[idx], self.direction[idx]

    def _set_zones(self, reg: _Region, slipping: np.ndarray, direction: np.ndarray) -> None:
        if not np.array_equal(self.zone_s, reg.info[0].s):  # a new region: its points start afresh
            self.restuck = np.zeros(len(slipping), dtype=bool)
            self.settled_stuck = np.zeros(len(slipping), dtype=bool)
        self.zone_s, self.slipping, self.direction = reg.info[0].s, slipping, direction

    # ------------------------------------------------------------------ terms and tractions

    def terms(self, a: float):
        """Stiffness, load and quadrature data of the region of size a with the current zones: stuck
        points tied at their reference jump, slipping points sliding along the normal with
        Coulomb's traction -mu p e, p the region's fitted pressure (affine in the dofs: a
        non-symmetric block of rank 6, left factor times the fit's rows). The terms are sums over
        the points: after a zone update only the points that changed are assembled again (their
        new terms added, their old ones taken away)."""
        m = len(self.dofs)
        if a <= 0.0:
            return sp.csr_matrix((m, m)), np.zeros(m), None
        reg = self.region(a)
        pts, bp, _, jump, flux, size, _ = reg.info
        slip, direction = self.zones_at(reg)
        grouped = self._grouped(reg, slip)
        free = slip | grouped  # no tangential tie of its own
        bands = ties.tangential_bands(pts.s, slip, self.h, TANGENTIAL_BAND)
        proj = np.where(free[:, None, None], projector("sliding", pts.normal), projector("fixed", pts.normal))
        info = (pts, bp, proj, jump, flux, size, a)
        rec = self._recovered_flux(reg, slip)
        old = reg.assembled if rec is None else None  # a recovered flux couples a point's terms to its neighbours' zones
        if old is not None:
            changed = np.flatnonzero((old[0] != slip) | (old[2] != free) | (old[3] != bands)
                                     | np.any(old[1] != direction, axis=1))
            if len(changed) <= INCREMENTAL_SHARE * len(slip):
                k_new, f_new, l_new = self._point_terms(reg, changed, slip, direction, free, bands)
                k_old, f_old, l_old = self._point_terms(reg, changed, old[0], old[1], old[2], old[3])
                parts = ((old[4] + k_new - k_old).tocsr(), old[5] + f_new - f_old, old[6] + l_new - l_old)
            else:
                parts = self._point_terms(reg, np.arange(len(slip)), slip, direction, free, bands)
        else:
            parts = self._point_terms(reg, np.arange(len(slip)), slip, direction, free, bands, rec)
        reg.assembled = (slip.copy(), direction.copy(), free.copy(), bands.copy()) + parts
        k_tie, f, left = parts
        if grouped.any():  # the diagnostic mean ties (solver.contact.friction_history_ties)
            mean, area, stiffness, _, _ = ties.mean_operator(reg.group, grouped, pts.weights, pts.normal, reg.layer_t)
            k_g, f_g = ties.mean_terms(mean, area, stiffness, jump, flux, pts.delta - reg.w_ref)
            k_tie, f = (k_tie + k_g).tocsr(), f + f_g
        if slip.any():
            return (k_tie - low_rank(left, reg.fit.rows, m)).tocsr(), f + left @ reg.fit.load, info
        return k_tie, f, info

    def _recovered_flux(self, reg: _Region, slip: np.ndarray):
        """(3 q, m) the diagnostic flux of the stuck points' tangential tie for the zones slip, or
        None for the bodies' mean stress at the point (``friction_history_ties.TIE_FLUX`` and
        ``RECOVERED_FLUX``)."""
        if ties.RECOVERED_FLUX is None and ties.TIE_FLUX == "mean":
            return None
        if reg.recovered is None or not np.array_equal(reg.recovered[0], slip):
            pts = reg.info[0]
            flux = ties.body_flux(self, pts, reg.info[4])
            if ties.RECOVERED_FLUX is not None:
                mean = ties.recovery_operator(pts.s, pts.weights, ~slip, 0.5 * ties.RECOVERED_FLUX * self.h)
                flux = (mean @ flux).tocsr()
            reg.recovered = (slip.copy(), flux)
        return reg.recovered[1]

    @staticmethod
    def _grouped(reg: _Region, slip: np.ndarray) -> np.ndarray:
        """(q,) the stuck points tied by their group's mean (solver.contact.friction_history_ties)."""
        if reg.group is None:
            return np.zeros(len(slip), dtype=bool)
        return ties.grouped(reg.group, slip)

    def _point_terms(self, reg: _Region, idx: np.ndarray, slip: np.ndarray, direction: np.ndarray,
                     free: np.ndarray | None = None, bands: np.ndarray | None = None, recovered=None):
        """(ties' stiffness, ties' load, Coulomb's left factor (m, k)) of the points idx of a region
        with zones (slip, direction): Coulomb's traction of the slipping points, -mu p e with p =
        B (R x + r0) the fitted pressure, adds -left R to the stiffness and left r0 to the load.
        The points ``free`` (the slipping ones and the stuck ones tied by their cell pair's mean)
        have no tangential tie of their own."""
        m = len(self.dofs)
        fit = reg.fit
        free = slip if free is None else free
        bands = np.full(len(slip), TANGENTIAL_BAND) if bands is None else bands
        if not len(idx):
            return sp.csr_matrix((m, m)), np.zeros(m), np.zeros((m, fit.basis.shape[1]))
        pts, _, _, jump, flux, size, a = reg.info
        rows = (3 * idx[:, None] + np.arange(3)).ravel()
        sl, fr, e = slip[idx], free[idx], direction[idx]
        normal, delta = pts.normal[idx], pts.delta[idx]
        sub_jump, sub_flux = jump[rows], flux[rows]
        bp = BoundaryPoints(pts.x1[idx], pts.weights[idx], normal, size[idx], sub_jump, sub_flux)
        target = -(delta - np.where(fr[:, None], 0.0, reg.w_ref[idx]))
        if recovered is None and np.all(bands[idx] == 1.0):  # one layer: a stuck point fixed, a slipping one sliding
            proj = np.where(fr[:, None, None], projector("sliding", normal), projector("fixed", normal))
            k, f = thin_band_terms(bp, proj, target, *self.layer, self.band_fraction, 1.0, jump=sub_jump)
        else:  # the normal tie on the contact's layer, the stuck points' tangential one on its own
            p_normal, p_tangential = _tie_projectors(normal, fr)
            k, f = thin_band_terms(bp, p_normal, target, *self.layer, self.band_fraction, 1.0,
                                   jump=sub_jump)
            if p_tangential.any():
                bp_t = bp if recovered is None else BoundaryPoints(pts.x1[idx], pts.weights[idx], normal, size[idx],
                                                                   sub_jump, recovered[rows])
                k_t, f_t = thin_band_terms(bp_t, p_tangential, target, *self.layer,
                                           bands[idx] * self.band_fraction, 1.0, jump=sub_jump)
                k, f = k + k_t, f + f_t
        left = np.zeros((m, fit.basis.shape[1]))
        if sl.any():
            g = point_blocks(-self.friction * np.where(sl[:, None], e, 0.0)) @ sub_jump
            wq = np.where(sl, pts.weights[idx], 0.0)
            left = np.asarray(g.T @ (wq[:, None] * fit.basis[idx]))
        return sp.csr_matrix(k), np.asarray(f).ravel(), left

    def point_state(self, x: np.ndarray, a: float, info):
        """Per quadrature point: traction on body 1 (q, 3), the fitted pressure p (the one Coulomb's
        law uses), tangential shear (q, 3) and tangential jump w_t (q, 3)."""
        reg = self.region(a)
        pts, _, _, jump, flux, size, _ = info
        slip, direction = self.zones_at(reg)
        grouped = self._grouped(reg, slip)
        free = slip | grouped
        w = (jump @ x).reshape(-1, 3) + pts.delta
        held = w - np.where(free[:, None], 0.0, reg.w_ref)
        p_normal, p_tangential = _tie_projectors(pts.normal, free)
        bands = ties.tangential_bands(pts.s, slip, self.h, TANGENTIAL_BAND)
        layer = layer_tensor(self, pts.normal, p_normal, size) \
            + layer_tensor(self, pts.normal, p_tangential, size) / bands[:, None, None]
        fx = (flux @ x).reshape(-1, 3)
        rec = self._recovered_flux(reg, slip)
        fx_t = fx if rec is None else (rec @ x).reshape(-1, 3)
        t1 = -np.einsum("qij,qj->qi", layer, held)
        t1 = t1 + np.einsum("qij,qj->qi", p_normal, fx) + np.einsum("qij,qj->qi", p_tangential, fx_t)
        if grouped.any():  # the diagnostic mean ties: one traction per group on its stuck points
            mean, _, stiffness, g, idx = ties.mean_operator(reg.group, grouped, pts.weights, pts.normal, reg.layer_t)
            t1[idx] += ties.mean_traction(mean, stiffness, w - reg.w_ref, fx)[g]
        p = reg.fit.pressure(x)
        t1 = t1 - np.where(slip[:, None], self.friction * p[:, None] * direction, 0.0)
        return t1, p, _tangential(t1, pts.normal), _tangential(w, pts.normal)

    def _means(self, reg: _Region, v: np.ndarray, slip: np.ndarray) -> np.ndarray:
        """Means of v (q,) or (q, 3) over the disc about each point, among points of the same zone;
        a stuck point's window is kept symmetric about it within the stick zone: only the stuck
        points at most twice its distance d from the slip zone (for a straight boundary, the
        points whose mirror image through it is stuck too). A mean over the whole stick side of
        the disc, mostly deeper points, is centred about 0.4 of the disc's radius inside: where the
        shear rises towards the boundary it held the boundary too far out (measured on the
        half sphere at Q/(mu N) = 0.45, a / h = 5.8: c/a 0.855 against Mindlin's 0.821 for its
        forces; with the symmetric windows 0.825 against 0.822).
        Far from a boundary (d beyond the disc) it is the plain mean over the disc."""
        bins, n = reg.neighbours, len(slip)
        vv = v.reshape(n, -1)
        out = np.zeros_like(vv)
        radius = bins.radius
        d = np.zeros(n) if slip.any() else np.full(n, np.inf)  # the distance to the slip zone
        if slip.any() and not slip.all():  # a slipping point's is 0: only the stuck points are queried
            d[~slip] = cKDTree(reg.info[0].s[slip]).query(reg.info[0].s[~slip])[0]
        e = self._edge_distance(reg) if EDGE_WINDOWS else np.full(n, np.inf)
        windowed = ~slip & (np.minimum(d, e) < radius)
        near = np.flatnonzero(windowed)
        for m in (slip, ~slip):  # plain means among the points of the same zone
            rows = np.flatnonzero(m & ~windowed)
            out[rows] = bins.means(vv, m, rows)
        if len(near):  # stuck points within the disc of the slip zone or of the region's edge: symmetric windows
            tol = 1e-12 * self.h

            def limit(c_rows):  # a row farther than the disc from the zone or edge takes every bin
                return np.where(c_rows >= radius, np.inf, 2.0 * c_rows + tol)
            out[near] = bins.means(vv, ~slip, near, ((d, d[near], limit), (e, e[near], limit)))
        return out.reshape(v.shape)

    def _edge_distance(self, reg: _Region) -> np.ndarray:
        """(q,) each point's distance to the region's edge along the ray from the centre."""
        length = np.linalg.norm(self.local(reg.info[0].s), axis=1)
        rho = self.normalised_radius(reg.info[0].s, reg.a)
        inner = rho > 1e-9  # the centre is on no ray: far from the edge
        out = np.full(len(rho), np.inf)
        out[inner] = length[inner] * np.maximum(1.0 - rho[inner], 0.0) / rho[inner]
        return out

    def force(self, x: np.ndarray, a: float, info) -> np.ndarray:
        if info is None:
            return np.zeros(3)
        return (self.point_state(x, a, info)[0] * info[0].weights[:, None]).sum(axis=0)

    def quadrature_traction(self, info, x: np.ndarray) -> np.ndarray:
        return self.point_state(x, info[6], info)[0]

    def is_symmetric(self) -> bool:
        return not bool(np.any(self.slipping))

    # ------------------------------------------------------------------ the driver's protocol

    def start_step(self) -> None:
        self.zone_updates = self.zone_changes = 0
        self.zone_s = np.zeros((0, 2))
        self.slipping, self.direction = np.zeros(0, dtype=bool), np.zeros((0, 3))
        self.restuck = np.zeros(0, dtype=bool)
        self.settled_stuck = np.zeros(0, dtype=bool)
        self.hold_width = self.width_held = self.step_count > 0
        self.step_count += 1

    def region_search(self, a0: float, final: bool, max_iterations: int, estimate: bool = False):
        """The size search; between zone updates the size is kept (one solve), and searched again
        only where the kept size's edge coefficient shows it moved."""
        if self.hold_width:
            return hold_size(self, a0)
        return super().region_search(a0, final, max_iterations, estimate)

    def _width_consistent(self, a: float) -> bool:
        return abs(self.held_edge) <= self.options.edge_tolerance * self.h / a

    def update_stick_and_shape(self, x: np.ndarray, a: float, info, final: bool = True) -> bool:
        """Centre, then the zones (see the module's docstring); True when nothing changed and the
        size is consistent with the zones."""
        if not self._update_centre(x, a, info, final):
            return False
        if info is None:
            return True
        if self.width_held and self.zone_updates == 0 and not self._width_consistent(a):
            self.hold_width = self.width_held = False  # the normal load moved the region: search it first
            return False
        if not self._update_zones(x, a, info):
            self.hold_width = self.width_held = True
            return False
        self.hold_width = False
        if self.width_held:
            self.width_held = False
            if not self._width_consistent(a):
                return False
        if not self._uzawa(x, a, info):
            self.hold_width = self.width_held = True
            return False
        return True

    def _uzawa(self, x: np.ndarray, a: float, info) -> bool:
        """One update of the diagnostic augmented-Lagrangian ties of the stuck points
        (``friction_history_ties.UZAWA_TOLERANCE``; None: none, True): each stuck point's anchor
        moves by its tie's tangential stretch from the jump at which it is held, so that at
        convergence the stuck points are held exactly, their traction the tie's multiplier; True
        when the largest stretch is within the tolerance times the step's largest jump increment
        (or after ``UZAWA_UPDATES`` updates: then listed in ``uzawa_unconverged``)."""
        if ties.UZAWA_TOLERANCE is None:
            return True
        reg = self.region(a)
        pts, jump = info[0], info[3]
        slip, _ = self.zones_at(reg)
        w = _tangential((jump @ x).reshape(-1, 3) + pts.delta, pts.normal)
        stretch = np.where(slip[:, None], 0.0, _tangential(w - reg.hold, pts.normal))
        scale = max(float(np.linalg.norm(w - reg.w_prev, axis=1).max()), 1e-300)
        size = float(np.linalg.norm(stretch, axis=1).max()) / scale
        self.uzawa_history.append(size)
        if size <= ties.UZAWA_TOLERANCE or len(self.uzawa_history) > ties.UZAWA_UPDATES:
            if size > ties.UZAWA_TOLERANCE:
                self.uzawa_unconverged.append([self.step_count, list(self.uzawa_history)])
            self.uzawa_updates.append(len(self.uzawa_history) - 1)
            self.uzawa_history = []
            return True
        reg.w_ref = reg.w_ref - stretch
        reg.assembled = None  # the terms' load holds the anchors
        return False

    def _commit_zones(self, reg, slip: np.ndarray, direction: np.ndarray, changed: int, info) -> bool:
        """Keep a zone update's zones and its stick ratio; True when it settled (no point changed)
        or when the step has used its zone updates: the step is then listed as unsettled and keeps
        the zones of its last solve (its forces, slips and friction work are the solved field's)."""
        if changed and self.zone_updates >= self.options.max_stick_iterations:
            self.unsettled_steps.append(self.step_count)
            return True
        self._set_zones(reg, slip, direction)
        self.zone_changes += changed
        area = plane_weights(self, info[0])
        self.stick_ratio = math.sqrt(float(area[~slip].sum() / max(area.sum(), 1e-300)))
        return changed == 0

    def _imposed_zones(self, x: np.ndarray, a: float, info) -> bool:
        """One update of the zones imposed by ``zone_rule`` for the solved force; True when no
        point changed its zone."""
        reg = self.region(a)
        old, _ = self.zones_at(reg)
        slip, direction = self.zone_rule.zones(self, reg.info[0].s, a, self.force(x, a, info))
        self.zone_updates += 1
        changed = int(np.count_nonzero(old != slip))
        return self._commit_zones(reg, slip, direction, changed, info)

    def _update_zones(self, x: np.ndarray, a: float, info) -> bool:
        """One zone update; True when no point changed its zone."""
        if self.zone_rule is not None:
            return self._imposed_zones(x, a, info)
        reg = self.region(a)
        slip, direction = (v.copy() for v in self.zones_at(reg))
        if len(self.restuck) != len(slip):
            self.restuck = np.zeros(len(slip), dtype=bool)
            self.settled_stuck = np.zeros(len(slip), dtype=bool)
        _, p, q_raw, wt = self.point_state(x, a, info)
        q = self._means(reg, q_raw, slip)  # the fitted pressure p is smooth already
        qn = np.linalg.norm(q, axis=1)
        dw = wt - reg.w_prev
        dwn = np.linalg.norm(dw, axis=1)
        mu = self.friction
        self.zone_updates += 1
        margin = np.where(self.restuck, RESLIP_MARGIN, SLIP_MARGIN)
        over = ~slip & (p > 0.0) & (qn > mu * p * (1.0 + margin)) & ~self.settled_stuck
        floor = 1e-4 * mu * max(float(p.max()), 0.0) * a / self.e_star
        scale = max(float(dwn.max()) if len(dwn) else 0.0, floor, 1e-300)
        along = np.einsum("qi,qi->q", dw, direction)
        back = slip & ((along < -REVERSAL_MARGIN * scale) | (p <= 0.0))
        direction = np.where(over[:, None], -q / np.maximum(qn, 1e-300)[:, None], direction)
        slip = (slip | over) & ~back
        self.settled_stuck |= back & self.restuck
        self.restuck |= back
        changed = int(np.count_nonzero(over | back))
        if changed and self.zone_updates >= LATE_UPDATES and changed <= max(1.0, LATE_CHANGE_SHARE * len(slip)):
            # settled late: the zones of the last solve are kept (the state's forces are those solved)
            self.late_settled.append([self.step_count, changed])
            return True
        return self._commit_zones(reg, slip, direction, changed, info)

    def end_step(self, x: np.ndarray, a: float, info) -> None:
        """Carry the step's state: the slips, their work, the new reference jumps."""
        reg = self.region(a)
        slip, direction = self.zones_at(reg)
        t1, p, q, wt = self.point_state(x, a, info)
        pts = info[0]
        if self.zone_rule is not None:
            self.zone_rule.step_end(self, (t1 * pts.weights[:, None]).sum(axis=0))
        dw = np.where(slip[:, None], wt - reg.w_prev, 0.0)
        # friction work: -sum q . dw dA over the slipping points (positive: dissipated)
        self.step_work = float(-np.sum(np.einsum("qi,qi->q", q, dw) * pts.weights))
        # a slipping point takes the reference at which its tie would carry its Coulomb traction (no
        # jump in its traction when it sticks); a stuck point keeps its own (its traction is the one
        # the step solved, open or not: the step's forces are recorded with these references)
        flux_t = _tangential((info[4] @ x).reshape(-1, 3), pts.normal)
        reg.w_ref = np.where(slip[:, None], wt - (flux_t - q) / reg.layer_t[:, None], reg.w_ref)
        if reg.hold is not None:  # a slipping point would be held where it sticks again
            reg.hold = np.where(slip[:, None], wt, reg.hold)
        reg.assembled = None  # the terms hold the reference jumps: the next step assembles them anew
        reg.accumulated = reg.accumulated + np.linalg.norm(dw, axis=1)
        reg.last_direction = np.where(slip[:, None], direction, reg.last_direction)
        self.step_state = {"pressure": p, "shear": q, "slip": slip, "direction": direction, "slip_increment": dw,
                           "accumulated_slip": reg.accumulated.copy(), "tangential_jump": wt,
                           "weights": plane_weights(self, pts), "s": pts.s, "points": pts.x2}
        reg.w_prev = wt
        self.carrier, self.x_prev = reg, x.copy()
        self.regions = {a: reg}

    def hold_step(self, x: np.ndarray, a: float, info) -> None:
        """Unchanged loads: the state is kept, with no slip increment and no work."""
        self.step_count += 1
        self.step_work = 0.0
        if self.step_state:
            self.step_state = dict(self.step_state, slip_increment=np.zeros_like(self.step_state["slip_increment"]))

    def stick_area(self) -> tuple[float, float]:
        """(stick zone's area, region's area) on the tangent plane at the last step's end."""
        st = self.step_state
        if not st:
            return 0.0, 0.0
        w = st["weights"]
        return float(w[~st["slip"]].sum()), float(w.sum())

    def step_fields(self, u: np.ndarray, a: float, info) -> dict:
        """The step record beside the forces: friction work, slip points, the stick area and the
        profiles along the principal axes (solver.contact.friction_history_profiles)."""
        stick, total = self.stick_area()
        out = {"friction_work": self.step_work, "slip_points": int(np.count_nonzero(self.step_state.get("slip", []))),
               "stick_area": stick, "region_area": total}
        st = self.step_state
        if st and a > 0.0:  # the state along the principal axes through the centre (an array record, not in summary.json)
            out["axis_profile"] = axis_profiles(self.local(st["s"]), st["weights"], self.extent, self.h,
                                                self.frame, self.centre, st)
        return out

    def summary_block(self, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
        block = super().summary_block(a, on2, u, info)
        block["friction_history"] = self.history_rule
        stick, total = self.stick_area()
        block["stick_area"] = stick
        block.setdefault("checks", {})
        return block

    def check_final(self, u: np.ndarray, a: float, info, bracket, block: dict) -> list[str]:
        messages = super().check_final(u, a, info, bracket, block)
        block["checks"]["steps_with_unsettled_zones"] = list(self.unsettled_steps)
        block["checks"]["steps_settled_with_points_changing"] = list(self.late_settled)
        messages += [f"{self.name}: load step {k}: the stick and slip zones did not settle in "
                     f"{self.options.max_stick_iterations} updates" for k in self.unsettled_steps]
        if ties.UZAWA_TOLERANCE is not None:  # the diagnostic exact hold: its stretch's history where it stopped short
            block["checks"]["steps_with_unconverged_exact_hold"] = [k for k, _ in self.uzawa_unconverged]
            messages += [f"{self.name}: load step {k}: the stuck points' largest stretch over the step's largest jump "
                         f"increment did not fall to {ties.UZAWA_TOLERANCE:g} in {ties.UZAWA_UPDATES} augmented-"
                         f"Lagrangian updates (first {h[0]:.3g}, last {h[-1]:.3g})" for k, h in self.uzawa_unconverged]
        return messages


def build(problem, model, b1, b2, options) -> HistoryEllipseContact:
    """The ellipse formulation of ``model`` with friction history."""
    base = ellipse_build(problem, model, b1, b2, options)
    if type(base) is not EllipseContact:
        raise ValueError(f"contact {'/'.join(model.bodies)}: friction with memory under load paths needs a point "
                         "contact (an elliptical region); this contact is a line or flat contact")
    c = HistoryEllipseContact(**{f.name: getattr(base, f.name) for f in dataclasses.fields(EllipseContact)})
    for name in ("grids", "given_point", "reach"):
        setattr(c, name, getattr(base, name))
    c.stick_ratio = 1.0
    return c
