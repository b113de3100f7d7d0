"""The summary.json contact block of a contact's final state: forces, the contact frame, and
the pressure and shear profiles sampled on the exact contact curve from the formulation's
tractions (``traction_samples``)."""

from __future__ import annotations

import numpy as np

__all__ = ["contact_block"]


def contact_block(c, a: float, on2: np.ndarray, u: np.ndarray) -> dict:
    """The 2D contact block of summary.json, with pressure and shear sampled on the exact contact curve.

    The traction of the thin-band terms is discontinuous from cell to cell (bilinear fields:
    sigma jumps across cell sides, w is piecewise smooth), so its point values oscillate with
    the grid by tens of percent while its integrals over the region are accurate. The profiles
    written are its projection onto a smooth space over the region (solver.contact.tractions:
    sqrt(1 - s^2/a^2) times Chebyshev polynomials, with the stick zone's deficit projected the
    same way for partial slip), which reproduces the transmitted force exactly, vanishes outside
    a, and is clipped to compression and, where the formulation enforces Coulomb's law, to
    |q| <= mu p (what the clipping removes and where it acted: ``profile_recovery``)."""
    from .tractions import modes_for, recover_tractions

    s_plus, s_minus = c.geom.s_limits
    e = float(c.centre)
    lo, hi = c.region_ends(a) if hasattr(c, "region_ends") else (e - a, e + a)
    margin = 0.25 * a
    out_s = np.linspace(max(lo - margin, -s_minus), min(hi + margin, s_plus), 201) if a > 0 else np.zeros(1)
    cell = _contact_cell(c)
    prof = recover_tractions(c, u, a, cell)
    friction = float(getattr(c.model, "friction", 0.0) or 0.0)
    nrm, tan = c.geom.normal, c.geom.tangent
    return {
        "bodies": list(c.geom.bodies),
        "type": c.kind,
        "friction": friction,
        "point": c.geom.point.tolist(),
        **({} if c.geom.given_point is None else {"given_point": c.geom.given_point.tolist()}),
        "normal": nrm.tolist(),
        "tangent": tan.tolist(),
        "half_width": float(a),
        "stick_half_width": float(min(c.stick(a), a)),
        # the final grid's resolution of the region: the half-width over the contact's cell
        "cells_per_half_width": float(a / cell) if cell > 0 else 0.0,
        "region_centre": e,
        "region": [float(lo), float(hi)] if a > 0 else [0.0, 0.0],
        "normal_force": float(-on2 @ nrm),
        "tangential_force": float(on2 @ tan),
        "pressure": {"s": out_s.tolist(), "value": prof.pressure(out_s).tolist()},
        "shear": {"s": out_s.tolist(), "value": prof.shear(out_s).tolist()},
        "profile_smoothing": 0.0,
        "profile_recovery": {"method": "projection", "pressure_modes": len(prof.p_coef),
                             "stick_modes": len(prof.r_coef), "shear_modes": len(prof.q_coef),
                             "cell": float(cell), "clipped_force": prof.clipped_force,
                             "clipped_fraction": prof.clipped},
    }


def _contact_cell(c) -> float:
    """The coarser of the two grids' cells at the contact point."""
    return max(
        float(b.grid.size[b.grid.locate(np.asarray(o)[None, :] - 1e-9 * b.grid.min_size * np.asarray(n))[0]])
        for b, o, n in ((c.b1, c.geom.origins[0], -c.geom.normal), (c.b2, c.geom.origins[1], c.geom.normal))
    )
