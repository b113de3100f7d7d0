"""The band terms of a contact with friction history (solver.contact.friction_history), assembled
point by point from a cache of the region's pieces.

A load step of a fretting run solves the same region many times while only the stick/slip
boundaries move (zone updates, then secant steps of the boundaries). The region's quadrature is
split at both grids' lines and at the zones' boundaries; each piece between two consecutive cuts
is evaluated once (points, jump and flux operators, local size) and kept, so a trial computes only
the pieces at the moved boundaries. Each point's operators touch a few contact dofs (the nodes of
its cell in each body): they are kept as dense rows over those dofs, and the stiffness and load
are sums of small per-point blocks (the terms of solver.fem.step_boundary.thin_band_terms and of
the friction traction of solver.contact.band, with the same points and weights), assembled by one
sparse construction instead of products of sparse operators.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..fem.integration import curve_gauss
from ..fem.step_boundary import PENALTY_FACTOR, BoundaryPoints, acoustic_tensor
from .band import contact_operators, tangents, zone_projector
from .geometry import _parameters_at_s, match_points

__all__ = ["RegionPieces", "history_terms", "point_blocks"]

#: the per-point fields of contact points (concatenated and split by the region's pieces)
POINT_FIELDS = ("s", "x1", "n1", "x2", "n2", "delta", "weights")


@dataclass
class LocalRows:
    """Operators at q points as dense rows over each point's own dofs: cols (q, k) contact dof
    indices, jump and flux (q, 2, k) (zero where a point's dofs are fewer than k)."""

    cols: np.ndarray
    jump: np.ndarray
    flux: np.ndarray

    @classmethod
    def from_sparse(cls, jump: sp.csr_matrix, flux: sp.csr_matrix) -> "LocalRows":
        jd, fd = jump.toarray(), flux.toarray()
        q, m = jd.shape[0] // 2, jd.shape[1]
        used = (jd.reshape(q, 2, m) != 0.0).any(axis=1) | (fd.reshape(q, 2, m) != 0.0).any(axis=1)
        k = max(int(used.sum(axis=1).max()) if q else 0, 1)
        cols = np.argsort(~used, axis=1, kind="stable")[:, :k]
        take = np.broadcast_to(cols[:, None, :], (q, 2, k))
        return cls(cols, np.take_along_axis(jd.reshape(q, 2, m), take, axis=2),
                   np.take_along_axis(fd.reshape(q, 2, m), take, axis=2))

    def padded(self, k: int) -> "LocalRows":
        """The same rows over k >= their own dofs per point (the extra ones zero, on dof 0)."""
        n = k - self.cols.shape[1]
        if n <= 0:
            return self
        q = self.cols.shape[0]
        return LocalRows(np.concatenate([self.cols, np.zeros((q, n), dtype=self.cols.dtype)], axis=1),
                         np.concatenate([self.jump, np.zeros((q, 2, n))], axis=2),
                         np.concatenate([self.flux, np.zeros((q, 2, n))], axis=2))

    @staticmethod
    def concatenate(parts: list["LocalRows"]) -> "LocalRows":
        """The rows of consecutive pieces (each with as many dofs per point)."""
        return LocalRows(np.concatenate([p.cols for p in parts]), np.concatenate([p.jump for p in parts]),
                         np.concatenate([p.flux for p in parts]))

    def sparse(self, rows: np.ndarray, m: int) -> sp.csr_matrix:
        """(2 q, m) sparse operator of the dense rows ``rows`` (q, 2, k)."""
        q, _, k = rows.shape
        cols = np.repeat(self.cols, 2, axis=0).ravel()
        return sp.csr_matrix((rows.reshape(-1), cols, np.arange(0, 2 * q * k + 1, k)), shape=(2 * q, m))


class RegionPieces:
    """The cache of the region's pieces of one contact: (lo, hi) -> (points, LocalRows, size)."""

    def __init__(self, contact):
        self.contact = contact
        self.pieces: dict = {}
        self.width = 1  # dofs per point of every piece (the largest seen)

    def points(self, a: float, zone_bounds: np.ndarray):
        """(points, LocalRows, size) of the region of half-width a, cut at the grids' lines and at
        ``zone_bounds``: the same rule and points as one quadrature over the whole region."""
        c = self.contact
        lo, hi = c.region_ends(a)
        brk = np.concatenate([c.breakpoints, zone_bounds])
        cuts = np.unique(np.concatenate([[lo, hi], brk[(brk > lo) & (brk < hi)]]))
        keys = list(zip(cuts[:-1].tolist(), cuts[1:].tolist()))
        missing = [k for k in keys if k not in self.pieces]
        if missing:
            self._add(missing)
        parts = [self.pieces[k] for k in keys]
        if len(self.pieces) > 8 * len(keys):  # forget the pieces of boundaries long gone
            self.pieces = dict(zip(keys, parts))
        pts = dataclasses.replace(parts[0][0], **{f: np.concatenate([getattr(p[0], f) for p in parts])
                                                  for f in POINT_FIELDS})
        return pts, LocalRows.concatenate([p[1] for p in parts]), np.concatenate([p[2] for p in parts])

    def _add(self, keys: list[tuple[float, float]]) -> None:
        """Quadrature and operators of the pieces ``keys`` (one evaluation for all, split per piece)."""
        c = self.contact
        t = _parameters_at_s(c.geom, 0, np.array(keys, dtype=float).ravel()).reshape(-1, 2)
        _, w, _, tq = curve_gauss(c.geom.curves[0], t[:, 0], t[:, 1], c.options.order)
        pts = match_points(c.geom, tq.ravel())
        pts.weights = w.ravel()
        jump, flux, size = contact_operators(c, pts)
        rows = LocalRows.from_sparse(jump, flux)
        if rows.cols.shape[1] > self.width:  # a point with more dofs: every piece padded to it
            self.width = rows.cols.shape[1]
            self.pieces = {k: (p, r.padded(self.width), z) for k, (p, r, z) in self.pieces.items()}
        rows = rows.padded(self.width)
        n = w.shape[1]
        for i, key in enumerate(keys):
            sel = slice(i * n, (i + 1) * n)
            piece = dataclasses.replace(pts, **{f: getattr(pts, f)[sel] for f in POINT_FIELDS})
            self.pieces[key] = (piece, LocalRows(rows.cols[sel], rows.jump[sel], rows.flux[sel]), size[sel])


def history_terms(c, a: float):
    """Contact stiffness (sparse m x m), load (m,) and the quadrature data (``info``) of a history
    contact at half-width a: the sums of the points' blocks (point_blocks)."""
    m = len(c.dofs)
    if a <= 0.0:
        return sp.csr_matrix((m, m)), np.zeros(m), None
    k, load, rows, info = point_blocks(c, a)
    cols = rows.cols
    kk = cols.shape[1]
    kc = sp.csr_matrix((k.ravel(), (np.repeat(cols, kk, axis=1).ravel(), np.tile(cols, (1, kk)).ravel())),
                       shape=(m, m))
    fc = np.bincount(cols.ravel(), weights=load.ravel(), minlength=m)
    return kc, fc, info


def point_blocks(c, a: float):
    """The terms of a history contact at half-width a (> 0) point by point: stiffness blocks k
    (q, k, k) and loads (q, k) over each point's dofs (``rows.cols``), the LocalRows and the
    quadrature data (``info`` of history_terms). The thin-band terms (consistency 1) of every point
    with its projector (tied in the stick zone, the normal where slipping) and, where slipping,
    Coulomb's traction -sign mu p t_c on body 1 with p linear in the contact dofs (the
    non-symmetric friction block). A point's force on the contact dofs is k x[cols] - load."""
    m = len(c.dofs)
    raw, rows, size = c.region_pieces.points(a, c.bounds)
    pts = c.with_offset(raw)
    nrm, w = pts.normal, pts.weights
    proj = zone_projector(c, pts, a)
    layer = (PENALTY_FACTOR / (c.band_fraction * size))[:, None, None] * (
        proj @ acoustic_tensor(nrm, *c.layer) @ proj)
    pen, wp = w[:, None, None] * layer, w[:, None, None] * proj
    e, f = rows.jump, rows.flux
    pe = np.einsum("qij,qjk->qik", wp, e)
    k = np.einsum("qil,qij,qjk->qlk", e, pen, e) - np.einsum("qil,qik->qlk", f, pe)
    k = k - np.transpose(np.einsum("qil,qik->qlk", f, pe), (0, 2, 1))
    target = -pts.delta
    load = np.einsum("qil,qi->ql", e, np.einsum("qij,qj->qi", pen, target)) \
        - np.einsum("qil,qi->ql", f, np.einsum("qij,qj->qi", wp, target))
    signs = c.slip_signs(pts.s, a)
    slip = signs != 0.0
    if slip.any():  # p = r . x + b with r = n^T P F - n^T L J, b = -n^T L delta; body 1 gets -sign mu p t_c
        nl = np.einsum("qi,qij->qj", nrm, layer)
        r = np.einsum("qj,qjk->qk", np.einsum("qi,qij->qj", nrm, proj), f) - np.einsum("qj,qjk->qk", nl, e)
        b = -np.einsum("qi,qi->q", nl, pts.delta)
        tdir = -(signs * c.friction)[:, None] * tangents(nrm)
        g = np.einsum("qi,qik->qk", tdir, e)
        ws = np.where(slip, w, 0.0)
        k = k - ws[:, None, None] * g[:, :, None] * r[:, None, :]
        load = load + (ws * b)[:, None] * g
    e_q, f_q = rows.sparse(e, m), rows.sparse(f, m)
    bp = BoundaryPoints(pts.x1, w, nrm, size, e_q, f_q)
    return k, load, rows, (pts, bp, proj, e_q, f_q, size)
