"""The SPEC section 4 contact block of a contact's final state: forces, the contact frame, and
the pressure and shear profiles sampled on the exact contact curve from the formulation's
tractions (``traction_samples``)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["contact_block"]


def contact_block(c, a: float, on2: np.ndarray, u: np.ndarray) -> dict:
    """SPEC section 4 contact block with pressure and shear sampled on the exact contact curve.

    The traction of the thin-band terms is discontinuous from cell to cell (bilinear fields:
    sigma jumps across cell sides, w is piecewise smooth), so its point values oscillate with
    the grid by tens of percent while its cell means are accurate. The profiles written are
    its moving average over one cell width (the coarser of the two grids at the contact
    point): a recovery that removes the grid-periodic part and, being a mean, keeps the
    force (the integral of the profile equals the transmitted force)."""
    s_plus, s_minus = c.geom.s_limits
    out_s = np.linspace(-min(1.25 * a, s_minus), min(1.25 * a, s_plus), 201) if a > 0 else np.zeros(1)
    width = max(
        float(b.grid.size[b.grid.locate(np.asarray(o)[None, :] - 1e-9 * b.grid.min_size * np.asarray(n))[0]])
        for b, o, n in ((c.b1, c.geom.origins[0], -c.geom.normal), (c.b2, c.geom.origins[1], c.geom.normal))
    )
    ds = c.options.sample_spacing * c.h
    reach_p, reach_m = min(1.25 * a + width, s_plus), min(1.25 * a + width, s_minus)
    s = np.linspace(-reach_m, reach_p, int(math.ceil((reach_p + reach_m) / ds)) + 1)
    pts, t1 = c.traction_samples(u, a, s)
    nl = pts.normal
    tl = np.stack([-nl[:, 1], nl[:, 0]], axis=1)
    pressure = np.einsum("qi,qi->q", t1, nl)  # compression positive
    shear = -np.einsum("qi,qi->q", t1, tl)  # on body 2 along the local tangent
    k = 2 * int(round(0.5 * width / (s[1] - s[0]))) + 1 if len(s) > 1 else 1  # odd: centred
    kernel = np.ones(k) / k
    pressure = np.convolve(pressure, kernel, mode="same")
    shear = np.convolve(shear, kernel, mode="same")
    friction = float(getattr(c.model, "friction", 0.0) or 0.0)
    nrm, tan = c.geom.normal, c.geom.tangent
    return {
        "bodies": list(c.geom.bodies),
        "type": c.kind,
        "friction": friction,
        "point": c.geom.point.tolist(),
        "normal": nrm.tolist(),
        "tangent": tan.tolist(),
        "half_width": float(a),
        "stick_half_width": float(min(c.stick(a), a)),
        "normal_force": float(-on2 @ nrm),
        "tangential_force": float(on2 @ tan),
        "pressure": {"s": out_s.tolist(), "value": np.interp(out_s, s, pressure).tolist()},
        "shear": {"s": out_s.tolist(), "value": np.interp(out_s, s, shear).tolist()},
        "profile_smoothing": float(width),
    }
