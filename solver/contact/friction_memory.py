"""Which frictional runs solve with friction memory although their scene gives no load path.

A proportional run's partial slip is Cattaneo and Mindlin's: one slip direction, the stick zone
centred, its size from the forces. That needs bodies whose pressure does not slip them apart
tangentially. Bodies of different elastic constants do slip apart under the normal load alone:
one end inward, the other outward (Dundurs' beta not 0; K. L. Johnson, Contact Mechanics, 1985,
sec. 5.4), and with a tangential load the two ends of the slip zones then slip in opposite
directions, which those zones cannot hold. On 2D scenes drawn at random every frictional pair with
|beta| / mu from 0.2 up and a tangential load ended, proportionally, with one end slipping against
its friction traction. Such a 2D contact is solved with friction memory instead: every condition
ramps from 0 to its value over at least MEMORY_STEPS load steps, and the zones are found point by
point from Coulomb's law on each step's increment, in either direction.
"""

from __future__ import annotations

import dataclasses

from ..model.load_paths import LoadHistory

__all__ = ["BETA_OVER_MU", "MEMORY_STEPS", "MEMORY_STICK_ITERATIONS", "with_friction_memory"]

#: a frictional contact whose |beta| is at least this fraction of mu keeps a friction history (2D)
#: and is warned of (3D, whose proportional zones have the same limit)
BETA_OVER_MU = 0.1
#: the ramp's load steps at least (the zones follow the load's increments: under a growing normal
#: load a step should grow the region by a few per cent)
MEMORY_STEPS = 10
#: zone updates per load step at least: the two ends' stick boundaries are refined each by up to
#: twelve secant steps besides the zone updates (a stiff rounded punch on a block, beta -0.28, took
#: 30 to 40 in a step)
MEMORY_STICK_ITERATIONS = 80


def with_friction_memory(problem):
    """``problem`` itself, or (a 2D problem without load paths whose frictional contacts include
    one of bodies slipping apart, |beta| >= BETA_OVER_MU mu) a copy that ramps every condition over
    max(load_steps, MEMORY_STEPS) steps with friction memory; the summary's load-step rule says so."""
    if problem.dim != 2 or getattr(problem, "history", None) is not None:
        return problem
    frictional = [(c, problem.dundurs_beta(c)) for c in problem.contacts if c.type == "frictional" and c.friction > 0.0]
    apart = [(c, beta) for c, beta in frictional if abs(beta) >= BETA_OVER_MU * c.friction]
    if not apart:
        return problem
    steps = max(problem.options.load_steps, MEMORY_STEPS)
    named = ", ".join(f"{'/'.join(c.bodies)} {beta:+.3g} (mu {c.friction:g})" for c, beta in apart)
    reason = (f"friction with memory over a ramp of {steps} steps: the bodies' elastic constants differ (Dundurs' "
              f"beta {named}), so the two ends may slip in opposite directions, which Cattaneo and Mindlin's "
              "proportional zones cannot hold")
    contacts = tuple(dataclasses.replace(c, options=dataclasses.replace(
        c.options, max_stick_iterations=max(c.options.max_stick_iterations, MEMORY_STICK_ITERATIONS)))
        if c.type == "frictional" else c for c in problem.contacts)
    history = LoadHistory(assignments=tuple(None for _ in problem.boundary_conditions), steps_per_unit=steps,
                          reason=reason)
    return dataclasses.replace(problem, contacts=contacts, history=history)
