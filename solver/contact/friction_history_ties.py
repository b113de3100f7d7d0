"""Diagnostic ties of the stuck points of the 3D friction history (solver.contact.friction_history3d).

The history ties each stuck point at its own jump (the contact's thin band terms). The ties here
were built to measure how the energy per cycle at small amplitudes depends on that tie
(docs/load-paths.md, "The stuck points' ties: where their stiffness acts and their stiff limit
(3D)" and "The stuck points' ties: the stiff limit's rate with h, the consistency flux and an
exact hold (3D)"); none is the default:

- a mean tie: the stuck points of a group of cells tied by their area-weighted mean tangential
  jump, one tie per group and component (a piecewise constant multiplier), its traction
  -k (mean jump - mean reference jump) plus the consistency term's mean flux, the same at every
  stuck point of the group; the groups tied so are those the slip zone cuts (``CUT_CELL_TIE``
  "mean") or all (``"all"``); the groups (``TIE_GROUPS``) are the two bodies' cell pairs, one
  body's cells, squares of n cells on the tangent plane from the contact's centre ("patchN") or
  squares of one cell about the grid's nodes ("nodes");
- the stuck points within ``NEAR_CELLS`` cells of the slip zone tied on a layer ``NEAR_BAND``
  times the others' (their stiffness divided by it);
- a recovered flux (``RECOVERED_FLUX``): the consistency term of the stuck points' tangential tie
  takes, instead of the bodies' mean stress at the point, its area-weighted mean over the stuck
  points within a disc of ``RECOVERED_FLUX`` cells in diameter, or one body's stress alone
  (``TIE_FLUX``; the normal tie keeps the two bodies' mean at the point);
- augmented-Lagrangian ties (``UZAWA_TOLERANCE``): the stuck points held exactly at their jump,
  the tie's anchor moved by its stretch solve after solve (Uzawa's update of the multiplier).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

__all__ = ["grouped", "mean_operator", "mean_terms", "mean_traction", "body_flux", "recovery_operator", "tangential_bands",
           "tie_groups"]

#: the stuck points tied by their group's mean: "points" none (each at its own jump, the default),
#: "mean" those of the groups holding slipping points too, "all" every stuck point
CUT_CELL_TIE = "points"
#: the groups of the mean ties: "pairs" (the two bodies' cells), "cell1", "cell2" (one body's
#: cells), "patchN" (squares of N cells from the contact's centre), "nodes" (squares of one cell
#: about the grid's nodes)
TIE_GROUPS = "pairs"
#: the mean tie's consistency term (the stuck points' mean flux): 1 Nitsche's, 0 a plain penalty
CUT_CELL_CONSISTENCY = 1.0
#: the stuck points within NEAR_CELLS cells of the slip zone tie on a layer NEAR_BAND times the
#: others' (None: all on the same layer)
NEAR_BAND = None
NEAR_CELLS = 1.0
#: the stuck points' tangential consistency flux averaged over a disc of this many cells in
#: diameter among the stuck points (None: the bodies' mean stress at each point, Nitsche's)
RECOVERED_FLUX = None
#: the stuck points' tangential consistency flux: "mean" the two bodies' mean stress (Nitsche's
#: symmetric weights), "1" or "2" one body's stress alone (the other's weight 0)
TIE_FLUX = "mean"
#: augmented-Lagrangian (Uzawa) ties of the stuck points: None none; else each stuck point's anchor is
#: moved by its tie's tangential stretch after the zones settle, solved again until the largest
#: stretch is this fraction of the step's largest jump increment, at most UZAWA_UPDATES times
UZAWA_TOLERANCE = None
UZAWA_UPDATES = 200


def tie_groups(local_s: np.ndarray, h: float, cells1: np.ndarray, cells2: np.ndarray) -> np.ndarray:
    """(q,) each point's group of ``TIE_GROUPS`` as an index; ``local_s`` the points' tangent-plane
    coordinates from the contact's centre, h the contact's cell, cells1/cells2 the bodies' cells."""
    if TIE_GROUPS == "nodes":
        key = np.floor(local_s / h + 0.5).astype(np.int64)
    elif TIE_GROUPS.startswith("patch"):
        key = np.floor(local_s / (float(TIE_GROUPS[5:]) * h)).astype(np.int64)
    elif TIE_GROUPS in ("pairs", "cell1", "cell2"):
        key = {"pairs": np.column_stack([cells1, cells2]), "cell1": cells1[:, None],
               "cell2": cells2[:, None]}[TIE_GROUPS]
    else:
        raise ValueError(f"friction_history_ties.TIE_GROUPS: unknown groups {TIE_GROUPS!r} "
                         "(pairs, cell1, cell2, patchN, nodes)")
    return np.unique(key, axis=0, return_inverse=True)[1].ravel()


def grouped(group: np.ndarray, slip: np.ndarray) -> np.ndarray:
    """(q,) the stuck points tied by their group's mean (``CUT_CELL_TIE``)."""
    if CUT_CELL_TIE == "all":
        return ~slip
    if CUT_CELL_TIE == "points" or not slip.any():
        return np.zeros(len(slip), dtype=bool)
    if CUT_CELL_TIE != "mean":
        raise ValueError(f"friction_history_ties.CUT_CELL_TIE: unknown tie {CUT_CELL_TIE!r} (points, mean, all)")
    has_slip = np.bincount(group, weights=slip.astype(float), minlength=int(group.max()) + 1) > 0.0
    return ~slip & has_slip[group]


def mean_operator(group: np.ndarray, tied: np.ndarray, weights: np.ndarray, normal: np.ndarray,
                  layer_t: np.ndarray):
    """(M, area, stiffness, g, idx): M (3 G, 3 q) the tangential mean over each group's tied points
    (area-weighted, each point's jump projected on its tangent plane), their area (G,), the tie's
    stiffness per area (G,, the area-weighted mean of ``layer_t``), the group (0..G-1) of each
    tied point and the tied points ``idx``."""
    idx = np.flatnonzero(tied)
    g = np.unique(group[idx], return_inverse=True)[1].ravel()
    wq = weights[idx]
    area = np.bincount(g, weights=wq)
    stiffness = np.bincount(g, weights=wq * layer_t[idx]) / area
    n = normal[idx]
    blocks = (wq / area[g])[:, None, None] * (np.eye(3)[None] - n[:, :, None] * n[:, None, :])
    rows = np.broadcast_to(3 * g[:, None, None] + np.arange(3)[None, :, None], blocks.shape)
    cols = np.broadcast_to(3 * idx[:, None, None] + np.arange(3)[None, None, :], blocks.shape)
    mean = sp.csr_matrix((blocks.ravel(), (rows.ravel(), cols.ravel())), shape=(3 * len(area), 3 * len(tied)))
    return mean, area, stiffness, g, idx


def mean_terms(mean: sp.csr_matrix, area: np.ndarray, stiffness: np.ndarray, jump: sp.csr_matrix,
               flux: sp.csr_matrix, offset: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Stiffness and load of the mean ties: per group the energy A k |M (J x + offset)|^2 / 2 less
    the consistency term A (M F x) . M (J x + offset) (symmetrised), ``offset`` (q, 3) the points'
    gap less their reference jump."""
    jb, fb = (mean @ jump).tocsr(), (mean @ flux).tocsr()
    d = mean @ np.asarray(offset, dtype=float).ravel()
    wk, wa = np.repeat(area * stiffness, 3), np.repeat(area, 3)
    cross = fb.T @ sp.diags(wa) @ jb
    k = jb.T @ sp.diags(wk) @ jb - CUT_CELL_CONSISTENCY * (cross + cross.T)
    f = -(jb.T @ (wk * d)) + CUT_CELL_CONSISTENCY * (fb.T @ (wa * d))
    return sp.csr_matrix(k), np.asarray(f).ravel()


def mean_traction(mean: sp.csr_matrix, stiffness: np.ndarray, held: np.ndarray, flux_at: np.ndarray) -> np.ndarray:
    """(G, 3) each group's traction on body 1: -k M held + M flux (``held`` (q, 3) the jump less the
    reference, ``flux_at`` (q, 3) the bodies' mean traction at the points)."""
    return -stiffness[:, None] * (mean @ held.ravel()).reshape(-1, 3) \
        + CUT_CELL_CONSISTENCY * (mean @ flux_at.ravel()).reshape(-1, 3)


def tangential_bands(s: np.ndarray, slip: np.ndarray, h: float, base: float) -> np.ndarray:
    """(q,) each point's tangential tie's layer over the contact's band: ``base``, times
    ``NEAR_BAND`` for the stuck points within ``NEAR_CELLS`` cells h of the slip zone."""
    out = np.full(len(slip), float(base))
    if NEAR_BAND is not None and slip.any():
        d = cKDTree(s[slip]).query(s)[0]
        out[~slip & (d < NEAR_CELLS * h)] *= NEAR_BAND
    return out


def recovery_operator(s: np.ndarray, weights: np.ndarray, stuck: np.ndarray, radius: float) -> sp.csr_matrix:
    """(3 q, 3 q) the recovered flux's operator on the points' fluxes (rows [x0, y0, z0, x1, ...]):
    a stuck point's row the area-weighted mean over the stuck points within ``radius`` of it
    (itself included), a slipping point's its own flux."""
    q = len(stuck)
    idx = np.flatnonzero(stuck)
    pairs = cKDTree(s[idx]).query_pairs(radius, output_type="ndarray") if len(idx) else np.zeros((0, 2), int)
    r = np.concatenate([pairs[:, 0], pairs[:, 1], np.arange(len(idx))])
    c = np.concatenate([pairs[:, 1], pairs[:, 0], np.arange(len(idx))])
    w = weights[idx][c]
    w = w / np.bincount(r, weights=w, minlength=len(idx))[r]
    free = np.flatnonzero(~stuck)
    rows = np.concatenate([idx[r], free])
    cols = np.concatenate([idx[c], free])
    vals = np.concatenate([w, np.ones(len(free))])
    mean = sp.csr_matrix((vals, (rows, cols)), shape=(q, q))
    return sp.kron(mean, sp.identity(3), format="csr")


def body_flux(contact, pts, mean_flux: sp.csr_matrix) -> sp.csr_matrix:
    """(3 q, m) the flux of ``TIE_FLUX`` at a region's points: the two bodies' mean (``mean_flux``)
    or one body's traction sigma n1 alone."""
    if TIE_FLUX == "mean":
        return mean_flux
    if TIE_FLUX not in ("1", "2"):
        raise ValueError(f"friction_history_ties.TIE_FLUX: unknown flux {TIE_FLUX!r} (mean, 1, 2)")
    from .band import locate_cells
    body, x, n, mapping = ((contact.b1, pts.x1, pts.n1, contact.maps[0]) if TIE_FLUX == "1"
                           else (contact.b2, pts.x2, pts.n2, contact.maps[2]))
    return body.traction_operator(x, locate_cells(body, x, n), pts.n1, mapping).tocsr()
