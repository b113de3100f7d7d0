"""A body's contact curve in 2D: the chain of the boundary edges through the contact point.

A CAD profile is a loop of edges (lines, arcs, elliptic arcs, B-splines) joined end to start,
tangentially (G1: a flat meeting its fillet) or at a corner (G0: a punch's sharp edge). The
contact region may cross any of these junctions, and a full circle's seam. The chain joins the
loop's edges into one curve with the parameter T: the k-th edge of the chain covers
k <= T <= k + 1 (its own parameter mapped linearly), the edge through the contact point sits
in the middle and the loop is walked once around on each side (a single closed edge, a bore,
appears three times: its seam is a junction like any other). The chain offers what the contact
geometry needs of a curve (``evaluate``, ``derivative``, ``axis_crossings``, ``breakpoints``,
``t_start``, ``t_end``), for exact edges and tessellated polylines alike.

Corners: at each junction the turn of the tangent, from the exact edges (positive to the left,
where the material lies: a convex corner). A turn above :data:`CORNER_ANGLE` is a corner of the
body, where a contact region of that body ends (a complete contact end).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.junctions import CORNER_ANGLE, nearest_junction, tangent_turn, unit_tangent

__all__ = ["CORNER_ANGLE", "ContactChain", "contact_chain"]

@dataclass
class ContactChain:
    """Edges ``names`` (curves ``curves``, each oriented along the loop) joined into one curve;
    ``turns[k]`` the tangent's turn at T = k + 1 (between edge k and edge k + 1)."""

    names: tuple[str, ...]
    curves: tuple
    turns: np.ndarray
    middle: int  # index of the edge through the contact point

    def __post_init__(self):
        self._lo = np.array([float(c.t_start) for c in self.curves])
        self._span = np.array([float(c.t_end) - float(c.t_start) for c in self.curves])

    @property
    def t_start(self) -> float:
        return 0.0

    @property
    def t_end(self) -> float:
        return float(len(self.curves))

    def to_chain(self, k: int, t) -> np.ndarray:
        """Chain parameter of the parameter ``t`` of edge k of the chain."""
        return k + (np.asarray(t, dtype=float) - self._lo[k]) / self._span[k]

    def local(self, k: int, T) -> np.ndarray:
        """Edge k's own parameter at chain parameters T (extrapolated beyond k <= T <= k + 1)."""
        return self._lo[k] + (np.asarray(T, dtype=float) - k) * self._span[k]

    def split(self, T) -> tuple[np.ndarray, np.ndarray]:
        """Edge index (n,) and the edge's own parameter (n,) of chain parameters T."""
        T = np.asarray(T, dtype=float).ravel()
        k = np.clip(np.floor(T).astype(np.intp), 0, len(self.curves) - 1)
        return k, self._lo[k] + (T - k) * self._span[k]

    def _each(self, T, method: str, scaled: bool) -> np.ndarray:
        T = np.asarray(T, dtype=float).ravel()
        if T.size:
            j = min(max(int(T[0]), 0), len(self.curves) - 1)
            if j <= T.min() and T.max() <= j + 1:  # all on one edge (the common case): no masks
                v = np.asarray(getattr(self.curves[j], method)(self._lo[j] + (T - j) * self._span[j]),
                               dtype=float).reshape(-1, 2)
                return v * self._span[j] if scaled else v
        k, t = self.split(T)
        out = np.empty((len(t), 2))
        for j in np.unique(k):
            sel = k == j
            v = np.asarray(getattr(self.curves[j], method)(t[sel]), dtype=float).reshape(-1, 2)
            out[sel] = v * self._span[j] if scaled else v
        return out

    def evaluate(self, T) -> np.ndarray:
        return self._each(T, "evaluate", False)

    def derivative(self, T) -> np.ndarray:
        """dX/dT (the edge's derivative times its parameter span)."""
        return self._each(T, "derivative", True)

    def axis_crossings(self, axis: int, value: float, lo: float | None = None, hi: float | None = None) -> np.ndarray:
        """Chain parameters where coordinate ``axis`` equals ``value`` (within [lo, hi] when given:
        only the edges overlapping it are asked)."""
        lo = 0.0 if lo is None else max(float(lo), 0.0)
        hi = self.t_end if hi is None else min(float(hi), self.t_end)
        out = [np.zeros(0)]
        for k in range(int(np.floor(lo)), min(int(np.floor(hi)), len(self.curves) - 1) + 1):
            t = np.asarray(self.curves[k].axis_crossings(axis, value), dtype=float).ravel()
            out.append(self.to_chain(k, t))
        T = np.concatenate(out)
        return np.unique(T[(T >= lo) & (T <= hi)])

    def breakpoints(self) -> np.ndarray:
        """Junctions (T = 1 ... K - 1) and each edge's own kinks: quadrature must not straddle them."""
        out = [np.arange(1, len(self.curves), dtype=float)]
        for k, c in enumerate(self.curves):
            brk = getattr(c, "breakpoints", None)
            if brk is not None:
                out.append(self.to_chain(k, np.asarray(brk(), dtype=float)))
        return np.unique(np.concatenate(out))

    def corners(self, convex_only: bool = True) -> np.ndarray:
        """Chain parameters of the corners (junctions turning by more than CORNER_ANGLE; to the
        left, where the material is, when ``convex_only``)."""
        turns = self.turns if convex_only else np.abs(self.turns)
        return np.nonzero(turns > CORNER_ANGLE)[0] + 1.0

    def edge_at(self, T: float) -> str:
        return self.names[int(self.split(np.array([T]))[0][0])]


def contact_chain(profile, curves: dict, edge: str) -> ContactChain:
    """The chain of ``edge``'s loop in ``profile``: the loop once around on each side of the
    edge, each edge taken from ``curves`` (the exact edges or their polylines, oriented along
    the loop); the turns at the junctions from the profile's exact edges."""
    loop = next(lp for lp in profile.loops if any(c.name == edge for c in lp))
    m = len(loop)
    j = next(i for i, c in enumerate(loop) if c.name == edge)
    order = [loop[(j + i) % m] for i in range(-m, m + 1)]
    turns = []
    for a, b in zip(order[:-1], order[1:]):
        turns.append(tangent_turn(unit_tangent(a, a.t_end), unit_tangent(b, b.t_start)))
    return ContactChain(names=tuple(c.name for c in order), curves=tuple(curves[c.name] for c in order),
                        turns=np.array(turns), middle=m)


def junction_near(profile, point: np.ndarray) -> tuple[float, tuple[str, str]]:
    """The junction of ``profile``'s loops nearest ``point``: the tangent's turn there (rad,
    positive at a convex corner) and the names of the two edges meeting there."""
    j = nearest_junction(profile, point)
    return (0.0, ("", "")) if j is None else (j.turn, (j.before.name, j.after.name))


def contact_allowed_at_junction(profile, point: np.ndarray, symmetry_edges) -> bool:
    """Whether a contact point at the junction nearest ``point`` is valid: a tangent (G1)
    junction (the contact curve runs smoothly through it), or a corner where one of the two
    edges is a symmetry line (``symmetry_edges``: the edges with a sliding condition; a half
    model cut through the contact)."""
    turn, edges = junction_near(profile, point)
    return abs(turn) <= CORNER_ANGLE or any(e in symmetry_edges for e in edges)
