"""Nitsche's weights for two bodies of different stiffness: which body's traction the
consistency flux takes, and which stiffness the penalty layer carries.

The contact terms hold the two bodies' jump to zero with a penalty layer (stiffness per unit
area ~ the acoustic tensor over the layer's thickness) and a consistency flux (the mean of the
bodies' tractions with weights w1 + w2 = 1). The layer must outweigh the flux's terms, which by
the inverse estimate grow as w1^2 E1 / h + w2^2 E2 / h. Equal weights (the "average" flux) with
the layer of body 1 hold this only when body 1 is the stiffer; when the stiffnesses differ by
orders of magnitude (a punch made nearly rigid on a steel block) the layer is as stiff as the
stiffer body, the jump cannot vanish on grids that do not match, and the point traction
oscillates from cell to cell by many times the pressure (measured: +-1 GPa on the tilted punch,
1000 times stiffer than its block, on grids turned by 7 degrees, where the pressure is 50 MPa).

The "weighted" flux takes the weights inversely proportional to the bodies' shear moduli,
w1 = mu2 / (mu1 + mu2), which minimises w1^2 E1 + w2^2 E2, so that the flux is mostly the softer
body's; the layer then needs only the harmonic mean of the stiffnesses, and its acoustic tensor
is that of the moduli 2 M1 M2 / (M1 + M2) (normal, M = lambda + 2 mu) and 2 mu1 mu2 / (mu1 + mu2)
(tangential) (J. E. Dolbow and I. Harari, Int. J. Numer. Meth. Engng 78 (2009) 229-252;
C. Annavarapu, M. Hautefeuille and J. E. Dolbow, Comput. Methods Appl. Mech. Engrg 225-228
(2012) 44-54). For two bodies of one material both choices are the plain average with body 1's
layer, to the last digit. Plane and solid contacts alike.
"""

from __future__ import annotations

__all__ = ["flux_weights", "layer_moduli"]


def _harmonic(x: float, y: float) -> float:
    return x if x == y else 2.0 * x * y / (x + y)


def flux_weights(flux: str, b1, b2) -> tuple[float, float]:
    """(w1, w2) of the consistency flux w1 t1 + w2 t2 for the option ``flux``."""
    if flux == "weighted":
        return (0.5, 0.5) if b1.mu == b2.mu else (b2.mu / (b1.mu + b2.mu), b1.mu / (b1.mu + b2.mu))
    return {"average": (0.5, 0.5), "body1": (1.0, 0.0), "body1_half": (0.5, 0.0)}[flux]


def layer_moduli(flux: str, b1, b2) -> tuple[float, float]:
    """(lambda, mu) whose acoustic tensor the penalty layer carries for the option ``flux``:
    the harmonic means of the bodies' normal and shear moduli for "weighted", body 1's own
    otherwise."""
    if flux != "weighted" or (b1.lam == b2.lam and b1.mu == b2.mu):
        return b1.lam, b1.mu
    mu = _harmonic(b1.mu, b2.mu)
    return _harmonic(b1.lam + 2.0 * b1.mu, b2.lam + 2.0 * b2.mu) - 2.0 * mu, mu
