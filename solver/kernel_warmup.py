"""Compile the solver's numba kernels into their on-disk cache (``ibfem compile``).

The large solves (the multifrontal Cholesky of 3D contact, the contact terms' per-point blocks,
the cut cells' geometry) run numba kernels compiled on first use and cached on disk (beside the
sources in ``__pycache__``, or in the user's cache directory where the package is read-only). A
user's first large 3D run after an install otherwise spends 7 to 11 s compiling them (the full
turned ball on a block: 98 s on a first run against 64 s warm).

Small problems take none of those paths: below a few hundred thousand stored entries a contact
condenses with SuperLU, a trial's small system is factored in double precision on one thread,
and no factor goes to disk. So the warm-up solves two small contact scenes (a full ball on a
block with friction in two load steps, its factors streamed to disk, and a half disc on a block
in 2D, its factors in memory) with every size threshold that selects a compiled path set to
zero, each path then taken on a problem of a few thousand dofs: about 10 to 30 s once, nothing
after."""

from __future__ import annotations

import contextlib
import os
import time
from typing import Callable

__all__ = ["WARM_SCENES", "warm_kernels"]


def _steel_scene(name: str, model: str, bodies: list, conditions: list, contact: dict) -> dict:
    """A scene of steel bodies in two load steps, no files written."""
    return {"name": name, "model": model, "solver": {"load_steps": 2}, "output": {"vtk": False, "plots": False},
            "materials": [{"name": "steel", "youngs_modulus": 2.0e11, "poissons_ratio": 0.3}],
            "bodies": [dict(body, material="steel") for body in bodies], "boundary_conditions": conditions,
            "contacts": [contact]}


def _ball_on_block() -> dict:
    """A full half ball on a block, friction 0.2: the 3D contact path (the coarse pass that sizes
    the candidate disc, the region's centre, the stick ratio)."""
    zone = [{"levels": 4, "around": "contact", "radius": 0.15}]
    return _steel_scene("warm-up ball on block", "solid", [
        {"name": "ball", "element_size": 0.25, "refinement": zone,
         "shape": {"type": "half_sphere", "center": [0.0, 0.0, 0.5], "radius": 0.5, "side": "below"}},
        {"name": "block", "element_size": 0.25, "refinement": zone,
         "shape": {"type": "box", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.0]}},
    ], [{"body": "ball", "face": "flat", "type": "displacement", "value": [3.0e-4, 0.0, -0.004]},
        {"body": "block", "face": "z_min", "type": "fixed"}],
        {"bodies": ["ball", "block"], "type": "frictional", "friction": 0.2, "point": [0.0, 0.0, 0.0]})


def _disc_on_block() -> dict:
    """A half disc on a block in plane strain, friction 0.3: the 2D contact path."""
    zone = [{"levels": 3, "around": "contact", "radius": 0.12}]
    return _steel_scene("warm-up disc on block", "plane_strain", [
        {"name": "disc", "element_size": 0.1, "refinement": zone,
         "shape": {"type": "half_disk", "center": [0.0, 1.0], "radius": 1.0, "side": "below"}},
        {"name": "block", "element_size": 0.1, "refinement": zone,
         "shape": {"type": "rectangle", "min": [-2.0, -2.0], "max": [2.0, 0.0]}},
    ], [{"body": "disc", "edge": "flat", "type": "displacement", "value": [3.65e-4, -2.5e-3]},
        {"body": "block", "edge": "bottom", "type": "fixed"}],
        {"bodies": ["disc", "block"], "type": "frictional", "friction": 0.3})


#: the warm-up's scenes, in the order solved, and whether each streams its factors to disk (the
#: 3D scene: the large bodies' path) or keeps them in memory (the 2D scene: the smaller ones')
WARM_SCENES = ((_ball_on_block, True), (_disc_on_block, False))


def _every_path_settings(streamed: bool) -> list[tuple[object, str, object]]:
    """(owner, attribute, value) of every size threshold between a plain path and a compiled one,
    set so that the compiled one is taken (the multifrontal Cholesky, its factor written to disk
    in small chunks where ``streamed`` else kept in memory, fronts of 64 rows or more on the
    thread pool and runs of smaller ones compiled together, a trial's system in single precision
    on threads, the order choice, the trailing block of G, the coarse pass that sizes a
    candidate disc)."""
    from .contact import sizing
    from .fem import linalg, multifrontal, pair_blocks

    return [(linalg, "CHOLESKY_NONZEROS", 0), (linalg, "ORDER_CHOICE_DOFS", 0),
            (linalg, "TRAILING_INVERSE_DOFS", 1), (linalg.SmallSystem, "SINGLE_PRECISION_ACTIVE", 1),
            (linalg.SmallSystem, "THREADED_ACTIVE", 1), (multifrontal, "DISK_CHUNK_BYTES", 1 << 16),
            (multifrontal, "ON_DISK_BYTES", 0 if streamed else 1 << 62), (multifrontal, "THREADED_FRONT_ROWS", 64),
            (pair_blocks, "THREADED_POINTS", 1), (sizing, "MIN_CONTACT_DOFS", 0.0)]


@contextlib.contextmanager
def _every_path(streamed: bool):
    """Within: the thresholds of :func:`_every_path_settings` and two threads; restored after."""
    settings = _every_path_settings(streamed)
    saved = [(owner, name, getattr(owner, name)) for owner, name, _ in settings]
    threads = os.environ.get("IBFEM_THREADS")
    try:
        for owner, name, value in settings:
            setattr(owner, name, value)
        os.environ["IBFEM_THREADS"] = "2"
        yield
    finally:
        for owner, name, value in saved:
            setattr(owner, name, value)
        if threads is None:
            os.environ.pop("IBFEM_THREADS", None)
        else:
            os.environ["IBFEM_THREADS"] = threads


def warm_kernels(report: Callable[[str], None] | None = None) -> list[dict]:
    """Solve the :data:`WARM_SCENES` with every compiled path taken; per scene its name, whether
    it converged and its seconds (the first time mostly compiling, then a second or two)."""
    from .io.scene import load_scene
    from .solving import solve

    rows = []
    for make, streamed in WARM_SCENES:
        data = make()
        if report is not None:
            report(f"{data['name']} ...")
        start = time.perf_counter()
        with _every_path(streamed):
            solution = solve(load_scene(data, label=data["name"]).problem)
        rows.append({"scene": data["name"], "converged": bool(solution.converged),
                     "seconds": time.perf_counter() - start})
    return rows
