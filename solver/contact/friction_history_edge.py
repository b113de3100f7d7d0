"""The stick boundary of a 3D friction history placed within the quadrature points' spacing.

The zone rule (solver.contact.friction_history3d) decides stick or slip per quadrature point, so
its stick boundary runs half-way between the last stuck and the first slipping point. Near a
stick boundary the deficit of the stuck shear below Coulomb's limit, 1 - |q| / (mu p), vanishes
with the square root of the distance from it (Cattaneo and Mindlin's edge of the stick zone), so
v = (1 - |q| / (mu p))^2 is linear in the distance there. Each stuck point within the zone
rule's disc of the slip zone fits v by least squares as a plane over the stuck points of its
disc; its root along the line to the nearest slipping point is where the boundary lies. The
points beside it then carry a share of each zone, each point's cell taken as its spacing (the
distance to its nearest point) centred on it along that line: a stuck point whose cell reaches
past the boundary slips with that share of it; a slipping point whose cell begins before the
boundary sticks with that share (the mean over the stuck points that see it as their nearest
slipping point).

Reference: K. L. Johnson, Contact Mechanics (1985), sections 7.2 and 7.3.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

__all__ = ["edge_shares"]


def _plane_fits(nb, s: np.ndarray, v: np.ndarray, rows: np.ndarray, stuck: np.ndarray):
    """(value, gradient (k, 2), valid) of the weighted least-squares plane of v over the stuck
    points of each row's disc, about the row's own point."""
    sub = nb[rows].tocoo()
    keep = stuck[sub.col]
    r, c, w = sub.row[keep], sub.col[keep], sub.data[keep]
    dx = s[c] - s[rows][r]
    k = len(rows)
    basis = np.column_stack([np.ones(len(r)), dx[:, 0], dx[:, 1]])
    normal = np.zeros((k, 3, 3))
    rhs = np.zeros((k, 3))
    for i in range(3):
        rhs[:, i] = np.bincount(r, weights=w * basis[:, i] * v[c], minlength=k)
        for j in range(3):
            normal[:, i, j] = np.bincount(r, weights=w * basis[:, i] * basis[:, j], minlength=k)
    det = np.linalg.det(normal)
    valid = np.abs(det) > 1e-6 * normal[:, 0, 0] * normal[:, 1, 1] * normal[:, 2, 2] + 1e-300
    coef = np.zeros((k, 3))
    if valid.any():
        coef[valid] = np.linalg.solve(normal[valid], rhs[valid][:, :, None])[:, :, 0]
    return coef[:, 0], coef[:, 1:], valid


def edge_shares(reg, slip: np.ndarray, direction: np.ndarray, ratio: np.ndarray, radius: float):
    """(slipping share (q,), direction (q, 3)) of a region's points for settled zones ``slip``,
    ``ratio`` the mean shear over Coulomb's limit, |q| / (mu p), of each point (the zone rule's
    means), ``radius`` that of the zone rule's disc; see the module's docstring. A stuck point
    given a slipping share takes the direction of its nearest slipping point."""
    share = slip.astype(float)
    direction = direction.copy()
    if not slip.any() or slip.all():
        return share, direction
    s = reg.info[0].s
    slipping = np.flatnonzero(slip)
    d, k = cKDTree(s[slipping]).query(s)
    nearest = slipping[k]
    front = np.flatnonzero(~slip & (d < radius) & (d > 0.0) & (ratio > 0.0))
    if not len(front):
        return share, direction
    v = np.maximum(1.0 - ratio, 0.0) ** 2
    value, grad, valid = _plane_fits(reg.neighbours, s, v, front, ~slip)
    toward = (s[nearest[front]] - s[front]) / d[front, None]
    slope = np.einsum("ki,ki->k", grad, toward)  # v falls towards the slip zone
    ok = valid & (slope < 0.0)
    spacing = cKDTree(s).query(s, k=2)[0][:, 1]  # each point's cell along the line: its spacing about it
    root = np.where(ok, np.maximum(value, 0.0) / np.maximum(-slope, 1e-300), np.inf)
    # the stuck point itself: the share of its spacing beyond the boundary slips
    hj = spacing[front]
    own = np.where(ok, np.clip((0.5 * hj - root) / hj, 0.0, 0.5), 0.0)
    share[front] = own
    given = own > 0.0
    direction[front[given]] = direction[nearest[front[given]]]
    # its nearest slipping point: the share of its spacing before the boundary sticks
    targets = nearest[front[ok]]
    hi = spacing[targets]
    beyond = np.clip((root[ok] - (d[front[ok]] - 0.5 * hi)) / hi, 0.0, 1.0)
    count = np.bincount(targets, minlength=len(s))
    total = np.bincount(targets, weights=beyond, minlength=len(s))
    seen = count > 0
    share[seen] = 1.0 - total[seen] / count[seen]
    return share, direction
