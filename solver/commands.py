"""``ibfem run SCENE [--out DIR]``: load and validate a scene, solve it, write the results.

Exit codes: 0 solved and converged; 1 solved but not converged (``summary.json`` is still
written, with ``converged`` false and the iteration history); 2 the scene is invalid (one
line per problem on stderr, no traceback); 3 the solver core is not available; 4 the
results could not be written; 5 an internal error (a bug: one line, ``--traceback`` shows it;
also a ValueError raised inside numpy / scipy, which is never reported as a scene error); 6 out of
memory (solver.cli)."""

from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path


def register(sub: "argparse._SubParsersAction") -> None:
    p = sub.add_parser(
        "run",
        help="solve a scene file (TOML or JSON) and write results",
        description="Solve a scene (2D, or 3D with model = \"solid\") and write summary.json, one VTU file "
        "per body and, when the scene asks, PNG plots.",
    )
    p.add_argument("scene", help="scene file (.toml, or .json with the same structure)")
    p.add_argument("--out", default=None, help="output directory (default: out/<scene file name>)")
    p.add_argument("--quiet", action="store_true", help="no progress display")
    p.add_argument("--check", action="store_true",
                   help="validate the scene and print the size of its grids; solves nothing but a 3D line "
                        "contact's coarse pass (its region sets the run's grid)")
    p.add_argument("--traceback", action="store_true", help="show tracebacks of solver errors")
    p.add_argument("--no-estimate", action="store_true",
                   help="skip the error estimate of the contacts' results (a second solve on a grid twice as "
                        "coarse, in 2D a third on one 4 times as coarse)")
    p.set_defaults(handler=_run)
    c = sub.add_parser(
        "compile",
        help="compile the solver's kernels once (a first large 3D run otherwise spends 7-11 s on it)",
        description="Compile the solver's numba kernels into their on-disk cache by solving two small contact "
        "scenes (3D and 2D) with every compiled path taken: about 10-30 s once; later runs load the kernels "
        "from the cache. `make` runs it after installing.",
    )
    c.add_argument("--quiet", action="store_true", help="print nothing but errors")
    c.set_defaults(handler=_compile)


def _compile(args) -> int:
    """``ibfem compile``: :func:`solver.kernel_warmup.warm_kernels`; exit 1 if a scene did not converge."""
    from ibfem.solver.fem.multifrontal import available
    from ibfem.solver.kernel_warmup import warm_kernels

    say = (lambda text: None) if args.quiet else (lambda text: print(f"ibfem compile: {text}", flush=True))
    if not available():
        say("numba is not installed (the `fast` extra): there are no compiled kernels to compile")
        return 0
    rows = warm_kernels(say)
    for row in rows:
        say(f"{row['scene']}: {'converged' if row['converged'] else 'NOT converged'} in {row['seconds']:.1f} s")
    return 0 if all(row["converged"] for row in rows) else 1


#: exit code of an internal error (solver.cli has the same)
INTERNAL_ERROR = 5
_OURS = "ibfem"
#: numerical libraries whose ValueErrors mean the solver handed them something broken
LIBRARIES = ("numpy", "scipy", "pyamg", "pymetis", "numba", "trimesh", "matplotlib", "pyvista")


def error_origin(err: BaseException) -> tuple[str | None, str]:
    """Where an exception was raised: (None, module) when not inside a numerical library (the
    solver's own checks), else (the library's name, the project's function that called it)."""
    tb = err.__traceback__
    ours, last = "the solver", ""
    while tb is not None:
        module = str(tb.tb_frame.f_globals.get("__name__", ""))
        if module.split(".")[0] == _OURS:
            ours = f"{module}.{tb.tb_frame.f_code.co_name}"
        last = module
        tb = tb.tb_next
    top = last.split(".")[0]
    return (top if top in LIBRARIES else None), ours


def _err(text: str) -> None:
    for line in str(text).splitlines() or [""]:
        print(f"ibfem run: {line}", file=sys.stderr)


def default_out_dir(scene_path: str | Path) -> Path:
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", Path(scene_path).stem).strip("_") or "scene"
    return Path("out") / stem


def _run(args: argparse.Namespace) -> int:
    t0 = time.perf_counter()
    from ibfem.solver.io.parallel_plots import PictureWorker

    # a scene asking for pictures: their process, started before the solver's modules are
    # imported, imports matplotlib while this one imports the solver, loads the scene and solves
    early = None if args.check else PictureWorker.early(args.scene)
    from ibfem.solver.io.scene import SceneError, load_scene

    try:
        scene = load_scene(args.scene)
    except SceneError as err:
        _err(str(err))
        return 2
    for note in scene.warnings:
        _err(f"warning: {note}")
    if args.check:
        return _print_check(args.scene, scene, quiet=args.quiet)
    if early is not None and not scene.output.plots:
        early.stop(at_once=True)
    worker = PictureWorker.start(scene.problem, early) if scene.output.plots else None
    try:
        from ibfem.solver.solving import solve
    except ImportError as err:
        _err(f"the solver core (solver.solving.solve) is not available: {err}")
        return 3

    from ibfem.solver.io.progress import ProgressReporter, silent
    from ibfem.solver.io.output import write_scene_results

    progress = silent if args.quiet else ProgressReporter()
    label = Path(args.scene).name
    out = Path(args.out) if args.out else default_out_dir(args.scene)
    pictures = _PictureStart(out, scene, progress, worker)
    try:
        solution, ladder = _solve_scene(scene.problem, solve, progress, estimate=not args.no_estimate,
                                        solved=pictures if scene.output.plots else None)
    except ValueError as err:  # the solver's own checks on the input: a scene problem
        if not args.quiet:
            progress.close()
        if args.traceback:
            raise
        return _solver_refused(label, err)
    except BaseException:
        if not args.quiet:
            progress.close()
        raise

    if scene.output.plots and pictures.started is None:  # no error estimate: they start now
        pictures(solution)
    extra = {"scene": str(Path(args.scene))}
    if ladder is not None:
        extra["accuracy"] = ladder
    if scene.warnings:
        extra["warnings"] = list(scene.warnings)
    try:  # the progress display goes on while the results are written
        summary = write_scene_results(out, scene, solution, total_s=time.perf_counter() - t0, extra=extra,
                                      progress=progress, pictures=pictures.started)
    except OSError as err:
        _err(f"cannot write results to {out}: {err.strerror or err}")
        return 4
    finally:
        if not args.quiet:
            progress.close()
    for note in summary.get("warnings", [])[len(scene.warnings):]:
        _err(f"warning: {note}")
    iterations = summary["iterations"]["total"]
    if not summary["converged"]:
        return _not_converged(label, summary, out)
    print(
        f"{scene.name}: converged in {iterations} iterations, {summary['timings']['total_s']:.2f} s; "
        f"results in {out}/"
    )
    _print_contacts(summary, ladder)
    return 0


def _not_converged(label: str, summary: dict, out: Path) -> int:
    """Report a run that did not converge (exit 1): where its history is, and the solver's
    diagnosis where it made one (a contact smaller than the grid resolves, a failed check)."""
    _err(f"{label}: not converged after {summary['iterations']['total']} iterations; the iteration history is in "
         f"{out / 'summary.json'}")
    for message in summary["iterations"].get("messages", []):
        _err(f"{label}: {message}")
    return 1


def _print_check(path: str, scene, quiet: bool = False) -> int:
    """``--check``: the scene is valid; the size of the run it would make (exit 0). A coarse pass
    the check solves (3D line contacts, large point contacts) shows its progress as a run does."""
    from ibfem.solver.io.progress import ProgressReporter, share
    from ibfem.solver.io.run_size import run_size

    progress = None if quiet else ProgressReporter()
    report = None if progress is None else share(progress, 0.0, 1.0, "check, coarse pass: ")

    def coarse_solve(problem):  # the solver's modules are imported only by a check that solves
        from ibfem.solver.solving import solve

        return solve(problem, progress=report)

    try:
        size, note = run_size(scene.problem, coarse_solve)
    finally:
        if progress is not None:
            progress.close()
    print(f"{path}: valid scene {scene.name!r} ({len(scene.problem.bodies)} bodies; {size})"
          + ("" if note is None else f"; {note}"))
    return 0


def _solver_refused(label: str, err: ValueError) -> int:
    """Report a ValueError of the solve: 2 for the solver's own checks on the input (a scene
    problem), INTERNAL_ERROR where numpy or scipy refused what the solver handed them (not the
    user's key: a gap in the checks)."""
    library, where = error_origin(err)
    if library is None:
        _err(f"{label}: {err}")
        return 2
    _err(f"{label}: the solver failed in {where}: {library} reported \"{str(err).splitlines()[0] if str(err) else type(err).__name__}\". "
         "This is a bug (an input the scene check lets through): rerun with --traceback and report it.")
    return INTERNAL_ERROR


class _PictureStart:
    """Called with the solution once it is there: starts the scene's pictures, which render
    while the error estimate solves (solver.io.output.start_scene_pictures); ``started`` is
    what it returned (None before, or when the output folder cannot be made: that is reported
    when the results are written)."""

    def __init__(self, out: Path, scene, progress, worker=None):
        self.out, self.scene, self.progress, self.started, self.worker = out, scene, progress, None, worker

    def __call__(self, solution) -> None:
        from ibfem.solver.io.output import start_scene_pictures

        self.progress("results: plots (started)")
        try:
            self.started = start_scene_pictures(self.out, self.scene, solution, self.worker)
        except OSError:
            self.started = None


def _solve_scene(problem, solve, progress, estimate: bool, solved=None):
    """(solution, accuracy ladder or None): the ladder of ``[solver] accuracy`` when the scene sets
    it, else one solve, followed by the error estimate (a second solve on a coarser grid) of a
    converged contact solution unless ``estimate`` is false; ``solved(solution)`` is called
    before that estimate (the pictures start there)."""
    if problem.options.accuracy is not None and problem.contacts:
        from ibfem.solver.solving import solve_to_accuracy

        return solve_to_accuracy(problem, progress=progress)
    from ibfem.solver.io.progress import share

    # a contact's error estimate solves again on a grid twice as coarse (an eighth of the cells
    # in 3D, a quarter in 2D): the first solve shows as the run's first nine tenths
    estimated = estimate and bool(problem.contacts)
    solution = solve(problem, progress=share(progress, 0.0, 0.9) if estimated else progress)
    if solution.contacts and solution.converged and estimate:
        if solved is not None:
            solved(solution)
        from ibfem.solver.solving import estimate_errors

        estimate_errors(problem, solution, progress=share(progress, 0.9, 1.0, "error estimate: "))
    return solution, None


#: fewer of the finest cells than this across a semi-axis (half-width) of a contact region: the
#: region is barely resolved and the error estimate (a solve twice as coarse) can understate the error
MIN_CELLS_ACROSS = 2.0


def _coarse_region_note(contact: dict) -> str | None:
    """A warning's text where the region spans fewer than ``MIN_CELLS_ACROSS`` finest cells along
    a semi-axis (3D) or its half-width (2D); None otherwise or without a region."""
    cells = contact.get("cells_per_semi_axis") or [contact.get("cells_per_half_width") or 0.0]
    sizes = contact.get("semi_axes") or [contact.get("half_width") or 0.0]
    thin = [(k, n, s) for k, (n, s) in enumerate(zip(cells, sizes)) if 0.0 < n < MIN_CELLS_ACROSS]
    if not thin:
        return None
    k, n, s = min(thin, key=lambda t: t[1])
    what = f"semi-axis {k} ({s:.3g} m)" if contact.get("cells_per_semi_axis") else f"half-width ({s:.3g} m)"
    return (f"the region's {what} spans only {n:.2g} of the finest cells there: the region is barely "
            f"resolved and the estimated error can understate the error; refine the grid around the contact "
            f"(more refinement levels) to at least {MIN_CELLS_ACROSS:g} cells across")


#: the initial gap at an elliptical region's edge may differ from the contact point's quadratic
#: (Hertz) model by this share before the region counts as not Hertzian
GAP_MODEL_SPREAD = 0.25
#: a region whose two axes' gap readings and curvatures agree to this share is taken as one of
#: revolution about the contact point, whose sizing by the gap's profile is exact
ROUND_SPREAD = 0.05


def _gap_model_note(contact: dict) -> str | None:
    """A warning's text where an elliptical region is not Hertzian (its edge sees a gap far from
    the quadratic of the contact point's curvatures) and not of revolution either: its sizes
    then follow the gap's profile along each axis, an estimate; None otherwise."""
    ratios = [r for r in contact.get("gap_at_edge_over_quadratic") or [] if isinstance(r, float) and r == r]
    off = [r for r in ratios if abs(r - 1.0) > GAP_MODEL_SPREAD]
    if not off:
        return None
    kappa = contact.get("relative_curvatures") or []
    if (len(ratios) == 2 and len(kappa) == 2 and abs(ratios[0] / ratios[1] - 1.0) <= ROUND_SPREAD
            and abs(kappa[0] / kappa[1] - 1.0) <= ROUND_SPREAD):
        return None
    worst = max(off, key=lambda r: abs(r - 1.0))
    return (f"the bodies' initial gap at the region's edge is {worst:.3g} times the quadratic gap of the contact "
            f"point's curvatures and differs between the region's axes: the region is neither Hertzian nor of "
            f"revolution, and its semi-axes, sized by the gap's profile along each axis, are an estimate")


def _friction_note(contact: dict) -> str | None:
    """A warning's text for partial slip on a 3D region that is not an ellipse (a line contact or
    a flat face), whose stick zone is not validated; None otherwise."""
    shape = contact.get("region_shape") or ""
    if contact.get("type") != "frictional" or not shape.startswith("star-shaped"):
        return None
    if contact.get("complete_contact"):
        return ("friction on a face in complete contact is not validated: its stick zone is not found (stick_semi_axes "
                "reads 0) and its shear is not reported; treat the tangential result as unchecked")
    return ("friction on a line or flat contact is not validated: the stick zone is scaled from the region's edge "
            "as Mindlin's is for an ellipse; treat the stick zone as an estimate")


#: the share of the slip (by its amount) running against the friction traction above which a run
#: warns: a whole end of the slip zones slipping the other way reads about half (a crowned
#: indenter 100 times stiffer than its block, Dundurs' beta -0.29: 0.45), an inner part creeping
#: back a few per cent (the same pair of one material: 0.04)
SLIP_AGAINST_WARN = 0.2


def _slip_direction_note(contact: dict) -> str | None:
    """A warning's text where a 2D frictional contact's final state slips against its friction
    traction over a large share of its slip; None otherwise."""
    share = (contact.get("checks") or {}).get("slip_against_traction")
    if contact.get("type") != "frictional" or not isinstance(share, float) or not share >= SLIP_AGAINST_WARN:
        return None
    return (f"{100 * share:.0f} % of the slip zones' slip runs against their friction traction: the two ends slip "
            "in opposite directions, which a proportional run's zones (one slip direction about a centred stick "
            "zone, as Cattaneo and Mindlin's) cannot hold, so its stick zone and shear are not Coulomb's. The normal "
            "load's own tangential displacements do this where the tangential load is small against mu N, or the "
            "bodies' elastic constants differ slightly. Load paths ([[paths]], or a path on any condition) solve "
            "friction with memory, whose slip zones take either direction")


def _dissimilar_friction_note(contact: dict, solid: bool) -> str | None:
    """A warning's text for a 3D (``solid``) frictional contact of two materials whose Dundurs beta
    is large against mu: the bound at which a 2D contact takes friction memory (2D runs check their
    final state instead: :func:`_slip_direction_note`)."""
    from ibfem.solver.contact.friction_memory import BETA_OVER_MU

    beta, mu = contact.get("dundurs_beta"), contact.get("friction") or 0.0
    if not solid or contact.get("type") != "frictional" or not isinstance(beta, float) or not mu > 0.0:
        return None
    if abs(beta) < BETA_OVER_MU * mu:
        return None
    return (f"the bodies' Dundurs beta is {beta:.3g} ({abs(beta) / mu:.2g} of mu): under the normal load alone "
            "bodies of different elastic constants slip radially against each other, which the proportional "
            "run's stick zone (Mindlin's, one slip direction) does not hold; treat stick_semi_axes and the shear "
            "as estimates. Load paths ([[paths]], or a path on any condition) solve friction with memory")


def _print_contacts(summary: dict, ladder: dict | None) -> None:
    """The accuracy ladder's line, each contact's result line, and a warning on stderr where an
    estimated error is above the warning level (runs without an accuracy target)."""
    from ibfem.solver.io.result_line import accuracy_line, contact_line
    from ibfem.solver.model.accuracy import WARN_ABOVE, largest_error

    if ladder is not None:
        print("  " + accuracy_line(ladder))
        if not ladder["reached"]:
            _err(f"warning: the accuracy target {ladder['target']:g} was not reached: {ladder['note']}")
    for c in summary["contacts"]:
        print("  contact " + " / ".join(c.get("bodies") or []) + ": " + contact_line(c))
        for note in (_coarse_region_note(c), _friction_note(c), _gap_model_note(c), _slip_direction_note(c),
                     _dissimilar_friction_note(c, summary.get("model") == "solid")):
            if note:
                _err(f"warning: contact {' / '.join(c.get('bodies') or [])}: {note}")
        key, value = largest_error(c.get("estimated_error") or {})
        if ladder is None and value > WARN_ABOVE:
            advice = ("grade the far field: zones about the contact one level coarser at every doubling of "
                      "the radius, out to the bodies' extent" if key == "normal_force"
                      else "refine the grid around the contact (more refinement levels)")
            _err(f"warning: contact {' / '.join(c.get('bodies') or [])}: the estimated error of {key} is "
                 f"{100 * value:.2g} %, above {100 * WARN_ABOVE:g} %: {advice}, or set [solver] accuracy")
        elif ladder is None and c.get("estimated_error") is None and c.get("estimate_note"):
            # no estimate: most often the grid twice as coarse no longer resolves the region, and
            # this one barely does (a cylinder's half-width 2 cells across: a 6 % short of Hertz's)
            cells = c.get("cells_per_half_width") or min(c.get("cells_per_semi_axis") or [0.0])
            span = f"the region spans {cells:.2g} of the finest cells across its half-width; " if cells else ""
            _err(f"warning: contact {' / '.join(c.get('bodies') or [])}: no error estimate ({c['estimate_note']}): "
                 f"{span}refine the grid around the contact (more refinement levels) until a grid twice as "
                 "coarse converges too, or set [solver] accuracy")
