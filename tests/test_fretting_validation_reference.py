"""The 2D fretting validation's closed form per cycle (solver.reports.validate_fretting.compare) is
Mindlin-Deresiewicz's W for the cycle's own amplitude and normal force: a parasitic shear during the
normal loading (a grid not symmetric about the contact transmits one, about 1e-5 of Q*) must not
pull the normal loading's smaller N into it. Checked on a synthetic run whose values are set by
hand against energy_per_cycle evaluated directly."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ibfem.solver.reference.fretting import energy_per_cycle
from ibfem.solver.reference.theory import effective_modulus
from ibfem.solver.reports.validate_fretting import compare

MU, R, E, NU = 0.3, 1.0, 2.0e11, 0.3
N_HELD = 9.7e7


def _step(t: float, n: float, q: float) -> dict:
    a = math.sqrt(4.0 * n * R / (math.pi * effective_modulus(E, NU, E, NU)))
    return {"t": t, "contacts": [{"half_width": a, "normal_force": n, "tangential_force": q,
                                  "stick_half_width": a, "region_centre": 0.0}]}


def _run(parasitic: float) -> tuple[dict, dict]:
    """A normal ramp carrying ``parasitic`` shear, then one cycle of Q at constant N."""
    q_star = 0.5 * MU * N_HELD
    ramp = [_step(0.25 * k, 0.25 * k * N_HELD, parasitic) for k in (1, 2, 3)]
    fret = [_step(1.0 + 0.25 * k, N_HELD, q) for k, q in enumerate([0.0, -q_star, 0.0, q_star, 0.0, -q_star])]
    steps = ramp + fret
    summary = {"steps": steps, "contacts": [{"friction": MU}],
               "fretting": [{"cycles": [{"t": [1.25, 2.25], "tangential_force_range": [-q_star, q_star],
                                         "energy_loop": 1.0, "energy_friction": 1.0}]}]}
    s = np.linspace(-0.05, 0.05, 41)
    return summary, {"s": s, "shear": np.zeros((len(steps), len(s)))}


@pytest.mark.parametrize("parasitic", [0.0, 400.0])
def test_cycle_closed_form_uses_the_cycles_normal_force(parasitic):
    summary, profiles = _run(parasitic)
    result = compare(summary, profiles, R, E, NU)
    expected = energy_per_cycle(0.5 * MU * N_HELD, N_HELD, MU, R, effective_modulus(E, NU, E, NU))
    (cycle,) = result["cycles"]
    assert cycle["energy_theory"] == pytest.approx(expected, rel=1e-12)
    assert result["steps"][0]["t"] == pytest.approx(1.25)  # the first step with shear, not the ramp's
