"""``ibfem sweep``: registered here; the sweep engine is imported when the command runs."""

from __future__ import annotations

import argparse
import sys


def register(sub: "argparse._SubParsersAction") -> None:
    p = sub.add_parser("sweep", help="run a parameter sweep of a scene (SPEC section 8)")
    p.add_argument("sweep_file", help="sweep description (TOML)")
    p.set_defaults(handler=_sweep)


def _sweep(args: argparse.Namespace) -> int:
    print("ibfem sweep: not available in this build yet (issue 16)", file=sys.stderr)
    return 2
