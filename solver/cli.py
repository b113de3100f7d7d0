"""The ``ibfem`` command line: ``run`` (solve a scene), ``import``, ``verify`` and ``info``
(Onshape and mesh import). Each command module registers its own sub-command and imports
its heavy dependencies only when the command runs, so ``ibfem --help`` is fast."""

from __future__ import annotations

import argparse
import sys
from importlib import import_module

# modules that each add sub-commands with ``register(subparsers)``, in ``--help`` order
COMMAND_MODULES = ("solver.commands", "solver.sweep.commands", "importers.commands")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ibfem",
        description="Immersed-boundary finite elements with exact CAD geometry: contact stresses "
        "from CAD parts (see README.md).",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMAND_MODULES:
        import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
