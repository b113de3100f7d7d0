"""Assembly of the linear problem without contact: every body's volume stiffness, the essential
conditions by the thin-band step boundary terms (solver.fem.step_boundary), tractions,
pressures and body forces on the exact boundary and cut cells; the reactions of the essential
conditions; the rigid-body check of the assembled stiffness."""

from __future__ import annotations

import functools
import operator
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..model.options import SolverOptions
from ..model.problem import BodyForce, Displacement, Fixed, Pressure, Sliding, Traction
from ..model.reference_point import ReferencePoint
from .linalg import rigid_body_modes
from .reference_point import distributing_traction, rigid_motion
from .space import BodyDiscretisation
from .step_boundary import projector, thin_band_terms, thin_band_traction

__all__ = [
    "EssentialTerm",
    "essential_condition",
    "essential_reactions",
    "rigid_modes_check",
    "LinearSystem",
    "assemble",
    "boundary_terms",
]


def essential_condition(bc, names, dim: int = 2):
    """(kind, free, target) of an essential condition, or None for natural ones."""
    if isinstance(bc, Fixed):
        return "fixed", (False,) * dim, lambda n: np.zeros_like(n)
    if isinstance(bc, Displacement):
        if len(bc.value) != dim:
            raise ValueError(
                f"boundary condition {bc.body}/{bc.edge}: value must have {dim} components, got {bc.value!r}"
            )
        free = tuple(v is None for v in bc.value)
        if all(free):
            raise ValueError(f"boundary condition {bc.body}/{bc.edge}: every displacement component is free")
        a = np.array([0.0 if v is None else float(v) for v in bc.value])
        return "displacement", free, lambda n: np.broadcast_to(a, n.shape).copy()
    if isinstance(bc, Sliding):
        an = float(bc.normal_displacement)
        return "sliding", (False,) * dim, lambda n: an * n
    return None


def _finite_vector(value, where: str, dim: int = 2) -> np.ndarray:
    v = np.asarray(value, dtype=float).ravel()
    if v.shape != (dim,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{where} must be {dim} finite numbers, got {value!r}")
    return v


_MOTIONS = {2: ["x translation", "y translation", "rotation"],
            3: ["x translation", "y translation", "z translation", "rotation about z", "rotation about y",
                "rotation about x"]}


def rigid_modes_check(k: sp.csr_matrix, bodies: list[BodyDiscretisation], tolerance: float = 1e-10) -> None:
    """Raise ValueError when a body can move rigidly (R^T K R singular for its rigid modes: 3 in
    2D, 6 in 3D, solver.fem.linalg.rigid_body_modes): an eigenvalue below ``tolerance`` times the
    body's mean diagonal times its node count. A free mode comes out at round-off, some 1e-16;
    a mode held only by a patch of a few small cells far from the body's size (a contact's
    initial region) lies near 1e-11 (a patch of 2 mm on a body of 2.4 m), which the contact
    driver's check after adding that patch must still count as held."""
    diag = np.abs(k.diagonal())
    for b in bodies:
        r = rigid_body_modes([b], b.n_total)
        sl = slice(b.dof_offset, b.dof_offset + b.n_dofs)
        m = r.T @ (k @ r)
        m = 0.5 * (m + m.T)
        scale = diag[sl].mean() * len(b.grid.free_nodes)
        ev, vec = np.linalg.eigh(m)
        small = np.abs(ev) < tolerance * scale
        if small.any():
            v = vec[:, np.argmin(np.abs(ev))]
            motion = " + ".join(f"{x:.2g} {w}" for x, w in zip(v, _MOTIONS[b.dim]) if abs(x) > 1e-3)
            raise ValueError(
                f"body {b.name!r} is not held against rigid-body motion ({motion}); add essential boundary conditions"
            )


@dataclass
class EssentialTerm:
    """One essential condition's thin-band terms, kept to recover its reaction. The points'
    operators are not kept: the edge's points are made again when the reaction is asked for
    (once, at the end of a solve). They are the largest arrays an assembly leaves behind: 43 MB
    at the 11k-dof 3D quarter ball, through every later phase of the solve."""

    key: str  # "body/edge"
    body: BodyDiscretisation
    edge: str
    points: np.ndarray  # (q, d) the edge's quadrature points
    weights: np.ndarray  # (q,)
    projector: np.ndarray
    target: np.ndarray

    def traction(self, u: np.ndarray, settings: SolverOptions, load_factor: float = 1.0) -> np.ndarray:
        """Traction along the edge with the prescribed values scaled by ``load_factor`` (a number, or
        one per component of the prescribed value)."""
        b = self.body
        passes = (b.edge_point_passes(self.edge, settings.boundary_order) if hasattr(b, "edge_point_passes")
                  else [b.edge_points(self.edge, settings.boundary_order)])
        factor = np.asarray(load_factor, dtype=float)
        target = self.target if np.all(factor == 1.0) else factor * self.target
        out, start = [], 0
        for bp in passes:  # each point's traction reads that point alone
            rows = slice(start, start + len(bp.weights))
            out.append(thin_band_traction(bp, self.projector[rows], target[rows], b.lam, b.mu, u,
                                          settings.band_fraction, settings.consistency))
            start = rows.stop
        if start != len(self.weights):
            raise RuntimeError(f"the points of {self.key} changed between assembly and the reaction")
        return np.concatenate(out) if len(out) > 1 else out[0]


def essential_reactions(
    essentials: list[EssentialTerm], u: np.ndarray, settings: SolverOptions, load_factor: float = 1.0
) -> tuple[dict[str, np.ndarray], dict]:
    """Force (dim,) each essential condition exerts on its body (summed over terms with the same
    "body/edge" key), and the (points, weights, traction) along it. ``load_factor``: one for all,
    or a dict "body/edge" -> the factor of that condition (load paths)."""
    reactions: dict[str, np.ndarray] = {}
    tractions = {}
    for e in essentials:
        factor = load_factor.get(e.key, 1.0) if isinstance(load_factor, dict) else load_factor
        tr = e.traction(u, settings, factor)
        force = (tr * e.weights[:, None]).sum(axis=0)
        reactions[e.key] = reactions.get(e.key, np.zeros_like(force)) + force
        tractions[e.key] = (e.points, e.weights, tr)
    return reactions, tractions


@dataclass
class LinearSystem:
    """K u = F of a problem without contact: the stiffness and loads of all bodies (block by
    block) and their boundary conditions. Contact terms are added on top of it."""

    bodies: list[BodyDiscretisation]
    stiffness: sp.csr_matrix
    load: np.ndarray
    essentials: list[EssentialTerm]
    settings: SolverOptions

    @property
    def n_dofs(self) -> int:
        return len(self.load)

    def reactions(self, u: np.ndarray) -> tuple[dict[str, np.ndarray], dict]:
        """Force (dim,) each essential condition exerts on its body, and the tractions along it."""
        return essential_reactions(self.essentials, u, self.settings)


def assemble(problem, bodies: list[BodyDiscretisation], settings: SolverOptions) -> LinearSystem:
    """Volume stiffness of every body, essential conditions (thin band), tractions, pressures
    and body forces."""
    k = sp.block_diag([b.stiffness(settings.fictitious_stiffness) for b in bodies], format="csr")
    k, f, essentials = boundary_terms(problem, bodies, settings, k)
    return LinearSystem(bodies, k, f, essentials, settings)


def boundary_terms(
    problem, bodies: list[BodyDiscretisation], settings: SolverOptions, stiffness: sp.spmatrix
) -> tuple[sp.csr_matrix, np.ndarray, list[EssentialTerm]]:
    """``stiffness`` plus the thin-band terms of the essential conditions, the load vector
    (their band loads, tractions, pressures, body forces) and the essential terms kept for
    the reactions."""
    n = bodies[0].n_total if bodies else 0
    bands = []  # summed among themselves first: one addition to the (large) stiffness
    f = np.zeros(n)
    by_name = {b.name: b for b in bodies}
    names = list(by_name)
    essentials = []
    for j, bc in enumerate(problem.boundary_conditions):
        if bc.body not in by_name:
            raise ValueError(f"boundary_conditions[{j}].body: unknown body {bc.body!r}; bodies: {', '.join(names)}")
        b = by_name[bc.body]
        if isinstance(bc, BodyForce):
            f += b.body_force(_finite_vector(bc.value, f"boundary_conditions[{j}].value", b.dim))
            continue
        if isinstance(bc, ReferencePoint):
            band, load, term = _reference_point_terms(bc, b, settings)
            bands += [band] if band is not None else []
            essentials += [term] if term is not None else []
            f += load
            continue
        ess = essential_condition(bc, names, b.dim)
        bp = b.edge_points(bc.edge, settings.boundary_order, traction=ess is not None)
        if ess is not None:
            ekind, free, target_of = ess
            proj = projector(ekind, bp.normals, free)
            target = target_of(bp.normals)
            kb, fa = thin_band_terms(bp, proj, target, b.lam, b.mu, settings.band_fraction, settings.consistency)
            bands.append(kb)
            f += fa
            essentials.append(EssentialTerm(f"{bc.body}/{bc.edge}", b, bc.edge, bp.points, bp.weights, proj, target))
        elif isinstance(bc, Traction):
            tr = np.broadcast_to(_finite_vector(bc.value, f"boundary_conditions[{j}].value", b.dim), bp.normals.shape)
            f += bp.load(tr * bp.weights[:, None])
        elif isinstance(bc, Pressure):
            if not np.isfinite(bc.value):
                raise ValueError(f"boundary_conditions[{j}].value: pressure must be finite, got {bc.value!r}")
            tr = -float(bc.value) * bp.normals
            f += bp.load(tr * bp.weights[:, None])
        else:
            raise ValueError(f"boundary_conditions[{j}]: unsupported condition type {type(bc).__name__}")
    k = stiffness + functools.reduce(operator.add, bands) if bands else stiffness
    return k.tocsr(), f, essentials




def _reference_point_terms(bc: ReferencePoint, b: BodyDiscretisation, settings: SolverOptions):
    """(band stiffness or None, load, essential term or None) of a reference point coupled to
    a face of ``b``: a kinematic coupling is the thin-band condition u = U + theta x (x - x0) on
    the coupled points (a projector of zero elsewhere), a distributing one the traction that
    carries the point's force and moment."""
    where = f"reference point on {bc.body}/{bc.edge}"
    bp = b.edge_points(bc.edge, settings.boundary_order, traction=bc.kinematic)
    coupled = bc.mask(bp.points)
    if not coupled.any():
        raise ValueError(f"{where}: no quadrature point of the face lies inside the region "
                         f"({len(bp.points)} points on the face)")
    point = _finite_vector(bc.point, f"{where}: point", b.dim)
    if not bc.kinematic:
        traction = distributing_traction(bp.points, np.where(coupled, bp.weights, 0.0), point, bc.force, bc.moment)
        return None, bp.load(traction * bp.weights[:, None]), None
    proj = projector("fixed", bp.normals) * coupled[:, None, None]
    target = rigid_motion(bp.points, point, bc.displacement, bc.rotation)
    kb, fa = thin_band_terms(bp, proj, target, b.lam, b.mu, settings.band_fraction, settings.consistency)
    weights = np.where(coupled, bp.weights, 0.0)
    return kb, fa, EssentialTerm(f"{bc.body}/{bc.edge}", b, bc.edge, bp.points, weights, proj, target)
