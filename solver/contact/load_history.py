"""The load steps of a contact run with load paths, and the record of each solved step.

Each step t solves the problem under F(t) = sum_j f_j(t) F_j (solver.fem.path_loads): the driver
keeps K0 factored once and solves K0 U_j = F_j once per column, so a step's right-hand side
costs a few vector sums. The record of a step (``summary.json`` ``steps``) holds the reactions
of the essential conditions and, per contact, the forces, the region, the stick zone and the
slip zones with their direction.
"""

from __future__ import annotations

import numpy as np

from ..fem.assembly import essential_reactions
from ..fem.linalg import scatter
from ..fem.path_loads import PathLoads, path_loads

__all__ = ["PathSteps", "slip_zones_of", "solid_entry"]


class PathSteps:
    """The step loads of a run with paths: per step t the load, its condensed parts and the
    factors of the essential conditions."""

    def __init__(self, problem, bodies, settings, lu, dofs, schur):
        self.loads: PathLoads = path_loads(problem, bodies, settings)
        self.times = problem.history.times()
        cols = self.loads.columns
        self.u0 = np.column_stack([lu.solve(np.ascontiguousarray(cols[:, j])) for j in range(cols.shape[1])]) \
            if cols.shape[1] else np.zeros_like(cols)
        self.bu0 = self.u0[dofs]
        self.sbu0 = schur @ self.bu0 if cols.shape[1] else np.zeros_like(self.bu0)
        self.gram = self.u0.T @ cols

    def at(self, t: float):
        """(f0, bu0, sbu0, u0 . f0) of the load at t."""
        g = self.loads.weights(t)
        return self.loads.columns @ g, self.bu0 @ g, self.sbu0 @ g, float(g @ self.gram @ g)

    def essential_factors(self, t: float) -> dict:
        return self.loads.essential_factors(t)


def slip_zones_of(contact, a: float) -> list[list[float]]:
    """[s_lo, s_hi, direction] of each slip zone of a contact's current state (2D): its own
    ``slip_zones`` when it keeps a history, else the two ends outside the stick zone."""
    own = getattr(contact, "slip_zones", None)
    if callable(own):
        return own(a)
    if getattr(contact, "kind", "") != "frictional" or a <= 0.0:
        return []
    c, e, sign = min(contact.stick(a), a), float(contact.centre), float(contact.slip_sign)
    if c >= a or sign == 0.0:
        return []
    return [[e - a, e - c, sign], [e + c, e + a, sign]]


def step_record(driver, t: float, u: np.ndarray, factors: dict) -> dict:
    """One entry of ``summary.json`` ``steps`` for the state the driver holds."""
    reactions, _ = essential_reactions(driver.essentials, u, driver.options, factors)
    contacts = []
    for c, a, info in zip(driver.contacts, driver.widths, driver.prev_infos):
        on2 = -c.force(u[c.dofs], a, info)
        if hasattr(c, "frame"):  # between solids
            contacts.append(solid_entry(c, a, info, on2))
            continue
        nrm, tan = c.geom.normal, c.geom.tangent
        entry = {"normal_force": float(-on2 @ nrm), "tangential_force": float(on2 @ tan), "half_width": float(a),
                 "stick_half_width": float(min(c.stick(a), a)), "region_centre": float(c.centre),
                 "slip_zones": slip_zones_of(c, a)}
        extra = getattr(c, "step_fields", None)
        if callable(extra):
            entry.update(extra(u, a, info))
        contacts.append(entry)
    return {"t": float(t), "reactions": {k: np.asarray(v).tolist() for k, v in reactions.items()},
            "face_displacements": face_displacements(driver, u), "contacts": contacts, "field": u}


def solid_entry(c, a: float, info, on2: np.ndarray) -> dict:
    """A step's record of a contact between solids: the forces on the second body (N, and the
    tangential force's components along the contact's axes), the region's and the stick zone's
    semi-axes, and what a friction history adds (friction work, slip points, stick area)."""
    frame = c.frame
    aa, bb = c.semi_axes(a) if a > 0.0 else (0.0, 0.0)
    ratio = min(max(float(c.stick_ratio), 0.0), 1.0)
    entry = {"normal_force": float(-on2 @ frame.normal),
             "tangential_force": [float(on2 @ frame.axes[0]), float(on2 @ frame.axes[1])],
             "semi_axes": [float(aa), float(bb)], "stick_semi_axes": [ratio * float(aa), ratio * float(bb)],
             "region_centre": np.asarray(c.centre, dtype=float).tolist()}
    extra = getattr(c, "step_fields", None)
    if callable(extra):
        entry.update(extra(None, a, info))
    return entry


def face_displacements(driver, u: np.ndarray) -> dict:
    """"body/edge" -> the mean displacement of each edge with an essential condition (for a
    prescribed face, its prescribed motion; the rigid displacement of a loaded face)."""
    cache = driver.__dict__.setdefault("_face_points", {})
    out = {}
    for e in driver.essentials:
        if e.key not in cache:
            cache[e.key] = e.body.edge_points(e.edge, driver.options.boundary_order)
        bp = cache[e.key]
        disp = bp.displacement_at(u)
        out[e.key] = (disp * bp.weights[:, None]).sum(axis=0) / bp.weights.sum()
        out[e.key] = out[e.key].tolist()
    return out


def step_field(driver, state, f0) -> np.ndarray:
    """The full field of a converged step state (one solve with K0's factors)."""
    lam, x, y = state[:3]
    return driver.lu.solve(lam * f0 + scatter(driver.n, driver.dofs, y))
