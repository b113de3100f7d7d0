"""The ellipse formulation of a contact between two solids (the thesis's section 7.2):
the band terms of the 2D formulation (solver.contact.band) on an elliptical contact region of
body 1's exact surface, semi-axes (a, b) along the principal axes of the relative curvature
(solver.contact.ellipse_geometry), tied or frictionless.

The region is searched as its size a with the shape b / a held, then the shape updated, as the
2D partial-slip driver iterates the stick ratio: the load-step driver (solver.contact.driver)
runs the size search (``region_search``, the root of the edge coefficient) and then
``update_stick_and_shape``, which here updates b / a and asks for another size search until the shape
settles. Edge coefficients: every Hertzian pressure on the ellipse is
p = Q(X, Y) / sqrt(1 - X^2 - Y^2) with X = s0/a, Y = s1/b and Q quadratic; with the weights
5 X^2 - 1 and 5 Y^2 - 1 the moments int p (5 X^2 - 1) dA and int p (5 Y^2 - 1) dA vanish for
Hertz's p0 sqrt(1 - X^2 - Y^2) (int over the unit disc of sqrt(1 - r^2) = 2 pi / 3, of
X^2 sqrt(1 - r^2) = 2 pi / 15) and are positive for a punch-like pressure (a region too small):
their mean drives the size, their difference the shape. The first shape is Hertz's for the
relative curvatures (solver.reference.theory.hertz_elliptic_contact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..fem.pair_blocks import PairBlocks, RecentRegions
from ..fem.step_boundary import PENALTY_FACTOR, BoundaryPoints, acoustic_tensor, band_tensors, projector
from ..model.options import ContactOptions
from .gap_moments import second_moment_targets, stick_ratio_targets
from .interface_weights import flux_weights, layer_moduli
from .band import CandidateRegionExceeded, locate_cells
from ..reference.theory import hertz_elliptic_contact
from .edge_pressure import agglomerated_cells, nodal_pressure
from .ellipse_geometry import (ContactFrame3D, RegionPoints, axis_points, matched_points,
                               region_points, surface_point, surrounds)
from .roots import edge_search, settling_tolerance
from .touching3d import touching_frame_3d

__all__ = ["EllipseContact", "build"]

#: Gauss order of the triangle rule on the region's pieces
REGION_ORDER = 3
#: panels of the region's quadrature per finest cell
PANELS_PER_CELL = 1.0
#: the shape b / a holds when the two edge coefficients differ by less than this
SHAPE_TOLERANCE = 0.005


@dataclass
class _Verdict:
    penetration: bool
    tension: bool
    gap: float
    pressure: float
    penetration_count: int
    tension_count: int
    min_gap: float
    min_pressure: float
    edge: float = math.nan
    edges: tuple = (math.nan, math.nan)
    overlap: float = math.nan  # how far out the bodies overlap beyond a too small region (_overlap_extent)


@dataclass
class EllipseContact:
    #: the final check's tension read through the squares' corners (regions of general shape)
    corner_reading = False
    #: whether the search iterates the shape b / a (a contact with friction history keeps the shape
    #: it starts with, Hertz's: its points' memory lives on the region's parametrisation); the final
    #: check judges the shape only where it was iterated
    shape_iterated = True
    model: object
    frame: ContactFrame3D
    solids: tuple
    b1: object
    b2: object
    kind: str
    dofs: np.ndarray
    maps: tuple
    h: float
    extent: float
    ranges: list
    samples: RegionPoints
    sample_axis: np.ndarray  # (ns,) 0 or 1: the axis of each sample
    e_samples: object = None
    f_samples: object = None
    size_samples: np.ndarray = None
    ratio: float = 1.0  # b / a
    circular: bool = True
    band_fraction: float = 0.25
    e_star: float = 0.0
    options: ContactOptions = field(default_factory=ContactOptions)
    history: list = field(default_factory=list)
    _shape: list = field(default_factory=list)  # (ratio, c0 - c1) of the settled size searches
    # stick ellipse = stick_ratio x (a, b): tied inside, sliding outside; tied contact: inf,
    # frictionless: 0, frictional: Mindlin's (1 - |Q| / (mu N))^(1/3), iterated
    stick_ratio: float = 0.0
    friction: float = 0.0
    slip_direction: np.ndarray | None = None  # unit tangential force on body 2 (the slip zone's traction on body 1 opposes it)
    beta: float = math.nan  # |Q| / N of the last state
    _stick_root: object = None
    #: the stick ratios the load steps settled at, in order (the next step's start is extrapolated)
    _settled_ratios: list = field(default_factory=list)
    _steps_started: int = 0
    #: the pressure's centroid an earlier load step settled with, where the next step starts
    _next_centre: np.ndarray | None = None
    #: the ellipse's centre in the tangent plane (along the axes): the pressure's centroid where
    #: body 1 has surface all around the contact point and region_centre is "pressure", else 0
    centre: np.ndarray = field(default_factory=lambda: np.zeros(2))
    #: the scene's point where the frame moved to the touching point nearest it (else None)
    given_point: np.ndarray | None = None
    _recent_regions: RecentRegions | None = field(default=None, repr=False)

    @property
    def name(self) -> str:
        return f"contact {self.model.bodies[0]}/{self.model.bodies[1]}"

    def semi_axes(self, a: float) -> tuple[float, float]:
        return a, self.ratio * a

    def normalised_radius(self, s: np.ndarray, a: float) -> np.ndarray:
        """(n,) the region's radial coordinate of tangent-plane points: 1 on its edge."""
        aa, bb = self.semi_axes(a)
        local = self.local(s)
        return np.hypot(local[:, 0] / aa, local[:, 1] / bb)

    def region_quadrature(self, a: float) -> RegionPoints:
        """Quadrature points of the region of size a on body 1, matched on body 2."""
        aa, bb = self.semi_axes(a)
        return region_points(*self.solids, self.frame, aa, bb, self.ranges, self.grids, self.h / PANELS_PER_CELL,
                             self.reach, REGION_ORDER, centre=self.centre)

    def sample_edges(self, s: np.ndarray, axis: np.ndarray, a: float) -> tuple[np.ndarray, np.ndarray]:
        """(inside, distance beyond the edge) of samples at local points s along the frame's axes
        (``axis`` 0 or 1 each): the ellipse's chord along each sample's axis line (through the
        contact point; it misses the centre by the centre's other coordinate)."""
        aa, bb = self.semi_axes(a)
        rows = np.arange(len(s))
        along = np.abs(s[rows, axis])
        across = s[rows, 1 - axis] / np.where(axis == 0, bb, aa)
        reach = np.where(axis == 0, aa, bb) * np.sqrt(np.clip(1.0 - across**2, 0.0, None))
        return along <= reach, along - reach

    def local(self, s: np.ndarray) -> np.ndarray:
        """Tangent-plane coordinates (n, 2) from the ellipse's centre."""
        return np.asarray(s, dtype=float) - self.centre

    @property
    def layer(self) -> tuple[float, float]:
        """(lambda, mu) of the penalty layer's acoustic tensor (solver.contact.interface_weights)."""
        return layer_moduli(self.options.flux, self.b1, self.b2)

    @property
    def surrounds_point(self) -> bool:
        """Whether body 1 has surface all around the contact point (not a symmetric model's
        sector, whose symmetry planes pass through the point)."""
        return surrounds(self.ranges)

    @property
    def centred(self) -> bool:
        """Whether the centre may move: body 1 all around the contact point (a symmetric model's
        symmetry planes hold the centre there)."""
        return self.options.region_centre == "pressure" and self.surrounds_point

    # -------------------------------------------------- the formulation protocol

    def initial_region(self) -> float:
        return 2.0 * self.h

    def next_region(self, a: float, load_ratio: float) -> float:
        return max(a * load_ratio ** (1.0 / 3.0), 2.0 * self.h)

    def region_search(self, a0: float, final: bool, max_iterations: int, estimate: bool = False):
        a_max = max(self.extent - float(np.abs(self.centre).max()), 0.0) / max(1.0, self.ratio)
        tol = settling_tolerance(self.options, self.h, final)
        return edge_search(a0, self.h, tol, a_max, step0=0.05 * self.h if estimate else None)

    def region_too_small(self) -> ValueError:
        return CandidateRegionExceeded(self.model.bodies, "refinement radius", (
            f"{self.name}: the contact ellipse reaches the candidate region's edge ({self.extent:.4g} m) "
            "and still penetrates; enlarge the contact refinement radius"))

    def terms(self, a: float):
        m = len(self.dofs)
        if a <= 0.0:
            return sp.csr_matrix((m, m)), np.zeros(m), None
        # the operators as per-point blocks over each point's two cells (solver.fem.pair_blocks):
        # the terms are summed per cell pair and mapped onto the contact dofs once
        pts, blocks, size = self._region_blocks(a)
        jump, flux = blocks.jump, blocks.flux
        bp = BoundaryPoints(pts.x1, pts.weights, pts.normal, size, jump, flux)
        proj = _projector(self, pts, a)
        pen, wp = band_tensors(bp, proj, *self.layer, self.band_fraction)
        kc, fc = blocks.band_terms(pen, wp, -pts.delta, 1.0)
        info = (pts, bp, proj, jump, flux, size, a)
        slip = _slip_mask(self, pts, a)
        if slip.any():
            # Coulomb's traction mu p on the slip zone, against the slip: p is affine in the contact
            # dofs (p = r x + b), so it enters exactly as a non-symmetric block (the 2D rule)
            nl, npf, b = _pressure_coefficients(self, pts, proj, size)
            g = blocks.rows(np.broadcast_to(-self.friction * self.slip_direction, pts.x1.shape))
            wq = np.where(slip, pts.weights, 0.0)
            kc = (kc - blocks.outer(g, blocks.rows(-nl, npf), wq)).tocsr()
            fc = fc + blocks.vector(g, wq * b)
        return kc, fc, info

    def _region_blocks(self, a: float):
        """The region's quadrature points, their operator blocks and band sizes. They depend on
        the region alone (size, shape, centre), not on the stick zone: a frictional contact keeps
        them for its last two ellipses, so the size search that follows a stick-ratio update, which
        starts at the last size, does not build them again (a region of general shape builds them
        every time)."""
        def build():
            pts = self.region_quadrature(a)
            if not len(pts.s):
                raise ValueError(f"{self.name}: body 1 has no surface under the trial contact ellipse (semi-axes "
                                 f"{np.round(self.semi_axes(a), 6).tolist()} m) about "
                                 f"{np.round(self.frame.point, 6).tolist()}: the contact point is not where the "
                                 "bodies touch; give the contact's point")
            return (pts,) + contact_blocks(self, pts)

        if self.kind != "frictional" or type(self).region_quadrature is not EllipseContact.region_quadrature:
            return build()  # no stick zone to update (or a region of general shape): nothing to reuse
        if self._recent_regions is None:
            self._recent_regions = RecentRegions(keep=2)
        return self._recent_regions.get((a, self.ratio, *self.centre), build)

    def judge(self, x: np.ndarray, a: float, info) -> _Verdict:
        gap, pressure, inside, edge_dist = _sample_state(self, x, a)
        v = _judge(self, gap, pressure, inside, edge_dist)
        v.edges = _edge_coefficients(self, info, x, a)
        v.edge = 0.5 * (v.edges[0] + v.edges[1])
        v.overlap = _overlap_extent(self, gap, inside)
        return v

    def force(self, x: np.ndarray, a: float, info) -> np.ndarray:
        if info is None:
            return np.zeros(3)
        return (_quadrature_traction(self, info, x) * info[0].weights[:, None]).sum(axis=0)

    def traction_samples(self, u: np.ndarray, a: float, s: np.ndarray):
        raise NotImplementedError("3D contacts report their profiles through summary_block")

    def is_symmetric(self) -> bool:
        return not (self.friction > 0.0 and self.slip_direction is not None)

    def start_step(self) -> None:
        self._shape = []
        if self._next_centre is not None:
            self.centre, self._next_centre = self._next_centre, None
        if self.kind == "frictional":
            from .roots import StickRoot

            if self._steps_started:
                self._settled_ratios.append(self.stick_ratio)
            self.stick_ratio = predicted_stick_ratio(self._settled_ratios, self.stick_ratio)
            if self.stick_ratio <= 0.0:
                self.stick_ratio = StickRoot.min_ratio
            self._stick_root = StickRoot(self.options.stick_tolerance, exponent=1.0 / 3.0)
        self._steps_started += 1

    def _update_stick(self, x: np.ndarray, a: float, info, final: bool = True) -> bool:
        """Stick ratio from the transmitted forces (P(c) / P(a) = 1 - |Q| / (mu N) under the
        bodies' gap, Mindlin's cube root for Hertz's) and the slip direction;
        True when both hold. Before the last load step (``final`` false) the direction only starts
        the next step, as the region's size and centre do: its turning does not hold the step."""
        on2 = -self.force(x, a, info)
        normal = float(-on2 @ self.frame.normal)
        tangential = on2 - (on2 @ self.frame.normal) * self.frame.normal
        q = float(np.linalg.norm(tangential))
        nxt, finished = self._stick_root.update(self.stick_ratio, normal, q, self.friction,
                                                self._stick_ratio_of(a))
        self.beta = q / normal if normal > 0 else math.nan
        if q > 0.0:
            e = tangential / q
            turned = self.slip_direction is None or float(e @ self.slip_direction) < 1.0 - 1e-6
            if turned and final:
                finished = finished and self.stick_ratio >= 1.0
            self.slip_direction = e
        if not finished:
            self.stick_ratio = nxt
        return finished

    def initial_sample_gap(self) -> tuple[np.ndarray, np.ndarray]:
        """The axis samples' tangent-plane coordinates (n, 2) from the contact point and the
        bodies' initial gap (n,) there along the contact normal."""
        smp = self.samples
        return np.asarray(smp.s, dtype=float), np.einsum("qi,qi->q", smp.delta, smp.normal)

    def _stick_ratio_of(self, a: float):
        """c / a for a load share 1 - |Q| / (mu N) under the bodies' own gap (Mindlin's cube root
        for Hertz's: solver.contact.gap_moments)."""
        if not a > 0.0:
            return None
        s, gap = self.initial_sample_gap()
        semi_axes = self.semi_axes(a)
        return lambda share: stick_ratio_targets(s, gap, self.sample_axis, semi_axes, share)

    def _update_centre(self, x: np.ndarray, a: float, info, final: bool) -> bool:
        """Move the centre to the pressure's centroid (the 2D rule, solver.contact.band); True when
        it moved by less than the size search's tolerance, or cannot move."""
        if not self.centred or info is None or a <= 0.0:
            return True
        centroid = _pressure_centroid(self, info, x)
        if not np.isfinite(centroid).all():
            return True
        if float(np.abs(centroid - self.centre).max()) <= settling_tolerance(self.options, self.h, final):
            if not final:  # within an earlier step's loose tolerance: the next step starts there
                self._next_centre = centroid
            return True
        self.centre = centroid
        return False

    def update_stick_and_shape(self, x: np.ndarray, a: float, info, final: bool = True) -> bool:
        """After a size search: the centre at the pressure's centroid, then (once it has settled)
        the shape b / a from the difference of the two edge coefficients (secant on log(b / a));
        True when both hold (the shape always for a circular contact)."""
        centred = self._update_centre(x, a, info, final)
        # the stick ratio and slip direction from this state even when the centre moved: the next
        # search starts from them (their change is checked again after it)
        stuck = self._update_stick(x, a, info, final) if self.kind == "frictional" and info is not None else True
        if not centred:
            return False
        if self.circular or info is None:
            return stuck
        c0, c1 = _edge_coefficients(self, info, x, a)
        d = c0 - c1  # > 0: pressure too concentrated at the ends of axis 0: a too small against b
        self._shape.append((math.log(self.ratio), d))
        if abs(d) <= SHAPE_TOLERANCE:
            return stuck
        if len(self._shape) >= 2 and self._shape[-1][1] != self._shape[-2][1]:
            (l0, d0), (l1, d1) = self._shape[-2], self._shape[-1]
            nxt = l1 - d1 * (l1 - l0) / (d1 - d0)
            nxt = min(max(nxt, l1 - 0.3), l1 + 0.3)
        else:
            nxt = math.log(self.ratio) - 0.5 * d  # b / a down when d > 0
        self.ratio = float(min(max(math.exp(nxt), 0.02), 1.0))
        return False

    def finish(self) -> list[str]:
        return []

    def check_final(self, u: np.ndarray, a: float, info, bracket, block: dict) -> list[str]:
        x = u[self.dofs]
        v = self.judge(x, a, info)
        sampled = v.pressure  # the point traction's mean over the axis samples' inner window
        tension_cells = _edge_verdict(self, v, info, x, a)
        messages = []
        unresolved = bool(v.penetration_count) and a <= 0.0  # no region, yet the bodies overlap
        if (v.penetration or v.tension) and not unresolved:  # (an edge pressure at a = 0 is not defined)
            messages.append(f"{self.name}: final state has penetration {v.penetration} (edge gap {v.gap:.3g} m) and "
                            f"tension {v.tension} (edge pressure {v.pressure:.3g} Pa) at semi-axes {self.semi_axes(a)}")
        elif v.penetration_count and a > 0.0:
            messages.append(f"{self.name}: the bodies interpenetrate outside the contact ellipse at "
                            f"{v.penetration_count} sample points (smallest gap {v.min_gap:.3g} m)")
        if unresolved:  # too small for the grid
            messages.append(self._unresolved(v))
        offset = self._centroid_offset(x, a, info)
        if offset > CENTROID_TOLERANCE:
            messages.append(f"{self.name}: the pressure's centroid lies {offset:.3g} of the semi-axes from the contact "
                            f"ellipse's centre {np.round(self.centre, 9).tolist()} m: the ellipse is off-centre "
                            "(region_centre = \"pressure\" centres it)")
        if not self.circular and self.shape_iterated and abs(v.edges[0] - v.edges[1]) > 2.0 * SHAPE_TOLERANCE:
            messages.append(f"{self.name}: the ellipse's shape did not settle (edge coefficients {v.edges[0]:.3g}, "
                            f"{v.edges[1]:.3g})")
        block["checks"] = {"penetration": bool(v.penetration or v.penetration_count), "tension": v.tension,
                           "edge_gap": v.gap, "edge_pressure": v.pressure, "penetration_points": v.penetration_count,
                           "tension_points": v.tension_count, "min_gap": v.min_gap,
                           "min_pressure": v.min_pressure, "edge_samples_pressure": sampled,
                           "tension_cells": tension_cells,
                           "edge_coefficients": list(v.edges),
                           "centroid_offset": offset,
                           "size_bracket": list(bracket)}
        return messages

    def _unresolved(self, v: _Verdict) -> str:
        """The final state has no region while the bodies overlap: the region the edge coefficient
        asks for is below half the finest cell (the search's smallest region). Hertz's estimate
        from the overlap (a^2 = delta / k for the relative curvature k) says how small."""
        k = float(np.sqrt(max(self.frame.curvatures[0], 0.0) * max(self.frame.curvatures[1], 0.0)))
        size = f"about {math.sqrt(-v.min_gap / k):.3g} m by Hertz's estimate from the overlap, " if k > 0 else ""
        return (f"{self.name}: no contact region of at least half the finest cell ({0.5 * self.h:.3g} m) carries "
                f"compression, yet the bodies overlap by up to {-v.min_gap:.3g} m at {v.penetration_count} sample "
                f"points: the contact ({size}smaller than the grid resolves) needs a finer grid there (more "
                "refinement levels around the contact, or a smaller element_size)")

    def _centroid_offset(self, x: np.ndarray, a: float, info) -> float:
        """|pressure centroid - centre| in semi-axes; 0 where body 1 is a symmetric model's sector
        (its centroid is off the contact point by construction)."""
        if info is None or a <= 0.0 or not self.surrounds_point:
            return 0.0
        d = _pressure_centroid(self, info, x) - self.centre
        return float(np.hypot(*(d / np.array(self.semi_axes(a)))))

    def history_entry(self, v: _Verdict, a: float, step: int, iteration: int, tag: int, ratio: float) -> None:
        self.history.append({"step": step, "iteration": iteration, "semi_axes": list(self.semi_axes(a)),
                             "penetration": v.penetration, "tension": v.tension, "edge_coefficients": list(v.edges),
                             "shape_iteration": tag, "work_ratio": ratio})

    def quadrature_traction(self, info, x: np.ndarray) -> np.ndarray:
        """Traction (q, 3) on body 1 at the region's quadrature points for contact dof values x."""
        return _quadrature_traction(self, info, x)

    def on_body1(self, axis: int, s: np.ndarray) -> np.ndarray:
        """Whether body 1 has surface above the points s along one axis (a symmetric model's half)."""
        return _on_body1(self.solids[0], self.frame, axis, s, self.reach)

    def summary_block(self, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
        """The summary.json contact block of a contact between solids."""
        from .ellipse_report import ellipse_block

        return ellipse_block(self, a, on2, u, info)


# ------------------------------------------------------------------ operators and tractions


def _semi_axes_of(pts: RegionPoints) -> np.ndarray:
    """The largest |s| along each axis of a set of region points (the ellipse they cover)."""
    return np.abs(pts.s).max(axis=0) if len(pts.s) else np.zeros(2)


def contact_operators(c: EllipseContact, pts: RegionPoints):
    """Jump J and flux F (3q, m) on the contact dofs, and the local size at the points."""
    cells1, cells2 = _prepared_cells(c, pts)
    map1, _, map2, _ = c.maps
    jump = c.b1.displacement_operator(pts.x1, cells1, map1) - c.b2.displacement_operator(pts.x2, cells2, map2)
    w1, w2 = flux_weights(c.options.flux, c.b1, c.b2)
    flux = w1 * c.b1.traction_operator(pts.x1, cells1, pts.n1, map1) + w2 * c.b2.traction_operator(
        pts.x2, cells2, pts.n1, map2)
    return jump.tocsr(), flux.tocsr(), _band_size(c, cells1, cells2)


def contact_blocks(c: EllipseContact, pts: RegionPoints) -> tuple[PairBlocks, np.ndarray]:
    """The jump and flux of :func:`contact_operators` as per-point blocks over each point's two
    cells (solver.fem.pair_blocks), and the local size at the points."""
    cells1, cells2 = _prepared_cells(c, pts)

    def tractions():  # both bodies' traction blocks again (an older trial region's flux, if asked)
        return (c.b1.cell_blocks(pts.x1, cells1, pts.n1).traction, c.b2.cell_blocks(pts.x2, cells2, pts.n1).traction)

    blocks = PairBlocks.between(c.b1.cell_blocks(pts.x1, cells1, pts.n1), c.b2.cell_blocks(pts.x2, cells2, pts.n1),
                                c.maps[0], c.maps[2], len(c.b1.grid.nodes),
                                flux_weights(c.options.flux, c.b1, c.b2), rebuild=tractions, family=c)
    return blocks, _band_size(c, cells1, cells2)


def _band_size(c: EllipseContact, cells1: np.ndarray, cells2: np.ndarray) -> np.ndarray:
    t1 = c.b1.material_thickness[cells1]
    t2 = c.b2.material_thickness[cells2]
    return np.maximum(np.minimum(t1, t2), 1e-6 * c.b1.grid.size[cells1])


def _prepared_cells(c: EllipseContact, pts: RegionPoints) -> tuple[np.ndarray, np.ndarray]:
    """The cells of both bodies holding the points, checked to lie among those prepared for the
    contact (every dof they depend on is a contact dof)."""
    cells1, cells2 = locate_cells(c.b1, pts.x1, pts.n1), locate_cells(c.b2, pts.x2, pts.n2)
    _, ok1, _, ok2 = c.maps
    bad1 = ~ok1[c.b1.grid.cells[cells1]].all(axis=1)
    bad2 = ~ok2[c.b2.grid.cells[cells2]].all(axis=1)
    if bad1.any() or bad2.any():
        where = pts.x1[bad1][:1].tolist() + pts.x2[bad2][:1].tolist()
        # the region search tried an ellipse that leaves the cells prepared for the contact (the
        # refinement zone around it, a few cells across on a coarse grid): a model limit, said plainly
        raise CandidateRegionExceeded(c.model.bodies, "refinement radius", (
            f"{c.name}: a trial contact ellipse (semi-axes {np.round(_semi_axes_of(pts), 6).tolist()} m) "
            f"reaches beyond the cells prepared for the contact ({int(bad1.sum())} points of body 1, "
            f"{int(bad2.sum())} of body 2, e.g. {np.round(where[0], 6).tolist()}); enlarge the contact "
            f"refinement radius (now {c.extent:.4g} m of reach) or refine the grid there"))
    return cells1, cells2


def _normalised_radius(c: EllipseContact, pts: RegionPoints, a: float) -> np.ndarray:
    return c.normalised_radius(pts.s, a)


def _projector(c: EllipseContact, pts: RegionPoints, a: float) -> np.ndarray:
    """Tied inside the stick ellipse (all of it for tied contact), sliding along the normal
    outside."""
    tied = _normalised_radius(c, pts, a) < c.stick_ratio if a > 0 else np.zeros(len(pts.s), dtype=bool)
    return np.where(tied[:, None, None], projector("fixed", pts.normal), projector("sliding", pts.normal))


def _slip_mask(c: EllipseContact, pts: RegionPoints, a: float) -> np.ndarray:
    """Points of the slip zone (between the stick ellipse and the region's edge) that carry
    Coulomb's traction."""
    if not (c.friction > 0.0 and c.slip_direction is not None) or a <= 0.0:
        return np.zeros(len(pts.s), dtype=bool)
    rho = _normalised_radius(c, pts, a)
    return (rho >= c.stick_ratio) & (rho <= 1.0)


def point_blocks(rows: np.ndarray):
    """Sparse (q, 3q) with row k holding rows[k] in columns 3k..3k+2."""
    import scipy.sparse as sp

    q = len(rows)
    return sp.csr_matrix((rows.ravel(), np.arange(3 * q), np.arange(0, 3 * q + 1, 3)), shape=(q, 3 * q))


def pressure_rows(c: EllipseContact, info):
    """Pressure at the quadrature points as an affine function of the contact dofs: p = r x + b."""
    pts, _, proj, jump, flux, size, _ = info
    nl, npf, b = _pressure_coefficients(c, pts, proj, size)
    return (-(point_blocks(nl) @ jump.tocsr()) + point_blocks(npf) @ flux.tocsr()).tocsr(), b


def _pressure_coefficients(c: EllipseContact, pts, proj, size):
    """p = -n^T L (J x + delta) + n^T P F x: the rows n^T L and n^T P (q, 3) and the constant."""
    nl = np.einsum("qi,qij->qj", pts.normal, layer_tensor(c, pts.normal, proj, size))  # n^T L
    npf = np.einsum("qi,qij->qj", pts.normal, proj)  # n^T P
    return nl, npf, -np.einsum("qi,qi->q", nl, pts.delta)


def layer_tensor(c: EllipseContact, normal, proj, size) -> np.ndarray:
    return (PENALTY_FACTOR / (c.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(normal, *c.layer) @ proj)


def _quadrature_traction(c: EllipseContact, info, x: np.ndarray) -> np.ndarray:
    """Traction (q, 3) on body 1 at the region's quadrature points."""
    pts, _, proj, jump, flux, size, a = info
    w = (jump @ x).reshape(-1, 3) + pts.delta
    t1 = -np.einsum("qij,qj->qi", layer_tensor(c, pts.normal, proj, size), w)
    t1 = t1 + np.einsum("qij,qj->qi", proj, (flux @ x).reshape(-1, 3))
    slip = _slip_mask(c, pts, a)
    if slip.any():
        p = np.einsum("qi,qi->q", t1, pts.normal)
        t1[slip] -= (c.friction * p[slip])[:, None] * c.slip_direction
    return t1


#: the final check: the pressure's centroid within this fraction of the semi-axes of the ellipse's
#: centre (where body 1 surrounds the contact point)
CENTROID_TOLERANCE = 0.01


def predicted_stick_ratio(settled: list, current: float) -> float:
    """The stick ratio a load step starts from: under equal load increments the ratio the last
    two steps settled at, extrapolated linearly (the ratio drifts with |Q| / N from step to step;
    each step's root then starts within about the drift's change instead of the drift), within
    [0, 1]; ``current`` while fewer than two steps have settled or one of them slipped grossly.
    Only the start moves: the step's ratio is still the root of Mindlin's condition."""
    if len(settled) < 2 or not (0.0 < settled[-2] <= 1.0 and 0.0 < settled[-1] <= 1.0):
        return current
    return float(min(max(2.0 * settled[-1] - settled[-2], 0.0), 1.0))


def _pressure_centroid(c: EllipseContact, info, x: np.ndarray) -> np.ndarray:
    """int p s dA / int p dA (2,) over the region (nan without compression)."""
    pts = info[0]
    wp = pts.weights * np.einsum("qi,qi->q", _quadrature_traction(c, info, x), pts.normal)
    total = float(wp.sum())
    return (wp @ pts.s) / total if total > 0.0 else np.full(2, np.nan)


def plane_weights(c: EllipseContact, pts) -> np.ndarray:
    """The quadrature weights (q,) as areas of the tangent plane, not of body 1's surface (its
    weights times the cosine of the surface's tilt against the frame's normal): the edge
    conditions are moments of the pressure over the plane's coordinates. The two differ by
    1 / cos, 1 + (a / R)^2 / 2 at the edge of a contact of radius a on a ball of radius R: 0.1 % for
    a / R = 0.045, 6 % for a conforming ball in a socket at a semi-angle of 20 degrees."""
    return pts.weights * np.abs(pts.n1 @ c.frame.normal)


def _edge_coefficients(c: EllipseContact, info, x: np.ndarray, a: float) -> tuple[float, float]:
    if info is None or a <= 0.0:
        return math.inf, math.inf
    pts = info[0]
    aa, bb = c.semi_axes(a)
    p = np.einsum("qi,qi->q", _quadrature_traction(c, info, x), pts.normal)
    wp = plane_weights(c, pts) * p
    total = float(wp.sum())
    if not total > 0.0:
        return -math.inf, -math.inf
    s = c.local(pts.s)
    X, Y = s[:, 0] / aa, s[:, 1] / bb
    tx, ty = _second_moment_targets(c, aa, bb)
    return float((wp * X**2).sum() / total - tx) * 5.0, float((wp * Y**2).sum() / total - ty) * 5.0


def _second_moment_targets(c: EllipseContact, aa: float, bb: float) -> tuple[float, float]:
    """<X^2>, <Y^2> of the pressure without an edge singularity for the bodies' own gap along the
    axes (1/5 for Hertz's quadratic gap: solver.contact.gap_moments)."""
    return second_moment_targets(*c.initial_sample_gap(), c.sample_axis, (aa, bb))


def _overlap_extent(c: EllipseContact, gap: np.ndarray, inside: np.ndarray) -> float:
    """How far out along the axes (in units of the first semi-axis) the bodies still overlap
    outside the region: the region search's hint where a trial is too small (nan: nowhere)."""
    over = (gap < 0.0) & ~inside
    if not over.any():
        return math.nan
    s = np.abs(c.local(c.samples.s))[over]
    axis = c.sample_axis[over]
    return float(np.max(np.where(axis == 0, s[:, 0], s[:, 1] / c.ratio)))


def _sample_state(c: EllipseContact, x: np.ndarray, a: float):
    """Normal gap and pressure at the axis samples, whether each lies in the region, and its
    distance beyond the region's edge along its axis (negative inside)."""
    smp = c.samples
    s = c.local(smp.s)
    if a > 0.0:
        inside, beyond = c.sample_edges(s, c.sample_axis, a)
    else:  # no region: every sample outside it, at its distance from the centre
        inside, beyond = np.zeros(len(s), dtype=bool), np.abs(s[np.arange(len(s)), c.sample_axis])
    w = (c.e_samples @ x).reshape(-1, 3) + smp.delta
    gap = np.einsum("qi,qi->q", w, smp.normal)
    proj = _projector(c, smp, a)
    t1 = -np.einsum("qij,qj->qi", layer_tensor(c, smp.normal, proj, c.size_samples), w)
    t1 = t1 + np.einsum("qij,qj->qi", proj, (c.f_samples @ x).reshape(-1, 3))
    pressure = np.where(inside, np.einsum("qi,qi->q", t1, smp.normal), 0.0)
    return gap, pressure, inside, beyond


#: cells of the inner edge window on which tension is judged in 3D, at least: the trilinear band's
#: point traction oscillates with the cell period along an axis (+-60 % of the mean pressure), so
#: a one-cell mean swings with the grid's phase: sphere_on_flat at a/h 2.8 / 5.7 / 7.2 / 9.6 (two
#: grids) / 11.6 gave -0.59 / +0.16 / +0.31 / -0.24 / -0.23 / +0.12 of the mean pressure (Hertz
#: +0.34..+0.66), three of them "not converged" with settled edge coefficients (1e-6..7e-5); over
#: two cells +0.87 / +0.51 / +0.48 / +0.12 / +0.12 / +0.33 (Hertz +0.48..+0.89)
TENSION_WINDOW_CELLS = 2.0


def _edge_verdict(c: EllipseContact, v: _Verdict, info, x: np.ndarray, a: float) -> int:
    """The final check's tension, judged on the pressure's means over agglomerated cells
    (solver.contact.edge_pressure: each square of the tangent plane that the region fills less
    than three quarters merged with its inner neighbour) along the whole edge: ``v.pressure`` becomes the
    smallest mean of the groups the edge cuts, ``v.tension`` whether it is below minus
    tension_tolerance times the region's mean pressure; returns how many are. The
    point traction in a sliver of a cut cell is tensile whatever the region's size (the weak
    condition cannot close the gap over it), so the axis samples' window is not a measure of the
    region; the merged means hold the sliver's deficit with the neighbour that carries it. A region
    of general shape (corner_reading) judges the pressure read through the squares' corners
    (solver.contact.edge_pressure.nodal_pressure), as its map shows it."""
    if info is None or a <= 0.0:
        return 0
    pts = info[0]
    w = plane_weights(c, pts)
    p = np.einsum("qi,qi->q", _quadrature_traction(c, info, x), pts.normal)
    read = nodal_pressure(pts.s, w, p, c.h) if c.corner_reading else p
    cells = agglomerated_cells(pts.s, w, read, c.h, c.centre)
    edge = cells.means[cells.cut]
    if not len(edge):
        return 0
    p_tol = c.options.tension_tolerance * max(float(w @ p) / float(w.sum()), 0.0)
    v.pressure = float(edge.min())
    v.tension = bool(v.pressure < -p_tol)
    return int((edge < -p_tol).sum())


def _judge(c: EllipseContact, gap, pressure, inside, edge_dist) -> _Verdict:
    p_mean = max(float(np.mean(pressure[inside])) if inside.any() else 0.0, 0.0)
    g_tol = c.options.gap_tolerance * c.h * max(p_mean, 1e-30) / c.e_star
    p_tol = c.options.tension_tolerance * p_mean
    width = c.options.window * c.h
    out_w = (edge_dist > 0) & (edge_dist <= width)
    in_w = (edge_dist <= 0) & (edge_dist > -max(c.options.window, TENSION_WINDOW_CELLS) * c.h)
    g = float(gap[out_w].mean()) if out_w.any() else np.inf
    p = float(pressure[in_w].mean()) if in_w.any() else np.inf
    outside = ~inside
    return _Verdict(
        penetration=bool(g < -g_tol), tension=bool(p < -p_tol), gap=g, pressure=p,
        # overlap beyond the edge windows (judged by the means above); without a region, any
        penetration_count=int((outside & ((edge_dist > width) | ~inside.any()) & (gap < -g_tol)).sum()),
        tension_count=int((inside & (pressure < -p_tol)).sum()) if p_mean > 0 else 0,
        min_gap=float(gap[outside].min()) if outside.any() else 0.0,
        min_pressure=float(pressure[inside].min()) if inside.any() else 0.0,
    )


# ------------------------------------------------------------------ set-up


def _cell_dofs_global(b, cells: np.ndarray) -> np.ndarray:
    rows = b.cell_dofs(np.unique(cells)).ravel()
    m = b.node_dof_map[np.unique(rows)]
    return np.unique(m.indices)


#: the smaller relative curvature below this fraction of the larger: not a point contact (b/a would
#: exceed about 100, Hertz's ellipse for curvature ratio 1e-3)
LINE_CONTACT_RATIO = 1e-3


#: a negative smaller relative curvature down to this fraction of the larger is zero within the
#: frame's finite-difference estimate of it: a ball in a conical seat touches along the seat's
#: circle, where the two hoop curvatures are equal (100 1/m for a 10 mm ball in a 90-degree cone),
#: and the frame read -0.22 against 100 1/m there. A point contact needs a positive one, and a
#: smaller one this slightly negative closes the gap along the line as slowly as a line contact's
CURVATURE_NOISE = 1e-2


def is_line_contact(frame: ContactFrame3D) -> bool:
    """The surfaces curve apart across one axis only (a cylinder on a flat, parallel cylinders):
    the smaller relative curvature vanishes to LINE_CONTACT_RATIO of the larger, or is negative
    by no more than CURVATURE_NOISE of it."""
    k0, k1 = (float(k) for k in frame.curvatures)
    return k1 > 0.0 and (abs(k0) <= LINE_CONTACT_RATIO * k1 or -CURVATURE_NOISE * k1 <= k0 < 0.0)


#: both relative curvatures below this over the candidate region's radius (radii of curvature
#: beyond 1e4 times it): the surfaces are flat against each other at the contact point
FLAT_CURVATURE = 1e-4


def is_flat_contact(frame: ContactFrame3D, extent: float) -> bool:
    """The surfaces are flat against each other at the contact point (a flat punch on a flat):
    both relative curvatures vanish to FLAT_CURVATURE over the candidate region's radius
    ``extent``, so the region's size is set by where the flat ends, not by curvature."""
    return float(np.abs(frame.curvatures).max()) * extent <= FLAT_CURVATURE


def _require_point_contact(model, frame: ContactFrame3D) -> None:
    """An elliptical region needs the surfaces to curve apart along both axes (a line contact
    takes a region of general shape instead): refuse conforming surfaces with what was found."""
    k0, k1 = (float(k) for k in frame.curvatures)
    if k1 > 0.0 and k0 > LINE_CONTACT_RATIO * k1:
        return
    name = "/".join(model.bodies)
    axis = np.round(frame.axes[0], 6).tolist()
    if is_line_contact(frame):
        what = "a line contact, which an ellipse cannot describe"
    elif k0 == 0.0 and k1 == 0.0:
        what = ("the surfaces are flat against each other there (a flat punch or face on a flat: the region's "
                "size is set by the edges of the flat, not by curvature), neither a point nor a line contact")
    else:
        what = "conforming surfaces (the gap closes or opens the wrong way), neither a point nor a line contact"
    raise ValueError(f"contact {name}: the relative curvatures at {np.round(frame.point, 6).tolist()} are "
                     f"{k0:.4g} and {k1:.4g} 1/m (smaller along {axis}): {what}. A 3D contact needs surfaces that "
                     "curve apart across at least one axis at the contact point")


def build(problem, model, b1, b2, options, general=None) -> EllipseContact:
    """The ellipse formulation of a contact between two discretised solids; a line contact and a
    flat contact (both curvatures 0) take ``general`` = (the formulation's class, its set-up, and a
    test of the other contacts that need it: an elongated contact that may reach body 1's free
    end), a region of general shape (solver.contact.contact3d passes solver.contact.star_region's),
    and are refused without."""
    opts = model.options
    solids = (b1.boundary, b2.boundary)
    h = float(min(b1.grid.min_size, b2.grid.min_size))
    extent = problem.candidate_extent(model, opts.extent_fraction)
    reach = 0.5 * extent
    frame, moved, ranges = touching_frame_3d(*solids, np.asarray(model.point, dtype=float), h, reach,
                                             getattr(model, "tangential_direction", None))
    e1 = 1.0 / (1.0 / _modulus(b1) + 1.0 / _modulus(b2))
    k0, k1 = frame.curvatures
    line = general is not None and (is_line_contact(frame) or is_flat_contact(frame, extent)
                                    or general[2](solids[0], frame, ranges, reach, extent, h))
    if line:  # a region of general shape ending at body 1's free edges
        kind, configure = general[:2]
    else:
        kind = EllipseContact
        _require_point_contact(model, frame)
    circular = abs(k1 - k0) <= 1e-4 * max(abs(k1), abs(k0), 1e-300)
    ratio = 1.0 if line or circular or min(k0, k1) <= 0 else hertz_elliptic_contact(1.0, (k0, k1), e1)[1] / \
        hertz_elliptic_contact(1.0, (k0, k1), e1)[0]
    # sample points along both axes, both signs, at the driver's sample spacing
    ds = opts.sample_spacing * h
    s_line = np.concatenate([-np.arange(extent, 0, -ds), np.arange(0.0, extent + ds, ds)])
    parts, axis = [], []
    for k in (0, 1):
        keep = _on_body1(solids[0], frame, k, s_line, reach)
        pts = axis_points(*solids, frame, k, s_line[keep], reach, 1e-4 * h,
                          offset=_axis_offsets(ranges, k, s_line[keep], 1e-3 * h))
        parts.append(pts)
        axis.append(np.full(len(pts.s), k))
    samples = RegionPoints(*(np.concatenate([getattr(p, f) for p in parts]) for f in
                             ("s", "x1", "x2", "n1", "n2", "weights", "normal")))
    c = kind(model=model, frame=frame, solids=solids, b1=b1, b2=b2, kind=model.type, dofs=np.zeros(0, int),
                       maps=(), h=h, extent=extent, ranges=ranges, samples=samples, sample_axis=np.concatenate(axis),
                       ratio=float(ratio), circular=bool(circular), band_fraction=options.band_fraction, e_star=e1,
                       options=opts, stick_ratio={"tied": math.inf, "frictionless": 0.0}.get(model.type, 1.0),
                       friction=float(model.friction or 0.0) if model.type == "frictional" else 0.0)
    c.grids = [(b.grid.origin, b.grid.h0 / 2.0**b.grid.max_level) for b in (b1, b2)]
    c.given_point = np.asarray(model.point, dtype=float) if moved else None
    c.reach = reach
    full = _dense_disc(solids, frame, extent, ranges, 0.25 * h, reach)
    cells1 = np.concatenate([_near_cells(b1, p.x1, p.n1) for p in (full, samples)])
    cells2 = np.concatenate([_near_cells(b2, p.x2, p.n2) for p in (full, samples)])
    c.dofs = np.union1d(_cell_dofs_global(b1, cells1), _cell_dofs_global(b2, cells2))
    c.maps = b1.restricted_dof_map(c.dofs) + b2.restricted_dof_map(c.dofs)
    c.e_samples, c.f_samples, c.size_samples = contact_operators(c, samples)
    if line:
        configure(c)
    return c


def _dense_disc(solids, frame, extent: float, ranges, spacing: float, reach: float) -> RegionPoints:
    """Points of the candidate disc (radius ``extent``) on a polar grid of ``spacing``."""
    rho = np.arange(0.0, extent + spacing, spacing)
    s = [np.zeros((1, 2))]
    for r in rho[1:]:
        for t0, t1 in ranges:
            t = np.linspace(t0, t1, max(2, int(np.ceil((t1 - t0) * r / spacing)) + 1))
            if t1 - t0 < 2 * math.pi - 1e-12:  # a range's edges are symmetry planes: just inside them
                margin = min(4e-3 * spacing / r, 0.25 * (t1 - t0))
                t = np.clip(t, t0 + margin, t1 - margin)
            s.append(r * np.stack([np.cos(t), np.sin(t)], axis=1))
    s = np.concatenate(s)
    x1, keep = surface_point(solids[0], frame, s, reach)
    return matched_points(*solids, frame, s[keep], np.zeros(int(keep.sum())), reach, 1e-4 * spacing,
                          on_body1=(x1[keep], keep[keep]))


def _near_cells(b, x, n) -> np.ndarray:
    """Cells holding boundary points and those a quarter of the finest cell around them (the
    region's pieces are cut on chords of curved surfaces)."""
    out = [locate_cells(b, x, n)]
    step = 0.25 * b.grid.min_size
    for k in range(3):
        for sign in (-1.0, 1.0):
            e = np.zeros(3)
            e[k] = sign * step
            cells = b.grid.locate(x + e - 1e-7 * b.grid.min_size * n)
            out.append(cells[cells >= 0])
    return np.concatenate(out)


def _inside_ranges(theta: float, ranges) -> bool:
    t = theta % (2 * math.pi)
    return any(t0 < t < t1 or t0 < t + 2 * math.pi < t1 for t0, t1 in ranges)


def _axis_offsets(ranges, axis: int, s: np.ndarray, shift: float) -> np.ndarray:
    """Offsets (n,) across the axis for samples along it: zero inside the region's angular ranges,
    ``shift`` towards their inside where the axis is a range's edge (a symmetry plane of a quarter
    model, where the bodies' signed distances have a kink)."""
    out = np.zeros(len(s))
    eps = 1e-6
    for sign in (1.0, -1.0):
        theta = (0.0 if axis == 0 else 0.5 * math.pi) + (0.0 if sign > 0 else math.pi)
        after, before = _inside_ranges(theta + eps, ranges), _inside_ranges(theta - eps, ranges)
        if after and before:  # inside a range: no shift (on its edge, whether or not the edge counts)
            continue
        side = 1.0 if after else (-1.0 if before else 0.0)
        # rotating by +eps moves the point along the other axis by sign(s) ... towards +theta
        out[np.sign(s) == sign] = side * sign * shift * (1.0 if axis == 0 else -1.0)
    return out


def _on_body1(solid1, frame, axis: int, s: np.ndarray, reach: float) -> np.ndarray:
    st = np.zeros((len(s), 2))
    st[:, axis] = s
    return surface_point(solid1, frame, st, reach)[1]


def _modulus(b) -> float:
    """E / (1 - nu^2) of a body (Hertz's E*) from its Lame constants."""
    lam, mu = b.lam, b.mu
    e = mu * (3 * lam + 2 * mu) / (lam + mu)
    nu = lam / (2 * (lam + mu))
    return e / (1 - nu**2)
