"""``python -m ibfem``: the ``ibfem`` command line."""

from ibfem.solver.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
