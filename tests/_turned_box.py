"""A box [0, L] turned by a rotation R and shifted (test-local, independent of geometry.solids):
exact signed distance, faces x0, x1, y0, y1, z0, z1 with their parameter panels and exact map,
for the 3D patch tests."""

import numpy as np


def rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


class BoxFace:
    def __init__(self, box, axis, side):
        self.box, self.axis, self.side = box, axis, side
        self.u, self.v = [k for k in range(3) if k != axis]

    def panels(self, resolution):
        L = self.box.size
        nu, nv = (max(1, int(np.ceil(L[k] / resolution))) for k in (self.u, self.v))
        eu, ev = np.linspace(0, L[self.u], nu + 1), np.linspace(0, L[self.v], nv + 1)
        u0, v0 = np.meshgrid(eu[:-1], ev[:-1], indexing="ij")
        u1, v1 = np.meshgrid(eu[1:], ev[1:], indexing="ij")
        return np.column_stack([u0.ravel(), v0.ravel()]), np.column_stack([u1.ravel(), v1.ravel()])

    def evaluate(self, uv):
        x = np.zeros((len(uv), 3))
        x[:, self.u], x[:, self.v] = uv[:, 0], uv[:, 1]
        x[:, self.axis] = self.side * self.box.size[self.axis]
        n = np.zeros(3)
        n[self.axis] = 1.0 if self.side else -1.0
        return self.box.to_world(x), np.broadcast_to(self.box.rotation @ n, (len(uv), 3)).copy(), np.ones(len(uv))

    def quadrature(self, resolution):
        lo, hi = self.panels(resolution)
        x, w = np.polynomial.legendre.leggauss(3)
        uu = lo[:, None, None, 0] + 0.5 * (hi - lo)[:, None, None, 0] * (x[None, :, None] + 1)
        vv = lo[:, None, None, 1] + 0.5 * (hi - lo)[:, None, None, 1] * (x[None, None, :] + 1)
        uv = np.stack(np.broadcast_arrays(uu, vv), axis=-1).reshape(-1, 2)
        wt = (0.25 * np.prod(hi - lo, axis=1)[:, None, None] * w[None, :, None] * w[None, None, :]).ravel()
        p, n, _ = self.evaluate(uv)
        return p, wt, n


class TurnedBox:
    def __init__(self, size, rotation_matrix=np.eye(3), shift=(0.0, 0.0, 0.0)):
        self.size = np.asarray(size, float)
        self.rotation = np.asarray(rotation_matrix, float)
        self.shift = np.asarray(shift, float)
        self.faces = {f"{'xyz'[k]}{s}": BoxFace(self, k, s) for k in range(3) for s in (0, 1)}

    def to_world(self, x):
        return x @ self.rotation.T + self.shift

    def to_local(self, p):
        return (np.asarray(p, float) - self.shift) @ self.rotation

    def signed_distance(self, p):
        x = self.to_local(p)
        d = np.minimum(x, self.size - x)
        inside = d.min(axis=1)
        return np.where(inside >= 0, inside, -np.linalg.norm(np.maximum(-d, 0.0), axis=1))

    @property
    def bounds(self):
        c = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)]) * self.size
        w = self.to_world(c)
        return w.min(axis=0), w.max(axis=0)


def uniform_stress_box(rng, youngs_modulus, poissons_ratio, h=0.25):
    """The 3D patch test's problem: a box 1 x 0.8 x 0.6 turned at random (``rng``) under a
    uniform stress sigma = R diag(1e8, -0.5e8, 0.3e8) R^T, sliding on the faces through one
    corner, loaded by the tractions sigma n on the others, cell size ``h``. Returns (problem,
    box, sigma)."""
    from ibfem.solver.model import problem as pb

    rot = rotation(rng.normal(size=3), rng.uniform(0, np.pi))
    box = TurnedBox([1.0, 0.8, 0.6], rot, rng.uniform(-0.05, 0.05, 3))
    sigma = rot @ np.diag([1.0e8, -0.5e8, 0.3e8]) @ rot.T
    bcs = [pb.Sliding("box", f) for f in ("x0", "y0", "z0")]
    bcs += [pb.Traction("box", f"{'xyz'[k]}1", tuple(sigma @ rot[:, k])) for k in range(3)]
    material = pb.Material("m", youngs_modulus, poissons_ratio)
    return pb.Problem("patch", "solid", 1.0, (pb.BodyModel("box", box, material, h),), tuple(bcs)), box, sigma
