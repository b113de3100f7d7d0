"""The step boundary method (thesis chapter 3) in its thin-band limit.

Trial and test fields u = H u_h + (I - H) a, v = H v_h with the approximate step H(phi) of
eq. 3-4 over a band of width delta. Integrating the band energy across its thickness and letting
delta -> 0 (docs/formulation.md) leaves boundary integrals on the exact edge:

    a(v, u) + sum_q w_q [ (P v).A_n (P w) 4/(3 delta)  - theta ((sigma(v) n).P w + (sigma(u) n).P v) ]

with w = u_h - a, A_n = (lambda + 2 mu) n n^T + mu (I - n n^T) the acoustic tensor of the exact
normal n, P the projector on the constrained components (I fixed, e_x e_x^T for a prescribed x
only, n n^T sliding) and theta = 1/2 (the band's value; theta = 1 is symmetric Nitsche). The
terms with a go to the right-hand side: the F_a load of eq. 3-30.

Everything here acts on sparse *point operators*: a displacement operator E_u (2q x ndof) and
a traction operator E_t (2q x ndof) giving u_h and sigma(u_h) n at q quadrature points. For one
body they come from its own grid; for the contact band of the next issues E_u is the jump
between two grids, so the same functions couple two bodies.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = [
    "step_function",
    "step_derivative",
    "band_integrals",
    "PENALTY_FACTOR",
    "THESIS_CONSISTENCY",
    "NITSCHE_CONSISTENCY",
    "DEFAULT_BAND_FRACTION",
    "DEFAULT_CONSISTENCY",
    "acoustic_tensor",
    "projector",
    "BoundaryPoints",
    "block_diagonal",
    "thin_band_terms",
    "thin_band_traction",
]

# int_0^delta H'^2 dphi = 4 / (3 delta): the layer stiffness factor.
PENALTY_FACTOR = 4.0 / 3.0
# int_0^delta H H' dphi = 1/2: weight of the consistency terms the band gives.
THESIS_CONSISTENCY = 0.5
NITSCHE_CONSISTENCY = 1.0
# delta = DEFAULT_BAND_FRACTION * local size (measured: docs/formulation.md, "Choosing delta").
DEFAULT_BAND_FRACTION = 0.25
# The solver's default weight: the fully consistent one (patch test exact, O(h^2) displacements);
# THESIS_CONSISTENCY is kept as an option (its O(delta) inconsistency is measured in the docs).
DEFAULT_CONSISTENCY = NITSCHE_CONSISTENCY


def step_function(phi: np.ndarray, delta: float) -> np.ndarray:
    """H(phi) of eq. 3-4: 0 outside, (phi/delta)(2 - phi/delta) in the band, 1 beyond it."""
    s = np.clip(np.asarray(phi, dtype=float) / delta, 0.0, 1.0)
    return s * (2.0 - s)


def step_derivative(phi: np.ndarray, delta: float) -> np.ndarray:
    """dH/dphi = (2/delta)(1 - phi/delta) in the band, 0 elsewhere."""
    phi = np.asarray(phi, dtype=float)
    inside = (phi >= 0.0) & (phi <= delta)
    return np.where(inside, 2.0 / delta * (1.0 - phi / delta), 0.0)


def band_integrals(delta: float) -> dict[str, float]:
    """Closed forms of the band integrals across its thickness used by the thin-band limit."""
    return {"H2": 8.0 * delta / 15.0, "HdH": 0.5, "dH2": 4.0 / (3.0 * delta)}


def acoustic_tensor(normals: np.ndarray, lam: float, mu: float) -> np.ndarray:
    """A_n (q, d, d) = sym(n x .) : C : sym(n x .) = (lambda + 2 mu) n n^T + mu (I - n n^T)."""
    nn = normals[:, :, None] * normals[:, None, :]
    return (lam + mu) * nn + mu * np.eye(normals.shape[1])[None]


def projector(kind: str, normals: np.ndarray, free: tuple[bool, ...] | None = None) -> np.ndarray:
    """P (q, d, d) on the constrained components: "fixed"/"displacement" in global axes (a
    component with free[i] True is not constrained), "sliding" along the exact local normal."""
    q, dim = normals.shape
    if kind == "sliding":
        return normals[:, :, None] * normals[:, None, :]
    if kind in ("fixed", "displacement"):
        d = np.array([0.0 if f else 1.0 for f in (free or (False,) * dim)])
        return np.broadcast_to(np.diag(d), (q, dim, dim)).copy()
    raise ValueError(f"unknown essential condition kind {kind!r}")


@dataclass
class BoundaryPoints:
    """Quadrature points on an edge with their operators onto the global dof vector."""

    points: np.ndarray  # (q, d)
    weights: np.ndarray  # (q,) ds (dA in 3D)
    normals: np.ndarray  # (q, d) exact outward normals of the body
    cell_size: np.ndarray  # (q,) local size setting delta (cell size, or less in a sliver)
    displacement: sp.csr_matrix  # (d q, ndof): u_h at the points, rows [x0, y0, (z0,) x1, ...]
    traction: sp.csr_matrix  # (d q, ndof): sigma(u_h) n at the points


def block_diagonal(blocks: np.ndarray) -> sp.csr_matrix:
    """Sparse block-diagonal matrix of q (d, d) blocks."""
    q, d = blocks.shape[:2]
    return sp.bsr_matrix((np.ascontiguousarray(blocks), np.arange(q), np.arange(q + 1)), shape=(d * q, d * q)).tocsr()


def thin_band_terms(
    bp: BoundaryPoints,
    proj: np.ndarray,
    target: np.ndarray,
    lam: float,
    mu: float,
    band_fraction: float = DEFAULT_BAND_FRACTION,
    consistency: float = DEFAULT_CONSISTENCY,
    jump: sp.csr_matrix | None = None,
) -> tuple[sp.csr_matrix, np.ndarray]:
    """Stiffness (ndof, ndof) and F_a load (ndof,) of the thin-band step boundary terms.

    ``target`` (q, d) is the prescribed displacement a at each point (only P a matters);
    ``jump`` replaces the displacement operator (contact: u_h1 - u_h2), default bp.displacement.
    """
    eu = bp.displacement if jump is None else jump
    et = bp.traction
    delta = band_fraction * bp.cell_size
    pen = (PENALTY_FACTOR / delta * bp.weights)[:, None, None] * (proj @ acoustic_tensor(bp.normals, lam, mu) @ proj)
    wp = bp.weights[:, None, None] * proj
    k_pen = block_diagonal(pen)
    k_con = block_diagonal(wp)
    cross = et.T @ k_con @ eu
    k = eu.T @ k_pen @ eu - consistency * (cross + cross.T)
    a = np.asarray(target, dtype=float).reshape(-1)
    f = eu.T @ (k_pen @ a) - consistency * (et.T @ (k_con @ a))
    return k.tocsr(), np.asarray(f).ravel()


def thin_band_traction(
    bp: BoundaryPoints,
    proj: np.ndarray,
    target: np.ndarray,
    lam: float,
    mu: float,
    u: np.ndarray,
    band_fraction: float = DEFAULT_BAND_FRACTION,
    consistency: float = DEFAULT_CONSISTENCY,
    jump: sp.csr_matrix | None = None,
) -> np.ndarray:
    """Traction (q, 2) the condition exerts on the body at each point: the layer's
    -4/(3 delta) P A_n P (u_h - a) plus the consistency part theta P sigma(u_h) n. Integrated
    with bp.weights it is the reaction; by the translation invariance of the bulk form the
    reactions and the applied loads balance exactly."""
    eu = bp.displacement if jump is None else jump
    d = bp.normals.shape[1]
    w = (eu @ u).reshape(-1, d) - np.asarray(target, dtype=float).reshape(-1, d)
    tn = (bp.traction @ u).reshape(-1, d)
    delta = band_fraction * bp.cell_size
    layer = (PENALTY_FACTOR / delta)[:, None, None] * (proj @ acoustic_tensor(bp.normals, lam, mu) @ proj)
    return -np.einsum("qij,qj->qi", layer, w) + consistency * np.einsum("qij,qj->qi", proj, tn)
