"""Weighted means over a disc about each point of a plane point set, in memory linear in the points.

A mean over the disc of radius r about each of q points costs, held as a neighbour matrix, the
points of a disc per point: ~180 on the aligned sphere's region, ~2700 on an elongated contact on
a grid turned against its plane (12 bytes each in a sparse matrix, 1.6 GB for 39k points). Here
the plane is cut into square bins of side r / BINS_PER_RADIUS; a mean sums, per bin, the weights,
the weighted positions and the weighted values of the points taken, then adds for each point the
bins whose weighted centre lies within r of it (the point's own bin always). The disc's rim is
thus drawn through the bins' centres: a point near the rim is in or out with its bin, within
half a bin's diagonal (0.18 r) of its own distance. Memory: the per-bin sums (at most about four
bins per point) and, per block of BLOCK_ROWS points, the bins of the stencil about them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: bins per disc radius: a bin's side is r / 4
BINS_PER_RADIUS = 4
#: points whose stencils are gathered at once (BLOCK_ROWS x ~100 bins of a few arrays)
BLOCK_ROWS = 4096


@dataclass
class DiscBins:
    """The bins of a plane point set for means over discs of one radius."""

    s: np.ndarray        # (q, 2) the points' plane coordinates
    weights: np.ndarray  # (q,) their weights (areas)
    radius: float
    side: float          # a bin's side
    cell: np.ndarray     # (q, 2) int the bin of each point
    shape: tuple         # the bin grid's (nx, ny)
    stencil: np.ndarray  # (S, 2) int the offsets of the bins that can hold points within the radius

    @classmethod
    def build(cls, s: np.ndarray, weights: np.ndarray, radius: float) -> "DiscBins":
        s = np.asarray(s, dtype=float)
        if s.ndim != 2 or s.shape[1] != 2:
            raise ValueError(f"disc means: the points must be plane coordinates (q, 2), got shape {s.shape}")
        if not radius > 0.0:
            raise ValueError(f"disc means: the radius must be positive, got {radius}")
        lo = s.min(axis=0) if len(s) else np.zeros(2)
        span = (s.max(axis=0) - lo) if len(s) else np.zeros(2)
        side = radius / BINS_PER_RADIUS
        # never many more bins than points (a region much larger than the disc on few points)
        side = max(side, math.sqrt(max(float(span[0] * span[1]), 0.0) / max(4.0 * len(s), 1.0)))
        cell = np.floor((s - lo) / side).astype(np.int64)
        shape = tuple(int(n) for n in (cell.max(axis=0) + 1 if len(s) else (1, 1)))
        reach = int(math.ceil(radius / side)) + 1
        o = np.arange(-reach, reach + 1)
        ox, oy = (g.ravel() for g in np.meshgrid(o, o, indexing="ij"))
        # a bin's weighted centre lies in the bin: the offset's nearest corner must be within r
        gap = side * np.hypot(np.maximum(np.abs(ox) - 1, 0), np.maximum(np.abs(oy) - 1, 0))
        keep = gap <= radius
        return cls(s, np.asarray(weights, dtype=float), float(radius), side, cell, shape,
                   np.column_stack([ox[keep], oy[keep]]))

    def nbytes(self) -> int:
        return int(self.s.nbytes + self.weights.nbytes + self.cell.nbytes + self.stencil.nbytes)

    def _flat(self, cell: np.ndarray) -> np.ndarray:
        return cell[..., 0] * self.shape[1] + cell[..., 1]

    def _bin_sums(self, members: np.ndarray, columns: np.ndarray) -> np.ndarray:
        """(bins, 3 + k) per bin the members' weight, weighted x, y and weighted columns."""
        nb = self.shape[0] * self.shape[1]
        w = np.where(members, self.weights, 0.0)
        vals = np.column_stack([np.ones(len(w)), self.s, columns])
        vals = np.where(members[:, None], vals, 0.0)  # an infinite column of a non-member counts nothing
        flat = self._flat(self.cell)
        return np.column_stack([np.bincount(flat, weights=w * vals[:, j], minlength=nb)
                                for j in range(vals.shape[1])])

    def means(self, values: np.ndarray, members: np.ndarray, rows: np.ndarray,
              conditions: tuple = ()) -> np.ndarray:
        """(len(rows), k) the weighted means of values (q, k) over the members within the disc
        about each row's point (0 where none). conditions: (c, c_rows, limit) triples, c (q,) a
        column's quantity and c_rows (len(rows),) the row's: a bin is taken only when its members'
        weighted mean of c is at most c_rows + ... as the caller's limit(c_rows) gives, unless it is
        the row's own bin."""
        values = np.asarray(values, dtype=float).reshape(len(self.s), -1)
        k = values.shape[1]
        extra = [c for c, _, _ in conditions]
        sums = self._bin_sums(np.asarray(members, dtype=bool), np.column_stack([values] + extra)
                              if extra else values)
        out = np.zeros((len(rows), k))
        for start in range(0, len(rows), BLOCK_ROWS):
            block = np.asarray(rows[start:start + BLOCK_ROWS])
            out[start:start + len(block)] = self._block_means(sums, block, k, conditions, start)
        return out

    def _block_means(self, sums, block, k, conditions, start) -> np.ndarray:
        cell = self.cell[block][:, None, :] + self.stencil[None, :, :]  # (b, S, 2)
        inside = ((cell >= 0) & (cell < np.asarray(self.shape))).all(axis=2)
        flat = np.where(inside, self._flat(np.maximum(cell, 0)), 0)
        own = (self.stencil == 0).all(axis=1)[None, :]
        bs = sums[flat]  # (b, S, 3 + k + len(conditions))
        w = np.where(inside, bs[..., 0], 0.0)
        safe = np.where(w > 0.0, w, 1.0)
        centre = bs[..., 1:3] / safe[..., None]
        take = (w > 0.0) & (own | (np.linalg.norm(centre - self.s[block][:, None, :], axis=2) <= self.radius))
        for j, (_, c_rows, limit) in enumerate(conditions):
            mean_c = bs[..., 3 + k + j] / safe
            take &= own | (mean_c <= limit(np.asarray(c_rows)[start:start + len(block)])[:, None])
        wt = np.where(take, w, 0.0)
        den = wt.sum(axis=1)
        num = np.einsum("bs,bsk->bk", take.astype(float), bs[..., 3:3 + k])
        ok = den > 0.0
        res = np.zeros((len(block), k))
        res[ok] = num[ok] / den[ok, None]
        return res
