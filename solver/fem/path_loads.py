"""The load vector of a problem with load paths, split by factor: F(t) = sum_j f_j(t) F_j.

Every load (the band terms of prescribed displacements, tractions, pressures, body forces) is
linear in the prescribed value, and the stiffness does not depend on it, so each condition's
load is a sum of one column per component, each scaled by the factor of its path. Columns of the
same factor are summed: a scene has as many columns as distinct factors (the ramp of the
conditions without a path included).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp

from ..model.load_paths import LoadHistory
from ..model.problem import Displacement, Fixed, Pressure, Sliding
from .assembly import boundary_terms

__all__ = ["PathLoads", "path_loads"]


@dataclasses.dataclass(frozen=True)
class PathLoads:
    """The load columns (n, J), the factor name of each column, and per essential condition
    ("body/edge") the factor name of each component of its prescribed value."""

    history: LoadHistory
    columns: np.ndarray
    names: tuple[str, ...]
    essential_names: dict

    def weights(self, t: float) -> np.ndarray:
        """The factor of each column at t."""
        return np.array([float(self.history.factor(n, t)) for n in self.names])

    def load(self, t: float) -> np.ndarray:
        return self.columns @ self.weights(t)

    def essential_factors(self, t: float) -> dict:
        """"body/edge" -> the factor (per component, or one) of its prescribed value at t."""
        return {key: np.array([float(self.history.factor(n, t)) for n in names])
                for key, names in self.essential_names.items()}


def _split(bc, names: tuple[str, ...]) -> list[tuple[str, object]]:
    """(factor name, condition with only the part that follows it) of one condition."""
    if isinstance(bc, Fixed):
        return []
    if isinstance(bc, (Sliding, Pressure)) or len(set(names)) == 1:
        return [(names[0], bc)]
    parts = []
    for k, name in enumerate(names):
        value = tuple(v if i == k or v is None else 0.0 for i, v in enumerate(bc.value))
        if isinstance(bc, Displacement) and value[k] is None:
            continue
        parts.append((name, dataclasses.replace(bc, value=value)))
    return parts


def _components(bc, dim: int) -> int:
    return 1 if isinstance(bc, (Sliding, Pressure, Fixed)) else dim


def path_loads(problem, bodies, settings) -> PathLoads:
    """The load columns of ``problem`` (which has a ``history``) on the discretised bodies."""
    history: LoadHistory = problem.history
    dim = problem.dim
    n = bodies[0].n_total
    zero = sp.csr_matrix((n, n))
    columns: dict[str, np.ndarray] = {}
    essential_names = {}
    for j, bc in enumerate(problem.boundary_conditions):
        names = history.names_of(j, _components(bc, dim))
        if isinstance(bc, (Displacement, Sliding)):
            essential_names[f"{bc.body}/{bc.edge}"] = names
        for name, part in _split(bc, names):
            single = dataclasses.replace(problem, boundary_conditions=(part,))
            _, f, _ = boundary_terms(single, bodies, settings, zero)
            columns[name] = columns.get(name, np.zeros(n)) + f
    names = tuple(columns)
    cols = np.column_stack([columns[k] for k in names]) if names else np.zeros((n, 0))
    return PathLoads(history, cols, names, essential_names)
