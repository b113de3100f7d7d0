"""ibfem's solver: immersed-boundary finite elements with the step boundary method on exact
geometry, two-body contact, scenes, results and the ``ibfem`` command line.

Public API (everything else is internal and may move)::

    from ibfem import solver
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

Names are imported lazily, so ``from ibfem import solver`` loads no numerics.
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
    "load_scene": ("ibfem.solver.io.scene", "load_scene"),
    "scene_from_dict": ("ibfem.solver.io.scene", "scene_from_dict"),
    "Scene": ("ibfem.solver.io.scene", "Scene"),
    "SceneError": ("ibfem.solver.io.scene", "SceneError"),
    "solve": ("ibfem.solver.solving", "solve"),
    "write_results": ("ibfem.solver.io.output", "write_scene_results"),
    "Problem": ("ibfem.solver.model.problem", "Problem"),
    "Solution": ("ibfem.solver.model.problem", "Solution"),
    "SolverOptions": ("ibfem.solver.model.options", "SolverOptions"),
    "ContactOptions": ("ibfem.solver.model.options", "ContactOptions"),
}


def __getattr__(name: str) -> Any:
    try:
        module, attr = _WHERE[name]
    except KeyError:
        raise AttributeError(f"module 'ibfem.solver' has no attribute {name!r}") from None
    value = getattr(import_module(module), attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
