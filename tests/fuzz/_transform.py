"""Rigid motions of plane scenes (as parsed dicts), for invariance checks: a scene turned by
``deg`` about the origin and then shifted must give the same forces (N within 1 %).
Displacement components given as "free" stay meaningful only for quarter turns, which swap
them."""

from __future__ import annotations

import copy
import math
from typing import Any


def moved(data: dict[str, Any], deg: float = 0.0, shift: tuple[float, float] = (0.0, 0.0)) -> dict[str, Any]:
    """``data`` turned by ``deg`` about the origin, then translated by ``shift``."""
    d = copy.deepcopy(data)
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))

    def vec(v):  # a direction (displacement, force)
        return [c * v[0] - s * v[1], s * v[0] + c * v[1]]

    def pos(p):  # a position
        v = vec(p)
        return [v[0] + shift[0], v[1] + shift[1]]

    for body in d["bodies"]:
        shape = body["shape"]
        pivot = shape.get("pivot", [0.0, 0.0])
        # the shape's own turn is about its pivot; compose: first its turn, then ours about the origin
        shape["rotate_deg"] = shape.get("rotate_deg", 0.0) + deg
        old_translate = shape.get("translate", [0.0, 0.0])
        # ours about the origin = the same turn about the pivot + a translation
        off = [pivot[0] + old_translate[0], pivot[1] + old_translate[1]]
        moved_off = pos(off)
        shape["translate"] = [moved_off[0] - pivot[0], moved_off[1] - pivot[1]]
        for zone in body.get("refinement", []) if isinstance(body.get("refinement"), list) else []:
            if zone.get("around") != "contact":
                zone["around"] = pos(zone["around"])
    for bc in d.get("boundary_conditions", []):
        if bc["type"] == "displacement":
            bc["value"] = _turn_components(bc["value"], deg, vec)
        elif bc["type"] in ("traction", "body_force"):
            bc["value"] = vec(bc["value"])
    for contact in d.get("contacts", []):
        if "point" in contact:
            contact["point"] = pos(contact["point"])
    out = d.get("output", {})
    if out.get("probes"):
        out["probes"] = [pos(p) for p in out["probes"]]
    for ln in out.get("lines", []):
        ln["start"], ln["end"] = pos(ln["start"]), pos(ln["end"])
    return d


def _turn_components(value, deg, vec):
    if "free" not in value:
        return vec(value)
    quarter = round(deg / 90.0)
    if abs(deg - 90.0 * quarter) > 1e-12:
        raise ValueError("a displacement with a free component turns only by multiples of 90 degrees")
    w = vec([0.0 if x == "free" else x for x in value])
    w = [0.0 if abs(x) < 1e-300 else x for x in w]
    if quarter % 2:  # x <-> y
        return ["free" if value[1] == "free" else w[0], "free" if value[0] == "free" else w[1]]
    return ["free" if value[0] == "free" else w[0], "free" if value[1] == "free" else w[1]]
