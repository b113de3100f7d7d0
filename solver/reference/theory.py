"""Analytical references for 2D (line) contact: Hertz, Cattaneo-Mindlin and McEwen.

Pure numpy, vectorised over points; every function validates its scalar inputs and raises a
``ValueError`` naming the argument. Sign conventions (used throughout):

* pressure ``p`` is compression positive; stresses are tension positive;
* the half-space occupies ``z >= 0`` (``z`` is the depth below the contact point, measured
  along the inward normal of the lower body), ``x`` runs along the contact tangent;
* the tangential traction ``q(x)`` is the x-component of the traction *applied to* the
  half-space's surface, so on the surface ``szz(x, 0) = -p(x)`` and ``sxz(x, 0) = -q(x)``
  (the surface's outward normal is -z).

Sources (formulas only; numbers quoted are the published ones):

* K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985: ch. 2 (Flamant line
  loads, eqs. 2.15-2.16), ch. 4 section 4.2 (2D Hertz contact of cylinders: half-width, pressure,
  the subsurface field and its on-axis values), ch. 7 section 7.1 (tangential loading of
  cylinders: McEwen's field, the Cattaneo-Mindlin line contact).
* E. McEwen, "Stresses in elastic cylinders in contact along a generatrix (including the effect
  of tangential friction)", Phil. Mag. 40 (1949) 454-459: closed-form field for a Hertz
  pressure plus a proportional tangential traction q = f p, in terms of the functions m, n.
* C. Cattaneo (1938), R. D. Mindlin (1949): the stick/slip solution; thesis eqs. 2-25 to 2-29.
* The thesis (J. Dews-Flick, MSc thesis, University of Florida, 2022), eqs. 2-19 to 2-23 (Hertz) and 6-1/6-2 (ellipse
  curvature; eq. 6-1 there is misprinted with sin^2 twice, the correct form is used here).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "exact_sphere_radius",
    "effective_modulus",
    "plane_strain_modulus",
    "effective_radius",
    "ellipse_radius_of_curvature",
    "hertz_half_width",
    "hertz_peak_pressure",
    "hertz_pressure",
    "load_for_half_width",
    "cattaneo_mindlin_stick_ratio",
    "cattaneo_mindlin_shear",
    "partial_slip_tractions",
    "mcewen_stress",
    "cattaneo_mindlin_stress",
    "von_mises_plane_strain",
    "max_shear_stress",
    "axis_peak",
    "field_peak",
    "axis_compression",
    "approach_estimate",
    "load_for_approach",
    "lame_sphere", "goodier_concentration", "hertz_sphere_radius", "hertz_sphere_peak_pressure", "hertz_sphere_pressure", "mindlin_sphere_stick_ratio", "hertz_elliptic_contact",
]


# --------------------------------------------------------------------------- validation helpers


def _positive(name: str, value) -> float:
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def _poisson(name: str, value) -> float:
    v = float(value)
    if not (-1.0 < v < 0.5):
        raise ValueError(f"{name} must lie in (-1, 0.5), got {value!r}")
    return v


def _non_negative(name: str, value) -> float:
    v = float(value)
    if not math.isfinite(v) or v < 0.0:
        raise ValueError(f"{name} must be a non-negative finite number, got {value!r}")
    return v


# --------------------------------------------------------------------------- composite values


def plane_strain_modulus(youngs_modulus: float, poissons_ratio: float) -> float:
    """E' = E / (1 - nu^2), the modulus of one body in plane strain."""
    E = _positive("youngs_modulus", youngs_modulus)
    nu = _poisson("poissons_ratio", poissons_ratio)
    return E / (1.0 - nu * nu)


def effective_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Contact modulus E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (thesis eq. 2-21,
    Johnson section 4.2 for line contact in plane strain). Steel on steel (2e11, 0.3): 1.0989e11."""
    return 1.0 / (1.0 / plane_strain_modulus(E1, nu1) + 1.0 / plane_strain_modulus(E2, nu2))


def effective_radius(R1: float, R2: float = math.inf) -> float:
    """Composite radius R* with 1/R* = 1/R1 + 1/R2 (thesis eq. 2-22). A flat is ``inf``, a
    concave surface has a negative radius; the pair must be non-conforming (1/R* > 0)."""
    curvatures = []
    for name, R in (("R1", R1), ("R2", R2)):
        r = float(R)
        if r == 0.0 or math.isnan(r):
            raise ValueError(f"{name} must be a non-zero radius (inf for a flat), got {R!r}")
        curvatures.append(0.0 if math.isinf(r) else 1.0 / r)
    k = curvatures[0] + curvatures[1]
    if k <= 0.0:
        raise ValueError(
            f"R1={R1!r}, R2={R2!r}: the surfaces are conforming or diverging (1/R1 + 1/R2 = {k!r}"
            " <= 0); Hertz line contact needs 1/R1 + 1/R2 > 0"
        )
    return 1.0 / k


def ellipse_radius_of_curvature(semi_axis_x: float, semi_axis_y: float, theta) -> np.ndarray:
    """Radius of curvature of the ellipse (ax cos t, ay sin t) at parametric angle ``theta``
    (radians): R = (ax^2 sin^2 t + ay^2 cos^2 t)^(3/2) / (ax ay) (thesis eqs. 6-1, 6-2 with
    the misprint corrected). At t = +-pi/2 (the ends of the y semi-axis) R = ax^2 / ay."""
    ax = _positive("semi_axis_x", semi_axis_x)
    ay = _positive("semi_axis_y", semi_axis_y)
    t = np.asarray(theta, dtype=float)
    return (ax**2 * np.sin(t) ** 2 + ay**2 * np.cos(t) ** 2) ** 1.5 / (ax * ay)


# --------------------------------------------------------------------------- Hertz line contact


def hertz_half_width(N: float, R_eff: float, E_eff: float) -> float:
    """Half-width a = sqrt(4 N R* / (pi E*)) (thesis eq. 2-23, Johnson eq. 4.43);
    N is the normal force per unit length (N/m)."""
    N = _non_negative("N", N)
    R = _positive("R_eff", R_eff)
    E = _positive("E_eff", E_eff)
    return math.sqrt(4.0 * N * R / (math.pi * E))


def load_for_half_width(a: float, R_eff: float, E_eff: float) -> float:
    """Inverse of :func:`hertz_half_width`: N = pi E* a^2 / (4 R*)."""
    a = _non_negative("a", a)
    R = _positive("R_eff", R_eff)
    E = _positive("E_eff", E_eff)
    return math.pi * E * a * a / (4.0 * R)


def hertz_peak_pressure(N: float, a: float) -> float:
    """Peak pressure p0 = 2 N / (pi a) (thesis eq. 2-20)."""
    N = _non_negative("N", N)
    a = _positive("a", a)
    return 2.0 * N / (math.pi * a)


def hertz_pressure(x, a: float, p0: float) -> np.ndarray:
    """p(x) = p0 sqrt(1 - x^2/a^2) inside |x| < a, 0 outside (compression positive)."""
    a = _positive("a", a)
    p0 = _non_negative("p0", p0)
    xi = np.asarray(x, dtype=float) / a
    return p0 * np.sqrt(np.clip(1.0 - xi * xi, 0.0, None))


# --------------------------------------------------------------------------- Cattaneo-Mindlin


def cattaneo_mindlin_stick_ratio(Q, N, mu: float, allow_gross_slip: bool = False):
    """c/a = sqrt(1 - |Q| / (mu N)) (thesis eq. 2-29, Johnson section 7.1 for cylinders).

    Gross slip (|Q| >= mu N) raises ``ValueError`` unless ``allow_gross_slip``, in which case
    c/a = 0 is returned there. Scalars in, float out; arrays broadcast."""
    mu = _positive("mu", mu)
    Q_arr = np.asarray(Q, dtype=float)
    N_arr = np.asarray(N, dtype=float)
    if np.any(~np.isfinite(N_arr)) or np.any(N_arr <= 0.0):
        raise ValueError(f"N must be positive and finite, got {N!r}")
    if np.any(~np.isfinite(Q_arr)):
        raise ValueError(f"Q must be finite, got {Q!r}")
    ratio = np.abs(Q_arr) / (mu * N_arr)
    if not allow_gross_slip and np.any(ratio >= 1.0):
        raise ValueError(
            f"gross slip: |Q|/(mu N) = {np.max(ratio):.6g} >= 1 (Q={Q!r}, N={N!r}, mu={mu!r}); "
            "no stick zone exists"
        )
    c_over_a = np.sqrt(np.clip(1.0 - ratio, 0.0, None))
    return float(c_over_a) if c_over_a.ndim == 0 else c_over_a


def cattaneo_mindlin_shear(x, a: float, c: float, mu: float, p0: float, sign: float = 1.0):
    """Tangential traction of the Cattaneo-Mindlin line contact (thesis eqs. 2-25, 2-26):

    q(x) = sign mu p0 [sqrt(1 - x^2/a^2) - (c/a) sqrt(1 - x^2/c^2)]  for |x| < c (stick),
    q(x) = sign mu p0 sqrt(1 - x^2/a^2)                                for c <= |x| < a (slip),
    0 outside; ``sign`` is the sign of the transmitted tangential force Q. Integrates to
    Q = sign mu p0 pi (a^2 - c^2) / (2 a) (thesis eq. 2-28)."""
    a = _positive("a", a)
    c = _non_negative("c", c)
    if c > a:
        raise ValueError(f"c must not exceed a, got c={c!r} > a={a!r}")
    mu = _non_negative("mu", mu)
    p0 = _non_negative("p0", p0)
    s = float(np.sign(sign))
    if s == 0.0:
        raise ValueError(f"sign must be non-zero, got {sign!r}")
    x = np.asarray(x, dtype=float)
    q = np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None))
    if c > 0.0:
        q = q - (c / a) * np.sqrt(np.clip(1.0 - (x / c) ** 2, 0.0, None))
    return s * mu * p0 * q


def partial_slip_tractions(x, N: float, Q: float, mu: float, R_eff: float, E_eff: float):
    """Hertz pressure and Cattaneo-Mindlin shear for transmitted forces N and Q.

    Returns ``(p, q, a, c)``: p(x), q(x) (signed by Q), the half-width and the stick half-width.
    Raises ``ValueError`` on gross slip."""
    a = hertz_half_width(N, R_eff, E_eff)
    p0 = hertz_peak_pressure(N, a)
    if Q == 0.0:
        x = np.asarray(x, dtype=float)
        return hertz_pressure(x, a, p0), np.zeros_like(x), a, a
    c = a * cattaneo_mindlin_stick_ratio(Q, N, mu)
    return hertz_pressure(x, a, p0), cattaneo_mindlin_shear(x, a, c, mu, p0, np.sign(Q)), a, c


# --------------------------------------------------------------------------- McEwen's field


def mcewen_stress(x, z, a: float, p0: float, q0: float = 0.0):
    """Stress field in a half-space z >= 0 under the Hertz pressure p = p0 sqrt(1 - x^2/a^2)
    and the proportional tangential traction q = (q0/p0) p (McEwen 1949; Johnson sections 4.2
    and 7.1).

    With (signs of m and n those of z and x)
        m^2 = [sqrt((a^2 - x^2 + z^2)^2 + 4 x^2 z^2) + (a^2 - x^2 + z^2)] / 2,
        n^2 = [sqrt((a^2 - x^2 + z^2)^2 + 4 x^2 z^2) - (a^2 - x^2 + z^2)] / 2,
    the normal pressure gives
        sxx = -(p0/a) [m (1 + (z^2 + n^2)/(m^2 + n^2)) - 2 z],
        szz = -(p0/a) m (1 - (z^2 + n^2)/(m^2 + n^2)),
        sxz = -(p0/a) n (m^2 - z^2)/(m^2 + n^2),
    and the tangential traction (q in +x on the half-space)
        sxx =  (q0/a) [n (2 + (m^2 - z^2)/(m^2 + n^2)) - 2 x],
        szz = -(q0/a) n (m^2 - z^2)/(m^2 + n^2),
        sxz = -(q0/a) [m (1 + (z^2 + n^2)/(m^2 + n^2)) - 2 z].
    The overall signs differ from Johnson's printed ones where his tangential traction and
    shear-stress conventions differ from the ones stated in this module; the signs here are
    those of the superposition of Flamant line loads (Johnson eqs. 2.15, 2.16) with the forces
    acting *on* the half-space, checked against that superposition in tests/test_theory.py.
    (The Flamant kernels show the x <-> z symmetry used: the tangential szz equals the normal
    sxz, and the tangential sxz the normal sxx, with p0 -> q0.)

    Returns (sxx, szz, sxz) broadcast over x and z; tension positive."""
    a = _positive("a", a)
    p0 = float(p0)
    q0 = float(q0)
    if not (math.isfinite(p0) and math.isfinite(q0)):
        raise ValueError(f"p0 and q0 must be finite, got p0={p0!r}, q0={q0!r}")
    x, z = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(z, dtype=float))
    if np.any(z < 0.0):
        raise ValueError("z must be >= 0 (depth below the surface)")
    b = a * a - x * x + z * z
    root = np.sqrt(b * b + 4.0 * x * x * z * z)
    m = np.sqrt(np.clip(0.5 * (root + b), 0.0, None))  # z >= 0, so m >= 0
    n = np.sign(x) * np.sqrt(np.clip(0.5 * (root - b), 0.0, None))
    r2 = m * m + n * n  # equals root; zero only at the contact edges x = +-a, z = 0
    safe = np.where(r2 > 0.0, r2, 1.0)
    A = np.where(r2 > 0.0, (z * z + n * n) / safe, 0.0)
    B = np.where(r2 > 0.0, (m * m - z * z) / safe, 0.0)
    sxx = -(p0 / a) * (m * (1.0 + A) - 2.0 * z)
    szz = -(p0 / a) * m * (1.0 - A)
    sxz = -(p0 / a) * n * B
    if q0 != 0.0:
        sxx = sxx + (q0 / a) * (n * (2.0 + B) - 2.0 * x)
        szz = szz - (q0 / a) * n * B
        sxz = sxz - (q0 / a) * (m * (1.0 + A) - 2.0 * z)
    return sxx, szz, sxz


def cattaneo_mindlin_stress(x, z, a: float, c: float, mu: float, p0: float, sign: float = 1.0):
    """Subsurface stress of the Cattaneo-Mindlin partial-slip line contact, by superposition
    (linear elasticity, the normal and tangential problems uncoupled for similar materials):
    McEwen's field for the Hertz pressure with the full-slip traction q = sign mu p, plus
    McEwen's tangential field of the stick correction q' = -sign mu p0 (c/a) sqrt(1 - x^2/c^2),
    a traction of Hertz shape over the half-width c (thesis eqs. 2-25, 2-26; Johnson section 7.1).
    Returns (sxx, szz, sxz); on the surface sxz = -q(x) of :func:`cattaneo_mindlin_shear`."""
    a = _positive("a", a)
    c = _non_negative("c", c)
    if c > a:
        raise ValueError(f"c must not exceed a, got c={c!r} > a={a!r}")
    mu = _non_negative("mu", mu)
    s = float(np.sign(sign))
    if s == 0.0:
        raise ValueError(f"sign must be non-zero, got {sign!r}")
    sxx, szz, sxz = mcewen_stress(x, z, a, p0, s * mu * p0)
    if c > 0.0:
        dxx, dzz, dxz = mcewen_stress(x, z, c, 0.0, -s * mu * p0 * c / a)
        sxx, szz, sxz = sxx + dxx, szz + dzz, sxz + dxz
    return sxx, szz, sxz


def von_mises_plane_strain(sxx, szz, sxz, nu: float):
    """Von Mises stress in plane strain, the out-of-plane stress being syy = nu (sxx + szz)."""
    nu = _poisson("nu", nu)
    sxx, szz, sxz = (np.asarray(s, dtype=float) for s in (sxx, szz, sxz))
    syy = nu * (sxx + szz)
    return np.sqrt(
        0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxz**2
    )


def max_shear_stress(sxx, szz, sxz):
    """In-plane principal shear stress tau_1 = sqrt(((sxx - szz)/2)^2 + sxz^2)."""
    sxx, szz, sxz = (np.asarray(s, dtype=float) for s in (sxx, szz, sxz))
    return np.sqrt(0.25 * (sxx - szz) ** 2 + sxz**2)


def axis_peak(nu: float = 0.3, measure: str = "von_mises") -> tuple[float, float]:
    """Peak of the frictionless Hertz field on the load axis x = 0, in units of p0 and a:
    returns (peak / p0, depth / a). ``measure`` is "von_mises" (plane strain with ``nu``) or
    "max_shear". Published: von Mises 0.5575 p0 at 0.704 a for nu = 0.3 (thesis: 0.558 p0 at
    0.703 a), max shear 0.300 p0 at 0.786 a (Johnson section 4.2)."""
    nu = _poisson("nu", nu)
    if measure not in ("von_mises", "max_shear"):
        raise ValueError(f"measure must be 'von_mises' or 'max_shear', got {measure!r}")

    def negative_measure(zeta: float) -> float:
        s = mcewen_stress(0.0, zeta, 1.0, 1.0)
        v = von_mises_plane_strain(*s, nu) if measure == "von_mises" else max_shear_stress(*s)
        return -float(v)

    # scipy's bounded Brent search: the on-axis measure is unimodal on (0, 3a)
    from scipy import optimize  # here: its import costs 0.1 s of every run

    res = optimize.minimize_scalar(negative_measure, bounds=(1e-6, 3.0), method="bounded",
                                   options={"xatol": 1e-10})
    return -float(res.fun), float(res.x)


def field_peak(stress, nu: float = 0.3, extent: float = 2.0, n: int = 161):
    """Largest plane-strain von Mises stress of a field ``stress(x, z) -> (sxx, szz, sxz)``
    over the region |x| <= extent, 0 <= z <= extent (lengths as the field's): a dense grid
    (brute force, vectorised) then a Nelder-Mead polish from the best grid point (scipy).
    Returns (peak, x, z). With partial slip the peak leaves the load axis: the tilt of the
    thesis's figure 6-17."""
    nu = _poisson("nu", nu)
    extent = _positive("extent", extent)
    xs = np.linspace(-extent, extent, 2 * n - 1)
    zs = np.linspace(0.0, extent, n)
    X, Z = np.meshgrid(xs, zs)
    vm = von_mises_plane_strain(*stress(X, Z), nu)
    k = np.unravel_index(int(np.argmax(vm)), vm.shape)

    def negative(v: np.ndarray) -> float:
        return -float(von_mises_plane_strain(*stress(v[0], max(v[1], 0.0)), nu))

    step = xs[1] - xs[0]
    from scipy import optimize

    res = optimize.minimize(negative, np.array([X[k], Z[k]]), method="Nelder-Mead",
                            options={"xatol": 1e-6 * step, "fatol": 1e-14})
    x_best, z_best = float(res.x[0]), max(float(res.x[1]), 0.0)
    peak = -float(res.fun)
    if peak < float(vm[k]):  # the polish never makes it worse than the grid
        return float(vm[k]), float(X[k]), float(Z[k])
    return peak, x_best, z_best


# --------------------------------------------------------------------------- approach (estimate)


def axis_compression(N: float, a: float, youngs_modulus: float, poissons_ratio: float,
                     depth: float) -> float:
    """Shortening of the load axis from the surface to ``depth`` in a plane-strain half-space
    under the Hertz pressure of force N and half-width a: the integral of -ezz along x = 0 with
    the on-axis stresses (Johnson section 4.2)
        szz = -p0 a / sqrt(a^2 + z^2),  sxx = -(p0/a) [(a^2 + 2 z^2)/sqrt(a^2 + z^2) - 2 z],
    which integrates in closed form to
        delta = (2N / (pi E)) [(1 - nu^2) asinh(d/a) - nu (1 + nu) (d sqrt(a^2 + d^2) - d^2)/a^2].

    In 2D the approach grows like ln(depth/a): it depends on the bodies' sizes and supports, so
    this is only an *estimate* of a finite body's compliance (good to tens of percent in N).
    Prefer choosing scenes by their force N; use this to turn N into a trial displacement."""
    N = _non_negative("N", N)
    a = _positive("a", a)
    E = _positive("youngs_modulus", youngs_modulus)
    nu = _poisson("poissons_ratio", poissons_ratio)
    d = _positive("depth", depth)
    # d sqrt(a^2 + d^2) - d^2 = d a^2 / (sqrt(a^2 + d^2) + d): the stable form for d >> a
    tail = d / (math.sqrt(a * a + d * d) + d)
    return 2.0 * N / (math.pi * E) * ((1.0 - nu * nu) * math.asinh(d / a) - nu * (1.0 + nu) * tail)


def approach_estimate(N: float, R_eff: float, E1: float, nu1: float, E2: float, nu2: float,
                      depth1: float, depth2: float) -> float:
    """Estimated approach of two loaded boundaries, at ``depth1`` / ``depth2`` from the contact
    in bodies 1 / 2, for normal force N: the sum of the two bodies' :func:`axis_compression`
    with the Hertz half-width. An estimate (see :func:`axis_compression`)."""
    a = hertz_half_width(N, R_eff, effective_modulus(E1, nu1, E2, nu2))
    if a == 0.0:
        return 0.0
    return axis_compression(N, a, E1, nu1, depth1) + axis_compression(N, a, E2, nu2, depth2)


def load_for_approach(delta: float, R_eff: float, E1: float, nu1: float, E2: float, nu2: float,
                      depth1: float, depth2: float) -> float:
    """Inverse of :func:`approach_estimate` (the approach increases monotonically with N while
    the half-width stays below the depths): the normal force N giving approach ``delta``."""
    delta = _positive("delta", delta)

    def residual(log_N: float) -> float:
        return approach_estimate(math.exp(log_N), R_eff, E1, nu1, E2, nu2, depth1, depth2) - delta

    # bracket in log N: from a vanishing force up to one whose half-width reaches the depths
    E_eff = effective_modulus(E1, nu1, E2, nu2)
    hi = math.log(load_for_half_width(0.5 * min(depth1, depth2), R_eff, E_eff))
    lo = hi - 60.0
    if residual(hi) < 0.0:
        raise ValueError(f"delta={delta!r} is too large for a small-strain Hertz estimate")
    from scipy import optimize

    return math.exp(optimize.brentq(residual, lo, hi, xtol=1e-12, rtol=1e-12))


# ------------------------------------------------------------------------------------------
# three dimensions (contact between solids)
# ------------------------------------------------------------------------------------------


def lame_sphere(r, inner: float, outer: float, pressure: float, youngs_modulus: float, poissons_ratio: float):
    """Thick spherical shell (radii inner < outer) under internal pressure: radial displacement
    u_r and the stresses (s_rr, s_tt) at radii r (Lame; e.g. Timoshenko & Goodier, Theory of
    Elasticity, section 141): with k = p a^3 / (b^3 - a^3),
    s_rr = k (1 - b^3 / r^3), s_tt = k (1 + b^3 / (2 r^3)),
    u_r = k / E ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2))."""
    a = _positive("inner", inner)
    b = _positive("outer", outer)
    if not b > a:
        raise ValueError(f"outer radius must exceed the inner one, got {inner!r}, {outer!r}")
    E = _positive("youngs_modulus", youngs_modulus)
    nu = _poisson("poissons_ratio", poissons_ratio)
    r = np.asarray(r, dtype=float)
    k = pressure * a**3 / (b**3 - a**3)
    u = k / E * ((1 - 2 * nu) * r + (1 + nu) * b**3 / (2 * r**2))
    return u, k * (1 - b**3 / r**3), k * (1 + b**3 / (2 * r**3))


def goodier_concentration(poissons_ratio: float) -> float:
    """Stress concentration of a spherical cavity in an infinite body under uniaxial tension: the
    axial stress at the cavity's equator over the remote stress, (27 - 15 nu) / (2 (7 - 5 nu))
    (Goodier 1933; 2.045 for nu = 0.3)."""
    nu = _poisson("poissons_ratio", poissons_ratio)
    return (27.0 - 15.0 * nu) / (2.0 * (7.0 - 5.0 * nu))


def hertz_sphere_radius(N: float, R_eff: float, E_eff: float) -> float:
    """Contact radius of two spheres (or a sphere on a flat) pressed by N [N]: a = (3 N R* / (4 E*))^(1/3)
    with 1/R* = 1/R1 + 1/R2 and 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (Johnson, Contact Mechanics, 4.2)."""
    N = _non_negative("N", N)
    return (3.0 * N * _positive("R_eff", R_eff) / (4.0 * _positive("E_eff", E_eff))) ** (1.0 / 3.0)


def exact_sphere_radius(N: float, R: float, E_eff: float) -> float:
    """Contact radius of a sphere of radius R on a half-space pressed by N, with the sphere's
    exact gap R - sqrt(R^2 - r^2) instead of Hertz's parabola r^2 / (2 R): the root of Sneddon's
    load of an axisymmetric punch (Int. J. Eng. Sci. 3, 47-57, 1965),
    N(a) = 2 E* int_0^a r^2 f'(r) / sqrt(a^2 - r^2) dr with f'(r) = r / sqrt(R^2 - r^2),
    integrated with r = a sin t by Gauss-Legendre on [0, pi/2] (the integrand is smooth there).
    For a / R -> 0 it is Hertz's radius; the exact gap is wider, so the radius is a little smaller
    (at a / R = 0.045, 0.027 % smaller)."""
    N, R, E_eff = _non_negative("N", N), _positive("R", R), _positive("E_eff", E_eff)
    t, w = np.polynomial.legendre.leggauss(64)
    t, w = 0.25 * math.pi * (t + 1.0), 0.25 * math.pi * w

    def load(a: float) -> float:
        r = a * np.sin(t)
        return 2.0 * E_eff * float(np.sum(w * r * r * r / np.sqrt(R * R - r * r)))

    if N == 0.0:
        return 0.0
    hi = hertz_sphere_radius(N, R, E_eff)  # the exact gap's radius lies below Hertz's
    if hi >= R:
        raise ValueError(f"N = {N:.4g} N presses the sphere to a contact radius of R = {R:.4g} m or more")
    lo = 0.5 * hi
    while load(lo) > N:
        lo *= 0.5
    for _ in range(200):  # bisection: load(a) grows with a
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if load(mid) < N else (lo, mid)
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi)


def hertz_sphere_peak_pressure(N: float, a: float) -> float:
    """p0 = 3 N / (2 pi a^2) of a circular Hertz contact."""
    return 3.0 * _non_negative("N", N) / (2.0 * math.pi * _positive("a", a) ** 2)


def hertz_sphere_pressure(r, a: float, p0: float) -> np.ndarray:
    """p(r) = p0 sqrt(1 - r^2/a^2) inside the circle, 0 outside."""
    r = np.asarray(r, dtype=float)
    return p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))


def mindlin_sphere_stick_ratio(Q: float, N: float, mu: float) -> float:
    """c/a = (1 - |Q| / (mu N))^(1/3) of two elastically similar spheres under partial slip
    (Cattaneo 1938, Mindlin 1949; Johnson 7.2)."""
    ratio = abs(Q) / (_positive("mu", mu) * _positive("N", N))
    if ratio >= 1.0:
        raise ValueError(f"|Q| / (mu N) = {ratio:.4g} >= 1: gross slip, no stick zone")
    return (1.0 - ratio) ** (1.0 / 3.0)


def hertz_sphere_axis_stress(z, a: float, p0: float, poissons_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """Stresses on the axis under a circular Hertz contact at depths ``z`` >= 0 (compression
    negative): sigma_r = sigma_theta = -p0 [(1 + nu)(1 - (z/a) arctan(a/z)) - 1 / (2 (1 + z^2/a^2))]
    and sigma_z = -p0 / (1 + z^2/a^2) (Johnson, Contact Mechanics, eq. 3.45). Their half difference
    is the largest shear stress there: 0.31 p0 at z = 0.48 a for nu = 0.3."""
    nu = _poisson("poissons_ratio", poissons_ratio)
    z = np.asarray(z, dtype=float)
    if np.any(z < 0.0):
        raise ValueError("z must be depths >= 0")
    t = z / _positive("a", a)
    with np.errstate(divide="ignore", invalid="ignore"):
        atan = np.where(t > 0.0, t * np.arctan(1.0 / np.where(t > 0.0, t, 1.0)), 0.0)
    sr = -p0 * ((1.0 + nu) * (1.0 - atan) - 0.5 / (1.0 + t**2))
    return sr, -p0 / (1.0 + t**2)


def hertz_elliptic_contact(N: float, curvatures: tuple[float, float], E_eff: float) -> tuple[float, float, float]:
    """Semi-axes (a >= b) and peak pressure of an elliptical Hertz contact pressed by N [N], the
    gap being h = x^2 / (2 R'_1) + y^2 / (2 R'_2) with ``curvatures`` = (1/R'_1, 1/R'_2) the
    principal relative curvatures; a lies along the smaller curvature. With h = A x^2 + B y^2,
    e^2 = 1 - b^2/a^2 and K, E the complete elliptic integrals of parameter e^2 (Johnson,
    Contact Mechanics, 4.2.2): B/A = (E - (1 - e^2) K) / ((1 - e^2)(K - E)) fixes e (bisection),
    then a^3 = 3 N (K - E) / (2 pi E* A e^2) and p0 = 3 N / (2 pi a b)."""
    from scipy.special import ellipe, ellipk

    k1, k2 = sorted((_positive("curvature", curvatures[0]), _positive("curvature", curvatures[1])))
    A, B = 0.5 * k1, 0.5 * k2
    E_eff = _positive("E_eff", E_eff)
    if B / A < 1.0 + 1e-12:
        a = hertz_sphere_radius(N, 1.0 / (2.0 * A), E_eff)
        return a, a, hertz_sphere_peak_pressure(N, a)

    def a_over_b(e2: float) -> float:  # A/B for eccentricity e^2
        K, Ek = ellipk(e2), ellipe(e2)
        return (K - Ek) * (1.0 - e2) / (Ek - (1.0 - e2) * K)

    lo, hi = 1e-12, 1.0 - 1e-15
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if a_over_b(mid) > A / B:
            lo = mid
        else:
            hi = mid
    e2 = 0.5 * (lo + hi)
    K, Ek = ellipk(e2), ellipe(e2)
    a = (3.0 * _non_negative("N", N) * (K - Ek) / (2.0 * math.pi * E_eff * A * e2)) ** (1.0 / 3.0)
    b = a * math.sqrt(1.0 - e2)
    return a, b, 3.0 * N / (2.0 * math.pi * a * b)
