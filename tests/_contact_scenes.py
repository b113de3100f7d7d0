"""The small cylinder-on-block scene the fast contact tests share: a half-disk R = 1 on a
3 x 1 block, the cylinder's flat edge moved by (ux, uy) and everything turned by ``turn``
degrees; about 10-13 refined cells across the contact."""

from __future__ import annotations

import math

from ibfem.solver.io.scene import scene_from_dict

E, NU = 2.0e11, 0.3


def cylinder_on_block(kind="frictionless", ux=0.0, uy=-2.0e-3, load_steps=2, turn=0.0, friction=None):
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    load = [c * ux - s * uy, s * ux + c * uy]
    refinement = [
        {"levels": 2, "around": "contact", "radius": 0.4},
        {"levels": 4, "around": "contact", "radius": 0.12},
    ]
    contact = {"bodies": ["cyl", "block"], "type": kind, "point": [0, 0]}
    if friction is not None:
        contact["friction"] = friction
    return scene_from_dict(
        {
            "name": f"small cylinder on block, {kind}",
            "model": "plane_strain",
            "thickness": 1.0,
            "solver": {"load_steps": load_steps},
            "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU}],
            "bodies": [
                {"name": "cyl", "material": "steel", "element_size": 0.1, "refinement": refinement,
                 "shape": {"type": "half_disk", "center": [0, 1], "radius": 1.0, "side": "below",
                           "rotate_deg": turn}},
                {"name": "block", "material": "steel", "element_size": 0.1, "refinement": refinement,
                 "shape": {"type": "rectangle", "min": [-1.5, -1.0], "max": [1.5, 0.0], "rotate_deg": turn}},
            ],
            "boundary_conditions": [
                {"body": "cyl", "edge": "flat", "type": "displacement", "value": load},
                {"body": "block", "edge": "bottom", "type": "fixed"},
            ],
            "contacts": [contact],
        }
    ).problem
