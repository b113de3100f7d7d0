"""Two-body contact on the IBFEM core (thesis chapter 5): tied, frictionless sliding and
frictional (partial slip) contact with the half-width and the stick zone found by the
non-linear solution. ``solve_contact(problem)``.

Discrete form (docs/contact.md). On body 1's contact curve, |s| <= a, with matched points
x1, x2 and w = u_h1(x1) - u_h2(x2) + Delta (eqs. 5-2 to 5-4 in the thin-band limit):

    K_c = J^T L J - (F^T W P J + J^T P W F),   f_c = -J^T L Delta + F^T W P Delta

J the jump operator u_h1(x1) - u_h2(x2) (each field in its own grid at its own matched point),
L = sum_q w_q 4/(3 delta) P A(n_c) P with body 1's moduli (delta = band_fraction x local cell
size), F the flux (default the band limit 1/2 sigma_1(u_h1) n1 + 1/2 sigma_2(u_h2) n1, the
symmetric average), P = I where tied (|s| <= stick half-width; all of a for tied contact) and
n_c n_c^T where sliding (frictionless: the tangential jump is free), n_c the pair's contact
normal (bisector of the two exact normals).

The half-width (default): the root of the edge coefficient int p (4 s^2/a^2 - 1) ds / int p ds,
the Chebyshev estimate of p sqrt(a^2 - s^2) at the region's ends (zero for the consistent
width, > 0 for a punch-like region that is too small, < 0 with tension): continuous in a and
blind to the grid-periodic traction oscillation. Alternatives: a bracket on the window verdicts
(penetration / tension judged on one-cell means at the edges) or the thesis's increment rule
(sections 5.5.3-5.5.4). The final state is always judged by the window verdicts.

Frictional contact (issue 6): stick zone |s| < c tied, slip zones c <= |s| <= a sliding with
Coulomb's traction mu p along the pair's tangent (eq. 5-24; p is affine in the dofs, so the
traction enters exactly as a non-symmetric block); c/a is the root of
sqrt(1 - |Q|/(mu N)) - c/a for the transmitted forces (eq. 2-29); gross slip is reported.

Speed: the bodies' stiffness K0 (volume + essential conditions) never changes. It is factored
once with the m dofs B of the cells the candidate contact region touches ordered last, the
Schur complement S = (B K0^-1 B^T)^-1 is read off the factors, each width trial is the m x m
solve (S + K_c) x = lambda S B U0 + f_c, and the full field U = K0^-1 (F0 + B^T (f_c - K_c x))
is recovered once.
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .contact import ContactGeometry, contact_geometry, contact_quadrature, grid_breakpoints, sample_points
from .ibfem import (
    IBFEMSolution,
    Settings,
    body_info,
    boundary_terms,
    discretise_body,
    essential_reactions,
    number_dofs,
    rigid_modes_check,
)
from .step_boundary import (
    PENALTY_FACTOR,
    BoundaryPoints,
    acoustic_tensor,
    projector,
    thin_band_terms,
)

__all__ = ["ContactSettings", "solve_contact", "resolve_contact_point", "single_threaded_blas"]


@contextlib.contextmanager
def single_threaded_blas():
    """Run dense linear algebra on one OpenBLAS thread, restoring the previous count.

    The width iterations factor dense matrices of a few hundred rows: threads gain nothing
    there, and on a loaded machine OpenBLAS's spinning threads made a 536 x 536 Cholesky
    25 times slower (0.4 s against 15 ms, measured). threadpoolctl is not a dependency, so
    the OpenBLAS libraries numpy and scipy loaded are driven through ctypes; without them
    this does nothing."""
    handles = []
    try:
        paths = {ln.split()[-1] for ln in open("/proc/self/maps") if "openblas" in ln.lower()}
    except OSError:
        paths = set()
    for path in sorted(paths):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for prefix, suffix in (("scipy_", ""), ("scipy_", "64_"), ("", ""), ("", "64_")):
            get = getattr(lib, f"{prefix}openblas_get_num_threads{suffix}", None)
            put = getattr(lib, f"{prefix}openblas_set_num_threads{suffix}", None)
            if get is not None and put is not None:
                handles.append((put, int(get())))
                put(1)
                break
    try:
        yield
    finally:
        for put, n in handles:
            put(n)

WIDTH_UPDATES = ("edge", "bracket", "thesis")
FLUXES = ("average", "body1", "body1_half")


@dataclass(frozen=True)
class ContactSettings:
    """Numerical choices of the contact solution (defaults measured in benchmarks/contact.py)."""

    core: Settings = field(default_factory=Settings)
    # "edge": root of the edge coefficient (continuous in a, sub-cell; docs/contact.md),
    # "bracket" (the one-cell window verdicts), "thesis" (sections 5.5.3-5.5.4)
    width_update: str = "edge"
    flux: str = "average"  # consistency flux: "average" (band limit), "body1" (weight 1), "body1_half" (1/2)
    order: int = 4  # Gauss points per contact-curve piece
    width_tolerance: float = 1.0 / 16.0  # bracket on a in the last load step, in finest contact cells
    edge_tolerance: float = 1e-3  # "edge": the root of the edge coefficient to this many finest cells (last step)
    step_tolerance: float = 0.25  # bracket on a in the earlier load steps (they only start the next)
    sample_spacing: float = 1.0 / 16.0  # penetration/tension samples, in finest contact cells
    window: float = 1.0  # penetration / tension are judged on means over this many cells at the edges
    gap_tolerance: float = 1e-3  # penetration: mean gap < -tol x (finest cell) x (mean pressure / E*)
    tension_tolerance: float = 0.01  # tension: mean pressure < -tol x mean pressure
    extent_fraction: float = 0.8  # candidate region: this fraction of the innermost contact refinement radius
    max_width_iterations: int = 60
    # boundary points in a sliver cell (material thickness < this fraction of its size) take the
    # fields of the cell half a cell further inside (0: off)
    sliver_fraction: float = 0.25
    # frictional contact (issue 6): the slip zone carries mu p (eq. 5-24); False: the thesis's
    # variant without it (section 5.4.2), the stick zone alone transmits the shear
    friction_traction: bool = True
    # direction of the normal constraint and of the friction traction: "frame" (the contact
    # frame's normal and tangent for every pair: the half-space assumption of Hertz and
    # Cattaneo-Mindlin) or "pair" (each matched pair's bisector of the two exact normals)
    contact_normal: str = "frame"
    stick_tolerance: float = 1e-3  # |sqrt(1 - |beta|/mu) - c/a| at the returned state
    max_stick_iterations: int = 30

    def __post_init__(self):
        if self.contact_normal not in ("frame", "pair"):
            raise ValueError(f"contact_normal must be 'frame' or 'pair', got {self.contact_normal!r}")
        if self.width_update not in WIDTH_UPDATES:
            raise ValueError(f"width_update must be one of {WIDTH_UPDATES}, got {self.width_update!r}")
        if self.flux not in FLUXES:
            raise ValueError(f"flux must be one of {FLUXES}, got {self.flux!r}")
        if not (isinstance(self.order, int) and 1 <= self.order <= 20):
            raise ValueError(f"order must be an integer in [1, 20], got {self.order!r}")
        if not (0.0 <= self.sliver_fraction < 1.0):
            raise ValueError(f"sliver_fraction must be in [0, 1), got {self.sliver_fraction!r}")
        if not (isinstance(self.max_stick_iterations, int) and self.max_stick_iterations >= 1):
            raise ValueError(f"max_stick_iterations must be an integer >= 1, got {self.max_stick_iterations!r}")
        for name in ("width_tolerance", "step_tolerance", "sample_spacing", "window", "gap_tolerance",
                     "tension_tolerance", "extent_fraction", "edge_tolerance", "stick_tolerance"):
            v = getattr(self, name)
            if not (v > 0 and math.isfinite(v)):
                raise ValueError(f"{name} must be a positive number, got {v!r}")


# ---------------------------------------------------------------------------------- set-up


def resolve_contact_point(problem, contact) -> np.ndarray:
    """The contact's point: given, or the midpoint of the closest points of the two exact
    boundaries (the deepest point of body 1 when they overlap)."""
    if contact.point is not None:
        p = np.asarray(contact.point, dtype=float)
        if p.shape != (2,) or not np.isfinite(p).all():
            raise ValueError(f"contacts.point must be [x, y], got {contact.point!r}")
        return p
    from .scene import closest_boundary_point

    first = problem.body(contact.bodies[0]).profile
    second = problem.body(contact.bodies[1]).profile
    size = min(problem.body(n).element_size for n in contact.bodies)
    xa = closest_boundary_point(first, second, 0.05 * size)
    xb = np.asarray(second.project(xa[None, :]).points[0], dtype=float)
    return 0.5 * (xa + xb)


def _resolved_body(body, points: list[np.ndarray]):
    """Copy of a BodyModel with every ``around = "contact"`` refinement centred on its contact
    points (one zone per point)."""
    refs = []
    for r in body.refinements:
        if r.center is None:
            if not points:
                raise ValueError(f"bodies[{body.name}].refinement.around is 'contact' but the body has no contact")
            refs += [dataclasses.replace(r, center=np.asarray(p, dtype=float)) for p in points]
        else:
            refs.append(r)
    return dataclasses.replace(body, refinements=tuple(refs))


def _contact_extent(problem, contact, factor: float) -> float:
    radii = [r.radius for n in contact.bodies for r in problem.body(n).refinements if r.center is None]
    if radii:
        return factor * min(radii)
    return 10.0 * min(problem.body(n).element_size for n in contact.bodies)


def _cell_dofs_global(b, cells: np.ndarray) -> np.ndarray:
    """Global free dofs the nodes of the cells depend on (hanging nodes resolved)."""
    rows = b.cell_dofs(np.unique(cells)).ravel()
    m = b.node_dof_map[np.unique(rows)]
    return np.unique(m.indices)


@dataclass
class _Contact:
    """Per-contact data of the solution."""

    model: object
    geom: ContactGeometry
    b1: object
    b2: object
    kind: str
    dofs: np.ndarray  # global contact dofs (sorted)
    h: float  # finest cell size along the contact
    samples: object  # ContactPoints at the sample chords
    e_samples: np.ndarray  # (2 ns, m) jump operator at samples on the contact dofs
    f_samples: np.ndarray  # (2 ns, m) flux operator at samples
    size_samples: np.ndarray  # (ns,) local size (sets delta) at the samples
    e_star: float
    breakpoints: np.ndarray
    history: list = field(default_factory=list)
    # stick ratio c/a: tied (P = I) for |s| <= c, sliding (P = n_c n_c^T) for c < |s| <= a.
    # Tied contact: inf; frictionless: 0; frictional (issue 6): sqrt(1 - |beta| / mu), iterated.
    stick_ratio: float = 0.0
    friction: float = 0.0  # mu: the slip zone carries mu p along -slip_sign t_c on body 1
    slip_sign: float = 0.0  # sign of the tangential force on body 2 (0: no friction traction)
    beta: float = math.nan  # Q / N of the last state (frictional)
    gross_slip: bool = False

    def stick(self, a: float) -> float:
        """Stick half-width c for the half-width a."""
        return math.inf if math.isinf(self.stick_ratio) else self.stick_ratio * a


def _flux_weights(flux: str) -> tuple[float, float]:
    return {"average": (0.5, 0.5), "body1": (1.0, 0.0), "body1_half": (0.5, 0.0)}[flux]


def _local_size(c: _Contact, pts, cells1, cells2) -> np.ndarray:
    t1 = c.b1.grid.material_thickness[cells1]
    t2 = c.b2.grid.material_thickness[cells2]
    return np.maximum(np.minimum(t1, t2), 1e-6 * c.b1.grid.size[cells1])


def _locate(b, x, n) -> np.ndarray:
    """Cells holding boundary points (nudged into the material, as the grid assigns pieces)."""
    cells = b.grid.locate(x - 1e-7 * b.grid.min_size * n)
    if (cells < 0).any():
        bad = x[cells < 0][0]
        raise ValueError(f"body {b.name!r}: contact point {bad.tolist()} lies in no grid cell")
    return cells


def _support_cells(b, x, n, cells, fraction: float) -> np.ndarray:
    """Cells whose fields represent the body at boundary points: the point's own cell, or, where
    that is a sliver (material thickness below ``fraction`` of its size), the cell half a cell
    further inside whose bilinear field is extended to the point.

    A sliver's far nodes are held only by a fragment of material: its stress (the flux) is
    unreliable and its thickness would set a tiny band, an enormous layer stiffness. Measured on
    example 6, whose grid line y = 0 touches the concave seat at the contact point: slivers
    h^2 / (4 R) thick put a 30 p0 spike into the pressure at s = 0 and a 1.8 % error into a."""
    ratio = b.grid.material_thickness[cells] / b.grid.size[cells]
    thin = ratio < fraction
    if not thin.any():
        return cells
    inner = b.grid.locate(x[thin] - 0.75 * b.grid.size[cells[thin]][:, None] * n[thin])
    ok = inner >= 0
    better = np.where(ok, b.grid.material_thickness[np.maximum(inner, 0)] / b.grid.size[np.maximum(inner, 0)], 0.0)
    out = cells.copy()
    idx = np.nonzero(thin)[0]
    use = ok & (better > ratio[thin])
    out[idx[use]] = inner[use]
    return out


def _operators(c: _Contact, pts, settings: ContactSettings):
    """Jump J and flux F (2q, n_total) and the local size at contact points."""
    cells1 = _locate(c.b1, pts.x1, pts.n1)
    cells2 = _locate(c.b2, pts.x2, pts.n2)
    if settings.sliver_fraction > 0.0:
        cells1 = _support_cells(c.b1, pts.x1, pts.n1, cells1, settings.sliver_fraction)
        cells2 = _support_cells(c.b2, pts.x2, pts.n2, cells2, settings.sliver_fraction)
    jump = c.b1.displacement_operator(pts.x1, cells1) - c.b2.displacement_operator(pts.x2, cells2)
    th1, th2 = _flux_weights(settings.flux)
    flux = th1 * c.b1.traction_operator(pts.x1, cells1, pts.n1)
    if th2:
        flux = flux + th2 * c.b2.traction_operator(pts.x2, cells2, pts.n1)
    return jump.tocsr(), flux.tocsr(), _local_size(c, pts, cells1, cells2)


def _projector(c: _Contact, pts, a: float) -> np.ndarray:
    """Constrained components of the jump per point: all where tied (|s| <= stick half-width,
    eq. 5-20), the contact normal n_c where sliding (eqs. 5-22, 5-23)."""
    tied = np.abs(pts.s) < c.stick(a)  # strict: with c = 0 (frictionless, gross slip) nothing is tied
    return np.where(tied[:, None, None], projector("fixed", pts.normal), projector("sliding", pts.normal))


def _terms(c: _Contact, a: float, settings: ContactSettings):
    """Contact stiffness and load on the contact dofs (dense m x m, m) for half-width a."""
    m = len(c.dofs)
    if a <= 0.0:
        return np.zeros((m, m)), np.zeros(m), None
    lo, hi = -min(a, c.geom.s_limits[1]), min(a, c.geom.s_limits[0])
    brk = c.breakpoints
    stick = c.stick(a)
    if 0.0 < stick < a:  # the projector changes at the stick zone's ends
        brk = np.concatenate([brk, [-stick, stick]])
    pts = contact_quadrature(c.geom, (c.b1.grid, c.b2.grid), lo, hi, settings.order, brk)
    jump, flux, size = _operators(c, pts, settings)
    bp = BoundaryPoints(pts.x1, pts.weights, pts.normal, size, jump, flux)
    proj = _projector(c, pts, a)
    k, f = thin_band_terms(bp, proj, -pts.delta, c.b1.lam, c.b1.mu, settings.core.band_fraction, 1.0, jump=jump)
    k = k.tocsr()
    kc = k[c.dofs][:, c.dofs]
    if abs(k.sum() - kc.sum()) > 1e-9 * abs(k).sum():
        raise RuntimeError("contact terms reach beyond the contact dofs")
    kc = kc.toarray()
    f = f[c.dofs]
    e_q, f_q = jump[:, c.dofs].toarray(), flux[:, c.dofs].toarray()
    slip = _slip_mask(c, pts, a)
    if slip.any():
        # friction traction of the slip zone (eq. 5-24), linear in the contact dofs through the
        # pressure p = n_c . (-L w + P F x) = r x + b: body 1 gets t_f = -sign mu p t_c, whose
        # virtual work moves to the left side as the non-symmetric K_f = sum w g^T r with
        # g = (-sign mu t_c)^T J (docs/contact.md); exact for the width, no inner iteration
        r, b = _pressure_rows(c, pts, proj, e_q, f_q, size, settings)
        tdir = -c.slip_sign * c.friction * _tangents(pts.normal)  # (q, 2) per unit pressure
        g = e_q[0::2] * tdir[:, 0:1] + e_q[1::2] * tdir[:, 1:2]  # (q, m)
        wq = np.where(slip, pts.weights, 0.0)
        kc = kc - g.T @ (wq[:, None] * r)
        f = f + g.T @ (wq * b)
    return kc, f, (pts, bp, proj, e_q, f_q, size)


def _tangents(normal: np.ndarray) -> np.ndarray:
    """(q, 2) tangent t_c = (-n_y, n_x) of each contact normal."""
    return np.stack([-normal[:, 1], normal[:, 0]], axis=1)


def _slip_mask(c: _Contact, pts, a: float) -> np.ndarray:
    """Points of the slip zone c <= |s| <= a that carry a friction traction."""
    if not (c.friction > 0.0 and c.slip_sign != 0.0) or a <= 0.0:
        return np.zeros(len(pts.s), dtype=bool)
    r = np.abs(pts.s)
    return (r >= c.stick(a)) & (r <= a)


def _pressure_rows(c: _Contact, pts, proj, e_q, f_q, size, settings):
    """Pressure at points as an affine function of the contact dofs: p = r @ x + b (r (q, m))."""
    nc = pts.normal
    layer = (PENALTY_FACTOR / (settings.core.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nc, c.b1.lam, c.b1.mu) @ proj
    )
    nl = np.einsum("qi,qij->qj", nc, layer)  # n^T L (q, 2)
    npf = np.einsum("qi,qij->qj", nc, proj)  # n^T P
    r = -(nl[:, 0:1] * e_q[0::2] + nl[:, 1:2] * e_q[1::2]) + npf[:, 0:1] * f_q[0::2] + npf[:, 1:2] * f_q[1::2]
    b = -np.einsum("qi,qi->q", nl, pts.delta)
    return r, b


def _friction_traction(c: _Contact, pts, t1: np.ndarray, a: float) -> np.ndarray:
    """Friction traction (q, 2) on body 1 in the slip zone: -sign mu p t_c with p = t1 . n_c."""
    slip = _slip_mask(c, pts, a)
    out = np.zeros_like(t1)
    if slip.any():
        p = np.einsum("qi,qi->q", t1, pts.normal)
        out[slip] = (-c.slip_sign * c.friction * p[slip])[:, None] * _tangents(pts.normal[slip])
    return out


def _tractions(c: _Contact, samples, e_op: np.ndarray, f_op: np.ndarray, size: np.ndarray, x: np.ndarray, a: float,
               settings: ContactSettings):
    """Normal gap (ns,), traction on body 1 (ns, 2) and the inside mask at sample points, from
    the contact dof values x: the layer's -4/(3 delta) P A P w plus the flux P F (zero outside a)."""
    w = (e_op @ x).reshape(-1, 2) + samples.delta
    nc = samples.normal
    gap = np.einsum("qi,qi->q", w, nc)
    inside = np.abs(samples.s) <= a
    proj = _projector(c, samples, a)
    layer = (PENALTY_FACTOR / (settings.core.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nc, c.b1.lam, c.b1.mu) @ proj
    )
    t1 = -np.einsum("qij,qj->qi", layer, w) + np.einsum("qij,qj->qi", proj, (f_op @ x).reshape(-1, 2))
    t1 = t1 + _friction_traction(c, samples, t1, a)
    t1[~inside] = 0.0
    return gap, t1, inside


def _sample_state(c: _Contact, x: np.ndarray, a: float, settings: ContactSettings):
    """Normal gap (ns,) and contact pressure (ns,) at the samples for contact dof values x."""
    gap, t1, inside = _tractions(c, c.samples, c.e_samples, c.f_samples, c.size_samples, x, a, settings)
    return gap, np.einsum("qi,qi->q", t1, c.samples.normal), inside


@dataclass
class _Verdict:
    """Contact conditions at the region's edges. ``gap`` / ``pressure``: the smaller of the two
    sides' mean normal gap just outside / mean pressure just inside, over a window of
    ``settings.window`` cells; the counts are the thesis's per-sample counts."""

    penetration: bool
    tension: bool
    gap: float
    pressure: float
    penetration_count: int
    tension_count: int
    min_gap: float
    min_pressure: float
    edge: float = math.nan  # edge coefficient (see _edge_coefficient); > 0: a too small


def _quadrature_traction(c: _Contact, info, x: np.ndarray, a: float, settings: ContactSettings) -> np.ndarray:
    """Traction (q, 2) on body 1 at the quadrature points of the region, friction included."""
    pts, _, proj, e_q, f_q, size = info
    w = (e_q @ x).reshape(-1, 2) + pts.delta
    nc = pts.normal
    layer = (PENALTY_FACTOR / (settings.core.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nc, c.b1.lam, c.b1.mu) @ proj
    )
    t1 = -np.einsum("qij,qj->qi", layer, w) + np.einsum("qij,qj->qi", proj, (f_q @ x).reshape(-1, 2))
    return t1 + _friction_traction(c, pts, t1, a)


def _edge_coefficient(c: _Contact, info, x: np.ndarray, a: float, settings: ContactSettings) -> float:
    """Edge coefficient of the pressure on the region |s| <= a: (Q(a) + Q(-a)) / (2 Q_mean) with
    Q(s) = p(s) sqrt(a^2 - s^2) fitted by Chebyshev polynomials of degree <= 2.

    Every pressure on a region |s| <= a of a contact whose initial gap is quadratic in s
    (Hertz's, Mindlin's) is p(s) = Q(s) / sqrt(a^2 - s^2) with Q a quadratic: Q(+-a) != 0 is
    the square-root singularity of a region too small (Q > 0: a punch's edges) or the tension
    of one too large (Q < 0); the consistent width has Q(+-a) = 0. With s = a cos(theta) the
    Chebyshev coefficients of Q are moments of p, q_k = (2 / pi) int p T_k(s/a) ds (q_0 half
    that), so that (q_0 + q_2) / q_0 = int p (4 s^2/a^2 - 1) ds / int p ds: an integral of
    the traction over the whole region. Unlike point or cell values it does not see the
    grid-periodic oscillation of the discrete traction, and its quadrature points move
    continuously with a (the pieces end at +-a exactly): a continuous, grid-position
    independent function of a whose root is the width (Hertz: int sqrt(1 - x^2)(4x^2 - 1) dx
    = 0)."""
    if info is None or a <= 0.0:
        return math.inf
    pts = info[0]
    p = np.einsum("qi,qi->q", _quadrature_traction(c, info, x, a, settings), pts.normal)
    wp = pts.weights * p
    total = float(wp.sum())
    if not total > 0.0:
        return -math.inf  # no compression at all: the region is far too large (or the bodies apart)
    return float((wp * (4.0 * (pts.s / a) ** 2 - 1.0)).sum() / total)


def _judge(c: _Contact, gap, pressure, inside, a, settings: ContactSettings) -> _Verdict:
    s = c.samples.s
    p_mean = max(float(np.mean(pressure[inside])) if inside.any() else 0.0, 0.0)
    g_tol = settings.gap_tolerance * c.h * max(p_mean, 1e-30) / c.e_star
    p_tol = settings.tension_tolerance * p_mean
    width = settings.window * c.h
    outside = ~inside
    gaps, pressures = [], []
    for sgn in (1.0, -1.0):
        r = sgn * s
        out_w = (r > a) & (r <= a + width)
        in_w = (r <= a) & (r > a - width) & inside
        gaps.append(float(gap[out_w].mean()) if out_w.any() else np.inf)
        pressures.append(float(pressure[in_w].mean()) if in_w.any() else np.inf)
    g, p = min(gaps), min(pressures)
    return _Verdict(
        penetration=bool(g < -g_tol),
        tension=bool(a > 0 and p < -p_tol),
        gap=g,
        pressure=p,
        penetration_count=int((outside & (gap < -g_tol)).sum()),
        tension_count=int((inside & (pressure < -p_tol)).sum()) if p_mean > 0 else 0,
        min_gap=float(gap[outside].min()) if outside.any() else 0.0,
        min_pressure=float(pressure[inside].min()) if inside.any() else 0.0,
    )


class _Bracket:
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


def _bracket_search(a0: float, h: float, tol: float, a_max: float, full: bool):
    """Generator of trial half-widths; receives the verdict of each, returns the final width
    and the bracket (a_pen, a_ten).

    Phase 1 brackets the smallest width without penetration a_pen (grow / shrink by a
    doubling step until the verdict changes), then closes the bracket to ``tol`` by a
    safeguarded secant on the edge gap (:class:`_Bracket`). Phase 2 (``full``) brackets the
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
                raise _RegionTooSmall()
            a = min(a + step, a_max)
            step *= 2.0
        elif lo is None:
            if a <= 0.0:
                return 0.0, (0.0, 0.0)
            a = max(a - step, 0.0)
            step *= 2.0
        else:
            break
    br = _Bracket(lo, hi, seen[lo].gap, seen[hi].gap, tol)
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
    br = _Bracket(lo, hi, -seen[lo].pressure, -seen[hi].pressure, tol)
    while not br.closed():
        a = br.propose()
        v = seen[a] if a in seen else (yield a)
        seen[a] = v
        br.update(a, not v.tension, -v.pressure)
    a_ten = br.lo
    return 0.5 * (a_pen + a_ten), (a_pen, a_ten)


def _thesis_search(a0: float, h: float, tol: float, a_max: float, max_iterations: int):
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


def _edge_search(a0: float, h: float, tol: float, a_max: float):
    """Generator of trial half-widths for the root of the edge coefficient g(a) (> 0: a too
    small); receives the verdict of each trial, returns the width and the final bracket.

    Grow / shrink from a0 by a doubling step until g changes sign, then close the bracket to
    ``tol`` by regula falsi with the Illinois modification (:class:`_Bracket`; g is smooth in
    a, so this converges superlinearly). Without compression (g = -inf) the trial is treated
    as too large."""
    step = max(0.05 * a0, 0.5 * h)
    lo = hi = None
    glo = ghi = None
    a = a0
    while True:
        v = yield a
        g = v.edge
        if g > 0.0:
            lo, glo = a, g
            if hi is None:
                if a >= a_max:
                    raise _RegionTooSmall()
                a = min(a + step, a_max)
        else:
            hi, ghi = a, g
            if lo is None:
                if a <= 0.5 * h:
                    return 0.0, (0.0, 0.0)
                a = max(a - step, 0.25 * h)
        if lo is not None and hi is not None:
            break
        step *= 2.0
    br = _Bracket(lo, hi, -glo, -ghi, tol)  # _Bracket wants g < 0 on the low side
    while not br.closed():
        a = br.propose()
        v = yield a
        br.update(a, v.edge > 0.0, -v.edge)
    # the end with the smaller |g| (the two are within tol)
    a = br.lo if abs(br.glo) <= abs(br.ghi) else br.hi
    return a, (br.lo, br.hi)


class _StickRoot:
    """Root of F(k) = sqrt(1 - |Q(k)| / (mu N(k))) - k for the stick ratio k = c/a in [0, 1]
    (eq. 2-29 made consistent with the transmitted forces). F decreases in k (a larger stick
    zone transmits more shear), F(1) <= 0: fixed-point steps k <- k + F (halving instead where
    that would drop below k / 2) until the root is bracketed, then regula falsi with the
    Illinois modification. k = 0 (gross slip) only when F < 0 down to ``min_ratio``."""

    min_ratio = 0.01  # below this c/a a stick zone is not resolved: gross slip

    def __init__(self, tol: float):
        self.tol = tol
        self.lo = self.hi = None  # k with F > 0 / F < 0
        self.flo = self.fhi = 0.0
        self.side = 0

    def update(self, k: float, normal: float, tangential: float, mu: float) -> tuple[float, bool]:
        """Next ratio and whether k is consistent (|F(k)| <= tol, or no compression)."""
        if not normal > 0.0:
            return k, True
        g = math.sqrt(max(0.0, 1.0 - abs(tangential) / (mu * normal)))
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


def _contact_force(c: _Contact, info, x: np.ndarray, a: float, settings: ContactSettings) -> np.ndarray:
    """Force (2,) on body 1 from body 2: the traction integrated over the region."""
    if info is None:
        return np.zeros(2)
    return (_quadrature_traction(c, info, x, a, settings) * info[0].weights[:, None]).sum(axis=0)


def _friction_checks(c: _Contact, info, x: np.ndarray, a: float, block: dict) -> dict:
    """Coulomb's conditions on the returned state: in the slip zone the tangential jump (the
    slip of body 1 on body 2) must point along slip_sign (the friction traction opposes it); in
    the stick zone the shear profile must stay within mu times the pressure profile. Reported as
    the fractions of each zone (by length) where they fail; not used to steer the iterations."""
    out = {"slip_direction_violations": 0.0, "stick_shear_above_mu_p": 0.0}
    if info is not None and c.slip_sign != 0.0:
        pts, e_q = info[0], info[3]
        w = (e_q @ x).reshape(-1, 2) + pts.delta
        wt = np.einsum("qi,qi->q", w, _tangents(pts.normal))
        slip = _slip_mask(c, pts, a)
        scale = max(float(np.abs(wt[slip]).max()) if slip.any() else 0.0, 1e-300)
        wrong = slip & (wt * c.slip_sign < -1e-6 * scale)
        if slip.any():
            out["slip_direction_violations"] = float(pts.weights[wrong].sum() / pts.weights[slip].sum())
    s = np.asarray(block["shear"]["s"])
    stick = np.abs(s) <= min(c.stick(a), a)
    if stick.any():
        q = np.abs(np.asarray(block["shear"]["value"])[stick])
        p = np.asarray(block["pressure"]["value"])[stick]
        out["stick_shear_above_mu_p"] = float(np.mean(q > 1.02 * c.friction * np.maximum(p, 0.0)))
    return out


class _RegionTooSmall(Exception):
    pass


# ---------------------------------------------------------------------------------- solve


def _setup_contact(model, geom, b1, b2, settings: ContactSettings) -> _Contact:
    s_plus, s_minus = geom.s_limits
    bk = grid_breakpoints(geom, (b1.grid, b2.grid), -s_minus, s_plus)
    # finest cell along the candidate region of body 1
    near = b1.grid.pieces.of(geom.edges[0])
    h = float(min(b1.grid.size[b1.grid.pieces.cell[near]].min(), b2.grid.min_size))
    # dofs of every cell the candidate region touches: the pieces of both curves in range and
    # the cells of the (dense) sample points
    ds = settings.sample_spacing * h
    n_plus, n_minus = int(math.ceil(s_plus / ds)), int(math.ceil(s_minus / ds))
    s = np.concatenate([-np.linspace(s_minus, 0, n_minus + 1)[:-1], np.linspace(0, s_plus, n_plus + 1)])
    samples = sample_points(geom, s)
    full = contact_quadrature(geom, (b1.grid, b2.grid), -s_minus, s_plus, settings.order, bk)
    cells1, cells2 = [], []
    for pts in (samples, full):
        for b, x, nn, out in ((b1, pts.x1, pts.n1, cells1), (b2, pts.x2, pts.n2, cells2)):
            own = _locate(b, x, nn)
            out.append(own)
            if settings.sliver_fraction:
                # the support cell of a sliver depends on where in it a point lies (x - 0.75 h n):
                # take every cell within 1.25 h of the sliver's centre (finer neighbours included)
                thin = np.unique(own[b.grid.material_thickness[own] < settings.sliver_fraction * b.grid.size[own]])
                if len(thin):
                    centre = b.grid.lower[thin] + 0.5 * b.grid.size[thin][:, None]
                    g = np.linspace(-1.25, 1.25, 11)
                    offs = np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
                    probe = centre[:, None, :] + b.grid.size[thin][:, None, None] * offs[None, :, :]
                    near = b.grid.locate(probe.reshape(-1, 2))
                    out.append(near[near >= 0])
    cells1, cells2 = np.concatenate(cells1), np.concatenate(cells2)
    dofs = np.union1d(_cell_dofs_global(b1, cells1), _cell_dofs_global(b2, cells2))
    c = _Contact(model, geom, b1, b2, model.type, dofs, h, samples, None, None, None, 0.0, bk,
                 stick_ratio={"tied": math.inf, "frictionless": 0.0}.get(model.type, 1.0),
                 friction=float(model.friction or 0.0) if model.type == "frictional" else 0.0)
    jump, flux, size = _operators(c, samples, settings)
    c.e_samples = jump[:, dofs].toarray()
    c.f_samples = flux[:, dofs].toarray()
    c.size_samples = size
    e1 = b1.elasticity[0, 0] - b1.elasticity[0, 1] ** 2 / b1.elasticity[0, 0]  # plane modulus E/(1-nu^2)
    e2 = b2.elasticity[0, 0] - b2.elasticity[0, 1] ** 2 / b2.elasticity[0, 0]
    c.e_star = 1.0 / (1.0 / e1 + 1.0 / e2)
    return c


def solve_contact(problem, progress: Callable | None = None,
                  settings: ContactSettings | Settings | None = None) -> IBFEMSolution:
    """Solve a problem with tied / frictionless / frictional contacts (issues 5, 6); returns an IBFEMSolution
    whose ``contacts`` holds the SPEC section 4 contact blocks. ``settings`` may be the core's
    :class:`solver.ibfem.Settings` (then the contact choices are the defaults), so that
    ``solver.ibfem.solve`` can pass its own through."""
    if isinstance(settings, Settings):
        settings = ContactSettings(core=settings)
    elif settings is not None and not isinstance(settings, ContactSettings):
        raise ValueError(f"settings must be ContactSettings or solver.ibfem.Settings, got {type(settings).__name__}")
    with single_threaded_blas():
        return _solve_contact(problem, progress, settings)


def _solve_contact(problem, progress, settings) -> IBFEMSolution:
    settings = settings or ContactSettings(core=Settings.from_options(problem.options))
    core = settings.core
    report = progress or (lambda stage, fraction=None: None)
    t_start = time.perf_counter()
    timings: dict[str, float] = {}
    if problem.model not in ("plane_strain", "plane_stress"):
        raise ValueError(f"model must be 'plane_strain' or 'plane_stress', got {problem.model!r}")
    if not problem.contacts:
        raise ValueError("the problem has no contacts; use solver.ibfem.solve")
    names = [b.name for b in problem.bodies]
    for i, cm in enumerate(problem.contacts):
        for nm in cm.bodies:
            if nm not in names:
                raise ValueError(f"contacts[{i}].bodies: unknown body {nm!r}; bodies: {', '.join(names)}")
        if cm.bodies[0] == cm.bodies[1]:
            raise ValueError(f"contacts[{i}].bodies: a contact needs two different bodies, got {list(cm.bodies)}")
        if cm.type not in ("tied", "frictionless", "frictional"):
            raise ValueError(f"contacts[{i}].type must be 'tied', 'frictionless' or 'frictional', got {cm.type!r}")
        if cm.type == "frictional":
            mu = cm.friction
            if not (isinstance(mu, (int, float)) and math.isfinite(mu) and mu > 0):
                raise ValueError(f"contacts[{i}].friction must be a positive number for frictional contact, got {mu!r}")
    opts = problem.options
    if not (isinstance(opts.load_steps, int) and opts.load_steps >= 1):
        raise ValueError(f"solver.load_steps must be an integer >= 1, got {opts.load_steps!r}")

    # contact points and refinement centres
    t = time.perf_counter()
    points = [resolve_contact_point(problem, cm) for cm in problem.contacts]
    bodies = []
    for i, body in enumerate(problem.bodies):
        report(f"grid {body.name}", 0.2 * i / len(problem.bodies))
        mine = [p for cm, p in zip(problem.contacts, points) if body.name in cm.bodies]
        bodies.append(discretise_body(_resolved_body(body, mine), i, problem.model, opts.exact_geometry, core))
    n = number_dofs(bodies)
    by_name = {b.name: b for b in bodies}
    timings["grid_s"] = time.perf_counter() - t

    report("assembly", 0.2)
    t = time.perf_counter()
    k0 = sp.block_diag([b.stiffness(core.fictitious_stiffness) for b in bodies], format="csr")
    k_ess, f0, essentials = boundary_terms(problem, bodies, core, sp.csr_matrix((n, n)))
    k0 = (k0 + k_ess).tocsr()
    contacts = []
    for cm, p in zip(problem.contacts, points):
        b1, b2 = by_name[cm.bodies[0]], by_name[cm.bodies[1]]
        geom = contact_geometry((b1, b2), cm.bodies, p, _contact_extent(problem, cm, settings.extent_fraction))
        geom.normal_mode = settings.contact_normal
        contacts.append(_setup_contact(cm, geom, b1, b2, settings))
    timings["assembly_s"] = time.perf_counter() - t

    # a body held only through a contact: K0 is singular. Keep a small fixed contact patch
    # (two finest cells) in K0 and update only the difference (documented in docs/contact.md).
    t = time.perf_counter()
    base = [0.0] * len(contacts)
    try:
        rigid_modes_check(k0, bodies)
    except ValueError:
        base = [2.0 * c.h for c in contacts]
        for c, a0 in zip(contacts, base):
            kc, _, _ = _terms(c, a0, settings)
            k0 = k0 + _embed(kc, c.dofs, n)
        rigid_modes_check(k0, bodies)  # still singular: a genuine rigid-body motion
    dofs = np.unique(np.concatenate([c.dofs for c in contacts]))
    m = len(dofs)
    where = [np.searchsorted(dofs, c.dofs) for c in contacts]
    lu, schur = _condensed_factor(k0, dofs)
    u0 = lu.solve(f0)
    bu0 = u0[dofs]
    sbu0 = schur @ bu0
    u0f0 = float(u0 @ f0)
    base_terms = [_terms(c, a0, settings)[:2] for c, a0 in zip(contacts, base)]
    timings["factor_s"] = time.perf_counter() - t

    def assemble(widths):
        kc = np.zeros((m, m))
        fc = np.zeros(m)
        extra = []
        for c, wh, a, (kb, fb) in zip(contacts, where, widths, base_terms):
            kk, ff, info = _terms(c, a, settings)
            kc[np.ix_(wh, wh)] += kk - kb
            fc[wh] += ff
            extra.append(info)
        return kc, fc, extra

    def solve_small(lam, kc, fc):
        if any(c.slip_sign != 0.0 and c.friction > 0.0 for c in contacts):  # K_f: non-symmetric
            return sla.solve(schur + kc, lam * sbu0 + fc)
        try:  # S + Kc is symmetric positive definite when the Nitsche terms are coercive
            return sla.cho_solve(sla.cho_factor(schur + kc), lam * sbu0 + fc)
        except np.linalg.LinAlgError:
            return sla.solve(schur + kc, lam * sbu0 + fc, assume_a="sym")

    # ------------------------------------------------------------------ load steps
    # With linear elasticity and a fixed contact region each load step is linear: the "Newton"
    # iterations of eqs. 5-11 to 5-14 are re-solves with updated contact terms, one per trial
    # width; the residual work between consecutive states is recorded (exact, on the contact dofs).
    t = time.perf_counter()
    steps = opts.load_steps
    per_step, work_history, converged = [], [], True
    widths = [2.0 * c.h for c in contacts]
    brackets = [(0.0, 0.0)] * len(contacts)
    prev = None  # (lam, x, y, kc, fc) of the last converged state
    prev_infos = None
    messages = []
    max_it = min(opts.max_iterations, settings.max_width_iterations)
    run = {"last": None, "ref_work": None}

    def width_search(step, lam, final, widths, tag):
        """The width iterations of one load step at fixed stick ratios: (widths, brackets, state,
        quadrature infos, solves, settled)."""
        tol_cells = settings.width_tolerance if final else settings.step_tolerance
        if settings.width_update == "edge":
            gens = [_edge_search(a, c.h, (settings.edge_tolerance if final else settings.step_tolerance) * c.h,
                                 c.geom.s_max()) for a, c in zip(widths, contacts)]
        elif settings.width_update == "thesis":
            gens = [_thesis_search(a, c.h, settings.width_tolerance * c.h, c.geom.s_max(), max_it)
                    for a, c in zip(widths, contacts)]
        else:
            gens = [_bracket_search(a, c.h, tol_cells * c.h, c.geom.s_max(), final) for a, c in zip(widths, contacts)]
        trial = [next(gn) for gn in gens]
        results = [None] * len(contacts)
        iters = 0
        cache = {}
        while True:
            key = tuple(trial)
            if key in cache:
                state, verdicts, infos_trial = cache[key]
            else:
                iters += 1
                kc, fc, infos_trial = assemble(trial)
                x = solve_small(lam, kc, fc)
                y = fc - kc @ x
                old = run["last"] if run["last"] is not None else prev
                if old is not None:
                    o_lam, o_x, o_y, o_kc, o_fc = old
                    r = fc - kc @ o_x - o_fc + o_kc @ o_x
                    work = float((x - o_x) @ r)
                    dl = lam - o_lam
                    if dl:
                        work += dl * (dl * u0f0 + (y - o_y) @ bu0)
                    work = abs(work)
                else:
                    work = abs(float(lam * lam * u0f0 + lam * (y @ bu0)))
                ref = run["ref_work"]
                run["ref_work"] = ref = work if ref is None else max(ref, work)
                ratio = float(work / ref) if ref > 0 else 0.0
                work_history.append(ratio)
                state = (lam, x, y, kc, fc)
                run["last"] = state
                verdicts = []
                for c, wh, a, inf in zip(contacts, where, trial, infos_trial):
                    gap, pres, inside = _sample_state(c, x[wh], a, settings)
                    v = _judge(c, gap, pres, inside, a, settings)
                    v.edge = _edge_coefficient(c, inf, x[wh], a, settings)
                    verdicts.append(v)
                    c.history.append({"step": step, "iteration": iters, "a": a, "penetration": v.penetration,
                                      "tension": v.tension, "edge_gap": v.gap, "edge_pressure": v.pressure,
                                      "edge_coefficient": v.edge, "stick_ratio": c.stick_ratio,
                                      "stick_iteration": tag, "work_ratio": ratio})
                cache[key] = (state, verdicts, infos_trial)
            if all(r is not None for r in results) or iters >= max_it:
                break
            nxt = []
            for k, (gn, v) in enumerate(zip(gens, verdicts)):
                if results[k] is not None:
                    nxt.append(results[k][0])
                    continue
                try:
                    nxt.append(gn.send(v))
                except StopIteration as stop:
                    results[k] = stop.value
                    nxt.append(stop.value[0])
                except _RegionTooSmall:
                    c = contacts[k]
                    raise ValueError(
                        f"contact {c.geom.bodies[0]}/{c.geom.bodies[1]}: the contact region reaches the end of the "
                        f"candidate region (s = {c.geom.s_max():.4g} m) and still penetrates; enlarge the contact "
                        "refinement radius"
                    ) from None
            trial = nxt
        settled = all(r is not None for r in results)
        results = [r if r is not None else (a, (a, a)) for r, a in zip(results, trial)]
        widths = [r[0] for r in results]
        key = tuple(widths)
        if key not in cache:  # unsettled: the last trial
            key = tuple(trial)
        state, _, infos = cache[key]
        return widths, [r[1] for r in results], state, infos, iters, settled

    frictional = [k for k, c in enumerate(contacts) if c.kind == "frictional"]
    for step in range(1, steps + 1):
        lam = step / steps
        final = step == steps
        report(f"load step {step}/{steps}", 0.3 + 0.6 * (step - 1) / steps)
        if prev is not None and prev[0] > 0:
            # start from the last width scaled as Hertz (a ~ sqrt(N) ~ sqrt(load))
            widths = [max(a * math.sqrt(lam / prev[0]), 2.0 * c.h) for a, c in zip(widths, contacts)]
        # stick ratios (frictional contacts): root of F(k) = sqrt(1 - |beta(k)| / mu) - k on [0, 1]
        # (F decreases: a larger stick zone transmits more shear), by the fixed-point step until
        # bracketed, then regula falsi (Illinois); the widths are searched at each trial ratio
        # each step starts from the previous ratio, or after gross slip from the smallest resolved
        # one (k = 0 is always consistent, F(0) = 0, see _StickRoot, and would never be left):
        # F < 0 there confirms gross slip in two solves, F > 0 climbs to the partial-slip root
        for k in frictional:
            if contacts[k].stick_ratio <= 0.0:
                contacts[k].stick_ratio = _StickRoot.min_ratio
        stick = {k: _StickRoot(settings.stick_tolerance) for k in frictional}
        iters, settled, tag = 0, True, 0
        while True:
            widths, brackets, state, infos, it, ok = width_search(step, lam, final, widths, tag)
            iters += it
            settled = settled and ok
            if not frictional:
                break
            done = True
            for k in frictional:
                c = contacts[k]
                on2 = -_contact_force(c, infos[k], state[1][where[k]], widths[k], settings)
                normal, tangential = float(-on2 @ c.geom.normal), float(on2 @ c.geom.tangent)
                nxt, finished = stick[k].update(c.stick_ratio, normal, tangential, c.friction)
                c.beta = tangential / normal if normal > 0 else math.nan
                if settings.friction_traction and tangential != 0.0:
                    sign = math.copysign(1.0, tangential)
                    if sign != c.slip_sign and c.stick_ratio < 1.0:
                        finished = False  # the friction traction pointed the wrong way
                    c.slip_sign = sign
                if not finished:
                    c.stick_ratio = nxt
                    done = False
            tag += 1
            if done:
                break
            if tag >= settings.max_stick_iterations:
                settled = False
                messages.append(f"load step {step}: the stick zone did not settle in {tag} iterations")
                break
        per_step.append(iters)
        if not settled:
            converged = False
            messages.append(f"load step {step}: the contact width did not settle in {iters} iterations")
        prev, prev_infos = state, infos
    for k in frictional:
        c = contacts[k]
        c.gross_slip = bool(c.stick_ratio == 0.0 and abs(c.beta) >= c.friction * (1.0 - 1e-6))
        if c.gross_slip:
            messages.append(
                f"contact {c.geom.bodies[0]}/{c.geom.bodies[1]}: gross slip, |Q|/N = {abs(c.beta):.4g} >= mu = "
                f"{c.friction:g}: no stick zone; solved with full sliding friction (the constraints still hold "
                "the bodies)"
            )
    timings["iterations_s"] = time.perf_counter() - t

    # ------------------------------------------------------------------ results
    t = time.perf_counter()
    lam, x, y, kc, fc = prev
    u = lu.solve(lam * f0 + _scatter(n, dofs, y))
    # two steps of iterative refinement on the full system K0 + B^T Kc B (the contact terms,
    # friction included, live on the contact dofs only: _terms checks it)
    infos = prev_infos
    k_full = (k0 + _embed(kc, dofs, n)).tocsr()
    f_full = lam * f0 + _scatter(n, dofs, fc)
    res = f_full - k_full @ u
    for _ in range(2):
        du = _condensed_apply(lu, schur, dofs, kc, res)
        u = u + du
        res = f_full - k_full @ u
    residual = float(np.linalg.norm(res) / max(np.linalg.norm(f_full), 1e-300))

    reactions, tractions = essential_reactions(essentials, u, core, lam)

    blocks = []
    for c, a, info, wh, bracket in zip(contacts, widths, infos, where, brackets):
        gap, pres, inside = _sample_state(c, u[c.dofs], a, settings)
        v = _judge(c, gap, pres, inside, a, settings)
        force1 = _contact_force(c, info, u[c.dofs], a, settings)  # force on body 1 from body 2
        on2 = -force1
        nrm, tan = c.geom.normal, c.geom.tangent
        ok = not v.penetration and not v.tension
        if not ok:
            converged = False
            messages.append(
                f"contact {c.geom.bodies[0]}/{c.geom.bodies[1]}: final state has penetration {v.penetration} "
                f"(edge gap {v.gap:.3g} m) and tension {v.tension} (edge pressure {v.pressure:.3g} Pa) at a = {a:.6g} m"
            )
        blocks.append(_contact_block(c, a, on2, nrm, tan, settings, u))
        blocks[-1]["checks"] = {"penetration": v.penetration, "tension": v.tension,
                                "edge_gap": v.gap, "edge_pressure": v.pressure,
                                "penetration_points": v.penetration_count, "tension_points": v.tension_count,
                                "min_gap": v.min_gap, "min_pressure": v.min_pressure,
                                "half_width_bracket": list(bracket), "force_on_first": force1.tolist(),
                                "edge_coefficient": _edge_coefficient(c, info, u[c.dofs], a, settings)}
        if c.kind == "frictional":
            nf, qf = float(-on2 @ nrm), float(on2 @ tan)
            ca = math.sqrt(max(0.0, 1.0 - abs(qf) / (c.friction * nf))) if nf > 0 else math.nan
            blocks[-1]["checks"].update({"stick_ratio": c.stick_ratio, "stick_ratio_from_forces": ca,
                                         "force_ratio": qf / nf if nf > 0 else math.nan,
                                         "friction_traction": settings.friction_traction})
            blocks[-1]["checks"].update(_friction_checks(c, info, u[c.dofs], a, blocks[-1]))
            blocks[-1]["gross_slip"] = c.gross_slip
            if not abs(ca - c.stick_ratio) <= 2.0 * settings.stick_tolerance:
                converged = False
                messages.append(f"contact {c.geom.bodies[0]}/{c.geom.bodies[1]}: c/a = {c.stick_ratio:.4g} but the "
                                f"forces give sqrt(1 - |Q|/(mu N)) = {ca:.4g}")
    timings["results_s"] = time.perf_counter() - t
    timings["total_s"] = time.perf_counter() - t_start
    report("done", 1.0)
    iterations = {
        "total": int(sum(per_step)),
        "per_step": per_step,
        "linear_residual": residual,
        "width_update": settings.width_update,
        "work_ratio": work_history,
        "contact_dofs": m,
        "contacts": [c.history for c in contacts],
        "messages": messages,
    }
    return IBFEMSolution(
        problem=problem,
        bodies=bodies,
        u=u,
        converged=bool(converged and np.isfinite(u).all() and residual < 1e-6),
        body_info=body_info(bodies),
        reactions=reactions,
        iterations=iterations,
        timings=timings,
        contacts=blocks,
        settings=core,
        boundary_tractions=tractions,
    )


def _embed(dense: np.ndarray, dofs: np.ndarray, n: int) -> sp.csr_matrix:
    """A dense block on the dofs ``dofs`` as an (n, n) sparse matrix."""
    r, c = np.nonzero(dense)
    return sp.csr_matrix((dense[r, c], (dofs[r], dofs[c])), shape=(n, n))


def _scatter(n, dofs, values):
    out = np.zeros(n)
    out[dofs] = values
    return out


def _condensed_apply(lu, schur, dofs, kc, r):
    """(K0 + B^T Kc B)^-1 r by static condensation: (S + Kc) x = S B K0^-1 r, then
    U = K0^-1 (r - B^T Kc x)."""
    z = lu.solve(r)
    sym = np.allclose(kc, kc.T, rtol=0.0, atol=1e-12 * max(np.abs(kc).max(), 1e-300))
    x = sla.solve(schur + kc, schur @ z[dofs], assume_a="sym" if sym else "gen")
    return lu.solve(r - _scatter(len(r), dofs, kc @ x))


class _PermutedLU:
    """Sparse LU of K0 with the contact dofs ordered last; ``solve`` in the original numbering."""

    def __init__(self, lu, order):
        self.lu, self.order = lu, order

    def solve(self, f):
        out = np.empty_like(f)
        out[self.order] = self.lu.solve(np.ascontiguousarray(f[self.order]))
        return out


def _condensed_factor(k0: sp.csr_matrix, dofs: np.ndarray):
    """Factor K0 once with the contact dofs last (fill-reducing order of the rest from SuperLU's
    MMD on the interior block, then natural order with diagonal pivots) and read the Schur
    complement S = K_cc - K_ci K_ii^-1 K_ic off the trailing block of the factors: S = L_cc U_cc.
    Then G = B K0^-1 B^T = S^-1 without m solves (scipy's SuperLU solves many right-hand sides
    one by one, ~20 ms each here)."""
    n = k0.shape[0]
    m = len(dofs)
    interior = np.setdiff1d(np.arange(n), dofs)
    kii = k0[interior][:, interior].tocsc()
    lu_i = spla.splu(kii, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    order = np.concatenate([interior[np.argsort(lu_i.perm_c)], dofs])
    kp = k0[order][:, order].tocsc()
    lu = spla.splu(kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    if (lu.perm_r != np.arange(n)).any() or (lu.perm_c != np.arange(n)).any():
        raise RuntimeError("the condensed factorisation pivoted off the diagonal")
    lcc = lu.L.tocsr()[n - m :, n - m :].toarray()
    ucc = lu.U.tocsr()[n - m :, n - m :].toarray()
    schur = lcc @ ucc
    return _PermutedLU(lu, order), 0.5 * (schur + schur.T)


def _contact_block(c: _Contact, a: float, on2, nrm, tan, settings, u) -> dict:
    """SPEC section 4 contact block with pressure and shear sampled on the exact contact curve.

    The traction of the thin-band terms is discontinuous from cell to cell (bilinear fields:
    sigma jumps across cell sides, w is piecewise smooth), so its point values oscillate with
    the grid by tens of percent while its cell means are accurate. The profiles written are
    its moving average over one cell width (the coarser of the two grids at the contact
    point): a recovery that removes the grid-periodic part and, being a mean, keeps the
    force (the integral of the profile equals the transmitted force)."""
    s_plus, s_minus = c.geom.s_limits
    out_s = np.linspace(-min(1.25 * a, s_minus), min(1.25 * a, s_plus), 201) if a > 0 else np.zeros(1)
    width = max(
        float(b.grid.size[b.grid.locate(np.asarray(o)[None, :] - 1e-9 * b.grid.min_size * np.asarray(n))[0]])
        for b, o, n in ((c.b1, c.geom.origins[0], -c.geom.normal), (c.b2, c.geom.origins[1], c.geom.normal))
    )
    ds = settings.sample_spacing * c.h
    reach_p, reach_m = min(1.25 * a + width, s_plus), min(1.25 * a + width, s_minus)
    s = np.linspace(-reach_m, reach_p, int(math.ceil((reach_p + reach_m) / ds)) + 1)
    pts = sample_points(c.geom, s)
    jump, flux, size = _operators(c, pts, settings)
    _, t1, _ = _tractions(c, pts, jump[:, c.dofs].toarray(), flux[:, c.dofs].toarray(), size, u[c.dofs], a, settings)
    nl = pts.normal
    tl = np.stack([-nl[:, 1], nl[:, 0]], axis=1)
    pressure = np.einsum("qi,qi->q", t1, nl)  # compression positive
    shear = -np.einsum("qi,qi->q", t1, tl)  # on body 2 along the local tangent
    k = 2 * int(round(0.5 * width / (s[1] - s[0]))) + 1 if len(s) > 1 else 1  # odd: centred
    kernel = np.ones(k) / k
    pressure = np.convolve(pressure, kernel, mode="same")
    shear = np.convolve(shear, kernel, mode="same")
    friction = float(getattr(c.model, "friction", 0.0) or 0.0)
    return {
        "bodies": list(c.geom.bodies),
        "type": c.kind,
        "friction": friction,
        "point": c.geom.point.tolist(),
        "normal": nrm.tolist(),
        "tangent": tan.tolist(),
        "half_width": float(a),
        "stick_half_width": float(min(c.stick(a), a)),
        "normal_force": float(-on2 @ nrm),
        "tangential_force": float(on2 @ tan),
        "pressure": {"s": out_s.tolist(), "value": np.interp(out_s, s, pressure).tolist()},
        "shear": {"s": out_s.tolist(), "value": np.interp(out_s, s, shear).tolist()},
        "profile_smoothing": float(width),
    }
