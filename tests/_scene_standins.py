"""Small stand-ins used by the scene/results/CLI tests: exact straight and circular edges
with the BoundedCurve/Profile interface of docs/architecture.md (only what the scene layer
uses), and a Solution built from a closed-form displacement field. They keep those tests
independent of the geometry package and the solver core, and let the assertions compare
the written files with a known field."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


class Segment:
    def __init__(self, name, start, end):
        self.name, self.start, self.end = name, np.asarray(start, float), np.asarray(end, float)
        self.t_start, self.t_end = 0.0, 1.0

    def evaluate(self, t):
        t = np.atleast_1d(t)[:, None]
        return self.start + t * (self.end - self.start)

    def normal(self, t):
        d = (self.end - self.start) / np.linalg.norm(self.end - self.start)
        return np.broadcast_to(np.array([d[1], -d[0]]), (np.size(t), 2)).copy()


class Arc:
    """Circular arc, angle parameter in radians, counter-clockwise when t_end > t_start."""

    def __init__(self, name, center, radius, a0_deg, a1_deg):
        self.name, self.center, self.radius = name, np.asarray(center, float), float(radius)
        self.t_start, self.t_end = np.radians(a0_deg), np.radians(a1_deg)

    def evaluate(self, t):
        t = np.atleast_1d(t)
        return self.center + self.radius * np.column_stack([np.cos(t), np.sin(t)])

    def normal(self, t):
        t = np.atleast_1d(t)
        s = np.sign(self.t_end - self.t_start)
        tangent = s * np.column_stack([-np.sin(t), np.cos(t)])
        return np.column_stack([tangent[:, 1], -tangent[:, 0]])


class Profile:
    """A closed counter-clockwise loop of the curves above; distances from a dense polyline
    (accurate to ~1e-6 of the size, plenty for the scene checks)."""

    def __init__(self, curves):
        self.edges = {c.name: c for c in curves}
        self.edge_names = tuple(self.edges)
        pts, idx = [], []
        for k, c in enumerate(curves):
            t = np.linspace(c.t_start, c.t_end, 2001)[:-1]
            pts.append(c.evaluate(t))
            idx.append(np.full(len(t), k))
        self._poly, self._idx = np.concatenate(pts), np.concatenate(idx)
        self.bounds = (self._poly.min(axis=0), self._poly.max(axis=0))

    def _closest(self, points):
        p = np.asarray(points, float)
        a, b = self._poly, np.roll(self._poly, -1, axis=0)
        ab = b - a
        s = np.clip(np.einsum("pij,ij->pi", p[:, None, :] - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
        q = a + s[..., None] * ab
        d = np.linalg.norm(p[:, None, :] - q, axis=2)
        k = np.argmin(d, axis=1)
        return q[np.arange(len(p)), k], d[np.arange(len(p)), k], k

    def signed_distance(self, points):
        from matplotlib.path import Path

        p = np.atleast_2d(np.asarray(points, float))
        _, d, _ = self._closest(p)
        inside = Path(self._poly).contains_points(p)
        return np.where(inside, d, -d)

    def contains(self, points):
        return self.signed_distance(points) > 0

    def project(self, points):
        p = np.atleast_2d(np.asarray(points, float))
        q, d, k = self._closest(p)
        a, b = self._poly[k], np.roll(self._poly, -1, axis=0)[k]
        t = (b - a) / np.linalg.norm(b - a, axis=1)[:, None]
        n = np.column_stack([t[:, 1], -t[:, 0]])

        @dataclass
        class P:
            points: np.ndarray
            normals: np.ndarray
            phi: np.ndarray

        return P(q, n, self.signed_distance(p))

    def tessellate(self, chord_tolerance):
        return [(self._poly, self._idx)]


def rectangle(lo, hi, rotate_deg=0.0):
    c = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]], float)
    th = np.radians(rotate_deg)
    R = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    c = c @ R.T
    names = ["bottom", "right", "top", "left"]
    return Profile([Segment(n, c[i], c[(i + 1) % 4]) for i, n in enumerate(names)])


def quarter_annulus(r_in, r_out, rotate_deg=0.0):
    a = rotate_deg
    th = np.radians(a)
    e1, e2 = np.array([np.cos(th), np.sin(th)]), np.array([-np.sin(th), np.cos(th)])
    return Profile(
        [
            Segment("bottom", r_in * e1, r_out * e1),
            Arc("outer", [0, 0], r_out, a, a + 90),
            Segment("left", r_out * e2, r_in * e2),
            Arc("inner", [0, 0], r_in, a + 90, a),
        ]
    )


def disk(center, radius):
    return Profile([Arc("boundary", center, radius, 0, 360)])


def half_disk_below(center, radius):
    c = np.asarray(center, float)
    return Profile([Arc("arc", c, radius, 180, 360), Segment("flat", c + [radius, 0], c - [radius, 0])])


def standin_profile(shape):
    """The scene-format shape dicts these tests use -> stand-in profiles."""
    kind = shape["type"]
    if kind == "rectangle":
        return rectangle(shape["min"], shape["max"], shape.get("rotate_deg", 0.0))
    if kind == "disk":
        return disk(shape["center"], shape["radius"])
    if kind == "half_disk" and shape.get("side") == "below":
        return half_disk_below(shape["center"], shape["radius"])
    if kind == "quarter_annulus":  # test-only shape
        return quarter_annulus(shape["inner"], shape["outer"], shape.get("rotate_deg", 0.0))
    raise ValueError(f"shape: field 'type' = {kind!r} is not one of: rectangle, disk, half_disk")


# ---------------------------------------------------------------------------------------
# a Solution from closed-form fields
# ---------------------------------------------------------------------------------------

E, NU = 2.0e11, 0.3


def plane_strain_stress(strain):
    """[sxx, syy, sxy] from [exx, eyy, gxy] (plane strain, E, NU above), written out."""
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    exx, eyy, gxy = strain[..., 0], strain[..., 1], strain[..., 2]
    return np.stack([(lam + 2 * mu) * exx + lam * eyy, lam * exx + (lam + 2 * mu) * eyy, mu * gxy], axis=-1)


@dataclass
class FieldBody:
    """A rectangle [lo, hi] carrying the field u = (a x^2 + c, b x y + d) (per body constants)."""

    name: str
    lo: tuple
    hi: tuple
    a: float
    b: float
    c: float = 0.0
    d: float = 0.0
    cells: tuple = (4, 2)

    def contains(self, x):
        return (x[:, 0] >= self.lo[0]) & (x[:, 0] <= self.hi[0]) & (x[:, 1] >= self.lo[1]) & (x[:, 1] <= self.hi[1])

    def displacement(self, x):
        return np.column_stack([self.a * x[:, 0] ** 2 + self.c, self.b * x[:, 0] * x[:, 1] + self.d])

    def strain(self, x):
        return np.column_stack([2 * self.a * x[:, 0], self.b * x[:, 0], self.b * x[:, 1]])

    def stress(self, x):
        return plane_strain_stress(self.strain(x))


@dataclass
class FieldSolution:
    """Satisfies solver.model.problem.Solution with the closed-form fields of FieldBody."""

    bodies: list
    converged: bool = True
    reactions: dict = field(default_factory=dict)
    iterations: dict = field(default_factory=lambda: {"total": 3, "per_step": [1, 2]})
    timings: dict = field(default_factory=lambda: {"total_s": 0.25, "assembly_s": 0.1})
    contacts: list = field(default_factory=list)

    @property
    def body_info(self):
        return {
            b.name: {"elements": b.cells[0] * b.cells[1], "dofs": 2 * (b.cells[0] + 1) * (b.cells[1] + 1),
                     "element_size": 0.25, "min_element_size": 0.125}
            for b in self.bodies
        }

    def _select(self, x, body):
        x = np.asarray(x, float).reshape(-1, 2)
        if body is None:
            return x, [(b, self.bodies.index(b)) for b in self.bodies]
        return x, [(b, i) for i, b in enumerate(self.bodies) if b.name == body]

    def body_at(self, points):
        x = np.asarray(points, float).reshape(-1, 2)
        out = np.full(len(x), -1)
        for i, b in enumerate(self.bodies):
            out[(out < 0) & b.contains(x)] = i
        return out

    def _eval(self, x, body, what, width):
        x, bodies = self._select(x, body)
        out = np.full((len(x), width), np.nan)
        for b, _ in bodies:
            sel = b.contains(x) & np.isnan(out[:, 0])
            out[sel] = getattr(b, what)(x[sel]).reshape(-1, width)
        return out

    def displacement(self, points, body=None):
        return self._eval(points, body, "displacement", 2)

    def stress(self, points, body=None):
        return self._eval(points, body, "stress", 3)

    def von_mises(self, points, body=None):
        s = self.stress(points, body)
        szz = NU * (s[:, 0] + s[:, 1])
        return np.sqrt(0.5 * ((s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - szz) ** 2 + (szz - s[:, 0]) ** 2) + 3 * s[:, 2] ** 2)

    def mesh(self, body):
        b = next(b for b in self.bodies if b.name == body)
        nx, ny = b.cells
        gx, gy = np.meshgrid(np.linspace(b.lo[0], b.hi[0], nx + 1), np.linspace(b.lo[1], b.hi[1], ny + 1))
        nodes = np.column_stack([gx.ravel(), gy.ravel()])
        i, j = np.meshgrid(np.arange(nx), np.arange(ny))
        n0 = (j * (nx + 1) + i).ravel()
        cells = np.column_stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1])
        centres = nodes[cells].mean(axis=1)
        return {"nodes": nodes, "cells": cells, "displacement": b.displacement(nodes),
                "cell_stress": b.stress(centres), "cell_inside_fraction": np.ones(len(cells))}
