"""ibfem's solver: immersed-boundary finite elements with the step boundary method on exact
geometry, two-body contact, scenes, results and the ``ibfem`` command line.

Public API (everything else is internal and may move)::

    import solver
    scene = solver.load_scene("examples/cylinder_on_flat_partial_slip.toml")   # or a dict
    solution = solver.solve(scene.problem)
    summary = solver.write_results("out/case", scene, solution)

- ``load_scene(source, label=None, base_dir=None) -> Scene``: a scene file (TOML, or JSON by
  extension) or the parsed data (a dict; ``label`` names it in errors, relative paths are taken
  from ``base_dir``). Raises ``SceneError`` (one line per problem, with its key path).
- ``scene_from_dict(data, label="scene", base_dir=".") -> Scene``: the same for plain data.
- ``solve(problem, progress=None) -> Solution``: solve a validated problem (``scene.problem``).
- ``write_results(out_dir, scene, solution, total_s=None, extra=None) -> dict``: write
  ``summary.json`` and the files the scene's ``[output]`` asks for; returns the summary.
- Types: ``Scene``, ``Problem``, ``Solution``, ``SceneError``, ``SolverOptions`` (the
  ``[solver]`` table), ``ContactOptions`` (the numerical keys of a ``[[contacts]]`` table).

Names are imported lazily, so ``import solver`` loads no numerics.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__all__ = [
    "load_scene",
    "scene_from_dict",
    "solve",
    "write_results",
    "Scene",
    "SceneError",
    "Problem",
    "Solution",
    "SolverOptions",
    "ContactOptions",
]

_WHERE = {
    "load_scene": ("solver.io.scene", "load_scene"),
    "scene_from_dict": ("solver.io.scene", "scene_from_dict"),
    "Scene": ("solver.io.scene", "Scene"),
    "SceneError": ("solver.io.scene", "SceneError"),
    "solve": ("solver.solve", "solve"),
    "write_results": ("solver.io.output", "write_scene_results"),
    "Problem": ("solver.model.problem", "Problem"),
    "Solution": ("solver.model.problem", "Solution"),
    "SolverOptions": ("solver.model.options", "SolverOptions"),
    "ContactOptions": ("solver.model.options", "ContactOptions"),
}


def __getattr__(name: str) -> Any:
    try:
        module, attr = _WHERE[name]
    except KeyError:
        raise AttributeError(f"module 'solver' has no attribute {name!r}") from None
    value = getattr(import_module(module), attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
