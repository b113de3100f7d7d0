"""The load-step driver of contact problems: it knows no formulation. Each contact supplies its
terms, verdicts and region search through the :class:`~solver.contact.formulation.ContactFormulation`
protocol; the driver owns the linear algebra and the iterations.

Speed: the bodies' stiffness K0 (volume + essential conditions) never changes. It is factored
once with the m dofs B of the cells the candidate contact regions touch ordered last, the
Schur complement S = (B K0^-1 B^T)^-1 is read off the factors (solver.fem.linalg), each trial
region is the m x m solve (S + K_c) x = lambda S B U0 + f_c, and the full field
U = K0^-1 (F0 + B^T (f_c - K_c x)) is recovered once, with two steps of iterative refinement.

With linear elasticity and a fixed contact region each load step is linear: the "Newton"
iterations of eqs. 5-11 to 5-14 are re-solves with updated contact terms, one per trial
region; the residual work between consecutive states is recorded (exact, on the contact dofs).
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
import scipy.sparse as sp

from ..fem.assembly import boundary_terms, essential_reactions, rigid_modes_check
from ..fem.linalg import (
    SmallSystem,
    condensed_apply,
    condensed_factor,
    contact_nearness,
    dof_order,
    embed,
    scatter,
    single_threaded_blas,
)
from ..fem.bodies import discretise
from ..fem.space import body_info
from ..solution import IBFEMSolution
from .region_overlap import overlapping_regions
from .follow import solve_following
from .formulation import formulation
from .friction_memory import with_friction_memory
from .grow import solve_growing
from .sizing import solve_sized
from .load_history import PathSteps, step_field, step_record
from .report import contact_block
from .roots import RegionTooSmall

__all__ = ["ContactDriver", "solve_contact"]


def solve_contact(problem, progress: Callable | None = None) -> IBFEMSolution:
    """Solve a (resolved) problem with contacts; returns an IBFEMSolution whose ``contacts``
    holds the contact blocks of summary.json."""
    if not problem.contacts:
        raise ValueError("the problem has no contacts")
    with single_threaded_blas():  # line contacts: a coarse pass, then a band along the region; a 2D
        # region beyond its refinement: coarse passes, then the refinement widened about it
        # a large point contact: a coarse pass, then the candidate disc sized about its region
        problem = with_friction_memory(problem)  # 2D friction of bodies that slip apart
        return solve_sized(problem, lambda r: solve_following(
            r, lambda p: solve_growing(p, lambda q: ContactDriver(q, progress).run())))


def _silent(stage, fraction=None) -> None:
    return None


def load_steps(problem) -> tuple[int, str]:
    """The load steps to solve, and why. Each step solves the total problem at its load factor
    (the region is found anew; only its starting guess comes from the step before), and in
    small-strain linear elasticity under proportional loading tied and frictionless contact do
    not depend on the loading path: their final load is solved directly. Frictional contact
    keeps the requested steps (the slip direction and the stick zone follow the load history)."""
    requested = problem.options.load_steps
    if getattr(problem, "history", None) is not None:
        n = len(problem.history.times())
        if problem.history.reason:
            return n, problem.history.reason
        return n, f"load paths: {n} steps to t = {problem.history.end:g}, every step solved and recorded"
    if any(c.type == "frictional" for c in problem.contacts):
        return requested, "frictional contact: the requested load steps (the stick zone follows the load history)"
    return 1, ("tied / frictionless contact, proportional loading: path-independent, the final load solved directly"
               + (f" (of {requested} requested)" if requested > 1 else ""))


class ContactDriver:
    """One contact solve: set-up (grids, K0, the contacts' formulations, the condensed factor),
    the load steps (region searches and friction updates), the final state and its report."""

    def __init__(self, problem, progress: Callable | None = None):
        self.problem = problem
        self.options = problem.options
        self.report = progress or _silent
        self.timings: dict[str, float] = {}
        self.messages: list[str] = []
        self.converged = True
        self.per_step: list[int] = []
        self.work_history: list[float] = []
        self.last = None  # (lam, x, y, kc, fc, small) of the last trial state
        self.ref_work = None
        self.steps, self.step_rule = load_steps(problem)
        self.path_steps = None  # PathSteps of a run with load paths
        self.step_records: list[dict] = []

    # ------------------------------------------------------------------ set-up

    def run(self) -> IBFEMSolution:
        t_start = time.perf_counter()
        self._discretise()
        self._assemble()
        self._factor()
        t = time.perf_counter()
        for step in range(1, self.steps + 1):
            self._load_step(step)
        for c in self.contacts:
            self.messages += c.finish()
        self.timings["iterations_s"] = time.perf_counter() - t
        self.timings["per_iteration_s"] = self.timings["iterations_s"] / max(sum(self.per_step), 1)
        t = time.perf_counter()
        solution = self._results()
        self.timings["results_s"] = time.perf_counter() - t
        self.timings["total_s"] = time.perf_counter() - t_start
        self.report("done", 1.0)
        return solution

    def _discretise(self) -> None:
        t = time.perf_counter()
        self.bodies = discretise(self.problem, self.options, lambda stage, f: self.report(stage, 0.5 * f))
        self.n = self.bodies[0].n_total
        self.timings["grid_s"] = time.perf_counter() - t

    def _assemble(self) -> None:
        self.report("assembly", 0.2)
        t = time.perf_counter()
        n = self.n
        k0 = sp.block_diag([b.stiffness(self.options.fictitious_stiffness) for b in self.bodies], format="csr")
        k_ess, self.f0, self.essentials = boundary_terms(self.problem, self.bodies, self.options, sp.csr_matrix((n, n)))
        self.k0 = (k0 + k_ess).tocsr()
        by_name = {b.name: b for b in self.bodies}
        self.contacts = [
            self._builder(cm)(self.problem, cm, by_name[cm.bodies[0]], by_name[cm.bodies[1]], self.options)
            for cm in self.problem.contacts
        ]
        self.timings["assembly_s"] = time.perf_counter() - t

    def _builder(self, cm):
        """The formulation of a contact: frictional contacts under load paths keep a friction history
        (2D: along the sample chords; 3D: on the region's quadrature points); without paths
        (proportional loading) the history cannot matter and is not kept."""
        if self.problem.history is not None and cm.type == "frictional":
            if self.problem.dim == 2:
                from .friction_history import build
            else:
                from .friction_history3d import build
            return build
        return formulation(cm.options.formulation, self.problem.dim)

    def _factor(self) -> None:
        """K0 factored with the contact dofs last. A body held only through a contact makes K0
        singular: a small fixed region (two finest cells) is kept in K0 and only the difference
        is updated (documented in docs/contact.md)."""
        t = time.perf_counter()
        self.base = [0.0] * len(self.contacts)
        try:
            rigid_modes_check(self.k0, self.bodies)
        except ValueError:
            self.base = [c.initial_region() for c in self.contacts]
            for c, a0 in zip(self.contacts, self.base):
                kc, _, _ = c.terms(a0)
                self.k0 = self.k0 + embed(kc, c.dofs, self.n)
            # still singular: a genuine rigid-body motion (round-off, not the small patch's stiffness)
            rigid_modes_check(self.k0, self.bodies, tolerance=1e-13)
        self.dofs = np.unique(np.concatenate([c.dofs for c in self.contacts]))
        self.where = [np.searchsorted(self.dofs, c.dofs) for c in self.contacts]
        try:
            # the contact dofs nearest the contact points last: a trial region's dofs are then those
            # of the trailing block of G = S^-1, the only part kept for large blocks
            near = contact_nearness(self.bodies, self.dofs, [c.point for c in self.problem.contacts])
            self.lu, self.schur, self.g_inverse = condensed_factor(self.k0, self.dofs, dof_order(self.bodies, self.k0),
                                                                   near)
        except MemoryError:
            raise MemoryError(
                f"the sparse direct factorisation of the {self.n} x {self.n} stiffness (with {len(self.dofs)} contact "
                "dofs condensed) does not fit in memory (SuperLU also limits its factors to 2^31 entries): coarsen "
                "the grid (element_size, refinement levels or radii)"
            ) from None
        if self.problem.history is not None:
            self.path_steps = PathSteps(self.problem, self.bodies, self.options, self.lu, self.dofs, self.schur)
            self.f0 = self.path_steps.at(self.path_steps.times[-1])[0]
        u0 = self.lu.solve(self.f0)
        self.bu0 = u0[self.dofs]
        self.sbu0 = self.schur @ self.bu0
        # G = S^-1 (from the factors) once: each trial then factors only its active dofs (fem.linalg.SmallSystem)
        self.u0f0 = float(u0 @ self.f0)
        # contact stiffness already in K0 (None: none)
        self.base_terms = [c.terms(a0)[0] if a0 > 0 else None for c, a0 in zip(self.contacts, self.base)]
        self.timings["factor_s"] = time.perf_counter() - t
        self.widths = [c.initial_region() for c in self.contacts]
        self.brackets = [(0.0, 0.0)] * len(self.contacts)
        self.prev = None  # (lam, x, y, kc, fc, small) of the last converged state
        self.prev_infos = None
        self.max_iterations = min([self.options.max_iterations]
                                  + [c.options.max_width_iterations for c in self.contacts])
        self.max_stick_iterations = min(c.options.max_stick_iterations for c in self.contacts)

    # ------------------------------------------------------------------ one trial state

    def _assemble_trial(self, widths):
        """Contact stiffness and load on the condensed dofs for trial regions ``widths``, less
        the fixed base regions kept in K0."""
        m = len(self.dofs)
        if len(self.contacts) == 1 and m == len(self.contacts[0].dofs):  # one contact: its own dofs
            (c,), (a,), (kb,) = self.contacts, widths, self.base_terms
            kc, fc, info = c.terms(a)
            if kb is not None:
                kc = kc - kb
            return kc, fc, [info]
        blocks, fc, infos = [], np.zeros(m), []
        for c, wh, a, kb in zip(self.contacts, self.where, widths, self.base_terms):
            kk, ff, info = c.terms(a)
            blocks.append(embed(kk if kb is None else kk - kb, wh, m))
            fc[wh] += ff
            infos.append(info)
        return sum(blocks[1:], blocks[0]).tocsr(), fc, infos

    def _solve_small(self, lam, kc, fc):
        """x of the condensed system (S + Kc) x = lam S B U0 + fc, and S + Kc factored (kept
        with the state: the final field's refinement reuses it)."""
        small = SmallSystem(self.schur, kc, all(c.is_symmetric() for c in self.contacts), self.g_inverse)
        return small.solve(lam * self.sbu0 + fc), small

    def _work_ratio(self, lam, x, y, kc, fc) -> float:
        """Residual work between this trial state and the previous one, relative to the largest
        seen (the thesis's convergence measure, recorded in the history)."""
        old = self.last if self.last is not None else self.prev
        if old is not None:
            o_lam, o_x, o_y, o_kc, o_fc = old[:5]
            r = fc - kc @ o_x - o_fc + o_kc @ o_x
            work = float((x - o_x) @ r)
            dl = lam - o_lam
            if dl:
                work += dl * (dl * self.u0f0 + (y - o_y) @ self.bu0)
            work = abs(work)
        else:
            work = abs(float(lam * lam * self.u0f0 + lam * (y @ self.bu0)))
        self.ref_work = work if self.ref_work is None else max(self.ref_work, work)
        return float(work / self.ref_work) if self.ref_work > 0 else 0.0

    def _trial(self, trial, lam, step, iteration, tag):
        """Solve the state of the trial regions; (state, verdicts, infos)."""
        kc, fc, infos = self._assemble_trial(trial)
        x, small = self._solve_small(lam, kc, fc)
        y = fc - kc @ x
        ratio = self._work_ratio(lam, x, y, kc, fc)
        self.work_history.append(ratio)
        state = (lam, x, y, kc, fc, small)
        self.last = state
        verdicts = []
        for c, wh, a, info in zip(self.contacts, self.where, trial, infos):
            v = c.judge(x[wh], a, info)
            c.history_entry(v, a, step, iteration, tag, ratio)
            verdicts.append(v)
        return state, verdicts, infos

    # ------------------------------------------------------------------ region search

    def _region_search(self, step, lam, final, tag):
        """The region searches of all contacts in one load step at fixed stick ratios: (widths,
        brackets, state, infos, solves, settled)."""
        estimate = self.prev is not None or tag > 0  # a0 from the last step or the last stick update
        gens = [c.region_search(a, final, self.max_iterations, estimate) for a, c in zip(self.widths, self.contacts)]
        trial = [next(gn) for gn in gens]
        results = [None] * len(self.contacts)
        iters, cache = 0, {}
        while True:
            key = tuple(trial)
            if key not in cache:
                iters += 1
                self.report(f"load step {step}/{self.steps}: region trial {iters}"
                            + (f" (shape update {tag})" if tag else ""), self._step_fraction(step))
                cache[key] = self._trial(trial, lam, step, iters, tag)
                self._forget_old_states(cache, keep=2)
            verdicts = cache[key][1]
            if all(r is not None for r in results) or iters >= self.max_iterations:
                break
            trial = self._advance(gens, results, verdicts)
        settled = all(r is not None for r in results)
        results = [r if r is not None else (a, (a, a)) for r, a in zip(results, trial)]
        widths = [r[0] for r in results]
        key = tuple(widths) if tuple(widths) in cache else tuple(trial)  # unsettled: the last trial
        state, _, infos = cache[key]
        if state[3] is None:  # an older trial's terms were dropped: rebuild them
            kc, fc, infos = self._assemble_trial(list(key))
            state = state[:3] + (kc, fc, None)
        if state[5] is None:  # ... or only its factored small system
            state = state[:5] + (SmallSystem(self.schur, state[3], all(c.is_symmetric() for c in self.contacts),
                                              self.g_inverse),)
        return widths, [r[1] for r in results], state, infos, iters, settled

    def _step_fraction(self, step: int) -> float:
        """The run's fraction at the start of load step ``step``: the steps share 0.3 to 0.9."""
        return 0.3 + 0.6 * (step - 1) / self.steps

    @staticmethod
    def _forget_old_states(cache: dict, keep: int) -> None:
        """Drop the contact terms and quadrature data of all but the latest ``keep`` trials, and
        the factored small system (dense, |A|^2 twice: about 20 MB at the 3D 12k-dof
        sphere_on_flat rung) of all but the latest; the verdicts and vectors stay, the rest is
        rebuilt if an older trial is chosen (the small system alone: one factorisation)."""
        for k, key in enumerate(reversed(list(cache))):
            state, verdicts, infos = cache[key]
            if k >= keep and state[3] is not None:
                cache[key] = (state[:3] + (None, None, None), verdicts, None)
            elif k >= 1 and state[5] is not None:
                cache[key] = (state[:5] + (None,), verdicts, infos)

    def _advance(self, gens, results, verdicts) -> list[float]:
        """Send each unsettled search its verdict; the next trial of every contact."""
        nxt = []
        for k, (gn, v) in enumerate(zip(gens, verdicts)):
            if results[k] is not None:
                nxt.append(results[k][0])
                continue
            try:
                nxt.append(gn.send(v))
            except StopIteration as stop:
                results[k] = stop.value
                nxt.append(stop.value[0])
            except RegionTooSmall:
                raise self.contacts[k].region_too_small() from None
        return nxt

    # ------------------------------------------------------------------ load steps

    def _load_step(self, step: int) -> None:
        steps = self.steps
        lam = step / steps
        final = step == steps
        if self.path_steps is not None:  # the step's load replaces the proportional one; every step is final
            t = self.path_steps.times[step - 1]
            self.f0, self.bu0, self.sbu0, self.u0f0 = self.path_steps.at(t)
            lam, final = 1.0, True
        self.report(f"load step {step}/{steps}", self._step_fraction(step))
        if self._load_held(step):
            self._hold_step(step)
            return
        if self.prev is not None and self.prev[0] > 0:
            self.widths = [c.next_region(a, lam / self.prev[0]) for a, c in zip(self.widths, self.contacts)]
        for c in self.contacts:
            c.start_step()
        iters, settled, tag = 0, True, 0
        while True:
            self.widths, self.brackets, state, infos, it, ok = self._region_search(step, lam, final, tag)
            iters += it
            settled = settled and ok
            done = True
            for c, wh, a, info in zip(self.contacts, self.where, self.widths, infos):
                done = c.update_stick_and_shape(state[1][wh], a, info, final) and done
            tag += 1
            if done:
                break
            # a region of general shape that inserted knots may take more updates (star_region)
            if tag >= self.max_stick_iterations + max(getattr(c, "extra_shape_updates", 0) for c in self.contacts):
                settled = False
                self.messages.append(f"load step {step}: the stick zone / region shape did not settle in {tag} iterations")
                break
        self.per_step.append(iters)
        if not settled:
            self.converged = False
            self.messages.append(f"load step {step}: the contact width did not settle in {iters} iterations")
        self.prev, self.prev_infos = state, infos
        if self.path_steps is not None:
            t = self.path_steps.times[step - 1]
            for c, wh, a, info in zip(self.contacts, self.where, self.widths, infos):
                getattr(c, "end_step", lambda *args: None)(state[1][wh], a, info)
            u = step_field(self, state, self.f0)
            self.step_records.append(step_record(self, t, u, self.path_steps.essential_factors(t)))

    def _load_held(self, step: int) -> bool:
        """Whether a path step's loads equal the last step's (a held segment of every path)."""
        if self.path_steps is None or self.prev is None or step < 2:
            return False
        loads, times = self.path_steps.loads, self.path_steps.times
        t, t_last = times[step - 1], times[step - 2]
        if not np.array_equal(loads.weights(t), loads.weights(t_last)):
            return False
        now, last = loads.essential_factors(t), loads.essential_factors(t_last)
        return all(np.array_equal(now[k], last[k]) for k in now)

    def _hold_step(self, step: int) -> None:
        """A held step keeps the last step's state: friction is rate independent, so unchanged loads
        change nothing (no slip, no work); the step is recorded without a solve."""
        t = self.path_steps.times[step - 1]
        self.per_step.append(0)
        for c, wh, a, info in zip(self.contacts, self.where, self.widths, self.prev_infos):
            getattr(c, "hold_step", lambda *args: None)(self.prev[1][wh], a, info)
        u = step_field(self, self.prev, self.f0)
        self.step_records.append(step_record(self, t, u, self.path_steps.essential_factors(t)))

    # ------------------------------------------------------------------ the final state

    def _final_field(self):
        """The full field of the last state, refined twice on K0 + B^T Kc B (the contact terms,
        friction included, live on the contact dofs only); (u, load factor, residual work ratio)."""
        lam, x, y, kc, fc, small = self.prev
        n, dofs = self.n, self.dofs
        u = self.lu.solve(lam * self.f0 + scatter(n, dofs, y))
        k_full = (self.k0 + embed(kc, dofs, n)).tocsr()
        f_full = lam * self.f0 + scatter(n, dofs, fc)
        res = f_full - k_full @ u
        for _ in range(2):
            u = u + condensed_apply(self.lu, small, self.schur, dofs, kc, res)
            res = f_full - k_full @ u
        work = abs(float(u @ res)) / max(abs(float(u @ f_full)), 1e-300)
        return u, lam, float(np.linalg.norm(res) / max(np.linalg.norm(f_full), 1e-300)), work

    def _results(self) -> IBFEMSolution:
        u, lam, residual, work = self._final_field()
        factors = lam if self.path_steps is None else self.path_steps.essential_factors(self.path_steps.times[-1])
        reactions, tractions = essential_reactions(self.essentials, u, self.options, factors)
        blocks = []
        for c, a, info, bracket in zip(self.contacts, self.widths, self.prev_infos, self.brackets):
            on2 = -c.force(u[c.dofs], a, info)
            writer = getattr(c, "summary_block", None)  # a formulation may write its own block (3D)
            block = writer(a, on2, u, info) if writer is not None else contact_block(c, a, on2, u)
            problems = c.check_final(u, a, info, bracket, block)
            blocks.append(block)
            if problems:
                self.converged = False
                self.messages += problems
        overlaps = overlapping_regions(blocks)
        if overlaps:
            self.converged = False
            self.messages += overlaps
        if not work <= self.options.tolerance:
            self.converged = False
            self.messages.append(
                f"the residual work of the final state is {work:.3g}, above solver.tolerance = {self.options.tolerance:g}"
            )
        iterations = {
            "total": int(sum(self.per_step)),
            "per_step": self.per_step,
            "load_steps": {"requested": self.options.load_steps, "solved": self.steps, "rule": self.step_rule},
            "friction_history": [getattr(c, "history_rule", "none") for c in self.contacts],
            "linear_residual": residual,
            "residual_work": work,
            "width_update": [c.options.width_update for c in self.contacts][0],
            "work_ratio": self.work_history,
            "contact_dofs": len(self.dofs),
            "contacts": [c.history for c in self.contacts],
            "messages": self.messages,
        }
        return IBFEMSolution(
            problem=self.problem,
            bodies=self.bodies,
            u=u,
            converged=bool(self.converged and np.isfinite(u).all() and residual < 1e-6),
            body_info=body_info(self.bodies),
            reactions=reactions,
            iterations=iterations,
            timings=self.timings,
            contacts=blocks,
            settings=self.options,
            boundary_tractions=tractions,
            steps=self.step_records,
        )
