"""Weighted means over a disc about each point of a plane point set, in memory linear in the points.

A mean over the disc of radius r about each of q points costs, held as a neighbour matrix, the
points of a disc per point: ~180 on the aligned sphere's region, ~2700 on an elongated contact on
a grid turned against its plane (12 bytes each in a sparse matrix, 1.6 GB for 39k points). Here
the plane is cut into square bins of side r / BINS_PER_RADIUS; a mean sums, per bin, the weights,
the weighted positions and the weighted values of the points taken, then adds for each point the
bins whose weighted centre lies within r of it (the point's own bin always). The disc's rim is
thus drawn through the bins' centres: a point near the rim is in or out with its bin, within
half a bin's diagonal (0.09 r) of its own distance. The bins wholly within r of every point of a
row's bin are taken without the test; in a mean without conditions they are summed as runs along the
grid's rows (one run sum per stencil column: 13 gathers per point instead of 137 with bins of r/8),
the rim's bins one by one. Memory: the per-bin sums (at most about four bins per point), the run
sums (one per half length of a column, 4 for each quantity with bins of r/8) and, per block of
BLOCK_ROWS points, the bins of the stencil about them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: bins per disc radius: a bin's side is r / 8
BINS_PER_RADIUS = 8
#: points whose stencils are gathered at once (BLOCK_ROWS x ~130 rim bins of a few arrays; blocks of 1024
#: rows keep them in the cache: 20 % less time per mean than 4096)
BLOCK_ROWS = 1024


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

    def _padded(self) -> tuple[int, np.ndarray, np.ndarray]:
        """(row length, each point's flat bin, the stencil's flat offsets) on the grid padded by the
        stencil's reach on every side (no offset leaves it)."""
        reach = int(np.abs(self.stencil).max()) if len(self.stencil) else 0
        ny = self.shape[1] + 2 * reach
        flat = (self.cell[:, 0] + reach) * ny + self.cell[:, 1] + reach
        return (self.shape[0] + 2 * reach) * ny, flat, self.stencil[:, 0] * ny + self.stencil[:, 1]

    def _inner(self) -> np.ndarray:
        """(S,) bool the stencil's bins wholly within the radius of any point of the row's bin (taken
        without the distance test)."""
        st = self.stencil
        return np.hypot(np.abs(st[:, 0]) + 1, np.abs(st[:, 1]) + 1) * self.side <= self.radius

    def _inner_columns(self, inner: np.ndarray) -> list[tuple[int, int]]:
        """The inner bins as columns of the padded grid: (flat offset of the column's middle, half
        length m), the column's bins at offsets -m..m along the row (the inner set is symmetric and
        shrinks away from the row's axis)."""
        ny = self._padded_ny()
        columns = []
        for ox in np.unique(self.stencil[inner, 0]):
            oy = self.stencil[inner & (self.stencil[:, 0] == ox), 1]
            m = int(oy.max())
            assert np.array_equal(np.sort(oy), np.arange(-m, m + 1))
            columns.append((int(ox) * ny, m))
        return columns

    def _padded_ny(self) -> int:
        reach = int(np.abs(self.stencil).max()) if len(self.stencil) else 0
        return self.shape[1] + 2 * reach

    def means(self, values: np.ndarray, members: np.ndarray, rows: np.ndarray,
              conditions: tuple = ()) -> np.ndarray:
        """(len(rows), k) the weighted means of values (q, k) over the members within the disc
        about each row's point (0 where none). conditions: (c, c_rows, limit) triples, c (q,) a
        quantity of the points and c_rows (len(rows),) the rows': a bin is taken only when its
        members' weighted mean of c is at most limit(c_rows), unless it is the row's own bin."""
        values = np.asarray(values, dtype=float).reshape(len(self.s), -1)
        members = np.asarray(members, dtype=bool)
        rows = np.asarray(rows, dtype=np.int64)
        n_bins, flat, offsets = self._padded()
        w = np.where(members, self.weights, 0.0)

        def per_bin(col):  # the members' weighted sums per bin (a non-member's infinity counts nothing)
            return np.bincount(flat, weights=np.where(members, w * col, 0.0), minlength=n_bins)
        wb = np.bincount(flat, weights=w, minlength=n_bins)
        safe = np.where(wb > 0.0, wb, 1.0)
        centre = [per_bin(self.s[:, j]) / safe for j in range(2)]
        sums = [per_bin(values[:, j]) for j in range(values.shape[1])]
        cond = [(per_bin(np.asarray(c, dtype=float)) / safe, np.asarray(c_rows, dtype=float), limit)
                for c, c_rows, limit in conditions]
        inner = self._inner()
        runs = None if cond else _runs(self._inner_columns(inner), wb, sums)
        own = offsets == 0
        parts = [(offsets[~inner], own[~inner], True)] + ([] if runs else [(offsets[inner], own[inner], False)])
        r2 = self.radius**2
        perm = np.argsort(flat[rows], kind="stable")  # the rows bin by bin: the gathers stay local
        rows = rows[perm]
        cond = [(mean_c, c_rows[perm], limit) for mean_c, c_rows, limit in cond]
        out = np.zeros((len(rows), values.shape[1]))
        for start in range(0, len(rows), BLOCK_ROWS):
            block = rows[start:start + BLOCK_ROWS]
            den, num = np.zeros(len(block)), np.zeros((len(block), len(sums)))
            if runs:  # the inner bins: one run sum per stencil column
                for step, (run_w, run_v) in runs:
                    b = flat[block] + step
                    den += run_w[b]
                    for j, vb in enumerate(run_v):
                        num[:, j] += vb[b]
            for offs, own_part, rim in parts:
                b = flat[block][:, None] + offs[None, :]  # (rows, stencil part) the bins about each row
                take = np.ones(b.shape, dtype=bool)
                if rim:
                    dx = centre[0][b] - self.s[block, 0][:, None]
                    dy = centre[1][b] - self.s[block, 1][:, None]
                    take = (dx * dx + dy * dy <= r2) | own_part[None, :]
                for mean_c, c_rows, limit in cond:
                    take &= (mean_c[b] <= limit(c_rows[start:start + len(block)])[:, None]) | own_part[None, :]
                weight = take.astype(float)
                den += np.einsum("rs,rs->r", weight, wb[b])
                for j, vb in enumerate(sums):
                    num[:, j] += np.einsum("rs,rs->r", weight, vb[b])
            ok = den > 0.0
            out[start + np.flatnonzero(ok)] = num[ok] / den[ok, None]
        unsorted = np.empty_like(out)
        unsorted[perm] = out
        return unsorted


def _runs(columns: list[tuple[int, int]], wb: np.ndarray, sums: list) -> list:
    """Per column (step, m) of the inner bins: (step, (the run sums of wb over -m..m along each
    bin's row, the same of each of sums)). The runs are summed outward from the bin, each bin's
    term once: the padding keeps them within the bin's row for every bin a row can hold."""
    def run_sums(a, half_lengths):
        out, run, m = {}, a.copy(), 0
        for target in sorted(half_lengths):
            while m < target:
                m += 1
                run[m:] += a[:-m]
                run[:-m] += a[m:]
            out[target] = run.copy()
        return out
    half = {m for _, m in columns}
    runs_w = run_sums(wb, half)
    runs_v = [run_sums(vb, half) for vb in sums]
    return [(step, (runs_w[m], [r[m] for r in runs_v])) for step, m in columns]
