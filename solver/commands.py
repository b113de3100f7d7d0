"""``ibfem run``: registered here, implemented with the scene and results modules."""

from __future__ import annotations

import argparse


def register(sub: "argparse._SubParsersAction") -> None:
    p = sub.add_parser("run", help="solve a scene file (TOML or JSON) and write results")
    p.add_argument("scene", help="scene file, SPEC section 4")
    p.add_argument("--out", default=None, help="output directory (default: out/<scene name>)")
    p.set_defaults(handler=_run)


def _run(args: argparse.Namespace) -> int:
    raise SystemExit("ibfem run: not implemented yet")
