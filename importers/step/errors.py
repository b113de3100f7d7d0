"""Errors of the STEP / IGES importer: both are ``ValueError`` subclasses, so the commands and
the scene loader report them as one line naming the file."""

from __future__ import annotations

__all__ = ["StepFormatError", "StepUnavailableError", "require_ocp", "INSTALL_HINT"]

INSTALL_HINT = "pip install 'ibfem[step]'"


class StepFormatError(ValueError):
    """A STEP or IGES file that cannot be read into a part: the message names the file and,
    where OpenCascade tells us, the entity (``#123`` in STEP, the directory entry in IGES)."""


class StepUnavailableError(ValueError):
    """OpenCascade's Python bindings (OCP, the ``step`` extra) are not installed."""


def require_ocp() -> None:
    """Raise :class:`StepUnavailableError` (one line naming the extra) when OCP is missing."""
    try:
        import OCP  # noqa: F401
        from OCP.STEPControl import STEPControl_Reader  # noqa: F401
    except ImportError as exc:
        raise StepUnavailableError(f"reading STEP/IGES files needs OpenCascade's Python bindings (OCP, "
                                   f"the 'step' extra): {INSTALL_HINT} ({exc})") from None
