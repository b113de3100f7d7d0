"""A scene turned rigidly about an axis through the origin, for the tests that check a rigid turn
changes nothing physical (test-local helper)."""

from __future__ import annotations

import numpy as np


def turned_scene(data: dict, axis, angle_deg: float) -> dict:
    """The scene ``data`` turned about ``axis`` through the origin (the contact point): each
    shape's rotation composed with the turn, its translation, the refinement balls' centres and
    the prescribed displacements turned; the contacts' points turned."""
    from scipy.spatial.transform import Rotation

    turn = Rotation.from_rotvec(np.radians(angle_deg) * np.asarray(axis, float) / np.linalg.norm(axis))
    for body in data["bodies"]:
        shape = body["shape"]
        own = shape.get("rotate")
        r = turn if own is None else turn * Rotation.from_rotvec(np.radians(own["angle_deg"]) * np.asarray(own["axis"], float))
        vec = r.as_rotvec()
        shape["rotate"] = {"axis": (vec / np.linalg.norm(vec)).tolist(), "angle_deg": float(np.degrees(np.linalg.norm(vec)))}
        shape["translate"] = turn.apply(np.asarray(shape.get("translate", [0, 0, 0]), float)).tolist()
        zones = body.get("refinement", [])
        body["refinement"] = zones = [zones] if isinstance(zones, dict) else zones
        for zone in zones:
            if zone["around"] != "contact":
                zone["around"] = turn.apply(np.asarray(zone["around"], float)).tolist()
    for bc in data["boundary_conditions"]:
        if bc["type"] == "displacement":
            bc["value"] = turn.apply(np.asarray(bc["value"], float)).tolist()
    for contact in data.get("contacts", []):
        if "point" in contact:
            contact["point"] = turn.apply(np.asarray(contact["point"], float)).tolist()
    return data
