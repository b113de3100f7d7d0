"""The scene's ``[[paths]]`` tables and the ``path`` key of boundary conditions, validated with
pydantic, and the :class:`solver.model.load_paths.LoadHistory` they make.

A path is given by its points or by a cycle generator::

    [[paths]]
    name = "hold"
    points = [[0.0, 0.0], [1.0, 1.0], [4.0, 1.0]]

    [[paths]]
    name = "fret"
    cycle = { amplitude = 1.0, cycles = 3, points_per_cycle = 4, start = 1.0 }

A condition's ``path`` is one name (every component) or a list of one name per component.
"""

from __future__ import annotations

from typing import Any, Union

from pydantic import BeforeValidator, Field, model_validator
from pydantic_core import PydanticCustomError
from typing import Annotated

from .strict_model import StrictTable, integer, number
from ..model.load_paths import LoadHistory, LoadPath, cycle_points

__all__ = ["CycleSpec", "PathSpec", "PathRef", "history_problems", "load_history"]


_number, _integer = number, integer

_Num = Annotated[float, BeforeValidator(_number)]
_Int = Annotated[int, BeforeValidator(_integer)]


_Table = StrictTable


class CycleSpec(_Table):
    """mean + amplitude sin(2 pi (t - start) / period), sampled at points_per_cycle per cycle,
    after a ramp from 0 at t = 0 to mean at start."""

    amplitude: _Num
    cycles: _Num = Field(gt=0.0, le=100_000)
    points_per_cycle: _Int = Field(4, ge=2, le=10_000)
    mean: _Num = 0.0
    start: _Num = Field(0.0, ge=0.0)
    period: _Num = Field(1.0, gt=0.0)


class PathSpec(_Table):
    name: str = Field(min_length=1)
    points: list[tuple[_Num, _Num]] | None = None
    cycle: CycleSpec | None = None

    @model_validator(mode="after")
    def _one_definition(self) -> "PathSpec":
        if (self.points is None) == (self.cycle is None):
            raise PydanticCustomError("path", "give either points = [[t, factor], ...] or cycle = {...}, not both "
                                              "and not neither")
        if self.points is not None:
            t = [p[0] for p in self.points]
            if not t:
                raise PydanticCustomError("path", "points must not be empty")
            if t[0] < 0.0 or any(b <= a for a, b in zip(t, t[1:])):
                raise PydanticCustomError("path", "the t of the points must start at 0 or later and increase "
                                                  "strictly")
        return self

    def path(self) -> LoadPath:
        if self.points is not None:
            return LoadPath(self.name, self.points)
        c = self.cycle
        return LoadPath(self.name, cycle_points(c.amplitude, c.cycles, c.points_per_cycle, c.mean, c.start, c.period))


#: a condition's ``path``: one name, or one per component
PathRef = Union[str, tuple[str, ...]]


def _components(bc: Any) -> int:
    value = getattr(bc, "value", None)
    return len(value) if isinstance(value, (tuple, list)) else 1


def history_problems(paths: list[PathSpec], conditions: list[Any], label: str) -> list[str]:
    """Duplicate path names, unknown names in a condition's ``path``, lists of the wrong length."""
    problems = []
    names: dict[str, int] = {}
    for i, p in enumerate(paths):
        if p.name in names:
            problems.append(f'{label}: paths[{i}].name = "{p.name}": duplicate name (also paths[{names[p.name]}])')
        names.setdefault(p.name, i)
    known = ", ".join(names) or "none: add [[paths]] tables"
    for j, bc in enumerate(conditions):
        ref = getattr(bc, "path", None)
        if ref is None:
            continue
        refs = (ref,) if isinstance(ref, str) else tuple(ref)
        n = _components(bc)
        if len(refs) not in (1, n):
            problems.append(f"{label}: boundary_conditions[{j}].path = {list(refs)}: give one path name or {n} "
                            f"(one per component of the value)")
        for k, r in enumerate(refs):
            if r not in names:
                where = f"boundary_conditions[{j}].path" + ("" if isinstance(ref, str) else f"[{k}]")
                problems.append(f'{label}: {where} = "{r}": unknown load path (known: {known})')
    return problems


def load_history(paths: list[PathSpec], conditions: list[Any], steps_per_unit: int | None,
                 load_steps: int) -> LoadHistory | None:
    """The LoadHistory of validated tables (None without paths: proportional loading)."""
    if not paths and all(getattr(bc, "path", None) is None for bc in conditions):
        return None
    assignments = []
    for bc in conditions:
        ref = getattr(bc, "path", None)
        assignments.append(None if ref is None else ((ref,) if isinstance(ref, str) else tuple(ref)))
    return LoadHistory(paths={p.name: p.path() for p in paths}, assignments=tuple(assignments),
                       steps_per_unit=steps_per_unit or load_steps)
