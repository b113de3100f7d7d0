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
        {"name": "round_left", "type": "arc", "center": [-b, radius], "radius": radius,
         "start_angle": -90.0 - EDGE_TURN, "end_angle": -90.0},
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
        "name": (f"{'one-sharp' if one_sharp else 'sharp' if sharp else 'rounded'} flat punch on a block"
                 f"{' (half model)' if half else ''}"),
        "model": "plane_strain", "thickness": 1.0, "solver": {"load_steps": 1},
        "materials": [{"name": "steel", "youngs_modulus": E, "poissons_ratio": NU},
                      {"name": "punch", "youngs_modulus": punch_modulus, "poissons_ratio": NU}],
        "bodies": [
            {"name": "punch", "material": "punch", "element_size": punch_size,
             "refinement": ([{"levels": punch_levels, "around": "contact", "radius": radius}] if cornered
                            else refinement),
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


def filleted_punch_step(path, thickness: float = 0.02) -> None:
    """Write a STEP file (millimetres) of the punch of punch_on_block made as CAD makes it: a
    trapezoid (the flat meets the flanks at sharp corners, turning EDGE_TURN degrees) whose two
    lower corners are rounded by OpenCascade's 2D fillet of radius EDGE_RADIUS (the fillet's
    tangent points lie R tan(turn / 2) from the corner: on the flat at +-HALF_FLAT), and of the
    block; both extruded by ``thickness``, the solids named "punch" and "block"."""
    import re
    from pathlib import Path

    from OCP.BRep import BRep_Builder, BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet2d
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakePrism
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.Interface import Interface_Static
    from OCP.Message import Message, Message_Gravity
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TopAbs import TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS, TopoDS_Compound

    mm, th = 1000.0, math.radians(EDGE_TURN)
    b, radius, height = HALF_FLAT * mm, EDGE_RADIUS * mm, PUNCH_HEIGHT * mm
    corner = b + radius * math.tan(th / 2.0)
    top = corner + height / math.tan(th)
    polygon = BRepBuilderAPI_MakePolygon()
    for x, y in ((-corner, 0.0), (corner, 0.0), (top, height), (-top, height)):
        polygon.Add(gp_Pnt(x, y, 0.0))
    polygon.Close()
    face = BRepBuilderAPI_MakeFace(polygon.Wire(), True).Face()
    fillet = BRepFilletAPI_MakeFillet2d(face)
    explorer, done = TopExp_Explorer(face, TopAbs_VERTEX), set()
    while explorer.More():
        to_vertex = TopoDS.Vertex_s if hasattr(TopoDS, "Vertex_s") else TopoDS.Vertex
        vertex = to_vertex(explorer.Current())
        p = BRep_Tool.Pnt_s(vertex)
        if abs(p.Y()) < 1e-9 and round(p.X(), 6) not in done:
            done.add(round(p.X(), 6))
            fillet.AddFillet(vertex, radius)
        explorer.Next()
    fillet.Build()
    depth = thickness * mm
    punch = BRepPrimAPI_MakePrism(fillet.Shape(), gp_Vec(0.0, 0.0, depth)).Shape()
    block = BRepPrimAPI_MakeBox(gp_Pnt(-600.0, -600.0, 0.0), gp_Pnt(600.0, 0.0, depth)).Shape()
    compound, builder = TopoDS_Compound(), BRep_Builder()
    builder.MakeCompound(compound)
    builder.Add(compound, punch)
    builder.Add(compound, block)
    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)
    writer = STEPControl_Writer()
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    writer.Transfer(compound, STEPControl_AsIs)
    writer.Write(str(path))
    text = Path(path).read_text()
    for k, name in enumerate(("punch", "block"), 1):  # the products of the solids, in order
        text = re.sub(rf"PRODUCT\('[^']*translator[^']* 1\.{k}',\s*'[^']*'", f"PRODUCT('{name}','{name}'", text)
    Path(path).write_text(text)


def tilted_punch(approach: float, tilt: float, levels: int = 7, point: str = "corner", punch_modulus: float = 1000 * E,
                 height: float = 0.02) -> dict:
    """A sharp flat punch (half-width HALF_FLAT, ``height`` tall, ``punch_modulus``: stiff against
    the block, and short, so that it barely bends under the eccentric load) turned by ``tilt`` rad
    clockwise about its right corner, which touches the block's top (y = 0) first (the left corner
    is ``2 HALF_FLAT sin(tilt)`` above it); moved down by ``approach`` without rotation. ``point``:
    the contact point at the touching corner ("corner"), beside the other corner ("far", a quarter
    cell inside the flat), or found as the bodies' closest points ("none")."""
    scene = punch_on_block(approach, levels=levels, sharp=True, punch_modulus=punch_modulus)
    b, c, s = HALF_FLAT, math.cos(tilt), math.sin(tilt)

    def turned(p):  # clockwise about the right corner (b, 0)
        x, y = p[0] - b, p[1]
        return [b + c * x + s * y, -s * x + c * y]

    for e in scene["bodies"][0]["shape"]["edges"]:
        e["start"], e["end"] = turned([e["start"][0], min(e["start"][1], height)]), turned([e["end"][0], min(e["end"][1], height)])
    finest = 0.04 / 2**levels
    if point == "none":
        del scene["contacts"][0]["point"]
    else:
        scene["contacts"][0]["point"] = turned([b, 0.0] if point == "corner" else [-b + 0.25 * finest, 0.0])
    scene["name"] = "tilted flat punch on a block"
    return scene
