"""Scenes of the 2D contacts CAD makes (shared by the fast tests and the slow validation): a flat
punch with rounded (or sharp) edges on a block, its half model, and a pin in a bore. Steel on
steel, plane strain, frictionless; sizes in m."""

from __future__ import annotations

import math

E, NU = 2.0e11, 0.3
#: composite plane-strain modulus of two steel bodies, 1 / (2 (1 - nu^2) / E)
E_STAR = E / (2.0 * (1.0 - NU**2))
#: the punch's flat half-width b, its edge radius R (the edges turn by EDGE_TURN degrees into straight
#: flanks) and its height: contact half-widths a <= 3 b stay below 0.03 R and 0.1 of the height
HALF_FLAT, EDGE_RADIUS, EDGE_TURN, PUNCH_HEIGHT = 0.01, 1.0, 10.0, 0.3


def _punch_edges(b: float, radius: float, height: float, sharp: bool) -> list[dict]:
    if sharp:
        return [
            {"name": "flat", "type": "line", "start": [-b, 0.0], "end": [b, 0.0]},
            {"name": "right", "type": "line", "start": [b, 0.0], "end": [b, height]},
            {"name": "top", "type": "line", "start": [b, height], "end": [-b, height]},
            {"name": "left", "type": "line", "start": [-b, height], "end": [-b, 0.0]},
        ]
    th = math.radians(EDGE_TURN)  # the rounded edges turn into straight flanks (tangent junctions)
    xe, ye = b + radius * math.sin(th), radius * (1.0 - math.cos(th))
    xt = xe + (height - ye) / math.tan(th)
    return [
        {"name": "flat", "type": "line", "start": [-b, 0.0], "end": [b, 0.0]},
        {"name": "round_right", "type": "arc", "center": [b, radius], "radius": radius, "start_angle": -90.0,
         "end_angle": -90.0 + EDGE_TURN},
        {"name": "flank_right", "type": "line", "start": [xe, ye], "end": [xt, height]},
        {"name": "top", "type": "line", "start": [xt, height], "end": [-xt, height]},
        {"name": "flank_left", "type": "line", "start": [-xt, height], "end": [-xe, ye]},
        {"name": "round_left", "type": "arc", "center": [-b, radius], "radius": radius, "start_angle": -90.0 - EDGE_TURN,
         "end_angle": -90.0},
    ]


def _one_sharp_edges(b: float, radius: float, height: float) -> list[dict]:
    """A flat of half-width b with a sharp right corner (a vertical side) and a left edge rounded
    with ``radius`` turning EDGE_TURN degrees into a straight flank."""
    th = math.radians(EDGE_TURN)
    xe, ye = b + radius * math.sin(th), radius * (1.0 - math.cos(th))
    xt = xe + (height - ye) / math.tan(th)
    return [
        {"name": "flat", "type": "line", "start": [-b, 0.0], "end": [b, 0.0]},
        {"name": "right", "type": "line", "start": [b, 0.0], "end": [b, height]},
        {"name": "top", "type": "line", "start": [b, height], "end": [-xt, height]},
        {"name": "flank_left", "type": "line", "start": [-xt, height], "end": [-xe, ye]},
        {"name": "round_left", "type": "arc", "center": [-b, radius], "radius": radius, "start_angle": -90.0 - EDGE_TURN,
         "end_angle": -90.0},
    ]


def _halved(edges: list[dict], height: float) -> list[dict]:
    """The right half (x >= 0) of a symmetric punch, closed by the symmetry line x = 0."""
    out = []
    for e in edges:
        if e["name"] in ("flat", "top"):
            e = dict(e)
            e["start" if e["name"] == "flat" else "end"] = [0.0, 0.0 if e["name"] == "flat" else height]
        if e["name"] in ("flat", "top") or "right" in e["name"]:
            out.append(e)
    return out + [{"name": "symmetry", "type": "line", "start": [0.0, height], "end": [0.0, 0.0]}]


def punch_on_block(approach: float, levels: int = 6, radius: float = 0.05, sharp: bool = False, half: bool = False,
                   punch_modulus: float = E, turn: float = 0.0, sliding: bool = True, one_sharp: bool = False) -> dict:
    """A punch (flat half-width HALF_FLAT, edges rounded with EDGE_RADIUS unless ``sharp``) pressed
    ``approach`` into a 1.2 m block (its top edge moved down; the block's bottom fixed). ``levels``
    of refinement within ``radius`` of the contact (finest cell 0.04 / 2^levels); ``half``: the
    half model x >= 0 with sliding conditions on x = 0 (``sliding`` false: none, an invalid model);
    ``turn``: everything turned by this many degrees about the contact point; ``one_sharp``: the
    right edge sharp, the left rounded (a region with one complete and one incomplete end)."""
    cornered = sharp or one_sharp
    b, height, width = HALF_FLAT, (0.1 if cornered else PUNCH_HEIGHT), 0.6
    edges = _one_sharp_edges(b, EDGE_RADIUS, height) if one_sharp else _punch_edges(b, EDGE_RADIUS, height, sharp)
    refinement = [{"levels": 2, "around": "contact", "radius": 6.0 * radius},
                  {"levels": levels, "around": "contact", "radius": radius}]
    rot = {"rotate_deg": turn} if turn else {}
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    if half:
        edges = _halved(edges, height)
        block = {"type": "polygon", "points": [[0.0, -width], [width, -width], [width, 0.0], [0.0, 0.0]],
                 "edge_names": ["bottom", "right", "top", "symmetry"], **rot}
    else:
        block = {"type": "rectangle", "min": [-width, -width], "max": [width, 0.0], **rot}
    punch_size = 0.005 if cornered else 0.04  # the grid must resolve the body (a sharp punch is 2 b wide)
    punch_levels = levels - 3 if cornered else levels
    bcs = [{"body": "punch", "edge": "top", "type": "displacement",
            "value": ["free" if half else s * approach, -c * approach]},
           {"body": "block", "edge": "bottom", "type": "fixed"}]
    if half and sliding:
        bcs += [{"body": n, "edge": "symmetry", "type": "sliding", "normal_displacement": 0.0} for n in ("punch", "block")]
    return {
        "name": f"{'one-sharp' if one_sharp else 'sharp' if sharp else 'rounded'} flat punch on a block{' (half model)' if half else ''}",
        "model": "plane_strain", "thickness": 1.0, "solver": {"load_steps": 1},
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU},
                      {"name": "punch", "youngs_modulus": punch_modulus, "poissons_ratio": NU}],
        "bodies": [
            {"name": "punch", "material": "punch", "element_size": punch_size,
             "refinement": [{"levels": punch_levels, "around": "contact", "radius": radius}] if cornered else refinement,
             "shape": {"type": "profile", "edges": edges, **rot}},
            {"name": "block", "material": "steel", "element_size": 0.04, "refinement": refinement, "shape": block},
        ],
        "boundary_conditions": bcs,
        "contacts": [{"bodies": ["punch", "block"], "type": "frictionless", "point": [0.0, 0.0]}],
    }


def pin_in_bore(load_displacement: float, pin_radius: float = 0.5, clearance: float = 5e-4, plate: float = 10.0,
                element_size: float = 0.25, levels: int = 4, radius: float = 0.8, seam: float = -90.0,
                hub: float = 0.1) -> dict:
    """A pin (radius ``pin_radius``, loaded through a hub of radius ``hub`` moved down by
    ``load_displacement``) in a bore ``clearance`` larger in a square plate of side ``plate``
    (fixed on its outer edges); both full circles have their seam at ``seam`` degrees (-90: at the
    contact point). The pin touches the bore at its lowest point."""
    cy = -clearance
    refinement = [{"levels": 2, "around": "contact", "radius": 2.0 * radius},
                  {"levels": levels, "around": "contact", "radius": radius}]
    h = plate / 2.0
    circle = {"type": "arc", "start_angle": seam, "end_angle": seam + 360.0}
    return {
        "name": "pin in a bore", "model": "plane_strain", "thickness": 1.0, "solver": {"load_steps": 1},
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU}],
        "bodies": [
            {"name": "pin", "material": "steel", "element_size": element_size / 4.0,
             "refinement": [dict(r, levels=max(r["levels"] - 2, 1)) for r in refinement],  # the plate's finest cell
             "shape": {"type": "profile",
                       "edges": [{"name": "rim", "center": [0.0, cy], "radius": pin_radius, **circle}],
                       "holes": [[{"name": "hub", "type": "arc", "center": [0.0, cy], "radius": hub,
                                   "start_angle": 0.0, "end_angle": 360.0}]]}},
            {"name": "plate", "material": "steel", "element_size": element_size, "refinement": refinement,
             "shape": {"type": "profile", "edges": [
                 {"name": "bottom", "type": "line", "start": [-h, -h], "end": [h, -h]},
                 {"name": "right", "type": "line", "start": [h, -h], "end": [h, h]},
                 {"name": "top", "type": "line", "start": [h, h], "end": [-h, h]},
                 {"name": "left", "type": "line", "start": [-h, h], "end": [-h, -h]}],
                 "holes": [[{"name": "bore", "center": [0.0, 0.0], "radius": pin_radius + clearance, **circle}]]}},
        ],
        "boundary_conditions": [{"body": "pin", "edge": "hub", "type": "displacement", "value": [0.0, -load_displacement]}]
        + [{"body": "plate", "edge": e, "type": "fixed"} for e in ("bottom", "right", "top", "left")],
        "contacts": [{"bodies": ["pin", "plate"], "type": "frictionless", "point": [0.0, -(pin_radius + clearance)],
                      "contact_normal": "pair"}],
    }
