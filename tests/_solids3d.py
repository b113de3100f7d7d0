"""Test-local exact solids (independent of geometry.solids): a ball and a half ball with their
faces' parameter panels and exact maps."""

import numpy as np


class SphereFace:
    """The sphere's surface for polar angles [theta0, theta1] (theta from +z... measured from the
    pole -z: the bottom first), parameters (theta, phi)."""

    def __init__(self, centre, radius, theta_range=(0.0, np.pi), sign=1.0, phi_range=(0.0, 2 * np.pi)):
        self.c, self.r, self.range, self.sign = np.asarray(centre, float), float(radius), theta_range, sign
        self.phi = phi_range

    def panels(self, resolution):
        t0, t1 = self.range
        f0, f1 = self.phi
        nt = max(2, int(np.ceil((t1 - t0) * self.r / resolution)))
        nphi = max(4, int(np.ceil((f1 - f0) * self.r / resolution)))
        t, p = np.linspace(t0, t1, nt + 1), np.linspace(f0, f1, nphi + 1)
        a0, b0 = np.meshgrid(t[:-1], p[:-1], indexing="ij")
        a1, b1 = np.meshgrid(t[1:], p[1:], indexing="ij")
        return np.column_stack([a0.ravel(), b0.ravel()]), np.column_stack([a1.ravel(), b1.ravel()])

    def evaluate(self, uv):
        t, p = uv[:, 0], uv[:, 1]
        d = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), -np.cos(t)], axis=1)
        return self.c + self.r * d, self.sign * d, self.r**2 * np.sin(t)


class DiscFace:
    """A flat disc z = const of radius r about (cx, cy), normal +z or -z, parameters (rho, phi)."""

    def __init__(self, centre, radius, up=True, phi_range=(0.0, 2 * np.pi)):
        self.c, self.r, self.up, self.phi = np.asarray(centre, float), float(radius), up, phi_range

    def panels(self, resolution):
        f0, f1 = self.phi
        nr = max(2, int(np.ceil(self.r / resolution)))
        nphi = max(4, int(np.ceil((f1 - f0) * self.r / resolution)))
        r, p = np.linspace(0, self.r, nr + 1), np.linspace(f0, f1, nphi + 1)
        a0, b0 = np.meshgrid(r[:-1], p[:-1], indexing="ij")
        a1, b1 = np.meshgrid(r[1:], p[1:], indexing="ij")
        return np.column_stack([a0.ravel(), b0.ravel()]), np.column_stack([a1.ravel(), b1.ravel()])

    def evaluate(self, uv):
        r, p = uv[:, 0], uv[:, 1]
        x = self.c + np.stack([r * np.cos(p), r * np.sin(p), np.zeros_like(r)], axis=1)
        n = np.broadcast_to([0.0, 0.0, 1.0 if self.up else -1.0], x.shape).copy()
        return x, n, r


class HalfBall:
    """The lower half of a ball (z <= centre z): faces "dome" and "flat" (the top disc)."""

    def __init__(self, centre, radius):
        self.c, self.r = np.asarray(centre, float), float(radius)
        self.faces = {"dome": SphereFace(self.c, self.r, (0.0, np.pi / 2)), "flat": DiscFace(self.c, self.r, up=True)}

    def signed_distance(self, p):
        d = np.asarray(p, float) - self.c
        rho = np.linalg.norm(d, axis=1)
        sphere = self.r - rho
        plane = -d[:, 2]  # inside: below the centre
        inside = np.minimum(sphere, plane)
        # outside above the flat: distance to the disc; outside the sphere below: to the sphere
        radial = np.hypot(d[:, 0], d[:, 1])
        above = d[:, 2] > 0
        to_disc = np.where(radial <= self.r, d[:, 2], np.hypot(radial - self.r, d[:, 2]))
        outside = np.where(above, -to_disc, sphere)
        return np.where((sphere >= 0) & (plane >= 0), inside, np.minimum(outside, 0.0) if False else outside)

    @property
    def bounds(self):
        return self.c - self.r, self.c + np.array([self.r, self.r, 0.0])


class QuarterDiscSide:
    """A symmetry face of a quarter half-ball: the quarter disc {w >= 0, z <= 0, w^2 + z^2 <= R^2}
    in the plane x_axis = centre (w the other horizontal axis), outward normal -e_axis."""

    def __init__(self, centre, radius, axis):
        self.c, self.r, self.axis = np.asarray(centre, float), float(radius), axis
        self.other = 1 - axis

    def panels(self, resolution):
        nr = max(2, int(np.ceil(self.r / resolution)))
        nt = max(2, int(np.ceil(0.5 * np.pi * self.r / resolution)))
        r, t = np.linspace(0, self.r, nr + 1), np.linspace(0, 0.5 * np.pi, nt + 1)
        a0, b0 = np.meshgrid(r[:-1], t[:-1], indexing="ij")
        a1, b1 = np.meshgrid(r[1:], t[1:], indexing="ij")
        return np.column_stack([a0.ravel(), b0.ravel()]), np.column_stack([a1.ravel(), b1.ravel()])

    def evaluate(self, uv):
        r, t = uv[:, 0], uv[:, 1]
        x = np.tile(self.c, (len(r), 1))
        x[:, self.other] += r * np.cos(t)
        x[:, 2] -= r * np.sin(t)
        n = np.zeros((len(r), 3))
        n[:, self.axis] = -1.0
        return x, n, r


class QuarterHalfBall(HalfBall):
    """The half ball's quarter x >= cx, y >= cy: faces dome, flat, sym_x (x = cx), sym_y (y = cy)."""

    def __init__(self, centre, radius):
        super().__init__(centre, radius)
        q = (0.0, 0.5 * np.pi)
        self.faces = {"dome": SphereFace(self.c, self.r, (0.0, np.pi / 2), phi_range=q),
                      "flat": DiscFace(self.c, self.r, up=True, phi_range=q),
                      "sym_x": QuarterDiscSide(self.c, self.r, 0), "sym_y": QuarterDiscSide(self.c, self.r, 1)}

    def signed_distance(self, p):
        """Exact inside; outside, the larger of the distances to the half ball and to the
        quadrant (a lower bound of the true one: safe for classifying cells)."""
        p = np.asarray(p, float)
        d = p - self.c
        whole = super().signed_distance(p)
        inside = (whole >= 0) & (d[:, 0] >= 0) & (d[:, 1] >= 0)
        quadrant = np.hypot(np.minimum(d[:, 0], 0.0), np.minimum(d[:, 1], 0.0))
        outside = -np.maximum(quadrant, np.maximum(-whole, 0.0))
        return np.where(inside, np.minimum(whole, np.minimum(d[:, 0], d[:, 1])), outside)

    @property
    def bounds(self):
        return self.c - np.array([0.0, 0.0, self.r]), self.c + np.array([self.r, self.r, 0.0])
