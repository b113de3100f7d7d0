"""SPEC section 7's contact block of a contact between solids: the frame, the semi-axes, the
forces, and the pressure and shear along both axes.

The band traction at the quadrature points oscillates from cell to cell (trilinear fields) while
its integrals are accurate; the profiles written are its weighted least-squares fit by
sqrt(1 - X^2 - Y^2) times a quadratic in (X, Y) = (s0 / a, s1 / b) (Hertz's pressure is the
constant term), evaluated along the axes and clipped to compression."""

from __future__ import annotations

import numpy as np

__all__ = ["ellipse_block", "fit_profile"]


def _basis(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    root = np.sqrt(np.clip(1.0 - X**2 - Y**2, 0.0, None))
    return root[:, None] * np.stack([np.ones_like(X), X, Y, X**2, X * Y, Y**2], axis=1)


def fit_profile(X: np.ndarray, Y: np.ndarray, weights: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Coefficients of the weighted least-squares fit of ``values`` at (X, Y) by _basis."""
    b = _basis(X, Y)
    w = np.sqrt(np.maximum(weights, 0.0))
    coef, *_ = np.linalg.lstsq(b * w[:, None], values * w, rcond=None)
    return coef


def ellipse_block(c, a: float, on2: np.ndarray, u: np.ndarray, info) -> dict:
    aa, bb = c.semi_axes(a)
    frame = c.frame
    out = {"bodies": list(c.model.bodies), "type": c.kind, "friction": float(getattr(c.model, "friction", 0.0) or 0.0),
           "point": frame.point.tolist(), "normal": frame.normal.tolist(), "axes": frame.axes.tolist(),
           "semi_axes": [float(aa), float(bb)],
           "stick_semi_axes": [float(min(c.stick_ratio, 1.0) * aa), float(min(c.stick_ratio, 1.0) * bb)],
           "normal_force": float(-on2 @ frame.normal),
           "tangential_force": [float(on2 @ frame.axes[0]), float(on2 @ frame.axes[1])],
           "pressure": {}, "shear": {}}
    if info is None or a <= 0.0:
        for key in ("pressure", "shear"):
            out[key] = {f"axis{k}": {"s": [], "value": []} for k in (0, 1)}
        return out
    pts = info[0]
    t1 = c.quadrature_traction(info, u[c.dofs])
    X, Y = pts.s[:, 0] / aa, pts.s[:, 1] / bb
    p = np.einsum("qi,qi->q", t1, pts.normal)
    fits = {"pressure": fit_profile(X, Y, pts.weights, p)}
    for k in (0, 1):
        fits[f"shear{k}"] = fit_profile(X, Y, pts.weights, t1 @ frame.axes[k])
    for k, reach in ((0, aa), (1, bb)):
        s = np.linspace(-1.25 * reach, 1.25 * reach, 201)
        present = c.on_body1(k, s)
        XY = np.zeros((len(s), 2))
        XY[:, k] = s / reach
        basis = _basis(XY[:, 0], XY[:, 1])
        pressure = np.clip(basis @ fits["pressure"], 0.0, None)
        shear = basis @ fits[f"shear{k}"] if c.kind != "frictionless" else np.zeros(len(s))
        out["pressure"][f"axis{k}"] = {"s": s[present].tolist(), "value": pressure[present].tolist()}
        out["shear"][f"axis{k}"] = {"s": s[present].tolist(), "value": shear[present].tolist()}
    out["relative_curvatures"] = [float(k) for k in frame.curvatures]
    out["profile_recovery"] = {"method": "least squares on sqrt(1 - X^2 - Y^2) x [1, X, Y, X^2, XY, Y^2]",
                               "pressure_coefficients": fits["pressure"].tolist(),
                               "quadrature_points": int(len(p))}
    return out
