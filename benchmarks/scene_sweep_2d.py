"""2D contact scenes of the kinds a user writes, drawn at random, run and checked against facts
that do not come from the solver.

    python benchmarks/scene_sweep_2d.py --seed 1 --count 200 --out out/sweep2d

Each scene is a body pressed on another, built only from what docs/scene-reference.md documents:
a cylinder (half disk), a half ellipse, a rounded flat punch (flat, arcs turning into flanks), a
flat punch with rounded corners, or a profile of lines and an arc, on a flat (wide rectangle), a
block, a concave seat (a profile with an arc) or another cylinder; sizes from 1 mm to 1 m;
steel, aluminium, a rubber-like material (nu 0.45) or one body 100 times stiffer; plane strain or
plane stress; tied, frictionless or frictional (mu 0.1-0.5, the tangential load aimed below
mu N); loaded by a displacement or, for tied and frictional contacts on a cylinder, ellipse or
arc profile, by a pressure (frictional: with the tangential displacement given); 3 to 30 cells
across the expected contact. About half the scenes
are turned by a random angle and shifted, and then solved unturned too.

Each run (``ibfem run SCENE.json --out DIR --quiet``, in a child process limited to 2 GB of
address space) is judged on:

- ``exit``: exit 0; 1 is ``not converged`` (``not converged, beta != 0`` for a tied or frictional
  contact whose Dundurs beta is not 0: the shear then changes the pressure), 2 ``refused`` (a scene the generator meant to be
  valid), 5 or any other ``crash``; ``traceback`` if stderr shows one, ``stray warning`` if it
  shows a Python warning; ``unclear error`` when an error line does not name the file;
- ``equilibrium``: the reactions plus the applied pressure's force sum to zero (1e-6 of the
  largest), and the base's reaction along the contact normal is the normal force;
- ``hertz``: a against Hertz's a = sqrt(4 N R* / (pi E*)) for the computed N, where Hertz applies
  (a smooth convex curve on a flat, a cylinder or a seat; a below R / 10 and a fifth of every
  body's depth; tied and frictional contacts only where Dundurs' beta vanishes, |beta| <= 0.01,
  else the shear changes a): within 3 % at 5 or more cells across 2a, (5 / cells)^2 times that
  below, or twice the run's own estimate of its error in a where that is larger (``hertz,
  warned`` where the run warned of its resolution or its estimate on stderr);
- ``turned``: a turned and shifted scene gives its unturned twin's a and force vector (N, Q) to
  0.5 % (of a and of |(N, Q)|) at 5 or more cells across 2a, (5 / cells)^2 times that below;
- ``stick``: frictional, |beta| <= 0.01, not gross slip: c / a within 0.02 plus a cell of
  sqrt(1 - |Q| / (mu N)) (Cattaneo and Mindlin);
- ``slips against its friction``: a frictional run whose final state has 0.2 or more of its slip
  running against the friction traction (``checks.slip_against_traction``: its two ends slip in
  opposite directions, which a proportional run's zones cannot hold), counted ``..., warned``
  where ``ibfem run`` said so on stderr.

The table of failures by check is printed and written to OUT/sweep.json, with every scene file
kept in OUT/scenes. ``--only K`` reruns scene K of the seed; ``--rejudge`` judges the runs kept in
OUT again; ``--ibfem CMD ...`` runs another checkout's ibfem (a before-and-after comparison)."""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

MATERIALS = {
    "steel": (2.0e11, 0.3),
    "aluminium": (7.0e10, 0.33),
    "rubber": (5.0e7, 0.45),
}
INDENTERS = ["cylinder", "ellipse", "rounded_punch", "cornered_punch", "arc_profile"]
COUNTERS = ["flat", "block", "seat", "cylinder"]
MEMORY = 2 * 1024 ** 3
IBFEM = [sys.executable, "-m", "ibfem"]  # --ibfem replaces it (another checkout's runner)


def _turn(v, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [c * v[0] - s * v[1], s * v[0] + c * v[1]]


def _place(p, deg, shift):
    q = _turn(p, deg)
    return [q[0] + shift[0], q[1] + shift[1]]


# ---------------------------------------------------------------------------------------------
# the shapes, drawn in the contact's own frame: contact at the origin, body 1 above, body 2 below
# ---------------------------------------------------------------------------------------------

def _arc_profile(R, half_angle, height, flat=0.0, name="crown"):
    """A profile whose bottom is a flat of half-width ``flat`` (none when 0) with arcs of radius R
    turning ``half_angle`` degrees on each side, straight flanks on up to ``height`` and a top.
    Returns the edges, the loaded edge's name and its length."""
    t = math.radians(half_angle)
    right_end = [flat + R * math.sin(t), R * (1.0 - math.cos(t))]
    left_end = [-right_end[0], right_end[1]]
    # flanks continue the arcs' tangents up to the top
    slope = [math.cos(t), math.sin(t)]
    height = max(height, 2.0 * right_end[1])
    run = (height - right_end[1]) / max(slope[1], 1e-12)
    top_right = [right_end[0] + run * slope[0], height]
    if half_angle >= 89.999:
        top_right = [right_end[0], height]
    top_left = [-top_right[0], height]
    edges = []
    if flat > 0.0:
        edges.append({"name": "flat", "type": "line", "start": [-flat, 0.0], "end": [flat, 0.0]})
    edges.append({"name": f"{name}_right" if flat > 0 else name, "type": "arc", "center": [flat, R], "radius": R,
                  "start_angle": -90.0, "end_angle": -90.0 + half_angle})
    edges += [
        {"name": "flank_right", "type": "line", "start": right_end, "end": top_right},
        {"name": "top", "type": "line", "start": top_right, "end": top_left},
        {"name": "flank_left", "type": "line", "start": top_left, "end": left_end},
    ]
    if flat > 0.0:
        edges.append({"name": f"{name}_left", "type": "arc", "center": [-flat, R], "radius": R,
                      "start_angle": -90.0 - half_angle, "end_angle": -90.0})
    else:
        # one arc through the bottom: replace by a single arc from -90-h to -90+h
        edges[0] = {"name": name, "type": "arc", "center": [0.0, R], "radius": R,
                    "start_angle": -90.0 - half_angle, "end_angle": -90.0 + half_angle}
    return edges, "top", 2.0 * top_right[0], height


def _indenter(rng, kind, R):
    """Body 1's shape, its loaded edge, that edge's length, its radius of curvature at the
    contact (inf for a flat), its height, its half width and the flat's half-width."""
    if kind == "cylinder":
        return ({"type": "half_disk", "center": [0.0, R], "radius": R, "side": "below"},
                "flat", 2 * R, R, R, R, 0.0)
    if kind == "ellipse":
        ax = R * rng.uniform(0.6, 1.6)
        ay = R
        return ({"type": "half_ellipse", "center": [0.0, ay], "semi_axes": [ax, ay], "side": "below"},
                "flat", 2 * ax, ax * ax / ay, ay, ax, 0.0)
    if kind == "arc_profile":
        half = rng.uniform(15.0, 60.0)
        height = R * rng.uniform(0.5, 1.0)
        edges, loaded, length, height = _arc_profile(R, half, height)
        # the arc's own half-width: a seat must not reach past it (the flanks leave the circle)
        return ({"type": "profile", "edges": edges}, loaded, length, R, height, R * math.sin(math.radians(half)), 0.0)
    b = R * rng.uniform(0.05, 0.3)  # the flat's half-width
    if kind == "rounded_punch":
        Rr = R * rng.uniform(2.0, 20.0)
        half = rng.uniform(5.0, 15.0)
        height = R * rng.uniform(0.3, 1.0)
        edges, loaded, length, height = _arc_profile(Rr, half, height, flat=b, name="round")
        return ({"type": "profile", "edges": edges}, loaded, length, math.inf, height, length / 2, b)
    # cornered punch: a flat with corners rounded by r, vertical sides
    r = b * rng.uniform(0.1, 1.0)
    height = R * rng.uniform(0.3, 1.0)
    edges, loaded, length, height = _arc_profile(r, 90.0, height, flat=b, name="corner")
    return ({"type": "profile", "edges": edges}, loaded, length, math.inf, height, length / 2, b)


def _counter(rng, kind, R1, width1):
    """Body 2's shape, its fixed edge, its radius at the contact (inf flat, negative concave),
    its depth and half-width."""
    if kind in ("flat", "block"):
        depth = R1 * rng.uniform(0.8, 3.0)
        half = max(depth if kind == "block" else depth * rng.uniform(2.0, 4.0), 1.5 * width1)
        return ({"type": "rectangle", "min": [-half, -depth], "max": [half, 0.0]}, "bottom", math.inf, depth, half)
    if kind == "cylinder":
        R2 = R1 * rng.uniform(0.5, 3.0)
        return ({"type": "half_disk", "center": [0.0, -R2], "radius": R2, "side": "above"}, "flat", R2, R2, R2)
    # seat: a block whose top is an arc of radius R2 > R1 through the origin
    R2 = R1 * rng.uniform(1.5, 5.0)
    half = R1 * rng.uniform(0.8, 1.2)
    half = min(half, 0.9 * R2, width1)
    depth = R1 * rng.uniform(0.8, 2.0)
    y_side = R2 - math.sqrt(R2 * R2 - half * half)
    a_right = math.degrees(math.atan2(y_side - R2, half))
    a_left = math.degrees(math.atan2(y_side - R2, -half))
    edges = [
        {"name": "bottom", "type": "line", "start": [-half, -depth], "end": [half, -depth]},
        {"name": "right", "type": "line", "start": [half, -depth], "end": [half, y_side]},
        {"name": "seat", "type": "arc", "center": [0.0, R2], "radius": R2, "start_angle": a_right, "end_angle": a_left},
        {"name": "left", "type": "line", "start": [-half, y_side], "end": [-half, -depth]},
    ]
    return {"type": "profile", "edges": edges}, "bottom", -R2, depth, half


def dundurs_beta(E1, nu1, E2, nu2, model) -> float:
    """Dundurs' beta of the pair (Johnson 1985, eq. 5.4, with kappa = 3 - 4 nu in plane strain
    and (3 - nu) / (1 + nu) in plane stress): 0 when normal and shear loads do not couple."""
    k1, k2 = ((3 - nu1) / (1 + nu1), (3 - nu2) / (1 + nu2)) if model == "plane_stress" else (3 - 4 * nu1, 3 - 4 * nu2)
    m1, m2 = E1 / (2 * (1 + nu1)), E2 / (2 * (1 + nu2))
    return (m1 * (k2 - 1) - m2 * (k1 - 1)) / (m1 * (k2 + 1) + m2 * (k1 + 1))


def _effective(E1, nu1, E2, nu2, model):
    if model == "plane_stress":
        return 1.0 / (1.0 / E1 + 1.0 / E2)
    return 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)


def _approach(N, a, E, nu, depth, model):
    """Compression of a body of ``depth`` under a Hertz pressure (N, a): a rough estimate for
    choosing the displacement (Johnson 1985, eq. 5.34 type, the logarithmic term)."""
    if model == "plane_stress":
        return 2 * N / (math.pi * E) * math.asinh(depth / a)
    d = depth
    tail = d / (math.sqrt(a * a + d * d) + d)
    return 2.0 * N / (math.pi * E) * ((1.0 - nu * nu) * math.asinh(d / a) - nu * (1.0 + nu) * tail)


def draw(seed: int, k: int) -> dict:
    """Scene k of the seed: its parameters (``meta``) and the data of the turned scene and of
    the unturned twin (None when not turned)."""
    rng = np.random.default_rng([seed, k])
    model = "plane_stress" if rng.random() < 0.25 else "plane_strain"
    kind1 = str(rng.choice(INDENTERS))
    kind2 = str(rng.choice(COUNTERS if kind1 in ("cylinder", "arc_profile") else ["flat", "block", "cylinder"]))
    R = float(10 ** rng.uniform(-3, 0))
    shape1, loaded, loaded_len, R1, height1, width1, flat = _indenter(rng, kind1, R)
    shape2, fixed, R2, depth2, half2 = _counter(rng, kind2, R, width1)
    pairs = [("steel", "steel"), ("aluminium", "steel"), ("steel", "aluminium"), ("aluminium", "aluminium"),
             ("rubber", "rubber"), ("stiff", "steel"), ("steel", "stiff"), ("stiff", "rubber")]
    mat1, mat2 = pairs[int(rng.integers(len(pairs)))]
    materials = dict(MATERIALS)
    materials["stiff"] = (100 * MATERIALS["steel"][0], 0.3)
    if "rubber" in (mat1, mat2) and "stiff" in (mat1, mat2):
        materials["stiff"] = (100 * MATERIALS["rubber"][0], 0.3)
    (E1, nu1), (E2, nu2) = materials[mat1], materials[mat2]
    Es = _effective(E1, nu1, E2, nu2, model)
    contact_type = str(rng.choice(["frictionless", "tied", "frictional", "frictional"]))
    mu = float(np.round(rng.uniform(0.1, 0.5), 2)) if contact_type == "frictional" else 0.0
    # the expected contact
    curv = (1.0 / R1 if math.isfinite(R1) else 0.0) + (1.0 / R2 if math.isfinite(R2) else 0.0)
    if flat > 0.0:
        arc = shape1["edges"][1]
        Rr, turn_arc = arc["radius"], math.radians(arc["end_angle"] - arc["start_angle"])
        # within the lower part of the arcs (a corner rounded by r turns 90 degrees: the region
        # would climb its flanks)
        a_target = flat + Rr * math.sin(min(turn_arc, math.radians(30.0))) * float(rng.uniform(0.05, 0.6))
        if math.isfinite(R2):  # on a cylinder the region is Hertz's when that is narrower than the flat
            a_target = min(a_target, flat * float(rng.uniform(0.3, 1.0)))
        if a_target > flat:  # Ciavarella, Hills and Monno (1998): the rounded flat punch
            phi0 = math.asin(flat / a_target)
            N_target = Es * a_target ** 2 / (2 * Rr) * (math.pi / 2 - phi0 - math.sin(phi0) * math.cos(phi0))
        else:
            N_target = math.pi * Es * a_target ** 2 / (4 * R2)
    else:
        Rs = 1.0 / curv
        a_target = R * float(10 ** rng.uniform(-2.3, -1.0))
        a_target = min(a_target, 0.2 * min(width1, half2))
        N_target = math.pi * Es * a_target ** 2 / (4 * Rs)
    d = _approach(N_target, a_target, E1, nu1, height1, model) + _approach(N_target, a_target, E2, nu2, depth2, model)
    cells = int(rng.integers(3, 31))  # cells across 2a
    h = 2 * a_target / cells
    sizes = []
    for box in ((loaded_len, height1), (2 * half2, depth2 if kind2 != "cylinder" else R2)):
        side = min(box)
        sizes.append(side / float(rng.uniform(2.5, 10.0)))
    refinement = []
    for e in sizes:
        levels = int(min(12, max(1, math.ceil(math.log2(e / h)))))
        radius = a_target * float(rng.uniform(1.5, 4.0))
        refinement.append([{"levels": levels, "around": "contact", "radius": radius}])
    # the load
    # a pressure on a punch's wide, thin top bends its wings onto the base: loads by force only on
    # the thick indenters
    force = contact_type != "frictionless" and kind1 in ("cylinder", "ellipse", "arc_profile") and rng.random() < 0.4
    tangential = 0.0
    if contact_type == "frictional":
        tangential = float(rng.uniform(0.1, 0.8)) * mu * d * (0.7 if model == "plane_strain" else 0.6)
    elif contact_type == "tied" and not force and rng.random() < 0.5:
        # (held by the tied contact alone, a tangential force at the top would roll the body over)
        tangential = float(rng.uniform(0.0, 0.3)) * d
    turn = float(rng.uniform(0.0, 360.0)) if rng.random() < 0.5 else 0.0
    if force and contact_type == "frictional" and turn:
        turn = float(rng.choice([90.0, 180.0, 270.0]))  # a free component turns only by quarter turns
    shift = [float(rng.uniform(-2, 2) * R), float(rng.uniform(-2, 2) * R)] if turn else [0.0, 0.0]
    give_point = bool(rng.random() < 0.6)
    steps = int(rng.choice([1, 2, 5, 10])) if contact_type != "frictional" else int(rng.choice([5, 10]))
    meta = dict(k=k, seed=seed, model=model, indenter=kind1, counter=kind2, R=R, R1=R1, R2=R2, flat=flat,
                materials=[mat1, mat2], E=[E1, E2], nu=[nu1, nu2], E_star=Es,
                beta=dundurs_beta(E1, nu1, E2, nu2, model), contact=contact_type, mu=mu,
                a_target=a_target, N_target=N_target, approach=d, cells_target=cells, finest=[
                    e / 2 ** z[0]["levels"] for e, z in zip(sizes, refinement)],
                height1=height1, depth2=depth2, width1=width1, half2=half2, force=force, tangential=tangential,
                turn=turn, shift=shift, point=give_point, fixed=fixed, steps=steps, loaded=loaded, loaded_length=loaded_len,
                pressure=N_target / loaded_len if force else 0.0)
    parts = dict(shapes=(shape1, shape2), materials=((mat1, E1, nu1), (mat2, E2, nu2)), sizes=sizes,
                 refinement=refinement, fixed=fixed)
    scene = _scene(meta, parts, turn, shift)
    twin = _scene(meta, parts, 0.0, [0.0, 0.0]) if turn else None
    return {"meta": meta, "scene": scene, "twin": twin}


def _scene(meta, parts, turn, shift) -> dict:
    (mat1, E1, nu1), (mat2, E2, nu2) = parts["materials"]
    materials = [{"name": mat1, "youngs_modulus": E1, "poissons_ratio": nu1}]
    if mat2 != mat1:
        materials.append({"name": mat2, "youngs_modulus": E2, "poissons_ratio": nu2})
    bodies = []
    for name, mat, shape, e, ref in zip(("indenter", "base"), (mat1, mat2), parts["shapes"], parts["sizes"],
                                        parts["refinement"]):
        s = json.loads(json.dumps(shape))
        if turn:
            s["rotate_deg"] = turn
            s["translate"] = shift
        elif shift != [0.0, 0.0]:
            s["translate"] = shift
        bodies.append({"name": name, "material": mat, "element_size": e, "refinement": ref, "shape": s})
    axes = [_turn([1.0, 0.0], turn), _turn([0.0, 1.0], turn)]
    bcs = [{"body": "base", "edge": parts["fixed"], "type": "fixed"}]
    if meta["force"] and meta["contact"] == "tied":  # a tied contact holds the indenter: forces only
        bcs.append({"body": "indenter", "edge": meta["loaded"], "type": "pressure", "value": meta["pressure"]})
        return _assemble(meta, parts, bodies, materials, bcs, turn, shift)
    if meta["force"]:
        quarter = round(turn / 90.0) % 4
        v = [meta["tangential"], "free"]
        if quarter in (1, 3):  # x and y swap: the tangent along y
            v = ["free", meta["tangential"] * (1 if quarter == 1 else -1)]
        elif quarter == 2:
            v = [-meta["tangential"], "free"]
        disp = {"body": "indenter", "edge": meta["loaded"], "type": "displacement", "value": v}
        bcs.append({"body": "indenter", "edge": meta["loaded"], "type": "pressure", "value": meta["pressure"]})
        bcs.insert(0, disp)
        return _assemble(meta, parts, bodies, materials, bcs, turn, shift)
    else:
        disp = {"body": "indenter", "edge": meta["loaded"], "type": "displacement",
                "value": [meta["tangential"], -meta["approach"]]}
    if turn:
        disp["axes"] = axes
    bcs.insert(0, disp)
    return _assemble(meta, parts, bodies, materials, bcs, turn, shift)


def _assemble(meta, parts, bodies, materials, bcs, turn, shift) -> dict:
    contact = {"bodies": ["indenter", "base"], "type": meta["contact"]}
    if meta["contact"] == "frictional":
        contact["friction"] = meta["mu"]
    if meta["point"]:
        contact["point"] = _place([0.0, 0.0], turn, shift)
    return {"name": f"sweep {meta['seed']}/{meta['k']}", "model": meta["model"],
            "solver": {"load_steps": meta["steps"]}, "materials": materials, "bodies": bodies,
            "boundary_conditions": bcs, "contacts": [contact], "output": {"vtk": False, "plots": False}}


# ---------------------------------------------------------------------------------------------
# running and judging
# ---------------------------------------------------------------------------------------------

def _limit():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def run(scene: dict, path: Path, timeout: float) -> dict:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(scene, indent=1))
    out = path.with_suffix("")
    t0 = time.time()
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        p = subprocess.run(IBFEM + ["run", str(path), "--out", str(out), "--quiet"], capture_output=True,
                           text=True, timeout=timeout, preexec_fn=_limit)
        code, err = p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        code, err = "timeout", ""
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = {"code": code, "stderr": err, "wall": time.time() - t0,
           "cpu": (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime), "path": str(path)}
    path.with_name(path.stem + "_run.json").write_text(json.dumps(res))
    return _with_summary(res)


def _with_summary(res: dict) -> dict:
    out = Path(res["path"]).with_suffix("")
    res["summary"] = None
    if (out / "summary.json").exists() and res["code"] in (0, 1):
        res["summary"] = json.loads((out / "summary.json").read_text())
    return res


def recorded(path: Path) -> dict | None:
    """A run's record as ``run`` left it (for --rejudge), None when it was not run."""
    rec = path.with_name(path.stem + "_run.json")
    return _with_summary(json.loads(rec.read_text())) if rec.exists() else None


def _exit_failures(res: dict) -> list[tuple[str, str]]:
    code, err = res["code"], res["stderr"]
    name = Path(res["path"]).name
    found = []
    if "Traceback" in err:
        found.append(("traceback", err.strip().splitlines()[-1][:300]))
    stray = [ln for ln in err.splitlines() if ".py:" in ln and "Warning:" in ln]
    if stray:
        found.append(("stray warning", stray[0][:300]))
    if code == 0:
        return found
    first = (err.strip().splitlines() or [""])[0][:400]
    if code == 1:
        found.append(("not converged", _why_not(res["summary"]) or first))
    elif code == 2:
        lines = [ln for ln in err.strip().splitlines() if ln.startswith("ibfem run: ")
                 and not ln.startswith("ibfem run: warning")]
        found.append(("refused", " | ".join(lines)[:400] or first))
        if not lines or any(not ln.startswith((f"ibfem run: {name}", f"ibfem run: {res['path']}")) for ln in lines):
            found.append(("unclear error", (lines or [first])[0][:300]))
    else:
        found.append(("crash", f"exit {code}: {first}"))
    return found


def _why_not(summary) -> str:
    if not summary:
        return ""
    msgs = []
    for per in summary.get("iterations", {}).get("contacts", []):
        pass
    for w in summary.get("warnings", []) or []:
        msgs.append(str(w)[:200])
    msgs += [str(m)[:200] for m in summary.get("iterations", {}).get("messages", [])]
    return "; ".join(msgs)[:400]


def _rotate_back(v, deg):
    return _turn(v, -deg)


def judge(meta: dict, res: dict, twin: dict | None) -> list[tuple[str, str]]:
    found = _exit_failures(res)
    if twin is not None:
        found += [(c, "twin: " + m) for c, m in _exit_failures(twin)]
    if meta["contact"] != "frictionless" and abs(meta["beta"]) > 0.01:  # normal and shear coupled
        found = [(c + ", beta != 0" if c == "not converged" else c, m) for c, m in found]
    s = res["summary"]
    if res["code"] != 0 or s is None:
        return found
    c = s["contacts"][0]
    a, N, Q = c["half_width"], c["normal_force"], c["tangential_force"]
    # equilibrium: reactions plus the applied pressure
    total = np.zeros(2)
    scale = abs(N)
    for key, f in s["reactions"].items():
        total += np.asarray(f, float)
        scale = max(scale, float(np.linalg.norm(f)))
    if meta["force"]:
        P = meta["pressure"] * meta["loaded_length"]
        applied = np.asarray(_turn([0.0, -P], meta["turn"]))
        total += applied
        scale = max(scale, P)
    if np.linalg.norm(total) > 1e-6 * scale:
        found.append(("equilibrium", f"reactions + load = {total.tolist()} against {scale:.4g}"))
    # the base's reaction balances the contact force
    base = np.asarray(s["reactions"].get(f"base/{meta['fixed']}", [0.0, 0.0]), float)
    frame = np.asarray(c["normal"]), np.asarray(c["tangent"])
    if abs(abs(float(base @ frame[0])) - N) > 1e-4 * max(N, 1e-300):
        found.append(("equilibrium", f"base reaction normal {float(base @ frame[0]):.6g} vs N {N:.6g}"))
    # Hertz
    cells = 2 * c.get("cells_per_half_width", 0.0)
    if _hertz_applies(meta, a):
        Rs = 1.0 / ((1.0 / meta["R1"]) + (1.0 / meta["R2"] if math.isfinite(meta["R2"]) else 0.0))
        a_h = math.sqrt(4 * N * Rs / (math.pi * meta["E_star"]))
        # 3 % from 5 cells across 2a, (5 / cells)^2 times that below; or twice the run's own
        # estimate of its error in a, where that is larger (a coarse run that says so)
        est = float((c.get("estimated_error") or {}).get("half_width") or 0.0)
        tol = max(0.03 * max(1.0, 5.0 / max(cells, 1e-9)) ** 2, 2.0 * est)
        coupled = meta["contact"] != "frictionless" and abs(meta["beta"]) > 0.01  # shear changes a (Spence)
        if not coupled and abs(a / a_h - 1) > tol:
            warned = any(w in res["stderr"] for w in ("barely resolved", "no error estimate", "the estimated error of"))
            found.append(("hertz, warned" if warned else "hertz", f"a {a:.6g} vs Hertz {a_h:.6g} ({100 * (a / a_h - 1):+.2f} %, {cells:.1f} cells)"))
    # Cattaneo-Mindlin
    if (meta["contact"] == "frictional" and abs(meta["beta"]) <= 0.01 and not c.get("gross_slip")
            and N > 0 and abs(Q) < meta["mu"] * N and meta["flat"] == 0.0 and _hertz_applies(meta, a)):
        ratio = math.sqrt(1 - abs(Q) / (meta["mu"] * N))
        got = c["stick_half_width"] / a
        if abs(got - ratio) > 0.02 + 1.0 / max(cells / 2, 1):
            found.append(("stick", f"c/a {got:.4f} vs {ratio:.4f} (Q/muN {abs(Q) / (meta['mu'] * N):.3f})"))
    # Coulomb's slip direction: a final state slipping against its friction traction must say so
    against = (c.get("checks") or {}).get("slip_against_traction")
    if meta["contact"] == "frictional" and isinstance(against, float) and against >= 0.2:
        warned = "runs against their friction traction" in res["stderr"]
        found.append(("slips against its friction, warned" if warned else "slips against its friction",
                      f"{100 * against:.0f} % of the slip against the traction (beta {meta['beta']:+.3f})"))
    # the twin
    if twin is not None and twin["code"] == 0 and twin["summary"]:
        t = twin["summary"]["contacts"][0]
        # 0.5 % from 5 cells across 2a; below, the grid's position moves the ends by a fraction
        # of a cell: (5 / cells)^2 times more
        tol = 0.005 * max(1.0, 5.0 / max(cells, 1e-9)) ** 2
        if abs(a - t["half_width"]) > tol * t["half_width"]:
            found.append(("turned", f"a {a:.6g} vs unturned {t['half_width']:.6g} "
                                    f"({100 * (a / t['half_width'] - 1):+.2f} %, {cells:.1f} cells)"))
        f, g = np.array([N, Q]), np.array([t["normal_force"], t["tangential_force"]])
        if np.linalg.norm(f - g) > tol * np.linalg.norm(g):
            found.append(("turned", f"(N, Q) {N:.6g}, {Q:.6g} vs unturned {g[0]:.6g}, {g[1]:.6g} "
                                    f"({100 * np.linalg.norm(f - g) / np.linalg.norm(g):.2f} % of |F|)"))
    return found


def _hertz_applies(meta, a) -> bool:
    if meta["flat"] > 0.0 or a <= 0.0:
        return False
    radii = [abs(meta["R1"])] + ([abs(meta["R2"])] if math.isfinite(meta["R2"]) else [])
    if meta["indenter"] == "arc_profile":
        radii.append(meta["width1"])
    return a <= 0.1 * min(radii) and 5 * a <= min(meta["height1"], meta["depth2"], meta["half2"])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=100, help="scenes drawn (default 100)")
    ap.add_argument("--first", type=int, default=0, help="first scene index (default 0)")
    ap.add_argument("--only", type=int, nargs="*", help="run only these scene indices")
    ap.add_argument("--out", type=Path, default=Path("out/sweep2d"))
    ap.add_argument("--timeout", type=float, default=300.0, help="wall seconds per run (default 300)")
    ap.add_argument("--no-twins", action="store_true", help="skip the unturned twins")
    ap.add_argument("--rejudge", action="store_true", help="judge the runs recorded in OUT again, without running")
    ap.add_argument("--ibfem", nargs="+", help="the command that runs ibfem (default: this Python's -m ibfem)")
    args = ap.parse_args(argv)
    if args.ibfem:
        IBFEM[:] = args.ibfem
    ks = args.only if args.only else range(args.first, args.first + args.count)
    records = []
    args.out.mkdir(parents=True, exist_ok=True)
    for k in ks:
        case = draw(args.seed, k)
        paths = [args.out / "scenes" / f"s{args.seed}_{k:04d}{tail}.json" for tail in ("", "_twin")]
        if args.rejudge:
            res, twin = recorded(paths[0]), recorded(paths[1])
            if res is None:
                continue
        else:
            res = run(case["scene"], paths[0], args.timeout)
            twin = None
            if case["twin"] is not None and not args.no_twins and res["code"] in (0, 1):
                twin = run(case["twin"], paths[1], args.timeout)
        found = judge(case["meta"], res, twin)
        m = case["meta"]
        c = (res["summary"] or {}).get("contacts", [{}])[0] if res["summary"] else {}
        records.append({"k": k, "meta": m, "code": res["code"], "cpu": res["cpu"], "failures": found,
                        "a": c.get("half_width"), "N": c.get("normal_force"),
                        "cells": 2 * c.get("cells_per_half_width", 0.0) if c else None,
                        "twin_cpu": twin["cpu"] if twin else None})
        tag = "ok" if not found else "; ".join(f"{x}: {y}" for x, y in found)
        print(f"{k:4d} {m['indenter']:>14s} on {m['counter']:<8s} {m['contact']:<12s} {m['model']:<12s} "
              f"turn {m['turn']:6.1f} R {m['R']:.3g} cells {m['cells_target']:2d} exit {res['code']} "
              f"{res['cpu']:.1f}s | {tag}", flush=True)
    table: dict[str, int] = {}
    for r in records:
        for cause in sorted({x for x, _ in r["failures"]}):
            table[cause] = table.get(cause, 0) + 1
    bad = sum(1 for r in records if r["failures"])
    print(f"\n{len(records)} scenes, {bad} with failures")
    for cause, n in sorted(table.items(), key=lambda kv: -kv[1]):
        print(f"  {cause:<14s} {n}")
    (args.out / ("rejudged.json" if args.rejudge else "sweep.json")).write_text(json.dumps({"seed": args.seed, "records": records, "table": table},
                                                    indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
