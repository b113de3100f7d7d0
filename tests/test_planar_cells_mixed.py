"""The planar model's early rejection (solver.fem.planar_cells._mixed_pieces): a cube where one
piece of the planes' arrangement holds sample centres of both signs is dropped before its pieces
are integrated. It must only drop cubes the model's own checks reject, and it must catch the
cubes where a curved face meets a planar one (a turned half ball's rim)."""

import numpy as np

from ibfem.geometry.solids import solid_from_dict
from ibfem.solver.fem import planar_cells as pc
from ibfem.solver.fem.cut_cells3d import CUT, PLANAR_SAMPLES, classify_cells

HALF_BALL = {"type": "revolution", "axis_origin": [0, 0, 1], "axis": [0, 0, 1], "angle_deg": 90,
             "profile": {"type": "profile", "edges": [
                 {"type": "line", "start": [0, 0], "end": [1, 0], "name": "flat"},
                 {"type": "arc", "center": [0, 0], "radius": 1, "start_angle": 0, "end_angle": -90, "name": "dome"},
                 {"type": "line", "start": [0, -1], "end": [0, 0], "name": "axis"}]}}


def test_dropped_cubes_fail_the_models_checks_and_the_rim_is_dropped():
    solid = solid_from_dict(HALF_BALL)
    h = 0.0625
    g = np.arange(-h, 1.0 + h, h) + 0.011  # off the solid's planes: cubes straddle them
    lower = np.stack(np.meshgrid(g, g, g + 0.0, indexing="ij"), -1).reshape(-1, 3)
    size = np.full(len(lower), h)
    cut = classify_cells(lower, size, solid.signed_distance) == CUT
    lower, size = lower[cut], size[cut]
    q = len(size)
    scale, lo, width = 0.5 * size, np.full((q, 3), -1.0), np.full(q, 2.0)
    lattice = np.linspace(-0.25, 1.25, PLANAR_SAMPLES)  # the solver's lattice
    pts, phi, normal, offset, count = pc._local_planes(solid.signed_distance, lower, scale, lo, width, lattice)
    some = (count >= 1) & (count <= pc.MAX_PLANES)
    s = np.flatnonzero(some)
    mixed = pc._mixed_pieces(pts[s, :, 0], phi[s, :, 0], normal[s], offset[s], lower[s], scale[s], lo[s], width[s])
    _, ok = pc._arrangement_moments(solid.signed_distance, pts[s], phi[s], normal[s], offset[s], count[s], lower[s],
                                    scale[s], lo[s], width[s])
    assert not (mixed & ok).any()  # sound: every dropped cube fails the full checks
    rim = np.abs(np.hypot(lower[s, 0] + 0.5 * h, lower[s, 1] + 0.5 * h) - 1.0) < 0.5 * h
    rim &= np.abs(lower[s, 2] + 0.5 * h - 1.0) < 0.5 * h
    assert rim.sum() >= 20 and mixed[rim].all()  # the rim's cubes are dropped early
    assert ok.sum() >= 1000  # cubes of the planes alone (the flat top, the two cut planes) keep the model
