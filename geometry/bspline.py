"""B-spline and NURBS curves and surfaces with vectorised closest-point projection
(thesis section 4.2.8: seed by sampling, then Newton on the distance minimisation).

Evaluation is scipy's: ``scipy.interpolate.BSpline`` for curves and
``scipy.interpolate.NdBSpline`` for surfaces, one call per derivative order. NdBSpline was
chosen over tensor products of dense 1D design matrices (``BSpline(t, eye(n), k)``):
for a cubic 10 x 10 net the six derivative calls of NdBSpline took about 1.5 s per 10^6
points against about 2.5 s for the design-matrix route, and NdBSpline's cost does not grow
with the size of the net. Rational splines are evaluated in homogeneous coordinates
``(w P, w)`` and differentiated by the quotient rule.

Curve projection (``BSplineCurve.project``): the curve is cut into cells between samples
(about 1/32 of the curve's size apart judged by the control polygon, at least 4 per knot
span; cells over which the tangent turns by more than 40 degrees are halved, since a rational
curve with large weights can turn sharply within a short stretch of parameter). Each cell is
one polynomial piece of the homogeneous curve, kept as its Taylor polynomial about the cell's
middle (coefficients from scipy's derivatives there) and bounded by the box of its Bezier net
in a frame along its chord (as thin as the cell bends). For every point, every cell whose box
is closer than the best distance known (at first the nearest sample) is a candidate; a
candidate over which ``f' = C'.(C - p)`` keeps one sign (interval bound from the Bezier net of
the numerator of C' against the box of C - p) is dropped, since its smallest distance is at
an end it shares with a neighbouring cell (not at the ends of an open curve, nor anywhere on a
curve with C0 kinks); every other candidate is solved exactly: its ends, and every local
minimum inside it, isolated by the Bernstein coefficients over the cell of a positive
multiple of ``g = C'.(C - p)`` (a polynomial of degree 2k - 1, or 3k - 1 for a rational
curve: ``(N' w - N w').(N - p w)``; tabulated per cell as ``G0 - p.G1`` by exact Bernstein
arithmetic from the Taylor coefficients, ``geometry._bernstein``). No sign change: no
stationary point; one, from - to +: exactly one, a minimum, found by Newton kept in the
bracket (bisection where a step leaves it; stop when the next step moves the point by less
than 5e-13 of the size, or after a Newton step below 1e-7 of it); more: the interval is
halved by de Casteljau until every part has at most one (to 2^-30 of the cell). This finds
two minima in one cell, as near a centre of curvature, where a Newton descent finds one
(hypothesis seed 12264). The closest result wins and is evaluated on its piece. The
compiled kernel (``geometry._kernels``, optional) runs the same per point, depth first over
a box hierarchy with the bound tightened as cells are solved and by a point of the curve
in every node visited (so that a first descent into a wrong subtree does not leave the
bound loose); the numpy path runs it over (point, cell) pairs, component-major ((3, n)
arrays). Exact up to round-off in the coefficients: a sign change lost to round-off where
g is at the noise level (a point at a centre of curvature, where the distance is flat to
that level anyway).

Surface projection (``BSplineSurface.project``): as for curves, over the cells of a grid of
samples (per direction spaced by the longest control polygon leg across the net, about 1/64
of the surface's size apart, at least 4 per knot span, every knot a grid line), so that each
cell lies inside one knot span in both directions: one polynomial or rational tensor patch,
kept as its Taylor polynomial about the cell's middle (coefficients from scipy's partial
derivatives there) and bounded by the box of its Bezier net in a frame aligned with its
tangents; the boxes form a hierarchy (cells in Morton order, 2 x 2 tiles per node). For
every point, every cell whose box is closer than the best distance known is a candidate; a
candidate over which ``S_u.(S - p)`` or ``S_v.(S - p)`` keeps one sign (interval bound from
the Bezier net of the numerator of S_u or S_v against the box of S - p) is dropped, since its
smallest distance lies on an edge it shares with a neighbouring cell (not at the domain's
edges, and not at all along a direction with creases: C0 knot lines, multiplicity >=
degree). Every other candidate gets a safeguarded 2D Newton kept inside the cell, from its
middle: Gauss-Newton (first fundamental form) where the Hessian is not clearly positive
definite; a coordinate at a bound that its descent points out of is frozen (1D Newton along
that edge); scaled steepest descent where the step would leave the cell at once; steps cut
exactly at the cell's bounds; a trial that increases the distance beyond round-off is
halved; stop as for curves. The closest result wins; S, S_u and S_v are evaluated on its
patch at the returned parameters (so the points lie on the spline to round-off). Creases are
cell edges, so no Newton step crosses one. Each of a candidate's four edges whose Bernstein
lower bound of the distance along it is below the best distance found is solved as a curve
cell (every minimum along it, by isolation as above; ``geometry._curve_cells``): a minimum on
an edge beside an inner one, or one the 2D descent did not reach, is found. The two paths
differ in the order of the search:

* compiled kernel (``geometry._kernels``): per point, best first over the top boxes and
  depth first below them, the bound tightened as cells are solved and by a point of the
  surface in every node visited;
* numpy path (``geometry._surface_cells``), in blocks of ``_BLOCK`` points: the bound is the
  distance to the nearest grid sample (a ``scipy.spatial.cKDTree``, or a distance matrix
  for few samples); all candidate (point, cell) pairs under it are found at once
  (``CellSearch.pairs``) and solved together over component-major arrays (more cells than
  the kernel solves, each array operation over all of them), then the edges under the best
  distance of the cells; a point left without a candidate keeps the cell of its nearest
  sample, and the sample itself where no Newton result is closer.

Not a proof: the 2D Newton is trusted to find a cell's smallest inner distance (a cell
holding two inner minima could hide one: cells are about 1/64 of the size, so only a
distance function flat over the cell, near a centre of curvature, can have two); random
tests with clustered knots, weights 0.2-5 and points 1-100 % of the size away
(``benchmarks/bspline_stress.py``, hypothesis) find no miss on either path. Cost: far points
(near centres of curvature) have more candidate cells than points near the surface.

Distances are signed Euclidean distances, ``|p - closest|`` with the sign
of ``(p - closest) . normal``: where the foot is on a surface's edge or corner, or beyond
the end of an open curve, ``p - closest`` is not along the normal and the dot product would
be shorter than the distance.

Normal conventions (free-form normals are the primitive's own):

* surfaces: ``unit(S_u x S_v)``; where that vanishes (degenerate patch corners) the
  direction to the point, or +z for points on such a corner;
* curves, 2D queries (curve in the z = 0 plane): the tangent turned by -90 degrees
  (the right-hand side of the direction of increasing parameter), signed distances; at a
  C0 kink (corner) ``+-unit(p - closest)`` on the side of the bisector of the two
  one-sided normals;
* curves, 3D queries: ``unit(p - closest)`` (at smooth interior parameters its part
  perpendicular to the tangent), so distances >= 0; for points on the curve (within 1e-14 of its size) a
  deterministic perpendicular, ``unit(T x z)`` (``unit(T x x)`` when T is nearly along z),
  which equals the 2D convention for curves in the z = 0 plane.

Periodic curves (``periodic: true``): ``control_points`` lists the n distinct control
points (the closing ones are not repeated) and ``knots`` is either the n + 1 knots of one
period ``t_0 <= ... <= t_n`` (period ``t_n - t_0``), or the full unwrapped vector of
n + 2 * degree + 1 knots whose spacing repeats with period n (the parameter domain is then
``[knots[degree], knots[degree + n]]``). The curve is built on the wrapped control
polygon ``P_0 .. P_{n-1}, P_0 .. P_{degree-1}``; parameters wrap around the period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # pragma: no cover
    from scipy.spatial import cKDTree

# scipy.interpolate takes ~0.6 s to import; it (and scipy.spatial) are imported when the
# first spline is built, so that ``from ibfem import geometry`` stays light


def _bspline_classes():
    from scipy.interpolate import BSpline, NdBSpline

    return BSpline, NdBSpline


def _kd_tree(points: np.ndarray) -> "cKDTree":
    from scipy.spatial import cKDTree

    return cKDTree(points)

from ._base import MAX_COORDINATE, Curve, Projection, Surface, as_points, register_primitive, restore_dim, signed_lengths
from .curves import check_fields
from . import _bernstein, _curve_cells, _jit
from . import _surface_cells
from ._cell_boxes import (
    CellSearch,
    bernstein_inverse,
    best_per_point,
    box_levels,
    coldot,
    frame_boxes,
    middle_leaves,
    morton_order,
    oriented_boxes,
)

__all__ = ["BSplineCurve", "BSplineSurface"]

# Newton stopping tolerances, relative to the size of the control net (see module doc).
_STRICT = 5e-13
_MAX_ITER = 60
_BLOCK = 16384  # points per block in the Newton loop
_PAIR_BLOCK = 16384  # (point, cell) pairs per cell-wise Newton run
_MAX_HALVINGS = 30  # a trial halved this often (2^-30) leaves the point where it is
_ISOLATE_DEPTH = 30  # halvings of a cell in isolating the stationary points of a curve's distance
# the compiled surface kernel (geometry._kernels) is used when numba is there (a switch for
# comparisons by hand)
_SURFACE_JIT = True
_CELL_TURN = math.radians(20.0)  # half-angle of a cell's tangent cone (see _split_turning)
_FINISH = 1e-7  # a Newton step this small (relative to the size) is the last one
_KINK_NUDGE = 1e-13  # steps stop this fraction of the domain short of a C0 kink
# seeding density (samples per knot span) and the sample count above which the nearest
# sample is found with a k-d tree instead of a brute-force (BLAS) distance matrix
_CURVE_SEEDS_PER_SPAN = 4  # at least
_CURVE_SEEDS_MAX = 2048
_CURVE_SEED_SPACING = 32  # samples about 1/32 of the curve size apart (control polygon)
_SURFACE_SEEDS_MAX = 160  # per direction
_SURFACE_SEED_SPACING = 64  # samples about 1/64 of the surface size apart per direction
_BRUTE_SEEDS = 96


# ---------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------


def _field(owner: str, field: str) -> str:
    return f"{owner}: field {field!r}"


def _degree(value: Any, owner: str, field: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer, float)):
        raise ValueError(f"{_field(owner, field)} must be an integer >= 1, got {value!r}")
    if isinstance(value, float) and not value.is_integer():
        raise ValueError(f"{_field(owner, field)} must be an integer >= 1, got {value!r}")
    k = int(value)
    if k < 1:
        raise ValueError(f"{_field(owner, field)} must be an integer >= 1, got {value!r}")
    return k


def _knots(value: Any, owner: str, field: str) -> np.ndarray:
    try:
        t = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{_field(owner, field)} must be a list of numbers, got {value!r}") from None
    if t.ndim != 1 or len(t) < 2:
        raise ValueError(f"{_field(owner, field)} must be a flat list of at least 2 numbers, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"{_field(owner, field)} must be finite, got {value!r}")
    bad = np.flatnonzero(np.diff(t) < 0)
    if len(bad):
        i = int(bad[0])
        raise ValueError(
            f"{_field(owner, field)} must be non-decreasing, got {t[i]!r} before {t[i + 1]!r} at index {i + 1}"
        )
    t.setflags(write=False)
    return t


def _array(value: Any, owner: str, field: str, shape_text: str) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{_field(owner, field)} must be {shape_text} of numbers") from None
    if a.dtype == object:
        raise ValueError(f"{_field(owner, field)} must be {shape_text} of numbers")
    return a


def _weights(value: Any, shape: tuple[int, ...], owner: str, field: str = "weights") -> np.ndarray | None:
    if value is None:
        return None
    w = _array(value, owner, field, "an array")
    if w.shape != shape:
        raise ValueError(f"{_field(owner, field)} must have shape {shape} (one per control point), got {w.shape}")
    if not np.all(np.isfinite(w)) or not np.all(w > 0):
        raise ValueError(f"{_field(owner, field)} must be finite and positive, got min {np.min(w)!r}")
    w.setflags(write=False)
    return w


def _check_multiplicity(t: np.ndarray, k: int, owner: str, field: str) -> None:
    """Interior knots may repeat at most ``k`` times (C^-1 breaks are not supported)."""
    _, counts = np.unique(t[1:-1], return_counts=True)
    if len(counts) and counts.max() > k + 1:
        raise ValueError(f"{_field(owner, field)}: a knot repeats {counts.max()} times, at most degree + 1 = {k + 1} allowed")


def _domain(t: np.ndarray, k: int, n: int, owner: str, field: str) -> tuple[float, float]:
    a, b = float(t[k]), float(t[n])
    if not b > a:
        raise ValueError(
            f"{_field(owner, field)}: empty parameter domain [knots[{k}], knots[{n}]] = [{a!r}, {b!r}]"
        )
    return a, b


def _kinks(t: np.ndarray, k: int, lo: float, hi: float) -> np.ndarray:
    """Parameters in (lo, hi) where the spline is only C0 (knot multiplicity >= degree):
    Newton steps are stopped there, since f jumps in slope across them."""
    vals, counts = np.unique(t, return_counts=True)
    return vals[(counts >= k) & (vals > lo) & (vals < hi)]


def _polygon_samples(t: np.ndarray, k: int, a: float, b: float, legs: np.ndarray, spacing: float, at_most: int) -> np.ndarray:
    """Sample parameters: in every non-empty knot span of [a, b] as many equal steps as
    the control polygon legs acting on that span are long (divided by the degree) in
    units of ``spacing``, at least ``_CURVE_SEEDS_PER_SPAN``; scaled down to at most
    ``at_most`` samples."""
    br = np.unique(np.concatenate([[a], t[(t > a) & (t < b)], [b]]))
    # span [t_i, t_i+1) is shaped by control points i-k .. i, i.e. legs i-k .. i-1
    i = np.searchsorted(t, br[:-1], side="right") - 1
    cum = np.concatenate([[0.0], np.cumsum(legs)])
    lo = np.clip(i - k, 0, len(legs))
    hi = np.clip(i, 0, len(legs))
    length = (cum[hi] - cum[lo]) / k  # each leg acts on k spans
    n = np.maximum(_CURVE_SEEDS_PER_SPAN, np.ceil(length / spacing)).astype(int)
    if n.sum() > at_most:
        n = np.maximum(2, (n * at_most) // n.sum())
    s = np.concatenate([br[j] + np.arange(n[j]) / n[j] * (br[j + 1] - br[j]) for j in range(len(n))])
    return np.append(s, b)


def _size(P: np.ndarray) -> float:
    """Size of a control net: its bounding-box diagonal (translation invariant), or the
    largest coordinate for a net collapsed to a point."""
    diag = float(np.linalg.norm(np.ptp(P, axis=0)))
    return diag if diag > 0 else max(float(np.abs(P).max()), 1e-300)


# ---------------------------------------------------------------------------------------
# global check: Bezier cell boxes and branch-and-bound over them
# ---------------------------------------------------------------------------------------

_CERT_REL = 2e-12  # a cell must be able to beat the best distance by this (relative, squared)
_BOX_MARGIN = 1e-9  # cell boxes are widened by this fraction of the size (Bezier round-off)
# children per node of the box hierarchies (surface cells in Morton order: 4 = 2 x 2 tiles)
_SURFACE_BRANCH = 4
_CURVE_BRANCH = 8
# curves of at most this many cells are searched without the hierarchy (all cell middles
# per point, vectorised, then balls and boxes): measured faster than the two-level
# hierarchy on the 35-cell benchmark curve
_FLAT_CELLS = 128


def _normalise_rows(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = np.sqrt(np.einsum("ij,ij->i", v, v))
    return v / np.where(n > 0, n, 1.0)[:, None], n



# ---------------------------------------------------------------------------------------
# component-major helpers of the Newton loops (vectors as (3, n) arrays: see _cell_boxes)
# ---------------------------------------------------------------------------------------


def _cols(a: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """Columns ``idx`` of a component-major array, C-contiguous: ``a[:, idx]`` would return
    them in Fortran order (rows strided), which made every later row operation several
    times slower."""
    return np.take(a, idx, axis=1)


def _on_threads(kernel: Any, P: np.ndarray, tables: dict[str, Any], shape_a: tuple, shape_b: tuple):
    """A compiled projection kernel (which returns two arrays per point) run over ranges of
    the points on the threads of :func:`geometry._jit.run_ranges` (it releases the GIL),
    each range's results copied into the whole arrays."""
    m = len(P)
    a, b = np.empty((m, *shape_a)), np.empty((m, *shape_b))

    def run(lo: int, hi: int) -> None:
        a[lo:hi], b[lo:hi] = kernel(P[lo:hi], **tables)

    _jit.run_ranges(run, m, per_thread=8)
    return a, b


def _nearest_cols(p: np.ndarray, Q: np.ndarray, tree: cKDTree | None) -> tuple[np.ndarray, np.ndarray]:
    """Index of the nearest sample ``Q[j]`` (n_s, 3) for every point of ``p`` (3, m), and
    the squared distance to it; for a few samples a chunked ``|Q|^2 - 2 Q.p`` argmin (one
    matrix product) beats the k-d tree several times over."""
    if tree is not None:
        dist, j = tree.query(p.T)
        return j, dist * dist
    QQ = np.einsum("ij,ij->i", Q, Q)[:, None]
    j = np.empty(p.shape[1], dtype=np.int64)
    chunk = max(128, 32_768 // max(len(Q), 1))  # small blocks stay in L2 (measured ~3x faster)
    for i in range(0, p.shape[1], chunk):
        j[i : i + chunk] = np.argmin(QQ - 2.0 * (Q @ p[:, i : i + chunk]), axis=0)
    d = Q[j].T - p
    return j, coldot(d, d)



# ---------------------------------------------------------------------------------------
# curve
# ---------------------------------------------------------------------------------------


@register_primitive
@dataclass(frozen=True, eq=False)
class BSplineCurve(Curve):
    """B-spline curve, rational (NURBS) when ``weights`` are given; see the module doc for
    the periodic convention and the normal convention."""

    type: ClassVar[str] = "bspline_curve"
    degree: int
    knots: np.ndarray
    control_points: np.ndarray
    weights: np.ndarray | None = None
    periodic: bool = False

    def __post_init__(self) -> None:
        owner = "bspline_curve"
        k = _degree(self.degree, owner, "degree")
        t = _knots(self.knots, owner, "knots")
        P = _array(self.control_points, owner, "control_points", "a list of 2- or 3-vectors")
        if P.ndim != 2 or P.shape[1] not in (2, 3):
            raise ValueError(
                f"{_field(owner, 'control_points')} must be a list of 2- or 3-vectors, got shape {P.shape}"
            )
        if not np.all(np.isfinite(P)):
            raise ValueError(f"{_field(owner, 'control_points')} must be finite")
        if np.any(np.abs(P) > MAX_COORDINATE):
            raise ValueError(
                f"{_field(owner, 'control_points')} must be within +-{MAX_COORDINATE:g} (squared distances would overflow)"
            )
        n = len(P)
        if n < k + 1:
            raise ValueError(
                f"{_field(owner, 'control_points')}: degree {k} needs at least {k + 1} control points, got {n}"
            )
        w = _weights(self.weights, (n,), owner)
        if not isinstance(self.periodic, (bool, np.bool_)):
            raise ValueError(f"{_field(owner, 'periodic')} must be true or false, got {self.periodic!r}")
        periodic = bool(self.periodic)
        P.setflags(write=False)
        for name, val in (("degree", k), ("knots", t), ("control_points", P), ("weights", w), ("periodic", periodic)):
            object.__setattr__(self, name, val)

        if periodic:
            full = self._periodic_knots(t, k, n, owner)
            coef_idx = np.arange(n + k) % n
        else:
            if len(t) != n + k + 1:
                raise ValueError(
                    f"{_field(owner, 'knots')}: expected len(control_points) + degree + 1 = {n + k + 1} knots, got {len(t)}"
                )
            full = t
            coef_idx = np.arange(n)
        _check_multiplicity(full, k, owner, "knots")
        n_coef = len(coef_idx)
        a, b = _domain(full, k, n_coef, owner, "knots")
        P3 = np.zeros((n, 3))
        P3[:, : P.shape[1]] = P
        if w is None:
            c = P3[coef_idx]
        else:
            c = np.column_stack([P3 * w[:, None], w])[coef_idx]
        BSpline, _ = _bspline_classes()
        object.__setattr__(self, "_spline", BSpline(full, c, k, extrapolate=True))
        object.__setattr__(self, "domain", (a, b))
        object.__setattr__(self, "dim", P.shape[1])
        object.__setattr__(self, "planar_z", bool(P.shape[1] == 2 or np.all(P[:, 2] == 0.0)))
        span = np.ptp(P3, axis=0)
        object.__setattr__(self, "scale", _size(P3))
        object.__setattr__(self, "extent", float(np.abs(P3).max()))

    @staticmethod
    def _periodic_knots(t: np.ndarray, k: int, n: int, owner: str) -> np.ndarray:
        if len(t) == n + 1:
            T = t[-1] - t[0]
            if not T > 0:
                raise ValueError(f"{_field(owner, 'knots')}: periodic knots must span a positive period, got {t.tolist()}")
            # n >= degree + 1 is checked above, so one period supplies the k wrapped knots
            full = np.empty(n + 2 * k + 1)
            full[k : k + n + 1] = t
            full[k + n + 1 :] = t[-1] + (t[1 : k + 1] - t[0])
            full[:k] = t[0] - (t[-1] - t[n - k : n])
            return full
        if len(t) == n + 2 * k + 1:
            T = t[k + n] - t[k]
            gaps = np.diff(t)
            if not np.allclose(gaps[n:], gaps[: len(gaps) - n], rtol=0, atol=1e-12 * max(abs(T), 1.0)):
                raise ValueError(
                    f"{_field(owner, 'knots')}: a periodic knot vector of {n + 2 * k + 1} knots must have knot "
                    f"spacing repeating every {n} knots"
                )
            return t
        raise ValueError(
            f"{_field(owner, 'knots')}: a periodic curve with {n} control points and degree {k} expects "
            f"{n + 1} knots (one period) or {n + 2 * k + 1} (unwrapped), got {len(t)}"
        )

    # -- dict round trip ------------------------------------------------------------------

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "BSplineCurve":
        f = check_fields(d, "bspline_curve", ("degree", "knots", "control_points"), ("weights", "periodic"))
        return cls(
            degree=f["degree"],
            knots=f["knots"],
            control_points=f["control_points"],
            weights=f.get("weights"),
            periodic=f.get("periodic", False),
        )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "type": self.type,
            "degree": self.degree,
            "knots": self.knots.tolist(),
            "control_points": self.control_points.tolist(),
        }
        if self.weights is not None:
            out["weights"] = self.weights.tolist()
        out["periodic"] = self.periodic
        return out

    # -- evaluation -------------------------------------------------------------------------

    def _wrap(self, t: np.ndarray) -> np.ndarray:
        a, b = self.domain
        if self.periodic:
            return a + np.mod(t - a, b - a)
        return np.clip(t, a, b)

    def derivatives(self, t: Any, order: int = 2) -> list[np.ndarray]:
        """``[C, C', ..., C^(order)]`` at parameters ``t`` (order <= 3), each (m, 3)
        (z = 0 for 2D curves). Parameters are clamped to (wrapped into) the domain."""
        t = self._wrap(np.asarray(t, dtype=float).ravel())
        sp = self._spline
        raw = [sp(t, nu) if nu <= self.degree else np.zeros((len(t), sp.c.shape[1])) for nu in range(order + 1)]
        if self.weights is None:
            return raw
        # quotient rule for C = A / w (Leibniz rule on A = w C)
        A = [r[:, :3] for r in raw]
        w = [r[:, 3:] for r in raw]
        inv = 1.0 / w[0]
        out = [A[0] * inv]
        binom = ((1,), (1, 1), (1, 2, 1), (1, 3, 3, 1))
        for k in range(1, order + 1):
            acc = A[k] - w[k] * out[0]
            for i in range(1, k):
                acc -= binom[k][i] * w[i] * out[k - i]
            out.append(acc * inv)
        return out

    def evaluate(self, t: Any) -> np.ndarray:
        """Points at parameters ``t``, shape (m, dim) in the dimension of the control points."""
        return self.derivatives(t, 0)[0][:, : self.dim]

    # -- projection -------------------------------------------------------------------------

    @cached_property
    def _seeds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, cKDTree | None]:
        """Sample parameters, the parameter distances to the neighbouring samples (2, n_s),
        the sample points (n_s, 3), and a k-d tree when there are too many samples for a
        brute-force nearest search."""
        a, b = self.domain
        # enough samples that neighbouring ones are about 1/32 of the curve's size apart,
        # judged by the control polygon (the curve lies in its convex hull span by span)
        coef = self._spline.c[:, :3] / (self._spline.c[:, 3:] if self.weights is not None else 1.0)
        legs = np.linalg.norm(np.diff(coef, axis=0), axis=1)
        s = _polygon_samples(self._spline.t, self.degree, a, b, legs, self.scale / _CURVE_SEED_SPACING, _CURVE_SEEDS_MAX)
        s = self._split_turning(s)
        gaps = np.diff(s)
        if self.periodic:
            s = s[:-1]
            reach = np.stack([np.roll(gaps, 1), gaps])
        else:
            reach = np.stack([np.r_[gaps[0], gaps], np.r_[gaps, gaps[-1]]])
        Q = np.ascontiguousarray(self.derivatives(s, 0)[0])
        tree = _kd_tree(Q) if len(s) > _BRUTE_SEEDS else None
        return s, reach, Q, tree

    def _tangent_nets(self, edges: np.ndarray) -> np.ndarray:
        """Bezier nets (n_cells, kn + 1, 3) of the numerator of C' over the cells between
        ``edges``: C' = (A' w - A w') / w^2 for C = A / w, a polynomial of degree <= 2k - 2
        (k - 1 without weights) on a knot span, so its net bounds its direction."""
        k = self.degree
        kn = 2 * k if self.weights is not None else k
        x = self._wrap((edges[:-1, None] + np.diff(edges)[:, None] * (np.arange(kn + 1) / kn)).ravel())
        H0, H1 = self._spline(x), self._spline(x, 1)
        N = H1[:, :3] * H0[:, 3:] - H0[:, :3] * H1[:, 3:] if self.weights is not None else H1[:, :3]
        return np.einsum("lm,cmd->cld", bernstein_inverse(kn), N.reshape(len(edges) - 1, kn + 1, 3))

    def _split_turning(self, s: np.ndarray) -> np.ndarray:
        """Cells (between neighbouring samples ``s``) over which the tangent may turn by more
        than ``2 _CELL_TURN`` (its Bezier net leaves a cone of that half-angle) are halved,
        until none is left or the samples number ``_CURVE_SEEDS_MAX``: a point near a sharp
        turn of the curve (a rational curve with large weights puts it in a short stretch of
        parameter) can have two local minima of its distance on one such cell."""
        cos_max = math.cos(_CELL_TURN)
        for _ in range(30):
            net = self._tangent_nets(s)
            u, length = _normalise_rows(net.reshape(-1, 3))
            u = u.reshape(net.shape)
            axis, _ = _normalise_rows(u.sum(axis=1))
            cos = np.einsum("cld,cd->cl", u, axis).min(axis=1)
            tiny = np.diff(s) <= 1e-9 * (s[-1] - s[0])
            bad = ((cos < cos_max) | (length.reshape(net.shape[:2]).min(axis=1) == 0.0)) & ~tiny
            if not bad.any() or len(s) + np.count_nonzero(bad) > _CURVE_SEEDS_MAX:
                return s
            s = np.sort(np.concatenate([s, 0.5 * (s[:-1] + s[1:])[bad]]))
        return s

    @cached_property
    def _pieces(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The cells between neighbouring samples (each inside one knot span, so one
        polynomial piece of the homogeneous curve) as Taylor polynomials about their
        middles: cell edges (n_c + 1,), middles (n_c,) and coefficients ((k + 1) D, n_c),
        row i D + d = d-th homogeneous coordinate of C^(i)(middle) / i!, from scipy."""
        s = self._seeds[0]
        edges = np.append(s, self.domain[1]) if self.periodic else s
        mids = 0.5 * (edges[:-1] + edges[1:])
        coef = np.concatenate([self._spline(mids, i).T / math.factorial(i) for i in range(self.degree + 1)])
        return edges, mids, np.ascontiguousarray(coef)

    def closest_parameters(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Parameters ``t`` (m,), closest points C(t) (m, 3) and derivatives C'(t) (m, 3)
        for (m, 3) points: the core of :meth:`project` (see the module doc)."""
        if len(points) == 0:
            return np.empty(0), np.empty((0, 3)), np.empty((0, 3))
        if _jit.enabled():
            return self._closest_jit(np.ascontiguousarray(points, dtype=float))
        p = np.ascontiguousarray(np.asarray(points, dtype=float).T)
        m = p.shape[1]
        s, _, Q, tree = self._seeds
        search = self._cells
        edges = self._pieces[0]
        n_cells = len(edges) - 1
        pis, cis = [], []
        # in blocks that stay in cache: the candidate (point, cell) pairs: cells closer
        # than the nearest sample
        for i0 in range(0, m, _BLOCK):
            q = p[:, i0 : i0 + _BLOCK]
            j, ub2 = _nearest_cols(q, Q, tree)
            pi, ci, ((low, high),) = search.pairs(q, ub2)
            if len(self._kinks) == 0:
                # a cell where f' = C'.(C - p) keeps one sign holds no minimum of its own:
                # the smallest distance on it is at an end it shares with a neighbouring
                # cell, which is a candidate too where that end is closer than the bound
                # (f' is continuous for a C1 curve, so two neighbours cannot both point at
                # their shared end); not at the ends of an open curve
                has_lo = np.ones(len(ci), bool) if self.periodic else ci > 0
                has_hi = np.ones(len(ci), bool) if self.periodic else ci < n_cells - 1
                keep = ~(((low > 0) & has_lo) | ((high < 0) & has_hi))
                pi, ci = pi[keep], ci[keep]
            # every point keeps a cell at its nearest sample (round-off safety net)
            orphan = np.ones(q.shape[1], dtype=bool)
            orphan[pi] = False
            rows = np.flatnonzero(orphan)
            pis += [pi + i0, rows + i0]
            cis += [ci, np.minimum(j[rows], n_cells - 1)]
        pi, ci = np.concatenate(pis), np.concatenate(cis)
        # Newton kept inside each candidate cell: the cell's own minimum (inner or an end);
        # the best per point wins
        t2, C2, C12 = np.empty(len(pi)), np.empty((3, len(pi))), np.empty((3, len(pi)))
        for i0 in range(0, len(pi), _PAIR_BLOCK):
            sl = slice(i0, i0 + _PAIR_BLOCK)
            t2[sl], C2[:, sl], C12[:, sl] = self._cell_minima(_cols(p, pi[sl]), ci[sl])
        r = C2 - _cols(p, pi)
        best = best_per_point(pi, coldot(r, r), m)
        return t2[best], C2[:, best].T, C12[:, best].T

    @cached_property
    def _cell_rows(self) -> dict[str, Any]:
        """The cells as rows of the curve-cell tables both paths use (see
        :mod:`geometry._curve_cells`): Taylor coefficients, end points, Bernstein nets of
        ``C'.(C - p)``."""
        edges, mids, coef = self._pieces
        D = 4 if self.weights is not None else 3
        return _curve_cells.cell_rows(coef, edges[:-1] - mids, edges[1:] - mids, self.degree, D)

    @cached_property
    def _jit_tables(self) -> dict[str, Any]:
        """The tables of the compiled kernel (see :mod:`geometry._jit`)."""
        edges, mids, coef = self._pieces
        # a deep hierarchy (one root group) suits the per-point traversal
        nodes, level_start = self._cell_search(_CURVE_BRANCH).flat_nodes()
        D = 4 if self.weights is not None else 3
        rows = self._cell_rows
        # a point of the curve in every node (the middle of the middle cell of its run of
        # leaves): an upper bound of the answer, tight from the first descent on
        rep_cell = middle_leaves(level_start, _CURVE_BRANCH, len(mids))
        middle = coef[:3] / coef[3:4] if D == 4 else coef[:3]
        return dict(
            rep=np.ascontiguousarray(middle[:, rep_cell].T), rep_cell=rep_cell,
            nodes=nodes, level_start=level_start, branch=_CURVE_BRANCH, mids=mids, edges=edges,
            M=rows["stat"].shape[1] // 4 - 1, k=self.degree, D=D,
            rational=self.weights is not None, periodic=self.periodic, prune=len(self._kinks) == 0,
            tol=_STRICT * self.scale, finish=_FINISH * self.scale, max_iter=_MAX_ITER,
            max_depth=_ISOLATE_DEPTH, cert=_CERT_REL, **rows,
        )

    @cached_property
    def _flat_tables(self) -> dict[str, Any]:
        """The tables of the compiled kernel without hierarchy (``curve_project_flat``, for
        at most ``_FLAT_CELLS`` cells): those of :attr:`_jit_tables` and the ball about
        every cell's middle holding its Bezier net (x, y, z, radius rows)."""
        t = self._jit_tables
        edges, mids, coef = self._pieces
        middle = coef[:3] / coef[3:4] if t["D"] == 4 else coef[:3]
        radius = np.linalg.norm(self._bezier_points - middle.T[:, None, :], axis=2).max(axis=1)
        balls = np.ascontiguousarray(np.vstack([middle, radius * (1.0 + 1e-12) + _BOX_MARGIN * self.scale]))
        leaf0 = int(t["level_start"][-2])
        keep = ("nodes", "coef", "mids", "edges", "ends", "stat", "M", "k", "D", "rational", "periodic", "prune",
                "tol", "finish", "max_iter", "max_depth", "cert")
        return dict(leaf0=leaf0, balls=balls, **{key: t[key] for key in keep})

    def _closest_jit(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`closest_parameters` by the compiled kernel (without the hierarchy for
        curves of few cells)."""
        if len(P) == 0:
            return np.empty(0), np.empty((0, 3)), np.empty((0, 3))
        if len(self._pieces[1]) <= _FLAT_CELLS:
            kernel, tables = _jit.kernels()["curve_project_flat"], self._flat_tables
        else:
            kernel, tables = _jit.kernels()["curve_project"], self._jit_tables
        t, CC = _on_threads(kernel, P, tables, (), (6,))
        return self._wrap(t), CC[:, :3], CC[:, 3:]

    @cached_property
    def _cells(self) -> CellSearch:
        return self._cell_search()

    @cached_property
    def _bezier_points(self) -> np.ndarray:
        """The Bezier control points (n_cells, k + 1, 3) of every cell's piece (its convex
        hull holds the cell, also for a rational piece: positive weights)."""
        edges = self._pieces[0]
        k = self.degree
        nodes = edges[:-1, None] + np.diff(edges)[:, None] * (np.arange(k + 1) / k)
        # Bezier nets of the pieces from their values (the pieces' own polynomials, so at a
        # cell's end the piece of that cell, also at a kink)
        n_cells = len(edges) - 1
        H = self._piece_values(np.repeat(np.arange(n_cells), k + 1), nodes.ravel())
        ctrl = np.einsum("lm,cmd->cld", bernstein_inverse(k), H.T.reshape(n_cells, k + 1, -1))
        return ctrl[..., :3] / ctrl[..., 3:] if self.weights is not None else ctrl[..., :3]

    def _cell_search(self, top: int | None = None) -> CellSearch:
        """Box hierarchy over the cells between neighbouring samples (every cell lies in one
        knot span, so it is one polynomial / rational Bezier piece), the cells' own oriented
        boxes (component-major) and the boxes of the direction of C' over each cell."""
        edges = self._pieces[0]
        margin = _BOX_MARGIN * self.scale
        pts = self._bezier_points
        chord = pts[:, -1] - pts[:, 0]
        bend = pts.mean(axis=1) - 0.5 * (pts[:, -1] + pts[:, 0])
        levels = box_levels(pts, chord, bend, _CURVE_BRANCH, margin, *(() if top is None else (top,)))
        origin, R, lo, hi = levels[-1]
        # the direction of C' over the cell, in the cell's frame
        N = self._tangent_nets(edges)
        return CellSearch(levels, _CURVE_BRANCH, extra=(frame_boxes(N, R),))

    def _piece_values(self, cell: np.ndarray, t: np.ndarray, order: int = 0):
        """Homogeneous values (and derivatives up to ``order``) of the pieces of cells
        ``cell`` at parameters ``t``, each (D, n)."""
        _, mids, coef = self._pieces
        out = _curve_cells.homogeneous_values(_cols(coef, cell), t - mids[cell], self.degree, order)
        return out if order else out[0]

    @cached_property
    def _kinks(self) -> np.ndarray:
        a, b = self.domain
        if self.periodic:  # steps stay within half a period of [a, b]
            return _kinks(self._spline.t, self.degree, 2 * a - b, 2 * b - a)
        return _kinks(self._spline.t, self.degree, a, b)

    def _cell_minima(self, p: np.ndarray, cell: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The closest point of each cell ``cell`` (n,) to its point (``p`` (3, n)): its
        ends and every local minimum inside, isolated by the Bernstein coefficients of
        ``C'.(C - p)`` over the cell (:func:`geometry._curve_cells.cell_minima`). Returns t
        (n,), C and C' (3, n) at the best."""
        edges, mids, coef = self._pieces
        x, _ = _curve_cells.cell_minima(
            p, cell, edges[cell] - mids[cell], edges[cell + 1] - edges[cell], k=self.degree,
            tol=_STRICT * self.scale, finish=_FINISH * self.scale, max_iter=_MAX_ITER, max_depth=_ISOLATE_DEPTH,
            **self._cell_rows,
        )
        C, C1 = _curve_cells.piece_values(_cols(coef, cell), x, self.degree, 1)
        return self._wrap(mids[cell] + x), C, C1

    def project(self, points: ArrayLike) -> Projection:
        p, dim = as_points(points, dims=(2, 3), finite=True)
        if dim == 2 and not self.planar_z:
            raise ValueError("bspline_curve: 2D query points need a curve in the z = 0 plane")
        t, C, C1 = self.closest_parameters(p)
        r = p - C
        kink = np.zeros(len(t), dtype=bool)
        if len(self._kinks):  # at (or held a nudge short of) a C0 kink
            gap = np.abs(t[:, None] - self._kinks[None, :]).min(axis=1)
            kink = gap <= 2.0 * _KINK_NUDGE * (self.domain[1] - self.domain[0])
        if dim == 2:
            T, _ = _normalise_rows(C1)
            normals = np.column_stack([T[:, 1], -T[:, 0], np.zeros(len(T))])
            normals, nn = _normalise_rows(normals)
            off, dd = _normalise_rows(r)
            normals[nn == 0] = off[nn == 0]
            if np.any(kink):
                # at a corner: along p - C, on the side of the bisector of the two one-sided
                # normals (the left tangent from just before the kink)
                a, b = self.domain
                Tl = _normalise_rows(self.derivatives(t[kink] - 1e-9 * (b - a), 1)[1])[0]
                bis = normals[kink] + np.column_stack([Tl[:, 1], -Tl[:, 0], np.zeros(len(Tl))])
                side = np.where(np.einsum("ij,ij->i", p[kink] - C[kink], bis) < 0, -1.0, 1.0)
                has = dd[kink] > 0
                k_idx = np.flatnonzero(kink)[has]
                normals[k_idx] = side[has, None] * off[k_idx]
        else:
            # the part of p - C perpendicular to the tangent: exactly normal to the curve
            # even where the closest point carries its convergence error along the tangent
            speed2 = np.einsum("ij,ij->i", C1, C1)
            with np.errstate(divide="ignore", invalid="ignore"):
                along = np.einsum("ij,ij->i", r, C1) / speed2
            along[speed2 == 0.0] = 0.0
            perp = r - along[:, None] * C1
            # at the ends and at kinks p - C may legitimately have a tangential part
            end = kink if self.periodic else kink | (t <= self.domain[0]) | (t >= self.domain[1])
            perp[end] = r[end]
            normals, dd = _normalise_rows(perp)
            on = dd <= 1e-14 * self.scale
            if np.any(on):
                Ton = _normalise_rows(C1[on])[0]
                axis = np.where(np.abs(Ton[:, 2:3]) > 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]))
                normals[on] = _normalise_rows(np.cross(Ton, axis))[0]
        distances = signed_lengths(r, normals)
        return restore_dim(Projection(points=C, normals=normals, distances=distances, parameters=t), dim)


# ---------------------------------------------------------------------------------------
# surface
# ---------------------------------------------------------------------------------------

_NU = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
_NU3 = _NU + ((3, 0), (2, 1), (1, 2), (0, 3))


@register_primitive
@dataclass(frozen=True, eq=False)
class BSplineSurface(Surface):
    """Tensor-product B-spline surface, rational (NURBS) when ``weights`` (nu x nv) are
    given. Parameter domain ``[knots_u[degree_u], knots_u[nu]] x [knots_v[degree_v],
    knots_v[nv]]``; normal ``unit(S_u x S_v)``."""

    type: ClassVar[str] = "bspline_surface"
    degree_u: int
    degree_v: int
    knots_u: np.ndarray
    knots_v: np.ndarray
    control_points: np.ndarray
    weights: np.ndarray | None = None

    def __post_init__(self) -> None:
        owner = "bspline_surface"
        ku = _degree(self.degree_u, owner, "degree_u")
        kv = _degree(self.degree_v, owner, "degree_v")
        tu = _knots(self.knots_u, owner, "knots_u")
        tv = _knots(self.knots_v, owner, "knots_v")
        P = _array(self.control_points, owner, "control_points", "an nu x nv x 3 array")
        if P.ndim != 3 or P.shape[2] != 3:
            raise ValueError(f"{_field(owner, 'control_points')} must be an nu x nv x 3 array, got shape {P.shape}")
        if not np.all(np.isfinite(P)):
            raise ValueError(f"{_field(owner, 'control_points')} must be finite")
        if np.any(np.abs(P) > MAX_COORDINATE):
            raise ValueError(
                f"{_field(owner, 'control_points')} must be within +-{MAX_COORDINATE:g} (squared distances would overflow)"
            )
        nu, nv = P.shape[:2]
        for kk, n, name in ((ku, nu, "nu"), (kv, nv, "nv")):
            if n < kk + 1:
                raise ValueError(
                    f"{_field(owner, 'control_points')}: degree {kk} needs {name} >= {kk + 1} control points, got {n}"
                )
        for t, kk, n, name in ((tu, ku, nu, "knots_u"), (tv, kv, nv, "knots_v")):
            if len(t) != n + kk + 1:
                raise ValueError(
                    f"{_field(owner, name)}: expected {n} control points + degree {kk} + 1 = {n + kk + 1} knots, got {len(t)}"
                )
            _check_multiplicity(t, kk, owner, name)
        dom_u = _domain(tu, ku, nu, owner, "knots_u")
        dom_v = _domain(tv, kv, nv, owner, "knots_v")
        w = _weights(self.weights, (nu, nv), owner)
        P.setflags(write=False)
        for name, val in (
            ("degree_u", ku),
            ("degree_v", kv),
            ("knots_u", tu),
            ("knots_v", tv),
            ("control_points", P),
            ("weights", w),
        ):
            object.__setattr__(self, name, val)
        c = P if w is None else np.concatenate([P * w[..., None], w[..., None]], axis=2)
        _, NdBSpline = _bspline_classes()
        object.__setattr__(self, "_spline", NdBSpline((tu, tv), np.ascontiguousarray(c), (ku, kv), extrapolate=True))
        object.__setattr__(self, "domain", (dom_u, dom_v))
        flat = P.reshape(-1, 3)
        object.__setattr__(self, "scale", _size(flat))
        object.__setattr__(self, "extent", float(np.abs(flat).max()))

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "BSplineSurface":
        f = check_fields(
            d, "bspline_surface", ("degree_u", "degree_v", "knots_u", "knots_v", "control_points"), ("weights",)
        )
        return cls(
            degree_u=f["degree_u"],
            degree_v=f["degree_v"],
            knots_u=f["knots_u"],
            knots_v=f["knots_v"],
            control_points=f["control_points"],
            weights=f.get("weights"),
        )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "type": self.type,
            "degree_u": self.degree_u,
            "degree_v": self.degree_v,
            "knots_u": self.knots_u.tolist(),
            "knots_v": self.knots_v.tolist(),
            "control_points": self.control_points.tolist(),
        }
        if self.weights is not None:
            out["weights"] = self.weights.tolist()
        return out

    # -- evaluation -------------------------------------------------------------------------

    def _clip(self, uv: np.ndarray) -> np.ndarray:
        (ua, ub), (va, vb) = self.domain
        return np.column_stack([np.clip(uv[:, 0], ua, ub), np.clip(uv[:, 1], va, vb)])

    def derivatives(self, uv: Any, order: int = 2) -> dict[tuple[int, int], np.ndarray]:
        """Partial derivatives ``{(i, j): d^(i+j) S / du^i dv^j}`` for i + j <= order
        (order <= 3) at (m, 2) parameters (clamped into the domain), each (m, 3)."""
        uv = self._clip(np.atleast_2d(np.asarray(uv, dtype=float)))
        nus = [nu for nu in _NU3 if sum(nu) <= order]
        width = self._spline.c.shape[-1]
        raw = {
            nu: self._spline(uv, nu=nu) if nu[0] <= self.degree_u and nu[1] <= self.degree_v else np.zeros((len(uv), width))
            for nu in nus
        }
        if self.weights is None:
            return raw
        # quotient rule for S = A / w: Leibniz on A = w S, in order of total degree
        A = {nu: r[:, :3] for nu, r in raw.items()}
        w = {nu: r[:, 3:] for nu, r in raw.items()}
        inv = 1.0 / w[(0, 0)]
        out = {(0, 0): A[(0, 0)] * inv}
        for a, b in nus[1:]:
            acc = A[(a, b)].copy()
            for i in range(a + 1):
                for j in range(b + 1):
                    if i or j:
                        acc -= (math.comb(a, i) * math.comb(b, j)) * w[(i, j)] * out[(a - i, b - j)]
            out[(a, b)] = acc * inv
        return out

    def evaluate(self, uv: Any) -> np.ndarray:
        """Points S(u, v) at (m, 2) parameters."""
        return self.derivatives(uv, 0)[(0, 0)]

    def normals_at(self, uv: Any) -> np.ndarray:
        """Unit normals ``unit(S_u x S_v)`` at (m, 2) parameters."""
        d = self.derivatives(uv, 1)
        return _normalise_rows(np.cross(d[(1, 0)], d[(0, 1)]))[0]

    # -- projection -------------------------------------------------------------------------

    @cached_property
    def _seeds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, cKDTree | None]:
        """The sample grid: its axes su (n_u,) and sv (n_v,), per direction spaced by the
        longest control polygon leg across the net (about 1/64 of the surface's size apart,
        at least 4 per knot span, every knot among them), its points (n_u n_v, 3; sample
        i n_v + j at (su[i], sv[j])), and a k-d tree of them when they are many."""
        axes = []
        P = self.control_points
        legs_u = np.linalg.norm(np.diff(P, axis=0), axis=2).max(axis=1)
        legs_v = np.linalg.norm(np.diff(P, axis=1), axis=2).max(axis=0)
        for t, k, (a, b), legs in (
            (self.knots_u, self.degree_u, self.domain[0], legs_u),
            (self.knots_v, self.degree_v, self.domain[1], legs_v),
        ):
            axes.append(_polygon_samples(t, k, a, b, legs, self.scale / _SURFACE_SEED_SPACING, _SURFACE_SEEDS_MAX))
        su, sv = axes
        U, V = np.meshgrid(su, sv, indexing="ij")
        Q = np.ascontiguousarray(self.evaluate(np.column_stack([U.ravel(), V.ravel()])))
        tree = _kd_tree(Q) if len(Q) > _BRUTE_SEEDS else None
        return su, sv, Q, tree

    @cached_property
    def _creases(self) -> tuple[np.ndarray, np.ndarray]:
        """Interior C0 knot lines (multiplicity >= degree) in u and in v."""
        (ua, ub), (va, vb) = self.domain
        return _kinks(self.knots_u, self.degree_u, ua, ub), _kinks(self.knots_v, self.degree_v, va, vb)

    @cached_property
    def _patches(self) -> dict[str, Any]:
        """The cells of the sample grid (each inside one knot span in both directions, so one
        polynomial or rational tensor patch) as Taylor polynomials about their middles, from
        scipy's partial derivatives there: ``coef`` (n_cells, (ku + 1) (kv + 1) D), cell
        i cv + j, column (a (kv + 1) + b) D + d the coefficient of x^a y^b of homogeneous
        component d. For the box hierarchy, in Morton order (``order``): the patches'
        Bezier control points ``pts`` (n_cells, (ku + 1) (kv + 1), 3), their directions
        along u and v, and the Bezier nets of the numerators of S_u and S_v (``tangent_nets``)."""
        su, sv, _, _ = self._seeds
        ku, kv = self.degree_u, self.degree_v
        cu, cv = len(su) - 1, len(sv) - 1
        mu, mv = 0.5 * (su[:-1] + su[1:]), 0.5 * (sv[:-1] + sv[1:])
        centres = np.column_stack([np.repeat(mu, cv), np.tile(mv, cu)])  # cell i cv + j
        D = 4 if self.weights is not None else 3
        coef = np.empty((cu * cv, (ku + 1) * (kv + 1) * D))
        for a in range(ku + 1):
            for b in range(kv + 1):
                col = (a * (kv + 1) + b) * D
                coef[:, col : col + D] = self._spline(centres, nu=(a, b)) / (math.factorial(a) * math.factorial(b))

        # Bezier nets from the Taylor polynomials (the patches Newton solves): values at
        # equally spaced nodes, mapped by the inverse Bernstein collocation matrix. With
        # x = h_u s, y = h_v t (s, t in [-1/2, 1/2]) the patch is sum c_ab h_u^a h_v^b s^a t^b.
        hu, hv = np.repeat(np.diff(su), cv), np.tile(np.diff(sv), cu)
        c = coef.reshape(cu * cv, ku + 1, kv + 1, D) * (
            (hu[:, None] ** np.arange(ku + 1))[:, :, None, None] * (hv[:, None] ** np.arange(kv + 1))[:, None, :, None]
        )

        def node_powers(k, deg, order):
            """d^order/ds^order of s^a (a = 0 .. k) at the nodes s_i = i / deg - 1/2."""
            s = np.arange(deg + 1) / deg - 0.5
            a = np.arange(k + 1)
            fall = np.array([math.perm(int(x), order) for x in a], dtype=float)
            return fall * s[:, None] ** np.maximum(a - order, 0) * (a >= order)

        def values(deg_u, deg_v, nu=(0, 0)):
            """d^nu A (homogeneous) at the (deg_u + 1) x (deg_v + 1) nodes of every cell."""
            H = np.einsum("ia,jb,cabd->cijd", node_powers(ku, deg_u, nu[0]), node_powers(kv, deg_v, nu[1]), c, optimize=True)
            return H / (hu ** nu[0] * hv ** nu[1])[:, None, None, None]

        def nets(H):
            deg_u, deg_v = H.shape[1] - 1, H.shape[2] - 1
            return np.einsum("am,bn,cmnd->cabd", bernstein_inverse(deg_u), bernstein_inverse(deg_v), H, optimize=True)

        rational = self.weights is not None
        net = nets(values(ku, kv))
        net = net[..., :3] / net[..., 3:] if rational else net
        along_u = net[:, -1, 0] - net[:, 0, 0] + net[:, -1, -1] - net[:, 0, -1]
        along_v = net[:, 0, -1] - net[:, 0, 0] + net[:, -1, -1] - net[:, -1, 0]
        order = morton_order(cu, cv)
        # the numerators of S_u, S_v: A_u w - A w_u for S = A / w (degree <= 2 ku - 1 in u
        # and 2 kv in v, so 2 ku + 1 by 2 kv + 1 nodes determine it); A_u, A_v without weights
        du, dv = (2 * ku, 2 * kv) if rational else (ku, kv)
        H0 = values(du, dv) if rational else None
        tangent_nets = []
        for nu in ((1, 0), (0, 1)):
            H = values(du, dv, nu)
            N = H[..., :3] * H0[..., 3:] - H0[..., :3] * H[..., 3:] if rational else H
            tangent_nets.append(nets(N).reshape(cu * cv, -1, 3)[order])
        tangent_nets = tuple(tangent_nets)
        return dict(
            coef=coef, order=order, pts=net.reshape(cu * cv, -1, 3)[order], along_u=along_u[order],
            along_v=along_v[order], tangent_nets=tangent_nets,
        )

    def _cell_search(self, top: int | None = None) -> CellSearch:
        """Box hierarchy over the cells (Morton order, so that groups of 4^n are 2^n x 2^n
        tiles) with the boxes of the numerators of S_u and S_v in the cells' frames; ``top``:
        the most nodes of its top level."""
        c = self._patches
        levels = box_levels(
            c["pts"], c["along_u"], c["along_v"], _SURFACE_BRANCH, _BOX_MARGIN * self.scale, *(() if top is None else (top,))
        )
        R = levels[-1][1]
        return CellSearch(levels, _SURFACE_BRANCH, extra=tuple(frame_boxes(N, R) for N in c["tangent_nets"]))

    @cached_property
    def _cells(self) -> CellSearch:
        # the numpy path screens a wide top level with one matrix product (see CellSearch)
        return self._cell_search()

    @cached_property
    def _cell_tables(self) -> dict[str, Any]:
        """The tables and tolerances both paths use (compiled: :mod:`geometry._jit`; numpy:
        :mod:`geometry._surface_cells`)."""
        c = self._patches
        su, sv, _, _ = self._seeds
        creases = self._creases
        return dict(
            leaf_cell=c["order"].astype(np.int64), coef=c["coef"], su=su, sv=sv, ku=self.degree_u, kv=self.degree_v,
            D=c["coef"].shape[1] // ((self.degree_u + 1) * (self.degree_v + 1)), rational=self.weights is not None,
            prune_u=len(creases[0]) == 0, prune_v=len(creases[1]) == 0, tol=_STRICT * self.scale,
            finish=_FINISH * self.scale, extent=self.extent, max_iter=_MAX_ITER, max_halvings=_MAX_HALVINGS,
        )

    @cached_property
    def _jit_tables(self) -> dict[str, Any]:
        """The tables of the compiled kernel (see :mod:`geometry._jit`): a deep hierarchy
        (at most ``_SURFACE_BRANCH`` top nodes) suits its per-point traversal. Every node
        carries a point of the surface, the middle of the cell in the middle of its run of
        leaves (``rep``, in cell ``rep_cell``): its distance bounds the answer from above, so
        the bound is tight from the first descent on (without it, a first descent into a
        wrong subtree whose boxes hold the point left the bound loose for hundreds of box
        tests)."""
        nodes, level_start = self._cell_search(_SURFACE_BRANCH).flat_nodes()
        cells = self._cell_tables
        coef, leaf_cell = cells["coef"], cells["leaf_cell"]
        middle = coef[:, :3] / coef[:, 3:4] if cells["D"] == 4 else coef[:, :3]  # S at the cell's middle
        rep_cell = leaf_cell[middle_leaves(level_start, _SURFACE_BRANCH, len(leaf_cell))]
        return dict(
            nodes=nodes, level_start=level_start, branch=_SURFACE_BRANCH, cert=_CERT_REL,
            rep=np.ascontiguousarray(middle[rep_cell]), rep_cell=rep_cell, **cells, **self._edge_tables,
        )

    @cached_property
    def _edge_tables(self) -> dict[str, Any]:
        """The four edges of every cell as curve cells (see :mod:`geometry._jit`): along u
        (``ue_*``, edge 2 c + s at the cell's lower (s = 0) or upper v bound) and along v
        (``ve_*``, at the lower or upper u bound): Taylor coefficients in the edge's own
        local parameter (from the patch's: the sum over the other coordinate's powers),
        end points, and the Bernstein nets of ``C'.(C - p)`` (``stat``) and of the squared
        distance (``fnet``, a lower bound of the distance along the edge)."""
        coef = self._patches["coef"]
        su, sv, _, _ = self._seeds
        ku, kv = self.degree_u, self.degree_v
        cu, cv = len(su) - 1, len(sv) - 1
        D = 4 if self.weights is not None else 3
        C = coef.reshape(cu * cv, ku + 1, kv + 1, D)
        half_u = np.repeat(0.5 * np.diff(su), cv)  # cell i cv + j
        half_v = np.tile(0.5 * np.diff(sv), cu)
        out: dict[str, Any] = {"max_depth": _ISOLATE_DEPTH}
        for name, k, half_along, half_other, spec in (
            ("ue", ku, half_u, half_v, "cabd,cb->cad"),
            ("ve", kv, half_v, half_u, "cabd,ca->cbd"),
        ):
            kk = kv if name == "ue" else ku  # degree of the coordinate held fixed
            sides = [np.einsum(spec, C, (s * half_other)[:, None] ** np.arange(kk + 1)) for s in (-1.0, 1.0)]
            E = np.stack(sides, axis=1).reshape(2 * cu * cv, (k + 1) * D)  # edge 2 c + s
            half = np.repeat(half_along, 2)
            rows = _curve_cells.cell_rows(np.ascontiguousarray(E.T), -half, half, k, D, distance=True)
            out.update({f"{name}_{key}": value for key, value in rows.items()})
            out[f"{name}_M"] = rows["stat"].shape[1] // 4 - 1
        return out

    def closest_parameters(self, points: np.ndarray) -> tuple[np.ndarray, dict[tuple[int, int], np.ndarray]]:
        """Parameters (m, 2) of the closest points and ``{(0,0): S, (1,0): S_u, (0,1): S_v}``
        there, for (m, 3) points: the core of :meth:`project` (see the module doc)."""
        p = np.ascontiguousarray(points, dtype=float)
        if len(p) == 0:
            return np.empty((0, 2)), {nu: np.empty((0, 3)) for nu in ((0, 0), (1, 0), (0, 1))}
        if _SURFACE_JIT and _jit.enabled():
            uv, S = _on_threads(_jit.kernels()["surface_project"], p, self._jit_tables, (2,), (9,))
        else:
            uv, S = self._closest_cells(p)
        return uv, {(0, 0): S[:, :3], (1, 0): S[:, 3:6], (0, 1): S[:, 6:]}

    def _closest_cells(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The numpy path (:mod:`geometry._surface_cells`), in blocks of ``_BLOCK`` points:
        the nearest grid sample gives each point's first bound. Returns uv (m, 2) and S,
        S_u, S_v (m, 9)."""
        p = np.ascontiguousarray(P.T)
        m = p.shape[1]
        _, _, Q, tree = self._seeds
        uv, S = np.empty((2, m)), np.empty((9, m))
        for i0 in range(0, m, _BLOCK):
            sl = slice(i0, i0 + _BLOCK)
            q = np.ascontiguousarray(p[:, sl])
            j, bound2 = _nearest_cols(q, Q, tree)
            uv[:, sl], S[:, sl] = _surface_cells.project_block(
                q, j, bound2, self._cells, edges=self._edge_tables, cert=_CERT_REL, **self._cell_tables
            )
        return uv.T, S.T

    def project(self, points: ArrayLike) -> Projection:
        p, _ = as_points(points, dims=(3,), finite=True)
        uv, d = self.closest_parameters(p)
        S = d[(0, 0)]
        normals, nn = _normalise_rows(np.cross(d[(1, 0)], d[(0, 1)]))
        bad = nn <= 1e-14 * self.scale**2
        if np.any(bad):
            off, dd = _normalise_rows(p[bad] - S[bad])
            off[dd == 0] = np.array([0.0, 0.0, 1.0])
            normals[bad] = off
        distances = signed_lengths(p - S, normals)
        return Projection(points=S, normals=normals, distances=distances, parameters=uv)
