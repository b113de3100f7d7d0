"""The ``ibfem`` command line: ``run`` (solve a scene), ``import``, ``verify`` and ``info``
(Onshape and mesh import). Each command module registers its own sub-command and imports
its heavy dependencies only when the command runs, so ``ibfem --help`` is fast."""

from __future__ import annotations

import argparse
import sys
from importlib import import_module

# modules that each add sub-commands with ``register(subparsers)``, in ``--help`` order
COMMAND_MODULES = ("ibfem.solver.commands", "ibfem.solver.sweep.commands", "ibfem.importers.commands")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ibfem",
        description="Immersed-boundary finite elements with exact CAD geometry: contact stresses "
        "from CAD parts. 'ibfem COMMAND --help' describes each command.",
    )
    parser.add_argument("--version", action=_Version, nargs=0, help="show the program's version number and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMAND_MODULES:
        import_module(name).register(sub)
    for command in sub.choices.values():  # every command can show the traceback of an internal error
        if not any("--traceback" in a.option_strings for a in command._actions):
            command.add_argument("--traceback", action="store_true",
                                 help="show the Python traceback of an internal error")
    return parser


class _Version(argparse.Action):
    """``--version``: the installed version, looked up only when asked for."""

    def __call__(self, parser, namespace, values, option_string=None):
        from ibfem import __version__

        print(f"ibfem {__version__}")
        parser.exit()


#: exit code of an error the program did not expect (a bug): one line, no traceback
INTERNAL_ERROR = 5
#: exit code when the machine's memory ran out
OUT_OF_MEMORY = 6


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except MemoryError as err:
        if getattr(args, "traceback", False):
            raise
        print(f"ibfem {args.command}: out of memory{': ' + str(err) if str(err) else ''}; coarsen the grid "
              "(element_size, refinement levels or radii)", file=sys.stderr)
        return OUT_OF_MEMORY
    except Exception as err:  # noqa: BLE001 - the last line of defence: one line, a distinct code
        if getattr(args, "traceback", False):
            raise
        text = str(err).splitlines()[0] if str(err) else ""
        print(f"ibfem {args.command}: internal error ({type(err).__name__}{': ' + text if text else ''}). This is "
              f"a bug: rerun with --traceback for the details and report it.", file=sys.stderr)
        return INTERNAL_ERROR


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
