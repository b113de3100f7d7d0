"""Conditions given along axes of their own: ``axes`` on a displacement, traction or body force.

An inclined contact (a dovetail's flank, a turned part) is loaded along its own normal and
tangent, not along x, y (and z). With ``axes``, a condition's ``value`` and its ``path`` are given
per axis::

    [[boundary_conditions]]
    type = "displacement"
    body = "pad"
    edge = "flat"
    axes = [[0.866, 0.5], [-0.5, 0.866]]   # the contact's tangent, then its normal
    value = [6.0e-4, -2.5e-3]              # along each axis
    path = ["fret", "hold"]                # the tangent cycles while the normal is held

The axes are directions (each scaled to unit length; they need not be orthogonal, only
independent). The value at t is sum_k value_k f_k(t) axis_k. Each global component is then a
sum of piecewise-linear factors, itself piecewise linear with corners where any of them has
one: :func:`in_global_components` writes it as a path of its own per component, so the solver
sees global components as always, and the run's load steps are the same.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import field_validator, model_validator
from pydantic_core import PydanticCustomError

from ..model.load_paths import RAMP, LoadHistory
from .load_paths_spec import PathSpec
from .strict_model import StrictTable

__all__ = ["AlongAxes", "in_global_components", "unit_axes"]

#: axes whose unit vectors span less than this (|det|) are refused as dependent
MIN_SPAN = 1e-6


def unit_axes(axes) -> np.ndarray:
    """The axes (k, d) each scaled to unit length."""
    a = np.asarray(axes, dtype=float)
    return a / np.linalg.norm(a, axis=1, keepdims=True)


class AlongAxes(StrictTable):
    """The check of ``axes`` (a mixin of the condition tables that have them): every axis non-zero,
    together independent, and every component of the value given."""

    @field_validator("axes", check_fields=False)
    @classmethod
    def _axes_span(cls, axes):
        if axes is None:
            return axes
        a = np.asarray(axes, dtype=float)
        if np.any(np.linalg.norm(a, axis=1) == 0.0):
            raise PydanticCustomError("axes", "an axis is the zero vector: give each axis's direction")
        if abs(np.linalg.det(unit_axes(a))) < MIN_SPAN:
            raise PydanticCustomError("axes", "the axes are not independent (they lie in one line or plane): "
                                              "give directions that span the space")
        return axes

    @model_validator(mode="after")
    def _values_given(self):
        if getattr(self, "axes", None) is not None and any(v is None for v in self.value):
            raise PydanticCustomError("axes", "value has a free component: with axes every component of the "
                                              "value is prescribed (a free component needs the global axes)")
        return self


def _names(bc: Any, dim: int) -> tuple[str, ...]:
    ref = getattr(bc, "path", None)
    if ref is None:
        return (RAMP,) * dim
    return (ref,) * dim if isinstance(ref, str) else tuple(ref)


def _corners(history: LoadHistory, names: tuple[str, ...]) -> np.ndarray:
    """Every t where one of the factors ``names`` has a corner (a ramp: 0 and the run's end)."""
    t = [np.array([0.0, history.end]) if n == RAMP else history.paths[n].points[:, 0] for n in names]
    return np.unique(np.concatenate(t))


def _component_paths(j: int, bc: Any, history: LoadHistory, dim: int) -> tuple[tuple, tuple, list[PathSpec]]:
    """(value, path names, new paths) of condition j in global components, one path per component."""
    names = _names(bc, dim)
    a = unit_axes(bc.axes)
    v = np.asarray(bc.value, dtype=float)
    t = _corners(history, names)
    factors = np.array([history.factor(n, t) for n in names])  # (axes, corners)
    g = (v[:, None] * factors).T @ a  # (corners, components): sum_k v_k f_k(t) axis_k
    value, refs, paths = [], [], []
    for i in range(dim):
        scale = float(np.abs(g[:, i]).max())
        name = f"boundary_conditions[{j}] along {'xyz'[i]}"
        value.append(scale)
        refs.append(name)
        factor = g[:, i] / scale if scale > 0.0 else np.zeros(len(t))
        paths.append(PathSpec(name=name, points=[(float(ti), float(fi)) for ti, fi in zip(t, factor)]))
    return tuple(value), tuple(refs), paths


def in_global_components(spec: Any, dim: int) -> Any:
    """``spec`` with every condition given along ``axes`` written in global components: one path of
    its own per component where its axes follow different paths, its value turned where they
    follow one (or none). Conditions without axes and scenes without any are returned as they are."""
    conditions = list(spec.boundary_conditions)
    if not any(getattr(bc, "axes", None) is not None for bc in conditions):
        return spec
    history = LoadHistory(paths={p.name: p.path() for p in spec.paths})
    added: list[PathSpec] = []
    for j, bc in enumerate(conditions):
        if getattr(bc, "axes", None) is None:
            continue
        if len(set(_names(bc, dim))) == 1:
            turned = np.asarray(bc.value, dtype=float) @ unit_axes(bc.axes)
            conditions[j] = bc.model_copy(update={"value": tuple(float(x) for x in turned), "axes": None})
            continue
        value, refs, paths = _component_paths(j, bc, history, dim)
        conditions[j] = bc.model_copy(update={"value": value, "axes": None, "path": refs})
        added += paths
    return spec.model_copy(update={"boundary_conditions": conditions, "paths": list(spec.paths) + added})
