"""``ibfem import``, ``ibfem verify`` and ``ibfem info``."""

from __future__ import annotations

import argparse


def register(sub: "argparse._SubParsersAction") -> None:
    """Add the import sub-commands (implemented by the importer work)."""
