"""What a contact formulation supplies to the load-step driver, and the registry of the
formulations a scene can name (``[[contacts]] formulation = "band"``).

A formulation is built per contact by ``build(problem, contact, body1, body2, options)``
(the discretised bodies, the problem's SolverOptions) and then answers the driver through the
:class:`ContactFormulation` protocol. Registered builders are imported only when used.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any, Callable, Iterator, Protocol

import numpy as np

__all__ = ["ContactFormulation", "FORMULATIONS", "FORMULATIONS_3D", "formulation"]

#: name -> "module:builder", imported on first use
FORMULATIONS = {"band": "ibfem.solver.contact.band:build", "ellipse": "ibfem.solver.contact.contact3d:build"}
#: the formulation a name means in 3D (the band terms on an elliptical region)
FORMULATIONS_3D = {"band": "ellipse"}


class ContactFormulation(Protocol):
    """One contact as the driver sees it. ``x`` are the values of the contact's dofs, ``a`` the
    size of its contact region (the half-width in 2D), ``info`` what :meth:`terms` returned."""

    dofs: np.ndarray  # global dofs the contact terms act on (sorted)
    options: Any  # the contact's ContactOptions
    history: list  # one record per trial (summary.json iterations.contacts)

    def initial_region(self) -> float: ...

    def next_region(self, a: float, load_ratio: float) -> float: ...

    def region_search(self, a0: float, final: bool, max_iterations: int, estimate: bool = False) -> Iterator[float]: ...

    def region_too_small(self) -> Exception: ...

    def terms(self, a: float) -> tuple[np.ndarray, np.ndarray, Any]: ...

    def judge(self, x: np.ndarray, a: float, info: Any) -> Any: ...

    def history_entry(self, verdict: Any, a: float, step: int, iteration: int, tag: int, ratio: float) -> None: ...

    def force(self, x: np.ndarray, a: float, info: Any) -> np.ndarray: ...

    def is_symmetric(self) -> bool: ...

    def start_step(self) -> None: ...

    def update_stick_and_shape(self, x: np.ndarray, a: float, info: Any, final: bool = True) -> bool: ...

    def finish(self) -> list[str]: ...

    def traction_samples(self, u: np.ndarray, a: float, s: np.ndarray) -> tuple[Any, np.ndarray]: ...

    def check_final(self, u: np.ndarray, a: float, info: Any, bracket: Any, block: dict) -> list[str]: ...


def formulation(name: str, dim: int = 2) -> Callable[..., ContactFormulation]:
    """The builder of a registered formulation (``dim`` 3: its 3D member, FORMULATIONS_3D)."""
    if dim == 3:
        name = FORMULATIONS_3D.get(name, name)
    try:
        module, attr = FORMULATIONS[name].split(":")
    except KeyError:
        raise ValueError(f"unknown contact formulation {name!r}; known: {', '.join(FORMULATIONS)}") from None
    return getattr(import_module(module), attr)
