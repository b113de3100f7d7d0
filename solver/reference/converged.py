"""Converged solutions of shipped examples by an independent code, where the half-space theory
is not the solution of the posed problem.

Hertz and McEwen describe two half-spaces; the examples' bodies are finite (a block 1.5 m deep,
a quarter cylinder loaded on its flat), which moves the subsurface von Mises peak 1.6-5.4 %
above the half-space value in the converged solution of the same bodies. These are that
solution: NGSolve P3 on curved meshes graded to h_c = a / 80 along both contact curves and over
the subsurface window, penalty contact (``ContactBoundary``), computed by
``benchmarks/examples_ngsolve.py`` (docs/contact.md, "An independent reference"; 2026-11-25 on
this project's 2-core machine). Its own error there: halving h_c moves the peak by 3e-6 to 6e-6
relative, doubling the penalty by 3e-6. Rerun that script to check or refresh the numbers.

Each entry: the example's file stem -> the converged normal force ``N`` (N/m, the supports'
reaction) and the largest plane-strain von Mises stress ``vm_peak`` (Pa) of body 2 below the
contact. A solver's N differs by a few 1e-4 (prescribed displacements), so compare peaks
scaled to a common force: the peak scales with p0 ~ sqrt(N) (:func:`vm_peak_for_force`).
"""

from __future__ import annotations

import math

__all__ = ["CONVERGED", "HALF_WIDTHS", "SPHERE_ON_FLAT", "vm_peak_for_force"]

CONVERGED: dict[str, dict[str, float]] = {
    # benchmarks/examples_ngsolve.py --only ex7: 130,510 dofs, h_c 3.90e-4 m
    "cylinder_on_wedge_frictionless": {"N": 84787753.263307, "vm_peak": 1011645024.9231527},
    # benchmarks/examples_ngsolve.py --only ex3: 122,656 dofs, h_c 3.56e-4 m
    "cylinder_on_cylinder_frictionless": {"N": 141441575.31389323, "vm_peak": 1784712594.963194},
}


#: Converged half widths (m) of the shipped 2D examples whose closed forms describe other bodies
#: (half-planes under the rounded flat punch, an infinite plate around the pin): the same scenes
#: (bodies, supports, prescribed displacements) solved by NGSolve P3 on fitted curved meshes with
#: penalty contact on ibfem's pairs of the undeformed geometry, a read from the fitted gap opening
#: just outside the region (``benchmarks/accuracy_reference_2d.py``, 2026-11-28, docs/accuracy.md
#: "References of the finite bodies"). ``half_width`` is the Richardson limit (or the finest mesh's
#: value where the meshes agree to round-off of the reading), ``uncertainty`` the spread of the
#: finest meshes' readings about it, ``N`` the converged normal force (N/m) for the same load.
HALF_WIDTHS: dict[str, dict[str, float]] = {
    # full model; h_c 4e-4 ... 1e-4 m: 0.0148000, 0.0147980, 0.0147975 (order 1.90); 5e-5 m: 0.0147973
    "rounded_punch": {"half_width": 0.0147973, "uncertainty": 3e-7, "N": 3.98170e6},
    # h_c 4e-4 ... 5e-5 m: 0.0147232, 0.0147228, 0.0147219, 0.0147217 (differences not yet
    # shrinking steadily: the finest value, the spread of the last two)
    "rounded_punch_half": {"half_width": 0.0147217, "uncertainty": 2e-7, "N": 3.87942e6},
    # h_c 0.016, 0.008, 0.004 m: 0.4783524, 0.4783222, 0.4783230
    "pin_in_bore": {"half_width": 0.478323, "uncertainty": 1e-6, "N": 8.56604e7},
}


#: The converged contact of examples/solid/sphere_on_flat.toml (a quarter of the lower half ball
#: R = 1 on the block [0, 1]^2 x [-1, 0], steel, the ball's top moved 2 mm down, frictionless).
#: ``N`` (the quarter model's normal force, N): the same bodies, supports and displacement solved
#: by NGSolve P3 on curved tetrahedral meshes graded to h_c on both contact surfaces and in
#: proportion to the distance from the contact beyond, penalty contact on ibfem's pairs of the
#: undeformed geometry (straight down), extrapolated to an infinite penalty from 1e3 and 1e4 E / h_c
#: (``benchmarks/accuracy_reference_3d.py``; docs/accuracy.md "The converged reference"): the
#: finest mesh's value, the two P3 meshes 0.015 % apart (``N_uncertainty``, relative).
#: ``a`` (the contact radius on the block's top, m): the half-space radius of the sphere's exact
#: gap for the force 4 N (``theory.exact_sphere_radius``, Sneddon's load). The P3 meshes read a
#: at a / h_c 2.8 and 4 only, still rising by 0.25 % between them; their Richardson limit at
#: order 2 is 0.045197 m (-0.04 %), and ibfem's three finest graded grids (262k, 695k and 1.91M
#: dofs) read 0.045183, 0.045210 and 0.045203 m: the bodies' finite size moves a for a given
#: force by less than ``a_uncertainty`` (relative), the largest of those differences.
SPHERE_ON_FLAT: dict[str, float] = {
    # P3, h_c 0.016, 0.0113 m (47829, 111300 dofs): N 3.388073e6, 3.388567e6; a 0.044973, 0.045085 m.
    # P2, h_c 0.016, 0.0113, 0.008 m (15405, 35136, 95865 dofs): N 3.39176e6, 3.39014e6, 3.39108e6;
    # a 0.0450865, 0.0451507, 0.0451343 m. Hertz's radius for 4 N: 0.0452265 m; the exact gap's 0.0452142 m.
    "N": 3.388567e6, "N_uncertainty": 2e-4, "a": 0.0452142, "a_uncertainty": 7e-4,
}


def vm_peak_for_force(name: str, normal_force: float) -> float | None:
    """The converged von Mises peak of example ``name`` scaled to ``normal_force`` (Hertz:
    stresses ~ p0 ~ sqrt(N)); None where no converged solution is stored."""
    ref = CONVERGED.get(name)
    if ref is None or not normal_force > 0.0:
        return None
    return ref["vm_peak"] * math.sqrt(normal_force / ref["N"])
