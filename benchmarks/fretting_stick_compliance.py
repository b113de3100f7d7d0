"""The tangential compliance of imposed stick circles (3D fretting example) against Mindlin's.

For a stick circle of radius c under a held normal load, with the slip annulus c < r < a carrying
Coulomb's traction mu p along a fixed direction, the contact's tangential stiffness is that of a
bonded circle of radius c: dQ / d delta = 8 G* c (Mindlin; 1 / G* = (2 - nu1) / G1 + (2 - nu2) / G2,
for identical materials 8 G* c = 4 G c / (2 - nu)). With the zones held the discrete problem is
linear in the rig's displacement, so two steps with the same zones give its stiffness exactly.

The script runs the fretting example (``examples/fretting/sphere_on_flat_fretting.toml``, its
normal displacement held from t = 1) with the rig's tangential displacement stepped 0, A, 0, A, ...
and, per pair of steps, one stick circle imposed (``HistoryEllipseContact.zone_rule``): stuck
inside c, slipping outside it with the ball. Per radius it prints the rig's compliance d delta / d Q
(full contact: the half model's forces over its share) and, against the compliance at c = a
(which holds the bodies' own linear compliance, away from the contact), the increase
C(c) - C(a) beside Mindlin's (1 / (8 G*)) (1 / c - 1 / a); from it, the energy per cycle of loops
whose branches have the closed form's zones and the measured tangent compliance (interpolated in
c), against Mindlin and Deresiewicz's at Q*/(mu N) = 0.15, 0.3, 0.6 (a linear compliance adds no
area to a loop: only the increase counts).

The tangent is half of the state: each pair of steps also gives the force line Q = K (delta -
delta_0) of the circle, from which the script reads Cattaneo's state (the memory of the stuck
points is the normal load's, as on a first loading, for the radii decrease): the rig's
displacement at which the circle carries Q = mu N (1 - c^3 / a^3), less the full stick's linear
compliance times Q, against Mindlin's 3 mu N / (16 a G*) (1 - c^2 / a^2) - Q / (8 a G*) (the
slip part of the displacement): its excess is where the annulus's Coulomb traction and the stick
zone's reaction to it, not the stick zone's stiffness, are off. That slip part is a small difference
(at c = 0.888 a 5 % of the displacement) and takes the full stick's compliance, ties' layer
included, as the linear part; the loading curve's sag below its chord (from rest to the state at
0.888 a or 0.7 a, at the radii between) holds no linear part at all, as a loop's area holds none;
a Masing loop (Mindlin and Deresiewicz's is one) has 8 times the area between the first loading's
curve and its chord, so the sags at the radii measured, summed by trapezoids against Mindlin's
through the same states, give the energy per cycle of the loop the loading curve draws.

    .venv/bin/python benchmarks/fretting_stick_compliance.py [--edge-ring | --edge-ring-levels K]
        [--refinement-levels 6] [--radii 1 0.95 0.9 0.85] [--band-fraction 0.5]

The example's grid takes about 8 s CPU and 0.5 GB; with ``--edge-ring`` (``--edge-ring-levels 1``)
about 30 s CPU and 0.95 GB; with ``--edge-ring-levels 2`` (a / h = 23.2 at the stick circle) 280 to
290 s CPU and 3.1 to 4.0 GB;
``--refinement-levels 6`` refines the whole contact once more (a / h = 11.6): 43 to 71 s CPU and
1.9 GB (the default radii the longer).
``--band-fraction`` sets the scene's [solver].band_fraction (the ties' layer, 0.25 by default);
``--tangential-band F`` the stuck points' tangential tie's layer alone (F times the contact's);
``--cut-cell-tie``, ``--tie-groups``, ``--cut-cell-consistency``, ``--near-band``, ``--recovered-flux``, ``--tie-flux`` and ``--uzawa`` the diagnostic
ties of ``solver.contact.friction_history_ties``. Prints only; writes nothing.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

DEFAULT_RADII = (1.0, 0.97, 0.94, 0.91, 0.888, 0.85, 0.8, 0.7)


class FixedStickCircle:
    """A ``zone_rule`` holding, for the pair of load steps 2 k, 2 k + 1 after the normal step, the
    stick circle of radius ``radii[k]`` a (slipping outside it with the ball, along +x: Q > 0)."""

    def __init__(self, radii):
        self.radii = list(radii)
        self.contact = None  # the contact the rule served (its records after the run)

    def zones(self, contact, s: np.ndarray, a: float, force: np.ndarray):
        self.contact = contact
        k = (contact.step_count - 2) // 2
        c = self.radii[k] if 0 <= k < len(self.radii) else 1.0
        slip = contact.normalised_radius(s, a) > c
        direction = np.where(slip[:, None], contact.frame.axes[0][None, :], 0.0)  # traction -mu p e on body 1: Q > 0
        return slip, direction

    def step_end(self, contact, force: np.ndarray) -> None:
        pass


def _scene(radii, amplitude: float, edge_ring: int, band_fraction: float | None = None,
           refinement_levels: int | None = None):
    from ibfem.solver.io.scene import scene_from_dict
    from ibfem.solver.reports.validate_fretting_sphere import EXAMPLE, scene_data

    data = scene_data(amplitude, 0.5, 20, refinement_levels=refinement_levels, edge_ring=edge_ring)
    if band_fraction is not None:
        data.setdefault("solver", {})["band_fraction"] = float(band_fraction)
    from ibfem.solver.contact import friction_history_ties
    if friction_history_ties.UZAWA_TOLERANCE is not None:  # the ties' updates are solves of the step
        for c in data["contacts"]:
            c["max_stick_iterations"] = friction_history_ties.UZAWA_UPDATES + 40
    end = 1.0 + 2 * len(radii)
    for p in data["paths"]:
        if p["name"] == "fret":  # 0 at t = 1, then A, 0, A, 0, ... one step each
            p.pop("cycle")
            p["points"] = [[0.0, 0.0], [1.0, 0.0]] + [[1.0 + k, float(k % 2)] for k in range(1, 2 * len(radii) + 1)]
        if p["name"] == "hold":
            p["points"] = [[0.0, 0.0], [1.0, 1.0], [end, 1.0]]
    return scene_from_dict(data, label=str(EXAMPLE), base_dir=EXAMPLE.parent)


def measure(radii, amplitude: float, edge_ring: int, band_fraction: float | None = None,
            refinement_levels: int | None = None) -> dict:
    """Per radius the rig's compliance of the full contact; the contact's N and a."""
    from ibfem.solver.contact.friction_history3d import HistoryEllipseContact
    from ibfem.solver.io.fretting_outputs import _relative_displacement, loop_force
    from ibfem.solver.solving import solve

    sc = _scene(radii, amplitude, edge_ring, band_fraction, refinement_levels)
    rule = HistoryEllipseContact.zone_rule = FixedStickCircle(radii)
    try:
        solution = solve(sc.problem)
    finally:
        HistoryEllipseContact.zone_rule = None
    contact = rule.contact
    steps = solution.steps
    block = solution.contacts[0]  # the run's summary block of the contact
    share = float(block.get("model_share", 1.0))
    q = np.array([loop_force(st["contacts"][0]) for st in steps]) / share
    delta = _relative_displacement(steps, 0, solution.contacts[0], sc.problem)
    t = np.array([st["t"] for st in steps])
    out = []
    for k, c in enumerate(radii):
        i, j = (int(np.argmin(np.abs(t - v))) for v in (2.0 + 2 * k, 3.0 + 2 * k))
        ratio = [st["contacts"][0]["stick_area"] / st["contacts"][0]["region_area"] for st in (steps[i], steps[j])]
        k_c = (q[j] - q[i]) / (delta[j] - delta[i])
        out.append({"c": c, "compliance": 1.0 / k_c, "offset": q[j] - k_c * delta[j],
                    "stick_ratio": math.sqrt(ratio[1]), "Q": (q[i], q[j])})
    m = sc.problem.bodies[0].material
    n = abs(float(steps[-1]["contacts"][0]["normal_force"])) / share
    a = float(steps[-1]["contacts"][0]["semi_axes"][0])
    return {"radii": out, "N": n, "a": a, "E": m.youngs_modulus, "nu": m.poissons_ratio,
            "mu": float(block["friction"]), "solves": solution.iterations["total"], "converged": solution.converged,
            "uzawa_updates": list(contact.uzawa_updates), "uzawa_unconverged": list(contact.uzawa_unconverged)}


def implied_energy(x: float, excess, n: float, mu: float, a: float, g_eff: float, samples: int = 4000) -> float:
    """The energy per cycle of a loop between +-x mu N whose branches have Mindlin's compliance plus
    ``excess(c / a)`` (the measured compliance's increase less Mindlin's), over W of the closed form - 1."""
    from ibfem.solver.reference.fretting_sphere import energy_per_cycle

    dq = np.linspace(0.0, 2.0 * x * mu * n, samples)  # the branch from +Q* down to -Q*
    c = np.clip(1.0 - dq / (2.0 * mu * n), 0.0, 1.0) ** (1.0 / 3.0)
    comp = 1.0 / (8.0 * g_eff * a * np.maximum(c, 1e-9)) + excess(c)
    d = np.concatenate([[0.0], np.cumsum(0.5 * (comp[1:] + comp[:-1]) * np.diff(dq))])
    # the loop's area: twice the area between the branch and its chord (the return branch is its image)
    chord = d[-1] * dq / dq[-1]
    area = 2.0 * np.trapezoid(chord - d, dq)
    return abs(area) / energy_per_cycle(x * mu * n, n, mu, a, g_eff) - 1.0


def main(argv: list[str] | None = None) -> int:
    from ibfem.solver.reference.fretting_sphere import effective_shear_modulus
    from ibfem.solver.reports.validate_fretting_sphere import amplitude_for

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edge-ring", action="store_true", help="one more refinement level about the contact's edge")
    ap.add_argument("--edge-ring-levels", type=int, default=None, metavar="K",
                    help="K levels more in graded rings about the contact's edge (validate_fretting_sphere)")
    ap.add_argument("--refinement-levels", type=int, default=None,
                    help="refinement levels about the contact in both bodies (the example's 5, a / h = 5.8; 6: 11.6)")
    ap.add_argument("--radii", type=float, nargs="+", default=list(DEFAULT_RADII), help="c / a, the first 1")
    ap.add_argument("--band-fraction", type=float, default=None, help="the ties' band ([solver].band_fraction)")
    ap.add_argument("--cut-cell-tie", choices=("points", "mean", "all"), default=None,
                    help="the stuck points tied each at its jump (points), or by their group's mean tangential jump in the "
                         "groups the stick circle cuts (mean) or in all (all) (friction_history_ties.CUT_CELL_TIE)")
    ap.add_argument("--cut-cell-consistency", type=float, default=None,
                    help="the mean tie's consistency factor (friction_history_ties.CUT_CELL_CONSISTENCY)")
    ap.add_argument("--tangential-band", type=float, default=None,
                    help="the stuck points' tangential tie's layer over the contact's (friction_history3d.TANGENTIAL_BAND)")
    ap.add_argument("--near-band", type=float, nargs=2, default=None, metavar=("FACTOR", "CELLS"),
                    help="a diagnostic: the stuck points within CELLS cells of the slip zone on a layer FACTOR times")
    ap.add_argument("--tie-groups", choices=("pairs", "cell1", "cell2", "patch2", "nodes"), default=None,
                    help="the mean ties' groups (friction_history_ties.TIE_GROUPS)")
    ap.add_argument("--recovered-flux", type=float, default=None, metavar="CELLS",
                    help="the stuck points' tangential consistency flux averaged over a disc of CELLS cells in diameter "
                         "among the stuck points (friction_history_ties.RECOVERED_FLUX)")
    ap.add_argument("--tie-flux", choices=("mean", "1", "2"), default=None,
                    help="the stuck points' tangential consistency flux: the bodies' mean stress or one body's "
                         "(friction_history_ties.TIE_FLUX)")
    ap.add_argument("--uzawa", type=float, default=None, metavar="TOL",
                    help="the stuck points held exactly by augmented-Lagrangian ties, to TOL of the step's largest "
                         "jump increment (friction_history_ties.UZAWA_TOLERANCE)")
    args = ap.parse_args(argv)
    from ibfem.solver.contact import friction_history3d, friction_history_ties as ties
    for option, module, name in (("tie_groups", ties, "TIE_GROUPS"), ("uzawa", ties, "UZAWA_TOLERANCE"),
                                 ("tie_flux", ties, "TIE_FLUX"), ("recovered_flux", ties, "RECOVERED_FLUX"),
                                 ("tangential_band", friction_history3d, "TANGENTIAL_BAND"),
                                 ("cut_cell_tie", ties, "CUT_CELL_TIE"),
                                 ("cut_cell_consistency", ties, "CUT_CELL_CONSISTENCY")):
        if getattr(args, option) is not None:  # a diagnostic switched on for this process
            setattr(module, name, getattr(args, option))
    if args.near_band is not None:
        ties.NEAR_BAND, ties.NEAR_CELLS = args.near_band
    if args.radii[0] != 1.0:
        raise SystemExit("--radii: the first radius must be 1 (the full stick, the reference of the increase)")
    ring = args.edge_ring_levels if args.edge_ring_levels is not None else int(args.edge_ring)
    r = measure(args.radii, amplitude_for(0.3), ring, args.band_fraction, args.refinement_levels)
    g = effective_shear_modulus(r["E"], r["nu"], r["E"], r["nu"])
    a = r["a"]
    print(f"converged {r['converged']}, {r['solves']} solves; N {r['N']:.5g} N, a {a:.5g} m (full contact)")
    if r.get("uzawa_updates"):
        print(f"augmented-Lagrangian updates per step {r['uzawa_updates']}; steps not converged "
              f"{[(k, [f'{v:.2g}' for v in h[-3:]]) for k, h in r['uzawa_unconverged']]}")
    c0 = r["radii"][0]["compliance"]
    print(f"full stick: rig's compliance {c0:.6g} m/N; Mindlin's 1 / (8 G* a) {1 / (8 * g * a):.6g} m/N")
    cs, ex = [], []
    for v in r["radii"]:
        inc = v["compliance"] - c0
        ref = (1.0 / v["c"] - 1.0) / (8.0 * g * a)
        cs.append(v["c"])
        ex.append(inc - ref)
        print(f"c/a {v['c']:.3f} (stick area's {v['stick_ratio']:.4f}): compliance {v['compliance']:.6g}, increase "
              f"{inc:.4g} against Mindlin's {ref:.4g} m/N; excess {(inc - ref) * 8 * g * a:+.5f} / (8 G* a), "
              f"as a share of Mindlin's compliance at c {(inc - ref) * 8 * g * a * v['c']:+.4%}")
    order = np.argsort(cs)

    def excess(c):
        return np.interp(c, np.array(cs)[order], np.array(ex)[order])

    for x in (0.15, 0.3, 0.6):
        print(f"Q*/(mu N) {x}: the loop with the measured tangent compliance: W / W_MD - 1 "
              f"{implied_energy(x, excess, r['N'], r['mu'], a, g):+.2%}")
    # Cattaneo's state of each circle from the loaded-from-rest memory: Q = mu N (1 - c^3 / a^3)
    mu, n = r["mu"], r["N"]
    unit = 3.0 * mu * n / (16.0 * a * g)
    for v in r["radii"]:
        q_md = mu * n * (1.0 - v["c"] ** 3)
        d_rig = (q_md - v["offset"]) * v["compliance"]  # the rig's displacement at which the circle carries it
        slip_num = d_rig - c0 * q_md  # less the full stick's linear compliance (bodies and contact)
        slip_md = unit * (1.0 - v["c"] ** 2) - q_md / (8.0 * g * a)
        print(f"c/a {v['c']:.3f}: Q_MD/(mu N) {1 - v['c'] ** 3:.4f}: the rig's displacement less the linear part "
              f"{slip_num:.5g} m against Mindlin's {slip_md:.5g} m ({slip_num / slip_md - 1 if slip_md else 0:+.2%}); "
              f"the excess {(slip_num - slip_md) / unit:+.5f} of 3 mu N / (16 a G*)")

    for line in loading_curve_sags(r, g):
        print(line)
    return 0 if r["converged"] else 1


def loading_curve_sags(r: dict, g_eff: float, ends=(0.888, 0.7)) -> list[str]:
    """The first loading curve's sag below its chord, against Mindlin's: per end radius c_e (of the
    measured ones) and each measured radius c between 1 and c_e, the rig's displacement at Mindlin's
    Q(c) less the chord's from rest to (Q(c_e), delta(c_e)). A linear compliance (the bodies', the
    ties' layer's under a full stick) adds nothing to it, as it adds no area to a loop: it is the
    nonlinear part of the curve, the part that makes a Masing loop's area."""
    mu, n, a = r["mu"], r["N"], r["a"]
    unit = 3.0 * mu * n / (16.0 * a * g_eff)
    states = {}
    for v in r["radii"]:
        q = mu * n * (1.0 - v["c"] ** 3)
        states[v["c"]] = (q, (q - v["offset"]) * v["compliance"], unit * (1.0 - v["c"] ** 2))
    out = []
    for c_e in ends:
        if c_e not in states:
            continue
        q_e, d_e, m_e = states[c_e]
        for c, (q, d, m) in sorted(states.items(), reverse=True):
            if not c_e < c < 1.0:
                continue
            sag, sag_md = d_e * q / q_e - d, m_e * q / q_e - m
            out.append(f"c/a {c:.3f} on the chord to {c_e:.3f}: the loading curve's sag {sag:.5g} m against "
                       f"Mindlin's {sag_md:.5g} m ({sag / sag_md - 1:+.2%})")
        qs = [v[0] for c, v in sorted(states.items(), reverse=True) if c_e <= c <= 1.0]
        sags = [(d_e * v[0] / q_e - v[1], m_e * v[0] / q_e - v[2]) for c, v in sorted(states.items(), reverse=True)
                if c_e <= c <= 1.0]
        if len(qs) > 2:  # a Masing loop's area is 8 times the area between the first loading's curve and its chord
            w, w_md = (8.0 * np.trapezoid([v[k] for v in sags], qs) for k in (0, 1))
            out.append(f"Q*/(mu N) {1 - c_e ** 3:.3f}: the Masing loop of the loading curve through {len(qs)} states: "
                       f"W {w:.5g} J against Mindlin's through the same states {w_md:.5g} J ({w / w_md - 1:+.2%})")
    return out


if __name__ == "__main__":
    raise SystemExit(main())
