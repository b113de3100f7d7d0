"""Every numerical option of the solver, in two frozen dataclasses with their defaults and
range checks (done once, here: the scene layer builds these and reports a ``ValueError`` with
the key path):

- :class:`SolverOptions`, the scene's ``[solver]`` table: load stepping, convergence, the
  step-boundary band, cut-cell quadrature, the tessellated variant, the grid offset;
- :class:`ContactOptions`, keys of a ``[[contacts]]`` table: the formulation and its region
  search, judged per contact.

Defaults are measured (docs/formulation.md, docs/contact.md, benchmarks/contact.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

__all__ = ["SolverOptions", "ContactOptions", "OptionError", "WIDTH_UPDATES", "FLUXES", "CONTACT_NORMALS", "REGION_CENTRES",
           "FORMULATION_NAMES"]

WIDTH_UPDATES = ("edge", "bracket", "thesis")
FLUXES = ("weighted", "average", "body1", "body1_half")
CONTACT_NORMALS = ("frame", "pair")
REGION_CENTRES = ("pressure", "point")
LINEAR_SOLVERS = ("auto", "direct", "iterative")
#: the names solver.contact.formulation.FORMULATIONS registers (kept equal by a test; the
#: contact layer is above this one)
FORMULATION_NAMES = ("band", "ellipse")
#: load steps beyond this are almost surely a typo (each step is at least one linear solve)
MAX_LOAD_STEPS = 10_000
#: the cut cells' fictitious stiffness only conditions them: above this it changes the result
MAX_FICTITIOUS_STIFFNESS = 1e-3


class OptionError(ValueError):
    """An option out of range; ``key`` is its name, the message says what is allowed."""

    def __init__(self, key: str, message: str):
        super().__init__(f"{key} {message}")
        self.key = key


def _positive(obj, *names: str) -> None:
    for name in names:
        v = getattr(obj, name)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0 and math.isfinite(v)):
            raise OptionError(name, f"must be a positive number, got {v!r}")


def _integer(obj, name: str, lo: int, hi: int) -> None:
    v = getattr(obj, name)
    if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
        raise OptionError(name, f"must be an integer in [{lo}, {hi}], got {v!r}")


def _choice(obj, name: str, allowed: tuple[str, ...]) -> None:
    v = getattr(obj, name)
    if v not in allowed:
        raise OptionError(name, f"must be one of {', '.join(repr(a) for a in allowed)}, got {v!r}")


@dataclass(frozen=True)
class SolverOptions:
    """The ``[solver]`` table of a scene file (every key is documented in the scene-file reference)."""

    load_steps: int = 10
    #: a state counts as converged when the residual work of its discrete equations, |u . r| /
    #: |u . f| with r = f - K u, is below this (and the contact region search settled)
    tolerance: float = 1e-10
    max_iterations: int = 100
    exact_geometry: bool = True
    #: step-function band delta as a fraction of the local cell size
    band_fraction: float = 0.25
    #: weight of the consistency terms: 1 symmetric Nitsche, 0.5 the thesis's band limit
    consistency: float = 1.0
    #: exact_geometry = false: tessellation chord (m); None: chord_fraction x element_size
    chord_tolerance: float | None = None
    chord_fraction: float = 0.1
    #: cut cells get this times the full cell's stiffness on their non-linear modes
    #: (conditioning of tiny cut cells; constant strains untouched: solver.fem.fictitious)
    fictitious_stiffness: float = 1e-9
    #: Gauss points per boundary piece for boundary conditions / for cut-cell moments
    boundary_order: int = 5
    curve_order: int = 8
    #: shift of every background grid's origin, as fractions of the element size
    grid_offset: tuple[float, ...] = (0.0, 0.0)
    #: linear systems without contact: "direct" (sparse LU), "iterative" (CG + smoothed
    #: aggregation AMG, pyamg), "auto" (iterative from 400k dofs when pyamg is installed);
    #: contact problems always factor directly (their condensation needs the factors)
    linear_solver: str = "auto"
    #: with load paths: load steps per unit of the load parameter t (None: load_steps per unit)
    steps_per_unit: int | None = None
    #: relative accuracy target of the contacts' results: the grid is refined (the far field
    #: graded while the normal force's error leads, then every cell made smaller by the ratio the
    #: estimates ask for, or a zone one level deeper around the contact regions where that is
    #: smaller) until the estimated error of each is below it (None: the scene's grid as given)
    accuracy: float | None = None

    def __post_init__(self):
        _integer(self, "load_steps", 1, MAX_LOAD_STEPS)
        if self.steps_per_unit is not None:
            _integer(self, "steps_per_unit", 1, MAX_LOAD_STEPS)
        _integer(self, "max_iterations", 1, 100_000)
        _integer(self, "boundary_order", 1, 20)
        _integer(self, "curve_order", 1, 40)
        if not isinstance(self.exact_geometry, bool):
            raise OptionError("exact_geometry", f"must be true or false, got {self.exact_geometry!r}")
        t = self.tolerance
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not 0.0 < t < 1.0:
            raise OptionError("tolerance", f"must lie in (0, 1), got {t!r}")
        _positive(self, "band_fraction", "chord_fraction")
        for name in ("band_fraction", "chord_fraction"):  # a band / chord wider than the cell
            if getattr(self, name) > 1.0:
                raise OptionError(name, f"must lie in (0, 1] (a fraction of the cell size), got {getattr(self, name)!r}")
        if self.chord_tolerance is not None:
            _positive(self, "chord_tolerance")
        c = self.consistency
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not 0.0 <= c <= 1.0:
            raise OptionError("consistency", f"must lie in [0, 1], got {c!r}")
        f = self.fictitious_stiffness
        if isinstance(f, bool) or not isinstance(f, (int, float)) or not 0.0 <= f <= MAX_FICTITIOUS_STIFFNESS:
            raise OptionError("fictitious_stiffness", f"must lie in [0, {MAX_FICTITIOUS_STIFFNESS:g}] (more changes the "
                              f"body's stiffness: 0.99 moved a contact force by 1.5 %), got {f!r}")
        _choice(self, "linear_solver", LINEAR_SOLVERS)
        acc = self.accuracy
        if acc is not None and (isinstance(acc, bool) or not isinstance(acc, (int, float)) or not 1e-5 <= acc < 1.0):
            raise OptionError("accuracy", f"must lie in [1e-5, 1) (a relative error: 0.005 is 0.5 %), got {acc!r}")
        off = self.grid_offset
        if len(off) not in (2, 3) or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and -1.0 <= x <= 1.0 for x in off
        ):
            raise OptionError("grid_offset", f"must be two (three in 3D) numbers in [-1, 1] (fractions of the "
                              f"element size), got {off!r}")


@dataclass(frozen=True)
class ContactOptions:
    """Keys of a ``[[contacts]]`` table beside bodies/type/friction/point (docs/contact.md)."""

    #: the contact formulation (solver.contact.formulation registry)
    formulation: str = "band"
    #: half-width search: "edge" (root of the edge coefficient), "bracket" (one-cell window
    #: verdicts), "thesis" (sections 5.5.3-5.5.4)
    width_update: str = "edge"
    #: consistency flux and penalty layer (solver.contact.interface_weights): "weighted" (the
    #: bodies' tractions weighted inversely to their shear moduli, the layer of the harmonic mean
    #: of their moduli; the plain average for one material), "average" (weights 1/2, body 1's
    #: layer), "body1" (weight 1), "body1_half" (1/2)
    flux: str = "weighted"
    #: Gauss points per contact-curve piece
    order: int = 4
    width_tolerance: float = 1.0 / 16.0  # bracket on a in the last load step, in finest contact cells
    edge_tolerance: float = 1e-3  # "edge": the root of the edge coefficient to this many finest cells
    step_tolerance: float = 0.25  # bracket on a in the earlier load steps (they only start the next)
    sample_spacing: float = 1.0 / 16.0  # penetration/tension samples, in finest contact cells
    window: float = 1.0  # penetration / tension are judged on means over this many cells at the edges
    gap_tolerance: float = 1e-3  # penetration: mean gap < -tol x (finest cell) x (mean pressure / E*)
    tension_tolerance: float = 0.01  # tension: mean pressure < -tol x mean pressure
    extent_fraction: float = 0.8  # candidate region: this fraction of the innermost contact refinement radius
    max_width_iterations: int = 60
    #: boundary points less deep in their cell (along the inward normal) than this fraction of
    #: its size blend its fields smoothly with those of the cell behind them (0: own cell only)
    sliver_fraction: float = 0.125
    #: the slip zone carries mu p (eq. 5-24); false: the thesis's variant without it
    friction_traction: bool = True
    #: direction of the normal constraint: "frame" (the contact frame, Hertz's half-space
    #: assumption) or "pair" (each matched pair's bisector of the two exact normals)
    contact_normal: str = "frame"
    stick_tolerance: float = 1e-3  # |sqrt(1 - |Q|/(mu N)) - c/a| at the returned state
    max_stick_iterations: int = 30
    #: the region's centre: "pressure" (2D: e - a <= s <= e + a, e the pressure's centroid: a
    #: region of its own two ends; 3D: the ellipse centred there) or "point" (about the contact
    #: point, the thesis's)
    region_centre: str = "pressure"

    def __post_init__(self):
        _choice(self, "formulation", FORMULATION_NAMES)
        _choice(self, "width_update", WIDTH_UPDATES)
        _choice(self, "flux", FLUXES)
        _choice(self, "contact_normal", CONTACT_NORMALS)
        _choice(self, "region_centre", REGION_CENTRES)
        _integer(self, "order", 1, 20)
        _integer(self, "max_width_iterations", 1, 10_000)
        _integer(self, "max_stick_iterations", 1, 10_000)
        if not isinstance(self.friction_traction, bool):
            raise OptionError("friction_traction", f"must be true or false, got {self.friction_traction!r}")
        s = self.sliver_fraction
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not 0.0 <= s < 1.0:
            raise OptionError("sliver_fraction", f"must lie in [0, 1), got {s!r}")
        _positive(self, "width_tolerance", "edge_tolerance", "step_tolerance", "sample_spacing", "window",
                  "gap_tolerance", "tension_tolerance", "extent_fraction", "stick_tolerance")

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))
